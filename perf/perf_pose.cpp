// This file is part of OpenCV project.
// It is subject to the license terms in the LICENSE file found in the top-level directory
// of this distribution and at http://opencv.org/license.html

#include "perf_precomp.hpp"
#include "../test/test_pose_common.hpp" // scene helpers shared with the accuracy tests

namespace opencv_test { namespace {

using namespace pose_test;

/** Hypotheses of the ape on VGA Kinect-like depth: scene (ape in front of a table plane, sensor
noise), ground truth, and a start 5 degrees / 10 mm off. */
struct Hypotheses
{
    explicit Hypotheses(int n)
        : mr(Mesh::load(cvtest::findDataFile("lmo_mini/models/obj_000001.ply")), Size(640, 480)),
          K(lmoIntrinsics())
    {
        RNG rng(123);
        for (int i = 0; i < n; ++i)
        {
            const double z = rng.uniform(500.0, 1000.0);
            const Vec3d t(z * rng.uniform(-0.2, 0.2), z * rng.uniform(-0.15, 0.15), z);
            const Matx33d R = uniformRotation(rng);
            Mat scene32 = mr.depth32(R, t, K);
            scene32.setTo(Scalar(t[2] + 120), scene32 == 0);
            scenes.push_back(sensorNoise(scene32, rng));
            Vec3d dir(rng.gaussian(1), rng.gaussian(1), rng.gaussian(1));
            dir /= cv::norm(dir);
            R_gt.push_back(R);
            t_gt.push_back(t);
            R0.push_back(randomRotation(rng, 5.0 * CV_PI / 180) * R);
            t0.push_back(t + 10.0 * dir);
            Mat d = mr.depth16(R0.back(), t0.back(), K);
            model_points.push_back(modelPointsFromDepth(d, K, R0.back(), t0.back()));
        }
    }
    MeshRenderer mr;
    Matx33d K;
    std::vector<Mat> scenes;
    std::vector<Matx33d> R_gt, R0;
    std::vector<Vec3d> t_gt, t0;
    std::vector<std::vector<Point3f> > model_points;
};

// One ICP pass on VGA depth, model points given (the visible surface rendered at the start pose;
// default ICPParams: up to 4000 points, 30 iterations). Time per hypothesis.
PERF_TEST(Forestmod_Pose, refineICP_one_pass_VGA)
{
    Hypotheses h(16);
    size_t i = 0;
    ICPResult res;
    double add_sum = 0;
    int runs = 0;
    TEST_CYCLE()
    {
        res = refineICP(h.model_points[i], h.scenes[i], h.K, h.R0[i], h.t0[i]);
        add_sum += addError(h.mr.mesh.vertices, res.R, res.t, h.R_gt[i], h.t_gt[i]);
        ++runs;
        i = (i + 1) % h.scenes.size();
    }
    ASSERT_LT(add_sum / runs, 0.1 * 102.099);
    SANITY_CHECK_NOTHING();
}

// What a detector runs per hypothesis: refinePose with 2 passes (render the visible surface at
// the current pose with the Renderer, back-project, ICP; twice).
PERF_TEST(Forestmod_Pose, refinePose_two_passes_VGA)
{
    Hypotheses h(16);
    size_t i = 0;
    ICPResult res;
    double add_sum = 0;
    int runs = 0;
    TEST_CYCLE()
    {
        res = refinePose(*h.mr.renderer, h.mr.handle, h.scenes[i], h.K, h.R0[i], h.t0[i]);
        add_sum += addError(h.mr.mesh.vertices, res.R, res.t, h.R_gt[i], h.t_gt[i]);
        ++runs;
        i = (i + 1) % h.scenes.size();
    }
    ASSERT_LT(add_sum / runs, 0.1 * 102.099);
    SANITY_CHECK_NOTHING();
}

// Without depth: the scene's edge maps (once per frame) on a real LM-O VGA frame.
PERF_TEST(Forestmod_Pose, computeEdgeMaps_VGA)
{
    const Mat img = imread(cvtest::findDataFile("lmo_mini/test/000002/rgb/000902.png"));
    ASSERT_FALSE(img.empty());
    EdgeMaps maps;
    TEST_CYCLE() computeEdgeMaps(img, maps);
    ASSERT_EQ((size_t)EdgeRefineParams().orientations, maps.distance.size());
    SANITY_CHECK_NOTHING();
}

// Without depth: refinePoseEdges of one hypothesis (the rendered ape pasted on a real frame,
// start 10 degrees / 10 mm off; default EdgeRefineParams: the start and 3 grid poses refined).
PERF_TEST(Forestmod_Pose, refinePoseEdges_VGA)
{
    MeshRenderer mr(Mesh::load(cvtest::findDataFile("lmo_mini/models/obj_000001.ply")),
                    Size(640, 480));
    const Matx33d K = lmoIntrinsics();
    Matx33d R;
    Vec3d t;
    const Mat img = pastedOnRealFrame(mr, K, 750, R, t);
    EdgeMaps maps;
    computeEdgeMaps(img, maps);
    RNG rng(7);
    const Vec3d c = R * Vec3d(mr.mesh.center().x, mr.mesh.center().y, mr.mesh.center().z) + t;
    const Matx33d dR = randomRotation(rng, 10.0 * CV_PI / 180);
    const Matx33d R0 = dR * R;
    const Vec3d t0 = dR * (t - c) + c + Vec3d(5, -5, 5);
    EdgeRefineResult res;
    TEST_CYCLE() res = refinePoseEdges(*mr.renderer, mr.handle, maps, K, R0, t0);
    ASSERT_LT(projectionError2D(mr.mesh.vertices, K, res.R, res.t, R, t), 2.0);
    SANITY_CHECK_NOTHING();
}

// Without depth: Detector::choosePoses of one location of 16 matches (the rendered ape pasted on a
// real frame; the matches' poses turned 4-40 degrees from the truth), the param being
// PoseParams::rgb_keep: 4 (the default) refines the 4 best fits after the first pass to the end,
// 16 every match. The frame's edge maps are made once, outside the loop. Time per location.
typedef perf::TestBaseWithParam<int> Forestmod_ChoosePoses;
PERF_TEST_P(Forestmod_ChoosePoses, ape_16_matches_VGA, testing::Values(2, 4, 16))
{
    const Mesh ape = Mesh::load(cvtest::findDataFile("lmo_mini/models/obj_000001.ply"));
    MeshRenderer mr(ape, Size(640, 480));
    const Matx33d K = lmoIntrinsics();
    Matx33d R;
    Vec3d t;
    const Mat img = pastedOnRealFrame(mr, K, 750, R, t);
    cv::forestmod::Detector det;
    det.setMesh("ape", ape);
    RNG rng(8);
    const Vec3d c = R * Vec3d(ape.center().x, ape.center().y, ape.center().z) + t;
    std::vector<std::vector<PoseMatch> > location(1);
    for (int i = 0; i < 16; ++i)
    {
        const Matx33d dR = randomRotation(rng, (4.0 + 36.0 * i / 15) * CV_PI / 180);
        location[0].push_back(matchAtPose(ape, K, dR * R, dR * (t - c) + c));
    }
    PoseParams params;
    params.rgb_hypotheses = 16;
    params.rgb_keep = GetParam();
    EdgeMaps maps;
    computeEdgeMaps(img, maps, params.edge_params);
    std::vector<PoseMatch> chosen;
    TEST_CYCLE() det.choosePoses(K, location, params, img, chosen, maps);
    ASSERT_EQ(1u, chosen.size());
    ASSERT_TRUE(chosen[0].refined);
    ASSERT_LT(projectionError2D(ape.vertices, K, chosen[0].R, chosen[0].t, R, t), 2.0);
    SANITY_CHECK_NOTHING();
}

// The depth check of one hypothesis (render + compare) on VGA.
PERF_TEST(Forestmod_Pose, depthCheck_VGA)
{
    Hypotheses h(4);
    size_t i = 0;
    double agreement = 0;
    TEST_CYCLE()
    {
        agreement = depthCheck(*h.mr.renderer, h.mr.handle, h.scenes[i], h.K, h.R_gt[i], h.t_gt[i],
                               5.0);
        i = (i + 1) % h.scenes.size();
    }
    ASSERT_GT(agreement, 0.9);
    SANITY_CHECK_NOTHING();
}

// ADI (k-d tree nearest neighbours) on 10 000 model points.
PERF_TEST(Forestmod_Pose, adi_10000_points)
{
    RNG rng(9);
    std::vector<Point3f> pts(10000);
    for (size_t i = 0; i < pts.size(); ++i)
        pts[i] = Point3f((float)rng.uniform(-50.0, 50.0), (float)rng.uniform(-40.0, 40.0),
                         (float)rng.uniform(-45.0, 45.0));
    const Matx33d Rg = uniformRotation(rng), Re = randomRotation(rng, 0.1) * Rg;
    const Vec3d tg(0, 0, 800), te(3, -2, 805);
    double adi = 0;
    TEST_CYCLE()
    {
        adi = adiError(pts, Re, te, Rg, tg);
    }
    ASSERT_GT(adi, 0.0);
    ASSERT_LE(adi, addError(pts, Re, te, Rg, tg));
    SANITY_CHECK_NOTHING();
}

}} // namespace
