// This file is part of OpenCV project.
// It is subject to the license terms in the LICENSE file found in the top-level directory
// of this distribution and at http://opencv.org/license.html

#include "test_precomp.hpp"
#include "../src/model_check.hpp"
#include "../src/scan.hpp"

#include <set>

namespace opencv_test { namespace {

// A flat-coloured L-shaped object with a disc, drawn rotated by `angle` around `centre`.
static void drawObject(Mat& img, Mat* mask, Point2f centre, float angle, float scale)
{
    const Point2f pts[] = { Point2f(-40, -50), Point2f(10, -50), Point2f(10, 10), Point2f(45, 10),
                            Point2f(45, 50), Point2f(-40, 50) };
    std::vector<Point> poly;
    const float c = std::cos(angle * (float)CV_PI / 180), s = std::sin(angle * (float)CV_PI / 180);
    for (size_t i = 0; i < sizeof(pts) / sizeof(pts[0]); ++i)
    {
        const Point2f p = pts[i] * scale;
        poly.push_back(Point(cvRound(centre.x + c * p.x - s * p.y),
                             cvRound(centre.y + s * p.x + c * p.y)));
    }
    fillConvexPoly(img, &poly[0], 4, Scalar(30, 60, 200), LINE_AA);
    std::vector<std::vector<Point> > polys(1, poly);
    fillPoly(img, polys, Scalar(30, 60, 200), LINE_AA);
    const Point2f d = Point2f(-15, 25) * scale;
    const Point disc(cvRound(centre.x + c * d.x - s * d.y), cvRound(centre.y + s * d.x + c * d.y));
    circle(img, disc, cvRound(14 * scale), Scalar(200, 140, 20), FILLED, LINE_AA);
    if (mask)
    {
        *mask = Mat::zeros(img.size(), CV_8U);
        fillPoly(*mask, polys, Scalar(255));
    }
}

static Mat clutter(Size size, RNG& rng)
{
    Mat coarse(size.height / 20 + 1, size.width / 20 + 1, CV_8UC3), img;
    rng.fill(coarse, RNG::UNIFORM, Scalar::all(40), Scalar::all(160));
    resize(coarse, img, size, 0, 0, INTER_LINEAR);
    for (int i = 0; i < 25; ++i)
    {
        const Point a(rng.uniform(0, size.width), rng.uniform(0, size.height));
        const Point b = a + Point(rng.uniform(-80, 80), rng.uniform(-80, 80));
        const Scalar col(rng.uniform(0, 255), rng.uniform(0, 255), rng.uniform(0, 255));
        if (i % 2)
            rectangle(img, a, b, col, FILLED);
        else
            line(img, a, b, col, 3);
    }
    return img;
}

// n templates of the object at angles -40..40 and two scales
template <typename D>
static void addObjectTemplates(D& det, int n, const String& class_id, std::vector<float>* angles)
{
    const Size size(640, 480);
    for (int i = 0; i < n; ++i)
    {
        const float angle = -40.f + 80.f * i / std::max(1, n - 1);
        const float scale = (i % 2) ? 1.0f : 0.85f;
        Mat img = Mat::zeros(size, CV_8UC3), mask;
        drawObject(img, &mask, Point2f(320, 240), angle, scale);
        std::vector<Mat> sources(det.getModalities().size(), img);
        ASSERT_GE(det.addTemplate(sources, class_id, mask), 0) << i;
        if (angles)
            angles->push_back(angle);
    }
}

static Ptr<linemod::Modality> gradient() { return linemod::Modality::create("ColorGradient"); }

// gradient + hue (getDefaultForestLINE's modalities)
static std::vector<Ptr<linemod::Modality> > gradientHue()
{
    std::vector<Ptr<linemod::Modality> > mods;
    mods.push_back(gradient());
    mods.push_back(ColorHue::create());
    return mods;
}

static std::vector<int> Tpyr()
{
    std::vector<int> T;
    T.push_back(5);
    T.push_back(8);
    return T;
}

TEST(Forestmod_Detector, exhaustive_mode_equals_linemod)
{
    const std::vector<Ptr<linemod::Modality> > mods = gradientHue();
    DetectorParams p;
    p.use_forest = false;
    p.nms_iou = 0.f;
    cv::linemod::Detector ref(mods, Tpyr());
    cv::forestmod::Detector det(mods, Tpyr(), p);
    addObjectTemplates(ref, 12, "obj", 0);
    addObjectTemplates(det, 12, "obj", 0);
    ASSERT_EQ(ref.numTemplates(), det.numTemplates());

    RNG rng(7);
    Mat scene = clutter(Size(640, 480), rng);
    drawObject(scene, 0, Point2f(260, 300), 12.f, 1.0f);
    std::vector<Mat> sources(2, scene);
    std::vector<linemod::Match> a, b;
    const float thr = 70.f;
    ref.match(sources, thr, a);
    det.match(sources, thr, b);
    ASSERT_FALSE(a.empty());
    ASSERT_FALSE(b.empty());
    // cv::linemod may add matches whose template wrapped around the right image border (its
    // linear memories do); every other match must be identical.
    int found = 0;
    for (size_t i = 0; i < b.size(); ++i)
    {
        bool same = false;
        for (size_t j = 0; j < a.size() && !same; ++j)
            same = a[j].x == b[i].x && a[j].y == b[i].y && a[j].template_id == b[i].template_id
                && std::fabs(a[j].similarity - b[i].similarity) <= 0.005f * a[j].similarity;
        found += same;
    }
    EXPECT_EQ((int)b.size(), found);
    EXPECT_GE(b.size(), (size_t)(0.9 * a.size())) << a.size() << " vs " << b.size();
    EXPECT_EQ(a[0].x, b[0].x);
    EXPECT_EQ(a[0].y, b[0].y);
    EXPECT_EQ(a[0].template_id, b[0].template_id);
    EXPECT_NEAR(a[0].similarity, b[0].similarity, 0.005 * a[0].similarity);
}

// the same program for both types: drop-in
template <typename D>
static void dropInProgram(const std::string& tag, bool* found)
{
    std::vector<Ptr<linemod::Modality> > mods(1, gradient());
    D det(mods, Tpyr());
    std::vector<float> angles;
    addObjectTemplates(det, 9, "L", &angles);
    const std::string fmt = cv::tempfile(("_" + tag + "_%s.yml.gz").c_str());
    det.writeClasses(fmt);
    D det2(mods, Tpyr());
    std::vector<String> ids(1, "L");
    det2.readClasses(ids, fmt);
    std::remove(cv::format(fmt.c_str(), "L").c_str());
    ASSERT_EQ(det.numTemplates(), det2.numTemplates());
    ASSERT_EQ(1, det2.numClasses());
    RNG rng(99);
    Mat scene = clutter(Size(640, 480), rng);
    drawObject(scene, 0, Point2f(400, 260), 10.f, 1.0f);
    std::vector<linemod::Match> matches;
    det2.match(std::vector<Mat>(1, scene), 80.f, matches, ids);
    ASSERT_FALSE(matches.empty()) << tag;
    const linemod::Match& m = matches[0];
    const std::vector<linemod::Template>& t = det2.getTemplates(m.class_id, m.template_id);
    const Point centre(m.x + t[0].width / 2, m.y + t[0].height / 2);
    EXPECT_LE(cv::norm(centre - Point(400, 260)), 12.0) << tag << " " << centre;
    EXPECT_LE(std::fabs(angles[m.template_id] - 10.f), 10.1f) << tag;
    *found = true;
}

TEST(Forestmod_Detector, drop_in_for_linemod_programs)
{
    bool a = false, b = false;
    dropInProgram<cv::linemod::Detector>("linemod", &a);
    dropInProgram<cv::forestmod::Detector>("forestmod", &b);
    EXPECT_TRUE(a);
    EXPECT_TRUE(b);
}

TEST(Forestmod_Detector, forest_finds_object_and_rejects_background)
{
    const std::vector<Ptr<linemod::Modality> > mods = gradientHue();
    DetectorParams p;
    p.exhaustive_ratio = -1.f; // the forest path in every frame, which is tested here
    cv::forestmod::Detector det(mods, Tpyr(), p);
    std::vector<float> angles;
    addObjectTemplates(det, 40, "L", &angles);
    det.train();
    ASSERT_TRUE(det.isTrained());
    RNG rng(3);
    int hits = 0;
    double rejected = 0;
    const int trials = 8;
    for (int k = 0; k < trials; ++k)
    {
        Mat scene = clutter(Size(640, 480), rng);
        const Point2f at(rng.uniform(150.f, 490.f), rng.uniform(130.f, 350.f));
        const float angle = rng.uniform(-35.f, 35.f);
        drawObject(scene, 0, at, angle, 1.0f);
        std::vector<cv::forestmod::PoseMatch> matches;
        DetectionStats stats;
        det.match(std::vector<Mat>(2, scene), 80.f, matches, std::vector<String>(),
                  std::vector<Mat>(), &stats);
        rejected += stats.rejectedFraction();
        EXPECT_GT(stats.locations, 0);
        if (matches.empty())
            continue;
        const Point2f c(matches[0].box.x + matches[0].box.width / 2.f,
                        matches[0].box.y + matches[0].box.height / 2.f);
        if (cv::norm(c - at) <= 10 && std::fabs(angles[matches[0].template_id] - angle) <= 12)
            ++hits;
    }
    EXPECT_GE(hits, trials - 1);
    std::cout << "[ INFO    ] rejected before validation: " << 100 * rejected / trials << " %"
              << std::endl;
    EXPECT_GE(rejected / trials, 0.5);
}

// The sample counts the trees' descents (DetectorParams::descent_cost): without them the 40
// templates' group stays on the forest path on clutter (its leaves let few pairs through); with
// a high cost per node the same sample sends it to the exhaustive search, whose matches are then
// those of exhaustive_ratio 0.
TEST(Forestmod_Detector, the_sample_counts_the_descents)
{
    const std::vector<Ptr<linemod::Modality> > mods = gradientHue();
    DetectorParams p;
    p.min_forest_templates = 0; // 40 templates: decided by the sample
    p.descent_cost = 0.f;
    cv::forestmod::Detector det(mods, Tpyr(), p);
    addObjectTemplates(det, 40, "L", 0);
    det.train();
    DetectorParams costly = p, exhaustive = p;
    costly.descent_cost = 100.f;
    exhaustive.exhaustive_ratio = 0.f;
    RNG rng(3);
    int on_forest = 0;
    const int trials = 4;
    for (int k = 0; k < trials; ++k)
    {
        Mat scene = clutter(Size(640, 480), rng);
        drawObject(scene, 0, Point2f(rng.uniform(150.f, 490.f), rng.uniform(130.f, 350.f)),
                   rng.uniform(-35.f, 35.f), 1.0f);
        const std::vector<Mat> src(2, scene);
        std::vector<linemod::Match> a, b, c;
        DetectionStats st, st_costly; // match() adds to the counters
        det.setParams(p);
        det.match(src, 80.f, a, std::vector<String>(), noArray(), std::vector<Mat>(), &st);
        on_forest += st.validated > 0;
        det.setParams(costly);
        det.match(src, 80.f, b, std::vector<String>(), noArray(), std::vector<Mat>(),
                  &st_costly);
        EXPECT_EQ(0, st_costly.validated) << "frame " << k << ": the descents send the group away";
        det.setParams(exhaustive);
        det.match(src, 80.f, c);
        expectSameMatches(c, b, "descent_cost 100 against exhaustive_ratio 0");
        EXPECT_FALSE(b.empty());
    }
    EXPECT_EQ(trials, on_forest) << "without the descents' cost the forest path is kept";
    // the parameter: written and read back, refused when negative or not finite
    costly.descent_cost = 3.5f;
    EXPECT_EQ(3.5f, writtenAndRead(costly).descent_cost);
    costly.descent_cost = -1.f;
    EXPECT_THROW(det.setParams(costly), cv::Exception);
    costly.descent_cost = std::numeric_limits<float>::quiet_NaN();
    EXPECT_THROW(det.setParams(costly), cv::Exception);
}

// setParams() keeps the trained forests when only match()'s parameters change (a loaded model
// of many objects would otherwise be trained again, for minutes, at the next match), and marks
// them for retraining when a parameter that shapes them changes.
TEST(Forestmod_Detector, setParams_keeps_the_forests_unless_they_change)
{
    const std::vector<Ptr<linemod::Modality> > mods = gradientHue();
    cv::forestmod::Detector det(mods, Tpyr()), fresh(mods, Tpyr());
    addObjectTemplates(det, 20, "L", 0);
    addObjectTemplates(fresh, 20, "L", 0);
    det.train();
    const Ptr<TemplateForest> forest = det.getForest(0);
    ASSERT_FALSE(forest.empty());
    DetectorParams p = det.getParams();
    p.min_window_labels = 0.4f;
    p.depth_range_tolerance = 0.3f;
    p.breadth_first = false;
    p.chunk_size = 8;
    p.alpha = 0.4f;
    p.max_survivors = 2;
    p.exhaustive_ratio = 0.05f;
    p.depth_samples = 32;
    p.depth_tolerance = 7;
    p.nms_iou = 0.3f;
    det.setParams(p);
    EXPECT_TRUE(det.isTrained());
    EXPECT_EQ(forest.get(), det.getForest(0).get());
    // the kept forests with the new parameters match as forests trained with them
    fresh.setParams(p);
    fresh.train();
    RNG rng(11);
    Mat scene = clutter(Size(640, 480), rng);
    drawObject(scene, 0, Point2f(300.f, 220.f), 10.f, 1.0f);
    std::vector<linemod::Match> a, b;
    det.match(std::vector<Mat>(2, scene), 80.f, a);
    fresh.match(std::vector<Mat>(2, scene), 80.f, b);
    ASSERT_FALSE(a.empty());
    expectSameMatches(a, b);
    // each parameter of the search index marks the forests for retraining
    for (int k = 0; k < 10; ++k)
    {
        det.train();
        ASSERT_TRUE(det.isTrained());
        DetectorParams q = det.getParams();
        switch (k)
        {
        case 0: q.forest.num_trees += 1; break;
        case 1: q.forest.rejector_dims /= 2; break;
        case 2: q.forest.fuzzy_margin += 1; break;
        case 3: q.forest.seed += 1; break;
        case 4: q.grid_size += 2; break;
        case 5: q.dominant_window = 1; break;
        case 6: q.group_size_ratio = 0.f; break;
        case 7: q.auto_depth_leaf_samples *= 2; break;
        case 8: q.group_templates = !q.group_templates; break;
        default: q.location_step = 2; break;
        }
        det.setParams(q);
        EXPECT_FALSE(det.isTrained()) << "change " << k;
        det.setParams(p);
    }
}

TEST(Forestmod_Detector, more_than_63_features_and_single_modality)
{
    // 150 gradient features per template: 8-bit accumulation would overflow
    std::vector<Ptr<linemod::Modality> > mods(1, linemod::ColorGradient::create(10.f, 150, 55.f));
    DetectorParams p;
    p.use_forest = false;
    cv::forestmod::Detector det(mods, Tpyr(), p);
    addObjectTemplates(det, 5, "L", 0);
    const std::vector<linemod::Template>& t = det.getTemplates("L", 0);
    ASSERT_GT(t[0].features.size(), 63u);
    RNG rng(5);
    Mat scene = clutter(Size(640, 480), rng);
    drawObject(scene, 0, Point2f(300, 200), -20.f, 1.0f); // template 1
    std::vector<linemod::Match> matches;
    det.match(std::vector<Mat>(1, scene), 80.f, matches);
    ASSERT_FALSE(matches.empty());
    EXPECT_LE(matches[0].similarity, 100.f);
    EXPECT_GT(matches[0].similarity, 80.f);
    const Point centre(matches[0].x + t[0].width / 2, matches[0].y + t[0].height / 2);
    EXPECT_LE(cv::norm(centre - Point(300, 200)), 12.0)
        << matches.size() << " matches; best " << matches[0].x << "," << matches[0].y << " "
        << matches[0].similarity << " t" << matches[0].template_id << " w " << t[0].width;
    // and with the forest on
    DetectorParams pf;
    det.setParams(pf);
    det.match(std::vector<Mat>(1, scene), 80.f, matches);
    ASSERT_FALSE(matches.empty());
    const Point c2(matches[0].x + t[0].width / 2, matches[0].y + t[0].height / 2);
    EXPECT_LE(cv::norm(c2 - Point(300, 200)), 12.0);
}

// The distinct (x, y, similarity) of a match list: matches of different templates at the same
// place and score are equal for Match::operator== and the unique() after sorting keeps one of
// them, depending on their order; the places and scores are the same whatever the order.
static std::vector<Vec3f> places(const std::vector<linemod::Match>& m)
{
    std::vector<Vec3f> p;
    for (size_t i = 0; i < m.size(); ++i)
        p.push_back(Vec3f((float)m[i].x, (float)m[i].y, m[i].similarity));
    std::sort(p.begin(), p.end(), [](const Vec3f& a, const Vec3f& b) {
        return a[0] != b[0] ? a[0] < b[0] : a[1] != b[1] ? a[1] < b[1] : a[2] < b[2];
    });
    p.erase(std::unique(p.begin(), p.end()), p.end());
    return p;
}

// DetectorParams::exhaustive_ratio = 0 searches every group exhaustively with the vectorised
// path: every position of the T grid keeps its best templates over the threshold, so the matches
// are those of the scalar exhaustive search (use_forest = false) that were among the best at
// their coarse position; with 8-bit (gradient + hue, <= 63 features) and 16-bit (150 features) sums alike.
TEST(Forestmod_Detector, exhaustive_groups_keep_the_best_of_the_exhaustive_search)
{
    for (int variant = 0; variant < 2; ++variant)
    {
        std::vector<Ptr<linemod::Modality> > mods = gradientHue();
        if (variant == 1)
            mods.assign(1, linemod::ColorGradient::create(10.f, 150, 55.f));
        DetectorParams p;
        p.use_forest = false;
        p.nms_iou = 0.f;
        p.max_survivors = 1; // 4 of the 10 templates per position: the lists must cut
        cv::forestmod::Detector det(mods, Tpyr(), p);
        addObjectTemplates(det, 10, "L", 0);
        if (variant == 1)
        {
            ASSERT_GT(det.getTemplates("L", 0)[1].features.size(), 63u);
        }
        RNG rng(11 + variant);
        Mat scene = clutter(Size(640, 480), rng);
        drawObject(scene, 0, Point2f(300, 220), -20.f, 1.0f);
        drawObject(scene, 0, Point2f(600, 420), 30.f, 0.85f); // partly outside the image
        const std::vector<Mat> sources(mods.size(), scene);
        std::vector<linemod::Match> ref, got;
        det.match(sources, 60.f, ref);
        ASSERT_GT(ref.size(), 5u) << variant;
        p.use_forest = true;
        p.exhaustive_ratio = 0.f;
        det.setParams(p);
        det.match(sources, 60.f, got);
        ASSERT_FALSE(got.empty()) << variant;
        // at most max_survivors x (T / step)^2 = 4 matches per position of the T grid of the
        // coarsest level (320 x 240, T = 8, step 4), as many as the forest path's locations there
        EXPECT_LE(got.size(), (size_t)(4 * 40 * 30)) << variant;
        EXPECT_LT(got.size(), ref.size()) << variant;
        const std::vector<Vec3f> a = places(ref), b = places(got);
        for (size_t i = 0; i < b.size(); ++i)
            EXPECT_TRUE(std::binary_search(a.begin(), a.end(), b[i], [](const Vec3f& u,
                                                                        const Vec3f& v) {
                return u[0] != v[0] ? u[0] < v[0] : u[1] != v[1] ? u[1] < v[1] : u[2] < v[2];
            })) << variant << " " << b[i];
        // the best match is the exhaustive search's
        EXPECT_EQ(ref[0].x, got[0].x) << variant;
        EXPECT_EQ(ref[0].y, got[0].y) << variant;
        EXPECT_EQ(ref[0].similarity, got[0].similarity) << variant;
        // never exhaustive: the forest's validation, which sees only its candidates
        p.exhaustive_ratio = -1.f;
        det.setParams(p);
        std::vector<linemod::Match> forest;
        det.match(sources, 60.f, forest);
        EXPECT_LT(forest.size(), ref.size()) << variant;
    }
}

// The exhaustive search reads each template's runs of the memories from offsets the index keeps
// for the frame size it last saw: a frame of another size, and templates added since, get their
// own (the same matches as a detector that never saw another frame or other templates), also when
// threads match frames of both sizes at once.
TEST(Forestmod_Detector, exhaustive_runs_follow_the_frame_size_and_the_templates)
{
    const std::vector<Ptr<linemod::Modality> > mods = gradientHue();
    DetectorParams p;
    p.nms_iou = 0.f;
    p.exhaustive_ratio = 0.f;
    RNG rng(5);
    Mat large = clutter(Size(640, 480), rng);
    drawObject(large, 0, Point2f(300, 220), -20.f, 1.0f);
    drawObject(large, 0, Point2f(450, 330), 15.f, 0.85f);
    const Mat small = large(Rect(40, 24, 560, 408)).clone(); // other strides and rows of cells
    const std::vector<Mat> L(mods.size(), large), S(mods.size(), small);
    cv::forestmod::Detector seen(mods, Tpyr(), p);
    addObjectTemplates(seen, 10, "L", 0);
    std::vector<linemod::Match> large1, small1, large2;
    seen.match(L, 60.f, large1);
    seen.match(S, 60.f, small1);
    seen.match(L, 60.f, large2);
    ASSERT_FALSE(large1.empty());
    ASSERT_FALSE(small1.empty());
    expectSameMatches(large1, large2, "the large frame again");
    {
        cv::forestmod::Detector fresh(mods, Tpyr(), p);
        addObjectTemplates(fresh, 10, "L", 0);
        std::vector<linemod::Match> ref;
        fresh.match(S, 60.f, ref);
        expectSameMatches(ref, small1, "the small frame after the large one");
    }
    // more templates (the model is trained again at the next match), the frame size unchanged
    addObjectTemplates(seen, 7, "M", 0);
    cv::forestmod::Detector fresh(mods, Tpyr(), p);
    addObjectTemplates(fresh, 10, "L", 0);
    addObjectTemplates(fresh, 7, "M", 0);
    std::vector<linemod::Match> got, ref, ref_small;
    seen.match(L, 60.f, got);
    fresh.match(L, 60.f, ref);
    ASSERT_GT(ref.size(), large1.size());
    expectSameMatches(ref, got, "after templates were added");
    // several threads at once, frames of both sizes: each search reads the offsets it took
    fresh.match(S, 60.f, ref_small);
    std::vector<std::vector<linemod::Match> > at_once(4);
    std::vector<std::thread> threads;
    for (int k = 0; k < 4; ++k)
        threads.push_back(std::thread([&, k]() {
            for (int rep = 0; rep < 3; ++rep)
                seen.match(k % 2 ? S : L, 60.f, at_once[k]);
        }));
    for (size_t k = 0; k < threads.size(); ++k)
        threads[k].join();
    for (int k = 0; k < 4; ++k)
        expectSameMatches(k % 2 ? ref_small : ref, at_once[k], cv::format("thread %d", k));
}

// The scan decides per frame and search group between the forest path and the exhaustive search
// from the (location, candidate) pairs of a sample of its locations; a group whose limit is many
// pairs descends only every k-th location of the sample and extrapolates. A ratio 4x below the
// group's pairs per (template, position) over the frame sends it to the exhaustive search; 4x
// above keeps it on the forest path, with the candidates of every location (the sample's too).
TEST(Forestmod_Detector, exhaustive_decision_from_a_strided_sample)
{
    const std::vector<Ptr<linemod::Modality> > mods = gradientHue();
    DetectorParams p;
    p.forest.num_trees = 1;
    p.forest.max_depth = 2;     // large leaves and no rejectors: most locations pass, with many
    p.forest.rejector_dims = 0; // candidates each, so that the sample's limit is many pairs
    p.group_size_ratio = 2.f;   // one search group
    p.min_forest_templates = 0; // of 60 templates, decided by the sample
    cv::forestmod::Detector det(mods, Tpyr(), p);
    addObjectTemplates(det, 60, "L", 0);
    det.train();
    ASSERT_EQ(1, det.numSearchGroups());
    const Size size(1280, 960);
    const double positions = (size.width / 16) * (size.height / 16); // T grid of the coarsest level
    for (int seed = 1; seed <= 3; ++seed)
    {
        SCOPED_TRACE(seed);
        RNG rng(seed);
        Mat scene = clutter(size, rng);
        drawObject(scene, 0, Point2f(500.f, 400.f), 10.f, 1.0f);
        const std::vector<Mat> sources(mods.size(), scene);
        std::vector<linemod::Match> matches;
        DetectionStats all, below, above;
        p.exhaustive_ratio = -1.f;
        det.setParams(p);
        det.match(sources, 80.f, matches, std::vector<String>(), noArray(), std::vector<Mat>(),
                  &all);
        const double ratio = all.candidates / (60 * positions);
        // the sample's limit for the ratio below: all.candidates / 4 pairs over the frame, / 8 on
        // the sample (every 8th row), descended at every k-th location for k = that / 512
        // (src/scan.cpp): at least 5 here
        ASSERT_GT(all.candidates, 5 * 4 * 8 * 512) << "the group's limit must be many pairs";
        p.exhaustive_ratio = (float)(ratio / 4);
        det.setParams(p);
        det.match(sources, 80.f, matches, std::vector<String>(), noArray(), std::vector<Mat>(),
                  &below);
        EXPECT_EQ(0, below.candidates);
        EXPECT_EQ(0, below.validated);
        p.exhaustive_ratio = (float)(ratio * 4);
        det.setParams(p);
        det.match(sources, 80.f, matches, std::vector<String>(), noArray(), std::vector<Mat>(),
                  &above);
        EXPECT_EQ(all.candidates, above.candidates);
        EXPECT_EQ(all.validated, above.validated);
        EXPECT_EQ(all.rejected, above.rejected);
    }
}

// A template whose coarsest level holds 2 x 8192 features (the most a model may hold) sums beyond
// 16 bits: the exhaustive search scores it with LINEMOD's similarity, position by position, and
// still keeps the best of the linear search.
TEST(Forestmod_Detector, exhaustive_search_of_a_template_beyond_16_bit_sums)
{
    const std::vector<Ptr<linemod::Modality> > mods = gradientHue();
    DetectorParams p;
    p.use_forest = false;
    p.nms_iou = 0.f;
    cv::forestmod::Detector source(mods, Tpyr(), p);
    addObjectTemplates(source, 1, "L", 0);
    // the coarsest level's features repeated up to 8192 per modality: the same similarity
    std::vector<linemod::Template> t = source.getTemplates("L", 0);
    const int M = (int)mods.size();
    int total = 0;
    for (int m = 0; m < M; ++m)
    {
        std::vector<linemod::Feature>& f = t[M + m].features;
        ASSERT_FALSE(f.empty());
        const size_t n = f.size();
        while (f.size() < 8192)
            f.push_back(f[f.size() % n]);
        total += (int)f.size();
    }
    ASSERT_GT(total, 65535 / 4);
    cv::forestmod::Detector det(mods, Tpyr(), p);
    ASSERT_EQ(0, det.addSyntheticTemplate(t, "L"));
    RNG rng(5);
    Mat scene = clutter(Size(640, 480), rng);
    drawObject(scene, 0, Point2f(300, 220), -40.f, 0.85f);
    const std::vector<Mat> sources(M, scene);
    std::vector<linemod::Match> ref, got;
    det.match(sources, 70.f, ref);
    ASSERT_FALSE(ref.empty());
    EXPECT_LE(std::abs(ref[0].x + t[0].width / 2 - 300), 8);
    p.use_forest = true;
    p.exhaustive_ratio = 0.f;
    det.setParams(p);
    det.match(sources, 70.f, got);
    ASSERT_FALSE(got.empty());
    EXPECT_EQ(ref[0].x, got[0].x);
    EXPECT_EQ(ref[0].y, got[0].y);
    EXPECT_EQ(ref[0].similarity, got[0].similarity);
}

TEST(Forestmod_Detector, object_without_hue_is_learned_by_the_other_modalities)
{
    const std::vector<Ptr<linemod::Modality> > mods = gradientHue();
    cv::forestmod::Detector det(mods, Tpyr());
    Mat img = Mat::zeros(480, 640, CV_8UC3), mask = Mat::zeros(480, 640, CV_8U);
    rectangle(img, Rect(250, 180, 120, 90), Scalar(235, 235, 235), FILLED); // white box
    rectangle(mask, Rect(250, 180, 120, 90), Scalar(255), FILLED);
    const int id = det.addTemplate(std::vector<Mat>(2, img), "white", mask);
    ASSERT_EQ(0, id);
    const std::vector<linemod::Template>& t = det.getTemplates("white", 0);
    EXPECT_GT(t[0].features.size(), 0u); // gradient
    EXPECT_EQ(0u, t[1].features.size()); // hue
    RNG rng(8);
    Mat scene = clutter(Size(640, 480), rng);
    rectangle(scene, Rect(100, 200, 120, 90), Scalar(235, 235, 235), FILLED);
    std::vector<linemod::Match> matches;
    det.match(std::vector<Mat>(2, scene), 80.f, matches);
    ASSERT_FALSE(matches.empty());
    EXPECT_LE(std::abs(matches[0].x + t[0].width / 2 - 160), 8);
    EXPECT_LE(std::abs(matches[0].y + t[0].height / 2 - 245), 8);
    // a template of nothing at all is still refused
    EXPECT_EQ(-1, det.addTemplate(std::vector<Mat>(2, Mat::zeros(480, 640, CV_8UC3)), "none",
                                  mask));
}

TEST(Forestmod_Detector, any_image_size)
{
    std::vector<Ptr<linemod::Modality> > mods(1, gradient());
    cv::forestmod::Detector det(mods, Tpyr());
    addObjectTemplates(det, 5, "L", 0);
    RNG rng(11);
    Mat scene = clutter(Size(533, 397), rng); // divisible by neither 16 nor T
    drawObject(scene, 0, Point2f(250, 190), 0.f, 1.0f);
    std::vector<linemod::Match> matches;
    ASSERT_NO_THROW(det.match(std::vector<Mat>(1, scene), 80.f, matches));
    ASSERT_FALSE(matches.empty());
}

// match() returns its matches best first (Match::operator<), without repeats, and non-maximum
// suppression keeps the greedy leaders of the boxes of their templates (each class's own sizes),
// also in a model read back from a file (TemplateStore::setClass).
TEST(Forestmod_Detector, matches_sorted_and_suppressed_by_their_templates_boxes)
{
    const std::vector<Ptr<linemod::Modality> > mods = gradientHue();
    DetectorParams p;
    p.use_forest = false;
    p.nms_iou = 0.f;
    cv::forestmod::Detector det(mods, Tpyr(), p);
    addObjectTemplates(det, 8, "large", 0);
    for (int i = 0; i < 6; ++i) // a second class of smaller boxes
    {
        Mat img = Mat::zeros(Size(640, 480), CV_8UC3), mask;
        drawObject(img, &mask, Point2f(320, 240), -30.f + 12.f * i, 0.55f);
        ASSERT_GE(det.addTemplate(std::vector<Mat>(2, img), "small", mask), 0) << i;
    }
    RNG rng(5);
    Mat scene = clutter(Size(640, 480), rng);
    drawObject(scene, 0, Point2f(220, 200), 8.f, 1.0f);
    drawObject(scene, 0, Point2f(450, 330), -10.f, 0.55f);
    const std::string file = cv::tempfile(".yml.gz");
    det.save(file);
    cv::forestmod::Detector loaded;
    loaded.load(file);
    remove(file.c_str());
    cv::forestmod::Detector* dets[] = { &det, &loaded };
    for (int k = 0; k < 2; ++k)
    {
        cv::forestmod::Detector& d = *dets[k];
        DetectorParams q = d.getParams();
        q.nms_iou = 0.f;
        d.setParams(q);
        std::vector<linemod::Match> all, kept;
        d.match(std::vector<Mat>(2, scene), 65.f, all);
        ASSERT_GT(all.size(), 20u) << k;
        std::set<String> classes;
        for (size_t i = 0; i < all.size(); ++i)
        {
            classes.insert(all[i].class_id);
            if (i == 0)
                continue;
            EXPECT_FALSE(all[i] < all[i - 1]) << k << " match " << i;
            EXPECT_FALSE(all[i] == all[i - 1]) << k << " repeat " << i;
        }
        EXPECT_EQ(2u, classes.size()) << k;
        // the greedy definition on the boxes of the templates' level-0 sizes
        const float iou = 0.5f;
        std::vector<Rect> boxes;
        for (size_t i = 0; i < all.size(); ++i)
        {
            const linemod::Template& t = d.getTemplates(all[i].class_id, all[i].template_id)[0];
            boxes.push_back(Rect(all[i].x, all[i].y, std::max(1, t.width), std::max(1, t.height)));
        }
        std::vector<linemod::Match> expected;
        std::vector<Rect> kept_boxes;
        for (size_t i = 0; i < all.size(); ++i)
        {
            bool lead = true;
            for (size_t j = 0; j < kept_boxes.size() && lead; ++j)
            {
                const double inter = (boxes[i] & kept_boxes[j]).area();
                lead = !(inter / (boxes[i].area() + kept_boxes[j].area() - inter) > iou);
            }
            if (lead)
            {
                kept_boxes.push_back(boxes[i]);
                expected.push_back(all[i]);
            }
        }
        ASSERT_LT(expected.size(), all.size()) << k;
        q.nms_iou = iou;
        d.setParams(q);
        d.match(std::vector<Mat>(2, scene), 65.f, kept);
        expectSameMatches(expected, kept, k ? "loaded" : "built");
        for (size_t i = 0; i < expected.size() && i < kept.size(); ++i)
            EXPECT_EQ(expected[i].class_id, kept[i].class_id) << k << " match " << i;
    }
}

TEST(Forestmod_Detector, threads_give_identical_results)
{
    const std::vector<Ptr<linemod::Modality> > mods = gradientHue();
    cv::forestmod::Detector det(mods, Tpyr());
    addObjectTemplates(det, 20, "L", 0);
    det.train();
    RNG rng(21);
    std::vector<Mat> scenes;
    for (int k = 0; k < 4; ++k)
    {
        Mat s = clutter(Size(640, 480), rng);
        drawObject(s, 0, Point2f(200.f + 60 * k, 240.f), 5.f * k, 1.0f);
        scenes.push_back(s);
    }
    std::vector<std::vector<linemod::Match> > serial(4), parallel(4);
    for (int k = 0; k < 4; ++k)
        det.match(std::vector<Mat>(2, scenes[k]), 75.f, serial[k]);
    for (int k = 0; k < 4; ++k)
    {
        std::vector<linemod::Match> again;
        det.match(std::vector<Mat>(2, scenes[k]), 75.f, again);
        ASSERT_EQ(serial[k].size(), again.size()) << "serial repeat " << k;
        for (size_t i = 0; i < again.size(); ++i)
            ASSERT_TRUE(serial[k][i] == again[i]) << "serial repeat " << k << " " << i;
    }
    std::vector<std::thread> threads;
    for (int k = 0; k < 4; ++k)
        threads.push_back(std::thread([&, k]() {
            det.match(std::vector<Mat>(2, scenes[k]), 75.f, parallel[k]);
        }));
    for (size_t k = 0; k < threads.size(); ++k)
        threads[k].join();
    for (int k = 0; k < 4; ++k)
    {
        ASSERT_EQ(serial[k].size(), parallel[k].size()) << k;
        for (size_t i = 0; i < serial[k].size(); ++i)
            EXPECT_TRUE(serial[k][i] == parallel[k][i])
                << k << " " << i << ": " << serial[k][i].x << "," << serial[k][i].y << " "
                << serial[k][i].similarity << " t" << serial[k][i].template_id << " vs "
                << parallel[k][i].x << "," << parallel[k][i].y << " " << parallel[k][i].similarity
                << " t" << parallel[k][i].template_id;
    }
}

TEST(Forestmod_Detector, bad_input_raises)
{
    std::vector<Ptr<linemod::Modality> > mods;
    mods.push_back(gradient());
    mods.push_back(linemod::Modality::create("DepthNormal"));
    cv::forestmod::Detector det(mods, Tpyr());
    Mat colour(480, 640, CV_8UC3, Scalar::all(0)), depth(480, 640, CV_16UC1, Scalar(800));
    std::vector<linemod::Match> m;
    // untrained / empty detector
    EXPECT_THROW(det.match(std::vector<Mat>{ colour, depth }, 80.f, m), cv::Exception);
    cv::forestmod::Detector none;
    EXPECT_THROW(none.match(std::vector<Mat>(1, colour), 80.f, m), cv::Exception);
    EXPECT_THROW(none.train(), cv::Exception);
    // sources: count, empty, types, sizes
    EXPECT_THROW(det.match(std::vector<Mat>(1, colour), 80.f, m), cv::Exception);
    EXPECT_THROW(det.match(std::vector<Mat>{ colour, Mat() }, 80.f, m), cv::Exception);
    EXPECT_THROW(det.match(std::vector<Mat>{ colour, Mat(480, 640, CV_32FC1) }, 80.f, m),
                 cv::Exception);
    EXPECT_THROW(det.match(std::vector<Mat>{ colour, Mat(240, 320, CV_16UC1) }, 80.f, m),
                 cv::Exception);
    Mat mask = Mat::zeros(480, 640, CV_8U);
    EXPECT_THROW(det.addTemplate(std::vector<Mat>{ colour, depth }, "x", mask), cv::Exception);
    EXPECT_THROW(det.addTemplate(std::vector<Mat>{ colour, depth }, "x", Mat()), cv::Exception);
    EXPECT_THROW(det.addTemplate(std::vector<Mat>{ depth, depth }, "x", mask + 255),
                 cv::Exception);
    EXPECT_THROW(cv::forestmod::Detector(std::vector<Ptr<linemod::Modality> >(), Tpyr()),
                 cv::Exception);
    try
    {
        det.match(std::vector<Mat>{ colour, Mat(480, 640, CV_32FC1) }, 80.f, m);
    }
    catch (const cv::Exception& e)
    {
        EXPECT_NE(std::string::npos, e.err.find("CV_16UC1")) << e.err;
    }
}

// Two classes of one object in one search group: "A", many views near the scene's, and "B", a
// few views 20-26 degrees off. Sharing each position's lists, A's templates fill them where the
// object lies and B loses its matches there; with search_per_class (one scan, each class's own
// survivors and lists) a class's matches are those of match() asked for it alone, on the
// exhaustive and on the forest path.
TEST(Forestmod_Detector, search_per_class_gives_each_class_its_own_matches)
{
    const std::vector<Ptr<linemod::Modality> > mods = gradientHue();
    DetectorParams p;
    p.nms_iou = 0.f;
    cv::forestmod::Detector det(mods, Tpyr(), p);
    const Size size(640, 480);
    for (int i = 0; i < 20; ++i)
    {
        const bool a = i < 16;
        Mat img = Mat::zeros(size, CV_8UC3), mask;
        drawObject(img, &mask, Point2f(320, 240), a ? 2.f + i : 30.f + 2 * (i - 16), 1.f);
        ASSERT_GE(det.addTemplate(std::vector<Mat>(2, img), a ? "A" : "B", mask), 0) << i;
    }
    RNG rng(3);
    Mat scene = clutter(size, rng);
    const Point2f at(300, 240);
    drawObject(scene, 0, at, 10.f, 1.f);
    const std::vector<Mat> sources(2, scene);
    const float thr = 60.f;
    // matches of `cls` whose box centre lies within 12 px of the object's centre
    const auto near = [&](const std::vector<linemod::Match>& ms, const String& cls) {
        std::vector<linemod::Match> out;
        for (size_t i = 0; i < ms.size(); ++i)
        {
            const linemod::Template& t = det.getTemplates(ms[i].class_id, ms[i].template_id)[0];
            const Point2f c(ms[i].x + t.width / 2.f, ms[i].y + t.height / 2.f);
            if (ms[i].class_id == cls && cv::norm(c - at) <= 12.0)
                out.push_back(ms[i]);
        }
        return out;
    };
    const auto ofClass = [](const std::vector<linemod::Match>& ms, const String& cls) {
        std::vector<linemod::Match> out;
        for (size_t i = 0; i < ms.size(); ++i)
            if (ms[i].class_id == cls)
                out.push_back(ms[i]);
        return out;
    };
    for (int path = 0; path < 2; ++path) // the default (exhaustive: a small group), the forest
    {
        DetectorParams q = p;
        q.exhaustive_ratio = path == 0 ? p.exhaustive_ratio : -1.f;
        q.min_forest_templates = path == 0 ? p.min_forest_templates : 0;
        det.setParams(q);
        std::vector<linemod::Match> shared, alone_a, alone_b, own;
        DetectionStats st_shared, st_own;
        det.match(sources, thr, shared, std::vector<String>(), noArray(), std::vector<Mat>(),
                  &st_shared);
        det.match(sources, thr, alone_a, std::vector<String>(1, "A"));
        det.match(sources, thr, alone_b, std::vector<String>(1, "B"));
        ASSERT_FALSE(near(alone_a, "A").empty()) << path;
        ASSERT_FALSE(alone_b.empty()) << path;
        if (path == 0) // shared lists: A's templates fill B's places at the object
        {
            ASSERT_FALSE(near(alone_b, "B").empty());
            EXPECT_LT(near(shared, "B").size(), near(alone_b, "B").size());
        }
        q.search_per_class = true;
        det.setParams(q);
        det.match(sources, thr, own, std::vector<String>(), noArray(), std::vector<Mat>(),
                  &st_own);
        expectSameMatches(ofClass(own, "A"), alone_a, cv::format("A, path %d", path));
        expectSameMatches(ofClass(own, "B"), alone_b, cv::format("B, path %d", path));
        for (size_t i = 1; i < own.size(); ++i)
            ASSERT_GE(own[i - 1].similarity, own[i].similarity) << i; // best first
        // one scan for both classes: the scan's counters are the shared lists' ones
        EXPECT_EQ(st_shared.locations, st_own.locations) << path;
        EXPECT_EQ(st_shared.validated, st_own.validated) << path;
        EXPECT_EQ(st_shared.candidates, st_own.candidates) << path;
        // asked for one class, search_per_class changes nothing
        std::vector<linemod::Match> one;
        det.match(sources, thr, one, std::vector<String>(1, "B"));
        expectSameMatches(one, alone_b, cv::format("B alone, path %d", path));
    }
    // the parameter is saved and read back
    DetectorParams q = p;
    q.search_per_class = true;
    EXPECT_TRUE(writtenAndRead(q).search_per_class);
    EXPECT_FALSE(DetectorParams().search_per_class);
}

TEST(Forestmod_Detector, model_file_roundtrip_and_corrupt_files)
{
    const std::vector<Ptr<linemod::Modality> > mods = gradientHue();
    cv::forestmod::Detector det(mods, Tpyr());
    std::vector<float> angles;
    const Size size(640, 480);
    for (int i = 0; i < 10; ++i)
    {
        Mat img = Mat::zeros(size, CV_8UC3), mask;
        drawObject(img, &mask, Point2f(320, 240), -30.f + 6.f * i, 1.f);
        // a rotation of its own per template, about the optical axis (i x 10 degrees)
        const double a = i * 10.0 * CV_PI / 180;
        const Matx33d R(std::cos(a), -std::sin(a), 0, std::sin(a), std::cos(a), 0, 0, 0, 1);
        ASSERT_GE(det.addTemplate(std::vector<Mat>(2, img), "L", mask, R, Vec3d(1, 2, 500 + i),
                                  Matx33d(500, 0, 320, 0, 500, 240, 0, 0, 1)),
                  0);
    }
    det.train();
    const std::string file = cv::tempfile(".yml.gz");
    det.save(file);
    EXPECT_THROW(det.save(file), cv::Exception); // no silent overwrite
    {
        std::ifstream f(file.c_str(), std::ios::binary); // gzip's magic bytes
        EXPECT_EQ(0x1f, f.get());
        EXPECT_EQ(0x8b, f.get());
    }
    // the other formats: plain YAML and JSON text, read back alike
    const char* const others[] = { ".yml", ".json" };
    for (int k = 0; k < 2; ++k)
    {
        const std::string other = cv::tempfile(others[k]);
        det.save(other);
        std::ifstream f(other.c_str());
        EXPECT_EQ(k == 0 ? '%' : '{', f.get()) << others[k];
        cv::forestmod::Detector again;
        again.load(other);
        EXPECT_EQ(det.numTemplates(), again.numTemplates()) << others[k];
        EXPECT_TRUE(again.isTrained()) << others[k];
        std::remove(other.c_str());
    }
    // a model longer than load() reads is refused, and nothing is written
    const std::string too_long = cv::tempfile(".yml.gz");
    EXPECT_THROW(cv::forestmod::detail::writeModelText(too_long, std::string(100, 'x'), 99),
                 cv::Exception);
    EXPECT_FALSE(utils::fs::exists(too_long));
    cv::forestmod::detail::writeModelText(too_long, std::string(100, 'x'), 100);
    EXPECT_TRUE(utils::fs::exists(too_long));
    std::remove(too_long.c_str());
    cv::forestmod::Detector back;
    back.load(file);
    EXPECT_EQ(det.numTemplates(), back.numTemplates());
    EXPECT_TRUE(back.isTrained());
    const TemplatePose p = back.getTemplatePose("L", 7);
    EXPECT_TRUE(p.valid);
    EXPECT_EQ(507, p.t[2]);
    EXPECT_EQ(std::cos(70.0 * CV_PI / 180), p.R(0, 0)); // template 7's rotation, to the bit
    EXPECT_EQ(std::sin(70.0 * CV_PI / 180), p.R(1, 0));
    RNG rng(4);
    Mat scene = clutter(size, rng);
    drawObject(scene, 0, Point2f(300, 250), 0.f, 1.f);
    std::vector<linemod::Match> a, b;
    det.match(std::vector<Mat>(2, scene), 80.f, a);
    back.match(std::vector<Mat>(2, scene), 80.f, b);
    ASSERT_EQ(a.size(), b.size());
    for (size_t i = 0; i < a.size(); ++i)
        EXPECT_TRUE(a[i] == b[i]);
    std::remove(file.c_str());

    // corrupt / foreign files
    const std::string bad = cv::tempfile(".yml");
    {
        std::ofstream f(bad.c_str());
        f << "%YAML:1.0\nforestmod_model_version: 999\n";
    }
    EXPECT_THROW(back.load(bad), cv::Exception);
    {
        std::ofstream f(bad.c_str());
        f << "%YAML:1.0\nsomething: [1, 2\n";
    }
    EXPECT_THROW(back.load(bad), cv::Exception);
    {
        std::ofstream f(bad.c_str());
        f << "%YAML:1.0\nnot_a_model: 1\n";
    }
    EXPECT_THROW(back.load(bad), cv::Exception);
    std::remove(bad.c_str());
    EXPECT_THROW(back.load("/nonexistent/forestmod_model.yml"), cv::Exception);
}

}} // namespace

namespace opencv_test { namespace {

// Two classes of very different size: two search groups, each with its forest, saved and loaded;
// a model file of the layout before groups (one forest, no group parameters) still loads.
TEST(Forestmod_Detector, search_groups_model_roundtrip)
{
    const std::vector<Ptr<linemod::Modality> > mods = gradientHue();
    cv::forestmod::Detector det(mods, Tpyr());
    const Size size(640, 480);
    for (int i = 0; i < 6; ++i)
    {
        Mat img = Mat::zeros(size, CV_8UC3), mask;
        drawObject(img, &mask, Point2f(320, 240), -20.f + 8.f * i, 0.6f);
        ASSERT_GE(det.addTemplate(std::vector<Mat>(2, img), "small", mask), 0);
        img = Mat::zeros(size, CV_8UC3);
        drawObject(img, &mask, Point2f(320, 240), -20.f + 8.f * i, 1.6f);
        ASSERT_GE(det.addTemplate(std::vector<Mat>(2, img), "large", mask), 0);
    }
    EXPECT_EQ(0, det.numSearchGroups());
    det.train();
    ASSERT_EQ(2, det.numSearchGroups());
    EXPECT_EQ(std::vector<String>(1, "small"), det.getSearchGroupClasses(0));
    EXPECT_EQ(std::vector<String>(1, "large"), det.getSearchGroupClasses(1));
    EXPECT_EQ(6, det.getForest(0)->numTemplates());
    EXPECT_EQ(6, det.getForest(1)->numTemplates());
    EXPECT_THROW(det.getForest(2), cv::Exception);
    EXPECT_THROW(det.getSearchGroupClasses(-1), cv::Exception);

    RNG rng(9);
    Mat scene = clutter(size, rng);
    drawObject(scene, 0, Point2f(200, 200), 0.f, 0.6f);
    drawObject(scene, 0, Point2f(430, 280), 4.f, 1.6f);
    std::vector<linemod::Match> a, b;
    det.match(std::vector<Mat>(2, scene), 80.f, a);
    std::set<String> found;
    for (size_t i = 0; i < a.size(); ++i)
        found.insert(a[i].class_id);
    EXPECT_EQ(2u, found.size()) << "both objects, each through its own group's forest";

    const std::string file = cv::tempfile(".yml");
    det.save(file);
    cv::forestmod::Detector back;
    back.load(file);
    EXPECT_TRUE(back.isTrained());
    ASSERT_EQ(2, back.numSearchGroups());
    back.match(std::vector<Mat>(2, scene), 80.f, b);
    ASSERT_EQ(a.size(), b.size());
    for (size_t i = 0; i < a.size(); ++i)
        EXPECT_TRUE(a[i] == b[i]);

    // the file's forests no longer fit the groups its parameters make: refused
    std::string text;
    {
        std::ifstream f(file.c_str());
        std::stringstream ss;
        ss << f.rdbuf();
        text = ss.str();
    }
    const size_t key = text.find("group_size_ratio:");
    ASSERT_NE(std::string::npos, key);
    const size_t eol = text.find('\n', key);
    {
        std::string one = text;
        one.replace(key, eol - key, "group_size_ratio: 0.");
        std::ofstream f(file.c_str());
        f << one;
    }
    EXPECT_THROW(back.load(file), cv::Exception);

    // written before groups existed: no group parameters, one forest for all classes
    DetectorParams p;
    p.group_size_ratio = 0.f;
    det.setParams(p);
    det.train();
    ASSERT_EQ(1, det.numSearchGroups());
    std::remove(file.c_str());
    det.save(file);
    {
        std::ifstream f(file.c_str());
        std::stringstream ss;
        ss << f.rdbuf();
        text = ss.str();
    }
    const char* keys[] = { "group_size_ratio:", "auto_depth_leaf_samples:", "group_templates:" };
    for (int k = 0; k < 3; ++k)
    {
        const size_t at = text.find(keys[k]);
        ASSERT_NE(std::string::npos, at) << keys[k];
        const size_t line0 = text.rfind('\n', at);
        text.erase(line0, text.find('\n', at) - line0);
    }
    {
        std::ofstream f(file.c_str());
        f << text;
    }
    cv::forestmod::Detector old;
    old.load(file);
    EXPECT_TRUE(old.isTrained());
    EXPECT_EQ(1, old.numSearchGroups());
    EXPECT_EQ(0.f, old.getParams().group_size_ratio);
    EXPECT_FALSE(old.getParams().group_templates);

    // written with an experiment switch this version no longer has (doc/experiments.md): the
    // templates load, the forests of the other layout are trained again at the first match
    const size_t at = text.find("group_templates:");
    ASSERT_EQ(std::string::npos, at);
    const size_t params_at = text.find("forestmod_params:");
    ASSERT_NE(std::string::npos, params_at);
    const size_t line_end = text.find('\n', params_at);
    const size_t indent = text.find_first_not_of(' ', line_end + 1) - (line_end + 1);
    text.insert(line_end + 1, std::string(indent, ' ') + "grey_hue_label: 1\n");
    {
        std::ofstream f(file.c_str());
        f << text;
    }
    cv::forestmod::Detector grey;
    grey.load(file);
    EXPECT_FALSE(grey.isTrained());
    EXPECT_EQ(det.numTemplates(), grey.numTemplates());
    std::vector<linemod::Match> mg;
    const Mat frame = Mat(size, CV_8UC3, Scalar::all(40));
    grey.match(std::vector<Mat>(2, frame), 80.f, mg);
    EXPECT_TRUE(grey.isTrained());

    // written before depth_range_tolerance, with the absolute depth_range_margin (0: off, its
    // default): the test stays off as it was; a margin that was on loads as the default
    const size_t tol_at = text.find("depth_range_tolerance:");
    ASSERT_NE(std::string::npos, tol_at);
    const size_t tol_end = text.find('\n', tol_at);
    const int margins[] = { 0, 100 };
    for (int k = 0; k < 2; ++k)
    {
        std::string t = text;
        t.replace(tol_at, tol_end - tol_at, cv::format("depth_range_margin: %d", margins[k]));
        {
            std::ofstream f(file.c_str());
            f << t;
        }
        cv::forestmod::Detector before;
        before.load(file);
        EXPECT_EQ(margins[k] ? DetectorParams().depth_range_tolerance : -1.f,
                  before.getParams().depth_range_tolerance) << margins[k];
    }
    std::remove(file.c_str());
}

// group_templates: one class seen at two sizes (two distances) gets a window and a forest per
// size; with class groups one window covers both and the small views fill a corner of it
TEST(Forestmod_Detector, search_groups_of_templates_split_one_class_by_size)
{
    const std::vector<Ptr<linemod::Modality> > mods = gradientHue();
    const Size size(640, 480);
    RNG rng(9);
    Mat scene = clutter(size, rng);
    drawObject(scene, 0, Point2f(200, 200), 0.f, 0.6f);
    drawObject(scene, 0, Point2f(430, 280), 4.f, 1.6f);
    for (int by_template = 0; by_template < 2; ++by_template)
    {
        DetectorParams p;
        p.group_templates = by_template != 0;
        cv::forestmod::Detector det(mods, Tpyr(), p);
        for (int i = 0; i < 6; ++i)
            for (int k = 0; k < 2; ++k)
            {
                Mat img = Mat::zeros(size, CV_8UC3), mask;
                drawObject(img, &mask, Point2f(320, 240), -20.f + 8.f * i, k ? 1.6f : 0.6f);
                ASSERT_GE(det.addTemplate(std::vector<Mat>(2, img), "obj", mask), 0);
            }
        det.train();
        ASSERT_EQ(by_template ? 2 : 1, det.numSearchGroups()) << by_template;
        for (int g = 0; g < det.numSearchGroups(); ++g)
        {
            EXPECT_EQ(std::vector<String>(1, "obj"), det.getSearchGroupClasses(g));
            EXPECT_EQ(by_template ? 6 : 12, det.getForest(g)->numTemplates()) << g;
        }
        std::vector<linemod::Match> matches;
        det.match(std::vector<Mat>(2, scene), 80.f, matches);
        bool small = false, large = false;
        for (size_t i = 0; i < matches.size(); ++i)
        {
            // templates were added small (even ids) and large (odd ids) in turn
            const linemod::Template& t0 = det.getTemplates("obj", matches[i].template_id)[0];
            const Point2f c(matches[i].x + t0.width / 2.f, matches[i].y + t0.height / 2.f);
            if (matches[i].template_id % 2 == 0)
                small = small || cv::norm(c - Point2f(200, 200)) < 30;
            else
                large = large || cv::norm(c - Point2f(430, 280)) < 40;
        }
        EXPECT_TRUE(small && large) << "both sizes found, by_template " << by_template;
    }
}

// The scan's row of windows (detail::gatherRowWindows): window c holds ptr[j][row + c * S] for
// every dimension j, whatever the step (the transposed path at S = 4), the number of locations
// (blocks of 16 and the rest) and of dimensions (multiples of 16 and the rest).
TEST(Forestmod_Scan, row_windows_equal_one_load_per_value)
{
    RNG rng(23);
    const int steps[] = { 1, 2, 4, 8 };
    const int widths[] = { 1, 16, 17, 33, 80 };
    const int dims[] = { 16, 288, 437 };
    for (int S : steps)
        for (int W : widths)
            for (int D : dims)
            {
                Mat planes(24, (W + 20) * S + 64, CV_8UC1);
                rng.fill(planes, RNG::UNIFORM, 0, 256);
                std::vector<const uchar*> ptr(D);
                for (int j = 0; j < D; ++j)
                    ptr[j] = planes.ptr<uchar>(rng.uniform(0, planes.rows))
                        + rng.uniform(0, 16 * S);
                const ptrdiff_t row = 3;
                std::vector<uchar> win((size_t)W * D, 0);
                cv::forestmod::detail::gatherRowWindows(ptr, row, W, S, win.data());
                for (int c = 0; c < W; ++c)
                    for (int j = 0; j < D; ++j)
                        ASSERT_EQ(win[(size_t)c * D + j], ptr[j][row + c * S])
                            << "S " << S << " W " << W << " D " << D << " c " << c << " j " << j;
            }
}

}} // namespace

