// This file is part of OpenCV project.
// It is subject to the license terms in the LICENSE file found in the top-level directory
// of this distribution and at http://opencv.org/license.html

// Detector::estimatePoses / detect: a 6-DoF pose per match, refined by ICP with depth.

#include "test_precomp.hpp"

namespace opencv_test { namespace {

static Matx33d lmoK()
{
    return Matx33d(572.4114, 0, 325.2611, 0, 573.57043, 242.04899, 0, 0, 1);
}

TEST(Forestmod_DetectorPose, rgbd_scenes_give_correct_poses)
{
    const Mesh ape = Mesh::load(cvtest::findDataFile("lmo_mini/models/obj_000001.ply"));
    const double diameter = ape.diameter();
    ViewSampler::Params sp;
    sp.level = 1;
    sp.min_elevation = 15;
    sp.radii = std::vector<double>(1, 800.0);
    sp.inplane_min = -20;
    sp.inplane_max = 20;
    sp.inplane_step = 20;
    const ViewSampler sampler(sp);
    Ptr<cv::forestmod::Detector> det = getDefaultForestLINEMOD();
    ASSERT_GT(det->addTemplates(ape, "ape", sampler, lmoK(), Size(640, 480)), 0);
    ASSERT_TRUE(det->hasMesh("ape"));
    det->train();

    Ptr<Renderer> renderer = Renderer::create(Size(640, 480));
    SyntheticSceneParams ssp;
    ssp.max_perturbation_deg = 10; // poses between templates (16 degrees apart)
    SceneSynthesizer synth(renderer, lmoK(), ssp);
    synth.addObject(ape);
    std::vector<Mat> bg(1, imread(cvtest::findDataFile("lmo_mini/test/000002/rgb/000902.png")));
    synth.setBackgrounds(bg);
    const std::vector<ViewPose> views = sampler.poses(Point3d(ape.center().x, ape.center().y,
                                                              ape.center().z));
    std::vector<Point3f> pts(ape.vertices.begin(), ape.vertices.end());
    RNG rng(5);
    const int scenes = 10;
    int correct = 0, rgb_close = 0, rgb_n = 0;
    double rgb_err = 0, rgb_err_unrefined = 0;
    for (int k = 0; k < scenes; ++k)
    {
        const ViewPose& v = views[rng.uniform(0, (int)views.size())];
        const SyntheticScene scene = synth.render(0, v.R, v.t, rng);
        std::vector<Mat> src;
        src.push_back(scene.color);
        src.push_back(scene.depth);
        src.push_back(scene.color);
        std::vector<PoseMatch> matches;
        det->detect(src, lmoK(), 80.f, matches);
        if (matches.empty())
            continue;
        ASSERT_TRUE(matches[0].has_pose);
        const double add = addError(pts, matches[0].R, matches[0].t, scene.R, scene.t);
        correct += matches[0].refined && isCorrect(add, diameter, 0.1);
        EXPECT_GE(matches[0].depth_agreement, 0.5);

        // RGB only: the initial pose projects the object centre near the truth; refined by
        // rendering, the 2D projection error is under 5 px more often
        std::vector<PoseMatch> rgb, initial;
        det->match(src, 80.f, rgb);
        initial = rgb;
        det->estimatePoses(noArray(), lmoK(), initial);
        det->estimatePoses(noArray(), lmoK(), rgb, PoseParams(), scene.color);
        if (!initial.empty() && initial[0].has_pose)
        {
            EXPECT_FALSE(initial[0].refined);
            EXPECT_TRUE(rgb[0].refined);
            const Vec3d c = lmoK() * (initial[0].R * Vec3d(ape.center().x, ape.center().y,
                                                           ape.center().z) + initial[0].t);
            rgb_close += cv::norm(Point2d(c[0] / c[2], c[1] / c[2]) - scene.center) < 10.0;
            rgb_err_unrefined += projectionError2D(pts, lmoK(), initial[0].R, initial[0].t,
                                                   scene.R, scene.t);
            rgb_err += projectionError2D(pts, lmoK(), rgb[0].R, rgb[0].t, scene.R, scene.t);
            ++rgb_n;
        }
    }
    EXPECT_GE(correct, scenes - 1);
    EXPECT_GE(rgb_close, scenes - 1);
    ASSERT_GE(rgb_n, scenes - 1);
    std::cout << "[ INFO    ] RGB only, mean 2D projection error: " << rgb_err_unrefined / rgb_n
              << " px from the template, " << rgb_err / rgb_n << " px refined by edge alignment (refinePoseEdges)"
              << std::endl;
    EXPECT_LT(rgb_err, 0.5 * rgb_err_unrefined); // measured 3.3 -> 0.67 px
}

TEST(Forestmod_DetectorPose, bad_input_raises)
{
    Ptr<cv::forestmod::Detector> det = getDefaultForestLINE();
    std::vector<PoseMatch> m(1);
    EXPECT_THROW(det->estimatePoses(Mat(480, 640, CV_32F), lmoK(), m), cv::Exception);
    EXPECT_THROW(det->estimatePoses(noArray(), Matx33d::zeros(), m), cv::Exception);
    PoseParams p;
    p.icp_passes = 0;
    EXPECT_THROW(det->estimatePoses(noArray(), lmoK(), m, p), cv::Exception);
    Mesh empty;
    EXPECT_THROW(det->setMesh("x", empty), cv::Exception);
}

}} // namespace
