// This file is part of OpenCV project.
// It is subject to the license terms in the LICENSE file found in the top-level directory
// of this distribution and at http://opencv.org/license.html

// Golden matches: the full match lists (class, template, x, y, similarity) of fixed detectors on
// fixed frames, as the code that wrote testdata/forestmod/golden/ produced them. A change of the
// pipeline that must not change results (a restructuring, a faster path) keeps this test green;
// a change that alters results on purpose regenerates the folder and says why in its commit:
//
//   FORESTMOD_GOLDEN_RECORD=<repo>/testdata/forestmod/golden
//   build/bin/opencv_test_forestmod --gtest_filter='Forestmod_Golden.*'   (with that variable)
//
// Inputs, all shipped: model files with the shipped ape's templates (RGB: gradient + hue; RGB-D:
// + depth normals; two distances, so two search groups) written by save(), which doubles as the
// test that older model files load and match alike; the three shipped real LM-O frames; two
// rendered RGB-D scenes. Each detector is run with 1 tree (the file's forests), 5 trees
// (retrained after load) and exhaustively (use_forest = false).

#include "test_precomp.hpp"

namespace opencv_test { namespace {

static Matx33d goldenK()
{
    return Matx33d(572.4114, 0, 325.2611, 0, 573.57043, 242.04899, 0, 0, 1);
}

static const char* const LMO_FRAMES[] = { "000224", "000902", "001038" };
static const int RGBD_SCENES = 2;

static std::string recordDir()
{
    const char* dir = getenv("FORESTMOD_GOLDEN_RECORD");
    return dir ? std::string(dir) : std::string();
}

static std::string goldenFile(const std::string& name)
{
    const std::string dir = recordDir();
    if (!dir.empty())
        return dir + "/" + name;
    return cvtest::findDataFile("golden/" + name);
}

static ViewSampler goldenSampler()
{
    ViewSampler::Params p;
    p.level = 1;
    p.min_elevation = -15;
    p.radii = std::vector<double>{ 700.0, 1000.0 };
    p.inplane_min = 0;
    p.inplane_max = 0;
    p.inplane_step = 30;
    return ViewSampler(p);
}

static std::vector<Mat> sourcesOf(const cv::forestmod::Detector& det, const Mat& color,
                                  const Mat& depth)
{
    std::vector<Mat> src;
    for (const Ptr<linemod::Modality>& m : det.getModalities())
        src.push_back(m->name() == "DepthNormal" ? depth : color);
    return src;
}

// Record mode: templates of the shipped ape, trained (1 tree), saved.
static void recordModel(bool rgbd, const std::string& path)
{
    Ptr<cv::forestmod::Detector> det = rgbd ? getDefaultForestLINEMOD() : getDefaultForestLINE();
    const Mesh ape = Mesh::load(cvtest::findDataFile("lmo_mini/models/obj_000001.ply"));
    ASSERT_GT(det->addTemplates(ape, "ape", goldenSampler(), goldenK(), Size(640, 480)), 40);
    det->train();
    det->save(path, true);
}

// Record mode: rendered RGB-D scenes of the ape over a smooth random texture (small files).
static void recordScenes()
{
    const Mesh ape = Mesh::load(cvtest::findDataFile("lmo_mini/models/obj_000001.ply"));
    SyntheticSceneParams sp;
    sp.color_noise = 0; // compressible; the depth keeps its sensor noise
    SceneSynthesizer synth(Renderer::create(Size(640, 480)), goldenK(), sp);
    synth.addObject(ape);
    const Point3f c = ape.center();
    const std::vector<ViewPose> views = goldenSampler().poses(Point3d(c.x, c.y, c.z));
    RNG rng(2026);
    for (int k = 0; k < RGBD_SCENES; ++k)
    {
        const ViewPose& v = views[rng.uniform(0, (int)views.size())];
        const SyntheticScene s = synth.render(0, v.R, v.t, rng);
        const std::vector<int> png = { IMWRITE_PNG_COMPRESSION, 9 };
        imwrite(goldenFile(cv::format("scene%d_rgb.png", k)), s.color, png);
        imwrite(goldenFile(cv::format("scene%d_depth.png", k)), s.depth, png);
    }
}

struct GoldenCase
{
    std::string name;
    std::vector<linemod::Match> matches;
};

// The cases of one model: 1 tree, 5 trees, exhaustive, on every frame of its kind.
static std::vector<GoldenCase> runModel(bool rgbd)
{
    std::vector<GoldenCase> out;
    const std::string kind = rgbd ? "rgbd" : "rgb";
    std::vector<Mat> colors, depths;
    if (rgbd)
    {
        for (int k = 0; k < RGBD_SCENES; ++k)
        {
            colors.push_back(imread(goldenFile(cv::format("scene%d_rgb.png", k)), IMREAD_COLOR));
            depths.push_back(imread(goldenFile(cv::format("scene%d_depth.png", k)),
                                    IMREAD_UNCHANGED));
        }
    }
    else
    {
        for (const char* f : LMO_FRAMES)
            colors.push_back(imread(cvtest::findDataFile(
                                        cv::format("lmo_mini/test/000002/rgb/%s.png", f)),
                                    IMREAD_COLOR));
    }
    for (size_t k = 0; k < colors.size(); ++k)
    {
        EXPECT_FALSE(colors[k].empty());
        if (rgbd)
        {
            EXPECT_EQ(CV_16UC1, depths[k].type());
        }
    }
    cv::forestmod::Detector det;
    det.load(goldenFile(cv::format("ape_%s.yml.gz", kind.c_str())));
    EXPECT_TRUE(det.isTrained()) << "the model file holds its forests";
    const char* modes[] = { "1tree", "5trees", "exhaustive" };
    for (int mode = 0; mode < 3; ++mode)
    {
        if (mode > 0)
        {
            DetectorParams p = det.getParams();
            p.forest.num_trees = 5;
            p.use_forest = mode == 1;
            det.setParams(p);
        }
        for (size_t k = 0; k < colors.size(); ++k)
        {
            GoldenCase c;
            c.name = cv::format("%s_%s_frame%d", kind.c_str(), modes[mode], (int)k);
            det.match(sourcesOf(det, colors[k], rgbd ? depths[k] : Mat()), 80.f, c.matches);
            out.push_back(c);
        }
    }
    return out;
}

static void writeCases(FileStorage& fs, const std::vector<GoldenCase>& cases)
{
    for (const GoldenCase& c : cases)
    {
        fs << c.name << "[";
        for (const linemod::Match& m : c.matches)
            fs << "{:" << "class" << m.class_id << "template" << m.template_id << "x" << m.x
               << "y" << m.y << "similarity" << m.similarity << "}";
        fs << "]";
    }
}

static void expectCases(const FileStorage& fs, const std::vector<GoldenCase>& cases)
{
    for (const GoldenCase& c : cases)
    {
        const FileNode n = fs[c.name];
        ASSERT_FALSE(n.empty()) << c.name << " is missing from the golden file";
        ASSERT_EQ((int)n.size(), (int)c.matches.size()) << c.name << ": number of matches";
        int i = 0;
        for (FileNodeIterator it = n.begin(); it != n.end(); ++it, ++i)
        {
            const linemod::Match& m = c.matches[i];
            const std::string where = cv::format("%s, match %d", c.name.c_str(), i);
            EXPECT_EQ((std::string)(*it)["class"], m.class_id) << where;
            EXPECT_EQ((int)(*it)["template"], m.template_id) << where;
            EXPECT_EQ((int)(*it)["x"], m.x) << where;
            EXPECT_EQ((int)(*it)["y"], m.y) << where;
            EXPECT_NEAR((float)(*it)["similarity"], m.similarity, 1e-4f) << where;
        }
    }
}

TEST(Forestmod_Golden, match_lists_reproduce_the_recorded_ones)
{
    applyTestTag(CV_TEST_TAG_LONG);
    const std::string record = recordDir();
    if (!record.empty())
    {
        ASSERT_TRUE(utils::fs::createDirectories(record));
        recordModel(false, goldenFile("ape_rgb.yml.gz"));
        recordModel(true, goldenFile("ape_rgbd.yml.gz"));
        recordScenes();
    }
    std::vector<GoldenCase> cases = runModel(false);
    const std::vector<GoldenCase> rgbd = runModel(true);
    cases.insert(cases.end(), rgbd.begin(), rgbd.end());
    size_t total = 0;
    for (const GoldenCase& c : cases)
        total += c.matches.size();
    EXPECT_GT(total, cases.size()) << "the golden cases must hold matches to compare";
    if (!record.empty())
    {
        FileStorage fs(goldenFile("matches.yml.gz"), FileStorage::WRITE);
        ASSERT_TRUE(fs.isOpened());
        writeCases(fs, cases);
        std::cout << "[ INFO    ] golden matches recorded in " << record << " (" << total
                  << " matches in " << cases.size() << " cases)" << std::endl;
        return;
    }
    FileStorage fs(goldenFile("matches.yml.gz"), FileStorage::READ);
    ASSERT_TRUE(fs.isOpened());
    expectCases(fs, cases);
}

}} // namespace
