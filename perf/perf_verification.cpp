// This file is part of OpenCV project.
// It is subject to the license terms in the LICENSE file found in the top-level directory
// of this distribution and at http://opencv.org/license.html

#include "perf_precomp.hpp"
#include "../test/test_pose_common.hpp" // scene helpers shared with the accuracy tests

namespace opencv_test { namespace {

using namespace pose_test;

// Detector::verify() of 10 hypotheses of one class (VerificationParams::top_k, the default) on a
// VGA frame, as detect() runs it: the rendered ape pasted on a real LM-O frame at the param's
// distance (mm), one hypothesis started at its pose and 9 elsewhere in the frame at poses turned
// 10-40 degrees, each refined by choosePoses() outside the loop (the verification scores the
// drawings that the refinement left, on the frame's edge maps that it made). Time per call.
typedef perf::TestBaseWithParam<int> Forestmod_Verify;
PERF_TEST_P(Forestmod_Verify, ten_hypotheses_VGA, testing::Values(500, 800))
{
    const Mesh ape = Mesh::load(cvtest::findDataFile("lmo_mini/models/obj_000001.ply"));
    MeshRenderer mr(ape, Size(640, 480));
    const Matx33d K = lmoIntrinsics();
    Matx33d R;
    Vec3d t;
    const Mat img = pastedOnRealFrame(mr, K, GetParam(), R, t);
    cv::forestmod::Detector det;
    det.setMesh("ape", ape);
    std::vector<std::vector<PoseMatch> > locations;
    RNG rng(9);
    const Vec3d c = R * Vec3d(ape.center().x, ape.center().y, ape.center().z) + t;
    for (int i = 0; i < 10; ++i)
    {
        Matx33d Ri = R;
        Vec3d ti = t;
        if (i != 5)
        {
            const Matx33d dR = randomRotation(rng, (10.0 + 30.0 * i / 9) * CV_PI / 180);
            const Vec3d shift(c[2] * rng.uniform(-0.3, 0.3), c[2] * rng.uniform(-0.2, 0.2), 0);
            Ri = dR * R;
            ti = dR * (t - c) + c + shift;
        }
        PoseMatch m = matchAtPose(ape, K, Ri, ti);
        m.similarity = 95.f - i; // the object is not the first by similarity
        locations.push_back(std::vector<PoseMatch>(1, m));
    }
    PoseParams pose_params;
    // as detect(): every verified detection has a pose
    pose_params.max_per_class = VerificationParams().top_k;
    const VerificationParams& params = pose_params.verification;
    EdgeMaps maps;
    computeEdgeMaps(img, maps, pose_params.edge_params);
    std::vector<PoseMatch> hypotheses;
    det.choosePoses(K, locations, pose_params, img, hypotheses, maps);
    ASSERT_EQ(locations.size(), hypotheses.size());
    for (size_t i = 0; i < hypotheses.size(); ++i)
        ASSERT_TRUE(hypotheses[i].refined && !hypotheses[i].drawing.empty()) << i;
    std::vector<PoseMatch> ranked;
    TEST_CYCLE()
    {
        ranked = hypotheses;
        det.verify(img, noArray(), K, ranked, params, 0, maps);
    }
    ASSERT_EQ(hypotheses.size(), ranked.size());
    ASSERT_GE(ranked[0].verification, 0.0);
    // the hypothesis refined from the object's pose comes first
    EXPECT_LT(projectionError2D(ape.vertices, K, ranked[0].R, ranked[0].t, R, t), 2.0);
    SANITY_CHECK_NOTHING();
}

}} // namespace
