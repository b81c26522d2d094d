// This file is part of OpenCV project.
// It is subject to the license terms in the LICENSE file found in the top-level directory
// of this distribution and at http://opencv.org/license.html

// forestmod_eval: command line, regimes, small helpers, results and progress bar.

#include "eval_common.hpp"

#include <opencv2/core/utils/filesystem.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <limits>
#include <sstream>

#ifdef __linux__
#include <unistd.h>
#endif

namespace fmeval {

static const char* const keys
    = "{help h usage ?  |          | print this message }"
      "{dataset         |          | BOP dataset root (camera.json, models/, <split>/) }"
      "{split           | test     | split folder }"
      "{scene           | 2        | scene id }"
      "{objects         |          | comma-separated object ids (default: every model with a "
      "mesh) }"
      "{frames          | 0        | frames to use (0: all) }"
      "{first_frame     | 0        | frames of the scene skipped before those used (to set a "
      "parameter on frames that a run without it reports) }"
      "{synthetic       | 0        | N > 0: evaluate on N rendered RGB-D scenes per object instead "
      "of the dataset's frames (ADD/ADI) }"
      "{rgb_only        |          | ignore the dataset's (or the rendered scenes') depth "
      "(RGB-only evaluation) }"
      "{modalities      |          | comma-separated ColorGradient, DepthNormal, ColorHue "
      "(default: ColorGradient,ColorHue; with depth ColorGradient,DepthNormal,ColorHue) }"
      "{threshold       | 80       | similarity threshold (percent) of both detectors }"
      "{rgb_refine      | true     | without depth: refine the best match's pose by edge alignment "
      "(PoseParams::rgb_refine, refinePoseEdges), the pose chosen among the overlapping matches "
      "(PoseParams::rgb_hypotheses); false: score the best template's pose as is }"
      "{rgb_hypotheses  |          | without depth: matches refined per location, the best edge "
      "fit kept (PoseParams::rgb_hypotheses; default: the library's, 24) }"
      "{rgb_keep        |          | without depth: hypotheses of a location refined past the "
      "first pass (PoseParams::rgb_keep; default: the library's, 4) }"
      "{rgb_grid        | false    | the coarse grid search of refinePoseEdges before the "
      "refinement (EdgeRefineParams::search_angle 12 degrees; library default: off) }"
      "{regime          | paper    | template sampling: paper (LINEMOD's: level 2 ~16 deg views, "
      "elevation -15..90, 650/900/1150 mm, in-plane -45..45 step 15: 2121 poses) or quick (level "
      "1, 700/1100 mm, in-plane -60..60 step 30: 260 poses); the flags below override it }"
      "{level           |          | view sampler: icosahedron subdivisions (1: ~32 deg, "
      "2: ~16 deg) }"
      "{min_elevation   |          | view sampler: lowest elevation (degrees) }"
      "{max_elevation   |          | view sampler: highest elevation (degrees) }"
      "{radii           |          | view sampler: camera distances (mm) }"
      "{inplane         |          | view sampler: in-plane rotations min,max,step (degrees) }"
      "{dry_run         |          | print the sampling of the regime (and flags) and stop }"
      "{tables          | true     | the paper's Tables 1 and 2 (false: the sweeps only) }"
      "{no_multi        |          | skip Table 2 (all objects in one model) }"
      "{five_trees      | true     | Table 1: the forestmod 5 trees row (false: skipped) }"
      "{sweep           | all      | scaling sweeps: none, templates, objects or all }"
      "{sweep_templates | 100,300,1000,3000,10000 | templates sweep: templates of one object "
      "(poses of a denser sampler, spread evenly) }"
      "{sweep_object    | 0        | templates sweep: object id (0: the first object) }"
      "{sweep_classes   | 1,2,4,8,16,32 | objects sweep: classes in one model (beyond the "
      "dataset's objects: recoloured and rescaled copies of its meshes) }"
      "{sweep_per_class | 500      | objects sweep: templates per class (0: every pose of the "
      "sampler) }"
      "{sweep_frames    | 5        | frames of the sweeps (0: the run's frames) }"
      "{plots           | forestmod_eval_plots | folder of the sweeps' PNG plots and scaling.json }"
      "{repeat          | 3        | match() calls per frame; every time is the best of them }"
      "{cache           |          | template cache folder (default: <build>/forestmod_cache) }"
      "{json            |          | write the results as JSON to this file }"
      "{heatmap         |          | folder for rejection heat maps (PNG) of the first frames }"
      "{heatmap_frames  | 3        | frames with a heat map }"
      "{threads         | 1        | OpenCV threads while matching (1: fair to single-threaded "
      "cv::linemod) }"
      "{train_threads   | 2        | OpenCV threads while training the forests (not timed) }"
      "{seed            | 1        | random seed of --synthetic }"
      "{depth_samples   | -1       | experiment: DetectorParams::depth_samples (-1: library "
      "default; 0: no depth samples, templates cached separately) }"
      "{depth_tolerance | -1       | experiment: DetectorParams::depth_tolerance (mm; -1: default) }"
      "{max_survivors   | -1       | experiment: DetectorParams::max_survivors (-1: default) }"
      "{exhaustive_ratio |         | experiment: DetectorParams::exhaustive_ratio (empty: default; "
      "negative: never exhaustive, 0: always) }"
      "{descent_cost    | -1       | experiment: DetectorParams::descent_cost (validated pairs "
      "per tree node the sample visits; -1: default) }"
      "{min_forest_templates | -1  | experiment: DetectorParams::min_forest_templates (-1: "
      "default; 0: every search group decided by the sample) }"
      "{search_per_class | false   | DetectorParams::search_per_class: each class of a model "
      "keeps lists of its own (Table 2: each object's matches those of its own templates alone) }"
      "{depth_range_tolerance |    | experiment: DetectorParams::depth_range_tolerance (empty: "
      "default; negative: off) }"
      "{fuzzy_margin    | -1       | experiment: ForestParams::fuzzy_margin of the forests (0: "
      "crisp splits; -1: default) }"
      "{any_tree        | -1       | experiment: ForestParams::reject_any_tree of the forests (0, 1; -1: default) }"
      "{hue_feature_saturation | -1 | experiment: ColorHue::Params::feature_saturation_threshold "
      "of the templates (0..255; -1: default) }"
      "{hue_feature_area | -1      | experiment: ColorHue::Params::min_feature_area of the "
      "templates (0..1; -1: default) }"
      "{leaf_samples    | -1       | experiment: DetectorParams::auto_depth_leaf_samples (-1: "
      "default; 0: the paper's depth 8 / 9) }"
      "{depth_validation | 1       | experiment: 0 turns the depth validation term off after the "
      "templates (with their depth samples, used for the initial poses) are made }"
      "{verify_k        | 10       | hypotheses per object (locations after grouping the "
      "matches), verified and counted in recall@k (VerificationParams::top_k) }"
      "{second_round    | -1       | VerificationParams::second_round_below of the verified "
      "rows without depth (0: one round of verify_k; -1: the library's default) }"
      "{background_weight | -1     | VerificationParams::background_weight of the verified rows "
      "(0: their hypotheses in the matcher's order; -1: the library's default) }"
      "{verify_weights  |          | w_similarity,w_color,w_edges,w_depth[,w_region] of the "
      "verification (default: VerificationParams') }"
      "{gt_similarity   |          | also match, for every object and frame, a template made at "
      "its ground-truth pose: its similarity on the object against the detectors' best matches "
      "(a table; JSON gt_similarity, and for both detectors correct_similarity and "
      "off_similarity) }"
      "{force           |          | overwrite the --json file, heat maps and plots }";

EvalOptions::EvalOptions()
    : scene(2), max_frames(0), first_frame(0), synthetic(0), rgb_only(false), threshold(80.f), rgb_refine(true),
      rgb_grid(false), rgb_hypotheses(fm::PoseParams().rgb_hypotheses),
      rgb_keep(fm::PoseParams().rgb_keep), regime("paper"),
      tables(true), multi(true), heat_frames(3), threads(1),
      train_threads(2), seed(1), repeat(3), force(false), dry_run(false), sweep_templates(true),
      sweep_objects(true), sweep_object(0), sweep_per_class(500), sweep_frames(5),
      depth_samples(-1), depth_tolerance(-1), max_survivors(-1), any_tree(-1),
      exhaustive_ratio(0.f), has_exhaustive_ratio(false), descent_cost(-1.f),
      min_forest_templates(-1),
      search_per_class(false),
      depth_range_tolerance(0.f),
      has_depth_range_tolerance(false), fuzzy_margin(-1.f), leaf_samples(-1.f),
      depth_validation(true), hue_feature_saturation(-1),
      hue_feature_area(-1.f), five_trees(true), verify_k(10), second_round(-1),
      background_weight(-1),
      gt_similarity(false)
{
    regimeSampler(regime, sampler);
}

bool regimeSampler(const std::string& regime, fm::ViewSampler::Params& p)
{
    p = fm::ViewSampler::Params();
    p.min_elevation = -15; // LM-O's poses go down to -14 degrees
    p.max_elevation = 90;
    if (regime == "paper")
    {
        // LINEMOD (ACCV 2012): ~15 degrees between views, distances over 650..1150 mm, in-plane
        // -45..45 step 15
        p.level = 2;
        p.radii.assign(1, 650.0);
        p.radii.push_back(900.0);
        p.radii.push_back(1150.0);
        p.inplane_min = -45;
        p.inplane_max = 45;
        p.inplane_step = 15;
        return true;
    }
    if (regime == "quick")
    {
        p.level = 1;
        p.radii.assign(1, 700.0);
        p.radii.push_back(1100.0);
        p.inplane_min = -60;
        p.inplane_max = 60;
        p.inplane_step = 30;
        return true;
    }
    return false;
}

std::string samplingText(const fm::ViewSampler::Params& p)
{
    const fm::ViewSampler s(p);
    std::string radii;
    if (p.radii.size() <= 8)
        for (size_t i = 0; i < p.radii.size(); ++i)
            radii += cv::format("%s%g", i ? ", " : "", p.radii[i]);
    else // the output must stay readable (and the JSON string short)
        radii = cv::format("%g, %g, ..., %g: %d distances", p.radii[0], p.radii[1],
                           p.radii.back(), (int)p.radii.size());
    return cv::format("level %d, elevation %g..%g deg, %d views x radii {%s} mm x in-plane %g..%g "
                      "step %g deg (%d angles) = %d poses per object",
                      p.level, p.min_elevation, p.max_elevation, (int)s.viewpoints().size(),
                      radii.c_str(), p.inplane_min, p.inplane_max, p.inplane_step,
                      (int)s.inplaneAngles().size(), s.size());
}

fm::ColorHue::Params hueParams(const EvalOptions& opt)
{
    fm::ColorHue::Params p;
    if (opt.hue_feature_saturation >= 0)
        p.feature_saturation_threshold = opt.hue_feature_saturation;
    if (opt.hue_feature_area >= 0.f)
        p.min_feature_area = opt.hue_feature_area;
    return p;
}

fm::DetectorParams experimentParams(const EvalOptions& opt, fm::DetectorParams p)
{
    if (opt.depth_samples >= 0)
        p.depth_samples = opt.depth_samples;
    if (opt.depth_tolerance > 0)
        p.depth_tolerance = opt.depth_tolerance;
    if (opt.max_survivors > 0)
        p.max_survivors = opt.max_survivors;
    if (opt.has_exhaustive_ratio)
        p.exhaustive_ratio = opt.exhaustive_ratio;
    if (opt.descent_cost >= 0.f)
        p.descent_cost = opt.descent_cost;
    if (opt.min_forest_templates >= 0)
        p.min_forest_templates = opt.min_forest_templates;
    p.search_per_class = opt.search_per_class;
    if (opt.has_depth_range_tolerance)
        p.depth_range_tolerance = opt.depth_range_tolerance;
    if (opt.fuzzy_margin >= 0.f)
        p.forest.fuzzy_margin = opt.fuzzy_margin;
    if (opt.any_tree >= 0)
        p.forest.reject_any_tree = opt.any_tree != 0;
    if (opt.leaf_samples >= 0.f)
        p.auto_depth_leaf_samples = opt.leaf_samples;
    return p;
}

static bool parseInts(const std::string& s, std::vector<int>& out)
{
    std::vector<double> v;
    if (!parseNumbers(s, v))
        return false;
    out.clear();
    for (size_t i = 0; i < v.size(); ++i)
    {
        if (v[i] != std::floor(v[i]))
            return false;
        out.push_back((int)v[i]);
    }
    return true;
}

static int fail(const std::string& message)
{
    std::cerr << "forestmod_eval: " << message << "\n";
    return 1;
}

int parseOptions(int argc, char** argv, EvalOptions& opt)
{
    cv::CommandLineParser parser(argc, argv, keys);
    parser.about("forestmod_eval: forestmod::Detector (1 and 5 trees) vs cv::linemod::Detector on "
                 "a BOP dataset or rendered RGB-D scenes (the paper's Tables 1 and 2) and the "
                 "scaling of both with templates and objects");
    if (parser.has("help"))
    {
        parser.printMessage();
        return -1; // done, exit code 0
    }
    opt.root = parser.get<std::string>("dataset");
    opt.split = parser.get<std::string>("split");
    opt.scene = parser.get<int>("scene");
    const std::string objects_arg = parser.get<std::string>("objects");
    opt.max_frames = parser.get<int>("frames");
    opt.first_frame = parser.get<int>("first_frame");
    opt.synthetic = parser.get<int>("synthetic");
    opt.rgb_only = parser.has("rgb_only");
    opt.modalities_arg = splitList(parser.get<std::string>("modalities"));
    opt.threshold = parser.get<float>("threshold");
    opt.rgb_refine = parser.get<bool>("rgb_refine");
    opt.rgb_grid = parser.get<bool>("rgb_grid");
    if (parser.has("rgb_hypotheses"))
        opt.rgb_hypotheses = parser.get<int>("rgb_hypotheses");
    if (parser.has("rgb_keep"))
        opt.rgb_keep = parser.get<int>("rgb_keep");
    opt.regime = parser.get<std::string>("regime");
    opt.dry_run = parser.has("dry_run");
    opt.tables = parser.get<bool>("tables");
    opt.multi = !parser.has("no_multi");
    opt.five_trees = parser.get<bool>("five_trees");
    const std::string sweep = parser.get<std::string>("sweep");
    const std::string counts_arg = parser.get<std::string>("sweep_templates");
    const std::string classes_arg = parser.get<std::string>("sweep_classes");
    opt.sweep_object = parser.get<int>("sweep_object");
    opt.sweep_per_class = parser.get<int>("sweep_per_class");
    opt.sweep_frames = parser.get<int>("sweep_frames");
    opt.plots_dir = parser.get<std::string>("plots");
    opt.repeat = parser.get<int>("repeat");
    opt.cache_dir = parser.get<std::string>("cache");
    opt.json_path = parser.get<std::string>("json");
    opt.heat_dir = parser.get<std::string>("heatmap");
    opt.heat_frames = parser.get<int>("heatmap_frames");
    opt.threads = parser.get<int>("threads");
    opt.train_threads = parser.get<int>("train_threads");
    opt.seed = parser.get<int>("seed");
    opt.depth_samples = parser.get<int>("depth_samples");
    opt.depth_tolerance = parser.get<int>("depth_tolerance");
    opt.depth_validation = parser.get<int>("depth_validation") != 0;
    opt.max_survivors = parser.get<int>("max_survivors");
    opt.min_forest_templates = parser.get<int>("min_forest_templates");
    opt.descent_cost = parser.get<float>("descent_cost");
    opt.search_per_class = parser.get<bool>("search_per_class");
    opt.has_exhaustive_ratio = !parser.get<std::string>("exhaustive_ratio").empty();
    if (opt.has_exhaustive_ratio)
        opt.exhaustive_ratio = parser.get<float>("exhaustive_ratio");
    opt.has_depth_range_tolerance = !parser.get<std::string>("depth_range_tolerance").empty();
    if (opt.has_depth_range_tolerance)
        opt.depth_range_tolerance = parser.get<float>("depth_range_tolerance");
    opt.fuzzy_margin = parser.get<float>("fuzzy_margin");
    opt.any_tree = parser.get<int>("any_tree");
    opt.leaf_samples = parser.get<float>("leaf_samples");
    opt.hue_feature_saturation = parser.get<int>("hue_feature_saturation");
    opt.hue_feature_area = parser.get<float>("hue_feature_area");
    opt.force = parser.has("force");
    opt.verify_k = parser.get<int>("verify_k");
    opt.gt_similarity = parser.has("gt_similarity");
    opt.background_weight = parser.get<double>("background_weight");
    opt.second_round = parser.get<double>("second_round");
    const std::string weights_arg = parser.get<std::string>("verify_weights");
    // the sampler: the regime's, then the flags given
    fm::ViewSampler::Params& sp = opt.sampler;
    if (!regimeSampler(opt.regime, sp))
        return fail("--regime is paper or quick, not '" + opt.regime + "'");
    opt.sampler_overrides.clear();
    if (parser.has("level"))
    {
        sp.level = parser.get<int>("level");
        opt.sampler_overrides.push_back("--level");
    }
    if (parser.has("min_elevation"))
    {
        sp.min_elevation = parser.get<double>("min_elevation");
        opt.sampler_overrides.push_back("--min_elevation");
    }
    if (parser.has("max_elevation"))
    {
        sp.max_elevation = parser.get<double>("max_elevation");
        opt.sampler_overrides.push_back("--max_elevation");
    }
    if (!parser.check())
    {
        parser.printErrors();
        return 1;
    }
    if (parser.has("radii"))
    {
        if (!parseNumbers(parser.get<std::string>("radii"), sp.radii) || sp.radii.empty())
            return fail("--radii is a list of distances (mm)");
        opt.sampler_overrides.push_back("--radii");
    }
    if (parser.has("inplane"))
    {
        std::vector<double> inplane;
        if (!parseNumbers(parser.get<std::string>("inplane"), inplane) || inplane.size() != 3)
            return fail("--inplane is min,max,step (degrees)");
        sp.inplane_min = inplane[0];
        sp.inplane_max = inplane[1];
        sp.inplane_step = inplane[2];
        opt.sampler_overrides.push_back("--inplane");
    }
    fm::ViewSampler(sp).validate();
    if (!objects_arg.empty())
    {
        if (!parseInts(objects_arg, opt.object_ids) || opt.object_ids.empty())
            return fail("--objects is a comma-separated list of ids");
    }
    if (opt.rgb_hypotheses < 1)
        return fail("--rgb_hypotheses must be >= 1");
    if (opt.rgb_keep < 1)
        return fail("--rgb_keep must be >= 1");
    if (opt.verify_k < 1)
        return fail("--verify_k must be >= 1");
    if (!(opt.second_round >= 0 || opt.second_round == -1) || !(opt.second_round < 1e6))
        return fail("--second_round must be finite and >= 0 (-1: the default)");
    if (opt.hue_feature_saturation < -1 || opt.hue_feature_saturation > 255)
        return fail("--hue_feature_saturation must be in [0, 255] (-1: the default)");
    if (opt.hue_feature_area != -1.f
        && !(opt.hue_feature_area >= 0.f && opt.hue_feature_area <= 1.f))
        return fail("--hue_feature_area must be in [0, 1] (-1: the default)");
    if (opt.fuzzy_margin < 0.f && opt.fuzzy_margin != -1.f)
        return fail("--fuzzy_margin must be >= 0 (-1: the default)");
    if (!weights_arg.empty()
        && (!parseNumbers(weights_arg, opt.verify_weights) || opt.verify_weights.size() < 4
            || opt.verify_weights.size() > 5))
        return fail("--verify_weights is w_similarity,w_color,w_edges,w_depth[,w_region]");
    if (sweep != "none" && sweep != "templates" && sweep != "objects" && sweep != "all")
        return fail("--sweep is none, templates, objects or all, not '" + sweep + "'");
    opt.sweep_templates = sweep == "templates" || sweep == "all";
    opt.sweep_objects = sweep == "objects" || sweep == "all";
    if (!parseInts(counts_arg, opt.sweep_counts) || opt.sweep_counts.empty()
        || !parseInts(classes_arg, opt.sweep_classes) || opt.sweep_classes.empty())
        return fail("--sweep_templates and --sweep_classes are comma-separated lists of counts");
    std::sort(opt.sweep_counts.begin(), opt.sweep_counts.end());
    std::sort(opt.sweep_classes.begin(), opt.sweep_classes.end());
    if (opt.sweep_counts[0] < 1 || opt.sweep_classes[0] < 1)
        return fail("--sweep_templates and --sweep_classes must be >= 1");
    if (opt.dry_run)
        return 0;
    if (opt.root.empty())
        return fail("--dataset is required (see --help)");
    if (!cv::utils::fs::exists(opt.root + "/camera.json"))
        return fail("no BOP dataset at " + opt.root + " (camera.json not found)");
    if (opt.max_frames < 0 || opt.first_frame < 0 || opt.synthetic < 0 || opt.threads < 1 || opt.train_threads < 1
        || opt.heat_frames < 0 || opt.threshold <= 0 || opt.threshold > 100 || opt.repeat < 1
        || opt.sweep_frames < 0 || opt.sweep_per_class < 0)
        return fail("--frames, --first_frame, --synthetic, --heatmap_frames, --sweep_frames, "
                    "--sweep_per_class must be >= 0, --threads, --train_threads and --repeat >= 1, --threshold in "
                    "(0, 100]");
    if (!opt.tables && !opt.sweep_templates && !opt.sweep_objects)
        return fail("--tables=false and --sweep=none: nothing to do");
    if (opt.cache_dir.empty())
        opt.cache_dir = executableDir(argc > 0 ? argv[0] : 0) + "/../forestmod_cache";
    return 0;
}

// ---------------------------------------------------------------------------------------------
// small helpers

bool parseNumbers(const std::string& s, std::vector<double>& out)
{
    out.clear();
    std::vector<std::string> items = splitList(s);
    for (size_t i = 0; i < items.size(); ++i)
    {
        char* end = 0;
        const double v = strtod(items[i].c_str(), &end);
        if (end == items[i].c_str() || *end != '\0')
            return false;
        out.push_back(v);
    }
    return true;
}

std::string lmoName(int obj_id)
{
    switch (obj_id)
    {
    case 1: return "ape";
    case 5: return "can";
    case 6: return "cat";
    case 8: return "driller";
    case 9: return "duck";
    case 10: return "eggbox";
    case 11: return "glue";
    case 12: return "holepuncher";
    default: return cv::format("obj_%06d", obj_id);
    }
}

double quantile(std::vector<double> v, double q)
{
    if (v.empty())
        return std::numeric_limits<double>::quiet_NaN();
    std::sort(v.begin(), v.end());
    const double pos = q * (v.size() - 1);
    const size_t i = (size_t)std::floor(pos);
    const size_t j = std::min(v.size() - 1, i + 1);
    return v[i] + (pos - i) * (v[j] - v[i]);
}

double median(std::vector<double> v)
{
    return quantile(v, 0.5);
}

// FNV-1a, 64 bit: the cache key of a mesh file and the sampling parameters
uint64_t fnv1a(const void* data, size_t n, uint64_t h)
{
    const unsigned char* p = static_cast<const unsigned char*>(data);
    for (size_t i = 0; i < n; ++i)
    {
        h ^= p[i];
        h *= 1099511628211ULL;
    }
    return h;
}

std::string executableDir(const char* argv0)
{
#ifdef __linux__
    char buf[4096];
    const ssize_t n = readlink("/proc/self/exe", buf, sizeof(buf) - 1);
    if (n > 0)
    {
        buf[n] = 0;
        std::string p(buf);
        return p.substr(0, p.find_last_of('/'));
    }
#endif
    std::string p(argv0 ? argv0 : "");
    const size_t k = p.find_last_of("/\\");
    return k == std::string::npos ? std::string(".") : p.substr(0, k);
}

// ---------------------------------------------------------------------------------------------
// results

Result::Result()
    : has_forest(false), locations(0), rejected(0), n2d(0), ok2d(0), okproj(0), nadd(0),
      okadd(0), ok2d_at10(0), okproj_at10(0), with_depth(false)
{
}

double ratio(int a, int b)
{
    return b > 0 ? double(a) / b : std::numeric_limits<double>::quiet_NaN();
}

double tTotal(const Result& r) { return median(r.total); }
double tQuant(const Result& r) { return median(r.quant); }
double tTree(const Result& r)
{
    return r.has_forest ? median(r.tree) : std::numeric_limits<double>::quiet_NaN();
}
double tValid(const Result& r)
{
    return r.has_forest ? median(r.valid) : std::numeric_limits<double>::quiet_NaN();
}
double rejectedFraction(const Result& r)
{
    return r.has_forest && r.locations > 0 ? double(r.rejected) / r.locations
                                           : std::numeric_limits<double>::quiet_NaN();
}
double addRate(const Result& r)
{
    return r.with_depth ? ratio(r.okadd, r.nadd) : std::numeric_limits<double>::quiet_NaN();
}

Result pooled(const std::vector<Result>& rs)
{
    Result p;
    if (rs.empty())
        return p;
    p = rs[0]; // times, locations: the same calls for every object
    p.n2d = p.ok2d = p.okproj = p.nadd = p.okadd = p.ok2d_at10 = p.okproj_at10 = 0;
    for (size_t i = 0; i < rs.size(); ++i)
    {
        p.ok2d_at10 += rs[i].ok2d_at10;
        p.okproj_at10 += rs[i].okproj_at10;
        p.n2d += rs[i].n2d;
        p.ok2d += rs[i].ok2d;
        p.okproj += rs[i].okproj;
        p.nadd += rs[i].nadd;
        p.okadd += rs[i].okadd;
    }
    return p;
}

// ---------------------------------------------------------------------------------------------
// progress bar (stderr)

void Progress::show(const std::string& what) const
{
    const int width = 30;
    const double f = total > 0 ? std::min(1.0, double(done) / total) : 1.0;
    const int filled = cvRound(f * width);
    fprintf(stderr, "\r[%s%s] %3d%% %-50.50s", std::string(filled, '#').c_str(),
            std::string(width - filled, '.').c_str(), cvRound(100 * f), what.c_str());
    fflush(stderr);
}

void Progress::step(const std::string& what)
{
    ++done;
    show(what);
}

void Progress::finish() const
{
    fprintf(stderr, "\n");
}

} // namespace fmeval
