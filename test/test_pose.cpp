// This file is part of OpenCV project.
// It is subject to the license terms in the LICENSE file found in the top-level directory
// of this distribution and at http://opencv.org/license.html

#include "test_precomp.hpp"
#include "test_pose_common.hpp"
#include "../src/pose_refine.hpp"

namespace opencv_test {
namespace {

using namespace pose_test;

static const double kApeDiameter = 102.099; // lmo_mini/models/models_info.json

/** A scene around the object at (R, t): the object in front of a tilted table plane; with
occluded > 0 also clutter (boxes around the object, partly in front of it) and an occluder (a
plane 60 mm in front of the object's centre) covering `occluded` of the object's pixels from a
random side. Returns the noisy depth (CV_16UC1). */
static Mat makeScene(MeshRenderer& mr, const Matx33d& R, const Vec3d& t, const Matx33d& K,
                     Size size, double occluded, RNG& rng, double* occluded_share = 0)
{
    Mat obj = mr.depth32(R, t, K);
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
        // clutter around the object: 8 boxes on the table near it, at depths from 40 mm in
        // front of the object's centre to the table, seen where the object does not hide them
        const Vec3d c = K * t;
        const Point2d centre(c[0] / c[2], c[1] / c[2]);
        const double half = 0.6 * K(0, 0) * 102.0 / t[2]; // about the object's size in pixels
        for (int b = 0; b < 8; ++b)
        {
            const Point2d p = centre + Point2d(rng.uniform(-2.0, 2.0) * half,
                                               rng.uniform(-2.0, 2.0) * half);
            const double w = rng.uniform(0.3, 1.0) * half, h = rng.uniform(0.3, 1.0) * half;
            const float zb = (float)(t[2] + rng.uniform(-40.0, 120.0));
            const Rect box = Rect(Point(cvRound(p.x - w), cvRound(p.y - h)),
                                  Point(cvRound(p.x + w), cvRound(p.y + h)))
                             & Rect(0, 0, size.width, size.height);
            for (int y = box.y; y < box.y + box.height; ++y)
                for (int x = box.x; x < box.x + box.width; ++x)
                {
                    float& z = scene.at<float>(y, x);
                    if (zb < z && !(obj.at<float>(y, x) > 0 && obj.at<float>(y, x) < zb))
                        z = zb;
                }
        }

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
        for (int y = 0; y < size.height; ++y)
            for (int x = 0; x < size.width; ++x)
                if (dir[0] * x + dir[1] * y > thr)
                    scene.at<float>(y, x) = zocc + (float)(0.05 * (x - size.width / 2));
        // the share of the object hidden by the occluder and the clutter
        int hidden = 0;
        for (int y = 0; y < size.height; ++y)
            for (int x = 0; x < size.width; ++x)
                hidden += obj.at<float>(y, x) > 0 && scene.at<float>(y, x) < obj.at<float>(y, x) - 1;
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

/** The ICP parameters of refinePose's passes before the last. */
static ICPParams earlyPassParams(const ICPParams& params)
{
    ICPParams p = params;
    if (p.early_pass_points > 0 && (p.max_points <= 0 || p.early_pass_points < p.max_points))
        p.max_points = p.early_pass_points;
    return p;
}

/** One random trial: random pose, scene depth rendered from the mesh with sensor-like noise in
front of a table (and an occluder), start 5 degrees and 10 mm off. ICP as a detector runs it
(refinePose): the model points are the visible surface rendered at the starting pose; a second
pass re-selects them at the refined pose (the visible rim moves with the pose; doc/pose.md). */
static IcpTrial runIcpTrial(MeshRenderer& mr, RNG& rng, double occluded,
                            const ICPParams& params = ICPParams(),
                            const cv::forestmod::detail::ObjectDrawer* drawer = 0)
{
    const Matx33d K = lmoIntrinsics();
    const Size size(640, 480);
    const double z = rng.uniform(500.0, 1000.0);
    const Vec3d t_gt(z * rng.uniform(-0.2, 0.2), z * rng.uniform(-0.15, 0.15), z);
    const Matx33d R_gt = uniformRotation(rng);
    Mat scene = makeScene(mr, R_gt, t_gt, K, size, occluded, rng);

    Vec3d dir(rng.gaussian(1), rng.gaussian(1), rng.gaussian(1));
    dir /= cv::norm(dir);
    const Matx33d R0 = randomRotation(rng, 5.0 * CV_PI / 180) * R_gt;
    const Vec3d t0 = t_gt + 10.0 * dir;

    // refinePose(passes = 2) is these two single passes, the first with early_pass_points
    // (icp_early_passes_use_early_pass_points); run them apart to report both (with `drawer`:
    // the object drawn by it instead of mr's renderer)
    const cv::forestmod::detail::RendererDrawer renderer(*mr.renderer, mr.handle);
    const cv::forestmod::detail::ObjectDrawer& draw = drawer ? *drawer : renderer;
    IcpTrial tr;
    ICPResult first = cv::forestmod::detail::refinePose(draw, scene, K, R0, t0,
                                                        earlyPassParams(params), 1);
    tr.rot_err_deg_1 = rotationErrorDeg(first.R, R_gt);
    tr.trans_err_mm_1 = cv::norm(first.t - t_gt);
    tr.res = cv::forestmod::detail::refinePose(draw, scene, K, first.R, first.t, params, 1);
    tr.rot_err_deg = rotationErrorDeg(tr.res.R, R_gt);
    tr.trans_err_mm = cv::norm(tr.res.t - t_gt);
    tr.add_mm = addError(mr.mesh.vertices, tr.res.R, tr.res.t, R_gt, t_gt);
    return tr;
}

static double medianOf(std::vector<double> v)
{
    std::sort(v.begin(), v.end());
    return v.empty() ? 0 : v[v.size() / 2];
}

TEST(Forestmod_Pose, icp_converges_on_rendered_ape_with_sensor_noise)
{
    MeshRenderer mr(apeMesh(), Size(640, 480));
    RNG rng(20161025);
    const int trials = 50;
    int good = 0;
    int good_1 = 0;
    std::vector<double> rot, trans;
    for (int i = 0; i < trials; ++i)
    {
        IcpTrial tr = runIcpTrial(mr, rng, 0.0);
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

// refinePose's passes before the last use early_pass_points model points, the last max_points:
// bit for bit the chain of single passes, and not the same as every pass with max_points.
TEST(Forestmod_Pose, icp_early_passes_use_early_pass_points)
{
    MeshRenderer mr(apeMesh(), Size(640, 480));
    RNG rng(20261125);
    const Matx33d K = lmoIntrinsics();
    const cv::forestmod::detail::RendererDrawer draw(*mr.renderer, mr.handle);
    int differs = 0;
    for (int i = 0; i < 4; ++i)
    {
        const Vec3d t_gt(rng.uniform(-60.0, 60.0), rng.uniform(-40.0, 40.0), 600.0);
        const Matx33d R_gt = uniformRotation(rng);
        const Mat scene = makeScene(mr, R_gt, t_gt, K, Size(640, 480), 0.0, rng);
        const Matx33d R0 = randomRotation(rng, 5.0 * CV_PI / 180) * R_gt;
        const Vec3d t0 = t_gt + Vec3d(6, -5, 5);
        ICPParams p;
        p.early_pass_points = 300 + 200 * i;
        const ICPResult both = cv::forestmod::detail::refinePose(draw, scene, K, R0, t0, p, 2);
        const ICPResult a = cv::forestmod::detail::refinePose(draw, scene, K, R0, t0,
                                                              earlyPassParams(p), 1);
        ICPParams one = p;
        one.early_pass_points = 0;
        const ICPResult b = cv::forestmod::detail::refinePose(draw, scene, K, a.R, a.t, one, 1);
        EXPECT_EQ(cvtest::norm(Mat(both.R), Mat(b.R), NORM_INF), 0.0) << i;
        EXPECT_EQ(cvtest::norm(Mat(both.t), Mat(b.t), NORM_INF), 0.0) << i;
        EXPECT_EQ(both.iterations, a.iterations + b.iterations) << i;
        // the same two passes with max_points in both end elsewhere
        const ICPResult full = cv::forestmod::detail::refinePose(draw, scene, K, R0, t0, one, 2);
        differs += cvtest::norm(Mat(both.t), Mat(full.t), NORM_INF) > 0;
        // a 3 mm slack of the rendered scenes' start: the pose is found either way
        EXPECT_LT(cv::norm(both.t - t_gt), 3.0) << i;
    }
    EXPECT_GT(differs, 0);
    // without a second pass early_pass_points changes nothing
    ICPParams p;
    p.early_pass_points = 50;
    RNG rng2(7);
    const Matx33d R_gt = uniformRotation(rng2);
    const Mat scene = makeScene(mr, R_gt, Vec3d(0, 0, 700), K, Size(640, 480), 0.0, rng2);
    ICPParams q = p;
    q.early_pass_points = 0;
    const ICPResult r1 = cv::forestmod::detail::refinePose(draw, scene, K, R_gt, Vec3d(5, 0, 700),
                                                           p, 1);
    const ICPResult r2 = cv::forestmod::detail::refinePose(draw, scene, K, R_gt, Vec3d(5, 0, 700),
                                                           q, 1);
    EXPECT_EQ(cvtest::norm(Mat(r1.t), Mat(r2.t), NORM_INF), 0.0);
}

// A run on the wrong surface (the ape's visible points over a bumpy surface with no ape in it)
// keeps a wide gate and runs out its iterations; max_stalled_iterations stops it where its gate
// stopped shrinking, as a run cut at that iteration. A run that locks on is not cut.
TEST(Forestmod_Pose, icp_stops_a_run_whose_gate_stalls)
{
    MeshRenderer mr(apeMesh(), Size(640, 480));
    const Matx33d K = lmoIntrinsics();
    RNG rng(20261125);
    const Matx33d R = uniformRotation(rng);
    const Vec3d t(20, -10, 700);
    const std::vector<Point3f> pts = modelPointsFromDepth(mr.depth16(R, t, K), K, R, t);
    ASSERT_GT(pts.size(), 500u);
    Mat bumps(480, 640, CV_32FC1);
    for (int y = 0; y < bumps.rows; ++y)
        for (int x = 0; x < bumps.cols; ++x)
            bumps.at<float>(y, x) = (float)(720 + 25 * std::sin(x / 9.0) * std::sin(y / 11.0)
                                            + 15 * std::sin((x + y) / 23.0));
    const Mat scene = sensorNoise(bumps, rng);
    ICPParams off;
    off.max_stalled_iterations = 0;
    const ICPParams on; // the default
    ASSERT_GT(on.max_stalled_iterations, 0);
    const ICPResult a = refineICP(pts, scene, K, R, t, off);
    const ICPResult b = refineICP(pts, scene, K, R, t, on);
    EXPECT_FALSE(a.converged);
    EXPECT_EQ(a.iterations, off.max_iterations);
    EXPECT_FALSE(b.converged);
    EXPECT_GE(b.iterations, on.max_stalled_iterations);
    EXPECT_LT(b.iterations, a.iterations);
    ICPParams cut = off;
    cut.max_iterations = b.iterations;
    const ICPResult c = refineICP(pts, scene, K, R, t, cut);
    EXPECT_EQ(cvtest::norm(Mat(c.R), Mat(b.R), NORM_INF), 0.0);
    EXPECT_EQ(cvtest::norm(Mat(c.t), Mat(b.t), NORM_INF), 0.0);

    // the ape's own scene, 5 degrees and 10 mm off: the same pose with and without the stop
    const Mat own = makeScene(mr, R, t, K, Size(640, 480), 0.0, rng);
    const Matx33d R0 = randomRotation(rng, 5.0 * CV_PI / 180) * R;
    const Vec3d t0 = t + Vec3d(6, -5, 5);
    const ICPResult d = refineICP(pts, own, K, R0, t0, off);
    const ICPResult e = refineICP(pts, own, K, R0, t0, on);
    EXPECT_TRUE(e.converged);
    EXPECT_EQ(d.iterations, e.iterations);
    EXPECT_EQ(cvtest::norm(Mat(d.t), Mat(e.t), NORM_INF), 0.0);
    EXPECT_LT(cv::norm(e.t - t), 2.0);
}

// The detector's ICP draws the coarse mesh on the CPU (coarseMesh, drawMesh: no lock, the
// hypotheses in parallel): as accurate as the OSMesa rendering of the full mesh, same trials.
TEST(Forestmod_Pose, icp_with_the_cpu_drawing_of_the_coarse_mesh)
{
    using namespace cv::forestmod::detail;
    CoarseApe ape;
    MeshRenderer& mr = ape.mr;
    const MeshDrawer& drawer = ape.drawer;
    RNG rng_renderer(20161025), rng_drawn(20161025);
    const int trials = 30;
    int good_renderer = 0, good_drawn = 0;
    for (int i = 0; i < trials; ++i)
    {
        const IcpTrial a = runIcpTrial(mr, rng_renderer, 0.0);
        const IcpTrial b = runIcpTrial(mr, rng_drawn, 0.0, ICPParams(), &drawer);
        good_renderer += a.rot_err_deg <= 0.5 && a.trans_err_mm <= 1.0;
        good_drawn += b.rot_err_deg <= 0.5 && b.trans_err_mm <= 1.0;
        EXPECT_GT(b.res.fitness, 0.5) << i;
    }
    std::cout << "[ INFO    ] ICP, no clutter: " << good_renderer << " / " << trials
              << " within 1 mm and 0.5 deg (renderer), " << good_drawn << " (drawn)" << std::endl;
    EXPECT_GE(good_drawn, (int)std::ceil(0.93 * trials));
    EXPECT_GE(good_drawn, good_renderer - 1);
    // the depth check of the drawing agrees with the renderer's
    const Matx33d K = lmoIntrinsics();
    RNG rng(17);
    const Matx33d R = uniformRotation(rng);
    const Vec3d t(0, 0, 750);
    const Mat occl = makeScene(mr, R, t, K, Size(640, 480), 0.3, rng);
    const double tol = 0.05 * kApeDiameter;
    EXPECT_NEAR(depthCheck(drawer, occl, K, R, t, tol),
                depthCheck(*mr.renderer, mr.handle, occl, K, R, t, tol), 0.02);
    EXPECT_LT(depthCheck(drawer, occl, K, R, t + Vec3d(0, 0, 30), tol), 0.1);
    EXPECT_THROW(depthCheck(drawer, Mat(240, 320, CV_16UC1, Scalar(1)), K, R, t, tol),
                 cv::Exception);
}

// SceneNormals::point: the back-projection of a pixel, from per-column and per-row factors when K
// has no skew, the same values as the formula (x - cx - s y_n) / fx, y_n = (y - cy) / fy, times z.
TEST(Forestmod_Pose, scene_points_equal_the_back_projection)
{
    using namespace cv::forestmod::detail;
    const Mat depth(48, 64, CV_16UC1, Scalar(700));
    Matx33d K = lmoIntrinsics();
    for (int skew = 0; skew < 2; ++skew)
    {
        K(0, 1) = skew ? 0.75 : 0.0;
        const SceneNormals normals(depth, K, ICPParams());
        for (int y = 0; y < depth.rows; y += 5)
            for (int x = 0; x < depth.cols; x += 3)
            {
                const double z = 500.0 + 7 * x + y;
                const double yn = (y - K(1, 2)) / K(1, 1);
                const double xn = (x - K(0, 2) - K(0, 1) * yn) / K(0, 0);
                const Vec3d p = normals.point(x, y, z);
                ASSERT_EQ(p[0], xn * z) << x << " " << y << " skew " << skew;
                ASSERT_EQ(p[1], yn * z) << x << " " << y << " skew " << skew;
                ASSERT_EQ(p[2], z);
            }
    }
}

// ICP's median (detail::medianOfNonNegative, a count in bins, then nth_element within one bin)
// is the value std::nth_element puts at rank size / 2: few and many values, ties, zeros, a long
// tail (most values in the first bin), all equal, and negative values (not binned: nth_element).
TEST(Forestmod_Pose, icp_median_equals_nth_element)
{
    RNG rng(17);
    const int sizes[] = { 1, 2, 63, 64, 65, 1000, 4001 };
    for (int kind = 0; kind < 6; ++kind)
        for (size_t si = 0; si < sizeof(sizes) / sizeof(sizes[0]); ++si)
            for (int rep = 0; rep < 4; ++rep)
            {
                std::vector<double> v(sizes[si]);
                for (size_t i = 0; i < v.size(); ++i)
                {
                    const double u = rng.uniform(0.0, 30.0);
                    v[i] = kind == 0 ? u
                        : kind == 1 ? std::floor(u) * 0.5           // ties
                        : kind == 2 ? (rng.uniform(0, 3) ? 0.0 : u) // zeros
                        : kind == 3 ? std::exp(rng.uniform(-8.0, 8.0)) // long tail
                        : kind == 4 ? 2.5                           // all equal
                                    : u - 20;                       // negative values
                }
                std::vector<double> expected = v, got = v;
                const size_t m = v.size() / 2;
                std::nth_element(expected.begin(), expected.begin() + m, expected.end());
                ASSERT_EQ(cv::forestmod::detail::medianOfNonNegative(got), expected[m])
                    << "kind " << kind << " size " << v.size() << " rep " << rep;
            }
}

// The detector refines a frame's hypotheses in parallel on one set of scene normals
// (detail::SceneNormals, each normal computed once): the same results, bit for bit, as each ICP
// computing its own, whatever the order, the threads, and whether the normals are new or kept.
TEST(Forestmod_Pose, icp_on_the_frames_shared_normals_equals_icp_alone)
{
    using namespace cv::forestmod::detail;
    MeshRenderer mr(apeMesh(), Size(640, 480));
    const Matx33d K = lmoIntrinsics();
    RNG rng(31);
    const Matx33d R_gt = uniformRotation(rng);
    const Vec3d t_gt(40, -20, 800);
    const Mat scene = makeScene(mr, R_gt, t_gt, K, Size(640, 480), 0.3, rng);
    const int n = 12;
    std::vector<std::vector<Point3f> > pts(n);
    std::vector<Matx33d> R0(n);
    std::vector<Vec3d> t0(n);
    std::vector<ICPResult> alone(n);
    for (int i = 0; i < n; ++i)
    {
        Vec3d dir(rng.gaussian(1), rng.gaussian(1), rng.gaussian(1));
        R0[i] = randomRotation(rng, (2.0 + i) * CV_PI / 180) * R_gt;
        t0[i] = t_gt + (3.0 + 2 * i) / cv::norm(dir) * dir;
        pts[i] = modelPointsFromDepth(mr.depth16(R0[i], t0[i], K), K, R0[i], t0[i]);
        alone[i] = refineICP(pts[i], scene, K, R0[i], t0[i]);
    }
    const ICPParams params;
    const SceneNormals normals(scene, K, params);
    const int threads = getNumThreads();
    setNumThreads(4);
    for (int round = 0; round < 2; ++round) // new normals, then kept ones
    {
        std::vector<ICPResult> shared(n);
        parallel_for_(Range(0, n), [&](const Range& r) {
            for (int k = r.start; k < r.end; ++k)
            {
                const int i = round ? k : n - 1 - k;
                shared[i] = refineICP(pts[i], scene, K, R0[i], t0[i], params, normals);
            }
        });
        for (int i = 0; i < n; ++i)
        {
            EXPECT_EQ(cvtest::norm(Mat(shared[i].R), Mat(alone[i].R), NORM_INF), 0.0) << i;
            EXPECT_EQ(cvtest::norm(Mat(shared[i].t), Mat(alone[i].t), NORM_INF), 0.0) << i;
            EXPECT_EQ(shared[i].fitness, alone[i].fitness) << i;
            EXPECT_EQ(shared[i].inlier_rmse, alone[i].inlier_rmse) << i;
            EXPECT_EQ(shared[i].iterations, alone[i].iterations) << i;
            EXPECT_EQ(shared[i].converged, alone[i].converged) << i;
        }
    }
    setNumThreads(threads);
    EXPECT_LT(rotationErrorDeg(alone[0].R, R_gt), 1.0); // the trials converge: a real check
    // a normal read back equals a new one's; none where the scene has no depth
    const SceneNormals fresh(scene, K, params);
    int valid = 0;
    for (int y = 0; y < scene.rows; y += 7)
        for (int x = 0; x < scene.cols; x += 7)
        {
            Vec3f a, b;
            const bool ok = normals.normal(x, y, a);
            ASSERT_EQ(ok, fresh.normal(x, y, b));
            ASSERT_EQ(ok, normals.normal(x, y, b));
            if (ok)
            {
                ASSERT_EQ(a, b);
            }
            valid += ok;
        }
    EXPECT_GT(valid, 1000);
    Mat holes = scene.clone();
    holes(Rect(300, 200, 40, 40)).setTo(0);
    Vec3f h;
    EXPECT_FALSE(SceneNormals(holes, K, params).normal(320, 220, h));
    // normals of another image, camera or parameters are refused
    ICPParams other = params;
    other.normal_radius = 4;
    EXPECT_THROW(refineICP(pts[0], holes, K, R0[0], t0[0], params, normals), cv::Exception);
    Matx33d K2 = K;
    K2(0, 0) += 1;
    EXPECT_THROW(refineICP(pts[0], scene, K2, R0[0], t0[0], params, normals), cv::Exception);
    EXPECT_THROW(refineICP(pts[0], scene, K, R0[0], t0[0], other, normals), cv::Exception);
}

TEST(Forestmod_Pose, icp_robust_to_30_percent_occlusion)
{
    MeshRenderer mr(apeMesh(), Size(640, 480));
    RNG rng(31415);
    const int trials = 50;
    int good = 0;
    std::vector<double> add;
    for (int i = 0; i < trials; ++i)
    {
        IcpTrial tr = runIcpTrial(mr, rng, 0.3);
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

// ---- initial pose ---------------------------------------------------------------------------

static std::vector<Point2d> projectAll(const std::vector<Point3f>& pts, const Matx33d& K,
                                       const Matx33d& R, const Vec3d& t)
{
    std::vector<Point2d> out;
    for (size_t i = 0; i < pts.size(); ++i)
    {
        const Vec3d c = K * (R * Vec3d(pts[i].x, pts[i].y, pts[i].z) + t);
        out.push_back(Point2d(c[0] / c[2], c[1] / c[2]));
    }
    return out;
}

/** Mean distance between the projections under (R, t) and the template's projections shifted. */
static double shiftedProjectionError(const std::vector<Point3f>& pts, const Matx33d& K_s,
                                     const Matx33d& R, const Vec3d& t,
                                     const std::vector<Point2d>& tmpl, const Point2d& shift)
{
    std::vector<Point2d> p = projectAll(pts, K_s, R, t);
    double sum = 0;
    for (size_t i = 0; i < p.size(); ++i)
        sum += cv::norm(p[i] - (tmpl[i] + shift));
    return sum / (double)p.size();
}

TEST(Forestmod_Pose, initial_pose_moves_template_to_match_location)
{
    const Mesh& mesh = apeMesh();
    const Matx33d K = lmoIntrinsics();
    RNG rng(7);
    const Matx33d R_t = uniformRotation(rng);
    const Vec3d t_t(0, 0, 800);
    const Vec3d c_t = K * t_t;
    const Point2d template_px(c_t[0] / c_t[2], c_t[1] / c_t[2]);
    const std::vector<Point2d> tmpl = projectAll(mesh.vertices, K, R_t, t_t);

    const Point2d shifts[] = { Point2d(150, -90), Point2d(-220, 140), Point2d(40, 200),
                               Point2d(-3.5, 2.25) };
    for (size_t k = 0; k < sizeof(shifts) / sizeof(shifts[0]); ++k)
    {
        const Point2d scene_px = template_px + shifts[k];
        Matx33d R;
        Vec3d t;
        initialPose(R_t, t_t, K, template_px, K, scene_px, 0, R, t);
        const double err = shiftedProjectionError(mesh.vertices, K, R, t, tmpl, shifts[k]);
        // where the object lands: centre of its projected points
        const std::vector<Point2d> moved = projectAll(mesh.vertices, K, R, t);
        Point2d c_moved(0, 0), c_tmpl(0, 0);
        for (size_t i = 0; i < moved.size(); ++i)
        {
            c_moved += moved[i];
            c_tmpl += tmpl[i];
        }
        c_moved *= 1.0 / (double)moved.size();
        c_tmpl *= 1.0 / (double)moved.size();
        const double centre_err = cv::norm(c_moved - (c_tmpl + shifts[k]));
        // without the off-axis correction: same rotation, moved along the new ray
        const Vec3d ray = K.inv() * Vec3d(scene_px.x, scene_px.y, 1);
        const double err_naive = shiftedProjectionError(mesh.vertices, K, R_t,
                                                        ray * (cv::norm(t_t) / cv::norm(ray)),
                                                        tmpl, shifts[k]);
        std::cout << "shift " << shifts[k] << ": object centre off by " << centre_err
                  << " px, points on average by " << err << " px (without the off-axis "
                  << "correction " << err_naive << " px)" << std::endl;
        EXPECT_LE(centre_err, 2.0);
        // a pure image shift is not a rigid motion: far off-axis the view of the same object
        // under the same angle is the template warped by the homography K Q K^-1
        if (cv::norm(shifts[k]) <= 200)
        {
            EXPECT_LE(err, 2.0);
        }
        EXPECT_NEAR(cv::norm(t), cv::norm(t_t), 1e-6); // same apparent size, same K
        if (cv::norm(shifts[k]) > 100)
        {
            EXPECT_LT(err, 0.5 * err_naive);
        }
    }

    // the scene camera differs (focal length x 1.2, other principal point): same apparent size
    const Matx33d K_s(1.2 * K(0, 0), 0, 300, 0, 1.2 * K(1, 1), 260, 0, 0, 1);
    const Point2d scene_px(420, 150);
    Matx33d R;
    Vec3d t;
    initialPose(R_t, t_t, K, template_px, K_s, scene_px, 0, R, t);
    EXPECT_LE(shiftedProjectionError(mesh.vertices, K_s, R, t, tmpl, scene_px - template_px), 2.0);
    EXPECT_NEAR(cv::norm(t), 1.2 * cv::norm(t_t), 1e-6);
}

TEST(Forestmod_Pose, initial_pose_rgbd_distance_from_scene_depth)
{
    MeshRenderer mr(apeMesh(), Size(640, 480));
    const Matx33d K = lmoIntrinsics();
    const Size size(640, 480);
    RNG rng(11);
    for (int trial = 0; trial < 5; ++trial)
    {
        const Matx33d R_t = uniformRotation(rng);
        const Vec3d t_t(0, 0, rng.uniform(600.0, 900.0));
        const Vec3d c_t = K * t_t;
        const Point2d template_px(c_t[0] / c_t[2], c_t[1] / c_t[2]);
        Mat tmpl_depth = mr.depth16(R_t, t_t, K);

        // the object in the scene: moved sideways and 3 % further away (same orientation)
        const Vec3d t_true(rng.uniform(-150.0, 150.0), rng.uniform(-100.0, 100.0), 1.03 * t_t[2]);
        const Vec3d c_s = K * t_true;
        const Point2d scene_px(c_s[0] / c_s[2], c_s[1] / c_s[2]);
        Mat obj = mr.depth32(R_t, t_true, K);
        Mat scene32(size, CV_32FC1, Scalar(1500));
        obj.copyTo(scene32, obj > 0);
        Mat scene = sensorNoise(scene32, rng);

        // template features: a grid over the template's object pixels
        std::vector<Point> positions;
        std::vector<float> depths;
        const Point offset(cvRound(scene_px.x - template_px.x), cvRound(scene_px.y - template_px.y));
        for (int y = 0; y < size.height; y += 5)
            for (int x = 0; x < size.width; x += 5)
                if (tmpl_depth.at<ushort>(y, x))
                {
                    positions.push_back(Point(x, y) + offset);
                    depths.push_back(tmpl_depth.at<ushort>(y, x));
                }
        ASSERT_GE(positions.size(), 30u);
        const double z = sceneDepthFromFeatures(scene, positions, depths, t_t[2]);
        Matx33d R;
        Vec3d t;
        initialPose(R_t, t_t, K, template_px, K, scene_px, z, R, t);
        std::cout << "true distance " << cv::norm(t_true) << " mm, estimated " << cv::norm(t)
                  << " mm (depth " << z << " vs " << t_true[2] << ")" << std::endl;
        EXPECT_NEAR(cv::norm(t), cv::norm(t_true), 0.01 * cv::norm(t_true));
        EXPECT_NEAR(t[2], z, 1e-6);
        // the centre is on the ray through scene_px
        const Vec3d c = K * t;
        EXPECT_NEAR(c[0] / c[2], scene_px.x, 1e-6);
        EXPECT_NEAR(c[1] / c[2], scene_px.y, 1e-6);
    }
}

TEST(Forestmod_Pose, scene_depth_from_features_is_robust)
{
    Mat depth(100, 100, CV_16UC1, Scalar(0));
    std::vector<Point> pos;
    std::vector<float> tmpl;
    RNG rng(3);
    for (int i = 0; i < 50; ++i)
    {
        const Point p(rng.uniform(0, 100), rng.uniform(0, 100));
        const float d = (float)rng.uniform(780.0, 820.0); // feature depth in the template (centre 800)
        // the object is 100 mm further in the scene; 40 % of the features see clutter
        depth.at<ushort>(p) = (ushort)(i % 5 < 2 ? rng.uniform(300, 2000) : cvRound(d + 100));
        pos.push_back(p);
        tmpl.push_back(d);
    }
    EXPECT_NEAR(sceneDepthFromFeatures(depth, pos, tmpl, 800.0), 900.0, 3.0);
    // no valid scene depth: 0
    EXPECT_EQ(sceneDepthFromFeatures(Mat(100, 100, CV_16UC1, Scalar(0)), pos, tmpl, 800.0), 0.0);
    // outside the image: ignored
    std::vector<Point> outside(pos.size(), Point(-5, 300));
    EXPECT_EQ(sceneDepthFromFeatures(depth, outside, tmpl, 800.0), 0.0);
    EXPECT_THROW(sceneDepthFromFeatures(Mat(10, 10, CV_32FC1), pos, tmpl, 800.0), cv::Exception);
    EXPECT_THROW(sceneDepthFromFeatures(depth, pos, std::vector<float>(3, 1.f), 800.0),
                 cv::Exception);
}

TEST(Forestmod_Pose, model_points_from_depth_reproject_to_their_pixels)
{
    MeshRenderer mr(apeMesh(), Size(640, 480));
    const Matx33d K = lmoIntrinsics();
    RNG rng(5);
    const Matx33d R = uniformRotation(rng);
    const Vec3d t(30, -20, 700);
    Mat d = mr.depth16(R, t, K);
    std::vector<Point3f> pts = modelPointsFromDepth(d, K, R, t, 2);
    ASSERT_GT(pts.size(), 300u);
    // every point is within the model's bounding box, and re-projects onto an object pixel
    for (size_t i = 0; i < pts.size(); ++i)
    {
        EXPECT_LT(std::abs(pts[i].x), 40.f);
        EXPECT_LT(std::abs(pts[i].y), 40.f);
        EXPECT_LT(std::abs(pts[i].z), 47.f);
        const Vec3d c = R * Vec3d(pts[i].x, pts[i].y, pts[i].z) + t;
        const Vec3d p = K * c;
        const Point px(cvRound(p[0] / p[2]), cvRound(p[1] / p[2]));
        ASSERT_TRUE(Rect(0, 0, 640, 480).contains(px));
        EXPECT_EQ(px.x % 2, 0);
        EXPECT_EQ(px.y % 2, 0);
        EXPECT_NEAR(c[2], d.at<ushort>(px), 1e-3);
    }
    EXPECT_THROW(modelPointsFromDepth(Mat(), K, R, t), cv::Exception);
    EXPECT_THROW(modelPointsFromDepth(Mat(4, 4, CV_32FC1), K, R, t), cv::Exception);
}

// ---- depth check ----------------------------------------------------------------------------

TEST(Forestmod_Pose, depth_agreement_counts_object_pixels_within_tolerance)
{
    MeshRenderer mr(apeMesh(), Size(640, 480));
    const Matx33d K = lmoIntrinsics();
    const Size size(640, 480);
    RNG rng(17);
    const Matx33d R = uniformRotation(rng);
    const Vec3d t(0, 0, 750);
    Mat rendered = mr.depth16(R, t, K);
    double occluded = 0;
    Mat clean = makeScene(mr, R, t, K, size, 0.0, rng);
    Mat occl = makeScene(mr, R, t, K, size, 0.3, rng, &occluded);
    const double tol = 0.05 * kApeDiameter;
    const double a_clean = depthAgreement(rendered, clean, tol);
    const double a_occl = depthAgreement(rendered, occl, tol);
    std::cout << "depth agreement: clean " << a_clean << ", occluded " << occluded << ": "
              << a_occl << std::endl;
    EXPECT_GT(a_clean, 0.97);
    EXPECT_NEAR(a_occl, 1.0 - occluded, 0.05);
    // a hypothesis 3 cm too far: almost nothing agrees
    Mat far = mr.depth16(R, t + Vec3d(0, 0, 30), K);
    EXPECT_LT(depthAgreement(far, clean, tol), 0.1);
    EXPECT_LT(depthCheck(*mr.renderer, mr.handle, clean, K, R, t + Vec3d(0, 0, 30), tol), 0.1);
    EXPECT_DOUBLE_EQ(depthCheck(*mr.renderer, mr.handle, occl, K, R, t, tol), a_occl);
    EXPECT_THROW(depthCheck(*mr.renderer, mr.handle, Mat(240, 320, CV_16UC1, Scalar(1)), K, R, t,
                            tol), cv::Exception);
    // no scene measurement at all: 0
    EXPECT_EQ(depthAgreement(rendered, Mat(size, CV_16UC1, Scalar(0)), tol), 0.0);
    EXPECT_THROW(depthAgreement(rendered, Mat(240, 320, CV_16UC1, Scalar(1)), tol), cv::Exception);
    EXPECT_THROW(depthAgreement(rendered, Mat(size, CV_32FC1, Scalar(1)), tol), cv::Exception);
    EXPECT_THROW(depthAgreement(rendered, clean, 0.0), cv::Exception);
}

// ---- metrics --------------------------------------------------------------------------------

TEST(Forestmod_Pose, add_of_a_pure_translation_is_its_length)
{
    const Mesh& mesh = apeMesh();
    RNG rng(1);
    const Matx33d R = uniformRotation(rng);
    const Vec3d t(10, 20, 800), v(3, -4, 12);
    EXPECT_NEAR(addError(mesh.vertices, R, t + v, R, t), 13.0, 1e-9);
    EXPECT_NEAR(addError(mesh.vertices, R, t, R, t), 0.0, 1e-12);
    const double adi = adiError(mesh.vertices, R, t + v, R, t);
    EXPECT_LE(adi, 13.0 + 1e-9);
    EXPECT_GT(adi, 1.0);
    EXPECT_THROW(addError(std::vector<Point3f>(), R, t, R, t), cv::Exception);
    EXPECT_THROW(adiError(std::vector<Point3f>(), R, t, R, t), cv::Exception);
}

// The pose errors of an estimate that moves a model point to a non-finite one are NaN (the k-d
// tree's nearest point had made ADI finite); such a ground truth, or a non-finite model point, is
// refused.
TEST(Forestmod_Pose, errors_of_non_finite_poses)
{
    const Mesh& mesh = apeMesh();
    const Matx33d R = Matx33d::eye(), K(600, 0, 320, 0, 600, 240, 0, 0, 1);
    const Vec3d t(10, 20, 800);
    const double nan = std::numeric_limits<double>::quiet_NaN();
    const Vec3d t_nan(nan, 0, 800);
    Matx33d R_inf = R;
    R_inf(1, 2) = std::numeric_limits<double>::infinity();
    EXPECT_TRUE(cvIsNaN(addError(mesh.vertices, R, t_nan, R, t)));
    EXPECT_TRUE(cvIsNaN(adiError(mesh.vertices, R, t_nan, R, t)));
    EXPECT_TRUE(cvIsNaN(adiError(mesh.vertices, R_inf, t, R, t)));
    EXPECT_TRUE(cvIsNaN(projectionError2D(mesh.vertices, K, R_inf, t, R, t)));
    EXPECT_THROW(addError(mesh.vertices, R, t, R, t_nan), cv::Exception);
    EXPECT_THROW(adiError(mesh.vertices, R, t, R_inf, t), cv::Exception);
    EXPECT_THROW(projectionError2D(mesh.vertices, K, R, t, R, t_nan), cv::Exception);
    std::vector<Point3f> pts = mesh.vertices;
    pts[5].y = std::numeric_limits<float>::quiet_NaN();
    EXPECT_THROW(adiError(pts, R, t, R, t), cv::Exception);
    // finite entries whose products overflow: the same
    Matx33d R_huge = R;
    R_huge(0, 1) = 1e308;
    EXPECT_TRUE(cvIsNaN(adiError(mesh.vertices, R_huge, t, R, t)));
    EXPECT_TRUE(cvIsNaN(addError(mesh.vertices, R_huge, t, R, t)));
    EXPECT_THROW(adiError(mesh.vertices, R, t, R_huge, t), cv::Exception);
    EXPECT_NEAR(0.0, adiError(mesh.vertices, R, t, R, t), 1e-9);
}

TEST(Forestmod_Pose, adi_equals_brute_force_nearest_neighbour)
{
    RNG rng(2);
    std::vector<Point3f> pts(2000);
    for (size_t i = 0; i < pts.size(); ++i)
        pts[i] = Point3f((float)rng.uniform(-50.0, 50.0), (float)rng.uniform(-30.0, 30.0),
                         (float)rng.gaussian(20.0));
    for (int k = 0; k < 3; ++k)
    {
        const Matx33d Rg = uniformRotation(rng), Re = randomRotation(rng, 0.3 * k) * Rg;
        const Vec3d tg(0, 0, 700), te = tg + Vec3d(k * 5.0, -k * 3.0, k * 40.0);
        double brute = 0;
        for (size_t i = 0; i < pts.size(); ++i)
        {
            const Vec3d e = Re * Vec3d(pts[i].x, pts[i].y, pts[i].z) + te;
            double best = DBL_MAX;
            for (size_t j = 0; j < pts.size(); ++j)
                best = std::min(best, cv::norm(e - (Rg * Vec3d(pts[j].x, pts[j].y, pts[j].z) + tg)));
            brute += best;
        }
        brute /= (double)pts.size();
        EXPECT_NEAR(adiError(pts, Re, te, Rg, tg), brute, 1e-9 * (1 + brute));
    }
}

TEST(Forestmod_Pose, adi_is_zero_under_symmetry_synthetic)
{
    // a box sampled on a grid that is symmetric under a half turn about z
    std::vector<Point3f> pts;
    for (int x = -30; x <= 30; x += 3)
        for (int y = -15; y <= 15; y += 3)
            for (int z = -10; z <= 10; z += 20)
                pts.push_back(Point3f((float)x, (float)y, (float)z));
    const double diameter = std::sqrt(60.0 * 60 + 30 * 30 + 20 * 20);
    RNG rng(4);
    const Matx33d Rg = uniformRotation(rng);
    const Vec3d tg(20, -10, 600);
    const Matx33d S(-1, 0, 0, 0, -1, 0, 0, 0, 1); // the symmetry
    const Matx33d Re = Rg * S;
    const double adi = adiError(pts, Re, tg, Rg, tg), add = addError(pts, Re, tg, Rg, tg);
    EXPECT_LT(adi, 1e-6);
    EXPECT_GT(add, 0.1 * diameter);
    EXPECT_TRUE(isCorrect(adi, diameter));
    EXPECT_FALSE(isCorrect(add, diameter));
}

TEST(Forestmod_Pose, adi_is_near_zero_for_eggbox_turned_by_its_symmetry)
{
    const std::string root = sharedDataPath();
    if (root.empty())
        throw SkipTestException("FORESTMOD_SHARED_DATA (../shared/data with lmo/) is not available: "
                                "the synthetic symmetric mesh test covers ADI");
    BopDataset ds = BopDataset::open(root + "/lmo");
    const ModelInfo egg = ds.model(10);
    ASSERT_TRUE(egg.symmetric);
    ASSERT_FALSE(egg.symmetries_discrete.empty());
    const Mesh mesh = Mesh::load(egg.mesh_path);
    const Matx44d S = egg.symmetries_discrete[0];
    const Matx33d Rs(S(0, 0), S(0, 1), S(0, 2), S(1, 0), S(1, 1), S(1, 2), S(2, 0), S(2, 1), S(2, 2));
    const Vec3d ts(S(0, 3), S(1, 3), S(2, 3));
    RNG rng(6);
    const Matx33d Rg = uniformRotation(rng);
    const Vec3d tg(0, 0, 900);
    // estimate = ground truth composed with the symmetry: x -> Rg (Rs x + ts) + tg
    const Matx33d Re = Rg * Rs;
    const Vec3d te = Rg * ts + tg;
    const double adi = adiError(mesh.vertices, Re, te, Rg, tg);
    const double add = addError(mesh.vertices, Re, te, Rg, tg);
    std::cout << "eggbox (d = " << egg.diameter << " mm) turned by its symmetry: ADI " << adi
              << " mm, ADD " << add << " mm" << std::endl;
    EXPECT_LT(adi, 0.02 * egg.diameter);
    EXPECT_GT(add, 0.1 * egg.diameter);
}

TEST(Forestmod_Pose, projection_error_and_box_iou)
{
    // points on a fronto-parallel plane at z = 500, moved by 2 mm in x: f * 2 / 500 pixels
    std::vector<Point3f> pts;
    for (int i = 0; i < 20; ++i)
        pts.push_back(Point3f((float)(i * 3 - 30), (float)(i % 7 - 3), 0.f));
    const Matx33d K = lmoIntrinsics(), I = Matx33d::eye();
    const Vec3d t(0, 0, 500);
    EXPECT_NEAR(projectionError2D(pts, K, I, t + Vec3d(2, 0, 0), I, t), K(0, 0) * 2 / 500, 1e-9);
    EXPECT_NEAR(projectionError2D(pts, K, I, t, I, t), 0.0, 1e-12);
    EXPECT_TRUE(cvIsInf(projectionError2D(pts, K, I, Vec3d(0, 0, -100), I, t)));

    EXPECT_DOUBLE_EQ(boxIoU(Rect2d(0, 0, 10, 10), Rect2d(0, 0, 10, 10)), 1.0);
    EXPECT_DOUBLE_EQ(boxIoU(Rect2d(0, 0, 10, 10), Rect2d(5, 0, 10, 10)), 50.0 / 150.0);
    EXPECT_DOUBLE_EQ(boxIoU(Rect2d(0, 0, 10, 10), Rect2d(20, 20, 5, 5)), 0.0);
    EXPECT_DOUBLE_EQ(boxIoU(Rect2d(0, 0, 0, 10), Rect2d(0, 0, 10, 10)), 0.0);

    EXPECT_TRUE(isCorrect(9.9, 100));
    EXPECT_FALSE(isCorrect(10.0, 100));
    EXPECT_TRUE(isCorrect(19.0, 100, 0.2));
    EXPECT_THROW(isCorrect(1.0, 0.0), cv::Exception);
}

// ---- parameters and bad input ---------------------------------------------------------------

TEST(Forestmod_Pose, icp_params_roundtrip_and_validation)
{
    ICPParams p;
    p.max_iterations = 17;
    p.max_correspondence_distance = 42.5;
    p.tukey_c_coarse = 2.0;
    p.max_points = 123;
    p.early_pass_points = 45;
    p.min_ray_cosine = 0.25;
    p.max_stalled_iterations = 9;
    FileStorage fs("icp.yml", FileStorage::WRITE | FileStorage::MEMORY);
    fs << "icp" << "{";
    p.write(fs);
    fs << "}";
    const std::string text = fs.releaseAndGetString();
    FileStorage in(text, FileStorage::READ | FileStorage::MEMORY);
    ICPParams q;
    q.read(in["icp"]);
    EXPECT_EQ(q.max_iterations, 17);
    EXPECT_EQ(q.max_correspondence_distance, 42.5);
    EXPECT_EQ(q.tukey_c_coarse, 2.0);
    EXPECT_EQ(q.max_points, 123);
    EXPECT_EQ(q.early_pass_points, 45);
    EXPECT_EQ(q.min_ray_cosine, 0.25);
    EXPECT_EQ(q.max_stalled_iterations, 9);
    EXPECT_EQ(q.normal_radius, ICPParams().normal_radius);

    const std::vector<Point3f> pts(100, Point3f(0, 0, 0));
    const Mat depth(48, 64, CV_16UC1, Scalar(500));
    const Matx33d K = lmoIntrinsics(), I = Matx33d::eye();
    const Vec3d t(0, 0, 500);
    ICPParams bad;
    bad.max_iterations = 0;
    EXPECT_THROW(refineICP(pts, depth, K, I, t, bad), cv::Exception);
    bad = ICPParams();
    bad.min_correspondence_distance = 2 * bad.max_correspondence_distance;
    EXPECT_THROW(refineICP(pts, depth, K, I, t, bad), cv::Exception);
    bad = ICPParams();
    bad.max_stalled_iterations = -1;
    EXPECT_THROW(refineICP(pts, depth, K, I, t, bad), cv::Exception);
    EXPECT_THROW(refineICP(pts, Mat(), K, I, t), cv::Exception);
    EXPECT_THROW(refineICP(pts, Mat(48, 64, CV_32FC1, Scalar(0.5)), K, I, t), cv::Exception);
    EXPECT_THROW(refineICP(std::vector<Point3f>(5), depth, K, I, t), cv::Exception);
    EXPECT_THROW(refineICP(pts, depth, K, 2.0 * I, t), cv::Exception);
    EXPECT_THROW(refineICP(pts, depth, Matx33d::zeros(), I, t), cv::Exception);
    // nothing to align with (all points in one spot, far from the scene): not converged, pose kept
    ICPResult r = refineICP(pts, depth, K, I, Vec3d(0, 0, 100));
    EXPECT_FALSE(r.converged);
    EXPECT_EQ(r.fitness, 0.0);
    EXPECT_EQ(cv::norm(r.t - Vec3d(0, 0, 100)), 0.0);
}

TEST(Forestmod_Pose, initial_pose_rejects_bad_input)
{
    Matx33d R;
    Vec3d t;
    const Matx33d K = lmoIntrinsics(), I = Matx33d::eye();
    EXPECT_THROW(initialPose(I, Vec3d(0, 0, -5), K, Point2d(1, 1), K, Point2d(1, 1), 0, R, t),
                 cv::Exception);
    EXPECT_THROW(initialPose(I, Vec3d(0, 0, 500), Matx33d::zeros(), Point2d(1, 1), K,
                             Point2d(1, 1), 0, R, t), cv::Exception);
    EXPECT_THROW(initialPose(I, Vec3d(0, 0, 500), K, Point2d(1, 1), K,
                             Point2d(std::numeric_limits<double>::quiet_NaN(), 1), 0, R, t),
                 cv::Exception);
    // same pixel, same camera: the template pose itself
    initialPose(I, Vec3d(5, 6, 500), K, Point2d(100, 100), K, Point2d(100, 100), 0, R, t);
    EXPECT_LT(cv::norm(Mat(R), Mat(I)), 1e-12);
    EXPECT_LT(cv::norm(t - Vec3d(5, 6, 500)), 1e-9);
}

} // namespace
} // namespace opencv_test

namespace opencv_test {
namespace {
using namespace pose_test;

// Not a test: the figures of doc/pose.md (run with --gtest_also_run_disabled_tests
// --gtest_filter='Forestmod_Pose.DISABLED_icp_*'): 200 trials of each test's scenario with the
// defaults, and an ablation of the ICP choices on 100 + 100 trials.
static void icpStatistics(MeshRenderer& mr, const ICPParams& p, int trials, const char* name)
{
    for (int occluded = 0; occluded < 2; ++occluded)
    {
        RNG rng(occluded ? 2718 : 1414);
        int good = 0, good_1 = 0, add_ok = 0;
        std::vector<double> rot, trans, add;
        for (int i = 0; i < trials; ++i)
        {
            IcpTrial tr = runIcpTrial(mr, rng, occluded ? 0.3 : 0.0, p);
            rot.push_back(tr.rot_err_deg);
            trans.push_back(tr.trans_err_mm);
            add.push_back(tr.add_mm);
            good += tr.rot_err_deg <= 0.5 && tr.trans_err_mm <= 1.0;
            good_1 += tr.rot_err_deg_1 <= 0.5 && tr.trans_err_mm_1 <= 1.0;
            add_ok += isCorrect(tr.add_mm, kApeDiameter);
        }
        printf("| %s | %s | %d/%d | %d/%d | %d/%d | %.3f | %.3f | %.3f |\n", name,
               occluded ? "30 % occluded" : "no clutter", good, trials, good_1, trials, add_ok,
               trials, medianOf(rot), medianOf(trans), medianOf(add));
    }
}

TEST(Forestmod_Pose, DISABLED_icp_statistics)
{
    MeshRenderer mr(apeMesh(), Size(640, 480));
    icpStatistics(mr, ICPParams(), 200, "defaults");
}

TEST(Forestmod_Pose, DISABLED_icp_ablation)
{
    MeshRenderer mr(apeMesh(), Size(640, 480));
    const int n = 100;
    ICPParams p;
    icpStatistics(mr, p, n, "defaults");
    p = ICPParams();
    p.search_radius = 2;
    icpStatistics(mr, p, n, "search_radius 2");
    p = ICPParams();
    p.max_rotation_step = 1.0;
    icpStatistics(mr, p, n, "no rotation trust region");
    p = ICPParams();
    p.tukey_c_coarse = p.tukey_c;
    icpStatistics(mr, p, n, "no coarse Tukey phase");
    p = ICPParams();
    p.min_ray_cosine = 1.0;
    icpStatistics(mr, p, n, "unweighted (min_ray_cosine 1)");
    p = ICPParams();
    p.max_points = 1000;
    icpStatistics(mr, p, n, "max_points 1000");
}

} // namespace
} // namespace opencv_test
