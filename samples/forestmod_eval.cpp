// This file is part of OpenCV project.
// It is subject to the license terms in the LICENSE file found in the top-level directory
// of this distribution and at http://opencv.org/license.html

// Evaluation of forestmod::Detector against cv::linemod::Detector on a BOP dataset (e.g. LM-O)
// or on rendered RGB-D scenes: the paper's Table 1 (one object per model: T_tree, T_valid,
// T_total, accuracy, locations rejected, for 1 and 5 trees and for cv::linemod) and Table 2 (all
// objects in one model). Both detectors get the same templates, modalities, pyramid and frames.
// See doc/tutorial_train_detect_eval.md.

#include <opencv2/core.hpp>
#include <opencv2/core/utils/filesystem.hpp>
#include <opencv2/forestmod.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <opencv2/rgbd/linemod.hpp>

#include "output_path.hpp"
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <limits>
#include <map>
#include <sstream>

#ifdef __linux__
#include <unistd.h>
#endif

namespace fm = cv::forestmod;

static const char* keys
    = "{help h usage ?  |          | print this message }"
      "{dataset         |          | BOP dataset root (camera.json, models/, <split>/) }"
      "{split           | test     | split folder }"
      "{scene           | 2        | scene id }"
      "{objects         |          | comma-separated object ids (default: every model with a "
      "mesh) }"
      "{frames          | 0        | frames to use (0: all) }"
      "{synthetic       | 0        | N > 0: evaluate on N rendered RGB-D scenes per object instead "
      "of the dataset's frames (ADD/ADI) }"
      "{rgb_only        |          | ignore the dataset's depth (RGB-only evaluation) }"
      "{modalities      |          | comma-separated ColorGradient, DepthNormal, ColorHue "
      "(default: ColorGradient,ColorHue; with depth ColorGradient,DepthNormal,ColorHue) }"
      "{threshold       | 80       | similarity threshold (percent) of both detectors }"
      "{rgb_refine      | true     | without depth: refine the best match's pose by edge alignment "
      "(PoseParams::rgb_refine, refinePoseEdges), the pose chosen among the overlapping matches "
      "(PoseParams::rgb_hypotheses); false: score the best template's pose as is }"
      "{rgb_grid        | false    | the coarse grid search of refinePoseEdges (library default: "
      "on; off here: 4x faster; on the LM-O ape 11 instead of 13 of 22 poses under 5 px) }"
      "{level           | 1        | view sampler: icosahedron subdivisions (1: ~32 deg, "
      "2: ~16 deg) }"
      "{min_elevation   | -15      | view sampler: lowest elevation (degrees) }"
      "{max_elevation   | 90       | view sampler: highest elevation (degrees) }"
      "{radii           | 700,1100 | view sampler: camera distances (mm) }"
      "{inplane         | -60,60,30 | view sampler: in-plane rotations min,max,step (degrees) }"
      "{no_multi        |          | skip Table 2 (all objects in one model) }"
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
      "{any_tree        | -1       | experiment: ForestParams::reject_any_tree of the forests (0, 1; -1: default) }"
      "{leaf_samples    | -1       | experiment: DetectorParams::auto_depth_leaf_samples (-1: "
      "default; 0: the paper's depth 8 / 9) }"
      "{depth_validation | 1       | experiment: 0 turns the depth validation term off after the "
      "templates (with their depth samples, used for the initial poses) are made }"
      "{force           |          | overwrite the --json file and heat map PNGs }";

// ---------------------------------------------------------------------------------------------
// small helpers

static std::vector<std::string> splitList(const std::string& s)
{
    std::vector<std::string> out;
    std::stringstream ss(s);
    std::string item;
    while (std::getline(ss, item, ','))
        if (!item.empty())
            out.push_back(item);
    return out;
}

static bool parseNumbers(const std::string& s, std::vector<double>& out)
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

static std::string lmoName(int obj_id)
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

static double median(std::vector<double> v)
{
    if (v.empty())
        return std::numeric_limits<double>::quiet_NaN();
    std::sort(v.begin(), v.end());
    const size_t n = v.size();
    return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

// FNV-1a, 64 bit: the cache key of a mesh file and the sampling parameters
static uint64_t fnv1a(const void* data, size_t n, uint64_t h = 14695981039346656037ULL)
{
    const unsigned char* p = static_cast<const unsigned char*>(data);
    for (size_t i = 0; i < n; ++i)
    {
        h ^= p[i];
        h *= 1099511628211ULL;
    }
    return h;
}

static bool fileHash(const std::string& path, uint64_t& hash, size_t& size)
{
    std::ifstream f(path.c_str(), std::ios::binary);
    if (!f)
        return false;
    std::vector<char> buf((std::istreambuf_iterator<char>(f)), std::istreambuf_iterator<char>());
    size = buf.size();
    hash = fnv1a(buf.empty() ? "" : &buf[0], buf.size());
    return true;
}

static std::string executableDir(const char* argv0)
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
// data

/** A test image with its ground truth (dataset frame or rendered scene). */
struct EvalFrame
{
    int scene_id, im_id;
    cv::Mat rgb, depth;
    cv::Matx33d K;
    std::vector<fm::GroundTruth> gt;
    int owner; // --synthetic: index of the object the scene was made for; -1: every object
};

struct ObjectInfo
{
    int obj_id;
    std::string name, class_id, mesh_path, cache_file;
    fm::Mesh mesh;
    std::vector<cv::Point3f> pts; // model points for the metrics (subsampled vertices)
    double diameter;
    bool symmetric;
    std::vector<cv::Matx44d> symmetries;
    int templates;
};

/** One frame's outcome for one object (the JSON's "per_frame" list). */
struct FrameRecord
{
    int scene_id, im_id;
    double t_ms;
    int template_id; //!< the hypothesis whose pose is scored; -1: none
    float similarity;
    cv::Point pos;
    double iou, proj, add; //!< NaN where not measured
    std::vector<cv::linemod::Match> top; //!< the class's best matches (up to 5), as matched
};

/** Accumulated results of one detector on one object (or on the multi-object model). */
struct Result
{
    Result() : has_forest(false), locations(0), rejected(0), n2d(0), ok2d(0), okproj(0), nadd(0),
               okadd(0), with_depth(false) {}
    bool has_forest;
    std::vector<double> total, tree, valid, quant;
    int64 locations, rejected;
    int n2d, ok2d, okproj, nadd, okadd;
    bool with_depth;
    std::vector<FrameRecord> per_frame;
};

static double ratio(int a, int b)
{
    return b > 0 ? double(a) / b : std::numeric_limits<double>::quiet_NaN();
}

// ---------------------------------------------------------------------------------------------
// progress bar (stderr)

struct Progress
{
    Progress() : done(0), total(1), last(-1) {}
    int64 done, total;
    int64 last;
    void show(const std::string& what)
    {
        const int width = 30;
        const double f = total > 0 ? std::min(1.0, double(done) / total) : 1.0;
        const int filled = cvRound(f * width);
        fprintf(stderr, "\r[%s%s] %3d%% %-50.50s", std::string(filled, '#').c_str(),
                std::string(width - filled, '.').c_str(), cvRound(100 * f), what.c_str());
        fflush(stderr);
    }
    void step(const std::string& what)
    {
        ++done;
        show(what);
    }
    void finish()
    {
        fprintf(stderr, "\n");
    }
};

// ---------------------------------------------------------------------------------------------
// templates: rendered once, cached as a forestmod model per object

struct TemplateSetup
{
    std::vector<std::string> modalities; // names, in order
    fm::ViewSampler sampler;
    cv::Matx33d K;   // intrinsics of the dataset
    cv::Size size;   // image size of the dataset
};

// --depth_samples / --depth_tolerance (-1: the library's defaults)
static int g_depth_samples = -1, g_depth_tolerance = -1;
static int g_max_survivors = -1, g_any_tree = -1;
static float g_leaf_samples = -1.f;
static bool g_depth_validation = true;

static fm::DetectorParams experimentParams(fm::DetectorParams p)
{
    if (g_depth_samples >= 0)
        p.depth_samples = g_depth_samples;
    if (g_depth_tolerance > 0)
        p.depth_tolerance = g_depth_tolerance;
    if (g_max_survivors > 0)
        p.max_survivors = g_max_survivors;
    if (g_any_tree >= 0)
        p.forest.reject_any_tree = g_any_tree != 0;
    if (g_leaf_samples >= 0.f)
        p.auto_depth_leaf_samples = g_leaf_samples;
    return p;
}

static cv::Ptr<fm::Detector> makeDetector(const std::vector<std::string>& modalities)
{
    // LINEMOD's pyramid (T = 5, 8) with the modalities asked for
    std::vector<cv::Ptr<cv::linemod::Modality> > mods;
    for (size_t i = 0; i < modalities.size(); ++i)
        mods.push_back(modalities[i] == "ColorHue"
                           ? cv::Ptr<cv::linemod::Modality>(fm::ColorHue::create())
                           : cv::linemod::Modality::create(modalities[i]));
    std::vector<int> T;
    T.push_back(5);
    T.push_back(8);
    return cv::makePtr<fm::Detector>(mods, T, experimentParams(fm::DetectorParams()));
}

/** Templates are rendered in a square window around the principal point, large enough for the
object at the nearest distance, with the principal point moved accordingly: the same templates as
from the full image (the sampler's cameras look at the object's centre), at a fraction of the
pixels to render and quantize. */
static int renderWindow(const ObjectInfo& obj, const TemplateSetup& setup, double& max_extent)
{
    const cv::Point3f c = obj.mesh.center();
    double rmax = 0;
    for (size_t i = 0; i < obj.mesh.vertices.size(); ++i)
    {
        const cv::Point3f d = obj.mesh.vertices[i] - c;
        rmax = std::max(rmax, std::sqrt(double(d.dot(d))));
    }
    double rmin_cam = 1e30;
    for (size_t i = 0; i < setup.sampler.params.radii.size(); ++i)
        rmin_cam = std::min(rmin_cam, setup.sampler.params.radii[i]);
    const double f = std::max(setup.K(0, 0), setup.K(1, 1));
    max_extent = rmin_cam > rmax ? f * rmax / (rmin_cam - rmax) : 1e4;
    const int margin = 24;
    int S = 2 * cvCeil(max_extent) + 2 * margin;
    S = (S + 7) / 8 * 8;
    return std::min(S, 2 * std::max(setup.size.width, setup.size.height));
}

static std::string cacheKey(const ObjectInfo& obj, const TemplateSetup& setup, int window)
{
    uint64_t mesh_hash = 0;
    size_t mesh_size = 0;
    if (!fileHash(obj.mesh_path, mesh_hash, mesh_size))
        CV_Error_(cv::Error::StsError, ("cannot read %s", obj.mesh_path.c_str()));
    cv::FileStorage fs(".yml", cv::FileStorage::WRITE | cv::FileStorage::MEMORY);
    fs << "version" << 1;
    fs << "modalities" << "[:";
    for (size_t i = 0; i < setup.modalities.size(); ++i)
        fs << setup.modalities[i];
    fs << "]";
    fs << "K" << cv::Mat(setup.K);
    fs << "window" << window;
    fs << "sampler" << "{";
    setup.sampler.params.write(fs);
    fs << "}";
    fs << "mesh_size" << (double)mesh_size;
    const int ds = experimentParams(fm::DetectorParams()).depth_samples;
    const bool has_depth = std::find(setup.modalities.begin(), setup.modalities.end(),
                                     std::string("DepthNormal")) != setup.modalities.end();
    if (ds > 0 && has_depth) // templates with depth samples (their selection as of this version)
        fs << "depth_samples" << ds << "depth_sampler" << 2;
    const std::string text = fs.releaseAndGetString();
    const uint64_t h = fnv1a(text.data(), text.size(), mesh_hash);
    return cv::format("%s_%016llx", obj.name.c_str(), (unsigned long long)h);
}

static void renderObjectTemplates(fm::Detector& det, const ObjectInfo& obj,
                                  const TemplateSetup& setup, int S, Progress& progress)
{
    // intrinsics of the window: the principal point at the window's centre
    cv::Matx33d Kw = setup.K;
    Kw(0, 2) = setup.K(0, 2) - (cvRound(setup.K(0, 2)) - S / 2);
    Kw(1, 2) = setup.K(1, 2) - (cvRound(setup.K(1, 2)) - S / 2);
    cv::Ptr<fm::Renderer> renderer = fm::Renderer::create(cv::Size(S, S));
    const int handle = renderer->addMesh(obj.mesh);
    const std::vector<cv::Ptr<cv::linemod::Modality> > mods = det.getModalities();
    fm::renderTemplates(*renderer, handle, cv::Point3d(obj.mesh.center()), setup.sampler, Kw,
                        [&](const fm::TemplateView& v, int done, int total) -> bool {
                            if (cv::countNonZero(v.mask) > 0)
                            {
                                std::vector<cv::Mat> sources;
                                for (size_t m = 0; m < mods.size(); ++m)
                                    sources.push_back(mods[m]->name() == "DepthNormal" ? v.depth
                                                                                       : v.color);
                                det.addTemplate(sources, obj.class_id, v.mask, v.R, v.t, v.K);
                            }
                            if (done % 25 == 0 || done == total)
                                progress.show(cv::format("%s: rendering templates %d/%d",
                                                         obj.name.c_str(), done, total));
                            return true;
                        });
    det.setMesh(obj.class_id, obj.mesh);
}

/** The object's templates: from the cache, or rendered and cached. */
static cv::Ptr<fm::Detector> objectTemplates(ObjectInfo& obj, const TemplateSetup& setup,
                                             const std::string& cache_dir, Progress& progress,
                                             double& render_s)
{
    render_s = 0;
    double extent = 0;
    const int S = renderWindow(obj, setup, extent);
    obj.cache_file = cache_dir + "/" + cacheKey(obj, setup, S) + ".yml.gz";
    cv::Ptr<fm::Detector> det = makeDetector(setup.modalities);
    if (cv::utils::fs::exists(obj.cache_file))
    {
        try
        {
            progress.show(obj.name + ": loading cached templates");
            det->load(obj.cache_file);
            // the cache holds templates; the parameters are this build's defaults (and the
            // command's flags), not those saved with the cached model
            fm::DetectorParams p = experimentParams(fm::DetectorParams());
            if (!g_depth_validation)
                p.depth_samples = 0; // the samples loaded stay
            det->setParams(p);
            det->setMesh(obj.class_id, obj.mesh);
            obj.templates = det->numTemplates(obj.class_id);
            return det;
        }
        catch (const cv::Exception& e)
        {
            fprintf(stderr, "\nforestmod_eval: cache file %s unreadable (%s); rendering again\n",
                    obj.cache_file.c_str(), e.err.c_str());
            det = makeDetector(setup.modalities);
        }
    }
    const std::string none_file = obj.cache_file + ".none";
    if (cv::utils::fs::exists(none_file))
    {
        obj.templates = 0;
        return cv::Ptr<fm::Detector>();
    }
    cv::TickMeter tm;
    tm.start();
    renderObjectTemplates(*det, obj, setup, S, progress);
    tm.stop();
    render_s = tm.getTimeSec();
    obj.templates = det->numTemplates(obj.class_id);
    if (obj.templates == 0)
    {
        // every view lacks features of some modality (e.g. ColorHue on a white object)
        std::ofstream(none_file.c_str()) << "no template\n";
        return cv::Ptr<fm::Detector>();
    }
    det->save(obj.cache_file, true); // untrained: the forest is trained per experiment
    return det;
}

/** cv::linemod::Detector with exactly the templates (and modality objects) of a forestmod one. */
static cv::Ptr<cv::linemod::Detector> linemodCopy(const fm::Detector& det)
{
    std::vector<int> T;
    for (int l = 0; l < det.pyramidLevels(); ++l)
        T.push_back(det.getT(l));
    cv::Ptr<cv::linemod::Detector> lm = cv::makePtr<cv::linemod::Detector>(det.getModalities(), T);
    const std::vector<cv::String> ids = det.classIds();
    for (size_t c = 0; c < ids.size(); ++c)
        for (int i = 0; i < det.numTemplates(ids[c]); ++i)
        {
            const int id = lm->addSyntheticTemplate(det.getTemplates(ids[c], i), ids[c]);
            CV_Assert(id == i);
        }
    return lm;
}

// ---------------------------------------------------------------------------------------------
// accuracy

static cv::Rect2d projectedBox(const std::vector<cv::Point3f>& pts, const cv::Matx33d& K,
                               const cv::Matx33d& R, const cv::Vec3d& t)
{
    double x0 = 1e30, y0 = 1e30, x1 = -1e30, y1 = -1e30;
    for (size_t i = 0; i < pts.size(); ++i)
    {
        const cv::Vec3d p = R * cv::Vec3d(pts[i].x, pts[i].y, pts[i].z) + t;
        if (p[2] <= 0)
            continue;
        const double u = K(0, 0) * p[0] / p[2] + K(0, 2), v = K(1, 1) * p[1] / p[2] + K(1, 2);
        x0 = std::min(x0, u);
        y0 = std::min(y0, v);
        x1 = std::max(x1, u);
        y1 = std::max(y1, v);
    }
    return x1 < x0 ? cv::Rect2d() : cv::Rect2d(x0, y0, x1 - x0, y1 - y0);
}

/** Scores the best hypothesis of an object in a frame. matches: the detector's output (sorted,
best first); posedet: a forestmod::Detector with the same templates (pose labels, meshes). */
static void scoreFrame(const std::vector<cv::linemod::Match>& matches, const fm::Detector& posedet,
                       const EvalFrame& f, const ObjectInfo& obj, bool use_depth,
                       bool rgb_refine, bool rgb_grid, Result& res)
{
    const fm::GroundTruth* gt = 0;
    for (size_t i = 0; i < f.gt.size(); ++i)
        if (f.gt[i].obj_id == obj.obj_id)
        {
            gt = &f.gt[i];
            break;
        }
    if (!gt)
        return;
    fm::PoseParams pp;
    pp.rgb_refine = rgb_refine;
    if (!rgb_grid)
        pp.edge_params.search_angle = 0;
    // RGB-D: the best matches go through ICP and the depth check, the first one left is the
    // hypothesis (LINEMOD ACCV 2012's post-processing). RGB: the best match; refined, its pose
    // is chosen among the matches of the class overlapping it (as Detector::detect() does with
    // PoseParams::rgb_hypotheses; both detectors' matches come here before any NMS)
    const bool choose = !use_depth && rgb_refine;
    const size_t keep = use_depth ? (size_t)pp.max_per_class
                                  : choose ? (size_t)pp.rgb_hypotheses : 1;
    if (choose)
        pp.max_per_class = pp.rgb_hypotheses;
    std::vector<fm::PoseMatch> hyp;
    for (size_t i = 0; i < matches.size() && hyp.size() < keep; ++i)
    {
        if (matches[i].class_id != obj.class_id)
            continue;
        fm::PoseMatch pm(matches[i]);
        pm.pose = posedet.getTemplatePose(matches[i].class_id, matches[i].template_id);
        const cv::linemod::Template& t0 = posedet.getTemplates(matches[i].class_id,
                                                               matches[i].template_id)[0];
        pm.box = cv::Rect(matches[i].x, matches[i].y, t0.width, t0.height);
        if (choose && !hyp.empty() && fm::boxIoU(pm.box, hyp[0].box) <= 0.5)
            continue;
        hyp.push_back(pm);
    }
    if (!hyp.empty())
        posedet.estimatePoses(use_depth ? f.depth : cv::Mat(), f.K, hyp, pp,
                              !use_depth && rgb_refine ? f.rgb : cv::Mat());
    const fm::PoseMatch* best = 0;
    for (size_t i = 0; i < hyp.size() && (!best || choose); ++i)
        if (hyp[i].has_pose && (!best || hyp[i].edge_fit > best->edge_fit))
            best = &hyp[i];
    ++res.n2d;
    if (use_depth)
        ++res.nadd;
    const double nan = std::numeric_limits<double>::quiet_NaN();
    FrameRecord rec;
    rec.scene_id = f.scene_id;
    rec.im_id = f.im_id;
    rec.t_ms = res.total.empty() ? nan : res.total.back();
    rec.template_id = -1;
    rec.similarity = 0.f;
    rec.iou = rec.proj = rec.add = nan;
    for (size_t i = 0; i < matches.size() && rec.top.size() < 5; ++i)
        if (matches[i].class_id == obj.class_id)
            rec.top.push_back(matches[i]);
    if (!best)
    {
        res.per_frame.push_back(rec);
        return;
    }
    rec.template_id = best->template_id;
    rec.similarity = best->similarity;
    rec.pos = cv::Point(best->x, best->y);
    cv::Rect2d gt_box = gt->bbox_obj;
    if (gt_box.area() <= 0)
        gt_box = projectedBox(obj.pts, f.K, gt->R, gt->t);
    const cv::Rect2d est_box = projectedBox(obj.pts, f.K, best->R, best->t);
    rec.iou = fm::boxIoU(est_box, gt_box);
    if (rec.iou >= 0.5)
        ++res.ok2d;
    // 2D projection error, the smallest over the object's discrete symmetries
    double proj = fm::projectionError2D(obj.pts, f.K, best->R, best->t, gt->R, gt->t);
    for (size_t s = 0; s < obj.symmetries.size(); ++s)
    {
        const cv::Matx44d& S = obj.symmetries[s];
        const cv::Matx33d SR(S(0, 0), S(0, 1), S(0, 2), S(1, 0), S(1, 1), S(1, 2), S(2, 0),
                             S(2, 1), S(2, 2));
        const cv::Vec3d St(S(0, 3), S(1, 3), S(2, 3));
        proj = std::min(proj, fm::projectionError2D(obj.pts, f.K, best->R, best->t, gt->R * SR,
                                                    gt->R * St + gt->t));
    }
    rec.proj = proj;
    if (proj < 5.0)
        ++res.okproj;
    if (use_depth)
    {
        const double err = obj.symmetric ? fm::adiError(obj.pts, best->R, best->t, gt->R, gt->t)
                                         : fm::addError(obj.pts, best->R, best->t, gt->R, gt->t);
        rec.add = err / obj.diameter;
        if (fm::isCorrect(err, obj.diameter, 0.1))
            ++res.okadd;
    }
    res.per_frame.push_back(rec);
}

// ---------------------------------------------------------------------------------------------
// heat map of the rejection depth (the paper's last figure)

static cv::Mat heatmapImage(const cv::Mat& frame, const cv::Mat& map, int max_depth)
{
    cv::Mat dim;
    frame.convertTo(dim, -1, 0.5);
    cv::Mat over = dim.clone();
    const double cell = double(frame.cols) / map.cols;
    const int w = std::max(1, cvRound(cell));
    const int D = std::max(1, max_depth);
    cv::Mat lut(1, 256, CV_8UC1);
    for (int i = 0; i < 256; ++i)
        lut.at<uchar>(i) = (uchar)i;
    cv::Mat colors;
    cv::applyColorMap(lut, colors, cv::COLORMAP_JET);
    for (int r = 0; r < map.rows; ++r)
        for (int c = 0; c < map.cols; ++c)
        {
            const short d = map.at<short>(r, c);
            const cv::Point p(cvRound(c * cell), cvRound(r * cell));
            const cv::Rect box(p.x - w / 2, p.y - w / 2, w, w);
            if (d < 0) // reached validation: a white dot, the image stays visible
                cv::circle(over, p, std::max(1, w / 4), cv::Scalar(255, 255, 255), cv::FILLED);
            else
            {
                const cv::Vec3b col = colors.at<cv::Vec3b>(std::min(255, 255 * d / D));
                cv::rectangle(over, box, cv::Scalar(col[0], col[1], col[2]), cv::FILLED);
            }
        }
    cv::Mat blend;
    cv::addWeighted(dim, 0.3, over, 0.7, 0, blend);
    // legend: colour bar of the depth, white = reached validation
    cv::Mat legend(40, frame.cols * 2, CV_8UC3, cv::Scalar::all(0));
    const int bar = std::min(legend.cols - 260, 400);
    for (int x = 0; x < bar; ++x)
    {
        const cv::Vec3b col = colors.at<cv::Vec3b>(255 * x / std::max(1, bar - 1));
        cv::line(legend, cv::Point(80 + x, 8), cv::Point(80 + x, 22),
                 cv::Scalar(col[0], col[1], col[2]));
    }
    cv::putText(legend, "depth 0", cv::Point(4, 20), cv::FONT_HERSHEY_SIMPLEX, 0.4,
                cv::Scalar::all(255));
    cv::putText(legend, cv::format("%d", D), cv::Point(86 + bar, 20), cv::FONT_HERSHEY_SIMPLEX,
                0.4, cv::Scalar::all(255));
    cv::putText(legend, "rejected at tree depth; white: reached validation",
                cv::Point(120 + bar, 20), cv::FONT_HERSHEY_SIMPLEX, 0.4, cv::Scalar::all(255));
    cv::Mat top, out;
    cv::hconcat(frame, blend, top);
    cv::vconcat(top, legend, out);
    return out;
}

static std::string heatFile(const std::string& dir, const char* model, const EvalFrame& f)
{
    return cv::format("%s/heatmap_%s_%06d_%06d.png", dir.c_str(), model, f.scene_id, f.im_id);
}

// ---------------------------------------------------------------------------------------------
// running the detectors

struct RunContext
{
    std::vector<EvalFrame>* frames;
    float threshold;
    bool use_depth;
    bool rgb_refine;
    bool rgb_grid;
    Progress* progress;
};

static std::vector<cv::Mat> sourcesOf(const std::vector<cv::Ptr<cv::linemod::Modality> >& mods,
                                      const EvalFrame& f)
{
    std::vector<cv::Mat> s;
    for (size_t m = 0; m < mods.size(); ++m)
        s.push_back(mods[m]->name() == "DepthNormal" ? f.depth : f.rgb);
    return s;
}

static bool frameFor(const EvalFrame& f, int object_index)
{
    return f.owner < 0 || object_index < 0 || f.owner == object_index;
}

/** Runs a forestmod detector (trained as it is) on the frames; scores every object in objs.
object_index >= 0: only the frames of that object (--synthetic). heat: rejection maps of the
first frames, when not null. */
static void runForestmod(const fm::Detector& det, const std::vector<ObjectInfo*>& objs,
                         int object_index, const RunContext& ctx, const std::string& label,
                         std::vector<Result>& res, std::vector<std::pair<int, cv::Mat> >* heat,
                         int heat_frames)
{
    const std::vector<cv::Ptr<cv::linemod::Modality> > mods = det.getModalities();
    int k = 0;
    for (size_t i = 0; i < ctx.frames->size(); ++i)
    {
        const EvalFrame& f = (*ctx.frames)[i];
        if (!frameFor(f, object_index))
            continue;
        const std::vector<cv::Mat> sources = sourcesOf(mods, f);
        fm::DetectionStats stats;
        std::vector<cv::linemod::Match> matches;
        cv::TickMeter tm;
        tm.start();
        det.match(sources, ctx.threshold, matches, std::vector<cv::String>(), cv::noArray(),
                  std::vector<cv::Mat>(), &stats);
        tm.stop();
        if (heat && k < heat_frames)
            heat->push_back(std::make_pair((int)i, stats.rejection_map.clone()));
        for (size_t o = 0; o < objs.size(); ++o)
        {
            Result& r = res[o];
            r.has_forest = true;
            r.with_depth = ctx.use_depth;
            r.total.push_back(tm.getTimeMilli());
            r.tree.push_back(stats.t_tree_ms);
            r.valid.push_back(stats.t_valid_ms);
            r.quant.push_back(stats.t_quantize_ms);
            r.locations += stats.locations;
            r.rejected += stats.rejected;
            scoreFrame(matches, det, f, *objs[o], ctx.use_depth, ctx.rgb_refine, ctx.rgb_grid,
                       r);
        }
        ++k;
        ctx.progress->step(cv::format("%s, frame %d", label.c_str(), k));
    }
}

static void runLinemod(const cv::linemod::Detector& lm, const fm::Detector& posedet,
                       const std::vector<ObjectInfo*>& objs, int object_index,
                       const RunContext& ctx, const std::string& label, std::vector<Result>& res)
{
    const std::vector<cv::Ptr<cv::linemod::Modality> > mods = lm.getModalities();
    int k = 0;
    for (size_t i = 0; i < ctx.frames->size(); ++i)
    {
        const EvalFrame& f = (*ctx.frames)[i];
        if (!frameFor(f, object_index))
            continue;
        const std::vector<cv::Mat> sources = sourcesOf(mods, f);
        std::vector<cv::linemod::Match> matches;
        cv::TickMeter tm;
        tm.start();
        lm.match(sources, ctx.threshold, matches);
        tm.stop();
        for (size_t o = 0; o < objs.size(); ++o)
        {
            Result& r = res[o];
            r.with_depth = ctx.use_depth;
            r.total.push_back(tm.getTimeMilli());
            scoreFrame(matches, posedet, f, *objs[o], ctx.use_depth, ctx.rgb_refine,
                       ctx.rgb_grid, r);
        }
        ++k;
        ctx.progress->step(cv::format("%s, frame %d", label.c_str(), k));
    }
}

struct TrainThreads
{
    int match, train;
};

/** Trains the forest with train threads, then goes back to the threads of the timed matching. */
static void train(fm::Detector& det, const TrainThreads& tt)
{
    cv::setNumThreads(tt.train);
    det.train();
    cv::setNumThreads(tt.match);
}

/** Results of several objects scored in one run (the multi-object model) pooled into one. */
static Result pooled(const std::vector<Result>& rs)
{
    Result p;
    if (rs.empty())
        return p;
    p = rs[0]; // times, locations: the same calls for every object
    p.n2d = p.ok2d = p.okproj = p.nadd = p.okadd = 0;
    for (size_t i = 0; i < rs.size(); ++i)
    {
        p.n2d += rs[i].n2d;
        p.ok2d += rs[i].ok2d;
        p.okproj += rs[i].okproj;
        p.nadd += rs[i].nadd;
        p.okadd += rs[i].okadd;
    }
    return p;
}

// ---------------------------------------------------------------------------------------------
// output

static std::string num(double v, const char* fmt = "%.2f")
{
    return cvIsNaN(v) || cvIsInf(v) ? std::string("-") : cv::format(fmt, v);
}

static std::string pct(double v)
{
    return cvIsNaN(v) ? std::string("-") : cv::format("%.1f %%", 100 * v);
}

static std::string jnum(double v)
{
    return cvIsNaN(v) || cvIsInf(v) ? std::string("null") : cv::format("%.6g", v);
}

static double tTotal(const Result& r) { return median(r.total); }
static double tTree(const Result& r)
{
    return r.has_forest ? median(r.tree) : std::numeric_limits<double>::quiet_NaN();
}
static double tValid(const Result& r)
{
    return r.has_forest ? median(r.valid) : std::numeric_limits<double>::quiet_NaN();
}
static double rejectedFraction(const Result& r)
{
    return r.has_forest && r.locations > 0 ? double(r.rejected) / r.locations
                                           : std::numeric_limits<double>::quiet_NaN();
}
static double addRate(const Result& r)
{
    return r.with_depth ? ratio(r.okadd, r.nadd) : std::numeric_limits<double>::quiet_NaN();
}

static std::string mdRow(const std::string& name, const std::string& det, int templates,
                         const Result& r)
{
    return cv::format("| %s | %s | %d | %s | %s | %s | %s | %s | %s | %s | %s |\n", name.c_str(),
                      det.c_str(), templates, num(tTree(r)).c_str(), num(tValid(r)).c_str(),
                      num(median(r.quant)).c_str(), num(tTotal(r)).c_str(),
                      pct(ratio(r.ok2d, r.n2d)).c_str(), pct(ratio(r.okproj, r.n2d)).c_str(),
                      pct(addRate(r)).c_str(), pct(rejectedFraction(r)).c_str());
}

/** The mean row of Table 1: times are the mean of the per-object medians, accuracy is pooled
over every (frame, object) pair, the rejected share over every location. */
static std::string meanRow(const std::string& det, const std::vector<Result>& rs)
{
    double tree = 0, valid = 0, quant = 0, total = 0;
    int64 locations = 0, rejected = 0;
    for (size_t o = 0; o < rs.size(); ++o)
    {
        tree += tTree(rs[o]);
        valid += tValid(rs[o]);
        quant += median(rs[o].quant);
        total += tTotal(rs[o]);
        locations += rs[o].locations;
        rejected += rs[o].rejected;
    }
    const double n = (double)rs.size();
    const Result p = pooled(rs);
    const double rej = p.has_forest && locations > 0 ? double(rejected) / locations
                                                     : std::numeric_limits<double>::quiet_NaN();
    return cv::format("| **mean** | %s | - | %s | %s | %s | %s | %s | %s | %s | %s |\n",
                      det.c_str(), num(tree / n).c_str(), num(valid / n).c_str(),
                      num(quant / n).c_str(), num(total / n).c_str(),
                      pct(ratio(p.ok2d, p.n2d)).c_str(), pct(ratio(p.okproj, p.n2d)).c_str(),
                      pct(addRate(p)).c_str(), pct(rej).c_str());
}

// the frames one by one: time, the scored hypothesis, its box IoU, projection error and ADD/ADI
// (in diameters), null where not measured; "top": the class's best matches as the detector
// returned them, [template_id, x, y, similarity]
static std::string jsonFrames(const Result& r)
{
    std::string s = "[";
    for (size_t i = 0; i < r.per_frame.size(); ++i)
    {
        const FrameRecord& f = r.per_frame[i];
        s += cv::format("%s\n       {\"scene_id\": %d, \"im_id\": %d, \"t_ms\": %s, "
                        "\"template_id\": %d, \"similarity\": %s, \"x\": %d, \"y\": %d, "
                        "\"iou\": %s, \"proj2d_px\": %s, \"add_d\": %s}",
                        i ? "," : "", f.scene_id, f.im_id, jnum(f.t_ms).c_str(), f.template_id,
                        jnum(f.similarity).c_str(), f.pos.x, f.pos.y, jnum(f.iou).c_str(),
                        jnum(f.proj).c_str(), jnum(f.add).c_str());
        s.resize(s.size() - 1);
        s += ", \"top\": [";
        for (size_t k = 0; k < f.top.size(); ++k)
            s += cv::format("%s[%d, %d, %d, %s]", k ? ", " : "", f.top[k].template_id,
                            f.top[k].x, f.top[k].y, jnum(f.top[k].similarity).c_str());
        s += "]}";
    }
    return s + "]";
}

static std::string jsonResult(const Result& r)
{
    return cv::format("{\"t_total_ms\": %s, \"t_tree_ms\": %s, \"t_valid_ms\": %s, "
                      "\"recall_2d\": %s, \"proj2d_5px\": %s, \"add_01d\": %s, "
                      "\"rejected_fraction\": %s,\n       \"per_frame\": %s}",
                      jnum(tTotal(r)).c_str(), jnum(tTree(r)).c_str(), jnum(tValid(r)).c_str(),
                      jnum(ratio(r.ok2d, r.n2d)).c_str(), jnum(ratio(r.okproj, r.n2d)).c_str(),
                      jnum(addRate(r)).c_str(), jnum(rejectedFraction(r)).c_str(),
                      jsonFrames(r).c_str());
}



static std::string jsonString(const std::string& s)
{
    std::string out = "\"";
    for (size_t i = 0; i < s.size(); ++i)
    {
        if (s[i] == '"' || s[i] == '\\')
            out += '\\';
        out += s[i];
    }
    return out + "\"";
}

// ---------------------------------------------------------------------------------------------

int main(int argc, char** argv)
{
    cv::CommandLineParser parser(argc, argv, keys);
    parser.about("forestmod_eval: forestmod::Detector (1 and 5 trees) vs cv::linemod::Detector on "
                 "a BOP dataset or rendered RGB-D scenes (the paper's Tables 1 and 2)");
    if (parser.has("help"))
    {
        parser.printMessage();
        return 0;
    }
    const std::string root = parser.get<std::string>("dataset");
    const std::string split = parser.get<std::string>("split");
    const int scene = parser.get<int>("scene");
    const std::string objects_arg = parser.get<std::string>("objects");
    const int max_frames = parser.get<int>("frames");
    const int synthetic = parser.get<int>("synthetic");
    const float threshold = parser.get<float>("threshold");
    const std::string radii_arg = parser.get<std::string>("radii");
    const std::string inplane_arg = parser.get<std::string>("inplane");
    std::string cache_dir = parser.get<std::string>("cache");
    const std::string json_path = parser.get<std::string>("json");
    const std::vector<std::string> modalities_arg
        = splitList(parser.get<std::string>("modalities"));
    const std::string heat_dir = parser.get<std::string>("heatmap");
    const int heat_frames = parser.get<int>("heatmap_frames");
    const int threads = parser.get<int>("threads");
    const int train_threads = parser.get<int>("train_threads");
    const int seed = parser.get<int>("seed");
    g_depth_samples = parser.get<int>("depth_samples");
    g_depth_tolerance = parser.get<int>("depth_tolerance");
    g_depth_validation = parser.get<int>("depth_validation") != 0;
    g_max_survivors = parser.get<int>("max_survivors");
    g_any_tree = parser.get<int>("any_tree");
    g_leaf_samples = parser.get<float>("leaf_samples");
    const bool force = parser.has("force");
    const bool multi = !parser.has("no_multi");
    fm::ViewSampler::Params sp;
    sp.level = parser.get<int>("level");
    sp.min_elevation = parser.get<double>("min_elevation");
    sp.max_elevation = parser.get<double>("max_elevation");
    if (!parser.check())
    {
        parser.printErrors();
        return 1;
    }
    std::vector<double> inplane;
    if (!parseNumbers(radii_arg, sp.radii) || sp.radii.empty()
        || !parseNumbers(inplane_arg, inplane) || inplane.size() != 3)
    {
        std::cerr << "forestmod_eval: --radii is a list of distances (mm), --inplane min,max,step "
                     "(degrees)\n";
        return 1;
    }
    sp.inplane_min = inplane[0];
    sp.inplane_max = inplane[1];
    sp.inplane_step = inplane[2];
    if (root.empty())
    {
        std::cerr << "forestmod_eval: --dataset is required (see --help)\n";
        return 1;
    }
    if (!cv::utils::fs::exists(root + "/camera.json"))
    {
        std::cerr << "forestmod_eval: no BOP dataset at " << root << " (camera.json not found)\n";
        return 1;
    }
    if (max_frames < 0 || synthetic < 0 || threads < 1 || train_threads < 1 || heat_frames < 0
        || threshold <= 0 || threshold > 100)
    {
        std::cerr << "forestmod_eval: --frames, --synthetic, --heatmap_frames must be >= 0, "
                     "--threads and --train_threads >= 1, --threshold in (0, 100]\n";
        return 1;
    }
    if (!json_path.empty() && forestmod_samples::refuseOutput("forestmod_eval", json_path, force))
        return 1;
    cv::setNumThreads(threads);

    try
    {
        fm::ViewSampler sampler(sp);
        sampler.validate();
        fm::BopDataset ds = fm::BopDataset::open(root, split);
        TemplateSetup setup;
        setup.sampler = sampler;
        setup.K = ds.cameraK();
        setup.size = ds.imageSize();

        // objects
        std::vector<ObjectInfo> objects;
        std::vector<int> ids;
        if (!objects_arg.empty())
        {
            std::vector<double> v;
            if (!parseNumbers(objects_arg, v) || v.empty())
            {
                std::cerr << "forestmod_eval: --objects is a comma-separated list of ids\n";
                return 1;
            }
            for (size_t i = 0; i < v.size(); ++i)
                ids.push_back(cvRound(v[i]));
        }
        else
        {
            const std::vector<fm::ModelInfo> models = ds.models();
            for (size_t i = 0; i < models.size(); ++i)
                if (cv::utils::fs::exists(models[i].mesh_path))
                    ids.push_back(models[i].obj_id);
        }
        if (ids.empty())
        {
            std::cerr << "forestmod_eval: no object with a mesh in " << root << "/models\n";
            return 1;
        }
        for (size_t i = 0; i < ids.size(); ++i)
        {
            const fm::ModelInfo mi = ds.model(ids[i]);
            if (!cv::utils::fs::exists(mi.mesh_path))
            {
                std::cerr << "forestmod_eval: object " << ids[i] << " has no mesh ("
                          << mi.mesh_path << ")\n";
                return 1;
            }
            ObjectInfo o;
            o.obj_id = mi.obj_id;
            o.name = lmoName(mi.obj_id);
            o.class_id = o.name;
            o.mesh_path = mi.mesh_path;
            o.mesh = fm::Mesh::load(mi.mesh_path);
            o.diameter = mi.diameter > 0 ? mi.diameter : o.mesh.diameter();
            o.symmetric = mi.symmetric;
            o.symmetries = mi.symmetries_discrete;
            const size_t step = std::max<size_t>(1, o.mesh.vertices.size() / 2000);
            for (size_t k = 0; k < o.mesh.vertices.size(); k += step)
                o.pts.push_back(o.mesh.vertices[k]);
            o.templates = 0;
            objects.push_back(o);
        }

        // frames
        std::vector<EvalFrame> frames;
        const std::vector<fm::Frame> dframes = ds.frames(scene);
        if (dframes.empty())
        {
            std::cerr << "forestmod_eval: scene " << scene << " of " << root << "/" << split
                      << " has no frames\n";
            return 1;
        }
        const size_t nuse = max_frames > 0 ? std::min<size_t>(max_frames, dframes.size())
                                           : dframes.size();
        bool all_depth = true;
        for (size_t i = 0; i < nuse; ++i)
            all_depth = all_depth && !dframes[i].depth_path.empty();
        const bool use_depth = synthetic > 0 || (all_depth && !parser.has("rgb_only"));
        if (modalities_arg.empty())
        {
            setup.modalities.push_back("ColorGradient");
            if (use_depth)
                setup.modalities.push_back("DepthNormal");
            setup.modalities.push_back("ColorHue");
        }
        for (size_t i = 0; i < modalities_arg.size(); ++i)
        {
            const std::string& m = modalities_arg[i];
            if (m != "ColorGradient" && m != "DepthNormal" && m != "ColorHue")
            {
                std::cerr << "forestmod_eval: unknown modality '" << m << "' (ColorGradient, "
                             "DepthNormal, ColorHue)\n";
                return 1;
            }
            if (m == "DepthNormal" && !use_depth)
            {
                std::cerr << "forestmod_eval: DepthNormal needs depth (the frames have none, or "
                             "--rgb_only)\n";
                return 1;
            }
            setup.modalities.push_back(m);
        }

        if (cache_dir.empty())
            cache_dir = executableDir(argc > 0 ? argv[0] : 0) + "/../forestmod_cache";
        cv::utils::fs::createDirectories(cache_dir);
        if (!cv::utils::fs::isDirectory(cache_dir))
        {
            std::cerr << "forestmod_eval: cannot create the cache folder " << cache_dir << "\n";
            return 1;
        }

        // templates of every object: from the cache, or rendered (and cached)
        Progress progress;
        std::vector<cv::Ptr<fm::Detector> > dets(objects.size());
        std::vector<double> render(objects.size());
        for (size_t o = 0; o < objects.size(); ++o)
            dets[o] = objectTemplates(objects[o], setup, cache_dir, progress, render[o]);

        if (synthetic == 0)
            for (size_t i = 0; i < nuse; ++i)
            {
                EvalFrame f;
                f.scene_id = dframes[i].scene_id;
                f.im_id = dframes[i].im_id;
                f.rgb = dframes[i].rgb();
                if (use_depth)
                    f.depth = dframes[i].depth();
                f.K = dframes[i].K;
                f.gt = dframes[i].gt;
                f.owner = -1;
                frames.push_back(f);
            }
        else
        {
            // rendered scenes: the object at a random template pose (perturbed, moved in the
            // image), the other meshes as clutter, the dataset's frames as colour background
            cv::Ptr<fm::Renderer> renderer = fm::Renderer::create(setup.size);
            fm::SceneSynthesizer synth(renderer, setup.K);
            for (size_t o = 0; o < objects.size(); ++o)
                synth.addObject(objects[o].mesh);
            // the dataset's other meshes are clutter too
            const std::vector<fm::ModelInfo> models = ds.models();
            for (size_t i = 0; i < models.size(); ++i)
                if (std::find(ids.begin(), ids.end(), models[i].obj_id) == ids.end()
                    && cv::utils::fs::exists(models[i].mesh_path))
                    synth.addObject(fm::Mesh::load(models[i].mesh_path));
            std::vector<cv::Mat> backgrounds;
            for (size_t i = 0; i < nuse; ++i)
                backgrounds.push_back(dframes[i].rgb());
            synth.setBackgrounds(backgrounds);
            cv::RNG rng((uint64)seed);
            for (size_t o = 0; o < objects.size(); ++o)
            {
                if (!dets[o])
                    continue; // no template: left out
                // the poses of the object's templates (not every sampler pose gives one)
                std::vector<fm::TemplatePose> poses;
                for (int i = 0; i < dets[o]->numTemplates(objects[o].class_id); ++i)
                    poses.push_back(dets[o]->getTemplatePose(objects[o].class_id, i));
                for (int n = 0; n < synthetic; ++n)
                {
                    progress.show(cv::format("%s: rendering scene %d/%d", objects[o].name.c_str(),
                                             n + 1, synthetic));
                    const fm::TemplatePose& vp = poses[rng.uniform(0, (int)poses.size())];
                    const fm::SyntheticScene s = synth.render((int)o, vp.R, vp.t, rng);
                    EvalFrame f;
                    f.scene_id = 0;
                    f.im_id = (int)(o * synthetic + n);
                    f.rgb = s.color;
                    f.depth = s.depth;
                    f.K = setup.K;
                    fm::GroundTruth g;
                    g.obj_id = objects[o].obj_id;
                    g.R = s.R;
                    g.t = s.t;
                    g.bbox_obj = cv::Rect(); // projected at scoring time
                    g.visib_fract = s.visible;
                    f.gt.push_back(g);
                    f.owner = (int)o;
                    frames.push_back(f);
                }
            }
        }

        // outputs that must not be overwritten
        // heat maps: the first object's model (1 tree) on its first frames, and the model of all
        // objects (5 trees); the files are named after the frame
        std::vector<std::string> heat_files;
        if (!heat_dir.empty())
        {
            for (size_t i = 0; i < frames.size(); ++i)
            {
                bool first = false;
                int rank = 0; // position among the frames of the object the scene was made for
                for (size_t j = 0; j < i; ++j)
                    rank += frames[j].owner == frames[i].owner;
                first = rank < heat_frames;
                if (first && frames[i].owner <= 0) // the first object's frames (all when real)
                    heat_files.push_back(heatFile(heat_dir, "single", frames[i]));
                if (i < (size_t)heat_frames && multi)
                    heat_files.push_back(heatFile(heat_dir, "all", frames[i]));
            }
            for (size_t i = 0; i < heat_files.size(); ++i)
                if (forestmod_samples::refuseOutput("forestmod_eval", heat_files[i], force))
                    return 1;
            cv::utils::fs::createDirectories(heat_dir);
        }

        const std::string mode = use_depth ? "RGB-D" : "RGB only";
        std::string modnames;
        for (size_t i = 0; i < setup.modalities.size(); ++i)
            modnames += (i ? " + " : "") + setup.modalities[i];
        printf("# forestmod_eval\n\n");
        if (synthetic > 0)
            printf("- data: %d rendered RGB-D scenes per object (SceneSynthesizer: clutter from "
                   "the other meshes, backgrounds from %d frames of %s scene %d)\n",
                   synthetic, (int)nuse, root.c_str(), scene);
        else
            printf("- data: %s, split %s, scene %d, %d frames\n", root.c_str(), split.c_str(),
                   scene, (int)frames.size());
        printf("- mode: %s; modalities %s; pyramid T = {5, 8}; threshold %.0f; %d OpenCV "
               "thread(s) while matching (cv::setNumThreads; %d while training the forests)\n",
               mode.c_str(), modnames.c_str(), threshold, threads, train_threads);
        printf("- templates (the same for every detector): level %d, elevation %.0f..%.0f deg, "
               "%d views x radii {%s} mm x in-plane %.0f..%.0f step %.0f deg = %d poses per "
               "object\n",
               sp.level, sp.min_elevation, sp.max_elevation, (int)sampler.viewpoints().size(),
               radii_arg.c_str(), sp.inplane_min, sp.inplane_max, sp.inplane_step, sampler.size());
        printf("- times: median ms per frame of the whole match() call (T_total includes the "
               "modalities' quantization, T_quant); T_tree, T_valid and rejected are forestmod's "
               "DetectionStats\n");
        printf("- accuracy of the best match per object: 2D = box of the projected model at the "
               "match's pose (%s), IoU >= 0.5 with bbox_obj; proj = 2D projection error < 5 px; "
               "ADD = ADD (ADI for symmetric objects) < 0.1 d after ICP (RGB-D only)\n\n",
               use_depth ? "after ICP" : parser.get<bool>("rgb_refine")
                   ? "refined by edge alignment" : "the template's pose");
        fflush(stdout);

        const TrainThreads tt = { threads, train_threads };
        int frames_per_object = synthetic > 0 ? synthetic : (int)frames.size();
        progress.total = (int64)objects.size() * frames_per_object * 3
            + (multi ? (int64)frames.size() * 2 : 0);

        RunContext ctx;
        ctx.frames = &frames;
        ctx.threshold = threshold;
        ctx.use_depth = use_depth;
        ctx.rgb_refine = parser.get<bool>("rgb_refine");
        ctx.rgb_grid = parser.get<bool>("rgb_grid");
        ctx.progress = &progress;

        // ---- Table 1: one object per model
        std::vector<Result> r1(objects.size()), r5(objects.size()), rl(objects.size());
        std::vector<double> train1(objects.size()), train5(objects.size());
        std::vector<std::pair<int, cv::Mat> > heat_single, heat_all;
        std::vector<std::string> skipped;
        for (size_t o = 0; o < objects.size(); ++o)
        {
            ObjectInfo& obj = objects[o];
            cv::Ptr<fm::Detector> det = dets[o];
            dets[o].release();
            if (!det)
            {
                skipped.push_back(obj.name);
                progress.done += 3 * frames_per_object;
                continue;
            }
            std::vector<ObjectInfo*> one(1, &obj);
            const int oi = synthetic > 0 ? (int)o : -1;
            fm::DetectorParams p = det->getParams();
            p.nms_iou = 0; // matches as cv::linemod returns them: the pose choice sees them all
            for (int trees = 1; trees <= 5; trees += 4)
            {
                p.forest.num_trees = trees;
                det->setParams(p);
                progress.show(cv::format("%s: training %d tree(s)", obj.name.c_str(), trees));
                cv::TickMeter tm;
                tm.start();
                train(*det, tt);
                tm.stop();
                (trees == 1 ? train1 : train5)[o] = tm.getTimeSec();
                std::vector<Result> rr(1);
                const bool want_heat = !heat_dir.empty() && o == 0 && trees == 1;
                runForestmod(*det, one, oi, ctx,
                             cv::format("%s: forestmod %d tree(s)", obj.name.c_str(), trees), rr,
                             want_heat ? &heat_single : 0, heat_frames);
                (trees == 1 ? r1 : r5)[o] = rr[0];
            }
            cv::Ptr<cv::linemod::Detector> lm = linemodCopy(*det);
            std::vector<Result> rr(1);
            runLinemod(*lm, *det, one, oi, ctx, obj.name + ": cv::linemod", rr);
            rl[o] = rr[0];
        }

        // objects without templates are left out from here on
        {
            size_t k = 0;
            for (size_t o = 0; o < objects.size(); ++o)
                if (objects[o].templates > 0)
                {
                    objects[k] = objects[o];
                    r1[k] = r1[o];
                    r5[k] = r5[o];
                    rl[k] = rl[o];
                    train1[k] = train1[o];
                    train5[k] = train5[o];
                    render[k] = render[o];
                    ++k;
                }
            objects.resize(k);
            if (objects.empty())
            {
                progress.finish();
                std::cerr << "forestmod_eval: no object has a template with these modalities\n";
                return 1;
            }
        }

        // ---- Table 2: every object in one model (forestmod 5 trees vs cv::linemod)
        Result m5, ml;
        int multi_templates = 0;
        double multi_train = 0;
        std::vector<Result> m5o(objects.size()), mlo(objects.size());
        if (multi)
        {
            progress.show("all objects: loading templates");
            cv::Ptr<fm::Detector> det = makeDetector(setup.modalities);
            for (size_t o = 0; o < objects.size(); ++o)
            {
                cv::FileStorage fs(objects[o].cache_file, cv::FileStorage::READ);
                if (!fs.isOpened())
                    CV_Error_(cv::Error::StsError,
                              ("cannot read %s", objects[o].cache_file.c_str()));
                cv::FileNode classes = fs["classes"];
                for (cv::FileNodeIterator it = classes.begin(); it != classes.end(); ++it)
                    det->readClass(*it);
                det->setMesh(objects[o].class_id, objects[o].mesh);
            }
            multi_templates = det->numTemplates();
            fm::DetectorParams p = det->getParams();
            p.nms_iou = 0; // as for one object
            p.forest.num_trees = 5;
            det->setParams(p);
            progress.show("all objects: training 5 trees");
            cv::TickMeter tm;
            tm.start();
            train(*det, tt);
            tm.stop();
            multi_train = tm.getTimeSec();
            std::vector<ObjectInfo*> all;
            for (size_t o = 0; o < objects.size(); ++o)
                all.push_back(&objects[o]);
            runForestmod(*det, all, -1, ctx, "all objects: forestmod 5 trees", m5o,
                         heat_dir.empty() ? 0 : &heat_all, heat_frames);
            cv::Ptr<cv::linemod::Detector> lm = linemodCopy(*det);
            runLinemod(*lm, *det, all, -1, ctx, "all objects: cv::linemod", mlo);
            m5 = pooled(m5o);
            ml = pooled(mlo);
        }
        progress.finish();

        // heat maps
        for (int kind = 0; kind < 2; ++kind)
        {
            const std::vector<std::pair<int, cv::Mat> >& heat = kind ? heat_all : heat_single;
            for (size_t i = 0; i < heat.size(); ++i)
            {
                const EvalFrame& f = frames[heat[i].first];
                double mx = 0;
                cv::minMaxLoc(heat[i].second, 0, &mx);
                const std::string file = heatFile(heat_dir, kind ? "all" : "single", f);
                if (!cv::imwrite(file, heatmapImage(f.rgb, heat[i].second, std::max(1, (int)mx))))
                    CV_Error_(cv::Error::StsError, ("cannot write %s", file.c_str()));
            }
        }

        // ---- tables
        printf("## Table 1: one object per model\n\n");
        for (size_t i = 0; i < skipped.size(); ++i)
            printf("- %s: left out, no view gave a template (every modality needs features: "
                   "ColorHue finds none on an unsaturated object)\n%s", skipped[i].c_str(),
                   i + 1 == skipped.size() ? "\n" : "");
        printf("| object | detector | templates | T_tree | T_valid | T_quant | T_total | 2D IoU "
               ">= 0.5 | proj < 5 px | ADD/ADI < 0.1 d | rejected |\n");
        printf("|---|---|---|---|---|---|---|---|---|---|---|\n");
        double s1 = 0, s5 = 0, sl = 0; // sums of the per-object median T_total
        for (size_t o = 0; o < objects.size(); ++o)
        {
            const ObjectInfo& obj = objects[o];
            printf("%s", mdRow(obj.name, "forestmod, 1 tree", obj.templates, r1[o]).c_str());
            printf("%s", mdRow(obj.name, "forestmod, 5 trees", obj.templates, r5[o]).c_str());
            printf("%s", mdRow(obj.name, "cv::linemod", obj.templates, rl[o]).c_str());
            s1 += tTotal(r1[o]);
            s5 += tTotal(r5[o]);
            sl += tTotal(rl[o]);
        }
        const double n = (double)objects.size();
        printf("%s", meanRow("forestmod, 1 tree", r1).c_str());
        printf("%s", meanRow("forestmod, 5 trees", r5).c_str());
        printf("%s", meanRow("cv::linemod", rl).c_str());
        printf("\nTemplate rendering (cold cache, s) / forest training 1 tree / 5 trees (s):");
        for (size_t o = 0; o < objects.size(); ++o)
            printf(" %s %.1f/%.1f/%.1f%s", objects[o].name.c_str(), render[o], train1[o],
                   train5[o], o + 1 < objects.size() ? "," : "\n");
        const double speedup_single = sl / s5;
        double growth_fm = std::numeric_limits<double>::quiet_NaN(), growth_lm = growth_fm,
               speedup_multi = growth_fm;
        if (multi)
        {
            printf("\n## Table 2: all %d objects in one model (%d templates, forest training "
                   "%.1f s)\n\n", (int)objects.size(), multi_templates, multi_train);
            printf("| object | detector | templates | T_tree | T_valid | T_quant | T_total | "
                   "2D IoU >= 0.5 | proj < 5 px | ADD/ADI < 0.1 d | rejected |\n");
            printf("|---|---|---|---|---|---|---|---|---|---|---|\n");
            printf("%s", mdRow("**all**", "forestmod, 5 trees", multi_templates, m5).c_str());
            printf("%s", mdRow("**all**", "cv::linemod", multi_templates, ml).c_str());
            for (size_t o = 0; o < objects.size(); ++o)
            {
                printf("%s", mdRow(objects[o].name, "forestmod, 5 trees", multi_templates,
                                   m5o[o]).c_str());
                printf("%s", mdRow(objects[o].name, "cv::linemod", multi_templates,
                                   mlo[o]).c_str());
            }
            speedup_multi = tTotal(ml) / tTotal(m5);
            growth_fm = tTotal(m5) / (s5 / n);
            growth_lm = tTotal(ml) / (sl / n);
        }
        printf("\n## Summary\n\n");
        printf("- speed-up, one object per model: cv::linemod / forestmod (5 trees) = %s "
               "(1 tree: %s), mean of the per-object median T_total\n",
               num(speedup_single).c_str(), num(sl / s1).c_str());
        if (multi)
        {
            printf("- speed-up, all objects in one model: cv::linemod / forestmod (5 trees) = %s\n",
                   num(speedup_multi).c_str());
            printf("- time growth, all objects in one model / mean single-object model: forestmod "
                   "(5 trees) %s, cv::linemod %s (%d objects)\n",
                   num(growth_fm).c_str(), num(growth_lm).c_str(), (int)objects.size());
        }
        fflush(stdout);

        // ---- JSON
        if (!json_path.empty())
        {
            std::ostringstream js;
            js << "{\n  \"frames\": " << (synthetic > 0 ? frames_per_object : (int)frames.size())
               << ",\n  \"objects\": [";
            for (size_t o = 0; o < objects.size(); ++o)
                js << (o ? "," : "") << "\n    {\"obj_id\": " << objects[o].obj_id
                   << ", \"name\": " << jsonString(objects[o].name)
                   << ",\n     \"forestmod\": " << jsonResult(r1[o])
                   << ",\n     \"forestmod_5\": " << jsonResult(r5[o])
                   << ",\n     \"linemod\": " << jsonResult(rl[o]) << "}";
            js << "\n  ],\n  \"multi\": ";
            if (multi)
                js << "{\"objects\": " << objects.size() << ",\n    \"forestmod\": "
                   << jsonResult(m5) << ",\n    \"linemod\": " << jsonResult(ml) << "}";
            else
                js << "null";
            js << ",\n  \"summary\": {\"speedup_single\": " << jnum(speedup_single)
               << ", \"speedup_multi\": " << jnum(speedup_multi)
               << ", \"growth_multi_over_single\": " << jnum(growth_fm) << "}\n}\n";
            std::ofstream out(json_path.c_str());
            out << js.str();
            if (!out)
                CV_Error_(cv::Error::StsError, ("cannot write %s", json_path.c_str()));
            std::cerr << "wrote " << json_path << "\n";
        }
    }
    catch (const cv::Exception& e)
    {
        std::cerr << "\nforestmod_eval: " << e.what() << std::endl;
        return 1;
    }
    return 0;
}
