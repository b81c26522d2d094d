// This file is part of OpenCV project.
// It is subject to the license terms in the LICENSE file found in the top-level directory
// of this distribution and at http://opencv.org/license.html

// Robust point-to-plane ICP of model points against a depth image (pose refinement of a match).
// Projective association with a local search, scene normals by PCA, a shrinking distance gate and
// Tukey biweights (IRLS); 6x6 normal equations solved with Eigen. See doc/pose.md.

#include "precomp.hpp"
#include "params_io.hpp"
#include "pose_refine.hpp"
#include "opencv2/calib3d.hpp"

#include <Eigen/Core>
#include <Eigen/Dense>

namespace cv {
namespace forestmod {

ICPParams::ICPParams()
    : max_iterations(30), max_correspondence_distance(30.0), min_correspondence_distance(5.0),
      gate_sigma_factor(3.0), tukey_c(4.685), tukey_c_coarse(2.5), search_radius(0), normal_radius(3),
      depth_discontinuity(15.0), rotation_epsilon(1e-4), translation_epsilon(0.01),
      max_stalled_iterations(8), max_points(4000), early_pass_points(1000),
      min_correspondences(20), inlier_distance(5.0), max_rotation_step(0.02), min_ray_cosine(0.5)
{
}

void ICPParams::read(const FileNode& fn)
{
    detail::readField(fn, "max_iterations", max_iterations);
    detail::readField(fn, "max_correspondence_distance", max_correspondence_distance);
    detail::readField(fn, "min_correspondence_distance", min_correspondence_distance);
    detail::readField(fn, "gate_sigma_factor", gate_sigma_factor);
    detail::readField(fn, "tukey_c", tukey_c);
    detail::readField(fn, "tukey_c_coarse", tukey_c_coarse);
    detail::readField(fn, "search_radius", search_radius);
    detail::readField(fn, "normal_radius", normal_radius);
    detail::readField(fn, "depth_discontinuity", depth_discontinuity);
    detail::readField(fn, "rotation_epsilon", rotation_epsilon);
    detail::readField(fn, "translation_epsilon", translation_epsilon);
    detail::readField(fn, "max_stalled_iterations", max_stalled_iterations);
    detail::readField(fn, "max_points", max_points);
    detail::readField(fn, "early_pass_points", early_pass_points);
    detail::readField(fn, "min_correspondences", min_correspondences);
    detail::readField(fn, "inlier_distance", inlier_distance);
    detail::readField(fn, "max_rotation_step", max_rotation_step);
    detail::readField(fn, "min_ray_cosine", min_ray_cosine);
}

void ICPParams::write(FileStorage& fs) const
{
    fs << "max_iterations" << max_iterations;
    fs << "max_correspondence_distance" << max_correspondence_distance;
    fs << "min_correspondence_distance" << min_correspondence_distance;
    fs << "gate_sigma_factor" << gate_sigma_factor;
    fs << "tukey_c" << tukey_c;
    fs << "tukey_c_coarse" << tukey_c_coarse;
    fs << "search_radius" << search_radius;
    fs << "normal_radius" << normal_radius;
    fs << "depth_discontinuity" << depth_discontinuity;
    fs << "rotation_epsilon" << rotation_epsilon;
    fs << "translation_epsilon" << translation_epsilon;
    fs << "max_stalled_iterations" << max_stalled_iterations;
    fs << "max_points" << max_points;
    fs << "early_pass_points" << early_pass_points;
    fs << "min_correspondences" << min_correspondences;
    fs << "inlier_distance" << inlier_distance;
    fs << "max_rotation_step" << max_rotation_step;
    fs << "min_ray_cosine" << min_ray_cosine;
}

ICPResult::ICPResult()
    : R(Matx33d::eye()), t(0, 0, 0), fitness(0), inlier_rmse(0), iterations(0), converged(false)
{
}

static void checkParams(const ICPParams& p)
{
    CV_CheckGE(p.max_iterations, 1, "refineICP: max_iterations must be >= 1");
    CV_Check(p.max_correspondence_distance, p.max_correspondence_distance > 0,
             "refineICP: max_correspondence_distance must be > 0");
    CV_Check(p.min_correspondence_distance,
             p.min_correspondence_distance > 0
                 && p.min_correspondence_distance <= p.max_correspondence_distance,
             "refineICP: min_correspondence_distance must be in (0, max_correspondence_distance]");
    CV_Check(p.gate_sigma_factor, p.gate_sigma_factor > 0,
             "refineICP: gate_sigma_factor must be > 0");
    CV_Check(p.tukey_c, p.tukey_c > 0, "refineICP: tukey_c must be > 0");
    CV_Check(p.tukey_c_coarse, p.tukey_c_coarse > 0, "refineICP: tukey_c_coarse must be > 0");
    CV_CheckGE(p.search_radius, 0, "refineICP: search_radius must be >= 0");
    CV_CheckGE(p.normal_radius, 1, "refineICP: normal_radius must be >= 1");
    CV_Check(p.depth_discontinuity, p.depth_discontinuity > 0,
             "refineICP: depth_discontinuity must be > 0");
    CV_Check(p.rotation_epsilon, p.rotation_epsilon >= 0,
             "refineICP: rotation_epsilon must be >= 0");
    CV_Check(p.translation_epsilon, p.translation_epsilon >= 0,
             "refineICP: translation_epsilon must be >= 0");
    CV_CheckGE(p.max_stalled_iterations, 0, "refineICP: max_stalled_iterations must be >= 0");
    CV_CheckGE(p.min_correspondences, 6, "refineICP: min_correspondences must be >= 6");
    CV_Check(p.inlier_distance, p.inlier_distance > 0, "refineICP: inlier_distance must be > 0");
    CV_Check(p.max_rotation_step, p.max_rotation_step > 0,
             "refineICP: max_rotation_step must be > 0");
    CV_Check(p.min_ray_cosine, p.min_ray_cosine > 0 && p.min_ray_cosine <= 1,
             "refineICP: min_ray_cosine must be in (0, 1]");
}

namespace {

/** Pixel (x, y) with depth z (mm) back-projected through the pinhole K (with skew). */
static inline Vec3d backProject(const Matx33d& K, int x, int y, double z)
{
    const double yn = (y - K(1, 2)) / K(1, 1);
    const double xn = (x - K(0, 2) - K(0, 1) * yn) / K(0, 0);
    return Vec3d(xn * z, yn * z, z);
}

/** The scene depth image seen as a point cloud, with the frame's normals. */
class SceneCloud
{
public:
    SceneCloud(const Mat& depth, const Matx33d& K, const detail::SceneNormals& normals)
        : depth_(depth), K_(K), normals_(normals)
    {
    }

    int rows() const { return depth_.rows; }
    int cols() const { return depth_.cols; }

    Vec3d point(int x, int y, double z) const { return normals_.point(x, y, z); }

    ushort depth(int x, int y) const { return depth_.at<ushort>(y, x); }

    bool project(const Vec3d& q, Point& px) const
    {
        if (q[2] <= 1e-6)
            return false;
        const double u = K_(0, 0) * q[0] / q[2] + K_(0, 1) * q[1] / q[2] + K_(0, 2);
        const double v = K_(1, 1) * q[1] / q[2] + K_(1, 2);
        if (!(u > -0.5 && v > -0.5 && u < depth_.cols - 0.5 && v < depth_.rows - 0.5))
            return false;
        px = Point(cvRound(u), cvRound(v));
        return true;
    }

    /** Unit normal at pixel (x, y) facing the camera; false when it cannot be estimated. */
    bool normal(int x, int y, Vec3f& n, double& ray_cosine) const
    {
        return normals_.normal(x, y, n, ray_cosine);
    }

private:
    const Mat& depth_;
    Matx33d K_;
    const detail::SceneNormals& normals_;
};

struct Correspondence
{
    Vec3d q;  // model point moved by the current pose (camera frame)
    Vec3d s;  // scene point
    Vec3d n;  // scene normal
    double r; // point-to-plane residual n.(q - s)
    double d; // 3D distance |q - s|
    double g; // |n . ray|: how much of the sensor's (axial) noise reaches r
};

/** Closest scene point to q in the (2 radius + 1)^2 window around its projection. */
static bool associate(const SceneCloud& cloud, const Vec3d& q, int radius, double gate,
                      Point& best_px, Vec3d& best_s, double& best_d2)
{
    Point px;
    if (!cloud.project(q, px))
        return false;
    best_d2 = gate * gate;
    bool found = false;
    for (int y = std::max(0, px.y - radius); y <= std::min(cloud.rows() - 1, px.y + radius); ++y)
        for (int x = std::max(0, px.x - radius); x <= std::min(cloud.cols() - 1, px.x + radius);
             ++x)
        {
            const ushort z = cloud.depth(x, y);
            if (!z)
                continue;
            const Vec3d s = cloud.point(x, y, z);
            const Vec3d d = s - q;
            const double d2 = d.dot(d);
            if (d2 <= best_d2)
            {
                best_d2 = d2;
                best_s = s;
                best_px = Point(x, y);
                found = true;
            }
        }
    return found;
}

} // namespace

namespace detail {

// Binning v * (256 / max) is monotonic, so the bin that holds the rank holds the value that
// nth_element would put there; nth_element then runs among that bin's values only (over every
// value it took a tenth of detect()'s time with depth). Few values (or a value that is not
// non-negative and finite): nth_element itself.
double medianOfNonNegative(std::vector<double>& v)
{
    CV_Assert(!v.empty());
    const size_t m = v.size() / 2;
    double hi = 0;
    bool binnable = v.size() >= 64;
    for (size_t i = 0; i < v.size(); ++i)
    {
        hi = std::max(hi, v[i]);
        binnable &= v[i] >= 0; // not for a negative value or NaN
    }
    if (!(binnable && hi > 0 && hi < DBL_MAX))
    {
        std::nth_element(v.begin(), v.begin() + m, v.end());
        return v[m];
    }
    const int bins = 256;
    const double scale = bins / hi;
    int count[bins] = { 0 };
    for (size_t i = 0; i < v.size(); ++i)
        count[std::min(bins - 1, (int)(v[i] * scale))]++;
    int bin = 0;
    size_t below = 0; // values in the bins before `bin`
    while (below + count[bin] <= m)
        below += count[bin++];
    static thread_local std::vector<double> bin_values;
    bin_values.clear();
    for (size_t i = 0; i < v.size(); ++i)
        if (std::min(bins - 1, (int)(v[i] * scale)) == bin)
            bin_values.push_back(v[i]);
    std::nth_element(bin_values.begin(), bin_values.begin() + (m - below), bin_values.end());
    return bin_values[m - below];
}

SceneNormals::SceneNormals(const Mat& depth, const Matx33d& K, const ICPParams& params)
    : depth_(depth), K_(K), radius_(params.normal_radius),
      discontinuity_(params.depth_discontinuity)
{
    CV_CheckType(depth.type(), depth.type() == CV_16UC1 && !depth.empty(),
                 "SceneNormals: the depth image must be a non-empty CV_16UC1 image (mm)");
    state_.reset(new std::atomic<uchar>[depth.total()]());
    normals_.create(depth.size(), CV_32FC3); // only read where computed: not filled
    cosine_.reset(new double[depth.total()]); // likewise
    // backProject's per-row and per-column factors (the same operations, so the same values:
    // without skew a column's factor does not depend on the row)
    if (K(0, 1) == 0)
    {
        yn_.resize(depth.rows);
        xn_.resize(depth.cols);
        for (int y = 0; y < depth.rows; ++y)
            yn_[y] = (y - K(1, 2)) / K(1, 1);
        for (int x = 0; x < depth.cols; ++x)
            xn_[x] = (x - K(0, 2) - K(0, 1) * yn_[0]) / K(0, 0);
    }
}

Vec3d SceneNormals::skewedPoint(int x, int y, double z) const
{
    return backProject(K_, x, y, z);
}

bool SceneNormals::madeFor(const Mat& depth, const Matx33d& K, const ICPParams& params) const
{
    return depth.data == depth_.data && depth.size() == depth_.size()
           && depth.step == depth_.step && K == K_ && params.normal_radius == radius_
           && params.depth_discontinuity == discontinuity_;
}

bool SceneNormals::normal(int x, int y, Vec3f& n) const
{
    double ray_cosine;
    return normal(x, y, n, ray_cosine);
}

bool SceneNormals::normal(int x, int y, Vec3f& n, double& ray_cosine) const
{
    const size_t i = (size_t)y * depth_.cols + x;
    std::atomic<uchar>& st = state_[i];
    uchar s = st.load(std::memory_order_acquire);
    Vec3f& stored = normals_.ptr<Vec3f>()[i];
    if (s == 1 || s == 2)
    {
        n = stored;
        ray_cosine = cosine_[i];
        return s == 1;
    }
    if (s == 0 && st.compare_exchange_strong(s, 3, std::memory_order_acq_rel))
    {
        const bool ok = compute(x, y, n, ray_cosine);
        stored = n;
        cosine_[i] = ray_cosine;
        st.store(ok ? 1 : 2, std::memory_order_release);
        return ok;
    }
    // in progress in another thread: the same values, not stored
    return compute(x, y, n, ray_cosine);
}

bool SceneNormals::compute(int x, int y, Vec3f& n, double& ray_cosine) const
{
    ray_cosine = 0;
    if (!compute(x, y, n))
        return false;
    const Vec3d s = point(x, y, depth_.at<ushort>(y, x));
    ray_cosine = std::abs(Vec3d(n[0], n[1], n[2]).dot(s)) / cv::norm(s);
    return true;
}

bool SceneNormals::compute(int x, int y, Vec3f& n) const
{
    n = Vec3f(0, 0, 0);
    const double zc = depth_.at<ushort>(y, x);
    if (zc <= 0)
        return false;
    const int r = radius_;
    // the sums of the points and of their outer products (the upper triangle: e_i e_j = e_j e_i)
    double sx = 0, sy = 0, sz = 0, sxx = 0, sxy = 0, sxz = 0, syy = 0, syz = 0, szz = 0;
    int cnt = 0;
    for (int yy = std::max(0, y - r); yy <= std::min(depth_.rows - 1, y + r); ++yy)
    {
        const ushort* row = depth_.ptr<ushort>(yy);
        for (int xx = std::max(0, x - r); xx <= std::min(depth_.cols - 1, x + r); ++xx)
        {
            const double z = row[xx];
            if (z <= 0 || std::abs(z - zc) > discontinuity_)
                continue;
            const Vec3d p = point(xx, yy, z);
            sx += p[0];
            sy += p[1];
            sz += p[2];
            sxx += p[0] * p[0];
            sxy += p[0] * p[1];
            sxz += p[0] * p[2];
            syy += p[1] * p[1];
            syz += p[1] * p[2];
            szz += p[2] * p[2];
            ++cnt;
        }
    }
    const int side = 2 * r + 1;
    if (cnt < std::max(5, side * side / 3))
        return false;
    Eigen::Matrix3d S;
    S << sxx, sxy, sxz, sxy, syy, syz, sxz, syz, szz;
    Eigen::Vector3d m(sx, sy, sz);
    m /= cnt;
    const Eigen::Matrix3d C = S / cnt - m * m.transpose();
    Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> es;
    es.computeDirect(C);
    Eigen::Vector3d e = es.eigenvectors().col(0); // smallest eigenvalue first
    if (!(e.allFinite()) || e.norm() < 0.5)
        return false;
    e.normalize();
    if (e.dot(m) > 0) // face the camera
        e = -e;
    n = Vec3f((float)e[0], (float)e[1], (float)e[2]);
    return true;
}

} // namespace detail

// The inputs of refineICP checked; returns R0 projected onto the closest rotation (ground-truth
// rotations of some datasets, LM-O, are orthonormal to a few 1e-3 only).
static Matx33d checkICPInputs(const std::vector<Point3f>& model_points, const Mat& depth,
                              const Matx33d& K, const Matx33d& R0, const Vec3d& t0,
                              const ICPParams& params)
{
    checkParams(params);
    if (depth.empty())
        CV_Error(Error::StsBadArg, "refineICP: scene_depth is empty");
    if (depth.type() != CV_16UC1)
        CV_Error_(Error::StsUnsupportedFormat,
                  ("refineICP: scene_depth must be CV_16UC1 (millimetres), got %s",
                   typeToString(depth.type()).c_str()));
    detail::checkIntrinsics(K, "refineICP", "K");
    if ((int)model_points.size() < params.min_correspondences)
        CV_Error_(Error::StsBadArg,
                  ("refineICP: %d model points, at least min_correspondences = %d are needed",
                   (int)model_points.size(), params.min_correspondences));
    bool finite = std::isfinite(t0[0]) && std::isfinite(t0[1]) && std::isfinite(t0[2]);
    for (int i = 0; i < 9; ++i)
        finite = finite && std::isfinite(R0.val[i]);
    if (!finite)
        CV_Error(Error::StsBadArg, "refineICP: R0 and t0 must be finite");
    for (size_t i = 0; i < model_points.size(); ++i)
        if (!(std::isfinite(model_points[i].x) && std::isfinite(model_points[i].y)
              && std::isfinite(model_points[i].z)))
            CV_Error_(Error::StsBadArg, ("refineICP: model point %d is not finite", (int)i));
    Mat Rm(R0);
    if (!(std::abs(determinant(Rm) - 1.0) < 0.1 && norm(Rm * Rm.t(), Mat::eye(3, 3, CV_64F)) < 0.1))
        CV_Error(Error::StsBadArg, "refineICP: R0 is not a rotation matrix");
    SVD svd(Rm);
    Mat Rp = svd.u * svd.vt;
    Matx33d R0n;
    Rp.copyTo(Mat(3, 3, CV_64F, R0n.val));
    return R0n;
}

// Deterministic, even subsampling of the model points.
static std::vector<Vec3d> subsample(const std::vector<Point3f>& model_points, int max_points)
{
    const size_t n_all = model_points.size();
    const size_t n = (max_points > 0 && n_all > (size_t)max_points) ? (size_t)max_points : n_all;
    std::vector<Vec3d> pts;
    pts.reserve(n);
    for (size_t i = 0; i < n; ++i)
    {
        const Point3f& p = model_points[n == n_all ? i : (size_t)((double)i * n_all / n)];
        pts.push_back(Vec3d(p.x, p.y, p.z));
    }
    return pts;
}

static void correspondences(const SceneCloud& cloud, const std::vector<Vec3d>& pts,
                            const Matx33d& R, const Vec3d& t, double gate,
                            const ICPParams& params, std::vector<Correspondence>& corr)
{
    corr.clear();
    for (size_t i = 0; i < pts.size(); ++i)
    {
        Correspondence c;
        c.q = R * pts[i] + t;
        Point px;
        double d2;
        if (!associate(cloud, c.q, params.search_radius, gate, px, c.s, d2))
            continue;
        Vec3f nf;
        double ray_cosine; // |n . s| / |s|, kept with the pixel's normal (c.s is its point)
        if (!cloud.normal(px.x, px.y, nf, ray_cosine))
            continue;
        c.n = Vec3d(nf[0], nf[1], nf[2]);
        c.r = c.n.dot(c.q - c.s);
        c.d = std::sqrt(d2);
        c.g = std::max(ray_cosine, params.min_ray_cosine);
        corr.push_back(c);
    }
}

// One robust Gauss-Newton step of point-to-plane ICP, linearised at the centroid of the moved
// model points (a well-conditioned 6x6 system): rotation omega and translation dt about `centre`.
// False when too few correspondences pass the kernel or the system is singular.
static bool icpStep(const std::vector<Correspondence>& corr, double gate, const ICPParams& params,
                    std::vector<double>& tmp, Vec3d& centre, Vec3d& omega, Vec3d& dt)
{
    // robust scale of the residuals, each divided by the share g of the axial sensor noise that
    // reaches it (noise-aware weighting: weight 1 / g^2)
    tmp.clear();
    for (size_t i = 0; i < corr.size(); ++i)
        tmp.push_back(std::abs(corr[i].r) / corr[i].g);
    const double sigma_min = params.min_correspondence_distance / params.gate_sigma_factor;
    const double sigma = std::max(sigma_min, 1.4826 * detail::medianOfNonNegative(tmp));
    // coarse phase (the gate is still shrinking): a tight kernel, so that a coherent group of
    // outliers (an occluder in front of the object) cannot pull the pose while the inliers'
    // residuals are still large; fine phase: the efficient kernel
    const bool coarse = gate > params.min_correspondence_distance * 1.0001;
    const double cutoff = (coarse ? params.tukey_c_coarse : params.tukey_c) * sigma;
    centre = Vec3d(0, 0, 0);
    for (size_t i = 0; i < corr.size(); ++i)
        centre += corr[i].q;
    centre *= 1.0 / (double)corr.size();
    Eigen::Matrix<double, 6, 6> A = Eigen::Matrix<double, 6, 6>::Zero();
    Eigen::Matrix<double, 6, 1> b = Eigen::Matrix<double, 6, 1>::Zero();
    int used = 0;
    for (size_t i = 0; i < corr.size(); ++i)
    {
        const Correspondence& c = corr[i];
        const double u = c.r / (c.g * cutoff);
        if (std::abs(u) >= 1)
            continue;
        const double w = (1 - u * u) * (1 - u * u) / (c.g * c.g);
        const Vec3d a = (c.q - centre).cross(c.n);
        const double J[6] = { a[0], a[1], a[2], c.n[0], c.n[1], c.n[2] };
        // A += w J J^T on the upper triangle, column by column with the products in the order
        // of Eigen's rankUpdate (the same sums; a call per point took 12 % of the pose stage)
        const double wr = w * c.r;
        for (int j = 0; j < 6; ++j)
        {
            const double wj = w * J[j];
            for (int k = 0; k <= j; ++k)
                A(k, j) += wj * J[k];
            b[j] -= wr * J[j];
        }
        ++used;
    }
    if (used < params.min_correspondences)
        return false;
    const Eigen::Matrix<double, 6, 6> Af = A.selfadjointView<Eigen::Upper>();
    Eigen::Matrix<double, 6, 1> x = Af.ldlt().solve(b);
    if (!x.allFinite())
        return false;
    // trust region on the rotation: the rotation of a roundish object is weakly constrained by
    // point-to-plane residuals, and a full Gauss-Newton step taken while outliers are still in
    // can turn it far away. Shorten the rotation, re-solve the translation for it.
    const double wn = x.head<3>().norm();
    if (wn > params.max_rotation_step)
    {
        x.head<3>() *= params.max_rotation_step / wn;
        const Eigen::Vector3d bt = b.tail<3>() - Af.block<3, 3>(3, 0) * x.head<3>();
        x.tail<3>() = Af.block<3, 3>(3, 3).ldlt().solve(bt);
        if (!x.allFinite())
            return false;
    }
    omega = Vec3d(x[0], x[1], x[2]);
    dt = Vec3d(x[3], x[4], x[5]);
    return true;
}

// Fitness and inlier RMSE at the final pose.
static void finalQuality(const SceneCloud& cloud, const std::vector<Vec3d>& pts,
                         const ICPParams& params, ICPResult& res)
{
    int inliers = 0;
    double sse = 0;
    for (size_t i = 0; i < pts.size(); ++i)
    {
        Point px;
        Vec3d s;
        double d2;
        if (associate(cloud, res.R * pts[i] + res.t, params.search_radius,
                      params.inlier_distance, px, s, d2))
        {
            ++inliers;
            sse += d2;
        }
    }
    res.fitness = (double)inliers / (double)pts.size();
    res.inlier_rmse = inliers ? std::sqrt(sse / inliers) : 0.0;
}

// refineICP from the rotation checkICPInputs() returned.
static ICPResult runICP(const std::vector<Point3f>& model_points, const Mat& depth,
                        const Matx33d& K, Matx33d R, const Vec3d& t0, const ICPParams& params,
                        const detail::SceneNormals& normals)
{
    const std::vector<Vec3d> pts = subsample(model_points, params.max_points);
    const SceneCloud cloud(depth, K, normals);
    Vec3d t = t0;
    ICPResult res;
    double gate = params.max_correspondence_distance;
    std::vector<Correspondence> corr;
    corr.reserve(pts.size());
    std::vector<double> tmp;
    tmp.reserve(pts.size());
    int stalled = 0; // iterations in a row whose gate, above its floor, did not shrink
    for (int it = 0; it < params.max_iterations; ++it)
    {
        correspondences(cloud, pts, R, t, gate, params, corr);
        if ((int)corr.size() < params.min_correspondences)
            break;
        Vec3d centre, omega, dt;
        if (!icpStep(corr, gate, params, tmp, centre, omega, dt))
            break;
        Matx33d dR;
        Rodrigues(omega, dR);
        // q' = dR (q - centre) + centre + dt
        R = dR * R;
        t = dR * (t - centre) + centre + dt;
        res.iterations = it + 1;
        // shrink the gate to gate_sigma_factor robust deviations of the 3D distances
        tmp.clear();
        for (size_t i = 0; i < corr.size(); ++i)
            tmp.push_back(corr[i].d);
        const double dsigma = 1.4826 * detail::medianOfNonNegative(tmp);
        const double next_gate = std::min(gate, std::max(params.min_correspondence_distance,
                                                         params.gate_sigma_factor * dsigma));
        const bool coarse = next_gate > params.min_correspondence_distance;
        stalled = coarse && next_gate >= gate * (1 - 1e-3) ? stalled + 1 : 0;
        gate = next_gate;
        if (norm(omega) < params.rotation_epsilon && norm(dt) < params.translation_epsilon)
        {
            res.converged = true;
            break;
        }
        if (params.max_stalled_iterations > 0 && stalled >= params.max_stalled_iterations)
            break;
    }
    res.R = R;
    res.t = t;
    finalQuality(cloud, pts, params, res);
    return res;
}

ICPResult refineICP(const std::vector<Point3f>& model_points, InputArray scene_depth,
                    const Matx33d& K, const Matx33d& R0, const Vec3d& t0, const ICPParams& params)
{
    Mat depth = scene_depth.getMat();
    const Matx33d R = checkICPInputs(model_points, depth, K, R0, t0, params);
    const detail::SceneNormals normals(depth, K, params);
    return runICP(model_points, depth, K, R, t0, params, normals);
}

namespace detail {

ICPResult refineICP(const std::vector<Point3f>& model_points, const Mat& scene_depth,
                    const Matx33d& K, const Matx33d& R0, const Vec3d& t0, const ICPParams& params,
                    const SceneNormals& normals)
{
    const Matx33d R = checkICPInputs(model_points, scene_depth, K, R0, t0, params);
    CV_Assert(normals.madeFor(scene_depth, K, params));
    return runICP(model_points, scene_depth, K, R, t0, params, normals);
}

} // namespace detail

} // namespace forestmod
} // namespace cv
