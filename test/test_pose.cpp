// This file is part of OpenCV project.
// It is subject to the license terms in the LICENSE file found in the top-level directory
// of this distribution and at http://opencv.org/license.html

#include "test_precomp.hpp"
#include "test_pose_common.hpp"

namespace opencv_test {
namespace {

using namespace pose_test;

static const TriMesh& apeMesh()
{
    static TriMesh m = readAsciiPly(cvtest::findDataFile("lmo_mini/models/obj_000001.ply"));
    return m;
}

static const double kApeDiameter = 102.099; // lmo_mini/models/models_info.json

/** A scene around the object at (R, t): the object in front of a tilted table plane, optionally
with an occluder (a plane 60 mm in front of the object) covering `occluded` of the object's
pixels from a random side. Returns the noisy depth (CV_16UC1). */
static Mat makeScene(const TriMesh& mesh, const Matx33d& R, const Vec3d& t, const Matx33d& K,
                     Size size, double occluded, RNG& rng, double* occluded_share = 0)
{
    Mat obj(size, CV_32FC1, Scalar(0));
    rasterizeDepth(mesh, R, t, K, obj);
    Mat scene(size, CV_32FC1);
    // table: plane through a point 120 mm behind the object's centre, tilted about x
    const double tilt = rng.uniform(-0.6, 0.6);
    const Vec3d n(0, std::sin(tilt), -std::cos(tilt));
    const Vec3d p0 = t + Vec3d(0, 0, 120);
    const Matx33d Kinv = K.inv();
    for (int y = 0; y < size.height; ++y)
        for (int x = 0; x < size.width; ++x)
        {
            const Vec3d ray = Kinv * Vec3d(x, y, 1);
            const double lambda = n.dot(p0) / n.dot(ray);
            float z = (float)(lambda * ray[2]);
            const float zo = obj.at<float>(y, x);
            if (zo > 0 && zo < z)
                z = zo;
            scene.at<float>(y, x) = z;
        }
    double share = 0;
    if (occluded > 0)
    {
        // half-plane occluder: pixels beyond a line, placed so that `occluded` of the object is
        // behind it
        const double a = rng.uniform(0.0, 2 * CV_PI);
        const Vec2d dir(std::cos(a), std::sin(a));
        std::vector<double> proj;
        for (int y = 0; y < size.height; ++y)
            for (int x = 0; x < size.width; ++x)
                if (obj.at<float>(y, x) > 0)
                    proj.push_back(dir[0] * x + dir[1] * y);
        CV_Assert(!proj.empty());
        std::sort(proj.begin(), proj.end());
        const double thr = proj[(size_t)((1 - occluded) * (proj.size() - 1))];
        const float zocc = (float)(t[2] - 60);
        int hidden = 0;
        for (int y = 0; y < size.height; ++y)
            for (int x = 0; x < size.width; ++x)
                if (dir[0] * x + dir[1] * y > thr)
                {
                    hidden += obj.at<float>(y, x) > 0;
                    scene.at<float>(y, x) = zocc + (float)(0.05 * (x - size.width / 2));
                }
        share = (double)hidden / (double)proj.size();
    }
    if (occluded_share)
        *occluded_share = share;
    return sensorNoise(scene, rng);
}

struct IcpTrial
{
    double rot_err_deg, trans_err_mm, add_mm;       // after both passes
    double rot_err_deg_1, trans_err_mm_1;           // after the first pass
    ICPResult res;
};

/** One random trial: random pose, start 5 degrees and 10 mm off. ICP as a detector runs it: the
model points are the visible surface rendered at the starting pose; a second pass re-selects them
at the refined pose (the visible rim moves with the pose; doc/pose.md). */
static IcpTrial runIcpTrial(RNG& rng, double occluded, const ICPParams& params = ICPParams())
{
    const TriMesh& mesh = apeMesh();
    const Matx33d K = lmoK();
    const Size size(640, 480);
    const double z = rng.uniform(500.0, 1000.0);
    const Vec3d t_gt(z * rng.uniform(-0.2, 0.2), z * rng.uniform(-0.15, 0.15), z);
    const Matx33d R_gt = uniformRotation(rng);
    Mat scene = makeScene(mesh, R_gt, t_gt, K, size, occluded, rng);

    Vec3d dir(rng.gaussian(1), rng.gaussian(1), rng.gaussian(1));
    dir /= cv::norm(dir);
    const Matx33d R0 = randomRotation(rng, 5.0 * CV_PI / 180) * R_gt;
    const Vec3d t0 = t_gt + 10.0 * dir;

    IcpTrial tr;
    Matx33d R = R0;
    Vec3d t = t0;
    for (int pass = 0; pass < 2; ++pass)
    {
        Mat model_depth = renderDepth16(mesh, R, t, K, size);
        std::vector<Point3f> pts = modelPointsFromDepth(model_depth, K, R, t, 1);
        tr.res = refineICP(pts, scene, K, R, t, params);
        R = tr.res.R;
        t = tr.res.t;
        if (pass == 0)
        {
            tr.rot_err_deg_1 = rotationErrorDeg(R, R_gt);
            tr.trans_err_mm_1 = cv::norm(t - t_gt);
        }
    }
    tr.rot_err_deg = rotationErrorDeg(R, R_gt);
    tr.trans_err_mm = cv::norm(t - t_gt);
    tr.add_mm = addError(mesh.vertices, R, t, R_gt, t_gt);
    return tr;
}

static double medianOf(std::vector<double> v)
{
    std::sort(v.begin(), v.end());
    return v.empty() ? 0 : v[v.size() / 2];
}

TEST(Forestmod_Pose, icp_converges_on_rendered_ape_with_sensor_noise)
{
    RNG rng(20161025);
    const int trials = 50;
    int good = 0;
    int good_1 = 0;
    std::vector<double> rot, trans;
    for (int i = 0; i < trials; ++i)
    {
        IcpTrial tr = runIcpTrial(rng, 0.0);
        rot.push_back(tr.rot_err_deg);
        trans.push_back(tr.trans_err_mm);
        good_1 += tr.rot_err_deg_1 <= 0.5 && tr.trans_err_mm_1 <= 1.0;
        if (tr.rot_err_deg <= 0.5 && tr.trans_err_mm <= 1.0)
            ++good;
        else
            std::cout << "trial " << i << ": " << tr.rot_err_deg << " deg, " << tr.trans_err_mm
                      << " mm, fitness " << tr.res.fitness << ", " << tr.res.iterations
                      << " iterations" << std::endl;
        EXPECT_GT(tr.res.fitness, 0.5);
        EXPECT_GT(tr.res.inlier_rmse, 0.0);
    }
    std::cout << "ICP, no clutter: " << good << "/" << trials
              << " within 1 mm and 0.5 deg; median errors " << medianOf(rot) << " deg, "
              << medianOf(trans) << " mm (first pass alone: " << good_1 << "/" << trials << ")"
              << std::endl;
    EXPECT_GE(good, (int)std::ceil(0.95 * trials));
}

TEST(Forestmod_Pose, icp_robust_to_30_percent_occlusion)
{
    RNG rng(31415);
    const int trials = 50;
    int good = 0;
    std::vector<double> add;
    for (int i = 0; i < trials; ++i)
    {
        IcpTrial tr = runIcpTrial(rng, 0.3);
        add.push_back(tr.add_mm);
        if (isCorrect(tr.add_mm, kApeDiameter))
            ++good;
        else
            std::cout << "trial " << i << ": ADD " << tr.add_mm << " mm, " << tr.rot_err_deg
                      << " deg, " << tr.trans_err_mm << " mm" << std::endl;
    }
    std::cout << "ICP, 30 % occluded: " << good << "/" << trials << " with ADD < 0.1 d; median ADD "
              << medianOf(add) << " mm" << std::endl;
    EXPECT_GE(good, (int)std::ceil(0.9 * trials));
}

} // namespace
} // namespace opencv_test

