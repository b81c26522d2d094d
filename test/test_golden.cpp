// This file is part of OpenCV project.
// It is subject to the license terms in the LICENSE file found in the top-level directory
// of this distribution and at http://opencv.org/license.html

// Golden matches: the full match lists (class, template, x, y, similarity) of fixed detectors on
// fixed frames, as the code that wrote testdata/forestmod/golden/ produced them, and what the scan
// did at every location (DetectionStats::rejection_map: the depth at which each location was
// rejected, or that it was validated; the counters of validated locations and candidates). A change of the
// pipeline that must not change results (a restructuring, a faster path) keeps this test green;
// a change that alters results on purpose regenerates the folder and says why in its commit:
//
//   FORESTMOD_GOLDEN_RECORD=<repo>/testdata/forestmod/golden
//   build/bin/opencv_test_forestmod --gtest_filter='Forestmod_Golden.*'   (with that variable)
//
// which rewrites matches.yml.gz; the model files and scenes are rendered and trained again only
// when they are missing from that folder (delete them to renew the inputs).
//
// Inputs, all shipped: model files with the shipped ape's templates (RGB: gradient + hue; RGB-D:
// + depth normals; two distances, so two search groups) written by save(), which doubles as the
// test that older model files load and match alike; the three shipped real LM-O frames; two
// rendered RGB-D scenes. Each detector is run with 1 tree (the file's forests; also with
// exhaustive_ratio < 0, the forest path in every group), 5 trees (retrained after load) and
// exhaustively (use_forest = false); the RGB-D one also with 1 tree and the out-of-depth-range
// test (the files predate DetectorParams::depth_range_tolerance and load with it off).

#include "test_precomp.hpp"

namespace opencv_test { namespace {

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
    ASSERT_GT(det->addTemplates(ape, "ape", goldenSampler(), lmoIntrinsics(), Size(640, 480)), 40);
    det->train();
    det->save(path, true);
}

// Record mode: rendered RGB-D scenes of the ape over a smooth random texture (small files).
static void recordScenes()
{
    const Mesh ape = Mesh::load(cvtest::findDataFile("lmo_mini/models/obj_000001.ply"));
    SyntheticSceneParams sp;
    sp.color_noise = 0; // compressible; the depth keeps its sensor noise
    SceneSynthesizer synth(Renderer::create(Size(640, 480)), lmoIntrinsics(), sp);
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
    DetectionStats stats;
};

// The cases of one model: 1 tree (with and without the exhaustive search of the groups that
// reject little), 5 trees, exhaustive, on every frame of its kind.
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
    // 1tree_forest: no group goes to the exhaustive search (on the real frames the default
    // exhaustive_ratio sends them all there), so the forests' scan is recorded on those too
    const char* modes[] = { "1tree", "1tree_forest", "5trees", "exhaustive", "1tree_depth_range" };
    const DetectorParams file_params = det.getParams();
    EXPECT_LT(file_params.depth_range_tolerance, 0.f) << "files without the key: off";
    for (int mode = 0; mode < (rgbd ? 5 : 4); ++mode)
    {
        if (mode > 0)
        {
            DetectorParams p = file_params;
            if (mode == 1)
                p.exhaustive_ratio = -1.f;
            else if (mode == 4)
                p.depth_range_tolerance = DetectorParams().depth_range_tolerance;
            else
            {
                p.forest.num_trees = 5;
                p.use_forest = mode == 2;
            }
            det.setParams(p);
        }
        for (size_t k = 0; k < colors.size(); ++k)
        {
            GoldenCase c;
            c.name = cv::format("%s_%s_frame%d", kind.c_str(), modes[mode], (int)k);
            det.match(sourcesOf(det, colors[k], rgbd ? depths[k] : Mat()), 80.f, c.matches,
                      std::vector<String>(), noArray(), std::vector<Mat>(), &c.stats);
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
        // the scan (forest modes): per location its outcome, and the counters
        if (c.stats.rejection_map.empty())
            continue;
        fs << c.name + "_scan" << "{" << "rejection_map" << c.stats.rejection_map
           << "validated" << (int)c.stats.validated << "candidates" << (int)c.stats.candidates
           << "}";
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
        const FileNode scan = fs[c.name + "_scan"];
        ASSERT_EQ(c.stats.rejection_map.empty(), scan.empty()) << c.name << ": scan record";
        if (scan.empty())
            continue;
        Mat map;
        scan["rejection_map"] >> map;
        ASSERT_EQ(map.size(), c.stats.rejection_map.size()) << c.name;
        ASSERT_EQ(map.type(), c.stats.rejection_map.type()) << c.name;
        EXPECT_EQ(0, cvtest::norm(map, c.stats.rejection_map, NORM_L1))
            << c.name << ": the scan's outcome differs at "
            << countNonZero(map != c.stats.rejection_map) << " locations";
        EXPECT_EQ((int)scan["validated"], (int)c.stats.validated) << c.name;
        EXPECT_EQ((int)scan["candidates"], (int)c.stats.candidates) << c.name;
    }
}

TEST(Forestmod_Golden, match_lists_reproduce_the_recorded_ones)
{
    applyTestTag(CV_TEST_TAG_LONG);
    const std::string record = recordDir();
    if (!record.empty())
    {
        ASSERT_TRUE(utils::fs::createDirectories(record));
        if (!utils::fs::exists(goldenFile("ape_rgb.yml.gz")))
            recordModel(false, goldenFile("ape_rgb.yml.gz"));
        if (!utils::fs::exists(goldenFile("ape_rgbd.yml.gz")))
            recordModel(true, goldenFile("ape_rgbd.yml.gz"));
        if (!utils::fs::exists(goldenFile("scene0_rgb.png")))
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

namespace opencv_test { namespace {

// Automatic training is thread-safe: 4 threads calling match() on one detector that has templates
// but no trained index give the serial results.
TEST(Forestmod_Detector, concurrent_match_on_an_untrained_detector)
{
    cv::forestmod::Detector serial, shared;
    serial.load(goldenFile("ape_rgb.yml.gz"));
    shared.load(goldenFile("ape_rgb.yml.gz"));
    DetectorParams p = shared.getParams();
    p.forest.num_trees = 2; // both detectors train at their first match
    serial.setParams(p);
    shared.setParams(p);
    ASSERT_FALSE(shared.isTrained());
    std::vector<Mat> frames;
    for (const char* f : LMO_FRAMES)
        frames.push_back(imread(cvtest::findDataFile(cv::format("lmo_mini/test/000002/rgb/%s.png",
                                                                f))));
    std::vector<std::vector<linemod::Match> > expected(frames.size());
    for (size_t k = 0; k < frames.size(); ++k)
        serial.match(std::vector<Mat>(2, frames[k]), 80.f, expected[k]);
    const int threads = 4;
    std::vector<std::vector<std::vector<linemod::Match> > > got(
        threads, std::vector<std::vector<linemod::Match> >(frames.size()));
    std::vector<std::thread> pool;
    for (int t = 0; t < threads; ++t)
        pool.push_back(std::thread([&, t]() {
            for (size_t k = 0; k < frames.size(); ++k)
                shared.match(std::vector<Mat>(2, frames[(k + t) % frames.size()]), 80.f,
                             got[t][(k + t) % frames.size()]);
        }));
    for (std::thread& th : pool)
        th.join();
    EXPECT_TRUE(shared.isTrained());
    for (int t = 0; t < threads; ++t)
        for (size_t k = 0; k < frames.size(); ++k)
        {
            ASSERT_EQ(expected[k].size(), got[t][k].size()) << "thread " << t << ", frame " << k;
            for (size_t i = 0; i < expected[k].size(); ++i)
                EXPECT_TRUE(expected[k][i] == got[t][k][i]) << "thread " << t << ", frame " << k;
        }
}

// match() refuses what it cannot search, naming the argument.
TEST(Forestmod_Detector, match_preconditions)
{
    cv::forestmod::Detector det;
    det.load(goldenFile("ape_rgb.yml.gz"));
    const Mat frame = imread(cvtest::findDataFile("lmo_mini/test/000002/rgb/000224.png"));
    std::vector<linemod::Match> m;
    const float bad_thresholds[] = { -1.f, 100.5f, std::numeric_limits<float>::quiet_NaN() };
    for (float t : bad_thresholds)
    {
        try
        {
            det.match(std::vector<Mat>(2, frame), t, m);
            ADD_FAILURE() << "threshold " << t << " accepted";
        }
        catch (const cv::Exception& e)
        {
            EXPECT_NE(std::string::npos, e.err.find("threshold")) << e.err;
        }
    }
    const Mat tiny(1, 1, CV_8UC3, Scalar::all(100));
    try
    {
        det.match(std::vector<Mat>(2, tiny), 80.f, m);
        ADD_FAILURE() << "a 1x1 image accepted";
    }
    catch (const cv::Exception& e)
    {
        EXPECT_NE(std::string::npos, e.err.find("at least")) << e.err;
    }
    det.match(std::vector<Mat>(2, frame(Rect(0, 0, 16, 16)).clone()), 80.f, m); // smallest size
    // estimatePoses: a depth of another size than the matched frame is refused, not ignored
    det.match(std::vector<Mat>(2, frame), 80.f, m);
    std::vector<PoseMatch> pm;
    det.match(std::vector<Mat>(2, frame), 80.f, pm);
    ASSERT_FALSE(pm.empty());
    const Mat small_depth(40, 40, CV_16UC1, Scalar(800));
    pm.resize(1);
    pm[0].x = pm[0].box.x = 500;
    pm[0].y = pm[0].box.y = 400;
    EXPECT_THROW(det.estimatePoses(small_depth, lmoIntrinsics(), pm), cv::Exception);
}

}} // namespace
