// This file is part of OpenCV project.
// It is subject to the license terms in the LICENSE file found in the top-level directory
// of this distribution and at http://opencv.org/license.html

#ifndef OPENCV_FORESTMOD_DETECTOR_HPP
#define OPENCV_FORESTMOD_DETECTOR_HPP

#include "opencv2/core.hpp"
#include "opencv2/rgbd/linemod.hpp"
#include "opencv2/forestmod/forest.hpp"
#include "opencv2/forestmod/pose.hpp"

#include <functional>

namespace cv {
namespace forestmod {

class Mesh;
struct ViewSampler;
namespace detail {
struct DetectorImpl;
struct Drawing;
}

//! @addtogroup forestmod_detector
//! @{

/** @brief Parameters of forestmod::Detector, grouped by the stage that reads them. FileStorage
keys are the field names. The measurements behind the defaults: doc/detector.md. */
struct CV_EXPORTS_W_SIMPLE DetectorParams
{
    CV_WRAP DetectorParams();

    // ---- search index (train()): search groups, descriptor windows, forests ----
    /** The forest of every search group (paper: 1 or 5 trees, depth 8 for one object, 9 for
    several). Defaults differ from ForestParams(): max_depth 0 (automatic, see
    auto_depth_leaf_samples), rejector_coverage 0.5, rejector_dims 64 (doc/detector.md,
    "Search"). */
    CV_PROP_RW ForestParams forest;
    /** Grid points per side of a group's descriptor window (paper: the sample locations r), over
    its largest template at the coarsest level. Default 12. */
    CV_PROP_RW int grid_size;
    /** Descriptors read the dominant label of a dominant_window^2 neighbourhood of the coarsest
    quantized image, tolerant to a pixel of misalignment (doc/detector.md, "Search"). 1: the plain
    label. Default 3. */
    CV_PROP_RW int dominant_window;
    /** Templates are sorted by size at the coarsest level and grouped while a group's largest is
    at most this times its smallest; each group has its own window and forest (doc/detector.md,
    "Search groups"). 0: one group. Default 1.3. */
    CV_PROP_RW float group_size_ratio;
    /** Search groups of templates (true) or of whole classes (false: model files written before
    template groups load this way). Default true (doc/detector.md, "Search groups"). */
    CV_PROP_RW bool group_templates;
    /** Automatic forest depth when forest.max_depth is 0: max(8, ceil(log2(samples / this))) +
    ceil(log2(classes)), at most log2(samples) + 1 (doc/detector.md, "Automatic forest depth").
    0: the paper's 8 / 9. Default 8. */
    CV_PROP_RW float auto_depth_leaf_samples;

    // ---- scan: the locations of the coarsest level through the forests ----
    /** Use the forests. false: every template is a candidate everywhere (exhaustive LINEMOD, for
    comparison). Default true. */
    CV_PROP_RW bool use_forest;
    /** Stride (coarsest-level pixels) of the locations; 0: T / 2 of that level. The forest is
    trained with every template shifted by up to half of it (doc/forest.md). Default 0. */
    CV_PROP_RW int location_step;
    /** A location leaves when its window holds fewer labelled values than this times the fewest
    of any training template (paper: "textureless background"). 0: off. Default 0.5. */
    CV_PROP_RW float min_window_labels;
    /** With depth (paper: "out-of-depth-range"): a template is searched only where the scene
    depth around its centre (3 x 3 cells of the coarsest level's T grid) reaches into its depth
    samples' range [z_min, z_max] widened to [z_min / (1 + x), z_max (1 + x)], a search group
    only at the locations where it reaches into one of its templates'. x covers the distances
    between the templates' radii (a template matches its object a few percent nearer or
    farther; 0.25 spans the gaps of the evaluation's radii, 650, 900 and 1150 mm). Negative:
    off. Default 0.25 (doc/detector.md, "Rejections before the forest"). */
    CV_PROP_RW float depth_range_tolerance;

    // ---- validation (paper: "Fast Breadth-first Leaf Validation") ----
    /** Breadth-first preemptive validation; false: every candidate scored on all its features.
    Default true. */
    CV_PROP_RW bool breadth_first;
    /** Features per chunk. Default 16 (a quarter of a 63-feature modality). */
    CV_PROP_RW int chunk_size;
    /** alpha of the pass condition s > max(median, alpha). Paper and default: 0.5. */
    CV_PROP_RW float alpha;
    /** Validation stops at this many candidates, which go on to pyramid refinement; a position
    of the exhaustive search keeps max_survivors x (T / location step)^2 coarse matches. In
    [1, 64]. Default 2 (the paper: 1): on real LM-O frames that no table reports, 2 raises the
    plain and the verified projection recall for a quarter more match() (doc/detector.md,
    "Validation"). */
    CV_PROP_RW int max_survivors;
    /** Bounded worst case: in a frame where a search group's forest costs more (the (location,
    candidate) pairs it lets through and its descents, descent_cost) than this times (its
    asked-for templates x the positions of the coarsest level's T grid) validated pairs,
    estimated on every 8th row of locations, the group leaves the scan
    and its templates are searched exhaustively as cv::linemod does (linearized memories, one
    SIMD add per feature over all positions of the T grid); each position keeps its best
    max_survivors x (T / location step)^2 templates over the threshold as coarse matches, as many
    as the forest path's locations in its cell keep. A validated pair costs about as much as
    9-14 exhaustive (position, template) pairs and the location grid has 4x the positions of
    the T grid; the trees' descents count too (descent_cost): default 0.01, measured on LM-O
    frames that the evaluation does not report (doc/detector.md, "Bounded worst case"). 0: every
    group exhaustive (no traversal); negative: never. */
    CV_PROP_RW float exhaustive_ratio;
    /** The sample's cost of a descent, in validated pairs per tree node visited: a group's
    sample counts its pairs plus this times the nodes its trees visit (the rejected locations'
    too), so that a forest whose descents cost more than the exhaustive search leaves the scan
    although its leaves hold few candidates. A node test costs 2-4 validated pairs (70-90 ns
    against 16-40 ns; doc/experiments.md, "The trees' descents counted in the sample"). Default
    2. 0: the pairs only. Model files written without it load with 0 (they match as they did). */
    CV_PROP_RW float descent_cost;
    /** With a positive exhaustive_ratio, a search group of at most this many asked-for templates
    is searched exhaustively without sampling its forest: that search costs little, and a forest
    of a few views, its rejectors made from renderings, rejects the object itself on real frames
    (LM-O frames 15-49 with 6 and with 42 templates per object: the can and the eggbox rejected at
    97-100 % of the locations and never found, where cv::linemod with the same templates finds
    them; doc/detector.md, "Small models"). Default 64. 0: every group decided by the sample.
    Model files written without it load with 0 (they match as they did). */
    CV_PROP_RW int min_forest_templates;
    /** The classes of a search group share its lists: each position of the exhaustive search and
    each location of the forest path keeps its best templates over all of them, so one class's
    templates can fill the lists at another's location, and that class then loses its match
    there (LM-O's 8 objects in one RGB model, frames 15-34: 10 of the 41 top matches that the
    objects' own models put on them; doc/experiments.md, "Lists per class"). true: one scan
    for all asked-for classes, then each class's own lists: a forest-path location's survivors
    are chosen among its candidates of one class, and each position of the exhaustive search
    keeps the best templates of every class, each with entry bars of its own (one search for
    all). A class's matches are then those of match() asked for it alone (before non-maximum
    suppression, which compares every class's) wherever the scan sends a search group the same
    way (exhaustive or forest) for the class alone as for all asked-for classes: always for
    groups of at most min_forest_templates templates and with exhaustive_ratio 0 or negative.
    The DetectionStats counters are the one scan's. That 8-object model's match() takes about
    2.5x as long as with shared lists. Default false. */
    CV_PROP_RW bool search_per_class;

    // ---- depth modality (paper: depth "as another modality in the validation stage") ----
    /** With a DepthNormal modality, addTemplate keeps up to this many depth samples per template;
    they are scored at every pyramid refinement level like the features of one more modality
    (relative depths, 0..4 each), give the initial pose and the depth range. 0: off. At most 256.
    Default 63 (doc/detector.md, "Depth modality"). */
    CV_PROP_RW int depth_samples;
    /** Tolerance (mm) of a depth sample's full score. Default 5 (3 sigma of Kinect-class noise at
    1 m). */
    CV_PROP_RW int depth_tolerance;

    // ---- non-maximum suppression ----
    /** A match is dropped when its box overlaps a better match (any template and class) by more
    than this intersection over union. <= 0 or >= 1: off (every match above the threshold, as
    cv::linemod). Default 0.5. */
    CV_PROP_RW float nms_iou;

    void read(const FileNode& fn);
    void write(FileStorage& fs) const;
};

/** @brief Counters and timing of one call to Detector::match, on request. */
struct CV_EXPORTS_W_SIMPLE DetectionStats
{
    CV_WRAP DetectionStats() { reset(); }
    CV_WRAP void reset();

    CV_PROP double t_quantize_ms;    //!< scene pyramid: quantization, spreading, response maps of
                                     //!< all levels, the forest's label planes, depth contexts
    CV_PROP double t_tree_ms;        //!< scan: rejections and forests of every location (T_tree)
    CV_PROP double t_valid_ms;       //!< validation + pyramid refinement + sorting (T_valid)
    CV_PROP double t_total_ms;       //!< the whole call (with an automatic training and NMS)
    /** verification stage (Detector::detect, Detector::verify): rendering the hypotheses,
    the scene's edge maps and colours, scoring and re-ranking; not part of t_total_ms */
    CV_PROP double t_verify_ms;
    /** background similarity of the hypotheses (Detector::detect with
    VerificationParams::background_weight > 0, Detector::backgroundSimilarity): each template
    scored over the whole frame; not part of t_total_ms */
    CV_PROP double t_background_ms;
    CV_PROP int64 verified;          //!< hypotheses scored by the verification stage
    CV_PROP int64 locations;         //!< locations visited on the coarsest level
    /** locations rejected before validation (all causes): by every search group on the forest
    path, and out of the depth range of every group searched exhaustively (such a group scores
    every other location, DetectorParams::exhaustive_ratio) */
    CV_PROP int64 rejected;
    //! of which: window nearly without labels in every search group
    CV_PROP int64 rejected_flat;
    CV_PROP int64 rejected_depth_range; //!< of which: scene depth outside the templates' range
    /** locations that reached validation with candidates from the forest path (the groups
    searched exhaustively, DetectorParams::exhaustive_ratio, score their locations without
    candidates; those locations are not counted here, nor as rejected) */
    CV_PROP int64 validated;
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

/** @brief Parameters of the verification stage (Detector::verify(), Detector::detect()): the
best hypotheses of each class, at their refined pose, are rendered (mask, colour, depth) and scored
on evidence the LINEMOD similarity does not use; they are then ranked by the weighted sum
verification = w_similarity * similarity / 100 + w_color * color_score + w_edges * edge_score
+ w_region * region_score (+ w_depth * depth_score with depth), the weights divided by their sum
(doc/verification.md).
FileStorage keys are the field names. */
struct CV_EXPORTS_W_SIMPLE VerificationParams
{
    CV_WRAP VerificationParams();
    /** detect() verifies and re-ranks its detections. Default true. */
    CV_PROP_RW bool enabled;
    /** Hypotheses verified per class, the first in detect()'s order (after non-maximum
    suppression; the matcher's order, or by background with background_weight > 0); the others
    keep their place after the verified ones. Default 10. */
    CV_PROP_RW int top_k;
    /** Without depth, detect() (and forestmod_eval's verified rows) poses and verifies the next
    top_k detections of a class whose best verified hypothesis scores below this, and ranks all of
    them together: a second round where the first holds no convincing hypothesis. 0: one round
    (above 1: always two). Default 0.75, set on LM-O frames the evaluation does not report
    (doc/verification.md, "A second round"). */
    CV_PROP_RW double second_round_below;
    /** A pixel whose HSV saturation (0..1) is below this, or whose value is below min_value, has
    no reliable hue: it falls into the achromatic bin (white, grey, black). A model pixel agrees
    with the scene when both are achromatic, or both chromatic with hues within hue_tolerance.
    Default 0.25. */
    CV_PROP_RW double min_saturation;
    /** HSV value (0..1) below which a pixel is achromatic (too dark for a hue). Default 0.15. */
    CV_PROP_RW double min_value;
    /** Hue tolerance (degrees) of a colour agreement. Default 20. */
    CV_PROP_RW double hue_tolerance;
    /** A point of the rendered contour agrees when a scene edge of its orientation (the
    directional distance maps of computeEdgeMaps(), edge_params) lies within this many pixels.
    Default 3. */
    CV_PROP_RW double edge_distance;
    /** Scene edges of the contour check (orientations, Canny thresholds, max_distance). */
    CV_PROP_RW EdgeRefineParams edge_params;
    /** Depth check tolerance, share of the object's diameter (LINEMOD ACCV 2012). Default 0.05. */
    CV_PROP_RW double depth_tolerance;
    /** Occlusion: a rendered pixel whose scene depth is nearer than the rendering by more than
    depth_tolerance is occluded (left out of the colour and depth scores); without depth, a
    contour point without a matching edge whose neighbourhood disagrees in colour is taken as
    covered. Whatever is left out, every score is divided by at least min_visible times the
    points it would count without occlusion, so a hypothesis cannot win by being hidden.
    Default 0.5. */
    CV_PROP_RW double min_visible;
    /** Pixel step of the colour and depth samples inside the rendered mask. Default 2. */
    CV_PROP_RW int sample_step;
    /** Weights of the final score, set on real LM-O frames that the evaluation does not report
    (doc/verification.md; on rendered RGB-D scenes w_depth 0, 0.4 and 0.8 rank alike). */
    CV_PROP_RW double w_similarity; //!< LINEMOD similarity / 100. Default 0.1
    CV_PROP_RW double w_color;      //!< color_score. Default 0.3
    CV_PROP_RW double w_edges;      //!< edge_score. Default 0.3
    CV_PROP_RW double w_depth;      //!< depth_score, with depth only. Default 0.4
    CV_PROP_RW double w_region;     //!< region_score. Default 0.3
    /** Width (px) of the ring around the rendered silhouette whose colours region_score compares
    with those inside it (the ring starts 2 px out: the silhouette's pixels mix both). Default 6. */
    CV_PROP_RW int region_width;
    /** detect(): before the pose stage, the matches are ordered by similarity -
    background_weight x background (PoseMatch::background: how well the match's template fits
    the frame anywhere), so that the top_k detections per class that get a pose and a
    verification are those that stand out from the frame, not templates that fit its clutter
    everywhere; non-maximum suppression keeps the first of overlapping matches in that order.
    0: the matcher's order. Default 1.5, set on LM-O frames the evaluation does not report
    (doc/verification.md, "Background similarity"). */
    CV_PROP_RW double background_weight;
    /** The quantile of a template's similarities over every position of the frame's coarsest
    level taken as its background (PoseMatch::background), in (0, 1]. Default 0.99 (about the
    twelfth best of the 1 200 positions of a VGA frame). */
    CV_PROP_RW double background_quantile;

    void read(const FileNode& fn);
    void write(FileStorage& fs) const;
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
    /** With depth, detect() and choosePoses(): a detection's pose is the first of up to this many
    of its matches (itself, then those non-maximum suppression merged into it, best first) whose
    ICP pose passes the depth check; each is refined only when the one before failed (LINEMOD
    ACCV 2012's post-processing). A detection none of whose passes is dropped. 1 = its own
    match only. Default 3. */
    CV_PROP_RW int depth_hypotheses;
    /** Without depth, given the colour image: refine the template's pose by aligning the
    object's rendered edges with the scene's edges (refinePoseEdges(), directional chamfer,
    Levenberg-Marquardt over the 6 DoF), for the best max_per_class matches of classes with a
    mesh. Template poses are as coarse as the view sampling (~16 degrees); this brings them to
    the pixel. Default true. */
    CV_PROP_RW bool rgb_refine;
    /** Parameters of that refinement (see EdgeRefineParams). */
    CV_PROP_RW EdgeRefineParams edge_params;
    /** detect(): the verification stage that re-ranks the detections (VerificationParams). With
    it enabled, the best max(max_per_class, verification.top_k) detections per class get a
    refined pose. */
    CV_PROP_RW VerificationParams verification;
    /** detect() without depth: the pose of each detection is chosen among this many matches of
    its class at overlapping locations (those that non-maximum suppression merges into it,
    best first), each refined by edge alignment; the one with the highest edge_fit gives the
    detection its template_id, pose label and pose (position, box and score stay the
    detection's, so the ranking is the matcher's). Template matching often ranks a
    wrong view of the object first (front / back); on the 50 real LM-O frames this took the ape's
    poses under 5 px from 4 to 10 of 20 detections (doc/pose.md). 1 = the best match's own
    template only. Default 24 (with rgb_keep; the edge alignment's points come from the mesh's
    silhouette edges, cheap enough that 24 cost less than 16 did with drawings, for more
    projection recall on LM-O's tuning frames: doc/pose.md). */
    CV_PROP_RW int rgb_hypotheses;
    /** Of a detection's rgb_hypotheses matches, those whose edge fit is among the rgb_keep best
    after the refinement's first pass go on to its other passes; the others keep their
    template's pose. On LM-O's tuning frames 4 of 16 gave a higher projection recall than all of
    8 refined fully, in about the same time, and 4 of 24 more than 6 of 16 (doc/pose.md).
    >= rgb_hypotheses refines every match fully. Default 4. */
    CV_PROP_RW int rgb_keep;

    void read(const FileNode& fn);
    void write(FileStorage& fs) const;
};

/** @brief A match with what cv::linemod::Match lacks: the template's pose label. */
struct CV_EXPORTS_W_SIMPLE PoseMatch : public cv::linemod::Match
{
    CV_WRAP PoseMatch()
        : has_pose(false), refined(false), depth_agreement(-1), edge_fit(-1), verification(-1),
          color_score(-1), edge_score(-1), depth_score(-1), occlusion(-1), region_score(-1),
          background(-1)
    {
    }
    CV_WRAP PoseMatch(const cv::linemod::Match& m)
        : cv::linemod::Match(m), has_pose(false), refined(false), depth_agreement(-1),
          edge_fit(-1), verification(-1), color_score(-1), edge_score(-1), depth_score(-1),
          occlusion(-1), region_score(-1), background(-1)
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
    // filled by the verification stage (Detector::verify, Detector::detect); -1: not verified
    /** Final score (0..1) of the verification, the weighted sum of the similarity and the parts
    below (VerificationParams); verified hypotheses are ranked by it. */
    CV_PROP_RW double verification;
    /** Share of the rendered object's visible pixels whose colour agrees with the scene (hue,
    or both achromatic). */
    CV_PROP_RW double color_score;
    /** Share of the rendered contour with a scene edge of its orientation nearby (covered
    fragments left out). */
    CV_PROP_RW double edge_score;
    /** With depth: share of the visible pixels whose scene depth agrees with the rendering. */
    CV_PROP_RW double depth_score;
    /** Share of the rendered object taken as occluded (depth nearer; without depth: contour
    fragments without edge whose colour disagrees). */
    CV_PROP_RW double occlusion;
    /** How much the scene's colours inside the rendered silhouette differ from those of a ring
    around it (total variation distance of their colour histograms, 0..1): an object stands out
    from its surroundings, a pose on clutter straddles it. Needs no model colours. */
    CV_PROP_RW double region_score;
    /** How well the match's template fits the frame anywhere: its similarity (percent, on the
    coarsest level) at VerificationParams::background_quantile of every position where it fits
    (Detector::backgroundSimilarity, Detector::detect: a detection's is its location's first
    match's, as its similarity); -1 when not computed. */
    CV_PROP_RW double background;
    /** The object as estimatePoses() last drew it, at exactly (R, t) (opaque): verify() scores
    that drawing instead of drawing the hypothesis again, and releases it; a drawing of another
    pose, camera or mesh (setMesh() since) is not used. Empty when not drawn; release() it to
    free the memory. */
    Ptr<detail::Drawing> drawing;
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
templates changed. match(), detect() and estimatePoses() are const and may be called from several
threads at once (the automatic training runs once, under a lock); adding templates, setParams(),
train(), read and load must not run concurrently with them.
*/
class CV_EXPORTS_W Detector : public cv::linemod::Detector
{
public:
    CV_WRAP Detector();
    /** What load() accepts, or StsBadArg naming the problem: 1..8 modalities (ColorGradient and
    DepthNormal with finite thresholds and 1..8192 features), 1..8 pyramid levels, each T in
    1..64; so every detector made can be saved and loaded again. */
    CV_WRAP Detector(const std::vector<Ptr<cv::linemod::Modality> >& modalities,
                     const std::vector<int>& T_pyramid,
                     const DetectorParams& params = DetectorParams());
    ~Detector();
    /** An independent copy, as cv::linemod::Detector's: the templates, parameters, trained
    forests and meshes; adding templates to one leaves the other as it is. As in cv::linemod the
    modalities are shared, and so are the trained forests until either detector trains again
    (getForest() of both gives the same object: train it through the detector, not directly). */
    Detector(const Detector& other);
    Detector& operator=(const Detector& other);

    /** Same as cv::linemod::Detector::match. */
    CV_WRAP void match(const std::vector<Mat>& sources, float threshold,
                       CV_OUT std::vector<cv::linemod::Match>& matches,
                       const std::vector<String>& class_ids = std::vector<String>(),
                       OutputArrayOfArrays quantized_images = noArray(),
                       const std::vector<Mat>& masks = std::vector<Mat>()) const;
    /** match() with statistics (timing, locations rejected per depth, ...), added to *stats: the
    counters and times of several calls sum up (DetectionStats::reset() between calls for one
    call's), the rejection map is the last call's. */
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
    /** addTemplate with the template's pose label (R, t in BOP convention, K of the rendering):
    a pose that load() would refuse (not finite, t_z <= 0, focal lengths below 1 pixel, K's last
    row not (0, 0, 1)) raises StsBadArg and adds nothing. */
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
                     const std::function<bool(int, int)>& progress
                     = std::function<bool(int, int)>());

    /** Same as cv::linemod::Detector::addSyntheticTemplate, with the checks of load(): one
    template per modality and level, sizes, feature labels 0..7 and positions inside their
    template (StsBadArg otherwise, nothing added). */
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
    set). The refined matches keep their last drawing (PoseMatch::drawing) for verify().
    @param depth CV_16UC1 scene depth in mm, or empty for RGB only.
    @param K     intrinsics of the scene images.
    @param color the scene's BGR image (for the refinement without depth), optional.
    */
    void estimatePoses(InputArray depth, const Matx33d& K, std::vector<PoseMatch>& matches,
                       const PoseParams& params = PoseParams(), InputArray color = noArray()) const;

    /** @overload
    The edge alignment reads `edge_maps` when they are not empty (computeEdgeMaps() of `color`
    with params.edge_params, over a roi that holds the matches), else it computes them around the
    refined matches and returns them there, for verify() or further calls on the same frame. */
    void estimatePoses(InputArray depth, const Matx33d& K, std::vector<PoseMatch>& matches,
                       const PoseParams& params, InputArray color, EdgeMaps& edge_maps) const;

    /** @brief How well each match's template fits the frame anywhere (PoseMatch::background).

    The frame (`sources`, as for match()) is quantized, each distinct template of `matches` is
    scored at every position of the coarsest level (as the exhaustive search scores it), and a
    match's `background` is its template's similarity at `quantile` of those positions. A
    template that fits the clutter everywhere has a high background; the object's own template
    peaks where the object is. detect() orders its hypotheses by similarity -
    VerificationParams::background_weight x background before the pose stage; this function
    gives the same to any matches of this detector's templates, e.g. cv::linemod's with the same
    templates (forestmod_eval's linemod_verified row).
    @param sources  the frame, one image per modality (as match()).
    @param matches  matches of this detector's classes and templates; `background` is set.
    @param quantile in (0, 1] (VerificationParams::background_quantile).
    @param stats    optional: t_background_ms is increased by the time taken.
    */
    void backgroundSimilarity(const std::vector<Mat>& sources, std::vector<PoseMatch>& matches,
                              double quantile, DetectionStats* stats = 0) const;

    /** @brief The pose of each location, chosen among several matches at it as detect() chooses
    it.

    locations[i] holds matches of one class at one location, best first: those that non-maximum
    suppression merges into one detection (detect()), or another matcher's matches grouped by
    box overlap (forestmod_eval groups cv::linemod's so). Each needs its template's pose label
    and box (PoseMatch(match) with getTemplatePose() and the template's size). Only the first
    params.max_per_class locations of each class whose class has a mesh are refined; the others
    keep their first match's initial pose.
    With depth (and params.icp): of a location's first params.depth_hypotheses matches, refined
    by ICP one after the other, the first that passes the depth check gives the pose; a location
    none of whose refined matches passes is left out of `detections`.
    Without depth: the first params.rgb_hypotheses matches are refined by edge alignment from
    their template's pose (refinePoseEdges()); after the first pass only the params.rgb_keep best
    edge fits of the location go on, and the best final fit gives the pose.
    The chosen match gives the detection its template_id, pose label, pose, edge_fit or
    icp/depth_agreement, and drawing; position, box and similarity stay those of the location's
    first match.
    @param depth  CV_16UC1 scene depth in mm, or empty for RGB only.
    @param K      intrinsics of the scene image.
    @param locations matches grouped by location (none empty, one class each).
    @param params see PoseParams.
    @param color  the scene's BGR image (needed without depth).
    @param detections one per location kept, in their order.
    @param edge_maps as for estimatePoses().
    */
    void choosePoses(InputArray depth, const Matx33d& K,
                     const std::vector<std::vector<PoseMatch> >& locations,
                     const PoseParams& params, InputArray color,
                     std::vector<PoseMatch>& detections, EdgeMaps& edge_maps) const;

    /** @overload Without depth. */
    void choosePoses(const Matx33d& K, const std::vector<std::vector<PoseMatch> >& locations,
                     const PoseParams& params, InputArray color,
                     std::vector<PoseMatch>& detections, EdgeMaps& edge_maps) const;

    /** @brief Verification stage: re-ranks pose hypotheses on evidence the LINEMOD score does
    not use.

    The first params.top_k matches of each class that have a pose (has_pose, e.g. from
    estimatePoses()) and a mesh (setMesh) are rendered at their pose and scored: colour
    agreement on the visible mask (color_score), agreement of the whole rendered contour with the
    scene's edges (edge_score, directional chamfer), occlusion (occlusion), and with depth the
    rendered-vs-scene depth check (depth_score); verification is their weighted sum with the
    similarity. The verified matches are moved to the front, highest verification first; the
    others follow in their order. The colour image is needed; depth is optional.
    @param color CV_8UC3 BGR scene image.
    @param depth CV_16UC1 scene depth (mm), same size, or empty.
    @param K     intrinsics of the scene images.
    @param matches hypotheses (any order; e.g. detect()'s or estimatePoses()'s output).
    @param params see VerificationParams.
    @param stats optional: t_verify_ms and verified are added to it.
    */
    void verify(InputArray color, InputArray depth, const Matx33d& K,
                std::vector<PoseMatch>& matches,
                const VerificationParams& params = VerificationParams(),
                DetectionStats* stats = 0) const;

    /** @overload
    The contour's scene edges are read from the frame's `edge_maps` (computeEdgeMaps() of `color`
    with params.edge_params, e.g. those estimatePoses() made for the refinement, over a roi that
    holds the hypotheses) instead of Canny on each hypothesis' crop: detect() does so. */
    void verify(InputArray color, InputArray depth, const Matx33d& K,
                std::vector<PoseMatch>& matches, const VerificationParams& params,
                DetectionStats* stats, const EdgeMaps& edge_maps) const;

    /** match() and the poses in one call: sources as for match(); the depth is taken from the
    DepthNormal source when the detector has one. Each of the best params.max_per_class
    detections per class takes its pose from the matches that non-maximum suppression merges into
    it (choosePoses()): with depth the first of them whose ICP pose passes the depth check
    (PoseParams::depth_hypotheses; a detection none of whose passes is dropped), without depth
    the best edge fit (PoseParams::rgb_hypotheses). With
    params.verification.enabled (the default) the detections are then verified and re-ranked
    (verify()): the returned order is the verification's. Without depth, a class whose best
    verified detection scores below verification.second_round_below has its next top_k
    detections posed and verified as well (in place of their template-posed ones), all of them
    ranked together. */
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
    /** Changing a parameter that shapes the search index (the "search index" section of
    DetectorParams, and location_step) marks the forests for retraining at the next match() or
    train(); the others (scan, validation, depth, NMS) apply to the next match() with the trained
    forests, e.g. those of a loaded model. */
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
    /** As cv::linemod's: a file per class, `format` with its %s replaced by the class id. The
    format must hold one %s and no other conversion (%% for a percent sign; StsBadArg otherwise:
    cv::linemod hands it to sprintf). writeClasses replaces existing files, as cv::linemod's does,
    but never writes through a dangling symbolic link. */
    CV_WRAP void readClasses(const std::vector<String>& class_ids,
                             const String& format = "templates_%s.yml.gz");
    CV_WRAP void writeClasses(const String& format = "templates_%s.yml.gz") const;

    /** Whole model (modalities, pyramid, params, templates with poses, trained forest) to one
    file (.yml, .yml.gz, .json). Refuses to overwrite an existing file unless overwrite is true,
    and, writing nothing, a model of more than 1 GiB of text, which load() would not read (the
    8 LM-O objects' 16 968 RGB-D templates in one model take 0.97 GB with 1 tree, 2.9 GB with
    5: the forests' rejectors and the templates' features are most of it). */
    CV_WRAP void save(const String& filename, bool overwrite = false) const;
    /** Loads a model written by save(); a corrupt file, another format version or an unknown
    modality raises cv::Exception and leaves the detector as it was (the file is read whole
    before it replaces anything). The meshes set with setMesh() stay. */
    CV_WRAP void load(const String& filename);

private:
    Ptr<detail::DetectorImpl> impl_;
};

/** @brief Sorts matches (stably) by similarity - weight x PoseMatch::background, best first: the
order Detector::detect() gives its matches before NMS and the pose stage
(VerificationParams::background_weight). Every match needs its background
(Detector::backgroundSimilarity); raises StsBadArg otherwise, StsOutOfRange for a negative or
non-finite weight. */
CV_EXPORTS void orderByBackground(std::vector<PoseMatch>& matches, double weight);

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
