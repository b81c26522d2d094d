// This file is part of OpenCV project.
// It is subject to the license terms in the LICENSE file found in the top-level directory
// of this distribution and at http://opencv.org/license.html

// Hostile inputs: mutated model files, bad PLY files, out-of-range parameters, degenerate
// meshes, dangling symbolic links as output paths, the inputs the fuzz targets found (fuzz/,
// scripts/fuzz.sh), and bad templates, poses and camera matrices given to the API. Each ends in
// a cv::Exception whose message names the problem.

#include "test_precomp.hpp"
#include "../samples/sample_utils.hpp"

#include <cstdio>
#include <regex>
#ifndef _WIN32
#include <unistd.h>
#endif

namespace opencv_test { namespace {

static std::string slurpFile(const std::string& path)
{
    std::ifstream f(path.c_str(), std::ios::binary);
    std::stringstream ss;
    ss << f.rdbuf();
    return ss.str();
}

static void writeFile(const std::string& path, const std::string& text)
{
    std::ofstream f(path.c_str(), std::ios::binary);
    f << text;
}

// A small shape drawn in view i (rotated, stretched), with its mask.
// runs f, which must raise a cv::Exception of `code` whose message holds `needle`
template <typename F>
static void expectRaises(F f, int code, const std::string& needle, const std::string& what)
{
    try
    {
        f();
        ADD_FAILURE() << what << ": no exception";
    }
    catch (const cv::Exception& e)
    {
        EXPECT_EQ(code, e.code) << what << ": " << e.err;
        EXPECT_NE(std::string::npos, e.err.find(needle)) << what << ": " << e.err;
    }
}

static void shapeView(int i, Mat& color, Mat& mask)
{
    color = Mat(160, 160, CV_8UC3, Scalar(0, 0, 0));
    mask = Mat::zeros(160, 160, CV_8UC1);
    const RotatedRect r(Point2f(80, 80), Size2f(70.f - 6 * i, 44.f + 5 * i), 15.f * i);
    Point2f p[4];
    r.points(p);
    std::vector<Point> poly(p, p + 4);
    fillConvexPoly(color, poly, Scalar(30, 60, 200));
    fillConvexPoly(mask, poly, Scalar(255));
    circle(color, Point(74, 86), 10, Scalar(200, 140, 20), FILLED);
}

static Mat shapeScene()
{
    Mat color, mask;
    shapeView(1, color, mask);
    Mat scene(240, 320, CV_8UC3, Scalar(60, 60, 60));
    color.copyTo(scene(Rect(70, 40, 160, 160)), mask);
    return scene;
}

// The text of a small trained LINE model (3 templates with poses), saved as plain YAML.
static std::string smallModelText()
{
    Ptr<cv::forestmod::Detector> det = getDefaultForestLINE();
    cv::forestmod::DetectorParams p = det->getParams();
    p.forest.num_trees = 1;
    det->setParams(p);
    for (int i = 0; i < 3; ++i)
    {
        Mat color, mask;
        shapeView(i, color, mask);
        CV_Assert(det->addTemplate(std::vector<Mat>(2, color), "shape", mask, Matx33d::eye(),
                                   Vec3d(0, 0, 700), Matx33d(500, 0, 80, 0, 500, 80, 0, 0, 1))
                  >= 0);
    }
    det->train();
    const std::string file = cv::tempfile(".yml");
    det->save(file);
    const std::string text = slurpFile(file);
    std::remove(file.c_str());
    return text;
}

// replaces the first match of `re` (or all) in text; the mutation must change the text
static std::string mutate(const std::string& text, const std::string& re, const std::string& by,
                          bool all = false)
{
    const std::string out = std::regex_replace(
        text, std::regex(re), by,
        all ? std::regex_constants::format_default : std::regex_constants::format_first_only);
    CV_Assert(out != text && "the mutation did not apply");
    return out;
}

// loads the text as a model file; returns the exception's message ("" when it loaded)
static std::string loadError(const std::string& text, int* num_matches = 0)
{
    const std::string file = cv::tempfile(".yml");
    writeFile(file, text);
    std::string err;
    try
    {
        cv::forestmod::Detector det;
        det.load(file);
        if (num_matches)
        {
            std::vector<linemod::Match> m;
            det.match(std::vector<Mat>(2, shapeScene()), 80.f, m);
            *num_matches = (int)m.size();
        }
    }
    catch (const cv::Exception& e)
    {
        err = e.err;
    }
    std::remove(file.c_str());
    return err;
}

TEST(Forestmod_HostileInputs, mutated_model_files_are_refused_with_the_field_named)
{
    const std::string text = smallModelText();
    int matches = 0;
    ASSERT_EQ("", loadError(text, &matches)); // the unmodified file loads and finds the shape
    EXPECT_GT(matches, 0);

    struct Case
    {
        const char* what;
        const char* re;
        const char* by;
        bool all;
        const char* needle;
    };
    const char* feature = "(features:\\s*- \\[ \\d+, \\d+, )\\d+ \\]";
    const Case cases[] = {
        // feature labels (the SIGSEGV in similarityAll of the issue) and positions
        { "label 8", feature, "$018 ]", false, "label 8, expected 0..7" },
        { "label -1", feature, "$01-1 ]", false, "label -1, expected 0..7" },
        { "label 100000", feature, "$01100000 ]", false, "label 100000, expected 0..7" },
        { "label nan", feature, "$01.nan ]", false, "not an [x, y, label] triple of integers" },
        { "label abc", feature, "$01abc ]", false, "not an [x, y, label] triple of integers" },
        { "feature x outside", "(features:\\s*- \\[ )\\d+", "$01100000", false,
          "lies outside the template" },
        { "features: [] everywhere", "features:(\\s*- \\[[^\\]]*\\])+", "features: []", true,
          "no feature at pyramid level" },
        // sizes
        { "width 0", "width: \\d+", "width: 0", false, "template size 0 x" },
        { "height -70", "height: \\d+", "height: -70", false, "template size" },
        { "width huge", "width: \\d+", "width: 100000", false, "template size 100000 x" },
        { "level width disagrees", "", "", false, "the level-0 size" }, // the 3rd width
        // template poses
        { "pose box empty", "box: \\[[^\\]]*\\]", "box: [ 0, 0, 0, 0 ]", false,
          "pose box 0 x 0" },
        { "pose box huge", "box: \\[ (\\d+), (\\d+), \\d+, \\d+ \\]",
          "box: [ $1, $2, 1000000, 1000000 ]", false, "pose box 1000000 x 1000000" },
        // fuzz finding: K(2, 2) 3e-310 put the depth modality's object centre at infinity
        { "pose K last row", "(K: !!opencv-matrix\\s*rows: 3\\s*cols: 3\\s*dt: d\\s*)"
          "data: !!binary \\|\\s*\\S+\\s*\\S+",
          "$01data: [ 500., 0., 80., 0., 500., 80., 0., 0., 3e-310 ]", false,
          "pose K's last row is (0, 0, 3e-310), expected (0, 0, 1)" },
        { "pose focal length 1e-40", "(K: !!opencv-matrix\\s*rows: 3\\s*cols: 3\\s*dt: d\\s*)"
          "data: !!binary \\|\\s*\\S+\\s*\\S+",
          "$01data: [ 1e-40, 0., 80., 0., 500., 80., 0., 0., 1. ]", false,
          "they must be at least 1 pixel" },
        { "pose centre at infinity", "(t: !!opencv-matrix\\s*rows: 3\\s*cols: 1\\s*dt: d\\s*)"
          "data: !!binary \\|\\s*\\S+", "$01data: [ 1., 0., 1e-300 ]", false,
          "beyond 1e6 pixels" },
        // parameters, through the check of setParams
        { "nms_iou -3", "nms_iou: [^\\n]*", "nms_iou: -3.", false, "nms_iou" },
        { "location_step 100000", "location_step: \\d+", "location_step: 100000", false,
          "location_step" },
        { "alpha nan", "alpha: [^\\n]*", "alpha: .nan", false, "alpha" },
        { "num_trees 10^6", "num_trees: \\d+", "num_trees: 1000000", false, "num_trees" },
        // fuzz finding: a string read as INT_MAX overflowed the exhaustive search's keep count
        { "max_survivors a string", "max_survivors: \\d+", "max_survivors: x1", false,
          "parameter 'max_survivors' must be a number" },
        { "max_survivors 2^31 - 1", "max_survivors: \\d+", "max_survivors: 2147483647", false,
          "max_survivors must be at most 64" },
        { "chunk_size 1e30", "chunk_size: \\d+", "chunk_size: 1.e+30", false,
          "parameter 'chunk_size' is out of the range of an integer" },
        { "T 0", "T: !!binary \\|\\s*\\S+", "T: [ 5, 0 ]", false,
          "T of pyramid level 1 is 0" },
        { "pyramid_levels 9, 9 values of T", "pyramid_levels: 2\\s*T: !!binary \\|\\s*\\S+",
          "pyramid_levels: 9\n   T: [ 5, 8, 8, 8, 8, 8, 8, 8, 8 ]", false,
          "pyramid_levels is 9" },
        { "weak_threshold nan", "weak_threshold: [^\\n]*", "weak_threshold: .nan", false,
          "weak_threshold" },
        // matrices whose header announces more than their data holds (fuzz finding: OpenCV
        // allocated 36 GB for the header first)
        { "patch mask rows 10^6", "(mask: !!opencv-matrix\\s*rows: )\\d+", "$011000000", false,
          "at most" },
        { "patch mask rows + 1", "", "", false, "template patch mask" },
    };
    for (size_t i = 0; i < sizeof(cases) / sizeof(cases[0]); ++i)
    {
        const Case& c = cases[i];
        std::string bad;
        if (std::string(c.what) == "level width disagrees")
        {
            // the first template of pyramid level 1 (the 3rd width) a size of its own
            size_t at = 0;
            for (int k = 0; k < 3; ++k)
                at = text.find("width: ", at + (k ? 1 : 0));
            ASSERT_NE(std::string::npos, at);
            bad = text.substr(0, at) + "width: 999" + text.substr(text.find('\n', at));
        }
        else if (std::string(c.what) == "patch mask rows + 1")
        {
            // one more row than the data holds
            std::smatch m;
            ASSERT_TRUE(std::regex_search(text, m, std::regex("mask: !!opencv-matrix\\s*rows: "
                                                              "(\\d+)")));
            const int rows = std::stoi(m[1].str());
            bad = text.substr(0, m.position(1)) + std::to_string(rows + 1)
                  + text.substr(m.position(1) + m.length(1));
        }
        else
            bad = mutate(text, c.re, c.by, c.all);
        const std::string err = loadError(bad);
        EXPECT_NE("", err) << c.what << ": loaded";
        EXPECT_NE(std::string::npos, err.find(c.needle)) << c.what << ": " << err;
    }
}

TEST(Forestmod_HostileInputs, detector_params_out_of_range_raise_naming_the_field)
{
    Ptr<cv::forestmod::Detector> det = getDefaultForestLINE();
    const cv::forestmod::DetectorParams ok = det->getParams();
    struct Case
    {
        const char* field;
        void (*set)(cv::forestmod::DetectorParams&);
    };
    const Case cases[] = {
        { "nms_iou", [](cv::forestmod::DetectorParams& p) { p.nms_iou = -3.f; } },
        { "nms_iou", [](cv::forestmod::DetectorParams& p) { p.nms_iou = 1.5f; } },
        { "nms_iou", [](cv::forestmod::DetectorParams& p) { p.nms_iou = std::nanf(""); } },
        { "location_step", [](cv::forestmod::DetectorParams& p) { p.location_step = 17; } },
        { "location_step", [](cv::forestmod::DetectorParams& p) { p.location_step = 100000; } },
        { "location_step", [](cv::forestmod::DetectorParams& p) { p.location_step = -1; } },
        { "alpha", [](cv::forestmod::DetectorParams& p) { p.alpha = std::nanf(""); } },
        { "group_size_ratio",
          [](cv::forestmod::DetectorParams& p) {
              p.group_size_ratio = std::numeric_limits<float>::infinity();
          } },
        { "auto_depth_leaf_samples",
          [](cv::forestmod::DetectorParams& p) { p.auto_depth_leaf_samples = std::nanf(""); } },
        { "depth_tolerance", [](cv::forestmod::DetectorParams& p) { p.depth_tolerance = 70000; } },
        { "depth_range_tolerance",
          [](cv::forestmod::DetectorParams& p) { p.depth_range_tolerance = std::nanf(""); } },
        { "max_survivors", [](cv::forestmod::DetectorParams& p) { p.max_survivors = 65; } },
        { "max_survivors", [](cv::forestmod::DetectorParams& p) { p.max_survivors = 0; } },
        { "num_trees", [](cv::forestmod::DetectorParams& p) { p.forest.num_trees = 1001; } },
        { "max_depth", [](cv::forestmod::DetectorParams& p) { p.forest.max_depth = 31; } },
    };
    for (size_t i = 0; i < sizeof(cases) / sizeof(cases[0]); ++i)
    {
        cv::forestmod::DetectorParams p = ok;
        cases[i].set(p);
        try
        {
            det->setParams(p);
            ADD_FAILURE() << "case " << i << " (" << cases[i].field << ") accepted";
        }
        catch (const cv::Exception& e)
        {
            EXPECT_NE(std::string::npos, e.err.find(cases[i].field)) << i << ": " << e.err;
        }
    }
    // the ends of the ranges are accepted
    cv::forestmod::DetectorParams p = ok;
    p.nms_iou = 0.f;
    EXPECT_NO_THROW(det->setParams(p));
    p.nms_iou = 1.f;
    p.location_step = 16;
    p.max_survivors = 64;
    EXPECT_NO_THROW(det->setParams(p));
    EXPECT_EQ(16, det->getParams().location_step);
}

// ---- meshes ---------------------------------------------------------------------------------

static std::string plyAscii(const std::vector<Point3f>& v, const std::vector<Vec3i>& f,
                            int declared_vertices = -1, int declared_faces = -1)
{
    std::ostringstream s;
    s << "ply\nformat ascii 1.0\nelement vertex "
      << (declared_vertices < 0 ? (int)v.size() : declared_vertices)
      << "\nproperty float x\nproperty float y\nproperty float z\nelement face "
      << (declared_faces < 0 ? (int)f.size() : declared_faces)
      << "\nproperty list uchar int vertex_indices\nend_header\n";
    for (size_t i = 0; i < v.size(); ++i)
        s << v[i].x << " " << v[i].y << " " << v[i].z << "\n";
    for (size_t i = 0; i < f.size(); ++i)
        s << "3 " << f[i][0] << " " << f[i][1] << " " << f[i][2] << "\n";
    return s.str();
}

static void tetra(std::vector<Point3f>& v, std::vector<Vec3i>& f, float scale)
{
    v.clear();
    v.push_back(Point3f(0, 0, 0) * scale);
    v.push_back(Point3f(40, 0, 0) * scale);
    v.push_back(Point3f(0, 30, 0) * scale);
    v.push_back(Point3f(0, 0, 20) * scale);
    f.clear();
    f.push_back(Vec3i(0, 2, 1));
    f.push_back(Vec3i(0, 1, 3));
    f.push_back(Vec3i(0, 3, 2));
    f.push_back(Vec3i(1, 2, 3));
}

// loads the bytes as a .ply; returns the exception's message ("" when it loaded)
static std::string meshError(const std::string& bytes, double scale = 1.0)
{
    const std::string file = cv::tempfile(".ply");
    writeFile(file, bytes);
    std::string err;
    try
    {
        Mesh::load(file, scale);
    }
    catch (const cv::Exception& e)
    {
        err = e.err;
    }
    std::remove(file.c_str());
    return err;
}

TEST(Forestmod_HostileInputs, bad_ply_files_are_refused_with_the_problem_named)
{
    std::vector<Point3f> v;
    std::vector<Vec3i> f;
    tetra(v, f, 1.f);
    ASSERT_EQ("", meshError(plyAscii(v, f))); // the good file loads

    // a header declaring 2e9 vertices fails at once, before anything is allocated
    const int64 t0 = getTickCount();
    std::string err = meshError(plyAscii(v, f, 2000000000));
    EXPECT_NE(std::string::npos, err.find("more than the limit")) << err;
    EXPECT_LT((getTickCount() - t0) / getTickFrequency(), 2.0);
    err = meshError(plyAscii(v, f, -1, 2000000000));
    EXPECT_NE(std::string::npos, err.find("more than the limit")) << err;

    // counts that disagree with the data
    err = meshError(plyAscii(v, f, -1, 2)); // fewer faces declared than present
    EXPECT_NE(std::string::npos, err.find("more data than its PLY header declares")) << err;
    err = meshError(plyAscii(v, f, -1, 6)); // more declared than present
    EXPECT_NE(std::string::npos, err.find("is truncated")) << err;
    err = meshError(plyAscii(v, f, 6)); // vertices: the faces are read as vertices
    EXPECT_NE("", err);

    // a value that is no number, a face of 1000 indices, a header line not understood
    std::string bad = plyAscii(v, f);
    bad.replace(bad.find("40 0 0"), 2, "4x");
    err = meshError(bad);
    EXPECT_NE(std::string::npos, err.find("where a number is expected")) << err;
    bad = plyAscii(v, f); // a NUL byte in a value (fuzz finding: assimp allocated 30 GB)
    bad.replace(bad.find("40 0 0"), 2, std::string("4\0", 2));
    err = meshError(bad);
    EXPECT_NE(std::string::npos, err.find("where a number is expected")) << err;
    bad = plyAscii(v, f); // beyond a float (fuzz finding: assimp allocated 7.6 GB)
    bad.replace(bad.find("40 0 0"), 2, "4e39");
    err = meshError(bad);
    EXPECT_NE(std::string::npos, err.find("holds '4e39' where a number is expected")) << err;
    bad = plyAscii(v, f);
    bad.replace(bad.rfind("3 1 2 3"), 1, "1000");
    err = meshError(bad);
    EXPECT_NE(std::string::npos, err.find("list of 1000 values")) << err;
    bad = plyAscii(v, f);
    bad.replace(bad.find("end_header"), 10, "end_head`er");
    err = meshError(bad);
    EXPECT_NE(std::string::npos, err.find("PLY header line")) << err;
    // more on a property line than its fields (fuzz finding: assimp allocated 11 GB)
    bad = plyAscii(v, f);
    bad.replace(bad.find("property float x"), 16, "property float x 05 0 255");
    err = meshError(bad);
    EXPECT_NE(std::string::npos, err.find("PLY header line 4 not understood")) << err;
    // names that are no identifiers (fuzz finding: "element 666...6vertex 4", 64 GB in assimp)
    bad = plyAscii(v, f);
    bad.replace(bad.find("element vertex"), 14, "element 666vertex");
    err = meshError(bad);
    EXPECT_NE(std::string::npos, err.find("PLY header line 3 not understood")) << err;
    bad = plyAscii(v, f);
    bad.replace(bad.find("property float y"), 16, "property float (y");
    err = meshError(bad);
    EXPECT_NE(std::string::npos, err.find("PLY header line 5 not understood")) << err;
    // lone CRs before a header keyword (fuzz finding: assimp 5.2 hangs on them)
    bad = plyAscii(v, f);
    bad.insert(bad.find("end_header"), "\r\r\r");
    err = meshError(bad);
    EXPECT_NE(std::string::npos, err.find("holds the control character 13")) << err;
    // a header that ends the file without a line end, an element without properties (fuzz
    // finding: assimp 5.2 reads forever on "element aaaaaaaaa 4\nend_header" at the end)
    err = meshError("ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nend_header");
    EXPECT_NE(std::string::npos, err.find("ends without a line break")) << err;
    err = meshError("ply\nformat ascii 1.0\nelement extra 4\nend_header\n");
    EXPECT_NE(std::string::npos, err.find("element 'extra' declares no property")) << err;

    // an ASCII element over several lines, or two on one line (fuzz finding: assimp 5.2 reads
    // line by line and took a coordinate for a face's count of -23: 32 GB)
    bad = plyAscii(v, f);
    bad.replace(bad.find("40 0 0"), 6, "40 0\n0");
    err = meshError(bad);
    EXPECT_NE(std::string::npos, err.find("PLY 'vertex' 1 is not one line of its values")) << err;
    bad = plyAscii(v, f);
    bad.replace(bad.rfind("\n3 "), 1, " ");
    err = meshError(bad);
    EXPECT_NE(std::string::npos, err.find("is not one line of its values")) << err;

    // degenerate and absurd geometry
    std::vector<Point3f> zero(4, Point3f(0, 0, 0));
    err = meshError(plyAscii(zero, f)); // assimp joins them: triangles on one vertex
    EXPECT_NE("", err);
    std::vector<Point3f> same(4, Point3f(1, 2, 3));
    Mesh m;
    m.vertices = same;
    m.faces = f;
    try
    {
        m.validate();
        ADD_FAILURE() << "a mesh of equal vertices validated";
    }
    catch (const cv::Exception& e)
    {
        EXPECT_NE(std::string::npos, e.err.find("zero extent")) << e.err;
    }
    std::vector<Point3f> line;
    for (int i = 0; i < 4; ++i)
        line.push_back(Point3f(10.f * i, 0, 0));
    err = meshError(plyAscii(line, f));
    EXPECT_NE(std::string::npos, err.find("zero area")) << err;
    err = meshError(plyAscii(v, f), 1e20);
    EXPECT_NE(std::string::npos, err.find("lies beyond")) << err;
    std::vector<Point3f> huge;
    tetra(huge, f, 1e18f);
    err = meshError(plyAscii(huge, f));
    EXPECT_NE(std::string::npos, err.find("lies beyond")) << err;
}

TEST(Forestmod_HostileInputs, binary_ply_counts_checked_against_the_data)
{
    std::vector<Point3f> v;
    std::vector<Vec3i> f;
    tetra(v, f, 1.f);
    auto binary = [&](int declared_faces, int extra_bytes) {
        std::ostringstream s;
        s << "ply\nformat binary_little_endian 1.0\nelement vertex 4\nproperty float x\n"
          << "property float y\nproperty float z\nelement face " << declared_faces
          << "\nproperty list uchar int vertex_indices\nend_header\n";
        std::string out = s.str();
        out.append((const char*)&v[0], v.size() * sizeof(Point3f));
        for (size_t i = 0; i < f.size(); ++i)
        {
            out += (char)3;
            out.append((const char*)&f[i][0], 3 * sizeof(int));
        }
        out.append(extra_bytes, '\x7f');
        return out;
    };
    ASSERT_EQ("", meshError(binary(4, 0)));
    std::string err = meshError(binary(3, 0));
    EXPECT_NE(std::string::npos, err.find("more data than its PLY header declares")) << err;
    err = meshError(binary(5, 0));
    EXPECT_NE(std::string::npos, err.find("is truncated")) << err;
    err = meshError(binary(4, 7));
    EXPECT_NE(std::string::npos, err.find("more data than its PLY header declares")) << err;
}

TEST(Forestmod_HostileInputs, addTemplates_refuses_views_without_or_covered_by_the_object)
{
    Ptr<cv::forestmod::Detector> det = getDefaultForestLINE();
    ViewSampler::Params sp = ViewSampler::Params::coarse(); // radius 800 mm
    const ViewSampler sampler(sp);
    const Matx33d K(500, 0, 160, 0, 500, 120, 0, 0, 1);
    const Size size(320, 240);
    // a normal box: templates
    EXPECT_GT(det->addTemplates(closedCube(50.f), "box", sampler, K, size), 0);
    // far too small to give features
    try
    {
        det->addTemplates(closedCube(0.005f), "speck", sampler, K, size);
        ADD_FAILURE() << "a box of 0.01 mm gave templates";
    }
    catch (const cv::Exception& e)
    {
        // the renderer gives it one pixel: no features, no template of any view
        EXPECT_NE(std::string::npos, e.err.find("none of the 6 rendered views gave a template"))
            << e.err;
    }
    // the camera 100 mm in front of a 1400 mm box: it covers the frame
    try
    {
        det->addTemplates(closedCube(700.f), "wall", sampler, K, size);
        ADD_FAILURE() << "a box covering the frame gave templates";
    }
    catch (const cv::Exception& e)
    {
        EXPECT_NE(std::string::npos, e.err.find("covers the whole")) << e.err;
    }
    std::vector<String> ids = det->classIds();
    EXPECT_EQ(1u, ids.size()); // no template of the refused classes
}

// ---- output paths -----------------------------------------------------------------------------

#ifndef _WIN32
TEST(Forestmod_HostileInputs, dangling_symlink_output_is_not_written_through)
{
    const std::string target = cv::tempfile(".yml");
    const std::string link = cv::tempfile(".yml");
    ASSERT_EQ(0, symlink(target.c_str(), link.c_str()));
    ASSERT_FALSE(utils::fs::exists(target));

    Ptr<cv::forestmod::Detector> det = getDefaultForestLINE();
    Mat color, mask;
    shapeView(0, color, mask);
    ASSERT_GE(det->addTemplate(std::vector<Mat>(2, color), "shape", mask), 0);
    for (int overwrite = 0; overwrite < 2; ++overwrite)
    {
        try
        {
            det->save(link, overwrite != 0);
            ADD_FAILURE() << "saved through a dangling link (overwrite " << overwrite << ")";
        }
        catch (const cv::Exception& e)
        {
            EXPECT_NE(std::string::npos, e.err.find("dangling symbolic link")) << e.err;
        }
        EXPECT_FALSE(utils::fs::exists(target));
    }

    // nor writeClasses (the link is its file for the class "shape")
    const std::string fmt = link.substr(0, link.size() - 4) + "%s.yml";
    ASSERT_EQ(0, std::rename(link.c_str(), cv::format(fmt.c_str(), "shape").c_str()));
    expectRaises([&] { det->writeClasses(fmt); }, Error::StsError, "dangling symbolic link",
                 "writeClasses");
    EXPECT_FALSE(utils::fs::exists(target));
    ASSERT_EQ(0, std::rename(cv::format(fmt.c_str(), "shape").c_str(), link.c_str()));

    // nor does the BOP results writer write through it
    for (int overwrite = 0; overwrite < 2; ++overwrite)
        EXPECT_THROW(cv::forestmod::BopResultWriter(link, overwrite != 0), cv::Exception);
    EXPECT_FALSE(utils::fs::exists(target));

    // the samples' check (every sample's output path, --force or not)
    EXPECT_TRUE(cv::forestmod::samples::isDanglingSymlink(link));
    EXPECT_TRUE(cv::forestmod::samples::refuseOutput("test", link, true));
    EXPECT_TRUE(cv::forestmod::samples::refuseOutput("test", link, false));
    EXPECT_FALSE(cv::forestmod::samples::refuseOutput("test", target, false)); // a new file
    writeFile(target, "x");
    EXPECT_FALSE(cv::forestmod::samples::isDanglingSymlink(link));
    EXPECT_TRUE(cv::forestmod::samples::refuseOutput("test", target, false)); // exists, no --force
    EXPECT_FALSE(cv::forestmod::samples::refuseOutput("test", target, true));
    std::remove(target.c_str());

    // and a sample end to end: forestmod_hue refuses the link, with --force too
    const std::string exe = testBinaryDir() + "/forestmod_hue";
    if (utils::fs::exists(exe))
    {
        const std::string input = cv::tempfile(".png");
        ASSERT_TRUE(imwrite(input, color));
        const std::string link_png = cv::tempfile(".png"), target_png = cv::tempfile(".png");
        ASSERT_EQ(0, symlink(target_png.c_str(), link_png.c_str()));
        const std::string cmd = "'" + exe + "' '" + input + "' '" + link_png + "' --force "
                                + "> /dev/null 2>&1";
        EXPECT_NE(0, std::system(cmd.c_str()));
        EXPECT_FALSE(utils::fs::exists(target_png));
        std::remove(link_png.c_str());
        std::remove(input.c_str());
    }
    std::remove(link.c_str());
}
#endif

// ---- the fuzz targets' seeds and findings ---------------------------------------------------

// A model file's brackets must balance and its YAML directive stand alone on the first line
// (OpenCV's YAML parser hangs on a stray ']' followed by an unclosed '[', and on some files with
// more on the directive's line): refused when they do not, while brackets, quotes and '#' inside class ids, in
// YAML, JSON and XML, still load.
TEST(Forestmod_HostileInputs, model_file_brackets)
{
    const std::string text = smallModelText();
    EXPECT_NE(std::string::npos, loadError(text + "\n]\n").find("closes no open bracket"));
    EXPECT_NE(std::string::npos, loadError(text + "\nextra: [ 1, 2\n").find("bracket is open"));
    EXPECT_NE(std::string::npos,
              loadError(mutate(text, "pyramid_levels: 2", "pyramid_levels: [ 2 }"))
                  .find("closes no open bracket"));
    EXPECT_NE(std::string::npos,
              loadError(mutate(text, "%YAML:1.0", "%YAML:1.0 - [ 7 ]")).find("directive alone"));
    EXPECT_EQ("", loadError(mutate(text, "%YAML:1.0", "%YAML:1.0  ")));
    // a dedent to a level no block opened (fuzz finding: OpenCV 4.6's parser loops forever)
    EXPECT_NE(std::string::npos,
              loadError("%YAML:1.0\n      - [ 10, 1, 4 ]\n   -\n      templates:\n")
                  .find("line 3 is indented to a level no enclosing YAML block has"));
    EXPECT_NE(std::string::npos,
              loadError("%YAML:1.0\n   T: 1\n...      - [ 35, 15, 0 ]\n")
                  .find("line 3 holds more than the YAML document marker '...'"));
    EXPECT_NE(std::string::npos, loadError(mutate(text, "pyramid_levels: 2", "pyramid_levels:\r 2"))
                                     .find("holds a carriage return inside it"));
    EXPECT_EQ("", loadError(mutate(text, "pyramid_levels: 2", "pyramid_levels: 2\r")));

    const char* formats[] = { ".yml", ".json", ".xml" };
    for (int f = 0; f < 3; ++f)
    {
        Ptr<cv::forestmod::Detector> det = getDefaultForestLINE();
        Mat color, mask;
        shapeView(0, color, mask);
        const std::string id = "it's [a] {b} #1 \"q\" ]";
        ASSERT_GE(det->addTemplate(std::vector<Mat>(2, color), id, mask), 0);
        const std::string file = cv::tempfile(formats[f]);
        det->save(file);
        cv::forestmod::Detector loaded;
        EXPECT_NO_THROW(loaded.load(file)) << formats[f];
        ASSERT_EQ(1u, loaded.classIds().size()) << formats[f];
        EXPECT_EQ(id, loaded.classIds()[0]) << formats[f];
        std::remove(file.c_str());
    }
}

TEST(Forestmod_HostileInputs, fuzz_seeds_load_and_fuzz_findings_are_refused)
{
    const std::string root = cvtest::findDataFile("fuzz/README.md");
    const std::string dir = root.substr(0, root.find_last_of('/'));
    std::vector<String> seeds;
    utils::fs::glob(dir + "/model", "*", seeds);
    ASSERT_GE(seeds.size(), 3u);
    for (size_t i = 0; i < seeds.size(); ++i)
    {
        cv::forestmod::Detector det;
        EXPECT_NO_THROW(det.load(seeds[i])) << seeds[i];
        EXPECT_GT(det.numTemplates(), 0) << seeds[i];
    }
    seeds.clear();
    utils::fs::glob(dir + "/mesh", "*", seeds);
    ASSERT_GE(seeds.size(), 3u);
    for (size_t i = 0; i < seeds.size(); ++i)
        EXPECT_EQ(4u, Mesh::load(seeds[i]).vertices.size()) << seeds[i];

    // every input a fuzz target stopped on (crash, hang, allocation, undefined behaviour):
    // a clean error now, or (match_*: a valid model) a clean match
    std::vector<String> found;
    utils::fs::glob(dir + "/regressions", "*", found);
    ASSERT_GE(found.size(), 4u);
    for (size_t i = 0; i < found.size(); ++i)
    {
        if (found[i].find("/match_") != std::string::npos)
        {
            cv::forestmod::Detector det;
            ASSERT_NO_THROW(det.load(found[i])) << found[i];
            std::vector<Mat> sources;
            Mat depth(96, 128, CV_16UC1, Scalar(800));
            rectangle(depth, Rect(30, 20, 50, 40), Scalar(760), FILLED);
            for (size_t m = 0; m < det.getModalities().size(); ++m)
                sources.push_back(det.getModalities()[m]->name() == "DepthNormal"
                                      ? depth : Mat(shapeScene(), Rect(0, 0, 128, 96)));
            std::vector<linemod::Match> matches;
            EXPECT_NO_THROW(det.match(sources, 50.f, matches)) << found[i];
            continue;
        }
        const bool model = found[i].find("/model_") != std::string::npos;
        // a model file goes through every reader of model-like files: Detector::load,
        // Detector::readClasses (a cv::linemod class file) and TemplateForest::load
        for (int reader = 0; reader < (model ? 3 : 1); ++reader)
        {
            try
            {
                if (!model)
                    Mesh::load(found[i]);
                else if (reader == 0)
                {
                    cv::forestmod::Detector det;
                    det.load(found[i]);
                }
                else if (reader == 1)
                {
                    cv::forestmod::Detector det;
                    det.readClasses(std::vector<String>(1, "x"), found[i]);
                }
                else
                    cv::forestmod::TemplateForest::load(found[i]);
                ADD_FAILURE() << found[i] << " loaded (reader " << reader << ")";
            }
            catch (const cv::Exception& e)
            {
                EXPECT_FALSE(e.err.empty()) << found[i];
            }
        }
    }
}

// ---- the public API's own inputs ------------------------------------------------------------

// addSyntheticTemplate and addTemplate refuse what load() refuses (a label the search indexes
// out of bounds crashed match(); a pose that load() refuses made a model that could be saved but
// not loaded), and add nothing then
TEST(Forestmod_HostileInputs, templates_added_are_checked_as_loaded_ones)
{
    Ptr<cv::forestmod::Detector> det = getDefaultForestLINE();
    Mat color, mask;
    shapeView(1, color, mask); // the view of shapeScene()
    const Matx33d K(500, 0, 80, 0, 500, 80, 0, 0, 1);
    const std::vector<Mat> src(2, color);
    ASSERT_GE(det->addTemplate(src, "shape", mask, Matx33d::eye(), Vec3d(0, 0, 700), K), 0);
    const std::vector<linemod::Template> good = det->getTemplates("shape", 0);
    ASSERT_GE(det->addSyntheticTemplate(good, "copy"), 0); // the same templates are accepted
    std::vector<linemod::Template> bad = good;
    ASSERT_FALSE(bad[0].features.empty());
    bad[0].features[0].label = 200;
    expectRaises([&] { det->addSyntheticTemplate(bad, "bad"); }, Error::StsBadArg,
                 "label 200, expected 0..7", "label 200");
    bad = good;
    bad.back().features.back().x = 100000;
    expectRaises([&] { det->addSyntheticTemplate(bad, "bad"); }, Error::StsBadArg,
                 "lies outside the template", "feature x 100000");
    expectRaises([&] { det->addTemplate(src, "shape", mask, Matx33d::eye(), Vec3d(0, 0, 0), K); },
                 Error::StsBadArg, "t_z is 0 mm", "t_z 0");
    expectRaises([&] { det->addTemplate(src, "shape", mask, Matx33d::eye(), Vec3d(0, 0, 700),
                                        Matx33d()); },
                 Error::StsBadArg, "focal lengths 0, 0", "K 0");
    EXPECT_EQ(2, det->numTemplates());
    EXPECT_EQ(1, det->numTemplates("shape"));
    std::vector<linemod::Match> m;
    EXPECT_NO_THROW(det->match(std::vector<Mat>(2, shapeScene()), 80.f, m));
    EXPECT_FALSE(m.empty());
}

// a model file that fails to load leaves the detector as it was (its templates, training and
// meshes), not half replaced by the file's first classes
TEST(Forestmod_HostileInputs, failed_load_leaves_the_detector_unchanged)
{
    const std::string text = smallModelText();
    cv::forestmod::Detector det;
    const std::string file = cv::tempfile(".yml");
    writeFile(file, text);
    det.load(file);
    const std::vector<Mat> scene(2, shapeScene());
    std::vector<linemod::Match> before, after;
    det.match(scene, 80.f, before);
    ASSERT_FALSE(before.empty());
    ASSERT_TRUE(det.isTrained());
    const cv::forestmod::DetectorParams params = det.getParams();

    // two classes: the first as in the file, a copy of it named "broken" with a label of 9
    const size_t at = text.find("classes:");
    ASSERT_NE(std::string::npos, at);
    const size_t first = text.find("\n   -", at);
    const size_t forest = text.find("\nforest", at);
    ASSERT_NE(std::string::npos, first);
    ASSERT_NE(std::string::npos, forest);
    std::string cls = text.substr(first, forest - first);
    cls = std::regex_replace(cls, std::regex("class_id: \"?shape\"?"), "class_id: broken",
                             std::regex_constants::format_first_only);
    cls = mutate(cls, "(features:\\s*- \\[ \\d+, \\d+, )\\d+ \\]", "$019 ]");
    const std::string two = text.substr(0, forest) + cls + text.substr(forest);
    writeFile(file, two);
    expectRaises([&] { det.load(file); }, Error::StsParseError, "label 9, expected 0..7",
                 "broken second class");
    std::remove(file.c_str());
    EXPECT_EQ(1, det.numClasses());
    EXPECT_EQ(3, det.numTemplates());
    EXPECT_TRUE(det.isTrained());
    EXPECT_EQ(params.forest.num_trees, det.getParams().forest.num_trees);
    det.match(scene, 80.f, after);
    ASSERT_EQ(before.size(), after.size());
    for (size_t i = 0; i < before.size(); ++i)
        EXPECT_TRUE(before[i] == after[i]) << i;
}

// the class files' format holds one %s and no other conversion: cv::linemod hands it to sprintf,
// which reads arguments that are not there for another one
TEST(Forestmod_HostileInputs, class_file_formats)
{
    Ptr<cv::forestmod::Detector> det = getDefaultForestLINE();
    Mat color, mask;
    shapeView(0, color, mask);
    ASSERT_GE(det->addTemplate(std::vector<Mat>(2, color), "shape", mask), 0);
    const std::string dir = cv::tempfile("_classes");
    ASSERT_TRUE(utils::fs::createDirectory(dir));
    const std::vector<String> ids(1, "shape");
    const char* bad[] = { "%s_%s.yml", "%d.yml", "%n%s.yml", "class.yml", "%s_100%.yml" };
    for (const char* b : bad)
    {
        expectRaises([&] { det->writeClasses(dir + "/" + b); }, Error::StsBadArg,
                     "must hold one %s", b);
        expectRaises([&] { det->readClasses(ids, dir + "/" + b); }, Error::StsBadArg,
                     "must hold one %s", b);
    }
    std::vector<cv::String> written;
    utils::fs::glob_relative(dir, "*", written);
    EXPECT_TRUE(written.empty()) << "nothing written";
    // checked before any class: also with no class, or no class id
    expectRaises([&] { getDefaultForestLINE()->writeClasses(dir + "/%d.yml"); }, Error::StsBadArg,
                 "must hold one %s", "no class");
    expectRaises([&] { det->readClasses(std::vector<String>(), dir + "/%d.yml"); },
                 Error::StsBadArg, "must hold one %s", "no class id");
    const std::string good = dir + "/100%%_%s.yml";
    det->writeClasses(good);
    ASSERT_TRUE(utils::fs::exists(dir + "/100%_shape.yml"));
    Ptr<cv::forestmod::Detector> back = getDefaultForestLINE();
    back->readClasses(ids, good);
    EXPECT_EQ(1, back->numTemplates("shape"));
    utils::fs::remove_all(dir);
}

// a copy of a detector is independent, as a copy of cv::linemod::Detector is (it shared the
// original's search index: templates added to the copy made the original's match() fail an
// internal assertion)
TEST(Forestmod_HostileInputs, copies_of_a_detector_are_independent)
{
    const std::string file = cv::tempfile(".yml");
    writeFile(file, smallModelText());
    cv::forestmod::Detector det;
    det.load(file);
    std::remove(file.c_str());
    const std::vector<Mat> scene(2, shapeScene());
    std::vector<linemod::Match> before, m;
    det.match(scene, 80.f, before);
    ASSERT_FALSE(before.empty());
    cv::forestmod::Mesh tetra;
    tetra.vertices = { Point3f(0, 0, 0), Point3f(40, 0, 0), Point3f(0, 40, 0), Point3f(0, 0, 40) };
    tetra.faces = { Vec3i(0, 2, 1), Vec3i(0, 1, 3), Vec3i(0, 3, 2), Vec3i(1, 2, 3) };
    det.setMesh("shape", tetra);
    cv::forestmod::Detector copy = det;
    EXPECT_TRUE(copy.isTrained()) << "the trained forests are copied";
    EXPECT_TRUE(copy.hasMesh("shape")) << "and the meshes";
    copy = copy; // self-assignment changes nothing
    EXPECT_EQ(3, copy.numTemplates());
    EXPECT_TRUE(copy.hasMesh("shape"));
    copy.match(scene, 80.f, m);
    ASSERT_EQ(before.size(), m.size());
    Mat color, mask;
    shapeView(1, color, mask);
    ASSERT_GE(copy.addTemplate(std::vector<Mat>(2, color), "other", mask), 0);
    cv::forestmod::DetectorParams p = copy.getParams();
    p.nms_iou = 0.f;
    copy.setParams(p);
    EXPECT_EQ(4, copy.numTemplates());
    EXPECT_EQ(3, det.numTemplates());
    EXPECT_TRUE(det.isTrained());
    EXPECT_NE(p.nms_iou, det.getParams().nms_iou);
    ASSERT_NO_THROW(det.match(scene, 80.f, m));
    ASSERT_EQ(before.size(), m.size());
    for (size_t i = 0; i < before.size(); ++i)
        EXPECT_TRUE(before[i] == m[i]) << i;
    ASSERT_NO_THROW(copy.match(scene, 80.f, m));
    EXPECT_GT(m.size(), before.size());
    // assignment: the same, and the assigned-to detector's own state is gone
    Ptr<cv::forestmod::Detector> assigned = getDefaultForestLINE();
    *assigned = copy;
    EXPECT_EQ(4, assigned->numTemplates());
    EXPECT_EQ(2, assigned->numClasses());
    EXPECT_EQ(0.f, assigned->getParams().nms_iou);
    copy.setMesh("other", tetra);
    EXPECT_FALSE(det.hasMesh("other"));
    *assigned = det;
    EXPECT_EQ(3, assigned->numTemplates());
    EXPECT_TRUE(assigned->hasMesh("shape"));
    EXPECT_FALSE(assigned->hasMesh("other"));
    EXPECT_EQ(4, copy.numTemplates());
    ASSERT_NO_THROW(assigned->match(scene, 80.f, m));
    EXPECT_EQ(before.size(), m.size());
}

// camera matrices: a NaN principal point is refused (it gave poses that never left the
// template's own and scores of 0), and a sampler of more poses than an int counts raises
TEST(Forestmod_HostileInputs, camera_matrices_and_sampler_sizes)
{
    const Matx33d K(572.4, 0, 325.3, 0, 573.6, 242.0, 0, 0, 1);
    for (int entry = 0; entry < 4; ++entry)
    {
        Matx33d bad = K;
        const int at[4] = { 2, 5, 0, 1 }; // cx, cy, fx, skew
        bad.val[at[entry]] = std::numeric_limits<double>::quiet_NaN();
        Matx33d R;
        Vec3d t;
        expectRaises([&] { cv::forestmod::initialPose(Matx33d::eye(), Vec3d(0, 0, 700), K,
                                                      Point2d(80, 80), bad, Point2d(320, 240),
                                                      700.0, R, t); },
                     Error::StsBadArg, "finite",
                     "initialPose, K entry " + std::to_string(at[entry]));
    }
    cv::forestmod::Detector det;
    const std::string file = cv::tempfile(".yml");
    writeFile(file, smallModelText());
    det.load(file);
    std::remove(file.c_str());
    Matx33d nan_cx = K;
    nan_cx(0, 2) = std::numeric_limits<double>::quiet_NaN();
    std::vector<cv::forestmod::PoseMatch> found;
    expectRaises([&] { det.detect(std::vector<Mat>(2, shapeScene()), nan_cx, 80.f, found); },
                 Error::StsBadArg, "finite", "detect, cx NaN");

    cv::forestmod::ViewSampler::Params vp;
    vp.level = 6;
    vp.inplane_min = -180;
    vp.inplane_max = 180;
    vp.inplane_step = 0.1;
    vp.radii.assign(30, 700.0);
    const cv::forestmod::ViewSampler sampler(vp);
    expectRaises([&] { sampler.size(); }, Error::StsOutOfRange, "more than an int counts",
                 "sampler size");
}


// a detector refuses at construction what load() refuses, so that every detector made can be
// saved and loaded again (T beyond 64 overflowed the pyramid's size check and ended in
// std::bad_alloc in match()); templates need a class id, a rotation and a pinhole K; a sampler
// without a pose raises and leaves no mesh behind
TEST(Forestmod_HostileInputs, detectors_and_templates_refuse_what_load_refuses)
{
    const std::vector<Ptr<linemod::Modality> > mods(1, makePtr<linemod::ColorGradient>());
    expectRaises([&] { cv::forestmod::Detector d(mods, std::vector<int>{ 5, 1 << 30 }); },
                 Error::StsBadArg, "T of pyramid level 1 is 1073741824, expected 1..64",
                 "T 2^30");
    expectRaises([&] { cv::forestmod::Detector d(mods, std::vector<int>(9, 4)); },
                 Error::StsBadArg, "pyramid_levels is 9, expected 1..8", "9 levels");
    expectRaises([&] { cv::forestmod::Detector d(std::vector<Ptr<linemod::Modality> >(
                                                     9, makePtr<linemod::ColorGradient>()),
                                                 std::vector<int>{ 5, 8 }); },
                 Error::StsBadArg, "9 modalities, at most 8", "9 modalities");
    expectRaises([&] { cv::forestmod::Detector d(std::vector<Ptr<linemod::Modality> >(
                           1, makePtr<linemod::ColorGradient>(
                                  std::numeric_limits<float>::quiet_NaN(), 63, 55.f)),
                                                 std::vector<int>{ 5, 8 }); },
                 Error::StsBadArg, "weak_threshold nan", "weak_threshold NaN");
    const std::string file = cv::tempfile(".yml");
    expectRaises([&] { cv::forestmod::Detector().save(file); }, Error::StsError,
                 "has no modalities", "save of a default-constructed detector");

    Ptr<cv::forestmod::Detector> det = getDefaultForestLINE();
    Mat color, mask;
    shapeView(1, color, mask);
    const Matx33d K(500, 0, 80, 0, 500, 80, 0, 0, 1);
    const std::vector<Mat> src(2, color);
    expectRaises([&] { det->addTemplate(src, "", mask); }, Error::StsBadArg,
                 "class_id must not be empty", "addTemplate, empty class id");
    expectRaises([&] { det->addTemplate(src, "shape", mask, Matx33d::zeros(), Vec3d(0, 0, 700),
                                        K); },
                 Error::StsBadArg, "pose R is not a rotation", "addTemplate, R = 0");
    expectRaises([&] { det->addTemplate(src, "shape", mask, Matx33d::diag(Vec3d(100, 1, 1)),
                                        Vec3d(0, 0, 700), K); },
                 Error::StsBadArg, "pose R is not a rotation", "addTemplate, R = diag(100, 1, 1)");
    Matx33d K10 = K;
    K10(1, 0) = 3;
    expectRaises([&] { det->addTemplate(src, "shape", mask, Matx33d::eye(), Vec3d(0, 0, 700),
                                        K10); },
                 Error::StsBadArg, "pose K(1, 0) is 3", "addTemplate, K(1, 0) = 3");
    ASSERT_GE(det->addTemplate(src, "shape", mask, Matx33d::eye(), Vec3d(0, 0, 700), K), 0);
    expectRaises([&] { det->addSyntheticTemplate(det->getTemplates("shape", 0), ""); },
                 Error::StsBadArg, "class_id must not be empty", "addSyntheticTemplate, no id");
    EXPECT_EQ(1, det->numTemplates());

    cv::forestmod::ViewSampler::Params vp = cv::forestmod::ViewSampler::Params::coarse();
    vp.min_elevation = 85; // no view of the subdivided icosahedron between 85 and 86 degrees
    vp.max_elevation = 86;
    const cv::forestmod::ViewSampler empty(vp);
    ASSERT_EQ(0, empty.size());
    expectRaises([&] { det->addTemplates(closedCube(30), "cube", empty, K, Size(160, 160)); },
                 Error::StsBadArg, "the sampler gives no pose", "addTemplates, no pose");
    EXPECT_FALSE(det->hasMesh("cube"));
    EXPECT_EQ(1, det->numTemplates());
}

// non-finite poses and parameters raise instead of giving NaN poses, ranked hypotheses, empty
// depth images or unparsable result files; template ids that overflowed the forest's tables
// (a write out of bounds) are refused
TEST(Forestmod_HostileInputs, non_finite_poses_and_parameters_raise)
{
    const double nan = std::numeric_limits<double>::quiet_NaN();
    const Matx33d K(500, 0, 80, 0, 500, 80, 0, 0, 1);
    Matx33d R, R_nan = Matx33d::eye();
    R_nan(0, 1) = nan;
    Vec3d t;
    expectRaises([&] { cv::forestmod::initialPose(R_nan, Vec3d(0, 0, 700), K, Point2d(80, 80), K,
                                                  Point2d(90, 90), 0, R, t); },
                 Error::StsBadArg, "initialPose: the template's pose (R_t, t_t) has entries",
                 "initialPose, R_t NaN");
    expectRaises([&] { cv::forestmod::initialPose(Matx33d::eye(), Vec3d(nan, 0, 700), K,
                                                  Point2d(80, 80), K, Point2d(90, 90), 0, R,
                                                  t); },
                 Error::StsBadArg, "not finite", "initialPose, t_t NaN");
    expectRaises([&] { cv::forestmod::initialPose(Matx33d::zeros(), Vec3d(0, 0, 700), K,
                                                  Point2d(80, 80), K, Point2d(90, 90), 0, R,
                                                  t); },
                 Error::StsBadArg, "is not a rotation", "initialPose, R_t = 0");

    const Mat depth(160, 160, CV_16UC1, Scalar(800));
    std::vector<Point3f> pts;
    for (int i = 0; i < 100; ++i)
        pts.push_back(Point3f((float)(i % 10) * 3, (float)(i / 10) * 3, 0.f));
    expectRaises([&] { cv::forestmod::refineICP(pts, depth, K, Matx33d::eye(),
                                                Vec3d(nan, 0, 800)); },
                 Error::StsBadArg, "R0 and t0 must be finite", "refineICP, t0 NaN");
    expectRaises([&] { cv::forestmod::modelPointsFromDepth(depth, K, R_nan, Vec3d(0, 0, 0)); },
                 Error::StsBadArg, "modelPointsFromDepth: the pose (R, t) has entries",
                 "modelPointsFromDepth, R NaN");
    expectRaises([&] { cv::forestmod::sceneDepthFromFeatures(
                           depth, std::vector<Point>(5, Point(10, 10)),
                           std::vector<float>(5, 790.f),
                           std::numeric_limits<double>::infinity()); },
                 Error::StsBadArg, "template_center_depth must be finite",
                 "sceneDepthFromFeatures, centre depth inf");
    std::vector<Point3f> bad_pts = pts;
    bad_pts[3].y = std::numeric_limits<float>::quiet_NaN();
    expectRaises([&] { cv::forestmod::refineICP(bad_pts, depth, K, Matx33d::eye(),
                                                Vec3d(0, 0, 800)); },
                 Error::StsBadArg, "model point 3 is not finite", "refineICP, point NaN");

    Mesh nan_cube = closedCube(30);
    nan_cube.vertices[5].y = std::numeric_limits<float>::quiet_NaN();
    expectRaises([&] { nan_cube.diameter(); }, Error::StsBadArg, "vertex 5 is not finite",
                 "Mesh::diameter, NaN vertex");
    expectRaises([&] { nan_cube.center(); }, Error::StsBadArg, "vertex 5 is not finite",
                 "Mesh::center, NaN vertex");

    Ptr<cv::forestmod::Detector> det = getDefaultForestLINE();
    det->setMesh("cube", closedCube(30));
    cv::forestmod::PoseMatch m;
    m.class_id = "cube";
    m.has_pose = true;
    m.R = R_nan;
    m.t = Vec3d(0, 0, 700);
    std::vector<cv::forestmod::PoseMatch> hyp(1, m);
    expectRaises([&] { det->verify(shapeScene(), noArray(), K, hyp); }, Error::StsBadArg,
                 "the pose of match 0 (has_pose set) has entries that are not finite",
                 "verify, R NaN");

    cv::forestmod::PoseParams pp;
    pp.min_depth_agreement = nan;
    std::vector<cv::forestmod::PoseMatch> none;
    expectRaises([&] { det->estimatePoses(depth, K, none, pp); }, Error::StsOutOfRange,
                 "min_depth_agreement is nan", "PoseParams::min_depth_agreement NaN");
    cv::forestmod::EdgeRefineParams ep;
    cv::forestmod::EdgeMaps maps;
    ep.search_steps = 100000;
    expectRaises([&] { cv::forestmod::computeEdgeMaps(shapeScene(), maps, ep); },
                 Error::StsOutOfRange, "search_steps in [0, 20]", "search_steps 100000");
    ep = cv::forestmod::EdgeRefineParams();
    ep.max_distance = std::numeric_limits<double>::infinity();
    expectRaises([&] { cv::forestmod::computeEdgeMaps(shapeScene(), maps, ep); },
                 Error::StsOutOfRange, "max_distance must be finite", "max_distance inf");

    Matx33d Rv;
    Vec3d tv;
    expectRaises([&] { cv::forestmod::ViewSampler::lookAt(Point3d(nan, 0, 0), Vec3d(0, 0, 1),
                                                          700, 0, Rv, tv); },
                 Error::StsBadArg, "center must be finite", "lookAt, centre NaN");
    expectRaises([&] { cv::forestmod::ViewSampler::lookAt(Point3d(0, 0, 0), Vec3d(0, 0, 1),
                                                          700, nan, Rv, tv); },
                 Error::StsError, "inplane_deg must be finite", "lookAt, in-plane NaN");
    expectRaises([&] { cv::forestmod::ViewSampler::lookAt(
                           Point3d(0, 0, 0), Vec3d(0, 0, 1),
                           std::numeric_limits<double>::infinity(), 0, Rv, tv); },
                 Error::StsError, "radius must be positive and finite", "lookAt, radius inf");

    Mat q;
    expectRaises([&] { cv::forestmod::quantizeHue(shapeScene(), q, -5, 300); },
                 Error::StsOutOfRange, "must be in [0, 255]", "quantizeHue thresholds");

    Ptr<cv::forestmod::TemplateForest> forest = cv::forestmod::TemplateForest::create();
    Mat desc(2, 8, CV_8UC1, Scalar(1)), fg(2, 8, CV_8UC1, Scalar(1));
    desc.at<uchar>(1, 0) = 2;
    const Mat ids = (Mat_<int>(2, 1) << 0, std::numeric_limits<int>::max());
    expectRaises([&] { forest->train(desc, fg, ids); }, Error::StsBadArg,
                 "template_ids[1] = 2147483647 is outside", "forest ids INT_MAX");

    TempDir dir;
    const std::string csv = dir.path + "/results.csv";
    {
        cv::forestmod::BopResultWriter w(csv);
        expectRaises([&] { w.write(2, 3, 1, nan, Matx33d::eye(), Vec3d(0, 0, 700)); },
                     Error::StsBadArg, "must be finite", "BopResultWriter, score NaN");
        w.write(2, 3, 1, 0.5, Matx33d::eye(), Vec3d(0, 0, 700));
    }
    const std::string written = slurpFile(csv);
    EXPECT_EQ(std::string::npos, written.find("nan")) << written;
    EXPECT_NE(std::string::npos, written.find("2,3,1,0.5,")) << written;

    cv::forestmod::Frame frame;
    frame.depth_path = dir.path + "/depth.png";
    ASSERT_TRUE(imwrite(frame.depth_path, depth));
    frame.depth_scale = nan;
    expectRaises([&] { frame.depth(); }, Error::StsBadArg, "depth_scale is nan",
                 "Frame::depth, scale NaN");
    frame.depth_scale = -1;
    expectRaises([&] { frame.depth(); }, Error::StsBadArg, "depth_scale is -1",
                 "Frame::depth, scale -1");
    frame.depth_scale = 0.5;
    EXPECT_EQ(400, frame.depth().at<ushort>(0, 0));
}

// SceneSynthesizer's parameters: NaN noise gave a depth image without a pixel, a dropout of 3 an
// empty one and a jitter of 5 an object behind the camera, all without an error
TEST(Forestmod_HostileInputs, scene_synthesizer_parameters_are_checked)
{
    Ptr<cv::forestmod::Renderer> r = cv::forestmod::Renderer::create(Size(64, 48));
    const Matx33d K(60, 0, 32, 0, 60, 24, 0, 0, 1);
    struct Case
    {
        const char* name;
        double cv::forestmod::SyntheticSceneParams::*field;
        double value;
        const char* needle;
    };
    const double nan = std::numeric_limits<double>::quiet_NaN();
    const Case cases[] = {
        { "depth_noise NaN", &cv::forestmod::SyntheticSceneParams::depth_noise, nan,
          "depth_noise is nan" },
        { "depth_dropout 3", &cv::forestmod::SyntheticSceneParams::depth_dropout, 3,
          "depth_dropout is 3" },
        { "distance_jitter 5", &cv::forestmod::SyntheticSceneParams::distance_jitter, 5,
          "distance_jitter is 5" },
        { "max_perturbation_deg -1", &cv::forestmod::SyntheticSceneParams::max_perturbation_deg,
          -1, "max_perturbation_deg is -1" },
        { "plane_offset inf", &cv::forestmod::SyntheticSceneParams::plane_offset,
          std::numeric_limits<double>::infinity(), "plane_offset is inf" },
        { "color_noise NaN", &cv::forestmod::SyntheticSceneParams::color_noise, nan,
          "color_noise is nan" },
    };
    for (size_t i = 0; i < sizeof(cases) / sizeof(cases[0]); ++i)
    {
        cv::forestmod::SyntheticSceneParams p;
        p.*(cases[i].field) = cases[i].value;
        expectRaises([&] { cv::forestmod::SceneSynthesizer s(r, K, p); }, Error::StsOutOfRange,
                     cases[i].needle, cases[i].name);
    }
    EXPECT_NO_THROW(cv::forestmod::SceneSynthesizer(r, K, cv::forestmod::SyntheticSceneParams()));
    // the renderer draws without skew: a K with one (or another last row) was drawn as if it had
    // none
    const int h = r->addMesh(closedCube(30));
    Mat color;
    for (int entry = 0; entry < 3; ++entry)
    {
        Matx33d bad = K;
        bad.val[entry == 0 ? 1 : entry == 1 ? 3 : 8] = entry == 2 ? 0 : 5;
        expectRaises([&] { r->render(h, Matx33d::eye(), Vec3d(0, 0, 300), bad, color); },
                     Error::StsBadArg, "the renderer draws without skew",
                     "Renderer, K entry " + std::to_string(entry));
    }
    EXPECT_NO_THROW(r->render(h, Matx33d::eye(), Vec3d(0, 0, 300), K, color));
    EXPECT_GT(countNonZero(color.reshape(1)), 0);
}

}} // namespace
