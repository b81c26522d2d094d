// This file is part of OpenCV project.
// It is subject to the license terms in the LICENSE file found in the top-level directory
// of this distribution and at http://opencv.org/license.html

// The background similarity of matches (Detector::backgroundSimilarity, PoseMatch::background,
// VerificationParams::background_weight): the quantile of a template's similarities over the
// frame, higher for a template that fits the frame in many places; detect() fills it.

#include "test_precomp.hpp"
#include "test_pose_common.hpp"

namespace opencv_test { namespace {

/** The ape drawn at one view over a plain noisy background, at `places` places of a 4 x 2 grid
of the 640 x 480 frame (the first places of it, row by row). */
static Mat apesOnPlainFrame(const Mesh& ape, const ViewPose& v, int places)
{
    const Matx33d K = lmoIntrinsics();
    Mat color(480, 640, CV_8UC3, Scalar(95, 105, 100));
    Mat noise(color.size(), CV_8UC3);
    RNG rng(5);
    rng.fill(noise, RNG::NORMAL, 0, 3);
    color += noise;
    Ptr<Renderer> r = Renderer::create(Size(640, 480));
    const int h = r->addMesh(ape);
    for (int k = 0; k < places; ++k)
    {
        // the image point (x, y) of the grid cell, moved to the view's depth
        const double x = 80 + 160 * (k % 4), y = 120 + 240 * (k / 4);
        const double z = v.t[2];
        const Vec3d t((x - K(0, 2)) * z / K(0, 0), (y - K(1, 2)) * z / K(1, 1), z);
        Mat c, mask;
        r->render(h, v.R, t, K, c, noArray(), mask);
        c.copyTo(color, mask);
    }
    return color;
}

struct ApeTemplates
{
    Mesh ape;
    std::vector<ViewPose> views;

    ApeTemplates() : ape(Mesh::load(cvtest::findDataFile("lmo_mini/models/obj_000001.ply")))
    {
        ViewSampler::Params sp;
        sp.level = 0;
        sp.min_elevation = 30;
        sp.radii = std::vector<double>(1, 900.0);
        sp.inplane_min = sp.inplane_max = 0;
        sp.inplane_step = 10;
        views = ViewSampler(sp).poses(Point3d(ape.center().x, ape.center().y, ape.center().z));
        CV_Assert(!views.empty());
    }
    Ptr<cv::forestmod::Detector> detector(const std::vector<int>& T, bool forest) const
    {
        std::vector<Ptr<linemod::Modality> > mods(1, linemod::Modality::create("ColorGradient"));
        DetectorParams p;
        p.use_forest = forest;
        Ptr<cv::forestmod::Detector> det = makePtr<cv::forestmod::Detector>(mods, T, p);
        Ptr<Renderer> r = Renderer::create(Size(640, 480));
        const int h = r->addMesh(ape);
        for (size_t i = 0; i < views.size(); ++i)
        {
            Mat c, mask;
            r->render(h, views[i].R, views[i].t, lmoIntrinsics(), c, noArray(), mask);
            det->addTemplate(std::vector<Mat>(1, c), "ape", mask);
        }
        CV_Assert(det->numTemplates() > 0);
        return det;
    }
    // the default pyramid (T = 5, 8) with the forest
    Ptr<cv::forestmod::Detector> forestDetector() const
    {
        std::vector<int> T;
        T.push_back(5);
        T.push_back(8);
        return detector(T, true);
    }
};

// On a detector of one pyramid level and the plain LINEMOD search, match() at threshold 0 and
// without NMS reports every position whose similarity exceeds 50 % (LINEMOD's threshold 0: half
// the largest raw score), each scored one by one; the background is the quantile of every
// position's similarity, read from the linearized memories (32 positions at a time).
TEST(Forestmod_Background, is_the_quantile_of_the_templates_similarity_over_the_frame)
{
    const ApeTemplates a;
    Ptr<cv::forestmod::Detector> det = a.detector(std::vector<int>(1, 8), false);
    DetectorParams p = det->getParams();
    p.nms_iou = 0; // every match
    det->setParams(p);
    const std::vector<Mat> src(1, apesOnPlainFrame(a.ape, a.views[0], 8));
    std::vector<linemod::Match> all;
    det->match(src, 0.f, all);
    ASSERT_FALSE(all.empty());
    int exact = 0;
    for (int id = 0; id < det->numTemplates("ape"); ++id)
    {
        const linemod::Template& t = det->getTemplates("ape", id)[0];
        const int positions = (640 / 8 - ((t.width - 1) / 8 + 1) + 1)
                              * (480 / 8 - ((t.height - 1) / 8 + 1) + 1);
        std::vector<float> sims;
        for (size_t i = 0; i < all.size(); ++i)
            if (all[i].template_id == id)
                sims.push_back(all[i].similarity);
        ASSERT_LE((int)sims.size(), positions);
        const size_t reported = sims.size();
        sims.resize(positions, -1.f); // not reported: at most 50.5 (LINEMOD's rounding offset)
        std::sort(sims.begin(), sims.end());
        const double qs[] = { 0.5, 0.9, 0.99, 0.995, 0.998, 1.0 };
        double last = -1;
        for (double q : qs)
        {
            std::vector<PoseMatch> m(1, PoseMatch(linemod::Match(0, 0, 0.f, "ape", id)));
            det->backgroundSimilarity(src, m, q);
            const size_t rank = std::max<size_t>(1, (size_t)std::ceil(q * positions));
            if (sims[rank - 1] >= 0)
            {
                EXPECT_NEAR(m[0].background, sims[rank - 1], 1e-3)
                    << "template " << id << ", q " << q << ", " << reported << " reported";
                ++exact;
            }
            else
                EXPECT_LE(m[0].background, 50.5 + 1e-3) << "template " << id << ", q " << q;
            EXPECT_GE(m[0].background, last);
            last = m[0].background;
        }
        EXPECT_GT(last, 90.0) << "the template fits one of the apes";
    }
    EXPECT_GE(exact, 2 * det->numTemplates("ape")) << "quantiles among the reported positions";
}

// A template that fits the frame in many places has a high background; where it fits once, its
// background is that of the plain frame.
TEST(Forestmod_Background, rises_with_the_places_the_template_fits)
{
    const ApeTemplates a;
    Ptr<cv::forestmod::Detector> det = a.forestDetector();
    std::vector<PoseMatch> m(1, PoseMatch(linemod::Match(0, 0, 0.f, "ape", 0)));
    double background[3];
    const int places[] = { 1, 4, 8 };
    for (int k = 0; k < 3; ++k)
    {
        const std::vector<Mat> src(1, apesOnPlainFrame(a.ape, a.views[0], places[k]));
        det->backgroundSimilarity(src, m, 0.99);
        background[k] = m[0].background;
    }
    std::cout << "background (q = 0.99) with the ape at 1 / 4 / 8 places: " << background[0]
              << " / " << background[1] << " / " << background[2] << std::endl;
    EXPECT_LT(background[0], 60.0);
    EXPECT_GT(background[1], background[0] + 15.0);
    EXPECT_GT(background[2], 90.0);
}

// detect() gives its detections their background when it orders by it, and leaves -1 without.
TEST(Forestmod_Background, detect_fills_background_when_it_orders_by_it)
{
    const ApeTemplates a;
    Ptr<cv::forestmod::Detector> det = a.forestDetector();
    det->setMesh("ape", a.ape);
    const std::vector<Mat> src(1, apesOnPlainFrame(a.ape, a.views[0], 2));
    for (int on = 0; on < 2; ++on)
    {
        PoseParams pp;
        pp.verification.background_weight = on ? 1.5 : 0.0;
        std::vector<PoseMatch> out;
        DetectionStats stats;
        det->detect(src, lmoIntrinsics(), 80.f, out, std::vector<String>(), pp, &stats);
        ASSERT_GE(out.size(), 2u) << "both apes";
        for (size_t i = 0; i < out.size(); ++i)
            if (on)
            {
                EXPECT_GE(out[i].background, 0.0);
                EXPECT_LE(out[i].background, out[i].similarity + 1e-3);
            }
            else
                EXPECT_EQ(out[i].background, -1.0);
        if (on)
            EXPECT_GT(stats.t_background_ms, 0.0);
        else
            EXPECT_EQ(stats.t_background_ms, 0.0);
    }
}

// orderByBackground(): stable, by similarity - weight x background.
TEST(Forestmod_Background, order_is_similarity_minus_weighted_background)
{
    std::vector<PoseMatch> m;
    const float sim[] = { 95.f, 90.f, 88.f, 90.f };
    const double bg[] = { 60.0, 40.0, 20.0, 40.0 };
    for (int i = 0; i < 4; ++i)
    {
        m.push_back(PoseMatch(linemod::Match(0, 0, sim[i], "ape", i)));
        m.back().background = bg[i];
    }
    std::vector<PoseMatch> w0 = m, w1 = m;
    orderByBackground(w0, 0.0); // the similarity's order, ties kept in place
    EXPECT_EQ(0, w0[0].template_id);
    EXPECT_EQ(1, w0[1].template_id);
    EXPECT_EQ(3, w0[2].template_id);
    EXPECT_EQ(2, w0[3].template_id);
    orderByBackground(w1, 1.5); // keys 5, 30, 58, 30
    EXPECT_EQ(2, w1[0].template_id);
    EXPECT_EQ(1, w1[1].template_id);
    EXPECT_EQ(3, w1[2].template_id);
    EXPECT_EQ(0, w1[3].template_id);
    EXPECT_THROW(orderByBackground(w1, -1.0), cv::Exception);
    w1[2].background = -1; // not computed
    EXPECT_THROW(orderByBackground(w1, 1.5), cv::Exception);
}

TEST(Forestmod_Background, bad_input_raises)
{
    const ApeTemplates a;
    Ptr<cv::forestmod::Detector> det = a.forestDetector();
    const std::vector<Mat> src(1, apesOnPlainFrame(a.ape, a.views[0], 1));
    std::vector<PoseMatch> m(1, PoseMatch(linemod::Match(0, 0, 0.f, "ape", 0)));
    EXPECT_THROW(det->backgroundSimilarity(src, m, 0.0), cv::Exception);
    EXPECT_THROW(det->backgroundSimilarity(src, m, 1.5), cv::Exception);
    EXPECT_THROW(det->backgroundSimilarity(src, m, std::numeric_limits<double>::quiet_NaN()),
                 cv::Exception);
    EXPECT_THROW(det->backgroundSimilarity(std::vector<Mat>(), m, 0.99), cv::Exception);
    EXPECT_THROW(det->backgroundSimilarity(std::vector<Mat>(1, Mat()), m, 0.99), cv::Exception);
    std::vector<PoseMatch> other(1, PoseMatch(linemod::Match(0, 0, 0.f, "duck", 0)));
    EXPECT_THROW(det->backgroundSimilarity(src, other, 0.99), cv::Exception);
    std::vector<PoseMatch> beyond(1, PoseMatch(linemod::Match(0, 0, 0.f, "ape", 9999)));
    EXPECT_THROW(det->backgroundSimilarity(src, beyond, 0.99), cv::Exception);
    // no matches: nothing to do
    std::vector<PoseMatch> none;
    EXPECT_NO_THROW(det->backgroundSimilarity(src, none, 0.99));
    EXPECT_NO_THROW(det->backgroundSimilarity(src, m, 0.99));
    EXPECT_GE(m[0].background, 0.0);
}

}} // namespace
