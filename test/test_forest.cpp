// This file is part of OpenCV project.
// It is subject to the license terms in the LICENSE file found in the top-level directory
// of this distribution and at http://opencv.org/license.html

#include "test_precomp.hpp"
#include "forest_synth.hpp"

#include "opencv2/rgbd/linemod.hpp"

#include <fstream>

namespace opencv_test {
namespace {

using namespace forest_synth;

const int kGrid = 8;   // 8 x 8 grid points x 2 modalities = 128 dims

struct Data
{
    Mat desc, fg, noisy;   // noisy: as trained (off-mask values replaced by noise)
};

static Data makeData(int n, int objects, uint64 seed, const ForestParams& p)
{
    Data d;
    makeTemplates(n, objects, kGrid, seed, d.desc, d.fg);
    TemplateForest::applyBackgroundModel(d.desc, d.fg, p.seed, d.noisy);
    return d;
}

/** Queries of templates with 10 % of their dims replaced by random values. */
struct NoisyOutcome
{
    double recall;    // share of queries whose candidates hold the template
    double rejected;  // share rejected
    double mean_candidates;
};

static NoisyOutcome noisyQueries(const TemplateForest& forest, const Mat& rows, int queries,
                                 uint64 seed)
{
    RNG rng(seed);
    const int D = rows.cols;
    std::vector<uchar> q(D);
    std::vector<int> cand;
    int hit = 0, rej = 0;
    double ncand = 0;
    for (int i = 0; i < queries; ++i)
    {
        const int t = rng.uniform(0, rows.rows);
        perturb(rows.ptr<uchar>(t), D, 0.1, rng, &q[0]);
        if (!forest.query(&q[0], cand))
        {
            rej++;
            continue;
        }
        ncand += (double)cand.size();
        hit += std::binary_search(cand.begin(), cand.end(), t) ? 1 : 0;
    }
    NoisyOutcome o;
    o.recall = (double)hit / queries;
    o.rejected = (double)rej / queries;
    o.mean_candidates = ncand / std::max(1, queries - rej);
    return o;
}

/** Descriptors of real-image windows: ColorGradient and ColorHue quantized (not spread) frames
of lmo_mini, sampled on the same grid geometry (8 x 8 points, 5 px apart) at random locations. */
static Mat realPatches(int count, uint64 seed)
{
    const char* frames[] = {"lmo_mini/test/000002/rgb/000224.png", "lmo_mini/test/000002/rgb/000902.png",
                            "lmo_mini/test/000002/rgb/001038.png"};
    const int step = 5;
    Mat out(count, 2 * kGrid * kGrid, CV_8U);
    std::vector<Mat> grads, hues;
    Ptr<linemod::Modality> grad = linemod::Modality::create("ColorGradient");
    Ptr<linemod::Modality> hue = ColorHue::create();
    for (int f = 0; f < 3; ++f)
    {
        Mat img = imread(cvtest::findDataFile(frames[f]), IMREAD_COLOR);
        CV_Assert(!img.empty());
        Mat qg, qh;
        grad->process(img)->quantize(qg);
        hue->process(img)->quantize(qh);
        grads.push_back(qg);
        hues.push_back(qh);
    }
    RNG rng(seed);
    const int span = step * kGrid;
    for (int i = 0; i < count; ++i)
    {
        const int f = i % 3;
        const int x0 = rng.uniform(0, grads[f].cols - span), y0 = rng.uniform(0, grads[f].rows - span);
        uchar* d = out.ptr<uchar>(i);
        for (int y = 0; y < kGrid; ++y)
            for (int x = 0; x < kGrid; ++x)
            {
                d[y * kGrid + x] = grads[f].at<uchar>(y0 + y * step, x0 + x * step);
                d[kGrid * kGrid + y * kGrid + x] = hues[f].at<uchar>(y0 + y * step, x0 + x * step);
            }
    }
    return out;
}

static double rejectionRate(const TemplateForest& forest, const Mat& rows, ForestQueryStats* stats = 0)
{
    std::vector<int> cand;
    int rej = 0;
    for (int i = 0; i < rows.rows; ++i)
        rej += forest.query(rows.ptr<uchar>(i), cand, 0, stats) ? 0 : 1;
    return (double)rej / rows.rows;
}

static Mat uniformBackground(int count, int D, uint64 seed)
{
    RNG rng(seed);
    Mat out(count, D, CV_8U);
    for (int i = 0; i < count; ++i)
        for (int j = 0; j < D; ++j)
            out.at<uchar>(i, j) = randomValue(rng);
    return out;
}

static std::string serialize(const TemplateForest& forest)
{
    FileStorage fs("forest.yml", FileStorage::WRITE + FileStorage::MEMORY);
    fs << TemplateForest::storageKey() << "{";
    forest.write(fs);
    fs << "}";
    return fs.releaseAndGetString();
}

// ------------------------------------------------------------------------------------------------

TEST(Forestmod_TemplateForest, self_recall_every_tree)
{
    ForestParams p;
    p.num_trees = 3;
    Data d = makeData(2000, 4, 11, p);
    Ptr<TemplateForest> forest = TemplateForest::create(p);
    forest->train(d.desc, d.fg);
    ASSERT_FALSE(forest->empty());
    ASSERT_EQ(2000, forest->numTemplates());
    ASSERT_EQ(d.desc.cols, forest->dims());

    std::vector<int> delta(d.desc.cols), plane_of(d.desc.cols, 0);
    for (int j = 0; j < d.desc.cols; ++j)
        delta[j] = j;
    std::vector<int> cand;
    int missing = 0;
    for (int i = 0; i < d.noisy.rows; ++i)
    {
        const uchar* planes[1] = {d.noisy.ptr<uchar>(i)};
        LocationView view;
        view.planes = planes;
        view.plane_of = &plane_of[0];
        view.delta = &delta[0];
        view.offset = 0;
        for (int t = 0; t < p.num_trees; ++t)
        {
            int depth = 0;
            const bool ok = forest->queryTree(t, view, cand, &depth);
            if (!ok || std::find(cand.begin(), cand.end(), i) == cand.end())
            {
                if (missing++ < 5)
                    ADD_FAILURE() << "template " << i << " tree " << t
                                  << (ok ? " not in its leaf" : " rejected at depth ")
                                  << (ok ? std::string() : cv::format("%d", depth));
            }
        }
        ASSERT_TRUE(forest->query(view, cand));
        ASSERT_TRUE(std::binary_search(cand.begin(), cand.end(), i));
    }
    EXPECT_EQ(0, missing);
    const TemplateForest::Statistics s = forest->statistics();
    std::cout << "self-recall: 2000 templates x 3 trees, all found; mean leaves per template "
              << s.mean_leaves_per_template << ", nodes " << s.nodes << ", lowered rejectors "
              << s.lowered_rejectors << std::endl;
}

TEST(Forestmod_TemplateForest, fuzzy_split_robust_to_noise)
{
    ForestParams p;
    Data d = makeData(1000, 4, 21, p);
    Ptr<TemplateForest> fuzzy = TemplateForest::create(p);
    fuzzy->train(d.desc, d.fg);
    ForestParams pc = p;
    pc.fuzzy_margin = 0.f;
    Ptr<TemplateForest> crisp = TemplateForest::create(pc);
    crisp->train(d.desc, d.fg);

    const NoisyOutcome f = noisyQueries(*fuzzy, d.noisy, 3000, 5);
    const NoisyOutcome c = noisyQueries(*crisp, d.noisy, 3000, 5);
    std::cout << "10 % noisy queries, 1000 templates: fuzzy (xi=" << p.fuzzy_margin << ") recall "
              << f.recall << " rejected " << f.rejected << " candidates " << f.mean_candidates
              << "; crisp recall " << c.recall << " rejected " << c.rejected << " candidates "
              << c.mean_candidates << std::endl;
    EXPECT_GE(f.recall, 0.95);
    EXPECT_LE(f.rejected, 0.01);
    EXPECT_GT(f.recall, c.recall + 0.05) << "the fuzzy split must do clearly better than xi = 0";
}

TEST(Forestmod_TemplateForest, rejects_background)
{
    ForestParams p;
    Data d = makeData(1000, 4, 31, p);
    Ptr<TemplateForest> forest = TemplateForest::create(p);
    forest->train(d.desc, d.fg);

    ForestQueryStats su, sr;
    const double uni = rejectionRate(*forest, uniformBackground(3000, d.desc.cols, 7), &su);
    const double real = rejectionRate(*forest, realPatches(3000, 8), &sr);
    const NoisyOutcome f = noisyQueries(*forest, d.noisy, 3000, 9);
    std::cout << "rejected: uniform background " << uni << ", real-image patches " << real
              << ", noisy templates " << f.rejected << "; real patches rejected by depth:";
    for (size_t i = 0; i < sr.rejected_at_depth.size(); ++i)
        std::cout << " " << sr.rejected_at_depth[i];
    std::cout << std::endl;
    EXPECT_GE(uni, 0.90);
    EXPECT_GE(real, 0.90);
    EXPECT_LE(f.rejected, 0.01);
    EXPECT_EQ(3000, su.locations);
    EXPECT_EQ(su.rejected, cvRound(uni * 3000));
    ForestQueryStats sum;
    sum.add(su);
    sum.add(sr);
    EXPECT_EQ(6000, sum.locations);
    EXPECT_EQ(su.rejected + sr.rejected, sum.rejected);
    int64 by_depth = 0;
    for (size_t i = 0; i < sum.rejected_at_depth.size(); ++i)
        by_depth += sum.rejected_at_depth[i];
    EXPECT_EQ(sum.rejected, by_depth);
}

TEST(Forestmod_TemplateForest, several_samples_per_template)
{
    // 300 templates, each with 3 samples: its view and two views with the window misaligned
    ForestParams p;
    std::vector<View> views;
    Mat desc, fg;
    makeTemplates(300, 3, kGrid, 45, desc, fg, 0, 0.5, 0.95, &views);
    std::vector<Shape> shapes;
    for (int o = 0; o < 3; ++o)
        shapes.push_back(makeShape(o));
    Mat sd(900, desc.cols, CV_8U), sf(900, desc.cols, CV_8U);
    std::vector<int> ids(900);
    RNG rng(46);
    for (int i = 0; i < 900; ++i)
    {
        const int t = i % 300;
        ids[i] = t;
        const View& v = views[t];
        const double step = 2.0 / kGrid;
        const double tx = i < 300 ? 0 : rng.uniform(-0.3, 0.3) * step;
        const double ty = i < 300 ? 0 : rng.uniform(-0.3, 0.3) * step;
        renderView(shapes[v.object], v.alpha, v.scale, v.squash, kGrid, sd.ptr<uchar>(i),
                   sf.ptr<uchar>(i), 0.5, 0.95, tx, ty);
    }
    Ptr<TemplateForest> f = TemplateForest::create(p);
    f->train(sd, sf, ids);
    EXPECT_EQ(300, f->numTemplates());
    Mat trained;
    TemplateForest::applyBackgroundModel(sd, sf, p.seed, trained);
    std::vector<int> cand;
    for (int i = 0; i < 900; ++i)
    {
        ASSERT_TRUE(f->query(trained.ptr<uchar>(i), cand)) << "sample " << i;
        ASSERT_TRUE(std::binary_search(cand.begin(), cand.end(), ids[i])) << "sample " << i;
        for (size_t k = 0; k < cand.size(); ++k)
            ASSERT_TRUE(cand[k] >= 0 && cand[k] < 300);
        for (size_t k = 1; k < cand.size(); ++k)
            ASSERT_LT(cand[k - 1], cand[k]);   // sorted, de-duplicated template ids
    }
    std::vector<int> counts;
    f->leavesPerTemplate(0, counts);
    EXPECT_EQ(300u, counts.size());
    EXPECT_EQ(0, (int)std::count(counts.begin(), counts.end(), 0));
    // bad ids
    std::vector<int> few(10, 0), negative(ids);
    negative[5] = -1;
    EXPECT_THROW(f->train(sd, sf, few), cv::Exception);
    EXPECT_THROW(f->train(sd, sf, negative), cv::Exception);
}

TEST(Forestmod_TemplateForest, tree_votes)
{
    // all-vote (default) rejects a location only when every tree does; any-vote when one does
    ForestParams p;
    p.num_trees = 3;
    Data d = makeData(600, 3, 35, p);
    Ptr<TemplateForest> all = TemplateForest::create(p);
    all->train(d.desc, d.fg);
    p.reject_any_tree = true;
    Ptr<TemplateForest> any = TemplateForest::create(p);
    any->train(d.desc, d.fg);   // same seed: same trees
    Mat q = uniformBackground(1000, d.desc.cols, 36);
    RNG rng(37);
    Mat noisy(1000, d.desc.cols, CV_8U);
    for (int i = 0; i < 1000; ++i)
        perturb(d.noisy.ptr<uchar>(i % 600), d.desc.cols, 0.2, rng, noisy.ptr<uchar>(i));
    vconcat(q, noisy, q);
    std::vector<int> ca, cb, ct;
    int only_any = 0;
    for (int i = 0; i < q.rows; ++i)
    {
        const bool a = all->query(q.ptr<uchar>(i), ca);
        const bool b = any->query(q.ptr<uchar>(i), cb);
        ASSERT_TRUE(a || !b) << "any-vote accepted what all-vote rejected";
        int trees_ok = 0;
        for (int t = 0; t < 3; ++t)
        {
            const uchar* planes[1] = {q.ptr<uchar>(i)};
            std::vector<int> delta(q.cols), plane_of(q.cols, 0);
            for (int j = 0; j < q.cols; ++j)
                delta[j] = j;
            LocationView v;
            v.planes = planes;
            v.plane_of = &plane_of[0];
            v.delta = &delta[0];
            v.offset = 0;
            trees_ok += all->queryTree(t, v, ct) ? 1 : 0;
        }
        ASSERT_EQ(a, trees_ok > 0);
        ASSERT_EQ(b, trees_ok == 3);
        if (b)
        {
            ASSERT_EQ(ca, cb);
        }
        only_any += a && !b;
    }
    EXPECT_GT(only_any, 0);   // the two policies differ on these data
}

TEST(Forestmod_TemplateForest, structure)
{
    ForestParams p;
    p.num_trees = 2;
    p.max_depth = 6;
    Data d = makeData(3000, 6, 41, p);
    Ptr<TemplateForest> forest = TemplateForest::create(p);
    forest->train(d.desc, d.fg);
    const TemplateForest::Statistics s = forest->statistics();
    EXPECT_EQ(2, s.trees);
    EXPECT_LE(s.max_depth, 6);
    EXPECT_GT(s.leaves, 1);
    EXPECT_EQ(s.nodes, 2 * s.leaves - s.trees);   // binary trees
    EXPECT_GT(s.bytes, 0u);
    for (int t = 0; t < 2; ++t)
    {
        std::vector<int> counts;
        forest->leavesPerTemplate(t, counts);
        ASSERT_EQ(3000u, counts.size());
        EXPECT_EQ(0, (int)std::count(counts.begin(), counts.end(), 0)) << "a template in no leaf";
    }
    // leaves are non-empty and duplication is bounded
    EXPECT_GE(s.mean_leaves_per_template, 1.0);
    EXPECT_LE(s.mean_leaves_per_template, 8.0);
    EXPECT_GE(s.mean_leaf_size, 1.0);
    std::cout << "structure: 3000 templates, depth <= 6: " << s.leaves << " leaves, mean leaf size "
              << s.mean_leaf_size << ", mean leaves per template " << s.mean_leaves_per_template
              << std::endl;

    // a small max_depth is honoured too, and max_depth = 0 gives a single leaf with everything
    ForestParams p0 = p;
    p0.max_depth = 0;
    p0.num_trees = 1;
    Ptr<TemplateForest> stump = TemplateForest::create(p0);
    stump->train(d.desc, d.fg);
    EXPECT_EQ(1, stump->statistics().nodes);
    std::vector<int> cand;
    ASSERT_TRUE(stump->query(d.noisy.ptr<uchar>(0), cand));
    EXPECT_EQ(3000u, cand.size());
}

TEST(Forestmod_TemplateForest, visits_grow_like_log_n)
{
    ForestParams p;
    p.num_trees = 1;
    p.max_depth = 30;   // let the size of the data alone decide the depth
    double visited[3];
    const int sizes[3] = {100, 1000, 10000};
    for (int k = 0; k < 3; ++k)
    {
        Data d = makeData(sizes[k], 4, 51 + k, p);
        Ptr<TemplateForest> forest = TemplateForest::create(p);
        forest->train(d.desc, d.fg);
        ForestQueryStats st;
        std::vector<int> cand;
        for (int i = 0; i < 1000; ++i)
            forest->query(d.noisy.ptr<uchar>(i % d.noisy.rows), cand, 0, &st);
        visited[k] = (double)st.nodes_visited / (double)st.locations;
        std::cout << sizes[k] << " templates: mean nodes visited " << visited[k]
                  << ", mean candidates " << (double)st.candidates / (double)(st.locations - st.rejected)
                  << ", depth " << forest->statistics().max_depth << std::endl;
    }
    EXPECT_LT(visited[2], 3 * visited[0]);
    EXPECT_GT(visited[2], visited[0]);
}

TEST(Forestmod_TemplateForest, deterministic_by_seed_and_threads)
{
    ForestParams p;
    p.num_trees = 2;
    Data d = makeData(1500, 4, 61, p);
    Ptr<TemplateForest> a = TemplateForest::create(p);
    a->train(d.desc, d.fg);
    const int threads = getNumThreads();
    setNumThreads(1);
    Ptr<TemplateForest> b = TemplateForest::create(p);
    b->train(d.desc, d.fg);
    setNumThreads(threads);
    EXPECT_EQ(serialize(*a), serialize(*b));

    ForestParams q = p;
    q.seed = 1;
    Ptr<TemplateForest> c = TemplateForest::create(q);
    c->train(d.desc, d.fg);
    EXPECT_NE(serialize(*a), serialize(*c));
}

TEST(Forestmod_TemplateForest, write_read_same_traversal)
{
    ForestParams p;
    p.num_trees = 2;
    Data d = makeData(1000, 4, 71, p);
    Ptr<TemplateForest> a = TemplateForest::create(p);
    a->train(d.desc, d.fg);
    const std::string path = cv::tempfile(".yml.gz");
    a->save(path);
    Ptr<TemplateForest> b = TemplateForest::load(path);
    Ptr<TemplateForest> b2 = Algorithm::load<TemplateForest>(path);
    remove(path.c_str());
    ASSERT_FALSE(b->empty());
    ASSERT_FALSE(b2.empty());
    EXPECT_EQ(a->dims(), b->dims());
    EXPECT_EQ(a->numTemplates(), b->numTemplates());
    EXPECT_EQ(a->statistics().nodes, b->statistics().nodes);

    Mat queries;
    vconcat(uniformBackground(500, d.desc.cols, 3), d.noisy.rowRange(0, 250), queries);
    RNG rng(4);
    Mat noisy(250, d.desc.cols, CV_8U);
    for (int i = 0; i < 250; ++i)
        perturb(d.noisy.ptr<uchar>(i), d.desc.cols, 0.1, rng, noisy.ptr<uchar>(i));
    vconcat(queries, noisy, queries);
    ASSERT_EQ(1000, queries.rows);
    std::vector<int> ca, cb;
    int accepted = 0;
    for (int i = 0; i < queries.rows; ++i)
    {
        int da = -2, db = -3;
        const bool oka = a->query(queries.ptr<uchar>(i), ca, &da);
        const bool okb = b->query(queries.ptr<uchar>(i), cb, &db);
        ASSERT_EQ(oka, okb) << i;
        ASSERT_EQ(da, db) << i;
        ASSERT_EQ(ca, cb) << i;
        accepted += oka;
    }
    EXPECT_GT(accepted, 400);   // both outcomes are exercised
    EXPECT_LT(accepted, 1000);
}

// The scan's path (leaf() on a gathered row, vectorised node tests; rootRejector() tested by the
// caller) reaches the same leaf, or rejects at the same depth, as queryTree() on every tree, for a
// trained forest and the same forest read back.
TEST(Forestmod_TemplateForest, leaf_of_a_row_equals_query_tree)
{
    std::vector<int> zeros(4096, 0), identity(4096);
    for (int j = 0; j < 4096; ++j)
        identity[j] = j;
    const uchar* plane = 0;
    auto view = [&](const uchar* row) {
        plane = row;
        LocationView v;
        v.planes = &plane;
        v.plane_of = &zeros[0];
        v.delta = &identity[0];
        v.offset = 0;
        return v;
    };
    ForestParams p;
    p.num_trees = 3;
    Data d = makeData(1000, 2, 73, p); // 2 objects: the roots have rejectors (4 do not)
    Ptr<TemplateForest> trained = TemplateForest::create(p);
    trained->train(d.desc, d.fg);
    const std::string path = cv::tempfile(".yml.gz");
    trained->save(path);
    Ptr<TemplateForest> read = TemplateForest::load(path);
    remove(path.c_str());
    Mat queries;
    vconcat(uniformBackground(400, d.desc.cols, 5), realPatches(400, 6), queries);
    vconcat(queries, d.noisy.rowRange(0, 400), queries);
    int reached[2] = { 0, 0 }, root_rejected = 0, max_nodes = 0;
    const int max_depth = trained->statistics().max_depth;
    for (const Ptr<TemplateForest>& f : { trained, read })
        for (int t = 0; t < p.num_trees; ++t)
        {
            std::vector<int> dims;
            std::vector<ushort> accepted;
            int min_accept = -1;
            const bool has_root = f->rootRejector(t, dims, accepted, min_accept);
            ASSERT_EQ(has_root, min_accept > 0);
            ASSERT_EQ(dims.size(), accepted.size());
            for (int i = 0; i < queries.rows; ++i)
            {
                const uchar* q = queries.ptr<uchar>(i);
                std::vector<int> expected;
                int depth = -2;
                const bool ok = f->queryTree(t, view(q), expected, &depth);
                // the root's rejector, as the scan tests it
                int acc = 0;
                for (size_t k = 0; k < dims.size(); ++k)
                    acc += q[dims[k]] ? (accepted[k] & q[dims[k]]) != 0 : (accepted[k] >> 8) & 1;
                const bool root_ok = !has_root || acc >= min_accept;
                if (!root_ok)
                {
                    ++root_rejected;
                    ASSERT_FALSE(ok) << "tree " << t << " query " << i;
                    ASSERT_EQ(0, depth) << "tree " << t << " query " << i;
                    continue;
                }
                for (int passed = 0; passed < 2; ++passed)
                {
                    const int* ids = 0;
                    int n = -1, leaf_depth = -2, nodes = -1;
                    const bool leaf_ok = f->leaf(t, q, ids, n, &leaf_depth, passed == 1,
                                                 &nodes);
                    ASSERT_EQ(ok, leaf_ok) << "tree " << t << " query " << i;
                    ASSERT_EQ(depth, leaf_depth) << "tree " << t << " query " << i;
                    // the nodes of the path: to the rejecting node, or to a leaf
                    if (!ok)
                        ASSERT_EQ(depth + 1, nodes) << "tree " << t << " query " << i;
                    else
                        ASSERT_TRUE(nodes >= 1 && nodes <= max_depth + 1) << nodes;
                    max_nodes = std::max(max_nodes, nodes);
                    if (ok)
                    {
                        ASSERT_EQ(expected, std::vector<int>(ids, ids + n)) << "query " << i;
                    }
                }
                reached[ok ? 1 : 0]++;
            }
        }
    // every outcome exercised: rejected at the root, deeper, and leaves reached
    std::cout << "root rejected " << root_rejected << ", rejected deeper " << reached[0]
              << ", leaves reached " << reached[1] << std::endl;
    EXPECT_GT(root_rejected, 100);
    EXPECT_GT(reached[0], 10);
    EXPECT_GT(reached[1], 100);
    EXPECT_GT(max_nodes, 2) << "descents deeper than the root's children";
}

TEST(Forestmod_TemplateForest, refuses_bad_files)
{
    ForestParams p;
    Data d = makeData(300, 2, 81, p);
    Ptr<TemplateForest> a = TemplateForest::create(p);
    a->train(d.desc, d.fg);
    const std::string text = serialize(*a);

    // wrong version
    std::string wrong = text;
    const size_t pos = wrong.find("format_version: 1");
    ASSERT_NE(std::string::npos, pos);
    wrong.replace(pos, 17, "format_version: 7");
    const std::string path = cv::tempfile(".yml");
    {
        std::ofstream f(path.c_str());
        f << wrong;
    }
    try
    {
        TemplateForest::load(path);
        ADD_FAILURE() << "a file of another version was accepted";
    }
    catch (const cv::Exception& e)
    {
        EXPECT_NE(std::string::npos, e.err.find("format_version 7")) << e.err;
    }
    // truncated at several places
    const double cuts[] = {0.3, 0.6, 0.95};
    for (int k = 0; k < 3; ++k)
    {
        {
            std::ofstream f(path.c_str());
            f << text.substr(0, (size_t)(cuts[k] * text.size()));
        }
        try
        {
            TemplateForest::load(path);
            ADD_FAILURE() << "a truncated file (" << cuts[k] << ") was accepted";
        }
        catch (const cv::Exception& e)
        {
            EXPECT_NE(std::string::npos, e.err.find(path)) << e.err;
        }
    }
    remove(path.c_str());
    // not a forest
    FileStorage fs("x.yml", FileStorage::WRITE + FileStorage::MEMORY);
    fs << "thing" << "{" << "a" << 1 << "}";
    FileStorage in(fs.releaseAndGetString(), FileStorage::READ + FileStorage::MEMORY);
    Ptr<TemplateForest> c = TemplateForest::create();
    EXPECT_THROW(c->read(in["thing"]), cv::Exception);
}

TEST(Forestmod_TemplateForest, refuses_bad_input)
{
    Ptr<TemplateForest> f = TemplateForest::create();
    EXPECT_TRUE(f->empty());
    Mat desc(10, 16, CV_8U, Scalar(4)), fg(10, 16, CV_8U, Scalar(1));
    EXPECT_THROW(f->train(Mat(), Mat()), cv::Exception);
    EXPECT_THROW(f->train(Mat(10, 16, CV_16U, Scalar(4)), fg), cv::Exception);
    EXPECT_THROW(f->train(desc, Mat(10, 15, CV_8U, Scalar(1))), cv::Exception);
    Mat multi = desc.clone();
    multi.at<uchar>(3, 5) = 3;   // two label bits: a scene value, not a template value
    EXPECT_THROW(f->train(multi, fg), cv::Exception);
    std::vector<int> cand;
    uchar row[16] = {0};
    EXPECT_THROW(f->query(row, cand), cv::Exception);   // untrained
    ForestParams bad;
    bad.num_trees = 0;
    EXPECT_THROW(TemplateForest::create(bad), cv::Exception);
    bad = ForestParams();
    bad.rejector_tau = 1.5f;
    EXPECT_THROW(TemplateForest::create(bad), cv::Exception);
    f->train(desc, fg);   // all identical: no split possible, one leaf with everything
    ASSERT_TRUE(f->query(desc.ptr<uchar>(0), cand));
    EXPECT_EQ(10u, cand.size());
    EXPECT_EQ(f->getParams().num_trees, f->statistics().nodes);   // one leaf per tree
    EXPECT_THROW(f->queryTree(f->getParams().num_trees, LocationView(), cand), cv::Exception);
    EXPECT_THROW(f->queryTree(-1, LocationView(), cand), cv::Exception);
}

TEST(Forestmod_TemplateForest, params_read_write)
{
    ForestParams p;
    p.num_trees = 5;
    p.max_depth = 9;
    p.fuzzy_margin = 2.5f;
    p.reject_any_tree = false;
    p.seed = 42;
    FileStorage fs("p.yml", FileStorage::WRITE + FileStorage::MEMORY);
    fs << "p" << "{";
    p.write(fs);
    fs << "}";
    FileStorage in(fs.releaseAndGetString(), FileStorage::READ + FileStorage::MEMORY);
    ForestParams q;
    q.read(in["p"]);
    EXPECT_EQ(5, q.num_trees);
    EXPECT_EQ(9, q.max_depth);
    EXPECT_EQ(2.5f, q.fuzzy_margin);
    EXPECT_FALSE(q.reject_any_tree);
    EXPECT_EQ(42, q.seed);
    EXPECT_EQ(p.rejector_rho, q.rejector_rho);
}

}} // namespace
