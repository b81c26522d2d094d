// This file is part of OpenCV project.
// It is subject to the license terms in the LICENSE file found in the top-level directory
// of this distribution and at http://opencv.org/license.html

#include "perf_precomp.hpp"
#include "../test/forest_synth.hpp"

namespace opencv_test { namespace {

using namespace forest_synth;

const int kGrid = 8;   // D = 2 x 64

/** 1000 query rows: half templates with 10 % of their values corrupted, half uniform background
(what a detector sees: mostly background, some object locations). */
static Mat makeQueries(const Mat& trained, int count, uint64 seed)
{
    RNG rng(seed);
    Mat q(count, trained.cols, CV_8U);
    for (int i = 0; i < count; ++i)
    {
        if (i % 2)
            perturb(trained.ptr<uchar>(rng.uniform(0, trained.rows)), trained.cols, 0.1, rng,
                    q.ptr<uchar>(i));
        else
            for (int j = 0; j < trained.cols; ++j)
                q.at<uchar>(i, j) = randomValue(rng);
    }
    return q;
}

typedef TestBaseWithParam<int> Forestmod_ForestTraversal;

// Cost of one location (all trees, rejectors, candidate de-duplication) vs number of templates;
// one cycle = 1000 locations.
PERF_TEST_P(Forestmod_ForestTraversal, per_location, Values(100, 1000, 10000))
{
    const int n = GetParam();
    Mat desc, fg, trained;
    makeTemplates(n, 4, kGrid, 7, desc, fg);
    ForestParams p;
    Ptr<TemplateForest> forest = TemplateForest::create(p);
    forest->train(desc, fg);
    TemplateForest::applyBackgroundModel(desc, fg, p.seed, trained);
    Mat queries = makeQueries(trained, 1000, 3);

    // the Detector's view: planes + offsets, no copy
    std::vector<int> delta(desc.cols), plane_of(desc.cols, 0);
    for (int j = 0; j < desc.cols; ++j)
        delta[j] = j;
    const uchar* planes[1] = {queries.ptr<uchar>(0)};
    LocationView view;
    view.planes = planes;
    view.plane_of = &plane_of[0];
    view.delta = &delta[0];
    std::vector<int> cand;
    cand.reserve(n);
    ForestQueryStats stats;
    TEST_CYCLE()
    {
        for (int i = 0; i < queries.rows; ++i)
        {
            view.offset = (ptrdiff_t)i * (ptrdiff_t)queries.step;
            forest->query(view, cand, 0, &stats);
        }
    }
    ASSERT_GT(stats.locations, 0);
    ASSERT_GT(stats.rejected, 0);
    std::cout << n << " templates: " << (double)stats.nodes_visited / stats.locations
              << " nodes visited, " << 100 * stats.rejectionRate() << " % rejected, "
              << (double)stats.candidates / std::max<int64>(1, stats.locations - stats.rejected)
              << " candidates per accepted location" << std::endl;
    SANITY_CHECK_NOTHING();
}

typedef TestBaseWithParam<int> Forestmod_ForestTraining;

PERF_TEST_P(Forestmod_ForestTraining, train, Values(1000, 10000))
{
    const int n = GetParam();
    Mat desc, fg;
    makeTemplates(n, 4, kGrid, 7, desc, fg);
    Ptr<TemplateForest> forest = TemplateForest::create();
    TEST_CYCLE_N(1)
    {
        forest->train(desc, fg);
    }
    ASSERT_FALSE(forest->empty());
    SANITY_CHECK_NOTHING();
}

}} // namespace
