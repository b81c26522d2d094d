// This file is part of OpenCV project.
// It is subject to the license terms in the LICENSE file found in the top-level directory
// of this distribution and at http://opencv.org/license.html

// Pose of a match: initial pose from the template, depth check, pose error measures
// (ADD / ADI of Hinterstoisser et al. ACCV 2012, 2D projection error, box IoU).
// ICP refinement is in icp.cpp.

#include "precomp.hpp"
#include "pose_refine.hpp"
#include "opencv2/calib3d.hpp"

#include <limits>

namespace cv {
namespace forestmod {

namespace detail {
void checkIntrinsics(const Matx33d& K, const char* func, const char* name)
{
    bool finite = true;
    for (int i = 0; i < 9; ++i)
        finite = finite && std::isfinite(K.val[i]);
    if (!finite || !(K(0, 0) > 0 && K(1, 1) > 0) || std::abs(K(2, 2) - 1.0) > 1e-9
        || K(2, 0) != 0 || K(2, 1) != 0 || K(1, 0) != 0)
        CV_Error_(Error::StsBadArg,
                  ("%s: %s is not a pinhole intrinsic matrix [fx s cx; 0 fy cy; 0 0 1] of finite "
                   "entries with fx, fy > 0", func, name));
}

void checkPose(const Matx33d& R, const Vec3d& t, const char* func, const char* name, int code)
{
    bool finite = std::isfinite(t[0]) && std::isfinite(t[1]) && std::isfinite(t[2]);
    for (int i = 0; i < 9; ++i)
        finite = finite && std::isfinite(R.val[i]);
    if (!finite)
        CV_Error_(code, ("%s: %s has entries that are not finite", func, name));
    const double err = norm(R * R.t() - Matx33d::eye(), NORM_INF), det = determinant(R);
    if (!(err <= 1e-2) || !(det > 0))
        CV_Error_(code, ("%s: %s is not a rotation (|R R^T - I| = %g, det = %g)", func, name, err,
                         det));
}
} // namespace detail
using detail::checkIntrinsics;
using detail::checkPose;

static Vec3d pixelRay(const Matx33d& K, const Point2d& px)
{
    Vec3d r = K.inv() * Vec3d(px.x, px.y, 1.0);
    return r / norm(r);
}

void initialPose(const Matx33d& R_t, const Vec3d& t_t, const Matx33d& K_t,
                 const Point2d& template_px, const Matx33d& K_s, const Point2d& scene_px,
                 double scene_depth_mm, Matx33d& R, Vec3d& t)
{
    checkIntrinsics(K_t, "initialPose", "K_t");
    checkIntrinsics(K_s, "initialPose", "K_s");
    checkPose(R_t, t_t, "initialPose", "the template's pose (R_t, t_t)");
    if (!(t_t[2] > 0))
        CV_Error(Error::StsBadArg, "initialPose: the template's object centre must be in front of "
                                   "its camera (t_t[2] > 0)");
    if (!(std::isfinite(template_px.x) && std::isfinite(template_px.y)
          && std::isfinite(scene_px.x) && std::isfinite(scene_px.y)
          && std::isfinite(scene_depth_mm)))
        CV_Error(Error::StsBadArg, "initialPose: pixel positions and depth must be finite");

    // Q: the smallest rotation taking the template's viewing ray to the scene's.
    const Vec3d a = pixelRay(K_t, template_px), b = pixelRay(K_s, scene_px);
    const Vec3d axis = a.cross(b);
    const double s = norm(axis), c = a.dot(b);
    Matx33d Q = Matx33d::eye();
    if (s > 1e-12)
    {
        const Vec3d rvec = axis * (std::atan2(s, c) / s);
        Rodrigues(rvec, Q);
    }
    R = Q * R_t;
    const Vec3d tq = Q * t_t;
    if (scene_depth_mm > 0)
    {
        if (!(tq[2] > 1e-9))
            CV_Error(Error::StsBadArg, "initialPose: the object centre is not in front of the scene "
                                       "camera after the off-axis correction");
        t = tq * (scene_depth_mm / tq[2]);
    }
    else
    {
        const double f_t = std::sqrt(K_t(0, 0) * K_t(1, 1));
        const double f_s = std::sqrt(K_s(0, 0) * K_s(1, 1));
        t = tq * (f_s / f_t);
    }
}

static Mat getDepth16(InputArray depth, const char* func, const char* name)
{
    Mat d = depth.getMat();
    if (d.empty())
        CV_Error_(Error::StsBadArg, ("%s: %s is empty", func, name));
    if (d.type() != CV_16UC1)
        CV_Error_(Error::StsUnsupportedFormat,
                  ("%s: %s must be CV_16UC1 (millimetres), got %s", func, name,
                   typeToString(d.type()).c_str()));
    return d;
}

double sceneDepthFromFeatures(InputArray scene_depth, const std::vector<Point>& scene_positions,
                              const std::vector<float>& template_depths,
                              double template_center_depth, int min_valid)
{
    Mat d = getDepth16(scene_depth, "sceneDepthFromFeatures", "scene_depth");
    if (scene_positions.size() != template_depths.size())
        CV_Error_(Error::StsBadSize,
                  ("sceneDepthFromFeatures: %d positions but %d template depths",
                   (int)scene_positions.size(), (int)template_depths.size()));
    if (!(template_center_depth > 0) || !std::isfinite(template_center_depth))
        CV_Error(Error::StsBadArg, "sceneDepthFromFeatures: template_center_depth must be finite "
                                   "and > 0");
    std::vector<double> z;
    z.reserve(scene_positions.size());
    const Rect img(0, 0, d.cols, d.rows);
    for (size_t i = 0; i < scene_positions.size(); ++i)
    {
        const Point& p = scene_positions[i];
        if (!img.contains(p) || !(template_depths[i] > 0))
            continue;
        const ushort s = d.at<ushort>(p);
        if (s == 0)
            continue;
        z.push_back(template_center_depth + (double)s - (double)template_depths[i]);
    }
    if ((int)z.size() < std::max(1, min_valid))
        return 0.0;
    const size_t m = z.size() / 2;
    std::nth_element(z.begin(), z.begin() + m, z.end());
    double med = z[m];
    if (z.size() % 2 == 0)
        med = 0.5 * (med + *std::max_element(z.begin(), z.begin() + m));
    return med > 0 ? med : 0.0;
}

std::vector<Point3f> modelPointsFromDepth(InputArray depth, const Matx33d& K, const Matx33d& R,
                                          const Vec3d& t, int step)
{
    Mat d = getDepth16(depth, "modelPointsFromDepth", "depth");
    checkIntrinsics(K, "modelPointsFromDepth", "K");
    CV_CheckGE(step, 1, "modelPointsFromDepth: step must be >= 1");
    checkPose(R, t, "modelPointsFromDepth", "the pose (R, t)");
    const Matx33d Kinv = K.inv(), Rt = R.t();
    std::vector<Point3f> pts;
    for (int y = 0; y < d.rows; y += step)
    {
        const ushort* row = d.ptr<ushort>(y);
        for (int x = 0; x < d.cols; x += step)
        {
            if (!row[x])
                continue;
            const Vec3d c = (Kinv * Vec3d(x, y, 1.0)) * (double)row[x];
            const Vec3d m = Rt * (c - t);
            pts.push_back(Point3f((float)m[0], (float)m[1], (float)m[2]));
        }
    }
    return pts;
}

double depthAgreement(InputArray rendered_depth, InputArray scene_depth, double tolerance_mm)
{
    Mat r = getDepth16(rendered_depth, "depthAgreement", "rendered_depth");
    Mat s = getDepth16(scene_depth, "depthAgreement", "scene_depth");
    if (r.size() != s.size())
        CV_Error_(Error::StsBadSize,
                  ("depthAgreement: rendered_depth is %dx%d but scene_depth is %dx%d", r.cols,
                   r.rows, s.cols, s.rows));
    if (!(tolerance_mm > 0))
        CV_Error(Error::StsBadArg, "depthAgreement: tolerance_mm must be > 0");
    int64 valid = 0, agree = 0;
    for (int y = 0; y < r.rows; ++y)
    {
        const ushort* pr = r.ptr<ushort>(y);
        const ushort* ps = s.ptr<ushort>(y);
        for (int x = 0; x < r.cols; ++x)
        {
            if (!pr[x] || !ps[x])
                continue;
            ++valid;
            if (std::abs((int)pr[x] - (int)ps[x]) <= tolerance_mm)
                ++agree;
        }
    }
    return valid ? (double)agree / (double)valid : 0.0;
}

// The model points moved by (R, t); false when one of them is not finite (a non-finite pose, or
// entries so large that the products overflow).
static bool movedPoints(const std::vector<Point3f>& pts, const Matx33d& R, const Vec3d& t,
                        std::vector<Vec3d>& out)
{
    out.resize(pts.size());
    bool finite = true;
    for (size_t i = 0; i < pts.size(); ++i)
    {
        out[i] = R * Vec3d(pts[i].x, pts[i].y, pts[i].z) + t;
        finite = finite && std::isfinite(out[i][0]) && std::isfinite(out[i][1])
                 && std::isfinite(out[i][2]);
    }
    return finite;
}

// The model points under the ground truth and the estimate: the ground truth must move every
// point to a finite one (StsBadArg; adiError's k-d tree needs an order); false when the estimate
// does not (the error is NaN then).
static bool movedByBoth(const std::vector<Point3f>& pts, const Matx33d& R_est, const Vec3d& t_est,
                        const Matx33d& R_gt, const Vec3d& t_gt, std::vector<Vec3d>& est,
                        std::vector<Vec3d>& gt, const char* func)
{
    if (pts.empty())
        CV_Error_(Error::StsBadArg, ("%s: no model points", func));
    if (!movedPoints(pts, R_gt, t_gt, gt))
        CV_Error_(Error::StsBadArg, ("%s: a model point moved by the ground-truth pose is not "
                                     "finite", func));
    return movedPoints(pts, R_est, t_est, est);
}

double addError(const std::vector<Point3f>& pts, const Matx33d& R_est, const Vec3d& t_est,
                const Matx33d& R_gt, const Vec3d& t_gt)
{
    std::vector<Vec3d> est, gt;
    if (!movedByBoth(pts, R_est, t_est, R_gt, t_gt, est, gt, "addError"))
        return std::numeric_limits<double>::quiet_NaN();
    double sum = 0;
    for (size_t i = 0; i < pts.size(); ++i)
        sum += norm(est[i] - gt[i]);
    return sum / (double)pts.size();
}

namespace {

/** Exact nearest neighbour in 3D: an implicit, balanced k-d tree over a permutation of the points
(median split, axis of largest extent, buckets of up to 8 points at the leaves). */
class KdTree3
{
public:
    explicit KdTree3(const std::vector<Vec3d>& pts) : p_(pts), axis_(pts.size(), 0)
    {
        idx_.resize(pts.size());
        for (size_t i = 0; i < idx_.size(); ++i)
            idx_[i] = (int)i;
        build(0, (int)idx_.size());
    }

    /** Squared distance to the nearest point. */
    double nearest2(const Vec3d& q) const
    {
        double best = std::numeric_limits<double>::max();
        search(0, (int)idx_.size(), q, best);
        return best;
    }

private:
    enum { kLeaf = 8 };

    void build(int lo, int hi)
    {
        if (hi - lo <= kLeaf)
            return;
        Vec3d mn = p_[idx_[lo]], mx = mn;
        for (int i = lo + 1; i < hi; ++i)
            for (int k = 0; k < 3; ++k)
            {
                mn[k] = std::min(mn[k], p_[idx_[i]][k]);
                mx[k] = std::max(mx[k], p_[idx_[i]][k]);
            }
        const Vec3d ext = mx - mn;
        const int ax = ext[0] >= ext[1] ? (ext[0] >= ext[2] ? 0 : 2) : (ext[1] >= ext[2] ? 1 : 2);
        const int mid = (lo + hi) / 2;
        const std::vector<Vec3d>& P = p_;
        std::nth_element(idx_.begin() + lo, idx_.begin() + mid, idx_.begin() + hi,
                         [&P, ax](int a, int b) { return P[a][ax] < P[b][ax]; });
        axis_[mid] = (uchar)ax;
        build(lo, mid);
        build(mid + 1, hi);
    }

    void search(int lo, int hi, const Vec3d& q, double& best) const
    {
        if (hi - lo <= kLeaf)
        {
            for (int i = lo; i < hi; ++i)
            {
                const Vec3d d = p_[idx_[i]] - q;
                best = std::min(best, d.dot(d));
            }
            return;
        }
        const int mid = (lo + hi) / 2;
        const Vec3d& pm = p_[idx_[mid]];
        const Vec3d d = pm - q;
        best = std::min(best, d.dot(d));
        const int ax = axis_[mid];
        const double diff = q[ax] - pm[ax];
        if (diff < 0)
        {
            search(lo, mid, q, best);
            if (diff * diff < best)
                search(mid + 1, hi, q, best);
        }
        else
        {
            search(mid + 1, hi, q, best);
            if (diff * diff < best)
                search(lo, mid, q, best);
        }
    }

    const std::vector<Vec3d>& p_;
    std::vector<int> idx_;
    std::vector<uchar> axis_;
};

} // namespace

double adiError(const std::vector<Point3f>& pts, const Matx33d& R_est, const Vec3d& t_est,
                const Matx33d& R_gt, const Vec3d& t_gt)
{
    std::vector<Vec3d> est, gt;
    if (!movedByBoth(pts, R_est, t_est, R_gt, t_gt, est, gt, "adiError"))
        return std::numeric_limits<double>::quiet_NaN();
    KdTree3 tree(gt);
    // the queries are independent: sum per stripe, then in a fixed order (deterministic)
    const int stripes = 16;
    std::vector<double> sums(stripes, 0.0);
    const int n = (int)est.size();
    parallel_for_(Range(0, stripes), [&](const Range& r) {
        for (int s = r.start; s < r.end; ++s)
        {
            double acc = 0;
            for (int i = (int)((int64)n * s / stripes); i < (int)((int64)n * (s + 1) / stripes); ++i)
                acc += std::sqrt(tree.nearest2(est[i]));
            sums[s] = acc;
        }
    });
    double sum = 0;
    for (int s = 0; s < stripes; ++s)
        sum += sums[s];
    return sum / (double)n;
}

double projectionError2D(const std::vector<Point3f>& pts, const Matx33d& K, const Matx33d& R_est,
                         const Vec3d& t_est, const Matx33d& R_gt, const Vec3d& t_gt)
{
    checkIntrinsics(K, "projectionError2D", "K");
    std::vector<Vec3d> est, gt;
    if (!movedByBoth(pts, R_est, t_est, R_gt, t_gt, est, gt, "projectionError2D"))
        return std::numeric_limits<double>::quiet_NaN();
    double sum = 0;
    for (size_t i = 0; i < pts.size(); ++i)
    {
        const Vec3d a = K * est[i];
        const Vec3d b = K * gt[i];
        if (!(a[2] > 0 && b[2] > 0))
            return std::numeric_limits<double>::infinity();
        sum += std::hypot(a[0] / a[2] - b[0] / b[2], a[1] / a[2] - b[1] / b[2]);
    }
    return sum / (double)pts.size();
}

double boxIoU(const Rect2d& a, const Rect2d& b)
{
    if (!(a.width > 0 && a.height > 0 && b.width > 0 && b.height > 0))
        return 0.0;
    const double inter = (a & b).area();
    const double uni = a.area() + b.area() - inter;
    return uni > 0 ? inter / uni : 0.0;
}

static void checkDrawing(const detail::ObjectDrawer& drawer, const Mat& scene, const char* func)
{
    if (drawer.imageSize() != scene.size())
        CV_Error_(Error::StsBadSize,
                  ("%s: the renderer makes %dx%d images but scene_depth is %dx%d", func,
                   drawer.imageSize().width, drawer.imageSize().height, scene.cols, scene.rows));
}

// K of the crop `rect` of an image: the same rays through its pixels
static Matx33d cropIntrinsics(const Matx33d& K, const Rect& rect)
{
    Matx33d Kc = K;
    Kc(0, 2) -= rect.x * K(2, 2);
    Kc(1, 2) -= rect.y * K(2, 2);
    return Kc;
}

ICPResult refinePose(Renderer& renderer, int handle, InputArray scene_depth, const Matx33d& K,
                     const Matx33d& R0, const Vec3d& t0, const ICPParams& params, int passes,
                     int step)
{
    return detail::refinePose(detail::RendererDrawer(renderer, handle), scene_depth, K, R0, t0,
                              params, passes, step);
}

double depthCheck(Renderer& renderer, int handle, InputArray scene_depth, const Matx33d& K,
                  const Matx33d& R, const Vec3d& t, double tolerance_mm)
{
    return detail::depthCheck(detail::RendererDrawer(renderer, handle), scene_depth, K, R, t,
                              tolerance_mm);
}

namespace detail {

ICPResult refinePose(const ObjectDrawer& drawer, InputArray scene_depth, const Matx33d& K,
                     const Matx33d& R0, const Vec3d& t0, const ICPParams& params, int passes,
                     int step, const SceneNormals* normals)
{
    Mat scene = getDepth16(scene_depth, "refinePose", "scene_depth");
    checkDrawing(drawer, scene, "refinePose");
    CV_CheckGE(passes, 1, "refinePose: passes must be >= 1");
    CV_CheckGE(step, 1, "refinePose: step must be >= 1");
    ICPResult res;
    res.R = R0;
    res.t = t0;
    int iterations = 0;
    for (int pass = 0; pass < passes; ++pass)
    {
        Mat depth, mask;
        Rect rect;
        drawer.draw(K, res.R, res.t, rect, depth, mask);
        std::vector<Point3f> pts;
        if (!depth.empty())
            pts = modelPointsFromDepth(depth, cropIntrinsics(K, rect), res.R, res.t, step);
        if ((int)pts.size() < params.min_correspondences)
        {
            if (pass == 0)
                res.fitness = 0;
            res.converged = false;
            break;
        }
        // the passes that bring the pose near need fewer points than the last one
        ICPParams pass_params = params;
        if (pass + 1 < passes && params.early_pass_points > 0
            && (params.max_points <= 0 || params.early_pass_points < params.max_points))
            pass_params.max_points = params.early_pass_points;
        res = normals ? refineICP(pts, scene, K, res.R, res.t, pass_params, *normals)
                      : forestmod::refineICP(pts, scene, K, res.R, res.t, pass_params);
        iterations += res.iterations;
    }
    res.iterations = iterations;
    return res;
}

double depthCheck(const ObjectDrawer& drawer, InputArray scene_depth, const Matx33d& K,
                  const Matx33d& R, const Vec3d& t, double tolerance_mm, Ptr<Drawing>* drawn)
{
    Mat scene = getDepth16(scene_depth, "depthCheck", "scene_depth");
    checkDrawing(drawer, scene, "depthCheck");
    const Ptr<Drawing> d = drawer.drawing(K, R, t);
    if (drawn)
        *drawn = d;
    const Rect rect = d->rect;
    const Mat& depth = d->depth;
    if (depth.empty())
    {
        if (!(tolerance_mm > 0))
            CV_Error(Error::StsBadArg, "depthAgreement: tolerance_mm must be > 0");
        return 0.0;
    }
    return depthAgreement(depth, scene(rect), tolerance_mm);
}

} // namespace detail

bool isCorrect(double error, double diameter, double k_m)
{
    if (!(diameter > 0))
        CV_Error(Error::StsBadArg, "isCorrect: the object diameter must be > 0");
    if (!(k_m > 0))
        CV_Error(Error::StsBadArg, "isCorrect: k_m must be > 0");
    return error < k_m * diameter;
}

} // namespace forestmod
} // namespace cv
