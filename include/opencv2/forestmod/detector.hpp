// This file is part of OpenCV project.
// It is subject to the license terms in the LICENSE file found in the top-level directory
// of this distribution and at http://opencv.org/license.html

#ifndef OPENCV_FORESTMOD_DETECTOR_HPP
#define OPENCV_FORESTMOD_DETECTOR_HPP

#include "opencv2/core.hpp"
#include "opencv2/rgbd/linemod.hpp"
#include "opencv2/forestmod/forest.hpp"
#include "opencv2/forestmod/render.hpp"
#include "opencv2/forestmod/pose.hpp"

#include <functional>

namespace cv {
namespace forestmod {

//! @addtogroup forestmod_detector
//! @{

/** @brief Parameters of forestmod::Detector. FileStorage keys are the field names. */
struct CV_EXPORTS_W_SIMPLE DetectorParams
{
    CV_WRAP DetectorParams();

    /** The template forest of every search group (paper: 1 or 5 trees, depth 8 for one object,
    9 for several). When max_depth is 0 it is chosen at train() per search group (see
    auto_depth_leaf_samples).
    Differences from ForestParams() (measured with samples/forestmod_detector_bench.cpp on
    rendered LM-O scenes, doc/detector.md "Search"): rejector_coverage 0.5 and rejector_dims 64
    reject about a point more than 0.8 / 32 at the same hits. */
    CV_PROP_RW ForestParams forest;
    /** Use the forest to choose the candidate templates of a location. false: every template is a
    candidate everywhere (exhaustive LINEMOD search, for comparison and tests). */
    CV_PROP_RW bool use_forest;
    /** Breadth-first preemptive validation (paper, "Fast Breadth-first Leaf Validation"). false:
    every candidate is scored on all its features. */
    CV_PROP_RW bool breadth_first;
    /** Features per chunk in breadth-first validation. Default 16: a quarter of a 63-feature
    modality, the trade-off the paper describes (larger chunks: more robust, slower). */
    CV_PROP_RW int chunk_size;
    /** alpha of the pass condition s > max(median, alpha), with s the accumulated score normalised
    to [0, 1]. Paper: 0.5. */
    CV_PROP_RW float alpha;
    /** Breadth-first validation stops when this many candidates (or fewer) are left, and this
    many best candidates of a location go on to pyramid refinement. Paper: 1 ("until there is
    only one or no candidate left"); 2 gives the same hits (doc/detector.md). With depth at the
    coarsest level (depth_coarse > 0) use 2: the coarse level then sometimes ranks the right view
    a hair below a neighbouring one at every location (1 of 90 hits lost on the rendered scenes
    with 1); the finer level decides when two go on. */
    CV_PROP_RW int max_survivors;
    /** Grid points per side of the descriptor window (paper: the template's sample locations r).
    The window covers every template at the coarsest pyramid level. Default 12 (144 points per
    modality); 10 and 16 gave the same result on the cases examined (doc/detector.md). */
    CV_PROP_RW int grid_size;
    /** Stride (pixels of the coarsest pyramid level) of the locations sent through the forest;
    0: T / 2 of that level. The forest is trained with every template also shifted by up to half
    the stride, so that a location that misses the object's anchor by that much still finds it
    (doc/forest.md, "Misaligned windows"). Smaller: more locations, higher recall, slower. */
    CV_PROP_RW int location_step;
    /** Non-maximum suppression: a match is dropped when its box overlaps a better match (of any
    template and class) by more than this intersection over union. <= 0 or >= 1: off (then the
    output is, as in cv::linemod, every match above the threshold). Default 0.5. */
    CV_PROP_RW float nms_iou;
    /** Depth as a validation modality (paper: "we add depth value as another modality in the
    validation stage to measure shape similarity"), with a DepthNormal modality: addTemplate
    keeps up to this many depth samples per template (spread over the object eroded by 2 px).
    At every pyramid refinement level (and, with depth_coarse, at the coarsest level) they are
    scored with the features, 0..4 each like LINEMOD's response, as many of them as the
    template has features per modality at that level: depth weighs like one more modality.
    Relative depths, the shape and not the distance: the template's depths are first predicted
    for the candidate's image position (turned onto its viewing ray with the template's pose and
    K, the scene's principal point taken as the image centre), the offset is the median of
    (scene - predicted) over the samples, and a sample scores 4 when predicted + offset lies
    within depth_tolerance of the scene's depth range around it (+-T / 2 pixels of the level:
    the depth counterpart of LINEMOD's spreading), 2 within 2 and 1 within 3 tolerances, else 0.
    A sample without scene depth (hole, outside the image) scores 0, as a feature without a
    value does; with fewer than a quarter of them with depth, all score 0. The samples also give
    the initial pose (estimatePoses) and the depth range (depth_range_margin). Set to 0 after
    templates were added, the term is off and the samples stay. Not used in the exhaustive mode
    (plain LINEMOD). At most 256.
    Where they are scored: depth_coarse (default: the pyramid refinement levels, not the
    coarsest level). Default 63 (as many as LINEMOD's features per modality), measured
    (doc/detector.md, "Depth"): on forestmod_eval --synthetic=5 the accuracy is that of 0 (ADD
    95 % with 1 tree) and the time per frame about the same; a flat picture of the object on
    the supporting plane loses points and falls under the threshold (test
    Forestmod_Detector.depth_modality_separates_object_from_flat_picture). 0: off. */
    CV_PROP_RW int depth_samples;
    /** Tolerance (mm) of the depth samples' score. Default 5: about 3 sigma of Kinect-class
    noise at 1 m (1.5 mm, SyntheticSceneParams::depth_noise); a candidate's position error is
    absorbed by the depth range, not by the tolerance. With 10 the pictures of shallow views
    pass (the ape's relief: half its pixels within 5-8 mm of its median depth) and near-ties
    between views are decided less well (doc/detector.md, "Depth"). */
    CV_PROP_RW int depth_tolerance;
    /** Flat-window rejection (paper: the rejectors remove "textureless background"): a location
    leaves before the forest when its window holds fewer labelled values (plain quantized, all
    modalities, at the descriptor's grid points) than min_window_labels times the fewest any
    training template (sample) has. The object's own window holds at least its template's labels
    (minus occlusion), so values well under 1 keep recall. 0: off. Default 0.5, measured
    (doc/detector.md): it removes 0-4 % of the locations, all of which the forest rejects as
    well, before the forest reads them, and costs no hit. */
    CV_PROP_RW float min_window_labels;
    /** Out-of-depth-range rejection (paper: "rejected due to out-of-depth-range"), with a
    DepthNormal modality: a location leaves before the forest when the scene depth is known at
    some of the window's central grid points and none of them lies within the templates' depth
    range (their depth samples, so depth_samples > 0 is needed) widened by this margin (mm).
    0: off. Default 0: on the rendered scenes (supporting plane 100 mm behind the object) a
    50 mm margin rejects nothing; useful on real scenes with far backgrounds. */
    CV_PROP_RW int depth_range_margin;
    /** The forest's descriptors (of the templates at training and of the scene's windows) take
    at each grid point the dominant label of a dominant_window x dominant_window neighbourhood
    of the coarsest level's plain quantized image (on the object mask for a template): one label
    per point as the forest needs (doc/forest.md: spread values mislead it), but tolerant to a
    misalignment or scale change of about a pixel. The shifted training samples of each
    template (location_step) are then taken in strides of dominant_window - 1 pixels. 1: the
    plain label, every shift. Default 3, measured (doc/detector.md, "Search"): with 1, a view
    between two coarse templates (15 % scale, 20 degrees) is rejected everywhere; with 3 and a
    stride of 2 (9 instead of 25 samples per template) the rendered scenes keep every hit with
    fewer candidates and more rejection. */
    CV_PROP_RW int dominant_window;
    /** Search groups (doc/detector.md, "Several objects in one detector"): the templates (with
    group_templates; else the classes, by their largest template) are sorted by their size at
    the coarsest level and grouped greedily; a group takes the next one while its size is at
    most group_size_ratio times the group's smallest. Each group has its own descriptor window (a grid over its own largest
    template), flat-window limit and forest; a location leaves when every group rejects it, its
    candidates are the union of the groups' leaves. With one window over the largest object the
    small objects have few on-mask grid points, their templates spread over hundreds of leaves
    and the rejectors accept almost everything. 0: no size limit (with max_group_classes 0: one
    window and one forest for all classes, the behaviour before groups; model files written
    before groups load that way). Default 1.3, measured on 8 LM-O objects (doc/detector.md):
    3 groups, 74 % of the locations rejected (one window: 1 %) at the same hits; one group per
    class (max_group_classes = 1) rejects as much but traverses 8 forests. */
    CV_PROP_RW float group_size_ratio;
    /** At most this many classes per search group (0: no limit). 1: one window and one forest
    per class. Default 0 (groups by size only). */
    CV_PROP_RW int max_group_classes;
    /** Automatic forest depth (forest.max_depth = 0), per search group:
    max(8, ceil(log2(samples / auto_depth_leaf_samples))) + ceil(log2(classes)), with samples =
    the group's templates x their shifted training samples and classes = the detector's classes.
    The first term follows the number of samples (doc/forest.md: depth must grow with them); the
    second generalises the paper's 8 for one object / 9 for several: a location leaves only when
    every group rejects it, so each group must accept less background the more classes there
    are. Default 8, measured with forestmod_eval --synthetic=5 (rendered RGB-D scenes, 8 LM-O
    objects, 260 templates each; doc/detector.md "Automatic depth"): 8 gives ADD 95 % with 1 tree
    and 97.5 % with 5 (depth 9 for one object), 2 gives 82.5 / 95 % (depth 11) at 1.3x the speed,
    0 (the paper's 8 / 9) 92.5 / 97.5 % at 0.85x the speed, and with all 8 objects in one model
    8 runs 2.3x faster than the paper's rule (which rejects nothing there). 0: the paper's 8 / 9. */
    CV_PROP_RW float auto_depth_leaf_samples;
    /** Colourless classes (most of their templates have no hue feature: white, grey, black
    objects) get search groups of their own whose forests read the ColorHue plane with "no
    reliable hue" as a label of its own (the 8 hue bins merged into 7, "grey" the 8th; the
    validation keeps the plain hue): on a white object the missing hue becomes evidence the
    rejectors can test, where before its descriptor had labels only at its silhouette
    (doc/detector.md, "Colourless objects"). Templates and scene alike; the flat-window test
    ignores the grey label; coloured classes are unchanged. Default false, measured: LM-O can
    with gradient + hue on rendered scenes 9.3 % -> 64.8 % of the locations rejected at 10/10
    hits (coloured objects identical), but on the real LM-O frames (RGB only) 5 trees reject
    99.6 % and find the can in 0 of 10 frames instead of 3 (the real can shows some hue where
    the rendered one is grey). Model files without this key load with false. */
    CV_PROP_RW bool grey_hue_label;
    /** How the depth samples (depth_samples) take part at the coarsest pyramid level, where
    the forest and breadth-first validation work. 0: not there; they are scored at every finer
    level of the pyramid refinement, where a match's position is known to +-T / 2 pixels, and
    decide there whether it passes the threshold and how it ranks. 1: also in the full score of
    the breadth-first survivors at the coarsest level. 2: also in every breadth-first chunk (the
    median rule). At each level a template scores as many samples as it has features per
    modality there (depth weighs like one more modality). Default 0, measured with
    forestmod_eval --synthetic=5 (doc/detector.md, "Depth"): at the coarsest level the samples
    are read +-S / 2 pixels (8 at level 0) from where the object may be, so the right view of a
    thin or steep object scores only 70-80 % there and, under LINEMOD's coarse threshold (90 %
    of the raw score for threshold 80), is lost: 1 tree ADD 95 % with 0, 90 % with 1, 82.5 %
    with 2, which also doubles the validation time (every candidate pays for its depth offset
    before its first chunk). */
    CV_PROP_RW int depth_coarse;
    /** Search groups of templates, not of classes: the templates (of all classes) are sorted by
    their size at the coarsest level and grouped by group_size_ratio as classes are otherwise,
    so the views of one object at different distances (or a long object seen end-on and
    side-on) get windows and forests of their own; a group's classes are the classes of its
    templates, and max_group_classes limits them. false: a class's templates all go to one
    group. Default true, measured (doc/detector.md, "Search groups of templates"): the can with
    templates at 700 and 1100 mm (forestmod_detector_bench --objects=5 --radii=700,1100) was
    rejected 14 % with class groups; one window over both scales leaves the far views few
    on-mask grid points, so the rejectors accept background. Model files without this key
    load with false. */
    CV_PROP_RW bool group_templates;

    void read(const FileNode& fn);
    void write(FileStorage& fs) const;
};

/** @brief Counters and timing of one call to Detector::match, on request. */
struct CV_EXPORTS_W_SIMPLE DetectionStats
{
    CV_WRAP DetectionStats() { reset(); }
    CV_WRAP void reset();

    CV_PROP double t_quantize_ms;    //!< modalities, spreading, response maps (all levels)
    CV_PROP double t_tree_ms;        //!< forest traversal of every location (paper: T_tree)
    CV_PROP double t_valid_ms;       //!< validation + pyramid refinement (paper: T_valid)
    CV_PROP double t_total_ms;       //!< the whole call
    CV_PROP int64 locations;         //!< locations visited on the coarsest level
    CV_PROP int64 rejected;          //!< locations rejected before validation (all causes)
    CV_PROP int64 rejected_flat;     //!< of which: window nearly without labels in every search group
    CV_PROP int64 rejected_depth_range; //!< of which: scene depth outside the templates' range
    CV_PROP int64 validated;         //!< locations that reached validation with candidates
    CV_PROP int64 candidates;        //!< candidate templates validated, summed over locations
    CV_PROP std::vector<int64> rejected_at_depth; //!< rejected locations per forest depth
    /** depth (forest) at which each coarse location was rejected, -1 when it was not, -2 when
    its window was flat, -3 when out of depth range; one CV_16SC1 image of the coarsest level's
    location grid per call, on request (Detector::match). */
    Mat rejection_map;
    //! share of visited locations rejected before validation
    CV_WRAP double rejectedFraction() const { return locations ? double(rejected) / locations : 0; }
};

/** @brief Pose label of a template: the view it was made from. */
struct CV_EXPORTS_W_SIMPLE TemplatePose
{
    CV_WRAP TemplatePose() : valid(false) {}
    CV_PROP_RW Matx33d R; //!< model -> camera rotation (BOP cam_R_m2c)
    CV_PROP_RW Vec3d t;   //!< model -> camera translation, mm (BOP cam_t_m2c)
    CV_PROP_RW Matx33d K; //!< intrinsics the template was rendered with
    CV_PROP_RW Rect box;  //!< the template's box (its features' extent) in its own image, level 0
    CV_PROP_RW bool valid; //!< false for templates added without a pose
};

/** @brief How Detector::estimatePoses turns matches into 6-DoF poses. FileStorage keys are the
field names. */
struct CV_EXPORTS_W_SIMPLE PoseParams
{
    CV_WRAP PoseParams();
    /** Matches refined per class, best first (the others keep their initial pose). Default 3. */
    CV_PROP_RW int max_per_class;
    /** Refine with ICP when depth is given and the class has a mesh (setMesh). Default true. */
    CV_PROP_RW bool icp;
    /** render + ICP passes (refinePose(); doc/pose.md: 2 remove the bias of the visible rim). */
    CV_PROP_RW int icp_passes;
    CV_PROP_RW ICPParams icp_params;
    /** Depth check tolerance as a share of the object's diameter (LINEMOD ACCV 2012). 0.05. */
    CV_PROP_RW double depth_check_tolerance;
    /** Refined hypotheses whose depth check is below this are dropped (ACCV 2012's post-
    processing); 0 keeps them all. Default 0.5. */
    CV_PROP_RW double min_depth_agreement;
    /** Without depth, given the colour image: refine the template's pose by aligning the
    object's rendered edges with the scene's edges (refinePoseEdges(), directional chamfer,
    Levenberg-Marquardt over the 6 DoF), for the best max_per_class matches of classes with a
    mesh. Template poses are as coarse as the view sampling (~16 degrees); this brings them to
    the pixel. Default true. */
    CV_PROP_RW bool rgb_refine;
    /** Parameters of that refinement (see EdgeRefineParams). */
    CV_PROP_RW EdgeRefineParams edge_params;
    /** detect() without depth: the pose of each detection is chosen among this many matches of
    its class at overlapping locations (those that non-maximum suppression merges into it,
    best first), each refined by edge alignment; the one with the highest edge_fit gives the
    detection its template_id, pose label and pose (position, box and score stay the
    detection's, so the ranking is the matcher's). Template matching often ranks a
    wrong view of the object first (front / back); on the 50 real LM-O frames this took the ape's
    poses under 5 px from 4 to 10 of 20 detections (doc/pose.md). 1 = the best match's own
    template only. Default 8. */
    CV_PROP_RW int rgb_hypotheses;

    void read(const FileNode& fn);
    void write(FileStorage& fs) const;
};

/** @brief A match with what cv::linemod::Match lacks: the template's pose label. */
struct CV_EXPORTS_W_SIMPLE PoseMatch : public cv::linemod::Match
{
    CV_WRAP PoseMatch() : has_pose(false), refined(false), depth_agreement(-1), edge_fit(-1) {}
    CV_WRAP PoseMatch(const cv::linemod::Match& m)
        : cv::linemod::Match(m), has_pose(false), refined(false), depth_agreement(-1),
          edge_fit(-1)
    {
    }
    CV_PROP_RW Rect box;          //!< the template's box at the match (level 0 pixels)
    CV_PROP_RW TemplatePose pose; //!< the matched template's pose label
    // filled by Detector::estimatePoses
    CV_PROP_RW bool has_pose;     //!< R, t below are set
    CV_PROP_RW Matx33d R;         //!< estimated pose in the scene camera, model -> camera
    CV_PROP_RW Vec3d t;           //!< mm
    CV_PROP_RW bool refined;      //!< R, t refined (ICP with depth, edge alignment without)
    CV_PROP_RW ICPResult icp;     //!< ICP result when refined
    CV_PROP_RW double depth_agreement; //!< depth check of the final pose, -1 when not checked
    /** Without depth: inlier ratio of the edge alignment (EdgeRefineResult::inlier_ratio), -1
    when the pose was not refined that way. */
    CV_PROP_RW double edge_fit;
};

/** @brief LINEMOD detector searched through a fuzzy template forest (Shao, Tang, Kim).

A drop-in cv::linemod::Detector: same constructors, same addTemplate / addSyntheticTemplate /
match / readClasses / writeClasses signatures and meanings (threshold in percent, sorted matches,
class filter, masks, quantized images), so code written for cv::linemod::Detector works after
changing the type. cv::linemod::Detector has no virtual functions: the methods here hide the
base's ones, so call them through a forestmod::Detector (a call through a base reference or
pointer runs plain LINEMOD, correct but slow).

What it adds: the forest and its background rejectors choose the candidate templates of every
location of the coarsest pyramid level; the candidates are validated breadth-first; survivors are
refined up the pyramid as in LINEMOD. Templates may carry their pose (R, t, K); match() can return
PoseMatch with it. The forest is trained by train(), or automatically by the first match() after
templates changed (train() is not thread-safe; match() is const and thread-safe once trained).
*/
class CV_EXPORTS_W Detector : public cv::linemod::Detector
{
public:
    CV_WRAP Detector();
    CV_WRAP Detector(const std::vector<Ptr<cv::linemod::Modality> >& modalities,
                     const std::vector<int>& T_pyramid,
                     const DetectorParams& params = DetectorParams());
    ~Detector();

    /** Same as cv::linemod::Detector::match. */
    CV_WRAP void match(const std::vector<Mat>& sources, float threshold,
                       CV_OUT std::vector<cv::linemod::Match>& matches,
                       const std::vector<String>& class_ids = std::vector<String>(),
                       OutputArrayOfArrays quantized_images = noArray(),
                       const std::vector<Mat>& masks = std::vector<Mat>()) const;
    /** match() with statistics (timing, locations rejected per depth, ...). */
    void match(const std::vector<Mat>& sources, float threshold,
               std::vector<cv::linemod::Match>& matches, const std::vector<String>& class_ids,
               OutputArrayOfArrays quantized_images, const std::vector<Mat>& masks,
               DetectionStats* stats) const;
    /** match() returning the matched templates' poses and boxes. */
    void match(const std::vector<Mat>& sources, float threshold, std::vector<PoseMatch>& matches,
               const std::vector<String>& class_ids = std::vector<String>(),
               const std::vector<Mat>& masks = std::vector<Mat>(),
               DetectionStats* stats = 0) const;

    /** Same as cv::linemod::Detector::addTemplate (no pose label). */
    CV_WRAP int addTemplate(const std::vector<Mat>& sources, const String& class_id,
                            const Mat& object_mask, CV_OUT Rect* bounding_box = NULL);
    /** addTemplate with the template's pose label (R, t in BOP convention, K of the rendering). */
    int addTemplate(const std::vector<Mat>& sources, const String& class_id,
                    const Mat& object_mask, const Matx33d& R, const Vec3d& t, const Matx33d& K,
                    Rect* bounding_box = NULL);
    /** Renders a mesh from every pose of a sampler and adds each view as a template with its
    pose label (sources per modality: the colour image for ColorGradient and ColorHue, the depth
    for DepthNormal). Views that yield no template (too few features) are skipped. A view
    without an object pixel or covered by the object (a degenerate mesh, a wrong scale, radii
    that do not fit the mesh), or no template from any view, raises a cv::Exception naming the
    class and the view. progress (optional) is called with (done, total); returning false
    stops. Returns the number of templates added. */
    int addTemplates(const Mesh& mesh, const String& class_id, const ViewSampler& sampler,
                     const Matx33d& K, Size size,
                     const std::function<bool(int, int)>& progress = std::function<bool(int, int)>());

    /** Same as cv::linemod::Detector::addSyntheticTemplate. */
    CV_WRAP int addSyntheticTemplate(const std::vector<cv::linemod::Template>& templates,
                                     const String& class_id);

    /** The mesh of a class, for pose refinement and depth checks (estimatePoses). addTemplates()
    sets it; after load() call it again (meshes are not stored in model files). */
    void setMesh(const String& class_id, const Mesh& mesh);
    bool hasMesh(const String& class_id) const;

    /** @brief 6-DoF poses for matches of match(..., std::vector<PoseMatch>&, ...).

    Every match whose template has a pose gets an initial pose: the template's rotation corrected
    for the off-axis viewing ray and its translation along the ray through the matched object, at
    the template's distance (no depth) or at the distance the scene depth implies under the
    template's depth samples. With depth and a mesh (setMesh), the best params.max_per_class
    matches of each class are refined with ICP (refinePose) and depth-checked; those below
    params.min_depth_agreement are dropped. Matches keep their order.
    Without depth, given the colour image and a mesh, the best params.max_per_class matches per
    class are refined by edge alignment (refinePoseEdges(), PoseParams::rgb_refine; edge_fit is
    set).
    @param depth CV_16UC1 scene depth in mm, or empty for RGB only.
    @param K     intrinsics of the scene images.
    @param color the scene's BGR image (for the refinement without depth), optional.
    */
    void estimatePoses(InputArray depth, const Matx33d& K, std::vector<PoseMatch>& matches,
                       const PoseParams& params = PoseParams(), InputArray color = noArray()) const;

    /** match() + estimatePoses() in one call: sources as for match(); the depth is taken from the
    DepthNormal source when the detector has one. Without depth, each of the best
    params.max_per_class detections per class takes its pose from the best edge fit among the
    matches that non-maximum suppression merges into it (PoseParams::rgb_hypotheses). */
    void detect(const std::vector<Mat>& sources, const Matx33d& K, float threshold,
                std::vector<PoseMatch>& matches,
                const std::vector<String>& class_ids = std::vector<String>(),
                const PoseParams& params = PoseParams(), DetectionStats* stats = 0) const;

    /** Pose label of a template (valid == false when it was added without one). */
    TemplatePose getTemplatePose(const String& class_id, int template_id) const;

    /** Builds the descriptor geometry and trains the forest on all templates. */
    CV_WRAP void train();
    /** true when the forest is up to date with the templates. */
    CV_WRAP bool isTrained() const;

    CV_WRAP DetectorParams getParams() const;
    /** Changing parameters that shape the forest (forest, grid_size) marks it for retraining. */
    CV_WRAP void setParams(const DetectorParams& params);

    /** The trained forest of a search group (DetectorParams::group_size_ratio; empty before
    train()). With one group (one class, or groups off) group 0 is the detector's only forest. */
    Ptr<TemplateForest> getForest(int group = 0) const;
    /** Number of search groups (each with its window and forest) of the trained detector; 0
    before train(). */
    CV_WRAP int numSearchGroups() const;
    /** The classes of a search group, smallest first. */
    CV_WRAP std::vector<String> getSearchGroupClasses(int group) const;

    /** Detector (modalities, pyramid) as cv::linemod::Detector writes it, plus params. */
    CV_WRAP void read(const FileNode& fn);
    void write(FileStorage& fs) const;
    String readClass(const FileNode& fn, const String& class_id_override = "");
    void writeClass(const String& class_id, FileStorage& fs) const;
    CV_WRAP void readClasses(const std::vector<String>& class_ids,
                             const String& format = "templates_%s.yml.gz");
    CV_WRAP void writeClasses(const String& format = "templates_%s.yml.gz") const;

    /** Whole model (modalities, pyramid, params, templates with poses, trained forest) to one
    file (.yml, .yml.gz, .json). Refuses to overwrite an existing file unless overwrite is true. */
    CV_WRAP void save(const String& filename, bool overwrite = false) const;
    /** Loads a model written by save(); a corrupt file, another format version or an unknown
    modality raises cv::Exception. */
    CV_WRAP void load(const String& filename);

    struct Impl;

private:
    // match() with stats; nms = false returns the matches before non-maximum suppression
    // (detect() picks a pose among the overlapping ones)
    void matchImpl(const std::vector<Mat>& sources, float threshold,
                   std::vector<cv::linemod::Match>& matches,
                   const std::vector<String>& class_ids, OutputArrayOfArrays quantized_images,
                   const std::vector<Mat>& masks, DetectionStats* stats, bool nms) const;

    Ptr<Impl> impl_;
};

/** @brief Color gradient + hue, T = {5, 8} (LINEMOD's getDefaultLINE plus the paper's hue).
Sources: {BGR image, BGR image}. */
CV_EXPORTS_W Ptr<Detector> getDefaultForestLINE();
/** @brief Color gradient + depth normal + hue, T = {5, 8} (getDefaultLINEMOD plus the hue).
Sources: {BGR image, depth CV_16UC1 mm, BGR image}: the hue is last, so a cv::linemod
getDefaultLINEMOD program appends its colour image once more. */
CV_EXPORTS_W Ptr<Detector> getDefaultForestLINEMOD();

/** @brief Creates a modality from a FileNode written by a modality's write(): ColorHue besides
cv::linemod's ColorGradient and DepthNormal. */
CV_EXPORTS Ptr<cv::linemod::Modality> createModality(const FileNode& fn);

//! @}

} // namespace forestmod
} // namespace cv

#endif // OPENCV_FORESTMOD_DETECTOR_HPP
