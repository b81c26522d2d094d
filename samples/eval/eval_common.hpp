// This file is part of OpenCV project.
// It is subject to the license terms in the LICENSE file found in the top-level directory
// of this distribution and at http://opencv.org/license.html

// forestmod_eval: the types and functions its files share (options, data, templates, runners,
// report). Everything lives in namespace fmeval; no mutable globals: the options travel in
// EvalOptions.

#ifndef FORESTMOD_EVAL_COMMON_HPP
#define FORESTMOD_EVAL_COMMON_HPP

#include <opencv2/core.hpp>
#include <opencv2/forestmod.hpp>
#include <opencv2/rgbd/linemod.hpp>

#include "../sample_utils.hpp"

#include <map>
#include <memory>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

namespace fmeval {

namespace fm = cv::forestmod;

// ---------------------------------------------------------------------------------------------
// options (eval_options.cpp)

/** Everything the command line sets. Filled once by parseOptions(), then read only. */
struct EvalOptions
{
    EvalOptions();

    std::string root, split;
    int scene;
    std::vector<int> object_ids;   //!< empty: every model with a mesh
    int max_frames;                //!< 0: all
    int first_frame;               //!< frames of the scene skipped
    int synthetic;
    bool rgb_only;
    std::vector<std::string> modalities_arg;
    float threshold;
    bool rgb_refine, rgb_grid;
    int rgb_hypotheses;            //!< PoseParams::rgb_hypotheses
    int rgb_keep;                  //!< PoseParams::rgb_keep

    std::string regime;            //!< "paper" or "quick"
    fm::ViewSampler::Params sampler;
    std::vector<std::string> sampler_overrides; //!< flags that replaced the regime's values

    bool tables, multi;
    std::string cache_dir, json_path, heat_dir, plots_dir;
    int heat_frames;
    int threads, train_threads, seed;
    int repeat;                    //!< match() calls per frame, the best one is kept
    bool force, dry_run;

    // scaling sweeps
    bool sweep_templates, sweep_objects;
    std::vector<int> sweep_counts;    //!< templates of one object
    std::vector<int> sweep_classes;   //!< classes in one model
    int sweep_object;                 //!< obj_id of the templates sweep (0: the first object)
    int sweep_per_class;              //!< templates per class in the objects sweep (0: all)
    int sweep_frames;                 //!< frames of the sweeps (0: the run's frames)

    // experiments (-1: the library's default)
    int depth_samples, depth_tolerance, max_survivors, any_tree;
    float exhaustive_ratio;      //!< DetectorParams::exhaustive_ratio when has_exhaustive_ratio
    bool has_exhaustive_ratio;
    float descent_cost;          //!< DetectorParams::descent_cost when >= 0
    int min_forest_templates;    //!< DetectorParams::min_forest_templates when >= 0
    bool search_per_class;       //!< DetectorParams::search_per_class
    float depth_range_tolerance; //!< DetectorParams::depth_range_tolerance when has_...
    bool has_depth_range_tolerance;
    float fuzzy_margin;          //!< ForestParams::fuzzy_margin when >= 0
    float leaf_samples;
    bool depth_validation;
    int hue_feature_saturation;  //!< ColorHue::Params::feature_saturation_threshold when >= 0
    float hue_feature_area;      //!< ColorHue::Params::min_feature_area when >= 0

    bool five_trees;                   //!< Table 1's forestmod 5 trees row

    // verification stage (the *_verified rows)
    int verify_k;                      //!< hypotheses per object (recall@verify_k)
    //! w_similarity, w_color, w_edges, w_depth; empty: VerificationParams' defaults
    std::vector<double> verify_weights;
    double second_round;      //!< VerificationParams::second_round_below (< 0: the default)
    double background_weight; //!< VerificationParams::background_weight (< 0: the default)

    /** --gt_similarity: each object also matched with a template made at its ground-truth pose
    (FrameRecord::gt_similarity, the "Similarity on the object" table) */
    bool gt_similarity;
};

/** Parses argv; returns 0 when the program should go on, -1 after printing the help (exit
code 0), otherwise the exit code after printing an error. */
int parseOptions(int argc, char** argv, EvalOptions& opt);

/** The sampler of a regime ("paper", "quick"); false for an unknown name. */
bool regimeSampler(const std::string& regime, fm::ViewSampler::Params& p);

/** One line: "level L, elevation a..b deg, V views x radii {..} mm x in-plane a..b step s deg =
N poses per object". */
std::string samplingText(const fm::ViewSampler::Params& p);

/** ColorHue's parameters with the experiment flags applied (--hue_feature_saturation,
--hue_feature_area). */
fm::ColorHue::Params hueParams(const EvalOptions& opt);
/** DetectorParams with the experiment flags applied. */
fm::DetectorParams experimentParams(const EvalOptions& opt,
                                    fm::DetectorParams p = fm::DetectorParams());

// ---------------------------------------------------------------------------------------------
// small helpers (eval_options.cpp)

using cv::forestmod::samples::splitList;
bool parseNumbers(const std::string& s, std::vector<double>& out);
std::string lmoName(int obj_id);
double median(std::vector<double> v);
double quantile(std::vector<double> v, double q);
uint64_t fnv1a(const void* data, size_t n, uint64_t h = 14695981039346656037ULL);
std::string executableDir(const char* argv0);

// ---------------------------------------------------------------------------------------------
// data

/** A test image with its ground truth (dataset frame or rendered scene). */
struct EvalFrame
{
    int scene_id, im_id;
    cv::Mat rgb, depth;
    cv::Matx33d K;
    std::vector<fm::GroundTruth> gt;
    int owner; //!< --synthetic: index of the object the scene was made for; -1: every object
};

struct ObjectInfo
{
    ObjectInfo() : obj_id(0), diameter(0), symmetric(false), templates(0) {}
    int obj_id;
    std::string name, class_id, mesh_path, cache_file;
    std::string variant; //!< empty: the mesh as loaded; otherwise how it was recoloured/rescaled
    fm::Mesh mesh;
    std::vector<cv::Point3f> pts; //!< model points for the metrics (subsampled vertices)
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
    double verification;   //!< PoseMatch::verification of the scored hypothesis (NaN: none)
    /** verified rows: every hypothesis in the verification's order, (similarity, color_score,
    edge_score, depth_score, occlusion, box IoU, projection error px, region_score): the features
    the verification weights are set on */
    std::vector<cv::Vec<double, 9> > hyps;
    std::vector<cv::linemod::Match> top; //!< the class's best matches (up to 5), as matched
    /** The best similarity of the class's matches whose template box lies on the object (box IoU
    >= 0.5 with the ground truth's), NaN without one */
    double correct_similarity;
    /** The best similarity of the class's other matches (box IoU < 0.5), NaN without one */
    double off_similarity;
    /** --gt_similarity: the best similarity on the object (box IoU >= 0.5) of a template made at
    the ground-truth pose, NaN when not measured */
    double gt_similarity;
};

/** Accumulated results of one detector on one object (or on the multi-object model). Times are
per frame, each the best of EvalOptions::repeat calls. */
struct Result
{
    Result();
    bool has_forest;
    std::vector<double> total, tree, valid, quant;
    int64 locations, rejected;
    int n2d, ok2d, okproj, nadd, okadd;
    int ok2d_at10, okproj_at10; //!< any of the first 10 hypotheses (RunContext::verify.top_k)
    std::vector<double> verify; //!< verified rows: t_verify_ms of every frame
    //! verified rows: t_verify_ms per 10 verified hypotheses, of every frame that verified any
    std::vector<double> verify_per10;
    //! verified rows: t_background_ms of every frame (Detector::backgroundSimilarity)
    std::vector<double> background;
    /** ms per frame of the hypotheses' poses (choosePoses of every location's matches: without
    depth refined by edge alignment, with depth ICP); verified rows: those of the hypotheses
    ordered by background (VerificationParams::background_weight), when they are made again */
    std::vector<double> pose;
    bool with_depth;
    std::vector<FrameRecord> per_frame;
};

double ratio(int a, int b);
double tTotal(const Result& r);
double tTree(const Result& r);
double tValid(const Result& r);
double tQuant(const Result& r);
double rejectedFraction(const Result& r);
double addRate(const Result& r);
/** Results of several objects scored in one run (the multi-object model) pooled into one. */
Result pooled(const std::vector<Result>& rs);

/** Progress bar on stderr. */
struct Progress
{
    Progress() : done(0), total(1) {}
    int64 done, total;
    void show(const std::string& what) const;
    void step(const std::string& what);
    void finish() const;
};

// ---------------------------------------------------------------------------------------------
// templates (eval_templates.cpp)

struct TemplateSetup
{
    std::vector<std::string> modalities; //!< names, in order
    fm::ViewSampler sampler;
    int subset;      //!< > 0: only this many of the sampler's poses, spread evenly (poseSubset)
    cv::Matx33d K;   //!< intrinsics of the dataset
    cv::Size size;   //!< image size of the dataset
};

cv::Ptr<fm::Detector> makeDetector(const EvalOptions& opt,
                                   const std::vector<std::string>& modalities);

/** Indices of n of total poses, spread evenly over the sampler's order (radius, direction,
in-plane), deterministic; all of them when n <= 0 or n >= total. */
std::vector<int> poseSubset(int total, int n);

/** The object's templates: from the cache, or rendered and cached. Returns an empty pointer
when no view gave a template. render_s: rendering time (0 when cached). */
cv::Ptr<fm::Detector> objectTemplates(const EvalOptions& opt, ObjectInfo& obj,
                                      const TemplateSetup& setup, Progress& progress,
                                      double& render_s);

/** For every ground truth of obj in frames, the rotation (degrees) from it to the nearest of the
detector's templates of obj's class, the ground truth turned as seen along its line of sight (a
template is drawn on the optical axis) and taken at the nearest of its discrete symmetries: how
well the templates cover the poses, whatever the matching. */
std::vector<double> templateCoverage(const fm::Detector& det, const ObjectInfo& obj,
                                     const std::vector<EvalFrame>& frames);

using cv::forestmod::samples::linemodCopy;
using cv::forestmod::samples::sourcesOf;

/** Loads the cached untrained templates of several objects into one detector. */
cv::Ptr<fm::Detector> multiObjectDetector(const EvalOptions& opt,
                                          const std::vector<std::string>& modalities,
                                          const std::vector<ObjectInfo*>& objects);

/** A copy of obj for the objects sweep: k-th variant, colours turned on the hue circle and
the mesh rescaled (k = 0: the object itself). */
ObjectInfo objectVariant(const ObjectInfo& obj, int k);

// ---------------------------------------------------------------------------------------------
// running the detectors (eval_run.cpp)

/** Templates made at the objects' ground-truth poses (rendered on the frame's camera) and their
best similarity on the object, kept per frame and object. */
class GroundTruthTemplates
{
public:
    /** The best similarity of the template made at gt's pose among its matches (threshold 50,
    every position scored) on f whose box lies on the object (IoU >= 0.5 with gt_box), with
    like's modalities and pyramid; NaN when no template can be made there. */
    double similarity(const fm::Detector& like, const ObjectInfo& obj, const EvalFrame& f,
                      const fm::GroundTruth& gt, const cv::Rect2d& gt_box);

private:
    cv::Ptr<fm::Renderer> renderer_;
    std::map<int, int> handles_;                      //!< obj_id -> mesh
    std::map<std::tuple<int, int, int>, double> measured_; //!< (scene, image, obj_id) -> similarity
};

struct RunContext
{
    const std::vector<EvalFrame>* frames;
    float threshold;
    bool use_depth;
    bool rgb_refine;
    bool rgb_grid;
    int rgb_hypotheses;
    int rgb_keep;
    int repeat;
    Progress* progress;
    fm::VerificationParams verify; //!< top_k: hypotheses per object scored (recall@top_k)
    /** --gt_similarity: the templates made at the ground-truth poses and their similarities (one
    per frame and object, shared by the rows); null when not asked */
    std::shared_ptr<GroundTruthTemplates> gt;
};

/** The run's context from the options (--threshold, --rgb_refine, --rgb_grid, --rgb_hypotheses,
--rgb_keep, --repeat, --verify_k, --verify_weights) for these frames and this progress line. */
RunContext runContext(const EvalOptions& opt, const std::vector<EvalFrame>& frames, bool use_depth,
                      Progress& progress);

/** Runs a forestmod detector (trained as it is) on the frames and scores every object of objs
(res: one entry per object; with no object, res[0] gets the times only). object_index >= 0:
only the frames of that object (--synthetic). heat: rejection maps of the first frames.
verified (optional, one entry per object): the same hypotheses after Detector::verify(). */
void runForestmod(const fm::Detector& det, const std::vector<ObjectInfo*>& objs,
                  int object_index, const RunContext& ctx, const std::string& label,
                  std::vector<Result>& res, std::vector<std::pair<int, cv::Mat> >* heat = 0,
                  int heat_frames = 0, std::vector<Result>* verified = 0);

/** The same for cv::linemod; quant: the modalities' process + pyrDown + quantize of every
level, timed separately on the same frame. posedet: forestmod detector with the same templates
(pose labels, meshes) for the scoring; may be null when objs is empty. verified: as for
runForestmod. */
void runLinemod(const cv::linemod::Detector& lm, const fm::Detector* posedet,
                const std::vector<ObjectInfo*>& objs, int object_index, const RunContext& ctx,
                const std::string& label, std::vector<Result>& res,
                std::vector<Result>* verified = 0);

/** Trains the forest with train_threads, then goes back to the matching threads; seconds. */
double trainDetector(fm::Detector& det, const EvalOptions& opt);

// ---------------------------------------------------------------------------------------------
// report (eval_report.cpp)

std::string num(double v, const char* fmt = "%.2f");
std::string pct(double v);
std::string mdRow(const std::string& name, const std::string& det, int templates,
                  const Result& r);
std::string meanRow(const std::string& det, const std::vector<Result>& rs);

/** Writes a number, or the string "n/a" when it is NaN (cv::FileStorage writes no JSON null). */
void writeNumber(cv::FileStorage& fs, const std::string& key, double v);
/** {t_total_ms, t_tree_ms, ..., per_frame} of one result. */
void writeResult(cv::FileStorage& fs, const std::string& key, const Result& r, bool per_frame);

cv::Mat heatmapImage(const cv::Mat& frame, const cv::Mat& map, int max_depth);
std::string heatFile(const std::string& dir, const char* model, const EvalFrame& f);

/** One curve of a plot. */
struct Series
{
    std::string label;
    cv::Scalar color;
    std::vector<double> x, y;
};

/** A log-log plot of the series (time in ms against x) and, when rejection is not empty, a
lower panel with those series as shares (0..1, drawn in percent). Axes labelled, legend.
x_ticks: where to label the x axis (empty: 1, 2, 5 x 10^k). */
cv::Mat plotCurves(const std::string& title, const std::string& xlabel,
                   const std::vector<Series>& times, const std::vector<Series>& rejection,
                   const std::vector<double>& x_ticks = std::vector<double>());

// ---------------------------------------------------------------------------------------------
// the two parts of a run

/** The paper's Tables 1 and 2 (eval_tables.cpp); writes into fs when it is open. */
int runTables(const EvalOptions& opt, std::vector<ObjectInfo>& objects,
              const std::vector<EvalFrame>& frames, const TemplateSetup& setup, bool use_depth,
              cv::FileStorage& fs);

/** The scaling sweeps (eval_sweep.cpp): JSON into fs (when open) and into
<plots_dir>/scaling.json, PNG plots into plots_dir. */
int runSweeps(const EvalOptions& opt, const std::vector<ObjectInfo>& objects,
              const std::vector<EvalFrame>& frames, const TemplateSetup& setup, bool use_depth,
              cv::FileStorage& fs);

/** Output files of the sweeps (for the overwrite check). */
std::vector<std::string> sweepOutputs(const EvalOptions& opt);

} // namespace fmeval

#endif
