// This file is part of OpenCV project.
// It is subject to the license terms in the LICENSE file found in the top-level directory
// of this distribution and at http://opencv.org/license.html

// The validator's fast paths against LINEMOD's similarity read in place (detail::similarityAll):
// the forest path's memories on its location grid (scoreAt) at any top-left, in or partly out of
// the image, and a template's run of neighbouring cells scored at once (sumRuns16),
// the exhaustive path's linearized memories (scoreEverywhere) at every position of the T grid and
// the refinement's local search (scoreLocal, its best position bestLocal), with 8-bit (<= 63
// features) and 16-bit sums, features on the templates' far edges included; the linearized
// memories built only where the scene pyramid's tiles are valid.

#include "test_precomp.hpp"
#include "../src/validator.hpp"
#include "../src/exhaustive_search.hpp"
#include "../src/quantize_fast.hpp"
#include "../src/score_kernels.hpp"
#include "../src/kernel_dispatch.hpp"

namespace opencv_test { namespace {

using namespace cv::forestmod::detail;

// A level (spread by T) of a random textured frame, gradient + hue.
static LevelMaps randomLevel(RNG& rng, Size size, int T = 8)
{
    Mat coarse(size.height / 12, size.width / 12, CV_8UC3), img;
    rng.fill(coarse, RNG::UNIFORM, Scalar::all(0), Scalar::all(255));
    resize(coarse, img, size, 0, 0, INTER_CUBIC);
    std::vector<Ptr<linemod::Modality> > mods;
    mods.push_back(linemod::Modality::create("ColorGradient"));
    mods.push_back(ColorHue::create());
    LevelMaps level;
    level.T = T;
    level.pad = 0;
    level.quantized.resize(2);
    level.spread.resize(2);
    for (int m = 0; m < 2; ++m)
    {
        mods[m]->process(img)->quantize(level.quantized[m]);
        spreadLabelsFast(level.quantized[m], level.spread[m], level.T, 0);
    }
    level.size = level.quantized[0].size();
    return level;
}

// A two-modality, one-level template of w x h with f features per modality, some on its far
// edges (x = width or y = height, as cv::linemod's cropping leaves them).
static TemplatePyramid randomTemplate(RNG& rng, int w, int h, int f)
{
    TemplatePyramid tp(2);
    for (int m = 0; m < 2; ++m)
    {
        tp[m].width = w;
        tp[m].height = h;
        tp[m].pyramid_level = 0;
        for (int k = 0; k < f; ++k)
        {
            const int x = k == 0 ? w : rng.uniform(0, w), y = k == 1 ? h : rng.uniform(0, h);
            tp[m].features.push_back(linemod::Feature(x, y, rng.uniform(0, 8)));
        }
    }
    return tp;
}

TEST(Forestmod_Validation, fast_paths_equal_linemod_similarity)
{
    RNG rng(2015);
    const Size sizes[] = { Size(320, 240), Size(203, 157) }; // the second: not whole cells
    for (const Size& size : sizes)
    {
        const LevelMaps level = randomLevel(rng, size);
        LinearMemories lm;
        lm.build(level);
        LinearMemories grid;  // the forest path's: location step 4, border of 60 pixels
        grid.buildGrid(level, 4, 15);
        std::vector<ushort> scores;
        std::vector<int> raw;
        int compared = 0, nonzero = 0;
        // 2 f features: 8-bit runs, then 16-bit sums; 600: past the local search's stack array
        for (int f : { 8, 31, 40, 100, 300 })
        {
            const TemplatePyramid tp = randomTemplate(rng, rng.uniform(20, 49),
                                                      rng.uniform(20, 49), f);
            int span_x = 0, span_y = 0;
            ASSERT_TRUE(scoreEverywhere(lm, tp, 0, 2, span_x, span_y, scores));
            EXPECT_EQ(size.width / 8 - ((tp[0].width - 1) / 8 + 1), span_x);
            EXPECT_EQ(size.height / 8 - ((tp[0].height - 1) / 8 + 1), span_y);
            for (int r = 0; r <= span_y; ++r)
                for (int c = 0; c <= span_x; ++c)
                {
                    const int ref = similarityAll(level, tp, 0, Point(c * 8, r * 8));
                    ASSERT_EQ(ref, (int)scores[(size_t)r * lm.stride + c])
                        << size << " f " << f << " at " << c << "," << r;
                    ++compared;
                    nonzero += ref > 0;
                }
            // the refinement's local search: 16 x 16 positions of the T grid
            int local[256];
            const int ox = 8 * rng.uniform(0, 3), oy = 8 * rng.uniform(0, 3);
            if (scoreLocal(lm, tp, 0, 2, ox, oy, local))
            {
                for (int k = 0; k < 256; ++k)
                    ASSERT_EQ(similarityAll(level, tp, 0, Point(ox + k % 16 * 8, oy + k / 16 * 8)),
                              local[k]) << size << " f " << f << " local " << k;
                // the refinement's choice: the first position (row by row) of the largest sum
                const int* top = std::max_element(local, local + 256);
                int best = -1, index = -2, num_features = 0;
                ASSERT_TRUE(bestLocal(lm, tp, 0, 2, ox, oy, best, index, num_features));
                EXPECT_EQ(2 * f, num_features) << size << " f " << f;
                EXPECT_EQ(*top, best) << size << " f " << f;
                EXPECT_EQ(*top > 0 ? (int)(top - local) : -1, index) << size << " f " << f;
                ++compared;
            }
            else
                EXPECT_GT(oy / 8 + 16 + tp[0].height / 8, lm.rows) << "only when out of range";
            // the forest path: any top-left within the border, also partly outside the image
            std::vector<Point> tls;
            for (int k = 0; k < 500; ++k)
                tls.push_back(Point(rng.uniform(-10 - tp[0].width, size.width + 10),
                                    rng.uniform(-10 - tp[0].height, size.height + 10)));
            scoreAt(grid, tp, 0, 2, tls, raw);
            for (size_t k = 0; k < tls.size(); ++k)
                ASSERT_EQ(similarityAll(level, tp, 0, tls[k]), raw[k]) << size << " " << tls[k];
            // runs of 1..64 neighbouring cells of the location grid at once, in both
            // instruction sets: each cell's score equals LINEMOD's at its top-left
            const bool was_optimized = useOptimized();
            for (int k = 0; k < 40; ++k)
            {
                const Point phase(rng.uniform(0, 4), rng.uniform(0, 4));
                const int len = k < 2 ? 64 - 63 * k : rng.uniform(1, 65);
                const int qx = rng.uniform(-grid.border, grid.stride - grid.border - len + 1);
                const int qy = rng.uniform(-grid.border, grid.cells_y); // rows below: border
                std::vector<int> off, b(3);
                grid.featureOffsets(tp, 0, 2, phase, &b[0], off);
                for (int pass = 0; pass < 2; ++pass)
                {
                    setUseOptimized(pass == 0);
                    std::vector<ushort> run(64, 7);  // whole vectors written
                    sumRuns16(&run[0], &grid.data[0] + grid.cell(qx, qy), &off[0],
                              static_cast<int>(off.size()), len);
                    for (int c = 0; c < len; ++c)
                    {
                        const Point tl((qx + c) * 4 + phase.x, qy * 4 + phase.y);
                        // a read past a row's last cell wraps into the next row: compare the
                        // cells whose features stay in their row
                        if (tl.x + tp[0].width + 10 >= (grid.cells_x + grid.border) * 4)
                            continue;
                        ASSERT_EQ(similarityAll(level, tp, 0, tl), (int)run[c])
                            << size << " f " << f << " pass " << pass << " run " << len
                            << " at " << tl;
                        ++compared;
                        nonzero += run[c] > 0;
                    }
                }
                setUseOptimized(was_optimized);
            }
        }
        EXPECT_GT(compared, 1000);
        EXPECT_GT(nonzero, compared / 2);
    }
}

// LinearMemories::build with a tile grid: the cells touching a marked tile as in the full build,
// every other cell 0.
TEST(Forestmod_Validation, linear_memories_hold_the_responses_for_every_T)
{
    // every byte of the memories on the T grid: the response of its pixel's spread labels, 0
    // for pixels outside the image and in the slack (gathers specialised for T = 4, 5, 8)
    RNG rng(7);
    for (int T : { 3, 4, 5, 6, 8 })
        for (const Size& size : { Size(160, 120), Size(203, 157) })
        {
            const LevelMaps level = randomLevel(rng, size, T);
            LinearMemories lm;
            // bytes left from an earlier frame: the build writes every one of them
            lm.data.assign((size_t)(size.width / T + 1) * (size.height / T + 1) * T * T * 8 * 2
                               + LinearMemories::kSlack,
                           (uchar)0xA5);
            lm.build(level);
            ASSERT_EQ(size.width / T + 1, lm.stride);
            ASSERT_EQ(size.height / T + 1, lm.rows);
            for (int m = 0; m < 2; ++m)
            {
                std::vector<Mat> resp(8);
                for (int o = 0; o < 8; ++o)
                    resp[o].create(size, CV_8U);
                for (int y = 0; y < size.height; ++y)
                {
                    uchar* d[8];
                    for (int o = 0; o < 8; ++o)
                        d[o] = resp[o].ptr<uchar>(y);
                    spreadResponses(level.spread[m].ptr<uchar>(y), size.width, d);
                }
                int inside = 0;
                for (int o = 0; o < 8; ++o)
                    for (int dy = 0; dy < T; ++dy)
                        for (int dx = 0; dx < T; ++dx)
                            for (int cy = 0; cy < lm.rows; ++cy)
                                for (int cx = 0; cx < lm.stride; ++cx)
                                {
                                    const int x = cx * T + dx, y = cy * T + dy;
                                    const bool in = x < size.width && y < size.height;
                                    inside += in;
                                    ASSERT_EQ(in ? resp[o].at<uchar>(y, x) : 0,
                                              lm.data[lm.index(m, o, dx, dy) + lm.cell(cx, cy)])
                                        << "T " << T << " " << size << " modality " << m
                                        << " label " << o << " pixel " << x << "," << y;
                                }
                EXPECT_EQ(8 * size.area(), inside);
            }
            const size_t n = (size_t)lm.stride * lm.rows * T * T * 8 * 2;
            ASSERT_EQ(n + LinearMemories::kSlack, lm.data.size());
            for (size_t i = n; i < lm.data.size(); ++i)
                ASSERT_EQ(0, lm.data[i]) << "slack";
        }
}

TEST(Forestmod_Validation, linear_memories_of_marked_tiles_equal_the_full_ones)
{
    RNG rng(7);
    for (const Size& size : { Size(320, 240), Size(203, 157) })
    {
        LevelMaps level = randomLevel(rng, size);
        level.T = 5; // a cell size that does not divide the tiles
        const Size tile(64, 32);
        Mat tiles = Mat::zeros((size.height + tile.height - 1) / tile.height,
                               (size.width + tile.width - 1) / tile.width, CV_8U);
        for (int k = 0; k < tiles.rows * tiles.cols / 3; ++k)
            tiles.at<uchar>(rng.uniform(0, tiles.rows), rng.uniform(0, tiles.cols)) = 1;
        tiles.at<uchar>(tiles.rows - 1, tiles.cols - 1) = 1; // the partial tiles at the far edges
        LinearMemories full, part, every;
        full.build(level);
        // over the bytes of an earlier frame: the cells left out are 0 all the same; with every
        // tile marked, the full build's bytes
        part.data.assign(full.data.size(), (uchar)0xA5);
        part.build(level, tiles, tile);
        ASSERT_EQ(full.data.size(), part.data.size());
        ASSERT_EQ(full.stride, part.stride);
        every.data.assign(full.data.size(), (uchar)0xA5);
        every.build(level, Mat::ones(tiles.size(), CV_8U), tile);
        ASSERT_TRUE(full.data == every.data) << size;
        int inside = 0, outside = 0;
        for (int m = 0; m < 2; ++m)
            for (int o = 0; o < 8; ++o)
                for (int dy = 0; dy < 5; ++dy)
                    for (int dx = 0; dx < 5; ++dx)
                        for (int cy = 0; cy < full.rows; ++cy)
                            for (int cx = 0; cx < full.stride; ++cx)
                            {
                                bool marked = false;
                                for (int ty = cy * 5 / tile.height;
                                     ty <= (cy * 5 + 4) / tile.height && ty < tiles.rows; ++ty)
                                    for (int tx = cx * 5 / tile.width;
                                         tx <= (cx * 5 + 4) / tile.width && tx < tiles.cols; ++tx)
                                        marked = marked || tiles.at<uchar>(ty, tx);
                                const size_t i = full.index(m, o, dx, dy) + cy * full.stride + cx;
                                if (marked)
                                {
                                    ASSERT_EQ(full.data[i], part.data[i]) << size << " cell " << cx
                                                                          << "," << cy;
                                    ++inside;
                                }
                                else
                                {
                                    ASSERT_EQ(0, part.data[i]) << size << " cell " << cx << ","
                                                               << cy;
                                    ++outside;
                                }
                            }
        EXPECT_GT(inside, 1000);
        EXPECT_GT(outside, 1000);
    }
}

// The kernels' AVX2 build (when the CPU has it) against the baseline one: the same scores.
TEST(Forestmod_Validation, instruction_sets_give_the_same_scores)
{
    RNG rng(11);
    const LevelMaps level = randomLevel(rng, Size(320, 240));
    LinearMemories lm;
    lm.build(level);
    const bool was_optimized = useOptimized();
    for (int f : { 20, 63, 150 })
    {
        const TemplatePyramid tp = randomTemplate(rng, 40, 32, f);
        std::vector<ushort> scores[2];
        int local[2][256];
        bool local_ok[2];
        for (int pass = 0; pass < 2; ++pass)
        {
            setUseOptimized(pass == 0);
            if (pass == 1)
            {
                EXPECT_STREQ("baseline", kernelsPath());
            }
            int span_x = 0, span_y = 0;
            ASSERT_TRUE(scoreEverywhere(lm, tp, 0, 2, span_x, span_y, scores[pass]));
            local_ok[pass] = scoreLocal(lm, tp, 0, 2, 8, 16, local[pass]);
        }
        setUseOptimized(was_optimized);
        ASSERT_EQ(scores[0].size(), scores[1].size());
        for (size_t k = 0; k < scores[0].size(); ++k)
            ASSERT_EQ(scores[0][k], scores[1][k]) << "f " << f << " position " << k;
        ASSERT_TRUE(local_ok[0] && local_ok[1]);
        for (int k = 0; k < 256; ++k)
            ASSERT_EQ(local[0][k], local[1][k]) << "f " << f << " local " << k;
    }
    // the local search's first largest sum: ties, the last lane, all zero
    for (int pass = 0; pass < 2; ++pass)
    {
        setUseOptimized(pass == 0);
        ushort v[256], best = 7;
        std::fill(v, v + 256, (ushort)0);
        EXPECT_EQ(-1, firstMax256(v, best));
        EXPECT_EQ(0, best);
        v[255] = 1;
        EXPECT_EQ(255, firstMax256(v, best));
        EXPECT_EQ(1, best);
        for (int k = 0; k < 256; ++k)
            v[k] = (ushort)rng.uniform(0, 500);
        v[77] = v[200] = v[201] = 600;
        EXPECT_EQ(77, firstMax256(v, best)) << "pass " << pass;
        EXPECT_EQ(600, best);
        v[0] = 60000;
        EXPECT_EQ(0, firstMax256(v, best)) << "pass " << pass;
        EXPECT_EQ(60000, best);
    }
    setUseOptimized(was_optimized);
    // the scan's row kernels, on every value a label plane holds, odd lengths
    std::vector<uchar> src(1001), out[2][2];
    for (size_t k = 0; k < src.size(); ++k)
        src[k] = k % 7 == 0 ? 0 : (uchar)(1 << rng.uniform(0, 8));
    for (int pass = 0; pass < 2; ++pass)
    {
        setUseOptimized(pass == 0);
        out[pass][0].assign(src.size(), 3);
        out[pass][1].assign(src.size(), 5);
        for (int n : { 1001, 17, 0 })
        {
            countLabels8(&out[pass][0][0], &src[0], n);
            countAccepted8(&out[pass][1][0], &src[0], n, 0x25, 0);
            countAccepted8(&out[pass][1][0], &src[0], n, 0x80, 1);
        }
    }
    setUseOptimized(was_optimized);
    for (size_t k = 0; k < src.size(); ++k)
    {
        const int times = 1 + (k < 17);
        ASSERT_EQ(3 + times * (src[k] != 0), out[0][0][k]) << k;
        const int accepted = ((src[k] & 0x25) != 0) + (src[k] == 0 || src[k] == 0x80);
        ASSERT_EQ(5 + times * accepted, out[0][1][k]) << k;
        ASSERT_EQ(out[0][0][k], out[1][0][k]) << k;
        ASSERT_EQ(out[0][1][k], out[1][1][k]) << k;
    }
    setUseOptimized(was_optimized);
    std::cout << "score kernels: " << kernelsPath() << std::endl;
}


// The exhaustive search's preemptive additions (sumRunsPassing16): every position whose full sum
// passes the threshold and its entry bar is found, in order, with its full sum, though vectors of
// positions leave between the stages of features; both instruction sets.
TEST(Forestmod_Validation, preemptive_sums_find_every_passing_position)
{
    RNG rng(5);
    const int n_max = 1000, run = n_max + 64;
    const bool was_optimized = useOptimized();
    for (int n_off : { 0, 5, 31, 32, 62, 94, 150 })
    {
        // run k holds the responses of feature k at the positions 0 .. n_max (+ 64 read beyond)
        std::vector<uchar> base((size_t)std::max(n_off, 1) * run + LinearMemories::kSlack, 4);
        std::vector<int> off(std::max(n_off, 1));
        for (int k = 0; k < n_off; ++k)
            off[k] = k * run;
        for (int p = 0; p < n_max; ++p)
        {
            const int kind = p % 97 == 3 ? 0 : p % 89 == 7 ? 1 : p % 83 == 11 ? 2 : 3;
            for (int k = 0; k < n_off; ++k)
            {
                uchar v = (uchar)rng.uniform(0, 5); // clutter: about half the largest sum
                if (kind == 0) // the object: every response the largest
                    v = 4;
                else if (kind == 1) // late: weak first features, then the largest
                    v = k < 24 ? 2 : 4;
                else if (kind == 2) // early: the largest first, then weak ones
                    v = k < 24 ? 4 : 2;
                base[(size_t)k * run + p] = v;
            }
        }
        const int raw_thr = (int)(0.8 * 4 * n_off), scale = 4 * std::max(n_off, 1);
        std::vector<ushort> bar(n_max + LinearMemories::kSlack, 0);
        for (int p = 0; p < n_max; p += 7) // bars between 70 and 100 % of the largest sum
            bar[p] = (ushort)rng.uniform(45875, 65536);
        for (int n : { 1000, 203, 33, 1, 0 })
        {
            std::vector<int> expect;
            std::vector<ushort> full(n);
            for (int p = 0; p < n; ++p)
            {
                int sum = 0;
                for (int k = 0; k < n_off; ++k)
                    sum += base[(size_t)off[k] + p];
                full[p] = (ushort)sum;
                if (sum > raw_thr && (int64)sum * 65536 >= (int64)bar[p] * scale - 65535)
                    expect.push_back(p);
            }
            for (int pass = 0; pass < 2; ++pass)
            {
                setUseOptimized(pass == 0);
                std::vector<ushort> sums(n + 64), need(n + 64);
                std::vector<int> vec(n / 16 + 1), hits(std::max(n, 1));
                hits.resize(sumRunsPassing16(&sums[0], &base[0], &off[0], n_off, n, &bar[0],
                                             (ushort)raw_thr, (ushort)scale, &need[0], &vec[0],
                                             &hits[0]));
                ASSERT_EQ(expect, hits) << "features " << n_off << " n " << n << " pass " << pass;
                for (int p : hits)
                    ASSERT_EQ(full[p], sums[p]) << "features " << n_off << " position " << p;
            }
            setUseOptimized(was_optimized);
            if (n == 1000 && n_off > 0)
            {
                // the object's positions all pass; the late and early ones with 94 features
                EXPECT_GE(expect.size(), 10u) << n_off;
                if (n_off == 94)
                {
                    EXPECT_TRUE(std::count(expect.begin(), expect.end(), 7 + 89 * 3) == 1);
                }
            }
        }
    }
}

}} // namespace
