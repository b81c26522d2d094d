// This file is part of OpenCV project.
// It is subject to the license terms in the LICENSE file found in the top-level directory
// of this distribution and at http://opencv.org/license.html

// The samples as programs: forestmod_eval on a small BOP dataset rendered here, and every
// sample's command line (--help, a missing input). The samples are found next to the test binary.

#include "test_precomp.hpp"

#include <cstdlib>
#include <limits>
#include <sys/wait.h>
#include <unistd.h>

namespace opencv_test { namespace {

static std::string samplePath(const std::string& name)
{
    const std::string p = testBinaryDir() + "/" + name;
    if (!cv::utils::fs::exists(p))
        throw SkipTestException("sample " + name + " not built next to the test binary ("
                                + testBinaryDir() + ")");
    return p;
}

static std::string readText(const std::string& path)
{
    std::ifstream f(path.c_str());
    return std::string((std::istreambuf_iterator<char>(f)), std::istreambuf_iterator<char>());
}

/** Runs a command; returns its exit code (-1 when it did not exit normally); stdout and stderr
go to out and err. */
static int run(const std::string& cmd, const std::string& dir, std::string& out, std::string& err)
{
    const std::string o = dir + "/stdout.txt", e = dir + "/stderr.txt";
    const int status = std::system((cmd + " > '" + o + "' 2> '" + e + "'").c_str());
    out = readText(o);
    err = readText(e);
    if (status == -1 || !WIFEXITED(status))
        return -1;
    return WEXITSTATUS(status);
}

static void writePly(const Mesh& m, const std::string& path)
{
    std::ofstream f(path.c_str());
    f << "ply\nformat ascii 1.0\nelement vertex " << m.vertices.size()
      << "\nproperty float x\nproperty float y\nproperty float z\n"
         "property uchar red\nproperty uchar green\nproperty uchar blue\n"
         "element face " << m.faces.size() << "\nproperty list uchar int vertex_indices\n"
         "end_header\n";
    for (size_t i = 0; i < m.vertices.size(); ++i)
    {
        const cv::Vec3b c = m.colors.empty() ? cv::Vec3b(128, 128, 128) : m.colors[i];
        f << m.vertices[i].x << " " << m.vertices[i].y << " " << m.vertices[i].z << " "
          << (int)c[2] << " " << (int)c[1] << " " << (int)c[0] << "\n";
    }
    for (size_t i = 0; i < m.faces.size(); ++i)
        f << "3 " << m.faces[i][0] << " " << m.faces[i][1] << " " << m.faces[i][2] << "\n";
    ASSERT_TRUE(f.good()) << path;
}

static std::string jsonList(const double* v, int n)
{
    std::string s = "[";
    for (int i = 0; i < n; ++i)
        s += cv::format("%s%.9g", i ? ", " : "", v[i]);
    return s + "]";
}

/** A BOP dataset with two objects (the LM-O ape and a copy 1.6 times its size) in `frames`
frames: each object at a pose of the level-0 view sampler at 700 mm, moved sideways, over a real
LM-O frame as background and a plane at 1000 mm (depth). */
static void makeDataset(const std::string& root, int frames)
{
    const std::string ape_path = cvtest::findDataFile("lmo_mini/models/obj_000001.ply");
    const std::string bg_path = cvtest::findDataFile("lmo_mini/test/000002/rgb/000902.png");
    const Mesh ape = Mesh::load(ape_path);
    Mesh big = ape;
    for (size_t i = 0; i < big.vertices.size(); ++i)
        big.vertices[i] *= 1.6f;
    const cv::Matx33d K = lmoIntrinsics();
    const cv::Size size(640, 480);
    cv::utils::fs::createDirectories(root + "/models");
    const std::string scene = root + "/test/000001";
    cv::utils::fs::createDirectories(scene + "/rgb");
    cv::utils::fs::createDirectories(scene + "/depth");
    {
        std::ofstream f((root + "/camera.json").c_str());
        f << "{\"cx\": 325.2611, \"cy\": 242.04899, \"depth_scale\": 1.0, \"fx\": 572.4114, "
             "\"fy\": 573.57043, \"height\": 480, \"width\": 640}\n";
    }
    writePly(ape, root + "/models/obj_000001.ply");
    writePly(big, root + "/models/obj_000002.ply");
    {
        std::ofstream f((root + "/models/models_info.json").c_str());
        f << "{";
        const Mesh* meshes[2] = { &ape, &big };
        for (int k = 0; k < 2; ++k)
        {
            const cv::Point3f lo = meshes[k]->bboxMin(), hi = meshes[k]->bboxMax();
            f << (k ? ", " : "") << "\"" << k + 1 << "\": {\"diameter\": " << meshes[k]->diameter()
              << ", \"min_x\": " << lo.x << ", \"min_y\": " << lo.y << ", \"min_z\": " << lo.z
              << ", \"size_x\": " << hi.x - lo.x << ", \"size_y\": " << hi.y - lo.y
              << ", \"size_z\": " << hi.z - lo.z << "}";
        }
        f << "}\n";
    }

    cv::Ptr<Renderer> renderer = Renderer::create(size);
    const int h_ape = renderer->addMesh(ape), h_big = renderer->addMesh(big);
    ViewSampler::Params sp = ViewSampler::Params::coarse();
    sp.radii.assign(1, 700.0);
    const ViewSampler sampler(sp);
    const std::vector<ViewPose> ape_poses = sampler.poses(cv::Point3d(ape.center()));
    const std::vector<ViewPose> big_poses = sampler.poses(cv::Point3d(big.center()));
    cv::Mat background = cv::imread(bg_path, cv::IMREAD_COLOR);
    ASSERT_FALSE(background.empty()) << bg_path;
    cv::resize(background, background, size);

    std::string cam_json = "{", gt_json = "{", info_json = "{";
    for (int i = 0; i < frames; ++i)
    {
        std::vector<int> handles;
        handles.push_back(h_ape);
        handles.push_back(h_big);
        const ViewPose& pa = ape_poses[i % ape_poses.size()];
        const ViewPose& pb = big_poses[(i + 2) % big_poses.size()];
        std::vector<cv::Matx33d> R;
        std::vector<cv::Vec3d> t;
        R.push_back(pa.R);
        t.push_back(pa.t + cv::Vec3d(-110, 20.0 * (i % 3 - 1), 0));
        R.push_back(pb.R);
        t.push_back(pb.t + cv::Vec3d(130, -20.0 * (i % 3 - 1), 0));
        cv::Mat color, depth, labels;
        renderer->renderScene(handles, R, t, K, color, depth, labels);
        cv::Mat rgb = background.clone();
        color.copyTo(rgb, labels > 0);
        cv::Mat scene_depth(size, CV_16UC1, cv::Scalar(1000));
        depth.copyTo(scene_depth, labels > 0);
        ASSERT_TRUE(cv::imwrite(cv::format("%s/rgb/%06d.png", scene.c_str(), i), rgb));
        ASSERT_TRUE(cv::imwrite(cv::format("%s/depth/%06d.png", scene.c_str(), i), scene_depth));

        const char* sep = i ? ", " : "";
        cam_json += cv::format("%s\"%d\": {\"cam_K\": %s, \"depth_scale\": 1.0}", sep, i,
                               jsonList(K.val, 9).c_str());
        gt_json += cv::format("%s\"%d\": [", sep, i);
        info_json += cv::format("%s\"%d\": [", sep, i);
        for (int k = 0; k < 2; ++k)
        {
            cv::Mat mask;
            renderer->render(handles[k], R[k], t[k], K, cv::noArray(), cv::noArray(), mask);
            const cv::Rect box = cv::boundingRect(mask);
            const int visible = cv::countNonZero(labels == k + 1), all = cv::countNonZero(mask);
            ASSERT_GT(visible, 0);
            const int bb[4] = { box.x, box.y, box.width, box.height };
            const double b[4] = { (double)bb[0], (double)bb[1], (double)bb[2], (double)bb[3] };
            gt_json += cv::format("%s{\"cam_R_m2c\": %s, \"cam_t_m2c\": %s, \"obj_id\": %d}",
                                  k ? ", " : "", jsonList(R[k].val, 9).c_str(),
                                  jsonList(t[k].val, 3).c_str(), k + 1);
            info_json += cv::format("%s{\"bbox_obj\": %s, \"bbox_visib\": %s, "
                                    "\"visib_fract\": %.4f}",
                                    k ? ", " : "", jsonList(b, 4).c_str(), jsonList(b, 4).c_str(),
                                    double(visible) / all);
        }
        gt_json += "]";
        info_json += "]";
    }
    std::ofstream((scene + "/scene_camera.json").c_str()) << cam_json << "}\n";
    std::ofstream((scene + "/scene_gt.json").c_str()) << gt_json << "}\n";
    std::ofstream((scene + "/scene_gt_info.json").c_str()) << info_json << "}\n";
}

// A rendered dataset in a temporary folder (make() writes it) and forestmod_eval's command on
// it: scene 1, views of level 0 from 0 degrees up at 700 mm, the templates cached in the folder;
// `flags` adds the rest.
struct EvalOnDataset
{
    explicit EvalOnDataset(const std::string& name) : tmp(name), dir(tmp.path), root(dir + "/data")
    {
    }
    void make(int frames) const { makeDataset(root, frames); }
    std::string command(const std::string& flags) const
    {
        return "'" + samplePath("forestmod_eval") + "' --dataset='" + root + "' --scene=1 "
               "--level=0 --min_elevation=0 --radii=700 --cache='" + dir + "/cache' " + flags;
    }
    const TempDir tmp;
    const std::string dir, root;
};

/** The sample writes its JSON with cv::FileStorage: it must read back with it as it is. */
static cv::FileStorage readJson(const std::string& path)
{
    return cv::FileStorage(path, cv::FileStorage::READ | cv::FileStorage::FORMAT_JSON);
}

static double number(const cv::FileNode& n)
{
    return n.isReal() || n.isInt() ? (double)n : std::numeric_limits<double>::quiet_NaN();
}

static const char* const RESULT_KEYS[] = { "t_total_ms", "t_tree_ms", "t_valid_ms", "recall_2d",
                                           "proj2d_5px", "add_01d", "rejected_fraction", 0 };

/** Checks one {t_total_ms, ...} entry; returns recall_2d. */
static double checkResult(const cv::FileNode& r, const std::string& what, bool forest)
{
    EXPECT_TRUE(r.isMap()) << what;
    for (int k = 0; RESULT_KEYS[k]; ++k)
        EXPECT_FALSE(r[RESULT_KEYS[k]].empty()) << what << ": no " << RESULT_KEYS[k];
    EXPECT_TRUE(r["t_total_ms"].isReal() || r["t_total_ms"].isInt()) << what;
    EXPECT_GT((double)r["t_total_ms"], 0.0) << what;
    // both detectors have their quantization timed, and the spread of the per-frame times
    EXPECT_GT(number(r["t_quant_ms"]), 0.0) << what;
    EXPECT_LT(number(r["t_quant_ms"]), number(r["t_total_spread"]["max"]) * 3) << what;
    const cv::FileNode spread = r["t_total_spread"];
    EXPECT_TRUE(spread.isMap()) << what;
    EXPECT_LE(number(spread["min"]), number(spread["median"])) << what;
    EXPECT_LE(number(spread["median"]), number(spread["max"])) << what;
    EXPECT_NEAR(number(spread["median"]), (double)r["t_total_ms"], 1e-6) << what;
    if (forest)
    {
        EXPECT_GE((double)r["t_tree_ms"], 0.0) << what;
        EXPECT_GE((double)r["t_valid_ms"], 0.0) << what;
        const double rej = r["rejected_fraction"];
        EXPECT_GE(rej, 0.0) << what;
        EXPECT_LE(rej, 1.0) << what;
    }
    else
    {
        EXPECT_TRUE(r["t_tree_ms"].isString()) << what << ": cv::linemod has no T_tree (n/a)";
        EXPECT_TRUE(r["rejected_fraction"].isString()) << what;
    }
    const char* acc[] = { "recall_2d", "proj2d_5px", "add_01d" };
    for (int k = 0; k < 3; ++k)
    {
        const cv::FileNode a = r[acc[k]];
        EXPECT_TRUE(a.isReal() || a.isInt()) << what << ": " << acc[k] << " must be measured "
                                              "(the dataset has depth)";
        EXPECT_GE((double)a, 0.0) << what << ": " << acc[k];
        EXPECT_LE((double)a, 1.0) << what << ": " << acc[k];
    }
    return r["recall_2d"].isString() ? -1.0 : (double)r["recall_2d"];
}

// the per-frame records of one detector's result agree with its rates
static void checkPerFrame(const cv::FileNode& r, int frames, bool with_depth,
                          const std::string& what)
{
    const cv::FileNode pf = r["per_frame"];
    ASSERT_TRUE(pf.isSeq()) << what;
    ASSERT_EQ(frames, (int)pf.size()) << what;
    int ok2d = 0, okadd = 0;
    for (int i = 0; i < (int)pf.size(); ++i)
    {
        const cv::FileNode f = pf[i];
        const std::string at = cv::format("%s, frame record %d", what.c_str(), i);
        EXPECT_TRUE(f["im_id"].isInt()) << at;
        EXPECT_TRUE(f["t_ms"].isReal() || f["t_ms"].isInt()) << at;
        const int tid = (int)f["template_id"];
        EXPECT_GE(tid, -1) << at;
        const cv::FileNode top = f["top"];
        ASSERT_TRUE(top.isSeq()) << at;
        EXPECT_LE((int)top.size(), 5) << at;
        for (int k = 0; k < (int)top.size(); ++k)
        {
            ASSERT_EQ(4, (int)top[k].size()) << at;
            EXPECT_GE((int)top[k][0], 0) << at;
        }
        if (tid < 0)
            continue;
        EXPECT_GT((int)top.size(), 0) << at << ": a scored hypothesis comes from the matches";
        EXPECT_GT((double)f["similarity"], 0.0) << at;
        const double iou = (double)f["iou"];
        EXPECT_GE(iou, 0.0) << at;
        EXPECT_LE(iou, 1.0) << at;
        EXPECT_GE((double)f["proj2d_px"], 0.0) << at;
        ok2d += iou >= 0.5;
        if (with_depth)
        {
            ASSERT_TRUE(f["add_d"].isReal() || f["add_d"].isInt()) << at;
            okadd += (double)f["add_d"] < 0.1;
        }
        else
        {
            EXPECT_TRUE(f["add_d"].isString()) << at << ": n/a without depth";
        }
    }
    EXPECT_NEAR((double)r["recall_2d"], double(ok2d) / frames, 1e-5) << what;
    if (with_depth)
    {
        EXPECT_NEAR((double)r["add_01d"], double(okadd) / frames, 1e-5) << what;
    }
}

TEST(Forestmod_Eval, json_on_a_rendered_bop_dataset)
{
    const EvalOnDataset data("forestmod_eval");
    const std::string& dir = data.dir;
    ASSERT_NO_FATAL_FAILURE(data.make(5));
    const std::string json = dir + "/out.json";
    const std::string cmd = data.command("--inplane=0,0,15 --threshold=70 --sweep=none --json='"
        + json + "' --heatmap='" + dir + "/heat' --heatmap_frames=2");
    std::string out, err;
    ASSERT_EQ(0, run(cmd, dir, out, err)) << out << err;
    EXPECT_NE(std::string::npos, out.find("## Table 1")) << out;
    EXPECT_NE(std::string::npos, out.find("1 OpenCV thread")) << out;
    EXPECT_NE(std::string::npos, out.find("best of 3 match() calls")) << out;

    cv::FileStorage fs = readJson(json);
    ASSERT_TRUE(fs.isOpened());
    EXPECT_EQ(5, (int)fs["frames"]);
    cv::FileNode objects = fs["objects"];
    ASSERT_TRUE(objects.isSeq());
    ASSERT_EQ(2, (int)objects.size());
    for (int i = 0; i < 2; ++i)
    {
        const cv::FileNode o = objects[i];
        EXPECT_EQ(i + 1, (int)o["obj_id"]);
        EXPECT_FALSE(((std::string)o["name"]).empty());
        const std::string what = cv::format("object %d", i + 1);
        const double recall1 = checkResult(o["forestmod"], what + " forestmod", true);
        checkResult(o["forestmod_5"], what + " forestmod_5", true);
        const double recall_lm = checkResult(o["linemod"], what + " linemod", false);
        checkPerFrame(o["forestmod"], 5, true, what + " forestmod"); // the dataset has depth
        checkPerFrame(o["linemod"], 5, true, what + " linemod");
        // the verified rows: the same hypotheses re-ranked; recall@10 of a row is at least its
        // recall@1 and the same with and without the verification (the same hypotheses)
        const char* rows[] = { "forestmod", "linemod" };
        for (int k = 0; k < 2; ++k)
        {
            const std::string row = rows[k], vrow = row + "_verified";
            checkResult(o[vrow], what + " " + vrow, k == 0);
            checkPerFrame(o[vrow], 5, true, what + " " + vrow);
            EXPECT_GE(number(o[vrow]["t_verify_ms"]), 0.0) << what << " " << vrow;
            EXPECT_GE(number(o[vrow]["t_verify_per10_ms"]), 0.0) << what << " " << vrow;
            EXPECT_GE(number(o[row]["t_pose_ms"]), 0.0) << what << " " << row;
            EXPECT_GE(number(o[row]["recall_2d_at10"]), number(o[row]["recall_2d"])) << what;
            EXPECT_GE(number(o[vrow]["recall_2d_at10"]), number(o[vrow]["recall_2d"])) << what;
            EXPECT_EQ(number(o[row]["recall_2d_at10"]), number(o[vrow]["recall_2d_at10"]))
                << what << " " << row;
            EXPECT_EQ(number(o[row]["proj2d_5px_at10"]), number(o[vrow]["proj2d_5px_at10"]))
                << what << " " << row;
            const cv::FileNode pf = o[vrow]["per_frame"];
            for (int f = 0; f < (int)pf.size(); ++f)
                if ((int)pf[f]["template_id"] >= 0)
                {
                    ASSERT_TRUE(pf[f]["hypotheses"].isSeq()) << what << " " << vrow;
                    EXPECT_EQ(9, (int)pf[f]["hypotheses"][0].size()) << what << " " << vrow;
                }
        }
        // template coverage: each ground truth seen along its line of sight against the nearest
        // of the templates (the eval's sampler: level 0, from 0 degrees up, 700 mm, in-plane 0)
        {
            ViewSampler::Params sp = ViewSampler::Params::coarse();
            sp.level = 0;
            sp.min_elevation = 0;
            sp.radii.assign(1, 700.0);
            sp.inplane_min = sp.inplane_max = 0;
            const Mesh mesh = Mesh::load(data.root + cv::format("/models/obj_%06d.ply", i + 1));
            const std::vector<ViewPose> views = ViewSampler(sp).poses(Point3d(mesh.center()));
            const std::vector<Frame> bop = BopDataset::open(data.root).frames(1);
            std::vector<double> angles;
            for (size_t f = 0; f < bop.size(); ++f)
                for (size_t g = 0; g < bop[f].gt.size(); ++g)
                    if (bop[f].gt[g].obj_id == i + 1)
                    {
                        const GroundTruth& gt = bop[f].gt[g];
                        const Point3f c = mesh.center();
                        const Vec3d ray = gt.R * Vec3d(c.x, c.y, c.z) + gt.t;
                        // the camera turned about ray x z until the ray lies on the optical axis
                        const Vec3d axis = ray.cross(Vec3d(0, 0, 1));
                        Matx33d Rc;
                        cv::Rodrigues(axis * (std::acos(ray[2] / cv::norm(ray)) / cv::norm(axis)),
                                      Rc);
                        double best = 180;
                        for (size_t v = 0; v < views.size(); ++v)
                            best = std::min(best, std::acos(std::min(1.0, (cv::trace(views[v].R
                                * (Rc * gt.R).t()) - 1) / 2)) * 180 / CV_PI);
                        angles.push_back(best);
                    }
            ASSERT_EQ(5u, angles.size()) << what;
            std::sort(angles.begin(), angles.end());
            const cv::FileNode cov = o["template_coverage_deg"];
            EXPECT_NEAR(angles[2], number(cov["median"]), 0.01) << what;
            EXPECT_NEAR(angles[4], number(cov["max"]), 0.01) << what;
            EXPECT_GT(angles[4], 1.0) << what << ": the objects lie off the optical axis";
        }
        if (i == 0)
        {
            // the ape is shown at template poses: both detectors must find it
            EXPECT_GT(recall1, 0.0);
            EXPECT_GT(recall_lm, 0.0);
        }
    }
    const cv::FileNode multi = fs["multi"];
    ASSERT_TRUE(multi.isMap());
    EXPECT_EQ(2, (int)multi["objects"]);
    checkResult(multi["forestmod"], "multi forestmod", true);
    checkResult(multi["linemod"], "multi linemod", false);
    const cv::FileNode summary = fs["summary"];
    ASSERT_TRUE(summary.isMap());
    EXPECT_GT((double)summary["speedup_single"], 0.0);
    EXPECT_GT((double)summary["speedup_multi"], 0.0);
    EXPECT_GT((double)summary["growth_multi_over_single"], 0.0);
    fs.release();

    // heat maps next to the frames
    const char* models[] = { "single", "all" };
    for (int k = 0; k < 2; ++k)
        for (int i = 0; i < 3; ++i)
        {
            const std::string file = cv::format("%s/heat/heatmap_%s_000001_%06d.png", dir.c_str(),
                                                models[k], i);
            if (i == 2) // --heatmap_frames=2
            {
                EXPECT_FALSE(cv::utils::fs::exists(file)) << file;
                continue;
            }
            cv::Mat heat = cv::imread(file, cv::IMREAD_COLOR);
            ASSERT_FALSE(heat.empty()) << file;
            EXPECT_EQ(2 * 640, heat.cols);
            EXPECT_GE(heat.rows, 480);
        }

    // a second run finds the templates in the cache, and refuses to overwrite the outputs
    std::string out2, err2;
    EXPECT_NE(0, run(cmd, dir, out2, err2));
    EXPECT_NE(std::string::npos, err2.find("--force")) << err2;
    std::vector<cv::String> cached;
    cv::utils::fs::glob(dir + "/cache", "*.yml.gz", cached);
    EXPECT_EQ(2u, cached.size());
}

// --gt_similarity: a template made at each object's ground-truth pose matches the rendered scene
// on the object almost exactly (the scene is that rendering on a real background), the matches on
// the object are recorded for both detectors, and the table says so; without the flag the JSON
// has no such similarity.
TEST(Forestmod_Eval, ground_truth_template_similarity_on_a_rendered_dataset)
{
    const EvalOnDataset data("forestmod_eval_gt_similarity");
    const std::string& dir = data.dir;
    ASSERT_NO_FATAL_FAILURE(data.make(3));
    const std::string common = data.command("--objects=1 --no_multi --five_trees=false "
                                            "--inplane=0,0,15 --threshold=70 --sweep=none "
                                            "--repeat=1");
    for (int with = 0; with < 2; ++with)
    {
        const std::string json = cv::format("%s/out%d.json", dir.c_str(), with);
        std::string out, err;
        ASSERT_EQ(0, run(common + (with ? " --gt_similarity" : "") + " --json='" + json + "'",
                         dir, out, err)) << out << err;
        EXPECT_EQ(with != 0, out.find("## Similarity on the object") != std::string::npos)
            << out;
        cv::FileStorage fs = readJson(json);
        ASSERT_TRUE(fs.isOpened());
        const cv::FileNode o = fs["objects"][0];
        int on_object = 0;
        for (int row = 0; row < 2; ++row)
        {
            const cv::FileNode pf = o[row ? "linemod" : "forestmod"]["per_frame"];
            ASSERT_EQ(3, (int)pf.size());
            for (int f = 0; f < 3; ++f)
            {
                const double gt = number(pf[f]["gt_similarity"]),
                             correct = number(pf[f]["correct_similarity"]);
                if (with)
                {
                    EXPECT_GE(gt, 97.5) << row << " " << f; // 150 mm farther: 95.6-96.3
                    EXPECT_LE(gt, 100.0) << row << " " << f;
                }
                else
                    EXPECT_TRUE(cvIsNaN(gt)) << row << " " << f;
                if (!cvIsNaN(correct))
                {
                    ++on_object;
                    EXPECT_GE(correct, 70.0) << row << " " << f;
                    EXPECT_LE(correct, 100.0) << row << " " << f;
                }
            }
        }
        EXPECT_GE(on_object, 4) << with; // the ape is shown at template poses
    }
}

// --first_frame skips the scene's first frames (a parameter is set on frames that the reported
// runs do not use), and skipping them all is an error that says so.
TEST(Forestmod_Eval, first_frame_skips_the_first_frames)
{
    const EvalOnDataset data("forestmod_eval_first_frame");
    const std::string& dir = data.dir;
    ASSERT_NO_FATAL_FAILURE(data.make(3));
    const std::string json = dir + "/out.json";
    const std::string common = data.command("--objects=1 --no_multi --five_trees=false "
                                            "--inplane=0,0,15 --sweep=none --repeat=1");
    std::string out, err;
    ASSERT_EQ(0, run(common + " --first_frame=2 --json='" + json + "'", dir, out, err))
        << out << err;
    EXPECT_NE(std::string::npos, out.find("1 frames (the first 2 skipped)")) << out;
    cv::FileStorage fs = readJson(json);
    ASSERT_TRUE(fs.isOpened());
    EXPECT_EQ(1, (int)fs["frames"]);
    EXPECT_NE(0, run(common + " --first_frame=3", dir, out, err));
    EXPECT_NE(std::string::npos, (out + err).find("has no frames (after --first_frame=3)"))
        << out << err;
    EXPECT_NE(0, run(common + " --first_frame=-1", dir, out, err));
    EXPECT_NE(std::string::npos, (out + err).find("--first_frame")) << out << err;
}

TEST(Forestmod_Eval, synthetic_scenes_give_add)
{
    const EvalOnDataset data("forestmod_eval_synthetic");
    const std::string& dir = data.dir;
    ASSERT_NO_FATAL_FAILURE(data.make(2));
    const std::string json = dir + "/out.json";
    std::string out, err;
    ASSERT_EQ(0, run(data.command("--objects=1 --synthetic=2 --no_multi --inplane=0,0,15 "
                                  "--sweep=none --repeat=1 --json='" + json + "'"),
                     dir, out, err)) << out << err;
    EXPECT_NE(std::string::npos, out.find("ColorGradient + DepthNormal + ColorHue")) << out;
    cv::FileStorage fs = readJson(json);
    ASSERT_TRUE(fs.isOpened());
    EXPECT_EQ(2, (int)fs["frames"]);
    ASSERT_EQ(1, (int)fs["objects"].size());
    EXPECT_TRUE(fs["multi"].isString()) << "--no_multi: multi is n/a";
    const cv::FileNode o = fs["objects"][0];
    checkResult(o["forestmod"], "forestmod", true);
    checkResult(o["linemod"], "linemod", false);
    checkPerFrame(o["forestmod_5"], 2, true, "forestmod_5");
    checkPerFrame(o["linemod"], 2, true, "linemod");
    // the scenes show the ape at (perturbed) template poses: ICP brings cv::linemod's and
    // forestmod's best hypotheses within 0.1 d in at least one of the two
    EXPECT_GT((double)o["linemod"]["add_01d"], 0.0);
    EXPECT_GT((double)o["forestmod_5"]["add_01d"], 0.0);
}

/** The "= N poses per object" of the sample's header. */
static int printedPoses(const std::string& out)
{
    const size_t k = out.find(" poses per object");
    if (k == std::string::npos)
        return -1;
    size_t b = out.rfind("= ", k);
    return b == std::string::npos ? -1 : atoi(out.c_str() + b + 2);
}

TEST(Forestmod_Eval, regimes_give_the_sampling_they_print)
{
    const std::string eval = samplePath("forestmod_eval");
    const TempDir tmp("forestmod_eval_regimes");
    const std::string& dir = tmp.path;
    std::string out, err;

    // paper: LINEMOD's sampling over LM-O's pose range, >= 2000 templates per object
    ASSERT_EQ(0, run("'" + eval + "' --dry_run", dir, out, err)) << out << err;
    EXPECT_NE(std::string::npos, out.find("regime paper")) << out << ": paper is the default";
    ViewSampler::Params paper;
    paper.level = 2;
    paper.min_elevation = -15;
    paper.max_elevation = 90;
    paper.radii.assign(1, 650.0);
    paper.radii.push_back(900.0);
    paper.radii.push_back(1150.0);
    paper.inplane_min = -45;
    paper.inplane_max = 45;
    paper.inplane_step = 15;
    const int n_paper = ViewSampler(paper).size();
    EXPECT_GE(n_paper, 2000);
    EXPECT_EQ(n_paper, printedPoses(out)) << out;
    EXPECT_NE(std::string::npos, out.find("level 2, elevation -15..90 deg")) << out;
    EXPECT_NE(std::string::npos, out.find("radii {650, 900, 1150} mm")) << out;
    EXPECT_NE(std::string::npos, out.find("in-plane -45..45 step 15 deg (7 angles)")) << out;

    // quick: 260 poses (level 1, 700 and 1100 mm, in-plane -60..60 step 30)
    ASSERT_EQ(0, run("'" + eval + "' --dry_run --regime=quick", dir, out, err)) << out << err;
    ViewSampler::Params quick = paper;
    quick.level = 1;
    quick.radii.assign(1, 700.0);
    quick.radii.push_back(1100.0);
    quick.inplane_min = -60;
    quick.inplane_max = 60;
    quick.inplane_step = 30;
    EXPECT_EQ(260, ViewSampler(quick).size());
    EXPECT_EQ(ViewSampler(quick).size(), printedPoses(out)) << out;

    // an explicit flag overrides the regime, and says so
    ASSERT_EQ(0, run("'" + eval + "' --dry_run --regime=paper --radii=700", dir, out, err))
        << out << err;
    EXPECT_EQ(n_paper / 3, printedPoses(out)) << out;
    EXPECT_NE(std::string::npos, out.find("overridden: --radii")) << out;

    // an unknown regime is refused
    EXPECT_NE(0, run("'" + eval + "' --dry_run --regime=dense", dir, out, err));
    EXPECT_NE(std::string::npos, err.find("--regime")) << err;
}

/** Checks the points of one sweep: increasing in `key` and in templates, every detector
timed; returns the number of points. */
static int checkSweep(const cv::FileNode& sweep, const char* key, const std::string& what)
{
    EXPECT_TRUE(sweep.isMap()) << what;
    const cv::FileNode points = sweep["points"];
    EXPECT_TRUE(points.isSeq()) << what;
    int prev_x = 0, prev_templates = 0;
    for (int i = 0; i < (int)points.size(); ++i)
    {
        const cv::FileNode p = points[i];
        const std::string at = cv::format("%s, point %d", what.c_str(), i);
        const int x = (int)p[key], templates = (int)p["templates"];
        EXPECT_GT(x, prev_x) << at;
        EXPECT_GT(templates, prev_templates) << at;
        prev_x = x;
        prev_templates = templates;
        const char* dets[] = { "forestmod", "forestmod_5", "linemod" };
        for (int d = 0; d < 3; ++d)
        {
            const cv::FileNode r = p[dets[d]];
            EXPECT_GT(number(r["t_total_ms"]), 0.0) << at << " " << dets[d];
            EXPECT_GT(number(r["t_quant_ms"]), 0.0) << at << " " << dets[d];
            EXPECT_LE(number(r["t_total_spread"]["min"]), number(r["t_total_ms"])) << at;
        }
        const double rej = number(p["forestmod"]["rejected_fraction"]);
        EXPECT_GE(rej, 0.0) << at;
        EXPECT_LE(rej, 1.0) << at;
        EXPECT_TRUE(p["linemod"]["rejected_fraction"].isString()) << at;
        EXPECT_NEAR(number(p["speedup_1tree"]),
                    number(p["linemod"]["t_total_ms"]) / number(p["forestmod"]["t_total_ms"]),
                    1e-6) << at;
    }
    return (int)points.size();
}

TEST(Forestmod_Eval, sweeps_write_json_and_plots)
{
    const EvalOnDataset data("forestmod_eval_sweeps");
    const std::string& dir = data.dir;
    ASSERT_NO_FATAL_FAILURE(data.make(2));
    const std::string plots = dir + "/plots", json = dir + "/out.json";
    // 6 views x 5 in-plane angles = 30 poses: 40 templates need a denser sampler (level 1)
    const std::string cmd = data.command("--tables=false --inplane=-30,30,15 --threshold=70 "
        "--sweep=all --sweep_templates=40,5,15 --sweep_classes=1,2,3 --sweep_per_class=6 "
        "--repeat=1 --plots='" + plots + "' --json='" + json + "'");
    std::string out, err;
    ASSERT_EQ(0, run(cmd, dir, out, err)) << out << err;
    EXPECT_NE(std::string::npos, out.find("## Scaling with templates")) << out;
    EXPECT_NE(std::string::npos, out.find("## Scaling with objects")) << out;
    EXPECT_NE(std::string::npos, out.find("recoloured")) << out
        << ": the classes beyond the dataset's objects are copies, and the output says so";

    cv::FileStorage fs = readJson(plots + "/scaling.json");
    ASSERT_TRUE(fs.isOpened());
    const cv::FileNode sweeps = fs["sweeps"];
    ASSERT_TRUE(sweeps.isMap());
    EXPECT_EQ(2, (int)sweeps["frames"]);
    EXPECT_EQ(1, (int)sweeps["repetitions"]);
    EXPECT_EQ(3, checkSweep(sweeps["templates"], "poses", "templates sweep"));
    EXPECT_GT((int)sweeps["templates"]["points"][2]["templates"], 30)
        << "40 poses asked of a 30-pose sampler: the sweep samples denser";
    EXPECT_EQ(3, checkSweep(sweeps["objects"], "classes", "objects sweep"));
    const cv::FileNode last = sweeps["objects"]["points"][2];
    ASSERT_EQ(3, (int)last["class_ids"].size());
    EXPECT_NE(std::string::npos, ((std::string)last["class_ids"][2]).find("_v1"));
    fs.release();

    // the same sweeps in the --json file
    cv::FileStorage fj = readJson(json);
    ASSERT_TRUE(fj.isOpened());
    EXPECT_EQ(3, (int)fj["sweeps"]["objects"]["points"].size());
    EXPECT_EQ("paper", (std::string)fj["regime"]);
    fj.release();

    const char* pngs[] = { "scaling_templates.png", "scaling_objects.png" };
    for (int k = 0; k < 2; ++k)
    {
        const cv::Mat img = cv::imread(plots + "/" + pngs[k], cv::IMREAD_COLOR);
        ASSERT_FALSE(img.empty()) << pngs[k];
        EXPECT_GE(img.cols, 400) << pngs[k];
        // curves in colour on white: not a blank image
        cv::Mat hsv;
        cv::cvtColor(img, hsv, cv::COLOR_BGR2HSV);
        cv::Mat sat;
        cv::extractChannel(hsv, sat, 1);
        EXPECT_GT(cv::countNonZero(sat > 100), 200) << pngs[k];
    }

    // outputs are not overwritten without --force
    EXPECT_NE(0, run(cmd, dir, out, err));
    EXPECT_NE(std::string::npos, err.find("--force")) << err;
}

struct SampleCall
{
    const char* name;
    const char* missing_input_args; // %s: a path that does not exist, %o: an output path
};

TEST(Forestmod_Eval, samples_answer_help_and_reject_a_missing_input)
{
    const SampleCall samples[] = {
        { "forestmod_eval", "--dataset=%s" },
        { "forestmod_train", "--meshes=%s --out=%o" },
        { "forestmod_render", "--mesh=%s --out=%o" },
        { "forestmod_hue", "%s %o" },
        { "forestmod_detect", "--model=%s --color=%o" },
        { "forestmod_reject_probe", "--dataset=. --object=1 --model=%s" },
        { "forestmod_forest_bench", "--templates=40 --queries=20 --frames=%s" },
    };
    const TempDir tmp("forestmod_samples");
    const std::string& dir = tmp.path;
    const std::string missing = dir + "/does_not_exist/input.ply";
    for (size_t i = 0; i < sizeof(samples) / sizeof(samples[0]); ++i)
    {
        const std::string exe = samplePath(samples[i].name);
        std::string out, err;
        EXPECT_EQ(0, run("'" + exe + "' --help", dir, out, err)) << samples[i].name;
        EXPECT_NE(std::string::npos, (out + err).find("--")) << samples[i].name
                                                             << ": --help prints no options";
        std::string args = samples[i].missing_input_args;
        const size_t s = args.find("%s");
        args.replace(s, 2, "'" + missing + "'");
        const size_t o = args.find("%o");
        if (o != std::string::npos)
            args.replace(o, 2, "'" + dir + "/out_" + samples[i].name + ".png'");
        const int code = run("'" + exe + "' " + args, dir, out, err);
        // 1, not the shell's 128 + signal of an uncaught exception's abort
        EXPECT_EQ(1, code) << samples[i].name << " " << args << ": must fail with a message";
        EXPECT_FALSE(err.empty()) << samples[i].name << ": no message on stderr";
        EXPECT_NE(std::string::npos, err.find("does_not_exist"))
            << samples[i].name << ": the message should name the missing path: " << err;
    }
}

// Option values out of range are refused, with a message naming the option, before any data is
// read (the dataset here does not exist).
TEST(Forestmod_Eval, out_of_range_options_are_refused)
{
    const TempDir tmp("forestmod_eval_options");
    const std::string exe = samplePath("forestmod_eval");
    const char* bad[] = { "--rgb_hypotheses=0", "--rgb_keep=0", "--verify_k=0",
                          "--fuzzy_margin=-0.5", "--hue_feature_saturation=256",
                          "--hue_feature_area=1.5" };
    const char* bound[] = { ">= 1", ">= 1", ">= 1", ">= 0", "in [0, 255]", "in [0, 1]" };
    for (size_t i = 0; i < sizeof(bad) / sizeof(bad[0]); ++i)
    {
        std::string out, err;
        const int code = run("'" + exe + "' --dataset='" + tmp.path + "/none' " + bad[i], tmp.path,
                             out, err);
        EXPECT_GT(code, 0) << bad[i];
        const std::string name = std::string(bad[i]).substr(0, std::string(bad[i]).find('='));
        EXPECT_NE(std::string::npos, err.find(name + " must be " + bound[i]))
            << bad[i] << ": " << err;
    }
}

// One line of forestmod_reject_probe --occupancy: the shares (percent) and the object's frames.
struct OccupancyLine
{
    double passing, cells, vectors;
    int object, frames;
};

static bool parseOccupancy(const std::string& out, const std::string& what, OccupancyLine& o)
{
    const size_t at = out.find(what + ": ");
    if (at == std::string::npos)
        return false;
    return sscanf(out.c_str() + at + what.size() + 2,
                  "locations passing %lf %% (the object's in %d / %d frames), T grid cells "
                  "holding one %lf %%, 32-cell vectors holding one %lf %%",
                  &o.passing, &o.object, &o.frames, &o.cells, &o.vectors) == 5;
}

// forestmod_reject_probe --occupancy (doc/experiments.md, "The forests' rejection and the
// exhaustive search's vectors") on a rendered BOP dataset with the ape's templates of its views:
// the whole forest passes a subset of the locations the tests before it pass; a cell of the T
// grid holds a passing location when one of its locations passes, a vector of 32 cells when one
// of its cells does, so neither share falls below the one before it; and the ape's own location
// passes in both frames (the forest also rejects some locations its root lets through). Without
// the forest path on every group (--exhaustive, or exhaustive_ratio >= 0) it is refused.
TEST(Forestmod_Eval, reject_probe_occupancy_on_a_rendered_dataset)
{
    const TempDir tmp("forestmod_probe");
    const std::string& dir = tmp.path;
    const std::string root = dir + "/data";
    ASSERT_NO_FATAL_FAILURE(makeDataset(root, 2));
    ViewSampler::Params sp = ViewSampler::Params::coarse();
    sp.radii.assign(1, 700.0);
    Ptr<cv::forestmod::Detector> det = getDefaultForestLINE();
    ASSERT_GT(det->addTemplates(Mesh::load(root + "/models/obj_000001.ply"), "ape",
                                ViewSampler(sp), lmoIntrinsics(), Size(640, 480)), 0);
    const std::string model = dir + "/ape.yml.gz";
    det->save(model);
    const std::string probe = "'" + samplePath("forestmod_reject_probe") + "' --dataset='" + root
        + "' --scene=1 --object=1 --model='" + model + "' --threshold=70 --occupancy";
    std::string out, err;
    ASSERT_EQ(0, run(probe + " --exhaustive_ratio=-1", dir, out, err)) << out << err;
    OccupancyLine before, forest;
    ASSERT_TRUE(parseOccupancy(out, "tests before the forest", before)) << out;
    ASSERT_TRUE(parseOccupancy(out, "whole forest", forest)) << out;
    std::cout << "[ INFO    ] passing (before the forest / whole forest): locations "
              << before.passing << " / " << forest.passing << " %, cells " << before.cells
              << " / " << forest.cells << " %, vectors " << before.vectors << " / "
              << forest.vectors << " %" << std::endl;
    EXPECT_GT(before.passing, 0.0);
    EXPECT_LE(before.passing, 100.0);
    // the ape's forest rejects some of what its root rejectors let through on these frames
    EXPECT_LT(forest.passing, before.passing);
    EXPECT_LE(forest.cells, before.cells);
    EXPECT_LE(forest.vectors, before.vectors);
    const OccupancyLine* lines[2] = { &before, &forest };
    for (int k = 0; k < 2; ++k)
    {
        const OccupancyLine& o = *lines[k];
        // every T grid cell holds (T / step)^2 = 4 locations; the rows of cells_x + 1 cells
        // (the search's layout) hold one cell that never passes
        EXPECT_GE(o.cells, o.passing - 1.0) << k;
        EXPECT_GE(o.vectors, o.cells * 40.0 / 41.0 - 1e-6) << k;
        EXPECT_LE(o.vectors, 100.0) << k;
        EXPECT_EQ(2, o.frames) << k;
        EXPECT_EQ(2, o.object) << k << ": the ape's location must pass";
    }
    // the groups searched exhaustively would count as passing everywhere
    const char* refused[] = { " --exhaustive", "", " --exhaustive_ratio=0.01" };
    for (int k = 0; k < 3; ++k)
    {
        EXPECT_EQ(1, run(probe + refused[k], dir, out, err)) << refused[k] << ": " << out << err;
        EXPECT_NE(std::string::npos, err.find("--occupancy")) << refused[k] << ": " << err;
    }
}

}} // namespace
