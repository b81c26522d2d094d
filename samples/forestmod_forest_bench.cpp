// This file is part of OpenCV project.
// It is subject to the license terms in the LICENSE file found in the top-level directory
// of this distribution and at http://opencv.org/license.html

// Synthetic benchmark of cv::forestmod::TemplateForest: trains a forest on synthetic template
// descriptors (views of a few textured shapes, see test/forest_synth.hpp) and reports self-recall,
// recall under corruption, candidates, rejection of uniform and real-image background, training
// time. The numbers and commands of doc/forest.md come from this program.

#include "opencv2/forestmod.hpp"
#include "opencv2/core/utility.hpp"
#include "opencv2/imgcodecs.hpp"
#include "opencv2/rgbd/linemod.hpp"

#include "../test/forest_synth.hpp"

#include <algorithm>
#include <cstdio>
#include <iostream>

using namespace cv;
using namespace cv::forestmod;
using namespace opencv_test::forest_synth;

static const char* keys =
    "{help h usage ? |      | print this message }"
    "{templates      | 1000 | number of synthetic templates }"
    "{objects        | 4    | number of synthetic objects }"
    "{grid           | 8    | grid points per side (D = 2 grid^2) }"
    "{noise          | 0.1  | share of a query's dims replaced by random values }"
    "{queries        | 3000 | queries per measurement }"
    "{frames         |      | folder of lmo_mini/test/000002/rgb (real background); empty: skip }"
    "{spread         | 1    | OR-spread of the real quantized images (1 = none, LINEMOD uses 4-8) }"
    "{trees          | -1   | ForestParams::num_trees (-1: default) }"
    "{depth          | -1   | max_depth }"
    "{min_node       | -1   | min_node_size }"
    "{d              | -1   | split_dims (d') }"
    "{pool           | -1   | pool_size }"
    "{xi             | -1   | fuzzy_margin }"
    "{split_cov      | -1   | split_coverage }"
    "{rdims          | -1   | rejector_dims }"
    "{rho            | -1   | rejector_rho }"
    "{tau            | -1   | rejector_tau }"
    "{rcov           | -1   | rejector_coverage }"
    "{rnoise         | -1   | rejector_noise }"
    "{any            | -1   | reject_any_tree (0/1) }"
    "{seed           | -1   | seed }"
    "{shift          | 0    | also query views re-rendered with the window misaligned by up to this "
    "many grid steps (uniform in x and y), on new background, with --noise corruption }"
    "{augment        | 0    | extra training samples per template, rendered with the window "
    "misaligned by up to --aug_shift grid steps (TemplateForest::train with template ids) }"
    "{aug_shift      | 0.25 | misalignment of the extra samples, grid steps }"
    "{qspread        | 0    | with --shift: OR the values sampled over +-qspread/2 grid steps around "
    "each point (what a spread image holds) }";

static void orSpread(const Mat& src, Mat& dst, int T)
{
    dst = src.clone();
    for (int r = 0; r < T; ++r)
        for (int c = 0; c < T; ++c)
        {
            if (!r && !c)
                continue;
            Mat d = dst(Rect(0, 0, src.cols - c, src.rows - r));
            bitwise_or(d, src(Rect(c, r, src.cols - c, src.rows - r)), d);
        }
}

static Mat realPatches(const std::string& folder, int count, int G, int spread)
{
    const char* frames[] = {"000224.png", "000902.png", "001038.png"};
    const int step = 5;
    std::vector<Mat> grads, hues;
    Ptr<linemod::Modality> grad = linemod::Modality::create("ColorGradient");
    Ptr<linemod::Modality> hue = ColorHue::create();
    for (int f = 0; f < 3; ++f)
    {
        Mat img = imread(folder + "/" + frames[f], IMREAD_COLOR);
        if (img.empty())
            CV_Error_(Error::StsError, ("cannot read %s/%s", folder.c_str(), frames[f]));
        Mat qg, qh;
        grad->process(img)->quantize(qg);
        hue->process(img)->quantize(qh);
        if (spread > 1)
        {
            Mat a, b;
            orSpread(qg, a, spread);
            orSpread(qh, b, spread);
            qg = a;
            qh = b;
        }
        grads.push_back(qg);
        hues.push_back(qh);
    }
    RNG rng(8);
    Mat out(count, 2 * G * G, CV_8U);
    for (int i = 0; i < count; ++i)
    {
        const int f = i % 3;
        const int x0 = rng.uniform(0, grads[f].cols - step * G);
        const int y0 = rng.uniform(0, grads[f].rows - step * G);
        uchar* d = out.ptr<uchar>(i);
        for (int y = 0; y < G; ++y)
            for (int x = 0; x < G; ++x)
            {
                d[y * G + x] = grads[f].at<uchar>(y0 + y * step, x0 + x * step);
                d[G * G + y * G + x] = hues[f].at<uchar>(y0 + y * step, x0 + x * step);
            }
    }
    return out;
}

static void printDepths(const ForestQueryStats& s)
{
    std::printf(" (by depth:");
    for (size_t i = 0; i < s.rejected_at_depth.size(); ++i)
        std::printf(" %lld", (long long)s.rejected_at_depth[i]);
    std::printf(")");
}

static int bench(int argc, char** argv)
{
    CommandLineParser parser(argc, argv, keys);
    parser.about("Synthetic benchmark of the fuzzy template forest and its background rejectors");
    if (parser.has("help"))
    {
        parser.printMessage();
        return 0;
    }
    const int n = parser.get<int>("templates"), objects = parser.get<int>("objects");
    const int G = parser.get<int>("grid"), Q = parser.get<int>("queries");
    const double noise = parser.get<double>("noise");
    ForestParams p;
    if (parser.get<int>("trees") >= 0) p.num_trees = parser.get<int>("trees");
    if (parser.get<int>("depth") >= 0) p.max_depth = parser.get<int>("depth");
    if (parser.get<int>("min_node") >= 0) p.min_node_size = parser.get<int>("min_node");
    if (parser.get<int>("d") >= 0) p.split_dims = parser.get<int>("d");
    if (parser.get<int>("pool") >= 0) p.pool_size = parser.get<int>("pool");
    if (parser.get<float>("xi") >= 0) p.fuzzy_margin = parser.get<float>("xi");
    if (parser.get<float>("split_cov") >= 0) p.split_coverage = parser.get<float>("split_cov");
    if (parser.get<int>("rdims") >= 0) p.rejector_dims = parser.get<int>("rdims");
    if (parser.get<float>("rho") >= 0) p.rejector_rho = parser.get<float>("rho");
    if (parser.get<float>("tau") >= 0) p.rejector_tau = parser.get<float>("tau");
    if (parser.get<float>("rcov") >= 0) p.rejector_coverage = parser.get<float>("rcov");
    if (parser.get<float>("rnoise") >= 0) p.rejector_noise = parser.get<float>("rnoise");
    if (parser.get<int>("any") >= 0) p.reject_any_tree = parser.get<int>("any") != 0;
    if (parser.get<int>("seed") >= 0) p.seed = parser.get<int>("seed");
    if (!parser.check())
    {
        parser.printErrors();
        return 1;
    }

    Mat desc, fg, trained;
    std::vector<View> views;
    makeTemplates(n, objects, G, 12345, desc, fg, 0, 0.5, 0.95, &views);
    Ptr<TemplateForest> forest = TemplateForest::create(p);
    const int augment = parser.get<int>("augment");
    Mat train_desc = desc, train_fg = fg;
    std::vector<int> ids;
    if (augment > 0)
    {
        const double as = parser.get<double>("aug_shift") * 2.0 / G;
        std::vector<Shape> shapes;
        for (int o = 0; o < objects; ++o)
            shapes.push_back(makeShape(o));
        RNG arng(77);
        train_desc.create(n * (augment + 1), desc.cols, CV_8U);
        train_fg.create(n * (augment + 1), desc.cols, CV_8U);
        desc.copyTo(train_desc.rowRange(0, n));
        fg.copyTo(train_fg.rowRange(0, n));
        for (int i = 0; i < n; ++i)
            ids.push_back(i);
        for (int k = 0; k < augment; ++k)
            for (int i = 0; i < n; ++i)
            {
                const View& v = views[i];
                const int row = n * (k + 1) + i;
                renderView(shapes[v.object], v.alpha, v.scale, v.squash, G,
                           train_desc.ptr<uchar>(row), train_fg.ptr<uchar>(row), 0.5, 0.95,
                           arng.uniform(-as, as), arng.uniform(-as, as));
                ids.push_back(i);
            }
    }
    TickMeter tm;
    tm.start();
    if (augment > 0)
        forest->train(train_desc, train_fg, ids);
    else
        forest->train(desc, fg);
    tm.stop();
    TemplateForest::applyBackgroundModel(desc, fg, p.seed, trained);
    const TemplateForest::Statistics st = forest->statistics();
    if (augment > 0)
        std::printf("%d samples per template (misaligned by up to %g grid steps)\n", augment + 1,
                    parser.get<double>("aug_shift"));
    std::printf("%d templates (%d objects), D = %d; trees %d depth %d min_node %d d' %d pool %d "
                "xi %g split_cov %g | rejector dims %d rho %g tau %g cov %g noise %g any %d\n",
                n, objects, desc.cols, p.num_trees, p.max_depth, p.min_node_size, p.split_dims,
                p.pool_size, p.fuzzy_margin, p.split_coverage, p.rejector_dims, p.rejector_rho,
                p.rejector_tau, p.rejector_coverage, p.rejector_noise, (int)p.reject_any_tree);
    std::printf("train %.1f ms (%d threads); nodes %d, leaves %d, deepest %d, mean leaf size %.1f, "
                "mean leaves per template %.2f, %.1f KB\n", tm.getTimeMilli(), getNumThreads(),
                st.nodes, st.leaves, st.max_depth, st.mean_leaf_size, st.mean_leaves_per_template,
                st.bytes / 1024.0);

    const int D = desc.cols;
    std::vector<int> cand;
    int self = 0;
    for (int i = 0; i < n; ++i)
        self += forest->query(trained.ptr<uchar>(i), cand) &&
                std::binary_search(cand.begin(), cand.end(), i);
    std::printf("self-recall %.4f\n", (double)self / n);

    RNG rng(5);
    std::vector<uchar> q(D);
    for (int fresh = 0; fresh < 3; ++fresh)
    {
        int hit = 0, rej = 0;
        double nc = 0;
        ForestQueryStats s;
        TickMeter tq;
        for (int i = 0; i < Q; ++i)
        {
            const int t = rng.uniform(0, n);
            perturb(trained.ptr<uchar>(t), D, noise, rng, &q[0]);
            if (fresh)   // off-mask values: new background, not the trained noise
                for (int j = 0; j < D; ++j)
                    if (!fg.at<uchar>(t, j))
                        q[j] = randomValue(rng);
            if (fresh == 2)   // spread-like: neighbouring labels OR-ed in, as spread images do
                for (int j = 0; j < D; ++j)
                {
                    const int v = q[j];
                    if (v && rng.uniform(0., 1.) < 0.5)
                        q[j] = (uchar)(v | ((v << 1) | (v >> 1) | (v == 1 ? 128 : 0) |
                                            (v == 128 ? 1 : 0)));
                    else if (!v && rng.uniform(0., 1.) < 0.3)
                        q[j] = (uchar)(1 << rng.uniform(0, 8));
                }
            tq.start();
            const bool ok = forest->query(&q[0], cand, 0, &s);
            tq.stop();
            if (!ok)
            {
                rej++;
                continue;
            }
            nc += (double)cand.size();
            hit += std::binary_search(cand.begin(), cand.end(), t);
        }
        std::printf("%s, %g %% corrupted: recall %.4f, rejected %.4f, candidates %.1f, nodes "
                    "visited %.1f, %.2f us/query\n",
                    fresh == 2 ? "same, spread-like (neighbour labels OR-ed in)"
                               : fresh ? "templates on new background" : "templates",
                    noise * 100,
                    (double)hit / Q, (double)rej / Q, nc / std::max(1, Q - rej),
                    (double)s.nodes_visited / s.locations, tq.getTimeMicro() / Q);
    }
    const double shift = parser.get<double>("shift"), qspread = parser.get<double>("qspread");
    if (shift > 0)
    {
        std::vector<Shape> shapes;
        for (int o = 0; o < objects; ++o)
            shapes.push_back(makeShape(o));
        const double step = 2.0 / G;   // one grid step in window units
        std::vector<uchar> r(D), m(D);
        int hit = 0, rej = 0;
        double nc = 0;
        for (int i = 0; i < Q; ++i)
        {
            const int t = rng.uniform(0, n);
            const View& v = views[t];
            const double tx = rng.uniform(-shift, shift) * step, ty = rng.uniform(-shift, shift) * step;
            std::fill(q.begin(), q.end(), (uchar)0);
            const int ns = qspread > 0 ? 3 : 1;
            for (int sy = 0; sy < ns; ++sy)
                for (int sx = 0; sx < ns; ++sx)
                {
                    const double ox = ns > 1 ? (sx - 1) * qspread * step / 2 : 0;
                    const double oy = ns > 1 ? (sy - 1) * qspread * step / 2 : 0;
                    renderView(shapes[v.object], v.alpha, v.scale, v.squash, G, &r[0], &m[0], 0.5,
                               0.95, tx + ox, ty + oy);
                    for (int j = 0; j < D; ++j)
                        q[j] |= m[j] ? r[j] : randomValue(rng);
                }
            std::vector<uchar> c(q);
            perturb(&c[0], D, noise, rng, &q[0]);
            if (!forest->query(&q[0], cand))
            {
                rej++;
                continue;
            }
            nc += (double)cand.size();
            hit += std::binary_search(cand.begin(), cand.end(), t);
        }
        std::printf("views misaligned by up to %g grid steps (query spread %g), %g %% corrupted: "
                    "recall %.4f, rejected %.4f, candidates %.1f\n", shift, qspread, noise * 100,
                    (double)hit / Q, (double)rej / Q, nc / std::max(1, Q - rej));
    }
    {
        ForestQueryStats s;
        for (int i = 0; i < Q; ++i)
        {
            for (int j = 0; j < D; ++j)
                q[j] = randomValue(rng);
            forest->query(&q[0], cand, 0, &s);
        }
        std::printf("uniform background: rejected %.4f", s.rejectionRate());
        printDepths(s);
        std::printf("\n");
    }
    const std::string folder = parser.get<std::string>("frames");
    if (!folder.empty())
    {
        const int spread = parser.get<int>("spread");
        Mat rp = realPatches(folder, Q, G, spread);
        ForestQueryStats s;
        for (int i = 0; i < rp.rows; ++i)
            forest->query(rp.ptr<uchar>(i), cand, 0, &s);
        std::printf("real-image windows (spread %d): rejected %.4f", spread, s.rejectionRate());
        printDepths(s);
        std::printf(", candidates of accepted %.1f\n",
                    (double)s.candidates / std::max<int64>(1, s.locations - s.rejected));
    }
    return 0;
}

int main(int argc, char** argv)
{
    try
    {
        return bench(argc, argv);
    }
    catch (const cv::Exception& e) // an unreadable frame, a parameter out of range
    {
        std::cerr << "forestmod_forest_bench: " << e.what() << std::endl;
        return 1;
    }
}
