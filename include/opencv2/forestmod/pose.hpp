// This file is part of OpenCV project.
// It is subject to the license terms in the LICENSE file found in the top-level directory
// of this distribution and at http://opencv.org/license.html

#ifndef OPENCV_FORESTMOD_POSE_HPP
#define OPENCV_FORESTMOD_POSE_HPP

#include "opencv2/core.hpp"

#include <vector>

namespace cv {
namespace forestmod {

class Renderer; // opencv2/forestmod/render.hpp

//! @addtogroup forestmod_pose
//! @{

/* Conventions (all functions of this header):
 - a pose (R, t) maps model coordinates to camera coordinates, x_cam = R * x_model + t, as BOP's
   cam_R_m2c / cam_t_m2c; t and all points in millimetres;
 - camera axes are OpenCV's: x right, y down, z forward; K is the usual pinhole matrix and pixel
   (u, v) = (fx x / z + cx, fy y / z + cy), pixel centres at integer coordinates;
 - depth images are CV_16UC1 in millimetres, 0 = no measurement.
*/

/** @brief Parameters of refineICP(). FileStorage keys are the field names.

The defaults were chosen on the LM-O ape (diameter 102 mm) at 0.5-1 m with Kinect-like depth,
starting 5 degrees / 10 mm off (the precision of a template match); see doc/pose.md for the
measurements behind them (ablation of each choice).
*/
struct CV_EXPORTS_W_SIMPLE ICPParams
{
    CV_WRAP ICPParams();

    /** Maximum number of Gauss-Newton iterations. Default 30 (Open3D's ICPConvergenceCriteria). */
    CV_PROP_RW int max_iterations;
    /** Correspondence gate (mm) of the first iteration: a model point whose associated scene point
    is farther away than this is ignored. Must cover the initial error. Default 30 mm: a template
    match is off by up to ~10 mm and ~10 degrees (about 0.1 of a diameter at the object's rim). */
    CV_PROP_RW double max_correspondence_distance;
    /** Smallest correspondence gate (mm). After each iteration the gate shrinks to
    `gate_sigma_factor` robust standard deviations of the current 3D distances, but not below
    this value (sensor noise). Default 5 mm (Kinect depth noise is 1.5-4 mm at 0.7-1.5 m). Also
    sets the floor of the residuals' robust scale, min_correspondence_distance /
    gate_sigma_factor. */
    CV_PROP_RW double min_correspondence_distance;
    /** The correspondence gate shrinks to this many robust standard deviations
    (1.4826 x median) of the 3D distances between paired points. Default 3. */
    CV_PROP_RW double gate_sigma_factor;
    /** Tukey biweight constant, in robust standard deviations of the point-to-plane residuals:
    residuals beyond tukey_c * sigma get weight 0. Default 4.685 (95 % Gaussian efficiency). */
    CV_PROP_RW double tukey_c;
    /** Tukey constant while the correspondence gate is still above min_correspondence_distance
    (coarse phase). Default 2.5: tighter, so that a coherent group of outliers (an occluder in
    front of the object) cannot pull the pose while the inliers' residuals are still large. */
    CV_PROP_RW double tukey_c_coarse;
    /** Half size (pixels) of the window searched around the projection of a model point for the
    closest scene point; 0 = pure projective association (KinectFusion). Default 0: with noisy
    depth the closest of several candidates is biased towards the model point, which slows the
    rotation down (doc/pose.md). */
    CV_PROP_RW int search_radius;
    /** Half size (pixels) of the window in which the scene normal is fitted (PCA of the
    back-projected depth). Default 3 (7x7 pixels, about 8 mm at 0.7 m): averages sensor noise. */
    CV_PROP_RW int normal_radius;
    /** Two scene depths in the normal window are on the same surface if they differ by less than
    this (mm). Default 15. */
    CV_PROP_RW double depth_discontinuity;
    /** Convergence: stop when an iteration's update rotates by less than this (radians).
    Default 1e-4 (0.006 degrees). */
    CV_PROP_RW double rotation_epsilon;
    /** Convergence: and moves by less than this (mm). Default 0.01 mm. */
    CV_PROP_RW double translation_epsilon;
    /** Stop (not converged) after this many iterations in a row in which the correspondence
    gate, still above min_correspondence_distance, did not shrink by 0.1 % or more; 0 = never.
    Default 8. A run whose gate has stopped shrinking moves little more if it is on the object
    and wanders until max_iterations if it is not (a hypothesis on clutter): on rendered RGB-D
    scenes the stop changed no outcome and took 3-26 % off the poses' time per object
    (doc/pose.md, "Runs whose gate stalls"). */
    CV_PROP_RW int max_stalled_iterations;
    /** At most this many model points are used (evenly subsampled, deterministic); <= 0 = all.
    Default 4000 (all the visible surface of a 100 mm object at 0.5 m in VGA): the rotation of
    a roundish object is noise-limited, so fewer points cost accuracy (doc/pose.md). */
    CV_PROP_RW int max_points;
    /** refinePose(): at most this many model points in every pass but the last (those bring the
    pose near; the last pass, with max_points, sets the precision); <= 0 = max_points. Default
    1000: on rendered RGB-D scenes the same ADD to 0.1 % of a diameter, and the poses of a frame
    6-40 % faster (doc/pose.md, "Points of the first pass"). refineICP() ignores it. */
    CV_PROP_RW int early_pass_points;
    /** At least this many correspondences are needed for an update. Default 20. */
    CV_PROP_RW int min_correspondences;
    /** A model point is an inlier for ICPResult::fitness / inlier_rmse if its scene point is
    within this distance (mm). Default 5 mm: a little above sensor noise. */
    CV_PROP_RW double inlier_distance;
    /** Trust region: an iteration rotates by at most this (radians); the translation is then
    re-solved for the shortened rotation. Default 0.02 (about 1.1 degrees): the rotation of a
    roundish object is weakly constrained and a full Gauss-Newton step taken while outliers are
    still in can swing it far away. */
    CV_PROP_RW double max_rotation_step;
    /** Noise-aware weighting: depth noise is along the viewing ray, so only the share
    g = |n . ray| of it reaches a point-to-plane residual; residuals are divided by
    max(g, min_ray_cosine) (weight 1 / g^2). Default 0.5: surfaces up to 60 degrees from
    the viewing direction get their full weight, steeper ones (which hold most of the
    information on the rotation) up to 4 times more. 1 = unweighted. */
    CV_PROP_RW double min_ray_cosine;

    void read(const FileNode& fn);
    void write(FileStorage& fs) const;
};

/** @brief Result of refineICP() (after Open3D's RegistrationResult). */
struct CV_EXPORTS_W_SIMPLE ICPResult
{
    CV_WRAP ICPResult();
    /** Refined pose, model -> camera. */
    CV_PROP_RW Matx33d R;
    CV_PROP_RW Vec3d t;
    /** Share (0..1) of the (subsampled) model points with a scene point within
    ICPParams::inlier_distance at the refined pose: low under occlusion or a wrong pose. */
    CV_PROP_RW double fitness;
    /** RMS distance (mm) between inlier model points and their scene points. */
    CV_PROP_RW double inlier_rmse;
    /** Iterations run. */
    CV_PROP_RW int iterations;
    /** True when the last update was below both epsilons (ICPParams); false when the iteration
    limit was reached or too few correspondences were left (then R, t is the last good pose). */
    CV_PROP_RW bool converged;
};

/** @brief Initial pose of a match from its template.

The template shows the object at pose (R_t, t_t) seen with K_t; the pixel template_px of the
template (usually the projection of t_t, the object centre) was matched at pixel scene_px of a
scene seen with K_s. A matcher finds the template's *appearance* shifted in the image, which is the
object seen under the same angle from a different direction: the pose is the template's pose
rotated about the camera centre by the rotation Q that takes the viewing ray through template_px
(with K_t) to the ray through scene_px (with K_s): R = Q R_t (the off-axis correction, zero when
the two rays coincide), t along Q t_t.

The distance: with scene_depth_mm <= 0 (RGB only) the object keeps its apparent size, so its
distance is the template's scaled by the focal lengths, |t| = |t_t| * f_s / f_t (f = sqrt(fx fy));
with scene_depth_mm > 0 (RGB-D), t is scaled so that its z (depth of the object centre in the
scene camera) equals scene_depth_mm (see sceneDepthFromFeatures()).

@param R_t, t_t   template pose (model -> template camera), mm.
@param K_t        intrinsics the template was rendered with.
@param template_px pixel of the template placed at scene_px (any pixel works; the object centre
                  keeps the distance semantics simple).
@param K_s        intrinsics of the scene.
@param scene_px   matched pixel in the scene.
@param scene_depth_mm depth (z, mm) of the object centre in the scene, or <= 0 for RGB only.
@param R, t       initial pose in the scene camera.
*/
CV_EXPORTS void initialPose(const Matx33d& R_t, const Vec3d& t_t, const Matx33d& K_t,
                            const Point2d& template_px, const Matx33d& K_s, const Point2d& scene_px,
                            double scene_depth_mm, Matx33d& R, Vec3d& t);

/** @brief Depth of the object centre implied by the scene depth under a template's features.

Each feature i of the template lies at scene pixel scene_positions[i] (template position + match
offset) and had depth template_depths[i] (mm) when the template was rendered with its centre at
depth template_center_depth (t_t[2]). If the scene shows the object there, the scene depth s_i at
that pixel is the feature's depth in the scene, and z_i = template_center_depth + s_i -
template_depths[i] is the depth of the object centre (offset correction: the feature's depth
relative to the centre is kept). Returns the median of z_i over the features with a valid scene
depth and a valid template depth (robust to occlusion and background under up to half of the
features), or 0 when fewer than `min_valid` features have both.

@param scene_depth CV_16UC1 depth (mm) of the scene.
@param scene_positions pixels of the features in the scene (outside the image: ignored).
@param template_depths depth (mm) of the rendered template at each feature (<= 0: ignored).
@param template_center_depth depth (mm) of the object centre in the template, t_t[2].
@param min_valid minimum number of usable features (default 3).
*/
CV_EXPORTS double sceneDepthFromFeatures(InputArray scene_depth,
                                         const std::vector<Point>& scene_positions,
                                         const std::vector<float>& template_depths,
                                         double template_center_depth, int min_valid = 3);

/** @brief Model points (model coordinates) of the visible surface, back-projected from a depth
image rendered at pose (R, t) with K; every `step`-th pixel in x and y. Use it to feed refineICP()
with the template's depth or with the depth rendered at the initial pose. */
CV_EXPORTS std::vector<Point3f> modelPointsFromDepth(InputArray depth, const Matx33d& K,
                                                     const Matx33d& R, const Vec3d& t,
                                                     int step = 1);

/** @brief Robust point-to-plane ICP of model points against a depth image.

Model points (model coordinates; the visible surface, e.g. from modelPointsFromDepth(), or any
sampling of the mesh surface facing the camera) are moved by the current pose, projected into
scene_depth with K and associated with the scene point at that pixel (projective association,
KinectFusion; search_radius > 0 searches a window for the closest point). Each pair gives a
point-to-plane residual along the scene normal (PCA over the normal window). Robustness to
clutter and occlusion:
- a distance gate that starts at max_correspondence_distance and shrinks to gate_sigma_factor
  robust standard deviations of the 3D distances (never below min_correspondence_distance);
- Tukey biweights on the residuals (iteratively reweighted least squares), scale from the median
  absolute residual; a tighter constant (tukey_c_coarse) while the gate is still shrinking, so
  that a coherent group of outliers (an occluder in front of the object) cannot pull the pose;
- a trust region on the rotation (max_rotation_step), the translation re-solved for it;
- noise-aware weights (min_ray_cosine): sensor noise is along the viewing ray.
The 6x6 normal equations, linearised about the centroid of the moved points, are solved with
Eigen (LDLT); the update is applied as an exact rotation (Rodrigues). R0 may deviate slightly
from a rotation (as LM-O's ground truth does, ~1e-2): it is projected onto the closest rotation.

@param model_points  model points, mm, model coordinates (at least params.min_correspondences).
@param scene_depth   CV_16UC1 scene depth in mm (0 = invalid).
@param K             intrinsics of the scene depth.
@param R0, t0        initial pose (model -> camera).
@param params        see ICPParams.
@return the refined pose and its quality; see ICPResult.
*/
CV_EXPORTS ICPResult refineICP(const std::vector<Point3f>& model_points, InputArray scene_depth,
                               const Matx33d& K, const Matx33d& R0, const Vec3d& t0,
                               const ICPParams& params = ICPParams());

/** @brief ICP with the model's visible surface rendered at the current pose (the usual way to
refine a match).

Each pass renders the depth of mesh `handle` at the current pose with `renderer` (same size as
scene_depth, intrinsics K), back-projects it to model points (modelPointsFromDepth(), every
`step`-th pixel) and runs refineICP() from the current pose. The visible rim of the object moves
with the pose, so a second pass from the refined pose removes the bias of points that were
visible only at the starting pose (doc/pose.md: 42/50 -> 49/50 trials within 1 mm / 0.5 degree).
Every pass but the last uses at most params.early_pass_points model points.

@param renderer  a Renderer of scene_depth's size with the object's mesh uploaded.
@param handle    the mesh's handle (Renderer::addMesh()).
@param scene_depth CV_16UC1 scene depth, mm.
@param K         intrinsics of the scene.
@param R0, t0    starting pose (e.g. initialPose()).
@param params    ICP parameters.
@param passes    render + ICP passes (>= 1; default 2).
@param step      pixel step of the model points (default 1; ICPParams::max_points subsamples).
@return the result of the last pass; `iterations` counts the iterations of all passes. When the
rendered object has fewer than params.min_correspondences pixels, the starting pose is returned
with fitness 0 and converged false.
*/
CV_EXPORTS ICPResult refinePose(Renderer& renderer, int handle, InputArray scene_depth,
                                const Matx33d& K, const Matx33d& R0, const Vec3d& t0,
                                const ICPParams& params = ICPParams(), int passes = 2,
                                int step = 1);

/** @brief Parameters of the edge-based pose refinement without depth (computeEdgeMaps(),
refinePoseEdges()). FileStorage keys are the field names.

The defaults were chosen on the shipped LM-O ape frames and on rendered scenes (doc/pose.md,
"Refinement without depth"). */
struct CV_EXPORTS_W_SIMPLE EdgeRefineParams
{
    CV_WRAP EdgeRefineParams();

    /** Edge orientation bins over 180 degrees (directional chamfer, Liu et al. CVPR 2010 /
    D2CO, Imperoli and Pretto 2015). A model edge point is compared with the scene edges of its
    own bin and the two neighbouring ones, i.e. within about +-1.5 bins. Default 16 (11.25
    degrees per bin, +-17 degrees of tolerance): on rendered apes over real clutter, 8 degrees
    off, 17/20 starts end under 2 px against 16/20 with 8 bins (doc/pose.md). */
    CV_PROP_RW int orientations;
    /** Canny thresholds on the scene image (3-channel images: the strongest channel, as
    LINEMOD's ColorGradient). Defaults 30 / 80 with the L2 gradient: the weak contours of
    texture-less objects in VGA Kinect images. */
    CV_PROP_RW double canny_low;
    CV_PROP_RW double canny_high;
    /** Distances (pixels) to the nearest scene edge are truncated here: a model point farther
    from any edge of its orientation is an outlier and does not pull. Default 15 px: the
    residual error of a template match (half a template step, ~8-15 px in VGA). */
    CV_PROP_RW double max_distance;
    /** Render + optimise passes: each pass renders the object at the current pose and takes its
    contour and inner edges as model points. Default 4. */
    CV_PROP_RW int passes;
    /** Levenberg-Marquardt iterations per pass. Default 15. */
    CV_PROP_RW int iterations;
    /** At most this many model edge points per pass (evenly subsampled). Default 400. */
    CV_PROP_RW int max_points;
    /** Huber threshold (pixels) of the chamfer residuals. Default 2 px. */
    CV_PROP_RW double huber;
    /** A model point is an inlier (EdgeRefineResult::inlier_ratio) when a scene edge of its
    orientation lies within this distance (pixels). Default 2 px. */
    CV_PROP_RW double inlier_distance;
    /** Also use the object's inner edges (depth discontinuities of the rendering, i.e.
    self-occlusion contours), not only its silhouette. Default false: on the real LM-O ape
    frames they helped as often as they hurt (doc/pose.md); the rendered colour's edges are never
    used (its shading does not match the scene's). */
    CV_PROP_RW bool inner_edges;
    /** Coarse search before the refinement: the start pose turned about the camera axes
    through the object's centre on a grid of +-search_angle degrees (search_steps steps each
    way, (2 search_steps + 1)^3 rotations), scored with the start's edge points (no rendering);
    the start and the best `hypotheses` grid poses are refined and the fit with the highest
    inlier ratio is kept. 0 = no search. Default 0: on real LM-O frames (frames the evaluation
    does not report) 12 degrees and 3 steps (a 4 degree grid) gave the same recalls as no search
    for 3x the time (doc/pose.md); on rendered starts 10 degrees off it brings 18 instead of 17 of
    20 under 2 px. */
    CV_PROP_RW double search_angle;
    CV_PROP_RW int search_steps;
    /** Grid poses refined besides the start itself (>= 1). Default 3. */
    CV_PROP_RW int hypotheses;

    void read(const FileNode& fn);
    void write(FileStorage& fs) const;
};

/** @brief Directional distance maps of a scene image's edges (computeEdgeMaps()). */
struct CV_EXPORTS_W_SIMPLE EdgeMaps
{
    /** One CV_32FC1 map per orientation bin: distance (pixels) to the nearest edge whose
    orientation is in that bin or a neighbouring one, truncated at max_distance. */
    CV_PROP_RW std::vector<Mat> distance;
    /** CV_8UC1 edge image (Canny), 255 on edges. */
    CV_PROP_RW Mat edges;
    /** Truncation distance the maps were made with. */
    CV_PROP_RW double max_distance;
};

/** @brief Result of refinePoseEdges(). */
struct CV_EXPORTS_W_SIMPLE EdgeRefineResult
{
    CV_WRAP EdgeRefineResult();
    CV_PROP_RW Matx33d R; //!< refined pose, model -> camera
    CV_PROP_RW Vec3d t;
    /** Share (0..1) of the final model edge points with a scene edge of their orientation within
    EdgeRefineParams::inlier_distance: the quality of the fit, comparable across hypotheses. */
    CV_PROP_RW double inlier_ratio;
    /** Mean truncated distance (pixels) of the final model edge points to the scene edges. */
    CV_PROP_RW double mean_distance;
    /** Model edge points of the last pass (0: the object was not visible; R, t = start). */
    CV_PROP_RW int points;
    /** Levenberg-Marquardt iterations over all passes and hypotheses. */
    CV_PROP_RW int iterations;
    /** Centroid (model coordinates, mm) of the final model edge points. */
    CV_PROP_RW Vec3d center;
};

/** @brief Edges of a scene image and their directional distance maps, for refinePoseEdges().
Computed once per frame and shared by all hypotheses.
@param image CV_8UC3 (BGR) or CV_8UC1 scene image.
@param maps  output.
@param params orientations, canny_low/high, max_distance are used.
@param roi   the part of the image where hypotheses will be refined (their boxes widened by a few
             max_distance); empty = the whole image. Outside it the maps hold max_distance. A
             roi around the matches is much cheaper than the whole frame (16 distance transforms).
*/
CV_EXPORTS void computeEdgeMaps(InputArray image, EdgeMaps& maps,
                                const EdgeRefineParams& params = EdgeRefineParams(),
                                const Rect& roi = Rect());

/** @brief Pose refinement without depth: directional chamfer alignment of the object's rendered
edges with the scene's edges (D2CO-like, Imperoli and Pretto 2015).

Each pass renders mesh `handle` at the current pose, takes its silhouette (and, with
params.inner_edges, its colour edges and depth discontinuities) as model edge points, each with
its 3D position (back-projected from the rendered depth) and its gradient orientation, and
minimises with Levenberg-Marquardt the robust (Huber) sum of the points' distances to the scene
edges of their orientation (maps), over the 6 DoF (rotation about the points' centroid,
translation). The distance maps are interpolated bilinearly; their finite differences give the
Jacobian. Distances are truncated at maps.max_distance, so clutter edges farther away than that
do not pull, and the start must be within about that many pixels of the object's contour.

@param renderer renderer of the scene's size with the mesh uploaded.
@param handle   the mesh's handle.
@param maps     computeEdgeMaps() of the scene image (same size as the renderer).
@param K        intrinsics of the scene.
@param R0, t0   starting pose (e.g. initialPose() of a template match).
@param params   see EdgeRefineParams.
*/
CV_EXPORTS EdgeRefineResult refinePoseEdges(Renderer& renderer, int handle, const EdgeMaps& maps,
                                            const Matx33d& K, const Matx33d& R0,
                                            const Vec3d& t0,
                                            const EdgeRefineParams& params = EdgeRefineParams());

/** @brief depthAgreement() of the pose (R, t) of mesh `handle`, rendered with `renderer` (same
size as scene_depth). */
CV_EXPORTS double depthCheck(Renderer& renderer, int handle, InputArray scene_depth,
                             const Matx33d& K, const Matx33d& R, const Vec3d& t,
                             double tolerance_mm);

/** @brief Depth check of a pose hypothesis (LINEMOD, Hinterstoisser et al. ACCV 2012).

Share of the object's pixels (rendered_depth > 0) where the scene depth is valid and agrees with
the rendered depth within tolerance_mm. Pixels without a scene measurement (0) are left out of the
count (no evidence either way); an occluder in front of the object counts as disagreement.
Returns 0 when no object pixel has a scene measurement.

@param rendered_depth CV_16UC1 depth (mm) rendered at the hypothesis, 0 = background.
@param scene_depth    CV_16UC1 scene depth (mm), same size.
@param tolerance_mm   tolerance (> 0); ACCV12 uses a share of the object's size, e.g. 0.05 d.
*/
CV_EXPORTS double depthAgreement(InputArray rendered_depth, InputArray scene_depth,
                                 double tolerance_mm);

/** @brief ADD (Hinterstoisser et al. ACCV 2012): mean distance (mm) between the model points
moved by the estimated and by the ground-truth pose.

In addError, adiError and projectionError2D the model points (at least one) moved by the
ground-truth pose must be finite (StsBadArg); an estimated pose that moves one to a non-finite
point gives NaN, which passes no threshold. */
CV_EXPORTS double addError(const std::vector<Point3f>& pts, const Matx33d& R_est,
                           const Vec3d& t_est, const Matx33d& R_gt, const Vec3d& t_gt);

/** @brief ADI (ADD-S) for symmetric objects: mean over the estimated points of the distance to the
closest ground-truth point. Exact nearest neighbours through a 3D k-d tree (O(n log n)). */
CV_EXPORTS double adiError(const std::vector<Point3f>& pts, const Matx33d& R_est,
                           const Vec3d& t_est, const Matx33d& R_gt, const Vec3d& t_gt);

/** @brief Mean 2D distance (pixels) between the projections of the model points under the
estimated and the ground-truth pose (Brachmann et al. 2016). Returns +infinity when a point is
behind the camera (z <= 0) under either pose. */
CV_EXPORTS double projectionError2D(const std::vector<Point3f>& pts, const Matx33d& K,
                                    const Matx33d& R_est, const Vec3d& t_est,
                                    const Matx33d& R_gt, const Vec3d& t_gt);

/** @brief Intersection over union of two boxes (0 when either is empty). */
CV_EXPORTS double boxIoU(const Rect2d& a, const Rect2d& b);

/** @brief The usual pose criterion: error (ADD or ADI, mm) < k_m * diameter (k_m = 0.1). */
CV_EXPORTS bool isCorrect(double error, double diameter, double k_m = 0.1);

//! @}

} // namespace forestmod
} // namespace cv

#endif // OPENCV_FORESTMOD_POSE_HPP
