// This file is part of OpenCV project.
// It is subject to the license terms in the LICENSE file found in the top-level directory
// of this distribution and at http://opencv.org/license.html

// Search benchmark of cv::forestmod::Detector on rendered LM-O scenes (the setting of
// test/test_detector_rendered.cpp): templates of each object from a view sampler, scenes from
// SceneSynthesizer (the object at a perturbed template pose, other meshes as clutter, a real LM-O
// frame as background, depth noise). Per object it prints the hits of the forest search and of
// the exhaustive LINEMOD search (top match within 10 px of the truth and a template within 25
// degrees of the true view), the share of locations rejected before validation, the candidates
// per validated location and the time split. With --together the objects share one detector (one
// class each), as in perf/perf_detector.cpp's 8-object case. The numbers of doc/detector.md come
// from this program.

#include <opencv2/core.hpp>
#include <opencv2/core/utility.hpp>
#include <opencv2/core/utils/filesystem.hpp>
#include <opencv2/forestmod.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <opencv2/calib3d.hpp>

#include <cstdio>
#include <iostream>
#include <sstream>
#include "sample_utils.hpp"

using cv::forestmod::samples::splitList;
using cv::forestmod::samples::lmoIntrinsics;
using cv::forestmod::samples::rayRotation;
using cv::forestmod::samples::rotationAngleDeg;

using namespace cv;
using namespace cv::forestmod;
using cv::forestmod::samples::sourcesOf;

static const char* keys
    = "{help h usage ? |         | print this message }"
      "{data           |         | shared data folder with lmo/models (default: $FORESTMOD_SHARED_DATA) }"
      "{mini           |         | folder lmo_mini (default: $OPENCV_TEST_DATA_PATH/forestmod/lmo_mini) }"
      "{objects        | 1,6,9   | LM-O object ids (1 = ape, 6 = cat, 9 = duck, ...) }"
      "{together       | 0       | 1: one detector with every object (one class each) }"
      "{scenes         | 30      | scenes per object }"
      "{threshold      | 80      | match threshold (percent) }"
      "{exhaustive     | 1       | 1: also run the exhaustive search (forest recall reference) }"
      "{modalities     | linemod | linemod (gradient + depth normal + hue) or line (gradient + hue) }"
      "{level          | 1       | view sampler: icosahedron subdivisions }"
      "{min_elevation  | 15      | view sampler: lowest elevation (degrees) }"
      "{radii          | 800     | view sampler: camera distances (mm), comma-separated }"
      "{inplane        | -20,20,20 | view sampler: in-plane min,max,step (degrees) }"
      "{trees          | -1      | forest.num_trees (-1: library default) }"
      "{depth          | -1      | forest.max_depth (0: automatic) }"
      "{xi             | -1      | forest.fuzzy_margin }"
      "{rdims          | -1      | forest.rejector_dims }"
      "{rcov           | -1      | forest.rejector_coverage }"
      "{rnoise         | -1      | forest.rejector_noise }"
      "{tau            | -1      | forest.rejector_tau }"
      "{rho            | -1      | forest.rejector_rho }"
      "{any            | -1      | forest.reject_any_tree (0/1) }"
      "{fseed          | -1      | forest.seed }"
      "{grid           | -1      | grid_size }"
      "{step           | -1      | location_step (0: T / 2) }"
      "{min_labels     | -1      | min_window_labels }"
      "{dominant       | -1      | dominant_window }"
      "{eratio         | -2      | exhaustive_ratio (-1: the forest path in every group, -2: the "
      "default) }"
      "{depth_tol      | -2      | depth_range_tolerance (-1: off, -2: the default) }"
      "{gratio         | -1      | group_size_ratio (0: no size limit) }"
      "{leaf_samples   | -1      | auto_depth_leaf_samples (0: the paper's depth) }"
      "{k              | -1      | max_survivors }"
      "{chunk          | -1      | chunk_size }"
      "{alpha          | -1      | alpha }"
      "{bf             | -1      | breadth_first (0/1) }"
      "{ds             | -1      | depth_samples }"
      "{dtol           | -1      | depth_tolerance (mm) }"
      "{seed           | 1000    | scene RNG seed (+ object id) }"
      "{map            |         | folder: write rej_<obj>.png (scene | rejection depth) of the first scene }"
      "{verbose v      | 0       | 1: one line per scene }"
      "{only           | -1      | match only this scene index (diagnostics) }";

struct TemplateInfo
{
    Point2d centre_offset; // object centre pixel relative to the template's box
    Matx33d R;
};

// the test's criterion: top match (of the object's class) within 10 px of the true centre, its
// template within 25 degrees of the true view (up to the ray rotation)
static bool evaluate(const std::vector<PoseMatch>& matches, const String& cls,
                     const std::map<String, std::vector<TemplateInfo> >& info,
                     const SyntheticScene& scene, const Matx33d& K, bool any_class)
{
    const PoseMatch* m = 0;
    for (size_t i = 0; i < matches.size() && !m; ++i)
        if (any_class || matches[i].class_id == cls)
            m = &matches[i];
    if (!m || m->class_id != cls)
        return false;
    const TemplateInfo& ti = info.find(cls)->second[m->template_id];
    const Point2d centre = Point2d(m->x, m->y) + ti.centre_offset;
    const Matx33d on_axis = rayRotation(K, scene.center).t() * scene.R;
    return cv::norm(centre - scene.center) <= 10.0 && rotationAngleDeg(ti.R, on_axis) <= 25.0;
}

int main(int argc, char** argv)
{
    CommandLineParser parser(argc, argv, keys);
    parser.about("forestmod_detector_bench: forest search vs exhaustive LINEMOD on rendered LM-O "
                 "scenes (hits, rejection, candidates, time)");
    if (parser.has("help"))
    {
        parser.printMessage();
        return 0;
    }
    std::string data = parser.get<std::string>("data");
    if (data.empty() && getenv("FORESTMOD_SHARED_DATA"))
        data = getenv("FORESTMOD_SHARED_DATA");
    std::string mini = parser.get<std::string>("mini");
    if (mini.empty() && getenv("OPENCV_TEST_DATA_PATH"))
        mini = std::string(getenv("OPENCV_TEST_DATA_PATH")) + "/forestmod/lmo_mini";
    const std::vector<std::string> obj_s = splitList(parser.get<std::string>("objects"));
    const bool together = parser.get<int>("together") != 0;
    const int scenes = parser.get<int>("scenes");
    const float threshold = parser.get<float>("threshold");
    const bool run_exhaustive = parser.get<int>("exhaustive") != 0;
    const std::string map_dir = parser.get<std::string>("map");
    const bool verbose = parser.get<int>("verbose") != 0;
    const int only = parser.get<int>("only");
    const std::vector<std::string> inplane = splitList(parser.get<std::string>("inplane"));
    const std::vector<std::string> radii_s = splitList(parser.get<std::string>("radii"));

    DetectorParams p;
#define BENCH_SET(flag, field, type) \
    if (parser.get<double>(flag) >= 0) \
        p.field = (type)parser.get<double>(flag);
    BENCH_SET("trees", forest.num_trees, int)
    BENCH_SET("depth", forest.max_depth, int)
    BENCH_SET("xi", forest.fuzzy_margin, float)
    BENCH_SET("rdims", forest.rejector_dims, int)
    BENCH_SET("rcov", forest.rejector_coverage, float)
    BENCH_SET("rnoise", forest.rejector_noise, float)
    BENCH_SET("tau", forest.rejector_tau, float)
    BENCH_SET("rho", forest.rejector_rho, float)
    BENCH_SET("any", forest.reject_any_tree, bool)
    BENCH_SET("fseed", forest.seed, int)
    BENCH_SET("grid", grid_size, int)
    BENCH_SET("step", location_step, int)
    BENCH_SET("min_labels", min_window_labels, float)
    BENCH_SET("dominant", dominant_window, int)
    if (parser.get<double>("depth_tol") > -2)
        p.depth_range_tolerance = (float)parser.get<double>("depth_tol");
    if (parser.get<double>("eratio") > -2)
        p.exhaustive_ratio = (float)parser.get<double>("eratio");
    BENCH_SET("gratio", group_size_ratio, float)
    BENCH_SET("leaf_samples", auto_depth_leaf_samples, float)
    BENCH_SET("k", max_survivors, int)
    BENCH_SET("chunk", chunk_size, int)
    BENCH_SET("alpha", alpha, float)
    BENCH_SET("bf", breadth_first, bool)
    BENCH_SET("ds", depth_samples, int)
    BENCH_SET("dtol", depth_tolerance, int)
#undef BENCH_SET
    if (!parser.check() || obj_s.empty() || scenes <= 0 || inplane.size() != 3 || radii_s.empty())
    {
        parser.printErrors();
        parser.printMessage();
        return 1;
    }

    try
    {
        std::vector<int> ids;
        std::vector<Mesh> meshes;
        for (size_t i = 0; i < obj_s.size(); ++i)
        {
            const int id = atoi(obj_s[i].c_str());
            std::string path = cv::format("%s/lmo/models/obj_%06d.ply", data.c_str(), id);
            if (!utils::fs::exists(path) && id == 1)
                path = mini + "/models/obj_000001.ply";
            if (!utils::fs::exists(path))
            {
                std::cerr << "no mesh for object " << id << " (" << path
                          << "): give --data or set FORESTMOD_SHARED_DATA" << std::endl;
                return 1;
            }
            ids.push_back(id);
            meshes.push_back(Mesh::load(path));
        }
        std::vector<Mat> bg;
        const char* frames[] = { "000224", "000902", "001038" };
        for (int i = 0; i < 3; ++i)
        {
            const std::string f = cv::format("%s/test/000002/rgb/%s.png", mini.c_str(), frames[i]);
            Mat img = imread(f, IMREAD_COLOR);
            if (img.empty())
            {
                std::cerr << "cannot read " << f << ": give --mini (testdata/forestmod/lmo_mini)"
                          << std::endl;
                return 1;
            }
            bg.push_back(img);
        }

        const Matx33d K = lmoIntrinsics();
        const Size size(640, 480);
        Ptr<Renderer> renderer = Renderer::create(size);
        SceneSynthesizer synth(renderer, K);
        for (size_t i = 0; i < meshes.size(); ++i)
            synth.addObject(meshes[i]);
        synth.setBackgrounds(bg);
        ViewSampler::Params sp;
        sp.level = parser.get<int>("level");
        sp.min_elevation = parser.get<double>("min_elevation");
        sp.radii.clear();
        for (size_t i = 0; i < radii_s.size(); ++i)
            sp.radii.push_back(atof(radii_s[i].c_str()));
        sp.inplane_min = atof(inplane[0].c_str());
        sp.inplane_max = atof(inplane[1].c_str());
        sp.inplane_step = atof(inplane[2].c_str());
        const ViewSampler sampler(sp);

        std::vector<Ptr<linemod::Modality> > mods;
        mods.push_back(linemod::Modality::create("ColorGradient"));
        if (parser.get<std::string>("modalities") == "linemod")
            mods.push_back(linemod::Modality::create("DepthNormal"));
        mods.push_back(ColorHue::create());
        std::vector<int> T;
        T.push_back(5);
        T.push_back(8);
        DetectorParams pe = p;
        pe.use_forest = false;

        std::printf("params: trees %d depth %d xi %.2f rdims %d rcov %.2f rnoise %.3f tau %.2f "
                    "any %d grid %d step %d min_labels %.2f dominant %d depth_tol %.2f k %d "
                    "chunk %d "
                    "depth_samples %d\n",
                    p.forest.num_trees, p.forest.max_depth, p.forest.fuzzy_margin,
                    p.forest.rejector_dims, p.forest.rejector_coverage, p.forest.rejector_noise,
                    p.forest.rejector_tau, (int)p.forest.reject_any_tree, p.grid_size,
                    p.location_step, p.min_window_labels, p.dominant_window,
                    p.depth_range_tolerance,
                    p.max_survivors, p.chunk_size, p.depth_samples);

        const int groups = together ? 1 : (int)meshes.size();
        double all_rej = 0, all_scenes = 0;
        for (int g = 0; g < groups; ++g)
        {
            cv::forestmod::Detector forest(mods, T, p), exhaustive(mods, T, pe);
            std::map<String, std::vector<TemplateInfo> > info;
            std::vector<std::vector<TemplateView> > views(meshes.size());
            const int o0 = together ? 0 : g, o1 = together ? (int)meshes.size() : g + 1;
            for (int o = o0; o < o1; ++o)
            {
                const String cls = cv::format("obj%d", ids[o]);
                const Point3f c = meshes[o].center();
                renderTemplates(meshes[o], sampler, K, size,
                                [&](const TemplateView& v, int, int) -> bool {
                                    const std::vector<Mat> src = sourcesOf(mods, v.color, v.depth);
                                    Rect bb;
                                    const int id = forest.addTemplate(src, cls, v.mask, v.R, v.t,
                                                                      v.K, &bb);
                                    if (id < 0)
                                        return true;
                                    if (run_exhaustive)
                                        exhaustive.addTemplate(src, cls, v.mask, v.R, v.t, v.K);
                                    const Vec3d pc = v.K * (v.R * Vec3d(c.x, c.y, c.z) + v.t);
                                    TemplateInfo ti;
                                    ti.centre_offset = Point2d(pc[0] / pc[2] - bb.x,
                                                               pc[1] / pc[2] - bb.y);
                                    ti.R = v.R;
                                    info[cls].push_back(ti);
                                    TemplateView light = v;
                                    light.color.release();
                                    light.depth.release();
                                    light.mask.release();
                                    views[o].push_back(light);
                                    return true;
                                });
            }
            const int64 tt0 = getTickCount();
            forest.train();
            const double train_ms = (getTickCount() - tt0) * 1000.0 / getTickFrequency();
            std::printf("detector %d: %d templates, %d classes, train %.0f ms, %d search "
                        "groups\n", g, forest.numTemplates(), (int)forest.classIds().size(),
                        train_ms, forest.numSearchGroups());
            for (int sg = 0; sg < forest.numSearchGroups(); ++sg)
            {
                const TemplateForest::Statistics fs = forest.getForest(sg)->statistics();
                const std::vector<String> gc = forest.getSearchGroupClasses(sg);
                std::string names;
                for (size_t c = 0; c < gc.size(); ++c)
                    names += (c ? "," : "") + gc[c];
                std::printf("  group %d (%s): %d templates, forest %d trees depth %d, %d "
                            "leaves, %.1f templates/leaf, %.2f leaves/template\n", sg,
                            names.c_str(), forest.getForest(sg)->numTemplates(), fs.trees,
                            fs.max_depth, fs.leaves, fs.mean_leaf_size,
                            fs.mean_leaves_per_template);
            }
            for (int o = o0; o < o1; ++o)
            {
                const String cls = cv::format("obj%d", ids[o]);
                if (views[o].empty())
                {
                    std::printf("%s: no template (every view was rejected by addTemplate)\n",
                                cls.c_str());
                    continue;
                }
                RNG rng(parser.get<int>("seed") + ids[o]);
                int hits_f = 0, hits_e = 0;
                double rejected = 0, rej_depth_range = 0, rej_flat = 0;
                DetectionStats sum;
                double t_exh = 0;
                for (int k = 0; k < scenes; ++k)
                {
                    const TemplateView& v = views[o][rng.uniform(0, (int)views[o].size())];
                    const SyntheticScene scene = synth.render(o, v.R, v.t, rng);
                    if (only >= 0 && k != only)
                        continue;
                    const std::vector<Mat> src = sourcesOf(mods, scene.color, scene.depth);
                    std::vector<PoseMatch> mf, me;
                    DetectionStats st;
                    forest.match(src, threshold, mf, std::vector<String>(), std::vector<Mat>(),
                                 &st);
                    const bool hf = evaluate(mf, cls, info, scene, K, true);
                    bool he = false;
                    if (run_exhaustive)
                    {
                        const int64 e0 = getTickCount();
                        exhaustive.match(src, threshold, me);
                        t_exh += (getTickCount() - e0) * 1000.0 / getTickFrequency();
                        he = evaluate(me, cls, info, scene, K, true);
                    }
                    hits_f += hf;
                    hits_e += he;
                    rejected += st.rejectedFraction();
                    rej_depth_range += st.locations ? double(st.rejected_depth_range) / st.locations : 0;
                    rej_flat += st.locations ? double(st.rejected_flat) / st.locations : 0;
                    sum.t_quantize_ms += st.t_quantize_ms;
                    sum.t_tree_ms += st.t_tree_ms;
                    sum.t_valid_ms += st.t_valid_ms;
                    sum.t_total_ms += st.t_total_ms;
                    sum.locations += st.locations;
                    sum.validated += st.validated;
                    sum.candidates += st.candidates;
                    if (verbose)
                        std::printf("  %s scene %d: forest %s exhaustive %s rejected %.1f %% "
                                    "matches %d\n", cls.c_str(), k, hf ? "hit " : "miss",
                                    he ? "hit " : "miss", 100 * st.rejectedFraction(),
                                    (int)mf.size());
                    if (verbose && (hf != he || !hf))
                    {
                        const PoseMatch* ms[2] = { mf.empty() ? 0 : &mf[0],
                                                   me.empty() ? 0 : &me[0] };
                        for (int w = 0; w < 2; ++w)
                            if (ms[w])
                            {
                                const TemplateInfo& ti = info[ms[w]->class_id][ms[w]->template_id];
                                const Point2d ce = Point2d(ms[w]->x, ms[w]->y) + ti.centre_offset;
                                std::printf("    %s top: %s tpl %d at (%d, %d) %.1f %%, centre "
                                            "error %.1f px\n", w ? "exhaustive" : "forest",
                                            ms[w]->class_id.c_str(), ms[w]->template_id,
                                            ms[w]->x, ms[w]->y, ms[w]->similarity,
                                            cv::norm(ce - scene.center));
                            }
                    }
                    if (!map_dir.empty() && k == 0)
                    {
                        Mat m = st.rejection_map, vis;
                        m.convertTo(vis, CV_8U, 25, 30);
                        vis.setTo(255, m == -1);
                        resize(vis, vis, scene.color.size(), 0, 0, INTER_NEAREST);
                        Mat col, both;
                        applyColorMap(vis, col, COLORMAP_JET);
                        hconcat(scene.color, col, both);
                        imwrite(cv::format("%s/rej_%d.png", map_dir.c_str(), ids[o]), both);
                    }
                }
                all_rej += rejected;
                all_scenes += scenes;
                std::printf("%s: %d templates | hits forest %d/%d exhaustive %d/%d | rejected "
                            "%.1f %% (flat %.1f %%, depth range %.1f %%) | candidates/validated "
                            "location %.1f | ms/frame quant %.1f tree %.1f valid %.1f total %.1f "
                            "(exhaustive %.1f)\n",
                            cls.c_str(), (int)info[cls].size(), hits_f, scenes, hits_e,
                            run_exhaustive ? scenes : 0, 100 * rejected / scenes,
                            100 * rej_flat / scenes, 100 * rej_depth_range / scenes,
                            sum.validated ? double(sum.candidates) / sum.validated : 0.,
                            sum.t_quantize_ms / scenes, sum.t_tree_ms / scenes,
                            sum.t_valid_ms / scenes, sum.t_total_ms / scenes, t_exh / scenes);
                std::fflush(stdout);
            }
        }
        std::printf("mean rejected %.1f %%\n", 100 * all_rej / std::max(1.0, all_scenes));
    }
    catch (const cv::Exception& e)
    {
        std::cerr << "error: " << e.what() << std::endl;
        return 1;
    }
    return 0;
}
