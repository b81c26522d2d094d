// This file is part of OpenCV project.
// It is subject to the license terms in the LICENSE file found in the top-level directory
// of this distribution and at http://opencv.org/license.html

// Validation alone, on the coarsest level of a VGA frame (320 x 240, T = 8, one modality), with
// the number of candidate templates and their features as parameters:
//  - scattered: the forest path's scoring of one pair at a time (src/validator.cpp: linearized
//    memories on the location grid, one read per feature) of every template at every location
//    of the location grid (step T / 2 = 4: 80 x 60 locations), the cost per (location,
//    candidate, feature);
//  - exhaustive: the bounded worst case's scoring (LINEMOD's linearized memories, SIMD) of every
//    template at every position of the T grid (40 x 30), the cost per (position, template,
//    feature);
//  - linemod: cv::linemod::Detector::match on the same templates (one pyramid level, T = 8, the
//    same 320 x 240 gradient image; it also quantizes, spreads and linearizes the frame; skipped
//    beyond 63 features, which its similarity asserts).
// Forestmod_Validation.forest_path runs the detector's forest path itself (validateLocations:
// the pairs of a block of locations scored template by template, a template's pairs at
// neighbouring locations in one vector addition per feature, breadth-first, the median rule per
// location) with `c` random candidates of 256 templates at every location of the grid: the
// cost per (location, candidate), and per (location, candidate, feature of the template) to
// set beside the scoring-only cases.
// The costs per triple are printed; compare them in one run (the machine may be shared).

#include "perf_precomp.hpp"
#include "../src/validator.hpp"
#include "../src/exhaustive_search.hpp"
#include "../src/quantize_fast.hpp"
#include "../src/scene_pyramid.hpp"
#include "../src/search_index.hpp"

namespace opencv_test { namespace {

using namespace cv::forestmod::detail;

enum { PATH_SCATTERED = 0, PATH_EXHAUSTIVE = 1, PATH_LINEMOD = 2 };
CV_ENUM(ValidationPath, PATH_SCATTERED, PATH_EXHAUSTIVE, PATH_LINEMOD)

typedef tuple<ValidationPath, int, int> ValidationParams;
typedef TestBaseWithParam<ValidationParams> Forestmod_Validation;

static const int kT = 8;

// A textured 320 x 240 image with gradients of every orientation.
static Mat textured(RNG& rng)
{
    Mat coarse(16, 21, CV_8UC3), img;
    rng.fill(coarse, RNG::UNIFORM, Scalar::all(0), Scalar::all(255));
    resize(coarse, img, Size(320, 240), 0, 0, INTER_CUBIC);
    for (int i = 0; i < 40; ++i)
        circle(img, Point(rng.uniform(0, 320), rng.uniform(0, 240)), rng.uniform(4, 30),
               Scalar(rng.uniform(0, 255), rng.uniform(0, 255), rng.uniform(0, 255)), 2);
    return img;
}

// The frame's coarsest level as the detector computes it (one modality).
static LevelMaps coarseLevel(const Mat& img, const Ptr<linemod::Modality>& gradient)
{
    LevelMaps level;
    level.T = kT;
    level.pad = 0;
    level.quantized.resize(1);
    level.spread.resize(1);
    gradient->process(img)->quantize(level.quantized[0]);
    level.size = level.quantized[0].size();
    spreadLabelsFast(level.quantized[0], level.spread[0], kT, 0);
    return level;
}

// n single-modality, single-level templates of f features in a 48 x 48 box.
static std::vector<TemplatePyramid> makeTemplates(int n, int f, RNG& rng)
{
    std::vector<TemplatePyramid> tps(n, TemplatePyramid(1));
    for (int i = 0; i < n; ++i)
    {
        linemod::Template& t = tps[i][0];
        t.width = 48;
        t.height = 48;
        t.pyramid_level = 0;
        for (int k = 0; k < f; ++k)
            t.features.push_back(linemod::Feature(rng.uniform(0, 48), rng.uniform(0, 48),
                                                  rng.uniform(0, 8)));
    }
    return tps;
}

PERF_TEST_P(Forestmod_Validation, per_candidate,
            Combine(ValidationPath::all(), Values(16, 256), Values(32, 63, 126)))
{
    const int path = get<0>(GetParam()), n = get<1>(GetParam()), f = get<2>(GetParam());
    RNG rng(15);
    const Mat img = textured(rng);
    const std::vector<TemplatePyramid> tps = makeTemplates(n, f, rng);
    Ptr<linemod::Modality> gradient = linemod::Modality::create("ColorGradient");

    const LevelMaps level = coarseLevel(img, gradient);

    int64 triples = 0;
    if (path == PATH_SCATTERED)
    {
        const int S = kT / 2;
        std::vector<Point> tls;
        for (int r = 0; r < level.size.height / S; ++r)
            for (int c = 0; c < level.size.width / S; ++c)
                tls.push_back(Point(c * S - 24 - S / 2, r * S - 24 - S / 2));
        LinearMemories grid;
        grid.buildGrid(level, S, (48 + kT) / S);
        std::vector<int> raw;
        int64 sum = 0;
        TEST_CYCLE()
        {
            for (int i = 0; i < n; ++i)
            {
                scoreAt(grid, tps[i], 0, 1, tls, raw);
                sum += raw[raw.size() / 2];
            }
        }
        ASSERT_GT(sum, 0);
        triples = (int64)tls.size() * n * f;
    }
    else if (path == PATH_EXHAUSTIVE)
    {
        LinearMemories lm;
        std::vector<ushort> scores;
        int64 sum = 0, positions = 0;
        TEST_CYCLE()
        {
            lm.build(level); // per frame, as the detector does
            for (int i = 0; i < n; ++i)
            {
                int span_x = 0, span_y = 0;
                ASSERT_TRUE(scoreEverywhere(lm, tps[i], 0, 1, span_x, span_y, scores));
                sum += scores[scores.size() / 2];
                positions = (int64)(span_x + 1) * (span_y + 1);
            }
        }
        ASSERT_GT(sum, 0);
        triples = positions * n * f;
    }
    else
    {
        if (f > 63)
            throw SkipTestException("cv::linemod scores at most 63 features per template and "
                                    "modality (its 8-bit similarity asserts it)");
        std::vector<Ptr<linemod::Modality> > mods(1, gradient);
        linemod::Detector det(mods, std::vector<int>(1, kT));
        for (int i = 0; i < n; ++i)
            ASSERT_EQ(i, det.addSyntheticTemplate(tps[i], "obj"));
        std::vector<linemod::Match> matches;
        const std::vector<Mat> sources(1, img);
        TEST_CYCLE() det.match(sources, 99.f, matches);
        triples = (int64)(level.size.width / kT - 48 / kT + 1)
            * (level.size.height / kT - 48 / kT + 1) * n * f;
    }
    const double ns = calcMetrics().median * 1e9 / cv::getTickFrequency();
    std::cout << "[ INFO    ] " << (path == PATH_SCATTERED ? "scattered" : path == PATH_EXHAUSTIVE
                                    ? "exhaustive" : "cv::linemod")
              << ": " << n << " templates x " << f << " features: "
              << ns / (double)triples << " ns per (location, candidate, feature)" << std::endl;
    SANITY_CHECK_NOTHING();
}

typedef tuple<int, int> ForestPathParams;
typedef TestBaseWithParam<ForestPathParams> Forestmod_ValidationForestPath;

PERF_TEST_P(Forestmod_ValidationForestPath, per_pair,
            Combine(Values(16, 64, 256), Values(32, 63, 126)))
{
    const int c = get<0>(GetParam()), f = get<1>(GetParam()), n = 256;
    RNG rng(15);
    const Mat img = textured(rng);
    ClassPyramids pyramids;
    pyramids["obj"] = makeTemplates(n, f, rng);
    ScenePyramid scene;
    scene.levels.push_back(coarseLevel(img, linemod::Modality::create("ColorGradient")));
    SearchIndex index;
    for (int i = 0; i < n; ++i)
    {
        TemplateRef ref;
        ref.class_id = "obj";
        ref.template_id = i;
        index.rows.push_back(ref);
    }
    // every location of the grid (step T / 2) with c random candidates, ascending
    LocationCandidates cands;
    cands.step = kT / 2;
    cands.begin.push_back(0);
    std::vector<int> all(n);
    for (int i = 0; i < n; ++i)
        all[i] = i;
    for (int r = 0; r < scene.coarsest().size.height / cands.step; ++r)
        for (int x = 0; x < scene.coarsest().size.width / cands.step; ++x)
        {
            cands.location.push_back(Point(x, r));
            for (int k = 0; k < c; ++k)  // a partial Fisher-Yates shuffle
                std::swap(all[k], all[rng.uniform(k, n)]);
            std::vector<int> pick(all.begin(), all.begin() + c);
            std::sort(pick.begin(), pick.end());
            cands.rows.insert(cands.rows.end(), pick.begin(), pick.end());
            cands.begin.push_back(static_cast<int>(cands.rows.size()));
        }
    forestmod::DetectorParams params;
    params.max_survivors = 1; // the paper's, as doc/detector.md measures it
    const std::vector<uchar> row_allowed(n, 1);
    std::vector<linemod::Match> coarse;
    TEST_CYCLE() validateLocations(scene, cands, index, pyramids, params, 10.f, row_allowed,
                                   coarse);
    ASSERT_FALSE(coarse.empty());
    ASSERT_LE(coarse.size(), cands.location.size());  // max_survivors 1 per location
    const double ns = calcMetrics().median * 1e9 / cv::getTickFrequency();
    const double pairs = static_cast<double>(cands.rows.size());
    std::cout << "[ INFO    ] forest path: " << c << " candidates x " << f << " features: "
              << ns / pairs << " ns per (location, candidate), " << ns / (pairs * f)
              << " ns per (location, candidate, feature)" << std::endl;
    SANITY_CHECK_NOTHING();
}

}} // namespace
