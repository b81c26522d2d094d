// This file is part of OpenCV project.
// It is subject to the license terms in the LICENSE file found in the top-level directory
// of this distribution and at http://opencv.org/license.html

// The verification stage (Detector::verify, VerificationParams): a decoy that the LINEMOD score
// prefers loses after verification; parameters round-trip through FileStorage; bad input raises.

#include "test_precomp.hpp"
#include "../src/verification.hpp"
#include "../src/edge_gradient.hpp"
#include "test_pose_common.hpp"

#include <map>

namespace opencv_test { namespace {

/** A rendered scene over a real LM-O frame: the ape, partly covered by a grey box, and a decoy,
the ape's shape rendered in blue (its silhouette and shading cut out of another colour), both
seen from the same template view. */
struct DecoyScene
{
    Mesh ape;
    Ptr<cv::forestmod::Detector> det;
    Mat color;
    Rect object_box, decoy_box;

    DecoyScene()
        : ape(Mesh::load(cvtest::findDataFile("lmo_mini/models/obj_000001.ply")))
    {
        // gradients only: the LINEMOD score does not see colour (cv::linemod's getDefaultLINE)
        std::vector<Ptr<linemod::Modality> > mods(1, linemod::Modality::create("ColorGradient"));
        std::vector<int> T;
        T.push_back(5);
        T.push_back(8);
        det = makePtr<cv::forestmod::Detector>(mods, T);
        ViewSampler::Params sp;
        sp.level = 1;
        sp.min_elevation = 15;
        sp.radii = std::vector<double>(1, 800.0);
        sp.inplane_min = -20;
        sp.inplane_max = 20;
        sp.inplane_step = 20;
        const ViewSampler sampler(sp);
        const Matx33d K = lmoIntrinsics();
        CV_Assert(det->addTemplates(ape, "ape", sampler, K, Size(640, 480)) > 0);
        det->train();

        const std::vector<ViewPose> views
            = sampler.poses(Point3d(ape.center().x, ape.center().y, ape.center().z));
        const ViewPose& v = views[views.size() / 3];
        Mesh decoy = ape;
        decoy.colors.assign(decoy.vertices.size(), Vec3b(210, 110, 30)); // blue (BGR)
        Ptr<Renderer> r = Renderer::create(Size(640, 480));
        const int h_ape = r->addMesh(ape), h_decoy = r->addMesh(decoy);
        // a plain background with sensor noise: the matches are on the object and the decoy
        color.create(480, 640, CV_8UC3);
        color.setTo(Scalar(95, 105, 100));
        Mat noise(color.size(), CV_8UC3);
        RNG rng(3);
        rng.fill(noise, RNG::NORMAL, 0, 3);
        color += noise;
        Mat c, mask;
        r->render(h_ape, v.R, v.t + Vec3d(-150, 0, 0), K, c, noArray(), mask);
        c.copyTo(color, mask);
        object_box = boundingRect(mask);
        r->render(h_decoy, v.R, v.t + Vec3d(150, 0, 0), K, c, noArray(), mask);
        c.copyTo(color, mask);
        decoy_box = boundingRect(mask);
        // a grey box over the lower part of the object: its LINEMOD score drops, the decoy's not
        Rect cover(object_box.x - 5, object_box.y + object_box.height * 6 / 10,
                   object_box.width + 10, object_box.height);
        cover &= Rect(0, 0, color.cols, color.rows);
        color(cover).setTo(Scalar(128, 128, 128));
    }

    // the matches of the scene (object, decoy and a few on the background)
    std::vector<PoseMatch> matches() const
    {
        std::vector<PoseMatch> m;
        det->match(std::vector<Mat>(1, color), 60.f, m);
        return m;
    }

    // the hypothesis' centre (projection of the mesh centre) lies in the box
    bool inside(const PoseMatch& m, const Rect& box) const
    {
        const Vec3d p = lmoIntrinsics() * (m.R * Vec3d(ape.center().x, ape.center().y,
                                                       ape.center().z) + m.t);
        return box.contains(Point(cvRound(p[0] / p[2]), cvRound(p[1] / p[2])));
    }
};

TEST(Forestmod_Verification, decoy_with_the_better_linemod_score_loses)
{
    const DecoyScene s;
    const std::vector<Mat> src(1, s.color);
    const float threshold = 60.f;
    // plain matching: the decoy's best match outscores the (partly covered) object's
    std::vector<PoseMatch> plain;
    s.det->match(src, threshold, plain);
    float best_object = 0, best_decoy = 0;
    for (size_t i = 0; i < plain.size(); ++i)
    {
        const Point c = (plain[i].box.tl() + plain[i].box.br()) / 2;
        if (s.object_box.contains(c))
            best_object = std::max(best_object, plain[i].similarity);
        if (s.decoy_box.contains(c))
            best_decoy = std::max(best_decoy, plain[i].similarity);
    }
    ASSERT_GT(best_object, 0.f) << "the object must be among the hypotheses";
    ASSERT_GT(best_decoy, best_object) << "the scene must fool the LINEMOD score";
    ASSERT_TRUE(s.decoy_box.contains((plain[0].box.tl() + plain[0].box.br()) / 2));

    // detect() without verification keeps the matcher's order: the decoy first
    PoseParams off;
    off.verification.enabled = false;
    std::vector<PoseMatch> unverified;
    DetectionStats stats_off;
    s.det->detect(src, lmoIntrinsics(), threshold, unverified, std::vector<String>(), off,
                  &stats_off);
    ASSERT_FALSE(unverified.empty());
    EXPECT_TRUE(s.inside(unverified[0], s.decoy_box));
    EXPECT_EQ(unverified[0].verification, -1);
    EXPECT_EQ(stats_off.verified, 0);

    // with it (the default) the object comes first
    std::vector<PoseMatch> verified;
    DetectionStats stats;
    s.det->detect(src, lmoIntrinsics(), threshold, verified, std::vector<String>(),
                  PoseParams(), &stats);
    ASSERT_FALSE(verified.empty());
    EXPECT_TRUE(s.inside(verified[0], s.object_box));
    EXPECT_GT(stats.verified, 0);
    EXPECT_GT(stats.t_verify_ms, 0.0);
    const PoseMatch* decoy = 0;
    for (size_t i = 0; i < verified.size() && !decoy; ++i)
        if (s.inside(verified[i], s.decoy_box) && verified[i].verification >= 0)
            decoy = &verified[i];
    ASSERT_TRUE(decoy != 0);
    EXPECT_GT(decoy->similarity, verified[0].similarity);
    EXPECT_GT(verified[0].verification, decoy->verification);
    EXPECT_GT(verified[0].color_score, decoy->color_score + 0.3);
    // sorted by the verification; every part in [0, 1], no depth part without depth
    for (size_t i = 0; i < verified.size(); ++i)
    {
        if (verified[i].verification < 0)
            continue;
        if (i > 0 && verified[i - 1].verification >= 0)
        {
            EXPECT_GE(verified[i - 1].verification, verified[i].verification);
        }
        EXPECT_LE(verified[i].verification, 1.0);
        EXPECT_GE(verified[i].color_score, 0.0);
        EXPECT_LE(verified[i].color_score, 1.0);
        EXPECT_GE(verified[i].edge_score, 0.0);
        EXPECT_LE(verified[i].edge_score, 1.0);
        EXPECT_EQ(verified[i].depth_score, -1.0);
    }
    std::cout << "[ INFO    ] LINEMOD score object " << best_object << ", decoy " << best_decoy
              << "; verification object " << verified[0].verification << " (colour "
              << verified[0].color_score << ", edges " << verified[0].edge_score << "), decoy "
              << decoy->verification << " (colour " << decoy->color_score << ", edges "
              << decoy->edge_score << "); " << stats.verified << " hypotheses verified in "
              << stats.t_verify_ms << " ms" << std::endl;
}

// VerificationParams::second_round_below: with one hypothesis verified per class, the decoy
// (first in detect()'s order) is all the first round sees; it is not convincing (its colour
// disagrees), so the second round verifies the next detection, the object, which then comes
// first. One round leaves the decoy first; a convincing first round makes no second.
TEST(Forestmod_Verification, second_round_finds_the_object_behind_an_unconvincing_decoy)
{
    const DecoyScene s;
    const std::vector<Mat> src(1, s.color);
    const float threshold = 60.f;
    PoseParams one;
    one.verification.top_k = 1;
    one.verification.second_round_below = 0;
    std::vector<PoseMatch> first;
    DetectionStats stats_one;
    s.det->detect(src, lmoIntrinsics(), threshold, first, std::vector<String>(), one, &stats_one);
    ASSERT_GE(first.size(), 2u);
    EXPECT_EQ(stats_one.verified, 1);
    ASSERT_TRUE(s.inside(first[0], s.decoy_box)) << "the scene must put the decoy first";
    ASSERT_GE(first[0].verification, 0.0);
    EXPECT_EQ(first[1].verification, -1.0);

    PoseParams two = one;
    two.verification.second_round_below = 0.75; // the default
    EXPECT_EQ(two.verification.second_round_below, PoseParams().verification.second_round_below);
    ASSERT_LT(first[0].verification, two.verification.second_round_below)
        << "the decoy must not convince the first round";
    std::vector<PoseMatch> both;
    DetectionStats stats_two;
    s.det->detect(src, lmoIntrinsics(), threshold, both, std::vector<String>(), two, &stats_two);
    EXPECT_EQ(stats_two.verified, 2);
    ASSERT_EQ(both.size(), first.size()) << "a second-round detection replaces its first-round one";
    ASSERT_GE(both[1].verification, 0.0);
    EXPECT_GE(both[0].verification, both[1].verification);
    EXPECT_TRUE(s.inside(both[0], s.object_box));
    EXPECT_TRUE(s.inside(both[1], s.decoy_box));
    EXPECT_DOUBLE_EQ(both[1].verification, first[0].verification);
    for (size_t i = 2; i < both.size(); ++i)
        EXPECT_EQ(both[i].verification, -1.0);
    for (size_t i = 0; i < both.size(); ++i) // each location once
        for (size_t j = i + 1; j < both.size(); ++j)
            EXPECT_FALSE(both[i].x == both[j].x && both[i].y == both[j].y
                         && both[i].box == both[j].box)
                << i << " and " << j;

    // a bar below the decoy's verification: the first round convinces, no second
    PoseParams low = one;
    low.verification.second_round_below = first[0].verification * 0.99;
    std::vector<PoseMatch> convinced;
    DetectionStats stats_low;
    s.det->detect(src, lmoIntrinsics(), threshold, convinced, std::vector<String>(), low,
                  &stats_low);
    EXPECT_EQ(stats_low.verified, 1);
    ASSERT_FALSE(convinced.empty());
    EXPECT_TRUE(s.inside(convinced[0], s.decoy_box));
    std::cout << "[ INFO    ] first round: decoy " << first[0].verification << "; second round: "
              << "object " << both[0].verification << std::endl;
}

// hypotheses in a fixed order (verify() sorts by its score): by place and template
static std::vector<PoseMatch> byPlace(std::vector<PoseMatch> m)
{
    std::sort(m.begin(), m.end(), [](const PoseMatch& a, const PoseMatch& b) {
        return a.x != b.x ? a.x < b.x : a.y != b.y ? a.y < b.y : a.template_id < b.template_id;
    });
    return m;
}

// The frame's edge maps, made once by the pose stage, stand for Canny on every hypothesis' crop:
// estimatePoses() returns the maps it made and reads given ones, verify() scores the contour on
// them as on its own edges (detect() passes them on).
TEST(Forestmod_Verification, the_frames_edge_maps_stand_for_canny_on_each_crop)
{
    const DecoyScene s;
    const Matx33d K = lmoIntrinsics();
    const std::vector<PoseMatch> matches = s.matches();
    ASSERT_GE(matches.size(), 2u);
    // the pose stage: the maps it makes around the refined matches, then the same maps given
    const PoseParams pp;
    std::vector<PoseMatch> hyp = matches, again = matches;
    EdgeMaps maps;
    s.det->estimatePoses(noArray(), K, hyp, pp, s.color, maps);
    ASSERT_EQ((int)maps.distance.size(), pp.edge_params.orientations);
    ASSERT_EQ(maps.distance[0].size(), s.color.size());
    s.det->estimatePoses(noArray(), K, again, pp, s.color, maps);
    for (size_t i = 0; i < hyp.size(); ++i)
    {
        EXPECT_EQ(cvtest::norm(hyp[i].t, again[i].t, NORM_INF), 0.0) << i;
        EXPECT_EQ(hyp[i].edge_fit, again[i].edge_fit) << i;
    }
    // the verification: Canny on each crop or the frame's maps, the same scores
    const VerificationParams vp;
    std::vector<PoseMatch> own = hyp, read = hyp;
    s.det->verify(s.color, noArray(), K, own, vp);
    s.det->verify(s.color, noArray(), K, read, vp, 0, maps);
    own = byPlace(own);
    read = byPlace(read);
    int verified = 0;
    for (size_t i = 0; i < own.size(); ++i)
    {
        if (own[i].verification < 0)
            continue;
        ++verified;
        EXPECT_NEAR(own[i].edge_score, read[i].edge_score, 0.03) << i;
        EXPECT_EQ(own[i].color_score, read[i].color_score) << i;
        EXPECT_NEAR(own[i].verification, read[i].verification, 0.01) << i;
    }
    EXPECT_GE(verified, 2);
    // the maps are what it reads: those of an image without edges match no contour
    EdgeMaps blank;
    computeEdgeMaps(Mat(s.color.size(), CV_8UC3, Scalar::all(100)), blank, vp.edge_params);
    std::vector<PoseMatch> none = hyp;
    s.det->verify(s.color, noArray(), K, none, vp, 0, blank);
    for (size_t i = 0; i < none.size(); ++i)
        if (none[i].verification >= 0)
        {
            EXPECT_EQ(none[i].edge_score, 0.0) << i;
        }
    // maps made with other orientation bins, or truncated below edge_distance, are refused
    EdgeRefineParams eight = vp.edge_params;
    eight.orientations = 8;
    EdgeMaps other;
    computeEdgeMaps(s.color, other, eight);
    EXPECT_THROW(s.det->verify(s.color, noArray(), K, none, vp, 0, other), cv::Exception);
    EXPECT_THROW(s.det->estimatePoses(noArray(), K, none, pp, s.color, other), cv::Exception);
    EdgeRefineParams tight = vp.edge_params;
    tight.max_distance = 2; // < edge_distance 3
    computeEdgeMaps(s.color, other, tight);
    EXPECT_THROW(s.det->verify(s.color, noArray(), K, none, vp, 0, other), cv::Exception);
}

// The ape, LM-O's intrinsics and the third view of the coarse sampler around the ape: what the
// scenes below are drawn with.
// Scores of the verified hypotheses, in a fixed order.
static std::vector<Vec4d> verifiedScores(const std::vector<PoseMatch>& matches)
{
    std::vector<Vec4d> s;
    const std::vector<PoseMatch> m = byPlace(matches);
    for (size_t i = 0; i < m.size(); ++i)
        if (m[i].verification >= 0)
            s.push_back(Vec4d(m[i].verification, m[i].color_score, m[i].edge_score,
                              m[i].region_score));
    return s;
}

// verify() of the hypotheses with their drawings and with the drawings released: the same scores
// (returned), and no drawing left after it
static std::vector<Vec4d> scoresOfKeptDrawings(const DecoyScene& s,
                                               const std::vector<PoseMatch>& hyp,
                                               const EdgeMaps& maps)
{
    const Matx33d K = lmoIntrinsics();
    std::vector<PoseMatch> kept = hyp, fresh = hyp;
    for (size_t i = 0; i < fresh.size(); ++i)
        fresh[i].drawing.release();
    s.det->verify(s.color, noArray(), K, kept, VerificationParams(), 0, maps);
    s.det->verify(s.color, noArray(), K, fresh, VerificationParams(), 0, maps);
    for (size_t i = 0; i < kept.size(); ++i)
        EXPECT_FALSE(kept[i].drawing) << "verify() releases the drawings";
    const std::vector<Vec4d> a = verifiedScores(kept), b = verifiedScores(fresh);
    EXPECT_EQ(a.size(), b.size());
    for (size_t i = 0; i < std::min(a.size(), b.size()); ++i)
        EXPECT_EQ(cvtest::norm(a[i], b[i], NORM_INF), 0.0) << i << ": " << a[i] << " " << b[i];
    return a;
}

// the largest change of any score between two lists of verifiedScores()
static double largestChange(const std::vector<Vec4d>& a, const std::vector<Vec4d>& b)
{
    EXPECT_EQ(a.size(), b.size());
    double changed = 0;
    for (size_t i = 0; i < std::min(a.size(), b.size()); ++i)
        changed = std::max(changed, cvtest::norm(a[i], b[i], NORM_INF));
    return changed;
}

// The pose stage keeps its last drawing of each refined hypothesis (PoseMatch::drawing) and the
// verification scores it instead of drawing again: the same scores as a drawing of its own; a
// hypothesis moved since, or whose class's mesh was set again, is drawn again; verify() releases
// the drawings.
TEST(Forestmod_Verification, the_pose_stages_drawing_is_scored_as_a_new_one)
{
    const DecoyScene s;
    std::vector<PoseMatch> hyp = s.matches();
    ASSERT_GE(hyp.size(), 2u);
    EdgeMaps maps;
    s.det->estimatePoses(noArray(), lmoIntrinsics(), hyp, PoseParams(), s.color, maps);
    int drawn = 0, first = -1;
    for (size_t i = 0; i < hyp.size(); ++i)
    {
        if (!hyp[i].drawing)
            continue;
        EXPECT_TRUE(hyp[i].refined) << i;
        first = first < 0 ? (int)i : first;
        ++drawn;
    }
    ASSERT_GE(drawn, 2);
    const std::vector<Vec4d> scores = scoresOfKeptDrawings(s, hyp, maps);
    EXPECT_GE(scores.size(), 2u);
    // one hypothesis moved by 12 mm (about 9 px) after the pose stage drew it
    std::vector<PoseMatch> moved = hyp;
    moved[first].t += Vec3d(12, 0, 0);
    EXPECT_GT(largestChange(scoresOfKeptDrawings(s, moved, maps), scores), 0.02)
        << "the move changes the moved hypothesis' scores";
    // the class's mesh set again (20 % larger) after the pose stage drew: drawn again
    Mesh larger = s.ape;
    const Point3f centre = s.ape.center();
    for (size_t i = 0; i < larger.vertices.size(); ++i)
        larger.vertices[i] = centre + 1.2f * (larger.vertices[i] - centre);
    s.det->setMesh("ape", larger);
    EXPECT_GT(largestChange(scoresOfKeptDrawings(s, hyp, maps), scores), 0.02)
        << "the larger mesh changes the scores";
}

struct ApeView
{
    Mesh ape;
    Matx33d K;
    ViewPose v;
    ApeView()
        : ape(Mesh::load(cvtest::findDataFile("lmo_mini/models/obj_000001.ply"))),
          K(lmoIntrinsics())
    {
        v = ViewSampler(ViewSampler::Params::coarse())
                .poses(Point3d(ape.center().x, ape.center().y, ape.center().z))[2];
    }
    // `det` with the ape's mesh for class "ape"
    Ptr<cv::forestmod::Detector> withApe(const Ptr<cv::forestmod::Detector>& det) const
    {
        det->setMesh("ape", ape);
        return det;
    }
};

// With depth: a flat picture of the object (its colours and contour, on a plane) ranked above
// the object by the matcher loses on the depth check.
TEST(Forestmod_Verification, flat_picture_loses_on_depth)
{
    const ApeView scene;
    const Matx33d& K = scene.K;
    const ViewPose& v = scene.v;
    Ptr<cv::forestmod::Detector> det = scene.withApe(getDefaultForestLINEMOD());
    const Vec3d t_obj = v.t + Vec3d(-120, 0, 0), t_pic = v.t + Vec3d(120, 0, 0);
    Ptr<Renderer> r = Renderer::create(Size(640, 480));
    const int h = r->addMesh(scene.ape);
    Mat color(480, 640, CV_8UC3, Scalar(95, 105, 100));
    Mat depth(480, 640, CV_16UC1, Scalar(v.t[2] + 150)); // a wall behind both
    Mat c, d, k;
    r->render(h, v.R, t_obj, K, c, d, k);
    c.copyTo(color, k);
    d.copyTo(depth, k);
    r->render(h, v.R, t_pic, K, c, d, k);
    c.copyTo(color, k); // the picture: the object's image ...
    depth.setTo(Scalar(cvRound(t_pic[2] + 60)), k); // ... on a plane
    std::vector<PoseMatch> m(2);
    m[0].class_id = m[1].class_id = "ape";
    m[0].similarity = 95.f; // the picture first
    m[1].similarity = 80.f;
    m[0].R = m[1].R = v.R;
    m[0].t = t_pic;
    m[1].t = t_obj;
    m[0].has_pose = m[1].has_pose = true;
    m[0].template_id = 0;
    m[1].template_id = 1;
    std::vector<PoseMatch> rgb = m;
    det->verify(color, noArray(), K, rgb);
    ASSERT_EQ(rgb.size(), 2u);
    EXPECT_EQ(rgb[0].template_id, 0) << "without depth the two look alike: the matcher decides";
    det->verify(color, depth, K, m);
    ASSERT_EQ(m.size(), 2u);
    EXPECT_EQ(m[0].template_id, 1);
    EXPECT_GT(m[0].depth_score, 0.9);
    EXPECT_LT(m[1].depth_score, 0.5);
    EXPECT_GT(m[0].color_score, 0.9);
    EXPECT_GT(m[1].color_score, 0.9);
}

// region_score compares the scene's colours inside the drawn silhouette with those of a ring
// around it: the object on a plain background stands out (disjoint colours: 1), a pose on the
// plain background (the same colours inside and out: 0) or on clutter (many colours on both
// sides) does not.
TEST(Forestmod_Verification, region_score_separates_the_object_from_its_surroundings)
{
    const ApeView scene;
    const Matx33d& K = scene.K;
    const ViewPose& v = scene.v;
    Ptr<cv::forestmod::Detector> det = scene.withApe(getDefaultForestLINE());
    const Vec3d t_obj = v.t + Vec3d(-120, 0, 0), t_plain = v.t + Vec3d(0, -90, 0),
                t_clutter = v.t + Vec3d(120, 0, 0);
    Mat color(480, 640, CV_8UC3, Scalar(200, 60, 20)); // saturated blue: not the ape's colours
    // clutter: random 8 x 8 blocks of every colour on the right
    RNG rng(5);
    for (int y = 0; y < 480; y += 8)
        for (int x = 400; x < 640; x += 8)
            color(Rect(x, y, 8, 8)).setTo(Scalar(rng.uniform(0, 256), rng.uniform(0, 256),
                                                 rng.uniform(0, 256)));
    Ptr<Renderer> r = Renderer::create(Size(640, 480));
    Mat c, k;
    r->render(r->addMesh(scene.ape), v.R, t_obj, K, c, noArray(), k);
    c.copyTo(color, k);
    std::vector<PoseMatch> m(3);
    const Vec3d ts[3] = { t_obj, t_plain, t_clutter };
    for (int i = 0; i < 3; ++i)
    {
        m[i].class_id = "ape";
        m[i].template_id = i;
        m[i].similarity = 90.f;
        m[i].has_pose = true;
        m[i].R = v.R;
        m[i].t = ts[i];
    }
    VerificationParams vp;
    vp.w_similarity = vp.w_color = vp.w_edges = 0;
    vp.w_region = 1; // ranked by region_score alone
    det->verify(color, noArray(), K, m, vp);
    ASSERT_EQ(m.size(), 3u);
    EXPECT_EQ(m[0].template_id, 0);
    double score[3] = { -1, -1, -1 };
    for (int i = 0; i < 3; ++i)
    {
        score[m[i].template_id] = m[i].region_score;
        EXPECT_DOUBLE_EQ(m[i].verification, m[i].region_score);
    }
    EXPECT_GT(score[0], 0.95) << "the ape's colours are not the background's";
    EXPECT_EQ(score[1], 0.0) << "the plain background on both sides";
    EXPECT_GE(score[2], 0.0);
    EXPECT_LT(score[2], 0.5) << "clutter on both sides";
    std::cout << "[ INFO    ] region_score object " << score[0] << ", plain " << score[1]
              << ", clutter " << score[2] << std::endl;
}

TEST(Forestmod_Verification, verify_keeps_unverifiable_hypotheses_in_order)
{
    Ptr<cv::forestmod::Detector> det = getDefaultForestLINE();
    std::vector<PoseMatch> m(3);
    for (int i = 0; i < 3; ++i)
    {
        m[i].class_id = "no_mesh";
        m[i].template_id = i;
        m[i].similarity = 90.f - i;
        m[i].has_pose = true;
        m[i].R = Matx33d::eye();
        m[i].t = Vec3d(0, 0, 800);
    }
    m[1].has_pose = false;
    const Mat color(480, 640, CV_8UC3, Scalar(30, 60, 90));
    DetectionStats stats;
    det->verify(color, noArray(), lmoIntrinsics(), m, VerificationParams(), &stats);
    ASSERT_EQ(m.size(), 3u);
    for (int i = 0; i < 3; ++i)
    {
        EXPECT_EQ(m[i].template_id, i);
        EXPECT_EQ(m[i].verification, -1.0);
    }
    EXPECT_EQ(stats.verified, 0);
}

/** A flat square plate of side `side` mm, vertices every millimetre, two faces per square. */
static Mesh densePlate(int side)
{
    Mesh m;
    for (int y = 0; y <= side; ++y)
        for (int x = 0; x <= side; ++x)
            m.vertices.push_back(Point3f((float)x, (float)y, 0.f));
    for (int y = 0; y < side; ++y)
        for (int x = 0; x < side; ++x)
        {
            const int i = y * (side + 1) + x;
            m.faces.push_back(Vec3i(i, i + 1, i + side + 2));
            m.faces.push_back(Vec3i(i, i + side + 2, i + side + 1));
        }
    return m;
}

// The drawn copy's cells: 1/64 of the diameter for small objects, at most 2.5 mm for large ones
// (the driller's silhouette, doc/pose.md "Drawing at detection time").
TEST(Forestmod_Verification, drawn_copy_keeps_cells_of_at_most_two_and_a_half_mm)
{
    using cv::forestmod::detail::coarseMesh;
    using cv::forestmod::detail::drawingCell;
    EXPECT_DOUBLE_EQ(drawingCell(100.0), 100.0 / 64);
    EXPECT_DOUBLE_EQ(drawingCell(262.0), 2.5);
    // a 200 mm plate (diameter 283 mm): cells of 2.5 mm leave about 80 x 80 vertices, cells of
    // 1/64 of the diameter (4.4 mm) would leave 46 x 46
    const Mesh plate = densePlate(200);
    const Mesh drawn = coarseMesh(plate, drawingCell(plate.diameter()));
    EXPECT_GE(drawn.vertices.size(), 78u * 78u);
    EXPECT_LE(drawn.vertices.size(), 82u * 82u);
    // a 50 mm plate (diameter 71 mm, cells of 1.1 mm): as 1/64 of the diameter gives
    const Mesh small = densePlate(50);
    EXPECT_EQ(coarseMesh(small, drawingCell(small.diameter())).vertices.size(),
              coarseMesh(small, small.diameter() / 64).vertices.size());
}

// The verification draws closed meshes without the faces seen from inside: the same pixels,
// depths and colours as drawing every face; the orientation of the faces is found from the mesh.
TEST(Forestmod_Verification, drawing_skips_the_inside_of_closed_meshes)
{
    using cv::forestmod::detail::closedWinding;
    using cv::forestmod::detail::coarseMesh;
    using cv::forestmod::detail::drawMesh;
    const Mesh ape = Mesh::load(cvtest::findDataFile("lmo_mini/models/obj_000001.ply"));
    const Mesh coarse = coarseMesh(ape, cv::forestmod::detail::drawingCell(ape.diameter()));
    EXPECT_EQ(closedWinding(ape), 1);
    ASSERT_EQ(closedWinding(coarse), 1);
    Mesh reversed = coarse;
    for (size_t f = 0; f < reversed.faces.size(); ++f)
        std::swap(reversed.faces[f][1], reversed.faces[f][2]);
    EXPECT_EQ(closedWinding(reversed), -1);
    Mesh open = coarse; // every 20th face removed: not closed
    for (size_t f = open.faces.size(); f-- > 0;)
        if (f % 20 == 0)
            open.faces.erase(open.faces.begin() + f);
    EXPECT_EQ(closedWinding(open), 0);
    EXPECT_EQ(closedWinding(Mesh()), 0);

    ViewSampler::Params sp;
    sp.level = 1;
    sp.radii = std::vector<double>(1, 700.0);
    const std::vector<ViewPose> views = ViewSampler(sp).poses(
        Point3d(ape.center().x, ape.center().y, ape.center().z));
    ASSERT_GE(views.size(), 10u);
    const Matx33d K = lmoIntrinsics();
    const Size image(640, 480);
    for (size_t i = 0; i < views.size(); i += views.size() / 10)
    {
        Rect r0, r1, r2, r3;
        Mat c0, d0, m0, c1, d1, m1, c2, d2, m2, c3, d3, m3;
        drawMesh(coarse, 0, K, views[i].R, views[i].t, image, 7, r0, c0, d0, m0);
        drawMesh(coarse, 1, K, views[i].R, views[i].t, image, 7, r1, c1, d1, m1);
        drawMesh(reversed, -1, K, views[i].R, views[i].t, image, 7, r2, c2, d2, m2);
        ASSERT_GT(countNonZero(m0), 1000) << i;
        EXPECT_EQ(r0, r1);
        EXPECT_EQ(r0, r2);
        EXPECT_EQ(cvtest::norm(m0, m1, NORM_INF), 0) << i;
        EXPECT_EQ(cvtest::norm(d0, d1, NORM_INF), 0) << i;
        EXPECT_EQ(cvtest::norm(c0, c1, NORM_INF), 0) << i;
        EXPECT_EQ(cvtest::norm(m0, m2, NORM_INF), 0) << i;
        EXPECT_LE(cvtest::norm(d0, d2, NORM_INF), 1) << i; // the corners' order rounds z
        // skipping the other side draws the far side of the object: farther on the mean
        drawMesh(coarse, -1, K, views[i].R, views[i].t, image, 7, r3, c3, d3, m3);
        EXPECT_GT(mean(d3, m3 & m0)[0], mean(d0, m3 & m0)[0] + 5) << i;
    }
}

// A face's corners as a canonical tuple (the corner of smallest coordinates first, the winding
// kept), so that two orderings of the same triangles can be compared.
static std::vector<float> faceCorners(const Mesh& mesh, size_t f)
{
    std::vector<Point3f> c(3);
    for (int k = 0; k < 3; ++k)
        c[k] = mesh.vertices[mesh.faces[f][k]];
    const auto less = [](const Point3f& a, const Point3f& b) {
        return a.x < b.x || (a.x == b.x && (a.y < b.y || (a.y == b.y && a.z < b.z)));
    };
    std::rotate(c.begin(), std::min_element(c.begin(), c.end(), less), c.end());
    std::vector<float> out;
    for (int k = 0; k < 3; ++k)
        out.insert(out.end(), { c[k].x, c[k].y, c[k].z });
    return out;
}

// n . (a - centre) for face f's outward normal n and first corner a: > 0 when the face faces away
// from a camera at centre.
static double facing(const Mesh& mesh, int f, int winding, const Vec3d& centre)
{
    const Vec3i& F = mesh.faces[f];
    const Point3f &p = mesh.vertices[F[0]], &q = mesh.vertices[F[1]], &r = mesh.vertices[F[2]];
    const Vec3d a(p.x, p.y, p.z), b(q.x, q.y, q.z), c(r.x, r.y, r.z);
    return (b - a).cross(c - a).dot(a - centre) * winding;
}

// clusterFaces() reorders the faces (the same triangles, colours following their vertices), and
// a drawing that skips the clusters facing away draws what drawing every face draws: the same
// face, depth and mask at every pixel as without the clusters, the same depth and mask as the
// mesh in its first order. Every face of a skipped cluster faces away (exact test in double),
// and the clusters skip most of the faces that do.
TEST(Forestmod_Verification, face_clusters_skip_only_faces_that_face_away)
{
    namespace fd = cv::forestmod::detail;
    const Mesh ape = Mesh::load(cvtest::findDataFile("lmo_mini/models/obj_000001.ply"));
    const Mesh coarse = fd::coarseMesh(ape, fd::drawingCell(ape.diameter()));
    Mesh open = coarse;
    open.faces.pop_back();
    const fd::FaceClusters none = fd::clusterFaces(open, 0);
    EXPECT_TRUE(none.begin.empty());
    EXPECT_TRUE(open.faces == std::vector<Vec3i>(coarse.faces.begin(), coarse.faces.end() - 1));
    Mesh reversed = coarse;
    for (size_t f = 0; f < reversed.faces.size(); ++f)
        std::swap(reversed.faces[f][1], reversed.faces[f][2]);
    const Matx33d K = lmoIntrinsics();
    const Size image(640, 480);
    for (int winding = 1; winding >= -1; winding -= 2)
    {
        const Mesh& first = winding > 0 ? coarse : reversed;
        Mesh sorted = first;
        const fd::FaceClusters clusters = fd::clusterFaces(sorted, winding);
        const size_t nf = first.faces.size();
        ASSERT_EQ(sorted.faces.size(), nf);
        ASSERT_EQ(sorted.vertices.size(), first.vertices.size());
        ASSERT_EQ(sorted.colors.size(), first.colors.size());
        std::vector<std::vector<float> > a, b;
        for (size_t f = 0; f < nf; ++f)
        {
            a.push_back(faceCorners(first, f));
            b.push_back(faceCorners(sorted, f));
        }
        std::sort(a.begin(), a.end());
        std::sort(b.begin(), b.end());
        EXPECT_TRUE(a == b) << winding;
        const auto key = [](const Point3f& v) { return std::vector<float>{ v.x, v.y, v.z }; };
        std::map<std::vector<float>, Vec3b> colour_at; // a vertex's colour moves with it
        for (size_t v = 0; v < first.vertices.size(); ++v)
            colour_at[key(first.vertices[v])] = first.colors[v];
        for (size_t v = 0; v < sorted.vertices.size(); ++v)
            ASSERT_EQ(colour_at[key(sorted.vertices[v])], sorted.colors[v]) << v;
        ASSERT_EQ(clusters.begin.front(), 0);
        ASSERT_EQ(clusters.begin.back(), (int)nf);
        ASSERT_EQ(clusters.bound.size() + 1, clusters.begin.size());
        EXPECT_EQ(clusters.box_min, first.bboxMin());
        EXPECT_EQ(clusters.box_max, first.bboxMax());
        for (size_t k = 0; k + 1 < clusters.begin.size(); ++k)
            ASSERT_LE(clusters.begin[k + 1] - clusters.begin[k], 16) << k;

        const std::vector<ViewPose> views = pose_test::hemisphereViews(ape,
                                                                        { 250.0, 700.0, 1400.0 });
        double skipped = 0, away = 0;
        int compared = 0;
        for (size_t i = 0; i < views.size(); i += 3)
        {
            Vec3d t = views[i].t;
            if (i % 2) // moved towards a corner: cut by the image border
                t += Vec3d(0.45 * t[2] * image.width / K(0, 0),
                           0.4 * t[2] * image.height / K(1, 1), 0);
            const Matx33d& R = views[i].R;
            const Vec3d centre = -(R.t() * t);
            for (size_t k = 0; k + 1 < clusters.begin.size(); ++k)
            {
                if (!clusters.facesAway((int)k, centre))
                    continue;
                for (int f = clusters.begin[k]; f < clusters.begin[k + 1]; ++f)
                    ASSERT_GT(facing(sorted, f, winding, centre), 0) << i << " " << f;
                skipped += clusters.begin[k + 1] - clusters.begin[k];
            }
            for (size_t f = 0; f < nf; ++f)
                away += facing(sorted, (int)f, winding, centre) > 0;
            fd::Drawing d[3];
            fd::drawMesh(sorted, winding, K, R, t, image, 8, d[0], &clusters);
            fd::drawMesh(sorted, winding, K, R, t, image, 8, d[1]);
            fd::drawMesh(first, winding, K, R, t, image, 8, d[2]);
            ASSERT_GT(countNonZero(d[0].mask), 100) << i;
            EXPECT_EQ(d[0].rect, d[1].rect) << i;
            EXPECT_EQ(d[0].rect, d[2].rect) << i;
            EXPECT_EQ(cvtest::norm(d[0].face, d[1].face, NORM_INF), 0) << i << " " << winding;
            for (int j = 1; j <= 2; ++j)
            {
                EXPECT_EQ(cvtest::norm(d[0].mask, d[j].mask, NORM_INF), 0) << i << " " << j;
                EXPECT_EQ(cvtest::norm(d[0].depth, d[j].depth, NORM_INF), 0) << i << " " << j;
            }
            ++compared;
        }
        EXPECT_GE(compared, 20);
        // about half the faces face away; the clusters hold most of them
        EXPECT_GT(away, 0.45 * nf * compared);
        EXPECT_GT(skipped, 0.6 * away) << skipped / away;
    }
}

// The rasterizer's vector path (faces four at a time, pixels four at a time) draws every pixel as
// the scalar path (cv::setUseOptimized(false)) does: the same face, depth and mask, bit for bit,
// for closed and open drawing (winding 1 and 0), near and far views, and objects cut by the image
// border (the crop's last columns, drawn by the scalar tail).
TEST(Forestmod_Verification, drawing_vector_path_draws_as_the_scalar_one)
{
    using cv::forestmod::detail::Drawing;
    namespace fd = cv::forestmod::detail;
    const Mesh ape = Mesh::load(cvtest::findDataFile("lmo_mini/models/obj_000001.ply"));
    const Mesh coarse = fd::coarseMesh(ape, fd::drawingCell(ape.diameter()));
    ViewSampler::Params sp;
    sp.level = 1;
    sp.radii = std::vector<double>{250.0, 700.0, 1400.0};
    const Point3d c(ape.center().x, ape.center().y, ape.center().z);
    const std::vector<ViewPose> views = ViewSampler(sp).poses(c);
    ASSERT_GE(views.size(), 30u);
    const Matx33d K = lmoIntrinsics();
    const Size image(640, 480);
    const bool was_optimized = useOptimized();
    int compared = 0, border = 0;
    for (size_t i = 0; i < views.size(); i += 3)
    {
        // every other view moved towards a corner, so that the image border cuts the object
        Vec3d t = views[i].t;
        if (i % 2)
            t += Vec3d(0.45 * t[2] * image.width / K(0, 0), 0.4 * t[2] * image.height / K(1, 1), 0);
        for (int winding = 0; winding <= 1; ++winding)
        {
            Drawing d[2];
            for (int pass = 0; pass < 2; ++pass)
            {
                setUseOptimized(pass == 0);
                fd::drawMesh(coarse, winding, K, views[i].R, t, image, 8, d[pass]);
            }
            setUseOptimized(was_optimized);
            ASSERT_FALSE(d[0].face.empty()) << i;
            ASSERT_GT(countNonZero(d[0].mask), 100) << i;
            EXPECT_EQ(d[0].rect, d[1].rect) << i;
            EXPECT_EQ(cvtest::norm(d[0].face, d[1].face, NORM_INF), 0) << i << " " << winding;
            EXPECT_EQ(cvtest::norm(d[0].depth, d[1].depth, NORM_INF), 0) << i << " " << winding;
            EXPECT_EQ(cvtest::norm(d[0].mask, d[1].mask, NORM_INF), 0) << i << " " << winding;
            ++compared;
            border += d[0].rect.br().x == image.width
                && countNonZero(d[0].mask.col(d[0].mask.cols - 1)) > 0;
        }
    }
    EXPECT_GE(compared, 20);
    EXPECT_GE(border, 4); // the scalar tail was exercised
}

// The contour check reads Sobel gradients at single pixels: equal to cv::Sobel on the image and
// on ROIs (whose neighbours outside are read), at every pixel including the image's edges, and to
// strongestGradient() (the edge refinement's) for colour images.
TEST(Forestmod_Verification, point_sobel_equals_sobel_on_images_and_rois)
{
    using cv::forestmod::detail::PointSobel;
    RNG rng(11);
    Mat img(37, 53, CV_8UC3);
    rng.fill(img, RNG::UNIFORM, 0, 256);
    Mat grey;
    cvtColor(img, grey, COLOR_BGR2GRAY);
    const Rect rois[] = { Rect(0, 0, 53, 37), Rect(5, 3, 20, 17), Rect(0, 10, 9, 27),
                          Rect(40, 0, 13, 8) };
    for (const Rect& roi : rois)
    {
        for (int k = 0; k < 2; ++k)
        {
            const Mat src = (k == 0 ? img : grey)(roi);
            Mat sx, sy;
            Sobel(src, sx, CV_32F, 1, 0, 3); // integers: exact in float
            Sobel(src, sy, CV_32F, 0, 1, 3);
            const PointSobel ps(src);
            int wrong = 0;
            for (int y = 0; y < src.rows; ++y)
                for (int x = 0; x < src.cols; ++x)
                    for (int c = 0; c < src.channels(); ++c)
                    {
                        int gx, gy;
                        ps.at(x, y, c, gx, gy);
                        wrong += (float)gx != sx.ptr<float>(y)[x * src.channels() + c]
                            || (float)gy != sy.ptr<float>(y)[x * src.channels() + c];
                    }
            EXPECT_EQ(wrong, 0) << roi << " channels " << src.channels();
        }
        Mat dx, dy;
        cv::forestmod::detail::strongestGradient(img(roi), dx, dy);
        const PointSobel ps(img(roi));
        int wrong = 0;
        for (int y = 0; y < roi.height; ++y)
            for (int x = 0; x < roi.width; ++x)
            {
                int gx = 0, gy = 0;
                ps.strongest(x, y, gx, gy);
                wrong += (float)gx != dx.at<float>(y, x) || (float)gy != dy.at<float>(y, x);
            }
        EXPECT_EQ(wrong, 0) << roi;
    }
}

TEST(Forestmod_Verification, params_read_write)
{
    VerificationParams p;
    p.enabled = false;
    p.top_k = 7;
    p.second_round_below = 0.6;
    p.min_saturation = 0.3;
    p.min_value = 0.2;
    p.hue_tolerance = 25;
    p.edge_distance = 2.5;
    p.edge_params.orientations = 8;
    p.depth_tolerance = 0.07;
    p.min_visible = 0.4;
    p.sample_step = 3;
    p.w_similarity = 0.1;
    p.w_color = 0.5;
    p.w_edges = 0.3;
    p.w_depth = 0.6;
    p.w_region = 0.25;
    p.region_width = 9;
    p.background_weight = 0.75;
    p.background_quantile = 0.95;
    PoseParams pp;
    pp.verification = p;
    pp.depth_hypotheses = 5;
    FileStorage fs(".yml", FileStorage::WRITE | FileStorage::MEMORY);
    fs << "pose" << "{";
    pp.write(fs);
    fs << "}";
    const String text = fs.releaseAndGetString();
    FileStorage in(text, FileStorage::READ | FileStorage::MEMORY);
    PoseParams qq;
    qq.read(in["pose"]);
    EXPECT_EQ(qq.depth_hypotheses, 5);
    const VerificationParams& q = qq.verification;
    EXPECT_EQ(q.enabled, p.enabled);
    EXPECT_EQ(q.top_k, p.top_k);
    EXPECT_EQ(q.second_round_below, p.second_round_below);
    EXPECT_EQ(q.min_saturation, p.min_saturation);
    EXPECT_EQ(q.min_value, p.min_value);
    EXPECT_EQ(q.hue_tolerance, p.hue_tolerance);
    EXPECT_EQ(q.edge_distance, p.edge_distance);
    EXPECT_EQ(q.edge_params.orientations, p.edge_params.orientations);
    EXPECT_EQ(q.depth_tolerance, p.depth_tolerance);
    EXPECT_EQ(q.min_visible, p.min_visible);
    EXPECT_EQ(q.sample_step, p.sample_step);
    EXPECT_EQ(q.w_similarity, p.w_similarity);
    EXPECT_EQ(q.w_color, p.w_color);
    EXPECT_EQ(q.w_edges, p.w_edges);
    EXPECT_EQ(q.w_depth, p.w_depth);
    EXPECT_EQ(q.w_region, p.w_region);
    EXPECT_EQ(q.region_width, p.region_width);
    EXPECT_EQ(q.background_weight, p.background_weight);
    EXPECT_EQ(q.background_quantile, p.background_quantile);
    // absent keys keep their values (files of older versions)
    FileStorage empty("{}", FileStorage::READ | FileStorage::MEMORY | FileStorage::FORMAT_JSON);
    VerificationParams d;
    d.read(empty.root());
    EXPECT_EQ(d.top_k, VerificationParams().top_k);
    EXPECT_EQ(d.second_round_below, VerificationParams().second_round_below);
    EXPECT_EQ(d.w_color, VerificationParams().w_color);
}

TEST(Forestmod_Verification, bad_input_raises)
{
    Ptr<cv::forestmod::Detector> det = getDefaultForestLINE();
    std::vector<PoseMatch> m(1);
    const Mat color(480, 640, CV_8UC3, Scalar::all(0));
    const Matx33d K = lmoIntrinsics();
    EXPECT_THROW(det->verify(Mat(), noArray(), K, m), cv::Exception);
    EXPECT_THROW(det->verify(Mat(480, 640, CV_8UC1), noArray(), K, m), cv::Exception);
    EXPECT_THROW(det->verify(color, Mat(480, 640, CV_32FC1), K, m), cv::Exception);
    EXPECT_THROW(det->verify(color, Mat(240, 320, CV_16UC1), K, m), cv::Exception);
    EXPECT_THROW(det->verify(color, noArray(), Matx33d::zeros(), m), cv::Exception);
    VerificationParams p;
    p.top_k = 0;
    EXPECT_THROW(det->verify(color, noArray(), K, m, p), cv::Exception);
    p = VerificationParams();
    p.w_color = -1;
    EXPECT_THROW(det->verify(color, noArray(), K, m, p), cv::Exception);
    p = VerificationParams();
    p.second_round_below = -0.1;
    EXPECT_THROW(det->verify(color, noArray(), K, m, p), cv::Exception);
    p.second_round_below = std::numeric_limits<double>::quiet_NaN();
    EXPECT_THROW(det->verify(color, noArray(), K, m, p), cv::Exception);
    p = VerificationParams();
    p.w_similarity = p.w_color = p.w_edges = p.w_region = 0;
    EXPECT_THROW(det->verify(color, noArray(), K, m, p), cv::Exception);
    p = VerificationParams();
    p.w_region = std::numeric_limits<double>::quiet_NaN();
    EXPECT_THROW(det->verify(color, noArray(), K, m, p), cv::Exception);
    p = VerificationParams();
    p.region_width = 0;
    EXPECT_THROW(det->verify(color, noArray(), K, m, p), cv::Exception);
    p = VerificationParams();
    p.edge_distance = p.edge_params.max_distance;
    EXPECT_THROW(det->verify(color, noArray(), K, m, p), cv::Exception);
    p = VerificationParams();
    p.hue_tolerance = 0;
    EXPECT_THROW(det->verify(color, noArray(), K, m, p), cv::Exception);
    p = VerificationParams();
    p.min_visible = 0;
    EXPECT_THROW(det->verify(color, noArray(), K, m, p), cv::Exception);
    p = VerificationParams();
    p.edge_params.orientations = 1;
    EXPECT_THROW(det->verify(color, noArray(), K, m, p), cv::Exception);
    p = VerificationParams();
    p.sample_step = 0;
    EXPECT_THROW(det->verify(color, noArray(), K, m, p), cv::Exception);
    p = VerificationParams();
    p.background_weight = -0.5;
    EXPECT_THROW(det->verify(color, noArray(), K, m, p), cv::Exception);
    p = VerificationParams();
    p.background_quantile = 0;
    EXPECT_THROW(det->verify(color, noArray(), K, m, p), cv::Exception);
    // detect() checks the verification's parameters too
    PoseParams pp;
    pp.verification.top_k = 0;
    std::vector<PoseMatch> out;
    EXPECT_THROW(det->detect(std::vector<Mat>(2, color), K, 80.f, out, std::vector<String>(), pp),
                 cv::Exception);
    // the defaults are valid
    EXPECT_NO_THROW(det->verify(color, noArray(), K, m));
}

}} // namespace
