// This file is part of OpenCV project.
// It is subject to the license terms in the LICENSE file found in the top-level directory
// of this distribution and at http://opencv.org/license.html

// Internal: the pose refinements (ICP with depth, edge alignment without) and the depth check
// with the object drawn by an ObjectDrawer, e.g. on the CPU by drawMesh() without the OSMesa
// Renderer's lock, so that a frame's hypotheses refine in parallel.

#ifndef OPENCV_FORESTMOD_POSE_REFINE_HPP
#define OPENCV_FORESTMOD_POSE_REFINE_HPP

#include "opencv2/forestmod/pose.hpp"
#include "draw_mesh.hpp"

#include <atomic>
#include <memory>

namespace cv {
namespace forestmod {
namespace detail {

/** Throws a cv::Exception (StsBadArg, its message starting with `func`) unless `K`, named `name`
in the message, is a pinhole intrinsic matrix [fx s cx; 0 fy cy; 0 0 1] of finite entries with
fx, fy > 0. */
void checkIntrinsics(const Matx33d& K, const char* func, const char* name);

/** A pose (R, t) with finite entries and R a rotation (|R R^T - I| <= 1e-2, det > 0: rotations
stored with few digits, LM-O's ground truth, deviate by a few 1e-3); raises `code` naming
`func` and `name`. */
void checkPose(const Matx33d& R, const Vec3d& t, const char* func, const char* name,
               int code = Error::StsBadArg);

/** Throws a cv::Exception (its message starting with `who`) unless `maps` hold one CV_32FC1
distance map per orientation bin, each of size `image`: computeEdgeMaps() of that image with
`orientations` bins. */
void checkEdgeMaps(const EdgeMaps& maps, int orientations, Size image, const char* who);

/** The Euclidean distance of every pixel to the nearest nonzero pixel of `edges` (CV_8UC1),
exact, truncated at max_distance (> 0): dist (CV_32FC1, the size of edges) = min(distance,
max_distance); max_distance where edges has no nonzero pixel. computeEdgeMaps() makes its maps
with it: up to a max_distance of 100 px by two passes bound by the truncation (per column the
nearest edge above and below, then per row the nearest of the columns within max_distance; the
vector path 4-16 pixels at a time), beyond with cv::distanceTransform (DIST_MASK_PRECISE). */
CV_EXPORTS void truncatedDistance(const Mat& edges, double max_distance, Mat& dist);

/** refinePoseEdges() with the object drawn by `drawer`; `last` (when given) receives the drawing
at the returned pose (empty when no start was refined). */
CV_EXPORTS EdgeRefineResult refinePoseEdges(const ObjectDrawer& drawer, const EdgeMaps& maps,
                                            const Matx33d& K, const Matx33d& R0, const Vec3d& t0,
                                            const EdgeRefineParams& params,
                                            Ptr<Drawing>* last = 0);

/** A point of the drawn object's silhouette: model coordinates (mm) and the orientation bin of
its normal in the image. */
struct EdgePoint
{
    Point3d model;
    int bin;
};

/** refinePoseEdges() from one start, in steps: run() the first passes, inlierRatio() at the pose
reached, finish() the rest. PoseEstimator refines a location's hypotheses this way and lets only
the best of them go on after the first pass (PoseParams::rgb_keep). The drawer and the maps must
outlive it. */
class CV_EXPORTS EdgeFit
{
public:
    EdgeFit(const ObjectDrawer& drawer, const EdgeMaps& maps, const Matx33d& K, const Matx33d& R0,
            const Vec3d& t0, const EdgeRefineParams& params);
    /** Runs the passes up to `end` (at most params.passes; those already run are skipped). */
    void run(int end);
    /** Share of the silhouette points within params.inlier_distance of a scene edge of their
    orientation, at the pose reached (the next pass starts from those points). */
    double inlierRatio();
    /** Runs the remaining passes; the result as refinePoseEdges() gives it, and the drawing at its
    pose in *last when asked. */
    EdgeRefineResult finish(Ptr<Drawing>* last = 0);

private:
    void levenbergMarquardt(const std::vector<EdgePoint>& pts, double dmax, Vec3d c);

    const ObjectDrawer* drawer_;
    const EdgeMaps* maps_;
    Matx33d K_;
    EdgeRefineParams params_;
    EdgeRefineResult res_;
    std::vector<EdgePoint> pts_;
    int pass_;
    bool drawn_;            // pts_ taken at res_'s pose, by inlierRatio()
    Ptr<Drawing> drawing_;  // their drawing (empty when they came without one)
};

/** The scene normals of point-to-plane ICP, made where ICP asks for them and kept for the frame.

A pixel's normal is the direction of least variance of the points within ICPParams::normal_radius
whose depth lies within depth_discontinuity of the pixel's, facing the camera. Each is computed
once, at the first normal() call for its pixel, and then read: the refinements of one frame's
hypotheses share them from any thread (a thread that finds a pixel in progress in another computes
it too, the same value, without storing it). The depth image is referenced, not copied. */
class CV_EXPORTS SceneNormals
{
public:
    SceneNormals(const Mat& depth, const Matx33d& K, const ICPParams& params);
    /** False when the pixel has no normal (no depth, or fewer than a third of its neighbourhood
    within the discontinuity). */
    bool normal(int x, int y, Vec3f& n) const;
    /** normal(), and the cosine between it and the pixel's ray, |n . s| / |s| for the pixel's
    point s (point()), kept with it (ICP weighs each correspondence by it); 0 without a normal. */
    bool normal(int x, int y, Vec3f& n, double& ray_cosine) const;
    /** Whether these are the normals of `depth` (the same data), `K` and `params`. */
    bool madeFor(const Mat& depth, const Matx33d& K, const ICPParams& params) const;
    /** The camera point of pixel (x, y) of the image at depth z (mm), as back-projected through
    K (without skew: from a factor per column and per row, computed once). */
    Vec3d point(int x, int y, double z) const
    {
        return xn_.empty() ? skewedPoint(x, y, z) : Vec3d(xn_[x] * z, yn_[y] * z, z);
    }

private:
    Vec3d skewedPoint(int x, int y, double z) const; // point() with skew: the formula
    bool compute(int x, int y, Vec3f& n) const;
    bool compute(int x, int y, Vec3f& n, double& ray_cosine) const;

    Mat depth_;
    Matx33d K_;
    std::vector<double> xn_, yn_; // x / z of each column and y / z of each row; empty with skew
    int radius_;
    double discontinuity_;
    std::unique_ptr<std::atomic<uchar>[]> state_; // 0 not yet, 1 valid, 2 none, 3 in progress
    mutable Mat normals_; // CV_32FC3, written where state_ says so (not initialised)
    std::unique_ptr<double[]> cosine_; // the ray cosines, likewise
};

/** The median of ICP's robust scales: the element of rank v.size() / 2, as std::nth_element
finds it. Non-negative, finite values are counted in 256 bins of [0, max v] and nth_element runs
within the bin that holds the rank (v is left as it is); other values (or fewer than 64) go to
nth_element over all of them (v is reordered). */
CV_EXPORTS double medianOfNonNegative(std::vector<double>& v);

/** refineICP() against normals made for the same depth image, intrinsics and parameters. */
CV_EXPORTS ICPResult refineICP(const std::vector<Point3f>& model_points, const Mat& scene_depth,
                               const Matx33d& K, const Matx33d& R0, const Vec3d& t0,
                               const ICPParams& params, const SceneNormals& normals);

/** refinePose() (render, back-project, ICP; `passes` times) with the object drawn by
`drawer`; with `normals` (made for this scene, K and params) its ICP reads them. */
CV_EXPORTS ICPResult refinePose(const ObjectDrawer& drawer, InputArray scene_depth,
                                const Matx33d& K, const Matx33d& R0, const Vec3d& t0,
                                const ICPParams& params, int passes, int step = 1,
                                const SceneNormals* normals = 0);

/** depthCheck() with the object drawn by `drawer`; `drawn` (when given) receives the drawing. */
CV_EXPORTS double depthCheck(const ObjectDrawer& drawer, InputArray scene_depth, const Matx33d& K,
                             const Matx33d& R, const Vec3d& t, double tolerance_mm,
                             Ptr<Drawing>* drawn = 0);

} // namespace detail
} // namespace forestmod
} // namespace cv

#endif
