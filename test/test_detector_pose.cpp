// This file is part of OpenCV project.
// It is subject to the license terms in the LICENSE file found in the top-level directory
// of this distribution and at http://opencv.org/license.html

// Detector::estimatePoses / detect: a 6-DoF pose per match, refined by ICP with depth and by edge
// alignment without.

#include "test_precomp.hpp"

namespace opencv_test { namespace {

/** The ape's templates between 15 and 90 degrees of elevation at 800 mm (views ~30 degrees
apart, in-plane -20..20) in a detector `det` with its mesh, and a synthesizer of scenes with the
ape up to 10 degrees off those views over a real LM-O frame. */
struct ApeScenes
{
    explicit ApeScenes(const Ptr<cv::forestmod::Detector>& d)
        : ape(Mesh::load(cvtest::findDataFile("lmo_mini/models/obj_000001.ply"))), det(d)
    {
        ViewSampler::Params sp;
        sp.level = 1;
        sp.min_elevation = 15;
        sp.radii = std::vector<double>(1, 800.0);
        sp.inplane_min = -20;
        sp.inplane_max = 20;
        sp.inplane_step = 20;
        const ViewSampler sampler(sp);
        CV_Assert(det->addTemplates(ape, "ape", sampler, lmoIntrinsics(), Size(640, 480)) > 0);
        det->train();
        SyntheticSceneParams ssp;
        ssp.max_perturbation_deg = 10; // poses between templates
        synth = makePtr<SceneSynthesizer>(Renderer::create(Size(640, 480)), lmoIntrinsics(), ssp);
        synth->addObject(ape);
        synth->setBackgrounds(std::vector<Mat>(
            1, imread(cvtest::findDataFile("lmo_mini/test/000002/rgb/000902.png"))));
        views = sampler.poses(Point3d(ape.center().x, ape.center().y, ape.center().z));
    }
    SyntheticScene render(RNG& rng) const
    {
        const ViewPose& v = views[rng.uniform(0, (int)views.size())];
        return synth->render(0, v.R, v.t, rng);
    }
    Mesh ape;
    Ptr<cv::forestmod::Detector> det;
    Ptr<SceneSynthesizer> synth;
    std::vector<ViewPose> views;
};

TEST(Forestmod_DetectorPose, rgbd_scenes_give_correct_poses)
{
    const ApeScenes as(getDefaultForestLINEMOD());
    const Mesh& ape = as.ape;
    const Ptr<cv::forestmod::Detector>& det = as.det;
    ASSERT_TRUE(det->hasMesh("ape"));
    const double diameter = ape.diameter();
    std::vector<Point3f> pts(ape.vertices.begin(), ape.vertices.end());
    RNG rng(5);
    const int scenes = 10;
    int correct = 0, rgb_close = 0, rgb_n = 0;
    double rgb_err = 0, rgb_err_unrefined = 0;
    for (int k = 0; k < scenes; ++k)
    {
        const SyntheticScene scene = as.render(rng);
        std::vector<Mat> src;
        src.push_back(scene.color);
        src.push_back(scene.depth);
        src.push_back(scene.color);
        std::vector<PoseMatch> matches;
        det->detect(src, lmoIntrinsics(), 80.f, matches);
        if (matches.empty())
            continue;
        ASSERT_TRUE(matches[0].has_pose);
        const double add = addError(pts, matches[0].R, matches[0].t, scene.R, scene.t);
        correct += matches[0].refined && isCorrect(add, diameter, 0.1);
        EXPECT_GE(matches[0].depth_agreement, 0.5);

        // RGB only: the initial pose projects the object centre near the truth; refined by edge
        // alignment, the 2D projection error drops
        std::vector<PoseMatch> rgb, initial;
        det->match(src, 80.f, rgb);
        initial = rgb;
        det->estimatePoses(noArray(), lmoIntrinsics(), initial);
        det->estimatePoses(noArray(), lmoIntrinsics(), rgb, PoseParams(), scene.color);
        if (!initial.empty() && initial[0].has_pose)
        {
            EXPECT_FALSE(initial[0].refined);
            EXPECT_TRUE(rgb[0].refined);
            const Vec3d c = lmoIntrinsics() * (initial[0].R * Vec3d(ape.center().x, ape.center().y,
                                                           ape.center().z) + initial[0].t);
            rgb_close += cv::norm(Point2d(c[0] / c[2], c[1] / c[2]) - scene.center) < 10.0;
            rgb_err_unrefined += projectionError2D(pts, lmoIntrinsics(), initial[0].R, initial[0].t,
                                                   scene.R, scene.t);
            rgb_err += projectionError2D(pts, lmoIntrinsics(), rgb[0].R, rgb[0].t, scene.R, scene.t);
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

// Without depth, detect() picks each detection's pose among the matches of its class that
// non-maximum suppression merges into it (PoseParams::rgb_hypotheses), by the edge fit.
TEST(Forestmod_DetectorPose, rgb_detect_chooses_pose_among_overlapping_matches)
{
    const ApeScenes as(getDefaultForestLINE());
    const Mesh& ape = as.ape;
    const Ptr<cv::forestmod::Detector>& det = as.det;
    RNG rng(11);
    // the verification would re-rank the detections: compared here is the pose choice alone
    PoseParams many_params;
    many_params.verification.enabled = false;
    PoseParams one = many_params;
    one.rgb_hypotheses = 1;
    int n = 0, chose_other = 0;
    double err_one = 0, err_many = 0;
    for (int k = 0; k < 6; ++k)
    {
        const SyntheticScene scene = as.render(rng);
        const std::vector<Mat> src(2, scene.color);
        std::vector<PoseMatch> many, single;
        det->detect(src, lmoIntrinsics(), 80.f, many, std::vector<String>(), many_params);
        det->detect(src, lmoIntrinsics(), 80.f, single, std::vector<String>(), one);
        ASSERT_EQ(single.size(), many.size());
        if (many.empty())
            continue;
        // same detections (position, score), only the pose may differ
        EXPECT_EQ(single[0].x, many[0].x);
        EXPECT_EQ(single[0].y, many[0].y);
        EXPECT_EQ(single[0].similarity, many[0].similarity);
        ASSERT_TRUE(many[0].refined && single[0].refined);
        EXPECT_GE(many[0].edge_fit, 0.0);
        EXPECT_LE(many[0].edge_fit, 1.0);
        // the detection's own template is among the hypotheses: the choice fits at least as well
        EXPECT_GE(many[0].edge_fit, single[0].edge_fit - 1e-9);
        EXPECT_TRUE(many[0].pose.valid);
        chose_other += many[0].template_id != single[0].template_id;
        err_one += projectionError2D(ape.vertices, lmoIntrinsics(), single[0].R, single[0].t, scene.R,
                                     scene.t);
        err_many += projectionError2D(ape.vertices, lmoIntrinsics(), many[0].R, many[0].t, scene.R,
                                      scene.t);
        ++n;
    }
    ASSERT_GE(n, 5);
    std::cout << "[ INFO    ] mean 2D projection error: " << err_one / n << " px (1 hypothesis), "
              << err_many / n << " px (" << PoseParams().rgb_hypotheses << "); another template "
              << "chosen in " << chose_other << " of " << n << " scenes" << std::endl;
    EXPECT_LE(err_many, err_one + 0.5 * n);
}

/** A match of `det`'s class at m's position with template `id`, as choosePoses() takes it. */
static PoseMatch hypothesisAt(const cv::forestmod::Detector& det, const cv::linemod::Match& m,
                              int id)
{
    PoseMatch pm(cv::linemod::Match(m.x, m.y, m.similarity, m.class_id, id));
    pm.pose = det.getTemplatePose(m.class_id, id);
    const cv::linemod::Template& t0 = det.getTemplates(m.class_id, id)[0];
    pm.box = Rect(m.x, m.y, t0.width, t0.height);
    return pm;
}

// choosePoses() refines a location's hypotheses one pass, and only the rgb_keep best edge fits
// go on: the best match put last behind views turned far from it must still be the one kept.
TEST(Forestmod_DetectorPose, choose_poses_keeps_the_best_fits_of_the_first_pass)
{
    const ApeScenes as(getDefaultForestLINE());
    const Ptr<cv::forestmod::Detector>& det = as.det;
    RNG rng(17);
    PoseParams keep1;
    keep1.rgb_keep = 1;
    PoseParams all = keep1;
    all.rgb_keep = 100;
    int n = 0, good = 0, same = 0;
    for (int k = 0; k < 6; ++k)
    {
        const SyntheticScene scene = as.render(rng);
        std::vector<cv::linemod::Match> matches;
        det->match(std::vector<Mat>(2, scene.color), 80.f, matches);
        if (matches.empty())
            continue;
        const cv::linemod::Match& m0 = matches[0];
        // three views more than 60 degrees from the best match's, first; the best match last
        const Matx33d R0 = det->getTemplatePose("ape", m0.template_id).R;
        std::vector<std::vector<PoseMatch> > loc(1);
        for (int id = 0; id < det->numTemplates("ape") && loc[0].size() < 3; ++id)
        {
            Vec3d r;
            Rodrigues(det->getTemplatePose("ape", id).R * R0.t(), r);
            if (cv::norm(r) > 60 * CV_PI / 180)
                loc[0].push_back(hypothesisAt(*det, m0, id));
        }
        ASSERT_EQ(loc[0].size(), 3u);
        loc[0].push_back(hypothesisAt(*det, m0, m0.template_id));
        EdgeMaps maps;
        std::vector<PoseMatch> one, full;
        det->choosePoses(lmoIntrinsics(), loc, keep1, scene.color, one, maps);
        det->choosePoses(lmoIntrinsics(), loc, all, scene.color, full, maps);
        ASSERT_EQ(one.size(), 1u);
        ASSERT_EQ(full.size(), 1u);
        ASSERT_TRUE(one[0].refined && full[0].refined);
        // position, box and score stay the location's first match's
        EXPECT_EQ(one[0].x, loc[0][0].x);
        EXPECT_EQ(one[0].similarity, loc[0][0].similarity);
        EXPECT_EQ(one[0].box, loc[0][0].box);
        // refined in steps or at once, the same hypothesis gives the same pose
        std::vector<PoseMatch> alone(1, loc[0][0]);
        for (size_t h = 0; h < loc[0].size(); ++h)
            if (loc[0][h].template_id == one[0].template_id)
                alone[0] = loc[0][h];
        det->estimatePoses(noArray(), lmoIntrinsics(), alone, keep1, scene.color, maps);
        ASSERT_TRUE(alone[0].refined);
        EXPECT_EQ(cv::norm(Mat(alone[0].R), Mat(one[0].R), NORM_INF), 0.0);
        EXPECT_EQ(cv::norm(Mat(alone[0].t), Mat(one[0].t), NORM_INF), 0.0);
        EXPECT_EQ(alone[0].edge_fit, one[0].edge_fit);
        // with one pass the first pass's drawing is also the final one: the same pose again
        PoseParams one_pass = keep1;
        one_pass.edge_params.passes = 1;
        std::vector<PoseMatch> short_fit, short_alone;
        det->choosePoses(lmoIntrinsics(), loc, one_pass, scene.color, short_fit, maps);
        ASSERT_EQ(short_fit.size(), 1u);
        ASSERT_TRUE(short_fit[0].refined);
        EXPECT_FALSE(short_fit[0].drawing.empty());
        for (size_t h = 0; h < loc[0].size(); ++h)
            if (loc[0][h].template_id == short_fit[0].template_id)
                short_alone.assign(1, loc[0][h]);
        ASSERT_EQ(short_alone.size(), 1u);
        det->estimatePoses(noArray(), lmoIntrinsics(), short_alone, one_pass, scene.color, maps);
        EXPECT_EQ(cv::norm(Mat(short_alone[0].R), Mat(short_fit[0].R), NORM_INF), 0.0);
        EXPECT_EQ(cv::norm(Mat(short_alone[0].t), Mat(short_fit[0].t), NORM_INF), 0.0);
        EXPECT_EQ(short_alone[0].edge_fit, short_fit[0].edge_fit);
        const double err = projectionError2D(as.ape.vertices, lmoIntrinsics(), one[0].R,
                                             one[0].t, scene.R, scene.t);
        good += err < 5;
        same += one[0].template_id == full[0].template_id;
        ++n;
    }
    ASSERT_GE(n, 5);
    std::cout << "[ INFO    ] 1 of 4 kept after the first pass: " << good << " of " << n
              << " under 5 px, the same choice as all 4 refined in " << same << std::endl;
    // the views turned 60 degrees away fit worse after one pass than the best match
    EXPECT_GE(good, n - 1);
    EXPECT_GE(same, n - 1);
}

// The same matches of `location`, each refined alone by estimatePoses(): the first that passes
// the depth check, or none (ACCV 2012's post-processing done the long way).
static bool firstPassing(const cv::forestmod::Detector& det, const Mat& depth,
                         const std::vector<PoseMatch>& location, const PoseParams& params,
                         PoseMatch& first)
{
    std::vector<PoseMatch> all(location.begin(), location.end());
    PoseParams every = params;
    every.max_per_class = (int)all.size();
    det.estimatePoses(depth, lmoIntrinsics(), all, every);
    for (size_t i = 0; i < all.size(); ++i)
        if (all[i].has_pose)
        {
            first = all[i];
            return true;
        }
    return false;
}

// With depth, choosePoses() refines a location's matches one after the other and keeps the
// first whose ICP pose passes the depth check: the pose of that match refined alone; a location
// of matches on the background plane is dropped. detect() chooses so among the matches
// non-maximum suppression merges into a detection.
TEST(Forestmod_DetectorPose, depth_choose_poses_keeps_the_first_that_passes)
{
    const ApeScenes as(getDefaultForestLINEMOD());
    const Ptr<cv::forestmod::Detector>& det = as.det;
    RNG rng(23);
    PoseParams params;
    params.verification.enabled = false; // the matcher's order
    int n = 0, later = 0, dropped = 0, detections = 0;
    for (int k = 0; k < 6; ++k)
    {
        const SyntheticScene scene = as.render(rng);
        std::vector<Mat> src;
        src.push_back(scene.color);
        src.push_back(scene.depth);
        src.push_back(scene.color);
        std::vector<cv::linemod::Match> matches;
        det->match(src, 80.f, matches);
        if (matches.empty())
            continue;
        const cv::linemod::Match& m0 = matches[0];
        // the best match's template first moved onto the background (a third of the frame
        // away), then at its place; and a location of the background alone
        cv::linemod::Match away = m0;
        away.x = (m0.x + 213) % 400;
        away.y = (m0.y + 160) % 300;
        std::vector<std::vector<PoseMatch> > locations(2);
        locations[0].push_back(hypothesisAt(*det, away, m0.template_id));
        locations[0].push_back(hypothesisAt(*det, m0, m0.template_id));
        locations[1].push_back(hypothesisAt(*det, away, m0.template_id));
        std::vector<PoseMatch> chosen;
        EdgeMaps maps;
        params.max_per_class = 2;
        det->choosePoses(scene.depth, lmoIntrinsics(), locations, params, scene.color, chosen,
                         maps);
        size_t c = 0;
        for (size_t g = 0; g < locations.size(); ++g)
        {
            PoseMatch first;
            if (!firstPassing(*det, scene.depth, locations[g], params, first))
            {
                ++dropped;
                continue;
            }
            ASSERT_LT(c, chosen.size());
            const PoseMatch& d = chosen[c++];
            ASSERT_TRUE(d.has_pose && d.refined);
            EXPECT_GE(d.depth_agreement, params.min_depth_agreement);
            EXPECT_EQ(cv::norm(Mat(d.R), Mat(first.R), NORM_INF), 0.0);
            EXPECT_EQ(cv::norm(Mat(d.t), Mat(first.t), NORM_INF), 0.0);
            EXPECT_EQ(d.depth_agreement, first.depth_agreement);
            // position, box and score stay the location's first match's
            EXPECT_EQ(d.x, locations[g][0].x);
            EXPECT_EQ(d.y, locations[g][0].y);
            EXPECT_EQ(d.box, locations[g][0].box);
            later += first.x != locations[g][0].x || first.y != locations[g][0].y;
        }
        EXPECT_EQ(c, chosen.size());
        // one hypothesis per location: the first location is dropped when its first fails
        PoseParams one = params;
        one.depth_hypotheses = 1;
        std::vector<PoseMatch> single;
        det->choosePoses(scene.depth, lmoIntrinsics(), locations, one, scene.color, single, maps);
        EXPECT_LE(single.size(), chosen.size());

        // detect(): a detection kept with its own match alone is kept with the same pose when
        // the matches it merged may stand in
        std::vector<PoseMatch> own, merged;
        params.max_per_class = PoseParams().max_per_class;
        one.max_per_class = params.max_per_class;
        det->detect(src, lmoIntrinsics(), 80.f, own, std::vector<String>(), one);
        det->detect(src, lmoIntrinsics(), 80.f, merged, std::vector<String>(), params);
        for (size_t i = 0; i < own.size(); ++i)
        {
            size_t j = 0;
            while (j < merged.size() && (merged[j].x != own[i].x || merged[j].y != own[i].y))
                ++j;
            ASSERT_LT(j, merged.size()) << "detection " << i << " lost";
            if (!own[i].refined)
                continue;
            EXPECT_EQ(merged[j].template_id, own[i].template_id);
            EXPECT_EQ(cv::norm(Mat(merged[j].R), Mat(own[i].R), NORM_INF), 0.0);
            EXPECT_EQ(cv::norm(Mat(merged[j].t), Mat(own[i].t), NORM_INF), 0.0);
        }
        detections += (int)own.size();
        ++n;
    }
    ASSERT_GE(n, 5);
    std::cout << "[ INFO    ] " << n << " scenes: a location's later match chosen " << later
              << " times, a location dropped " << dropped << " times" << std::endl;
    // both branches ran: a location's later match chosen, a location dropped
    EXPECT_GE(later, 1);
    EXPECT_GE(dropped, 1);
    EXPECT_GE(detections, n);
}

TEST(Forestmod_DetectorPose, bad_input_raises)
{
    Ptr<cv::forestmod::Detector> det = getDefaultForestLINE();
    std::vector<PoseMatch> m(1);
    EXPECT_THROW(det->estimatePoses(Mat(480, 640, CV_32F), lmoIntrinsics(), m), cv::Exception);
    EXPECT_THROW(det->estimatePoses(noArray(), Matx33d::zeros(), m), cv::Exception);
    PoseParams p;
    p.icp_passes = 0;
    EXPECT_THROW(det->estimatePoses(noArray(), lmoIntrinsics(), m, p), cv::Exception);
    PoseParams q;
    q.rgb_hypotheses = 0;
    EXPECT_THROW(det->estimatePoses(noArray(), lmoIntrinsics(), m, q), cv::Exception);
    PoseParams keep0;
    keep0.rgb_keep = 0;
    EXPECT_THROW(det->estimatePoses(noArray(), lmoIntrinsics(), m, keep0), cv::Exception);
    PoseParams depth0;
    depth0.depth_hypotheses = 0;
    EXPECT_THROW(det->estimatePoses(noArray(), lmoIntrinsics(), m, depth0), cv::Exception);
    // choosePoses: an empty location, a location of two classes
    const Mat color(480, 640, CV_8UC3, Scalar::all(0));
    std::vector<PoseMatch> out;
    EdgeMaps maps;
    std::vector<std::vector<PoseMatch> > empty_location(1);
    EXPECT_THROW(det->choosePoses(lmoIntrinsics(), empty_location, PoseParams(), color, out, maps),
                 cv::Exception);
    std::vector<std::vector<PoseMatch> > two_classes(1, std::vector<PoseMatch>(2));
    two_classes[0][0].class_id = "a";
    two_classes[0][1].class_id = "b";
    EXPECT_THROW(det->choosePoses(lmoIntrinsics(), two_classes, PoseParams(), color, out, maps),
                 cv::Exception);
    Mesh empty;
    EXPECT_THROW(det->setMesh("x", empty), cv::Exception);
}

}} // namespace
