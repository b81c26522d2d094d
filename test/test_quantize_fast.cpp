// This file is part of OpenCV project.
// It is subject to the license terms in the LICENSE file found in the top-level directory
// of this distribution and at http://opencv.org/license.html

// The fast quantization (src/quantize_fast.*) against the modalities' own virtual calls, the
// fast spreading / response maps against detail::spreadLabels / computeResponseMaps, and the
// scene pyramid's on-demand tiles against the full-frame maps.

#include "test_precomp.hpp"
#include "../src/quantize_fast.hpp"
#include "../src/quantize_kernels.hpp"
#include "../src/kernel_dispatch.hpp"
#include "../src/scene_pyramid.hpp"
#include "../src/refine.hpp"

namespace opencv_test { namespace {

using cv::forestmod::detail::ModalityInfo;

// What the detector computed before the fast paths: process + (pyrDown + quantize) per level.
static std::vector<Mat> referenceLevels(const Ptr<linemod::Modality>& m, const Mat& src,
                                        const Mat& mask, int levels)
{
    std::vector<Mat> out(levels);
    Ptr<linemod::QuantizedPyramid> qp = m->process(src, mask);
    for (int l = 0; l < levels; ++l)
    {
        if (l > 0)
            qp->pyrDown();
        qp->quantize(out[l]);
    }
    return out;
}

// Number of differing pixels (sizes and types must agree).
static int differences(const Mat& a, const Mat& b)
{
    if (a.size() != b.size() || a.type() != b.type())
        return -1;
    Mat ne;
    cv::compare(a, b, ne, CMP_NE);
    return countNonZero(ne);
}

static void expectSameLevels(const Ptr<linemod::Modality>& m, const Mat& src, const Mat& mask,
                             int levels, const std::string& what, int min_labelled = 50)
{
    const std::vector<Mat> ref = referenceLevels(m, src, mask, levels);
    std::vector<Mat> fast;
    ASSERT_TRUE(cv::forestmod::detail::fastQuantize(m, src, mask, levels, fast)) << what;
    ASSERT_EQ((size_t)levels, fast.size()) << what;
    for (int l = 0; l < levels; ++l)
    {
        ASSERT_EQ(CV_8UC1, fast[l].type()) << what << " level " << l;
        ASSERT_EQ(ref[l].size(), fast[l].size()) << what << " level " << l;
        EXPECT_EQ(0, differences(ref[l], fast[l])) << what << " level " << l << " of " << levels
                                                   << ", " << m->name() << ", size "
                                                   << fast[l].size();
        // the comparison means something only where the images hold labels
        if (l == 0)
        {
            EXPECT_GE(countNonZero(ref[l]), min_labelled) << what << ", " << m->name();
        }
    }
}

static std::vector<Ptr<linemod::Modality> > colourModalities()
{
    std::vector<Ptr<linemod::Modality> > ms;
    ms.push_back(linemod::Modality::create("ColorGradient"));
    ms.push_back(ColorHue::create());
    Ptr<linemod::ColorGradient> strong = makePtr<linemod::ColorGradient>(30.f, 63, 55.f);
    ms.push_back(strong);
    ColorHue::Params hp;
    hp.blur_size = 0;
    hp.saturation_threshold = 20;
    hp.value_threshold = 10;
    ms.push_back(ColorHue::create(hp));
    hp.blur_size = 5;
    ms.push_back(ColorHue::create(hp));
    return ms;
}

// An object-like mask: an ellipse and a rectangle with ragged borders.
static Mat someMask(Size size, uint64 seed)
{
    RNG rng(seed);
    Mat mask = Mat::zeros(size, CV_8U);
    ellipse(mask, Point(size.width / 3, size.height / 2), Size(size.width / 4, size.height / 3),
            rng.uniform(0., 180.), 0, 360, Scalar(255), FILLED);
    rectangle(mask, Rect(size.width / 2, size.height / 4, size.width / 3, size.height / 3),
              Scalar(7), FILLED);
    Mat noise(size, CV_8U);
    rng.fill(noise, RNG::UNIFORM, 0, 20);
    mask.setTo(0, noise == 0);
    return mask;
}

// A random image with edges of every orientation and saturated colours.
static Mat randomScene(Size size, uint64 seed)
{
    RNG rng(seed);
    Mat img(size, CV_8UC3);
    rng.fill(img, RNG::UNIFORM, 0, 256);
    GaussianBlur(img, img, Size(0, 0), 1.5);
    for (int i = 0; i < 12; ++i)
    {
        const Point c(rng.uniform(0, size.width), rng.uniform(0, size.height));
        const Scalar col(rng.uniform(0, 256), rng.uniform(0, 256), rng.uniform(0, 256));
        if (i % 2)
            circle(img, c, rng.uniform(3, std::max(4, size.width / 4)), col, FILLED);
        else
            fillConvexPoly(img, std::vector<Point>{c, c + Point(rng.uniform(-60, 60), 30),
                                                   c + Point(40, rng.uniform(-60, 60))},
                           col);
    }
    return img;
}

static std::vector<std::string> shippedFrames()
{
    const std::string dir = cvtest::findDataDirectory("lmo_mini/test/000002/rgb", false);
    std::vector<String> files;
    glob(dir + "/*.png", files);
    return std::vector<std::string>(files.begin(), files.end());
}

TEST(Forestmod_QuantizeFast, classifies_modalities)
{
    using namespace cv::forestmod::detail;
    Ptr<linemod::ColorGradient> g = makePtr<linemod::ColorGradient>(12.5f, 40, 60.f);
    ModalityInfo gi = classifyModality(g);
    EXPECT_EQ(MODALITY_COLOR_GRADIENT, gi.kind);
    EXPECT_EQ(12.5f, gi.weak_threshold);
    EXPECT_TRUE(hasFastPath(gi));
    ModalityInfo di = classifyModality(makePtr<linemod::DepthNormal>(1500, 40, 63, 2));
    EXPECT_EQ(MODALITY_DEPTH_NORMAL, di.kind);
    EXPECT_EQ(1500, di.distance_threshold);
    EXPECT_EQ(40, di.difference_threshold);
    ColorHue::Params hp;
    hp.saturation_threshold = 33;
    ModalityInfo hi = classifyModality(ColorHue::create(hp));
    EXPECT_EQ(MODALITY_COLOR_HUE, hi.kind);
    EXPECT_EQ(33, hi.saturation_threshold);
    // a subclass may override processImpl: it keeps its virtual calls
    struct MyGradient : public linemod::ColorGradient
    {
    };
    ModalityInfo si = classifyModality(makePtr<MyGradient>());
    EXPECT_EQ(MODALITY_OTHER, si.kind);
    EXPECT_FALSE(hasFastPath(si));
    std::vector<Mat> q;
    EXPECT_FALSE(fastQuantize(si, Mat(10, 10, CV_8UC3, Scalar::all(0)), Mat(), 2, q));
    EXPECT_TRUE(q.empty());
    EXPECT_EQ(MODALITY_OTHER, classifyModality(Ptr<linemod::Modality>()).kind);
}

TEST(Forestmod_QuantizeFast, shipped_frames_all_levels)
{
    const std::vector<std::string> files = shippedFrames();
    ASSERT_FALSE(files.empty());
    const std::vector<Ptr<linemod::Modality> > ms = colourModalities();
    for (size_t f = 0; f < files.size(); ++f)
    {
        const Mat img = imread(files[f], IMREAD_COLOR);
        ASSERT_FALSE(img.empty()) << files[f];
        const Mat mask = someMask(img.size(), f + 1);
        for (size_t i = 0; i < ms.size(); ++i)
        {
            for (int levels = 2; levels <= 4; levels += 2)
            {
                expectSameLevels(ms[i], img, Mat(), levels, files[f]);
                expectSameLevels(ms[i], img, mask, levels, files[f] + " masked");
            }
        }
    }
}

TEST(Forestmod_QuantizeFast, real_rgbd_colour_frames)
{
    const std::string shared = sharedDataPath();
    if (shared.empty() || !utils::fs::exists(shared + "/real_rgbd"))
        throw SkipTestException("FORESTMOD_SHARED_DATA/real_rgbd is not available");
    std::vector<String> files;
    glob(shared + "/real_rgbd/*_rgb.png", files);
    if (files.empty())
        throw SkipTestException("no *_rgb.png in FORESTMOD_SHARED_DATA/real_rgbd");
    const std::vector<Ptr<linemod::Modality> > ms = colourModalities();
    for (size_t f = 0; f < files.size(); ++f)
    {
        const Mat img = imread(files[f], IMREAD_COLOR);
        ASSERT_FALSE(img.empty()) << files[f];
        for (size_t i = 0; i < ms.size(); ++i)
        {
            expectSameLevels(ms[i], img, Mat(), 2, files[f]);
            expectSameLevels(ms[i], img, Mat(), 5, files[f]);
            expectSameLevels(ms[i], img, someMask(img.size(), 7), 3, files[f] + " masked");
        }
    }
}

TEST(Forestmod_QuantizeFast, random_odd_sizes)
{
    const Size sizes[] = { Size(161, 97), Size(333, 211), Size(40, 23), Size(17, 9), Size(3, 3),
                           Size(2, 5), Size(641, 479) };
    const std::vector<Ptr<linemod::Modality> > ms = colourModalities();
    for (size_t s = 0; s < sizeof(sizes) / sizeof(sizes[0]); ++s)
    {
        const Mat img = randomScene(sizes[s], 100 + s);
        const Mat mask = someMask(sizes[s], 200 + s);
        const int min_labelled = sizes[s].area() > 1000 ? 50 : 0;
        for (size_t i = 0; i < ms.size(); ++i)
        {
            std::ostringstream what;
            what << "random " << sizes[s];
            const int max_levels = sizes[s].area() > 1000 ? 4 : 2;
            for (int levels = 1; levels <= max_levels; ++levels)
            {
                expectSameLevels(ms[i], img, Mat(), levels, what.str(), min_labelled);
                expectSameLevels(ms[i], img, mask, levels, what.str() + " masked", 0);
            }
        }
    }
}

// The row kernels' AVX2 build (when the CPU has it) and the baseline one: each equal to the
// modalities' own quantization run with the same OpenCV setting, and to each other, on widths
// around the vector sizes (16 and 32 bytes: the last vector of a row overlaps the one before, a
// narrower row takes the scalar path); the spreading, responses and label planes likewise.
TEST(Forestmod_QuantizeFast, instruction_sets_give_the_same_images)
{
    using namespace cv::forestmod::detail;
    const int widths[] = { 8, 15, 16, 17, 31, 32, 33, 47, 50, 65, 97 };
    const std::vector<Ptr<linemod::Modality> > ms = colourModalities();
    const bool was_optimized = useOptimized();
    std::vector<Mat> out[2];
    for (int pass = 0; pass < 2; ++pass)
    {
        setUseOptimized(pass == 0);
        if (pass == 1)
        {
            EXPECT_STREQ("baseline", kernelsPath());
        }
        for (size_t w = 0; w < sizeof(widths) / sizeof(widths[0]); ++w)
        {
            const Size size(widths[w], 37 + (int)w);
            const Mat img = randomScene(size, 300 + w);
            const Mat mask = someMask(size, 400 + w);
            std::ostringstream what;
            what << "pass " << pass << " size " << size;
            for (size_t i = 0; i < ms.size(); ++i)
            {
                expectSameLevels(ms[i], img, mask, 2, what.str(), 0);
                std::vector<Mat> fast;
                ASSERT_TRUE(fastQuantize(ms[i], img, Mat(), 2, fast));
                out[pass].insert(out[pass].end(), fast.begin(), fast.end());
            }
            const std::vector<Mat> q = referenceLevels(ms[0], img, Mat(), 1);
            Mat spread, spread_ref, planes, planes_ref;
            std::vector<Mat> resp, resp_ref;
            spreadLabelsFast(q[0], spread, 4, 0);
            spreadLabelsReference(q[0], spread_ref, 4, 0);
            EXPECT_EQ(0, differences(spread_ref, spread)) << what.str();
            computeResponseMapsFast(spread, resp);
            computeResponseMapsReference(spread, resp_ref);
            ASSERT_EQ(8u, resp.size());
            for (int o = 0; o < 8; ++o)
            {
                EXPECT_EQ(0, differences(resp_ref[o], resp[o])) << what.str() << " o " << o;
            }
            dominantLabelsFast(q[0], 5, planes);
            dominantLabelsReference(q[0], 5, planes_ref);
            EXPECT_EQ(0, differences(planes_ref, planes)) << what.str();
            EXPECT_GT(countNonZero(planes_ref), 0) << what.str();
            out[pass].push_back(spread);
            out[pass].push_back(planes);
        }
    }
    setUseOptimized(was_optimized);
    ASSERT_EQ(out[0].size(), out[1].size());
    for (size_t k = 0; k < out[0].size(); ++k)
        EXPECT_EQ(0, differences(out[0][k], out[1][k])) << "image " << k;
    std::cout << "quantize kernels: " << kernelsPath() << std::endl;
}

// The hue kernel computes OpenCV's 8-bit HSV itself (hueBinsRow): equal to quantizeHue
// (cv::cvtColor + hueBin) on every one of the 2^24 colours, for several thresholds, rows of
// every width class (the last vector overlapping, the scalar path), both instruction sets.
TEST(Forestmod_QuantizeFast, hue_bins_equal_cvtColor_on_every_colour)
{
    using namespace cv::forestmod::detail;
    Mat all(4096, 4096, CV_8UC3);
    for (int y = 0; y < all.rows; ++y)
    {
        Vec3b* p = all.ptr<Vec3b>(y);
        for (int x = 0; x < all.cols; ++x)
        {
            const int i = y * all.cols + x;
            p[x] = Vec3b((uchar)(i & 255), (uchar)((i >> 8) & 255), (uchar)(i >> 16));
        }
    }
    const Mat mask = someMask(Size(all.cols, 64), 17).row(32).clone();
    const int thresholds[][2] = { { 50, 40 }, { 0, 0 }, { 1, 255 }, { 255, 1 }, { 128, 200 } };
    const int widths[] = { 4096, 31, 33, 7 }; // rows cut into pieces of these widths
    const bool was_optimized = useOptimized();
    for (int pass = 0; pass < 2; ++pass)
    {
        setUseOptimized(pass == 0);
        for (size_t t = 0; t < sizeof(thresholds) / sizeof(thresholds[0]); ++t)
        {
            const int smin = thresholds[t][0], vmin = thresholds[t][1];
            Mat ref, fast(all.size(), CV_8U, Scalar(77));
            quantizeHue(all, ref, smin, vmin);
            EXPECT_GT(countNonZero(ref), 0);
            const int w = widths[t % (sizeof(widths) / sizeof(widths[0]))];
            for (int y = 0; y < all.rows; ++y)
                for (int x = 0; x < all.cols; x += w)
                    hueBinsRow(all.ptr<uchar>(y) + 3 * x, 0, std::min(w, all.cols - x), smin,
                               vmin, fast.ptr<uchar>(y) + x);
            EXPECT_EQ(0, differences(ref, fast))
                << "pass " << pass << " thresholds " << smin << " " << vmin << " width " << w;
            // masked: zero where the mask is
            Mat row;
            hueBinsRow(all.ptr<uchar>(100), mask.ptr<uchar>(), all.cols, smin, vmin,
                       fast.ptr<uchar>(100));
            ref.row(100).copyTo(row);
            row.setTo(Scalar(0), mask == 0);
            EXPECT_EQ(0, differences(row, fast.row(100))) << "masked, pass " << pass;
        }
    }
    setUseOptimized(was_optimized);
}

// DepthNormal's 5x5 median of one-hot labels (medianOneHotRow): equal to cv::medianBlur
// (BORDER_REPLICATE) on images of 0 and single bits, regions of one label with noise, every width
// class (scalar path, one vector, overlapping last vector), both instruction sets.
TEST(Forestmod_QuantizeFast, median_of_one_hot_labels_equals_medianBlur)
{
    using namespace cv::forestmod::detail;
    const Size sizes[] = { Size(1, 1), Size(3, 7), Size(5, 2), Size(15, 9), Size(16, 16),
                           Size(17, 5), Size(32, 11), Size(33, 33), Size(64, 3), Size(97, 41),
                           Size(640, 48) };
    const bool was_optimized = useOptimized();
    for (int pass = 0; pass < 2; ++pass)
    {
        setUseOptimized(pass == 0);
        for (size_t i = 0; i < sizeof(sizes) / sizeof(sizes[0]); ++i)
        {
            const Size size = sizes[i];
            RNG rng(900 + i);
            // blobs of one label, then noise of any label (0 .. 128 one-hot) on a share of pixels
            Mat img(size, CV_8U);
            for (int y = 0; y < size.height; ++y)
                for (int x = 0; x < size.width; ++x)
                {
                    const int blob = ((x / 6) * 7 + (y / 5) * 3) % 9;
                    const int j = rng.uniform(0, 4) == 0 ? rng.uniform(0, 9) : blob;
                    img.at<uchar>(y, x) = (uchar)(j == 8 ? 0 : 1 << j);
                }
            Mat ref, fast(size, CV_8U, Scalar(3));
            medianBlur(img, ref, 5);
            std::vector<uchar> planes(3 * (size.width + 4));
            for (int y = 0; y < size.height; ++y)
            {
                const uchar* around[5];
                for (int k = 0; k < 5; ++k)
                    around[k] = img.ptr<uchar>(std::min(std::max(y - 2 + k, 0), size.height - 1));
                medianOneHotRow(around, size.width, &planes[0], fast.ptr<uchar>(y));
            }
            EXPECT_EQ(0, differences(ref, fast)) << "pass " << pass << " size " << size;
        }
    }
    setUseOptimized(was_optimized);
}

TEST(Forestmod_QuantizeFast, roi_and_threads)
{
    // a ROI of a larger image: OpenCV's filters then read the pixels around it
    const Mat big = randomScene(Size(420, 300), 5);
    const Mat roi = big(Rect(37, 21, 301, 203));
    ASSERT_TRUE(roi.isSubmatrix());
    const std::vector<Ptr<linemod::Modality> > ms = colourModalities();
    const int threads = getNumThreads();
    for (int t = 1; t <= 4; t *= 2)
    {
        setNumThreads(t);
        for (size_t i = 0; i < ms.size(); ++i)
        {
            expectSameLevels(ms[i], roi, Mat(), 3, "roi, threads " + std::to_string(t));
            expectSameLevels(ms[i], big, someMask(big.size(), 3), 2,
                             "masked, threads " + std::to_string(t));
        }
    }
    setNumThreads(threads);
}

TEST(Forestmod_QuantizeFast, all_modalities_shared_pyramids)
{
    using namespace cv::forestmod::detail;
    const std::vector<std::string> files = shippedFrames();
    ASSERT_FALSE(files.empty());
    const Mat img = imread(files[0], IMREAD_COLOR);
    ASSERT_FALSE(img.empty());
    // a depth image for DepthNormal (no fast path: its virtual calls)
    Mat depth(img.size(), CV_16U);
    for (int r = 0; r < depth.rows; ++r)
        for (int c = 0; c < depth.cols; ++c)
            depth.at<ushort>(r, c) = (ushort)(800 + r + (c / 40 % 2) * 30);
    std::vector<Ptr<linemod::Modality> > ms = colourModalities();
    ms.push_back(linemod::Modality::create("DepthNormal"));
    std::vector<Mat> sources(ms.size(), img), masks(ms.size());
    sources.back() = depth;
    const Mat mask = someMask(img.size(), 11);
    for (size_t i = 0; i < ms.size(); i += 2)
        masks[i] = mask;
    for (int pass = 0; pass < 2; ++pass)
    {
        std::vector<ModalityInfo> infos;
        if (pass == 1)
            for (size_t i = 0; i < ms.size(); ++i)
                infos.push_back(classifyModality(ms[i]));
        std::vector<std::vector<Mat> > q;
        quantizeAllLevels(ms, infos, sources, masks, 3, q);
        ASSERT_EQ(3u, q.size());
        for (size_t i = 0; i < ms.size(); ++i)
        {
            const std::vector<Mat> ref = referenceLevels(ms[i], sources[i], masks[i], 3);
            for (int l = 0; l < 3; ++l)
            {
                ASSERT_EQ(ms.size(), q[l].size());
                EXPECT_EQ(0, differences(ref[l], q[l][i]))
                    << ms[i]->name() << " #" << i << " level " << l;
                EXPECT_GT(countNonZero(q[l][i]), 20) << ms[i]->name() << " #" << i << " level "
                                                     << l;
            }
        }
    }
}

// quantizeLevelRect on a grid of tiles (the scene pyramid's 64 x 32 and odd ones), random
// rectangles and slivers at the edges: equal there to the whole level, nothing else written.
static void expectRectsEqualLevel(const Ptr<linemod::Modality>& m, const Mat& img, const Mat& mask,
                                  const std::string& what, RNG& rng)
{
    using namespace cv::forestmod::detail;
    const ModalityInfo info = classifyModality(m);
    ASSERT_TRUE(hasRectPath(info)) << m->name();
    std::vector<Mat> whole;
    ASSERT_TRUE(fastQuantize(info, img, mask, 1, whole));
    const Mat& ref = whole[0];
    const Size size = img.size();
    for (const Size& tile : { Size(64, 32), Size(37, 11) })
    {
        Mat part(size, CV_8U, Scalar::all(77)); // 77: never a label set (one bit or 0)
        for (int y = 0; y < size.height; y += tile.height)
            for (int x = 0; x < size.width; x += tile.width)
                quantizeLevelRect(info, img, mask, Rect(Point(x, y), tile), part);
        ASSERT_EQ(0, cvtest::norm(ref, part, NORM_INF)) << what << " " << m->name() << " tiles "
                                                       << tile;
    }
    std::vector<Rect> rects;
    for (int k = 0; k < 12; ++k)
    {
        const int x = rng.uniform(0, size.width), y = rng.uniform(0, size.height);
        rects.push_back(Rect(x, y, rng.uniform(1, size.width - x + 1),
                             rng.uniform(1, size.height - y + 1)));
    }
    rects.push_back(Rect(size.width - 3, size.height - 1, 3, 1)); // a sliver in the corner
    rects.push_back(Rect(0, 0, 1, 2));
    for (const Rect& r : rects)
    {
        Mat part(size, CV_8U, Scalar::all(77));
        quantizeLevelRect(info, img, mask, r, part);
        ASSERT_EQ(0, cvtest::norm(ref(r), part(r), NORM_INF)) << what << " " << m->name() << " "
                                                              << r;
        Mat outside = part.clone();
        outside(r).setTo(Scalar::all(77));
        ASSERT_EQ(size.area(), countNonZero(outside == 77)) << what << " " << r;
    }
}

TEST(Forestmod_QuantizeFast, rectangles_equal_the_whole_level)
{
    using cv::forestmod::detail::fastQuantize;
    RNG rng(31);
    const std::vector<Ptr<linemod::Modality> > ms = colourModalities();
    std::vector<std::pair<Mat, std::string> > images;
    const std::vector<std::string> files = shippedFrames();
    ASSERT_FALSE(files.empty());
    const Mat frame = imread(files[0], IMREAD_COLOR);
    ASSERT_FALSE(frame.empty()) << files[0];
    images.push_back(std::make_pair(frame, files[0]));
    const Size sizes[] = { Size(161, 97), Size(333, 211), Size(40, 23), Size(17, 9) };
    for (size_t s = 0; s < sizeof(sizes) / sizeof(sizes[0]); ++s)
        images.push_back(std::make_pair(randomScene(sizes[s], 300 + s), "random"));
    for (size_t k = 0; k < images.size(); ++k)
    {
        const Mat& img = images[k].first;
        int labelled = 0;
        for (size_t i = 0; i < ms.size(); ++i)
        {
            expectRectsEqualLevel(ms[i], img, Mat(), images[k].second, rng);
            expectRectsEqualLevel(ms[i], img, someMask(img.size(), 9), images[k].second
                                  + " masked", rng);
            std::vector<Mat> q;
            ASSERT_TRUE(fastQuantize(ms[i], img, Mat(), 1, q));
            labelled += countNonZero(q[0]);
        }
        EXPECT_GT(labelled, img.size().area() / 20) << images[k].second; // not all empty
    }
}

static std::vector<Ptr<linemod::Modality> > depthModalities()
{
    std::vector<Ptr<linemod::Modality> > ms;
    ms.push_back(linemod::Modality::create("DepthNormal"));
    ms.push_back(makePtr<linemod::DepthNormal>(1200, 20, 63, 2));
    ms.push_back(makePtr<linemod::DepthNormal>(5000, 240, 63, 2));
    return ms;
}

// A depth image (mm) with planes, spheres, steps, noise and holes.
static Mat randomDepth(Size size, uint64 seed)
{
    RNG rng(seed);
    Mat depth(size, CV_32F);
    const double a = rng.uniform(-3., 3.), b = rng.uniform(-3., 3.);
    for (int r = 0; r < size.height; ++r)
        for (int c = 0; c < size.width; ++c)
            depth.at<float>(r, c) = (float)(900 + a * c + b * r);
    for (int i = 0; i < 6; ++i)
    {
        const Point2d centre(rng.uniform(0, size.width), rng.uniform(0, size.height));
        const double radius = rng.uniform(5., std::max(6., size.width / 3.));
        const double z = rng.uniform(500., 1500.);
        for (int r = 0; r < size.height; ++r)
            for (int c = 0; c < size.width; ++c)
            {
                const double dx = c - centre.x, dy = r - centre.y;
                const double q = radius * radius - dx * dx - dy * dy;
                if (q > 0)
                    depth.at<float>(r, c) = std::min(depth.at<float>(r, c),
                                                     (float)(z - 3 * std::sqrt(q)));
            }
    }
    Mat noise(size, CV_32F);
    rng.fill(noise, RNG::NORMAL, 0, 2);
    depth += noise;
    Mat out;
    depth.convertTo(out, CV_16U);
    Mat holes(size, CV_8U);
    rng.fill(holes, RNG::UNIFORM, 0, 50);
    out.setTo(0, holes == 0);
    circle(out, Point(size.width / 2, size.height / 3), std::max(2, size.width / 12), Scalar(0),
           FILLED);
    return out;
}

TEST(Forestmod_QuantizeFast, depth_normals_random_odd_sizes)
{
    const Size sizes[] = { Size(161, 97), Size(333, 211), Size(40, 23), Size(17, 9), Size(11, 12),
                           Size(3, 3), Size(641, 479) };
    const std::vector<Ptr<linemod::Modality> > ms = depthModalities();
    for (size_t s = 0; s < sizeof(sizes) / sizeof(sizes[0]); ++s)
    {
        const Mat depth = randomDepth(sizes[s], 300 + s);
        const Mat mask = someMask(sizes[s], 400 + s);
        const int min_labelled = sizes[s].area() > 1000 ? 50 : 0;
        for (size_t i = 0; i < ms.size(); ++i)
        {
            std::ostringstream what;
            what << "random depth " << sizes[s] << " #" << i;
            // (cv::linemod refuses to reduce an image to 0 pixels)
            const int max_levels = std::min(sizes[s].width, sizes[s].height) >= 8 ? 4 : 2;
            for (int levels = 1; levels <= max_levels; levels += max_levels - 1)
            {
                expectSameLevels(ms[i], depth, Mat(), levels, what.str(), min_labelled);
                expectSameLevels(ms[i], depth, mask, levels, what.str() + " masked", 0);
            }
        }
    }
}

// The normals' row kernel in its AVX2 build (when the CPU has it) and the baseline one: both equal
// cv::linemod's DepthNormal, and each other, on rows whose vectorised part is around the vector
// sizes (8 and 16 pixels; the kernel leaves the last pixels of a row to the scalar code).
TEST(Forestmod_QuantizeFast, depth_normals_instruction_sets)
{
    using namespace cv::forestmod::detail;
    const int widths[] = { 19, 26, 27, 28, 43, 44, 60, 100, 333 };
    const std::vector<Ptr<linemod::Modality> > ms = depthModalities();
    const bool was_optimized = useOptimized();
    std::vector<Mat> out[2];
    for (int pass = 0; pass < 2; ++pass)
    {
        setUseOptimized(pass == 0);
        for (size_t w = 0; w < sizeof(widths) / sizeof(widths[0]); ++w)
        {
            const Size size(widths[w], 41 + (int)w);
            const Mat depth = randomDepth(size, 500 + w);
            for (size_t i = 0; i < ms.size(); ++i)
            {
                std::ostringstream what;
                what << "pass " << pass << " depth " << size << " #" << i;
                expectSameLevels(ms[i], depth, Mat(), 2, what.str(), 0);
                std::vector<Mat> fast;
                ASSERT_TRUE(fastQuantize(ms[i], depth, Mat(), 2, fast)) << what.str();
                EXPECT_GT(countNonZero(fast[0]), 0) << what.str();
                out[pass].insert(out[pass].end(), fast.begin(), fast.end());
            }
        }
    }
    setUseOptimized(was_optimized);
    ASSERT_EQ(out[0].size(), out[1].size());
    for (size_t k = 0; k < out[0].size(); ++k)
        EXPECT_EQ(0, differences(out[0][k], out[1][k])) << "image " << k;
}

TEST(Forestmod_QuantizeFast, depth_normals_real_frames)
{
    const std::string shared = sharedDataPath();
    if (shared.empty() || !utils::fs::exists(shared + "/real_rgbd"))
        throw SkipTestException("FORESTMOD_SHARED_DATA/real_rgbd is not available");
    std::vector<String> files;
    glob(shared + "/real_rgbd/*_depth.png", files);
    if (files.empty())
        throw SkipTestException("no *_depth.png in FORESTMOD_SHARED_DATA/real_rgbd");
    const std::vector<Ptr<linemod::Modality> > ms = depthModalities();
    for (size_t f = 0; f < files.size(); ++f)
    {
        const Mat depth = imread(files[f], IMREAD_UNCHANGED);
        ASSERT_EQ(CV_16UC1, depth.type()) << files[f];
        for (size_t i = 0; i < ms.size(); ++i)
        {
            expectSameLevels(ms[i], depth, Mat(), 2, files[f], 1000);
            expectSameLevels(ms[i], depth, Mat(), 5, files[f], 1000);
            expectSameLevels(ms[i], depth, someMask(depth.size(), 9), 3, files[f] + " masked");
        }
        // a ROI: its own rows, as in a copy of it (cv::linemod reads a ROI's depth as if it were
        // continuous, from other rows of the wider image)
        const Mat roi = depth(Rect(13, 7, 401, 333));
        ASSERT_FALSE(roi.isContinuous());
        expectSameLevels(ms[0], roi.clone(), Mat(), 3, files[f] + " roi copy", 1000);
        std::vector<Mat> of_roi, of_copy;
        ASSERT_TRUE(cv::forestmod::detail::fastQuantize(ms[0], roi, Mat(), 3, of_roi));
        ASSERT_TRUE(cv::forestmod::detail::fastQuantize(ms[0], roi.clone(), Mat(), 3, of_copy));
        for (int l = 0; l < 3; ++l)
            EXPECT_EQ(0, differences(of_roi[l], of_copy[l])) << files[f] << " roi, level " << l;
    }
}

TEST(Forestmod_QuantizeFast, depth_normals_without_fast_path)
{
    using namespace cv::forestmod::detail;
    // a difference threshold beyond what the 32-bit arithmetic holds: the virtual calls
    Ptr<linemod::Modality> wide = makePtr<linemod::DepthNormal>(2000, 241, 63, 2);
    EXPECT_FALSE(hasFastPath(classifyModality(wide)));
    EXPECT_TRUE(hasFastPath(classifyModality(makePtr<linemod::DepthNormal>(2000, 240, 63, 2))));
    std::vector<Mat> q;
    EXPECT_FALSE(fastQuantize(wide, randomDepth(Size(64, 48), 1), Mat(), 2, q));
    // a depth of another type is cv::linemod's business
    Ptr<linemod::Modality> dn = linemod::Modality::create("DepthNormal");
    Mat depth_f;
    randomDepth(Size(64, 48), 2).convertTo(depth_f, CV_32F);
    EXPECT_FALSE(fastQuantize(dn, depth_f, Mat(), 2, q));
    // and quantizeAllLevels takes the virtual calls for both
    std::vector<Ptr<linemod::Modality> > ms(1, wide);
    std::vector<Mat> sources(1, randomDepth(Size(64, 48), 3));
    std::vector<std::vector<Mat> > all;
    quantizeAllLevels(ms, std::vector<ModalityInfo>(), sources, std::vector<Mat>(), 2, all);
    const std::vector<Mat> ref = referenceLevels(wide, sources[0], Mat(), 2);
    EXPECT_EQ(0, differences(ref[0], all[0][0]));
    EXPECT_EQ(0, differences(ref[1], all[1][0]));
}

TEST(Forestmod_QuantizeFast, frames_in_a_row_and_threads)
{
    using namespace cv::forestmod::detail;
    // one output vector for frames of different content and size (its Mats are written in
    // place when they fit), at 1, 2 and 4 threads
    std::vector<Ptr<linemod::Modality> > ms = colourModalities();
    ms.push_back(linemod::Modality::create("DepthNormal"));
    std::vector<ModalityInfo> infos;
    for (size_t i = 0; i < ms.size(); ++i)
        infos.push_back(classifyModality(ms[i]));
    const Size sizes[] = { Size(320, 240), Size(320, 240), Size(161, 97), Size(320, 240) };
    std::vector<std::vector<Mat> > q;
    const int threads = getNumThreads();
    for (int t = 1; t <= 4; t *= 2)
    {
        setNumThreads(t);
        for (int f = 0; f < 4; ++f)
        {
            std::vector<Mat> sources(ms.size(), randomScene(sizes[f], 50 + f + 10 * t));
            sources.back() = randomDepth(sizes[f], 60 + f + 10 * t);
            quantizeAllLevels(ms, infos, sources, std::vector<Mat>(), 2, q);
            for (size_t i = 0; i < ms.size(); ++i)
            {
                const std::vector<Mat> ref = referenceLevels(ms[i], sources[i], Mat(), 2);
                for (int l = 0; l < 2; ++l)
                {
                    EXPECT_EQ(0, differences(ref[l], q[l][i]))
                        << "threads " << t << " frame " << f << " modality " << i << " level "
                        << l;
                }
                EXPECT_GT(countNonZero(q[0][i]), 100) << "frame " << f << " modality " << i;
            }
        }
    }
    setNumThreads(threads);
}

TEST(Forestmod_QuantizeFast, wrong_inputs_are_refused)
{
    std::vector<Mat> q;
    Ptr<linemod::Modality> g = linemod::Modality::create("ColorGradient");
    EXPECT_THROW(cv::forestmod::detail::fastQuantize(g, Mat(), Mat(), 2, q), cv::Exception);
    EXPECT_THROW(cv::forestmod::detail::fastQuantize(g, Mat(20, 20, CV_8UC1), Mat(), 2, q),
                 cv::Exception);
    EXPECT_THROW(cv::forestmod::detail::fastQuantize(g, Mat(20, 20, CV_8UC3), Mat(10, 20, CV_8U),
                                                     2, q),
                 cv::Exception);
}

static std::vector<Mat> quantizedTestImages()
{
    std::vector<Mat> out;
    Ptr<linemod::Modality> g = linemod::Modality::create("ColorGradient");
    const std::vector<std::string> files = shippedFrames();
    if (!files.empty())
    {
        const Mat img = imread(files[0], IMREAD_COLOR);
        std::vector<Mat> q = referenceLevels(g, img, Mat(), 2);
        out.insert(out.end(), q.begin(), q.end());
    }
    const Size sizes[] = { Size(161, 97), Size(333, 211), Size(5, 3), Size(1, 1) };
    for (size_t s = 0; s < sizeof(sizes) / sizeof(sizes[0]); ++s)
    {
        // any byte, not only single bits: the maps are defined for every value
        Mat q(sizes[s], CV_8U);
        theRNG().fill(q, RNG::UNIFORM, 0, 256);
        q.setTo(0, q < 128);
        out.push_back(q);
    }
    return out;
}

TEST(Forestmod_QuantizeFast, spread_equals_reference)
{
    using namespace cv::forestmod::detail;
    const std::vector<Mat> images = quantizedTestImages();
    ASSERT_GE(images.size(), 5u);
    const int Ts[] = { 1, 2, 3, 4, 5, 8, 11 };
    const int pads[] = { 0, 7, 40 };
    for (size_t i = 0; i < images.size(); ++i)
        for (int T : Ts)
            for (int pad : pads)
            {
                Mat ref, fast;
                spreadLabelsReference(images[i], ref, T, pad);
                spreadLabelsFast(images[i], fast, T, pad);
                ASSERT_EQ(ref.size(), fast.size());
                EXPECT_EQ(0, differences(ref, fast)) << "image " << i << " T " << T << " pad "
                                                     << pad;
                if (images[i].total() > 100 && T > 1)
                {
                    EXPECT_GT(countNonZero(fast), countNonZero(images[i]));
                }
            }
}

TEST(Forestmod_QuantizeFast, response_maps_equal_reference)
{
    using namespace cv::forestmod::detail;
    std::vector<Mat> images = quantizedTestImages();
    // every byte value, at every position of a SIMD vector and in the tail
    Mat all(3, 256 + 7, CV_8U);
    for (int r = 0; r < all.rows; ++r)
        for (int c = 0; c < all.cols; ++c)
            all.at<uchar>(r, c) = (uchar)(c + r * 3);
    images.push_back(all);
    for (size_t i = 0; i < images.size(); ++i)
    {
        Mat spread;
        spreadLabelsReference(images[i], spread, 5, 9);
        for (int pass = 0; pass < 2; ++pass)
        {
            const Mat& src = pass == 0 ? spread : images[i];
            std::vector<Mat> ref, fast;
            computeResponseMapsReference(src, ref);
            computeResponseMapsFast(src, fast);
            ASSERT_EQ(8u, fast.size());
            for (int o = 0; o < 8; ++o)
            {
                EXPECT_EQ(0, differences(ref[o], fast[o])) << "image " << i << " orientation "
                                                           << o;
                double vmax = 0;
                minMaxLoc(fast[o], 0, &vmax);
                if (src.total() > 100)
                {
                    EXPECT_EQ(4, vmax) << "image " << i << " orientation " << o;
                }
            }
        }
    }
}

TEST(Forestmod_QuantizeFast, dominant_labels_equal_reference)
{
    using namespace cv::forestmod::detail;
    std::vector<Mat> images = quantizedTestImages(); // any bytes: several bits per pixel
    for (size_t i = 0; i < images.size(); i += 2) // and one-hot labels
    {
        Mat onehot(images[i].size(), CV_8U);
        for (int r = 0; r < onehot.rows; ++r)
            for (int c = 0; c < onehot.cols; ++c)
            {
                const uchar v = images[i].at<uchar>(r, c);
                onehot.at<uchar>(r, c) = v ? (uchar)(1 << (v & 7)) : 0;
            }
        images.push_back(onehot);
    }
    for (size_t i = 0; i < images.size(); ++i)
        for (int k = 1; k <= 9; ++k)
        {
            Mat ref, fast;
            dominantLabelsReference(images[i], k, ref);
            dominantLabelsFast(images[i], k, fast);
            EXPECT_EQ(0, differences(ref, fast)) << "image " << i << " k " << k;
            // in place, into a ROI of a bordered plane
            Mat plane = Mat::zeros(images[i].rows + 6, images[i].cols + 6, CV_8U);
            Mat inner = plane(Rect(3, 3, images[i].cols, images[i].rows));
            dominantLabelsFast(images[i], k, inner);
            EXPECT_EQ(0, differences(ref, inner)) << "image " << i << " k " << k;
            EXPECT_EQ(countNonZero(ref), countNonZero(plane));
        }
}

TEST(Forestmod_QuantizeFast, tiles_equal_full_frame_maps)
{
    using namespace cv::forestmod::detail;
    const std::vector<Mat> images = quantizedTestImages();
    ASSERT_GE(images.size(), 5u);
    RNG rng(11);
    const int Ts[] = { 1, 2, 5, 8, 11 };
    for (size_t i = 0; i < images.size(); ++i)
        for (int T : Ts)
        {
            const Mat& q = images[i];
            Mat spread_full;
            spreadLabelsFast(q, spread_full, T, 0);
            // unset pixels keep a value no spread image has with these labels
            Mat spread(q.size(), CV_8U, Scalar(0xEE)), done = Mat::zeros(q.size(), CV_8U);
            for (int k = 0; k < 6; ++k)
            {
                // tiles of any size, some over the right or bottom border or outside
                const Rect tile(rng.uniform(-8, q.cols + 4), rng.uniform(-8, q.rows + 4),
                                rng.uniform(1, 80), rng.uniform(1, 40));
                spreadTile(q, T, tile, spread);
                done(tile & Rect(0, 0, q.cols, q.rows)).setTo(1);
            }
            const Mat outside = done == 0;
            ASSERT_GT(countNonZero(done), 0);
            Mat expect = spread_full.clone();
            expect.setTo(0xEE, outside);
            EXPECT_EQ(0, differences(expect, spread)) << "image " << i << " T " << T;
        }
}

// The response of a label to a spread byte, as the readers of the spread images compute it
// (responseOf, the vectorised spreadResponses), against LINEMOD's response maps as similarity.cpp
// computes them (computeResponseMapsReference), for every byte and label.
TEST(Forestmod_QuantizeFast, responses_of_spread_bytes_equal_linemod_response_maps)
{
    using namespace cv::forestmod::detail;
    Mat bytes(1, 256 + 13, CV_8U); // a tail that the vector loop leaves to the scalar one
    for (int x = 0; x < bytes.cols; ++x)
        bytes.at<uchar>(0, x) = (uchar)(x * 7 + 3);
    std::vector<Mat> ref;
    computeResponseMapsReference(bytes, ref);
    ASSERT_EQ(8u, ref.size());
    std::vector<Mat> fast(8);
    uchar* d[8];
    for (int o = 0; o < 8; ++o)
    {
        fast[o].create(bytes.size(), CV_8U);
        d[o] = fast[o].ptr<uchar>();
    }
    spreadResponses(bytes.ptr<uchar>(), bytes.cols, d);
    int fours = 0;
    for (int o = 0; o < 8; ++o)
        for (int x = 0; x < bytes.cols; ++x)
        {
            const int r = ref[o].at<uchar>(0, x);
            ASSERT_EQ(r, (int)responseOf(o, bytes.at<uchar>(0, x))) << "label " << o << ", " << x;
            ASSERT_EQ(r, (int)fast[o].at<uchar>(0, x)) << "label " << o << " x " << x;
            fours += r == 4;
        }
    EXPECT_GT(fours, 8 * 100); // half the bytes hold a given label
    EXPECT_EQ(0, (int)responseOf(3, 0));
}

// Refinement reads the finer levels only where refinementRegions() says: coarse matches of
// real templates at random positions (borders included), refined on tiles computed on demand and
// on maps computed everywhere, threshold 0 (no match dropped, also those whose best position is
// "none") and 60: the same matches, the same spread and quantized images where computed. 2 pyramid
// levels (few matches: part of level 0 computed; more: level 0 whole) and
// 3 (the regions of level 0 hold every position level 1 may choose).
static void expectRefinementOnTiles(const std::vector<int>& T, int num_matches, bool partial,
                                    int whole_level0 = -1)
{
    using namespace cv::forestmod::detail;
    std::vector<Ptr<linemod::Modality> > mods;
    mods.push_back(linemod::Modality::create("ColorGradient"));
    mods.push_back(ColorHue::create());
    const int L = (int)T.size() - 1;
    cv::linemod::Detector templ_src(mods, T);
    const Mat train = imread(cvtest::findDataFile("lmo_mini/test/000002/rgb/000224.png"),
                             IMREAD_COLOR);
    const Mat frame = imread(cvtest::findDataFile("lmo_mini/test/000002/rgb/000902.png"),
                             IMREAD_COLOR);
    ASSERT_FALSE(train.empty());
    ASSERT_FALSE(frame.empty());
    RNG rng(5);
    ClassPyramids pyramids;
    std::vector<Mat> train_src(2, train);
    for (int k = 0; k < 12; ++k)
    {
        Mat mask = Mat::zeros(train.size(), CV_8U);
        const Size s(rng.uniform(30, 100), rng.uniform(30, 100));
        ellipse(mask, Point(rng.uniform(120, 520), rng.uniform(120, 360)), s, 0, 0, 360,
                Scalar(255), FILLED);
        const int id = templ_src.addTemplate(train_src, "obj", mask);
        if (id >= 0)
            pyramids["obj"].push_back(templ_src.getTemplates("obj", id));
    }
    ASSERT_GE(pyramids["obj"].size(), 8u);

    const ModalityRoles roles = ModalityRoles::of(mods);
    const std::vector<Mat> sources(2, frame);
    ScenePyramid on_demand, full;
    quantizeScene(mods, roles, T, sources, std::vector<Mat>(), on_demand, noArray());
    // asking for the quantized images: every level quantized whole, nothing deferred
    std::vector<Mat> whole;
    quantizeScene(mods, roles, T, sources, std::vector<Mat>(), full, whole);
    ASSERT_TRUE(full.deferred[0][0].image.empty());
    ASSERT_FALSE(on_demand.deferred[0][0].image.empty());
    std::vector<std::vector<Rect> > everything(L);
    for (int l = 0; l < L; ++l)
        everything[l].push_back(Rect(Point(0, 0), full.levels[l].size));
    prepareRefinementLevels(full, everything);

    const Size top = on_demand.coarsest().size;
    std::vector<linemod::Match> coarse;
    for (int k = 0; k < num_matches; ++k)
    {
        const int id = rng.uniform(0, (int)pyramids["obj"].size());
        // a third on the left or right border, the rest anywhere
        int x = rng.uniform(-10, top.width + 10), y = rng.uniform(-10, top.height + 10);
        if (k % 3 == 0)
            x = k % 2 ? rng.uniform(-4, 8) : top.width - rng.uniform(-4, 8);
        coarse.push_back(linemod::Match(x, y, 90.f, "obj", id));
    }
    // the store's records hold the features' extents that refinementRegions reads
    TemplateStore store;
    const std::vector<TemplatePyramid> tps = pyramids["obj"];
    store.setClass(pyramids, "obj", tps, std::vector<TemplateRecord>(tps.size()));
    std::vector<std::vector<Rect> > regions;
    refinementRegions(on_demand, pyramids, store, coarse, regions);
    ASSERT_EQ((size_t)L, regions.size());
    ASSERT_EQ(coarse.size(), regions[0].size());
    prepareRefinementLevels(on_demand, regions);
    Mat maps0;
    bitwise_and(on_demand.tiles[0], Scalar(ScenePyramid::TILE_MAPS), maps0);
    const int tiles0 = countNonZero(maps0);
    EXPECT_GT(tiles0, 0);
    if (partial)
    {
        EXPECT_LT(tiles0, (int)on_demand.tiles[0].total());
    }
    // level 0 quantized whole (many tiles) or in tiles (few)
    if (whole_level0 >= 0)
    {
        EXPECT_EQ(whole_level0 != 0, on_demand.deferred[0][0].image.empty());
    }
    // the deferred quantized images of the finer levels equal the whole ones in their tiles
    for (int l = 0; l < L; ++l)
        for (int ty = 0; ty < on_demand.tiles[l].rows; ++ty)
            for (int tx = 0; tx < on_demand.tiles[l].cols; ++tx)
            {
                if (!(on_demand.tiles[l].at<uchar>(ty, tx) & ScenePyramid::TILE_QUANTIZED))
                    continue;
                const Rect tile = Rect(tx * ScenePyramid::TILE_W, ty * ScenePyramid::TILE_H,
                                       ScenePyramid::TILE_W, ScenePyramid::TILE_H)
                                  & Rect(Point(0, 0), on_demand.levels[l].size);
                for (size_t m = 0; m < mods.size(); ++m)
                    ASSERT_EQ(0, cvtest::norm(full.levels[l].quantized[m](tile),
                                              on_demand.levels[l].quantized[m](tile), NORM_INF))
                        << "level " << l << " modality " << m << " tile " << tile;
                if (!(on_demand.tiles[l].at<uchar>(ty, tx) & ScenePyramid::TILE_MAPS))
                    continue;
                // the spread images (in tiles, or whole when the tiles cover much of the level)
                for (size_t m = 0; m < mods.size(); ++m)
                    ASSERT_EQ(0, cvtest::norm(full.levels[l].spread[m](tile),
                                              on_demand.levels[l].spread[m](tile), NORM_INF))
                        << "spread: level " << l << " modality " << m << " tile " << tile;
            }

    for (int pass = 0; pass < 2; ++pass)
    {
        const float thr = pass == 0 ? 0.f : 60.f;
        std::vector<linemod::Match> a = coarse, b = coarse;
        refineMatches(on_demand, pyramids, store, thr, a);
        refineMatches(full, pyramids, store, thr, b);
        ASSERT_EQ(b.size(), a.size()) << "threshold " << thr;
        if (pass == 0)
        {
            EXPECT_EQ(coarse.size(), a.size());
        }
        expectSameMatches(b, a, cv::format("threshold %g", thr));
    }
}

TEST(Forestmod_QuantizeFast, refinement_on_tiles_equals_full_maps)
{
    expectRefinementOnTiles(std::vector<int>{ 5, 8 }, 1, true);
    expectRefinementOnTiles(std::vector<int>{ 5, 8 }, 6, false); // most of level 0: whole
    expectRefinementOnTiles(std::vector<int>{ 5, 8 }, 200, false, 1);
    expectRefinementOnTiles(std::vector<int>{ 4, 6, 8 }, 40, false);
}

// A small region: level 0 quantized in the few tiles it needs (not whole), equal there to the
// whole level.
TEST(Forestmod_QuantizeFast, few_tiles_quantized_in_place)
{
    using namespace cv::forestmod::detail;
    std::vector<Ptr<linemod::Modality> > mods;
    mods.push_back(linemod::Modality::create("ColorGradient"));
    mods.push_back(ColorHue::create());
    const Mat frame = imread(cvtest::findDataFile("lmo_mini/test/000002/rgb/000902.png"),
                             IMREAD_COLOR);
    ASSERT_FALSE(frame.empty());
    const std::vector<Mat> sources(2, frame);
    const ModalityRoles roles = ModalityRoles::of(mods);
    const std::vector<int> T{ 5, 8 };
    ScenePyramid scene;
    quantizeScene(mods, roles, T, sources, std::vector<Mat>(), scene, noArray());
    std::vector<std::vector<Rect> > regions(1, std::vector<Rect>(1, Rect(300, 200, 20, 10)));
    prepareRefinementLevels(scene, regions);
    ASSERT_FALSE(scene.deferred[0][0].image.empty()) << "level 0 was quantized whole";
    std::vector<Mat> whole;
    for (size_t m = 0; m < mods.size(); ++m)
    {
        ASSERT_TRUE(fastQuantize(mods[m], frame, Mat(), 1, whole));
        int tiles = 0;
        for (int ty = 0; ty < scene.tiles[0].rows; ++ty)
            for (int tx = 0; tx < scene.tiles[0].cols; ++tx)
                if (scene.tiles[0].at<uchar>(ty, tx) & ScenePyramid::TILE_QUANTIZED)
                {
                    const Rect tile = Rect(tx * ScenePyramid::TILE_W, ty * ScenePyramid::TILE_H,
                                           ScenePyramid::TILE_W, ScenePyramid::TILE_H)
                                      & Rect(Point(0, 0), frame.size());
                    ASSERT_EQ(0, cvtest::norm(whole[0](tile), scene.levels[0].quantized[m](tile),
                                              NORM_INF)) << "modality " << m << " " << tile;
                    ++tiles;
                }
        EXPECT_GE(tiles, 1);
        EXPECT_LE(tiles, 4); // the region's tile and its right / lower neighbours
    }
}

// match() with the scene pyramid's fast paths and on-demand tiles gives the same matches and scan
// outcome with 1 and 4 threads, and its quantized_images are the modalities' own: the golden models (RGB and
// RGB-D ape), 1 tree and exhaustive, on a shipped frame and a golden RGB-D scene.
TEST(Forestmod_QuantizeFast, match_same_with_1_and_4_threads)
{
    const Mat lmo = imread(cvtest::findDataFile("lmo_mini/test/000002/rgb/000902.png"),
                           IMREAD_COLOR);
    const Mat rgb = imread(cvtest::findDataFile("golden/scene0_rgb.png"), IMREAD_COLOR);
    const Mat depth = imread(cvtest::findDataFile("golden/scene0_depth.png"), IMREAD_UNCHANGED);
    ASSERT_FALSE(lmo.empty());
    ASSERT_FALSE(rgb.empty());
    ASSERT_EQ(CV_16UC1, depth.type());
    const int old_threads = getNumThreads();
    size_t compared = 0;
    for (int rgbd = 0; rgbd < 2; ++rgbd)
    {
        cv::forestmod::Detector det;
        det.load(cvtest::findDataFile(rgbd ? "golden/ape_rgbd.yml.gz" : "golden/ape_rgb.yml.gz"));
        std::vector<Mat> src;
        for (const Ptr<linemod::Modality>& m : det.getModalities())
            src.push_back(m->name() == "DepthNormal" ? depth : (rgbd ? rgb : lmo));
        for (int exhaustive = 0; exhaustive < 2; ++exhaustive)
        {
            DetectorParams p = det.getParams();
            p.use_forest = !exhaustive;
            det.setParams(p);
            std::vector<linemod::Match> one, four;
            std::vector<Mat> q1, q4;
            DetectionStats s1, s4;
            setNumThreads(1);
            det.match(src, 70.f, one, std::vector<String>(), q1, std::vector<Mat>(), &s1);
            setNumThreads(4);
            det.match(src, 70.f, four, std::vector<String>(), q4, std::vector<Mat>(), &s4);
            setNumThreads(old_threads);
            ASSERT_EQ(one.size(), four.size()) << "rgbd " << rgbd << " exhaustive " << exhaustive;
            // the scan (its sample rows go as many at a time as there are threads): the same
            // outcome at every location, the same exhaustive groups
            ASSERT_EQ(s1.rejection_map.size(), s4.rejection_map.size());
            if (!exhaustive)
            {
                ASSERT_FALSE(s1.rejection_map.empty());
                EXPECT_EQ(0, differences(s1.rejection_map, s4.rejection_map));
            }
            EXPECT_EQ(s1.validated, s4.validated);
            EXPECT_EQ(s1.candidates, s4.candidates);
            EXPECT_EQ(s1.rejected, s4.rejected);
            expectSameMatches(one, four, cv::format("rgbd %d exhaustive %d", rgbd, exhaustive));
            ASSERT_EQ(q1.size(), q4.size());
            ASSERT_EQ(det.getModalities().size() * det.pyramidLevels(), q1.size());
            for (size_t k = 0; k < q1.size(); ++k)
            {
                EXPECT_EQ(0, differences(q1[k], q4[k])) << "quantized image " << k;
            }
            // match()'s quantized_images: what the modalities' own virtual calls give
            const int M = (int)src.size(), levels = det.pyramidLevels();
            for (int i = 0; i < M; ++i)
            {
                const std::vector<Mat> ref = referenceLevels(det.getModalities()[i], src[i],
                                                             Mat(), levels);
                for (int l = 0; l < levels; ++l)
                {
                    EXPECT_EQ(0, differences(ref[l], q1[l * M + i])) << "modality " << i
                                                                     << " level " << l;
                }
            }
            compared += one.size();
        }
    }
    EXPECT_GT(compared, 0u);
}

// A user's modality (here a ColorGradient subclass, which may override processImpl) goes through
// its own virtual calls inside match(), with the same matches as the fast path of the plain
// ColorGradient; the fast path reads a modality's parameters at every frame.
struct CountingGradient : public linemod::ColorGradient
{
    static int calls;

protected:
    Ptr<linemod::QuantizedPyramid> processImpl(const Mat& src, const Mat& mask) const CV_OVERRIDE
    {
        ++calls;
        return linemod::ColorGradient::processImpl(src, mask);
    }
};
int CountingGradient::calls = 0;

TEST(Forestmod_QuantizeFast, match_user_modality_and_changed_parameters)
{
    const Mat train = imread(cvtest::findDataFile("lmo_mini/test/000002/rgb/000224.png"),
                             IMREAD_COLOR);
    const Mat frame = imread(cvtest::findDataFile("lmo_mini/test/000002/rgb/000902.png"),
                             IMREAD_COLOR);
    ASSERT_FALSE(train.empty());
    ASSERT_FALSE(frame.empty());
    DetectorParams p;
    p.use_forest = false; // the exhaustive search: no training needed
    const std::vector<int> T{ 5, 8 };
    std::vector<Ptr<linemod::Modality> > plain, user;
    plain.push_back(linemod::Modality::create("ColorGradient"));
    plain.push_back(ColorHue::create());
    user.push_back(makePtr<CountingGradient>());
    user.push_back(ColorHue::create());
    cv::forestmod::Detector a(plain, T, p), b(user, T, p);
    RNG rng(9);
    for (int k = 0; k < 6; ++k)
    {
        Mat mask = Mat::zeros(train.size(), CV_8U);
        ellipse(mask, Point(rng.uniform(150, 490), rng.uniform(150, 330)),
                Size(rng.uniform(40, 90), rng.uniform(40, 90)), 0, 0, 360, Scalar(255), FILLED);
        const std::vector<Mat> src(2, train);
        EXPECT_EQ(a.addTemplate(src, "obj", mask), b.addTemplate(src, "obj", mask));
    }
    ASSERT_GT(a.numTemplates(), 0);
    const std::vector<Mat> src(2, frame);
    std::vector<linemod::Match> ma, mb;
    CountingGradient::calls = 0;
    a.match(src, 60.f, ma);
    EXPECT_EQ(0, CountingGradient::calls);
    b.match(src, 60.f, mb);
    EXPECT_EQ(1, CountingGradient::calls) << "the user's modality keeps its virtual calls";
    ASSERT_FALSE(ma.empty());
    expectSameMatches(ma, mb);

    // parameters changed after the detector was made are those of the next frame
    Ptr<linemod::ColorGradient> g = a.getModalities()[0].dynamicCast<linemod::ColorGradient>();
    ASSERT_FALSE(g.empty());
    std::vector<Mat> before, after;
    a.match(src, 60.f, ma, std::vector<String>(), before);
    g->weak_threshold = 40.f;
    a.match(src, 60.f, ma, std::vector<String>(), after);
    const std::vector<Mat> ref = referenceLevels(g, frame, Mat(), 2);
    EXPECT_EQ(0, differences(ref[0], after[0]));
    EXPECT_EQ(0, differences(ref[1], after[2]));
    EXPECT_GT(differences(before[0], after[0]), 0);
}

}} // namespace
