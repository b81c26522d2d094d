// This file is part of OpenCV project.
// It is subject to the license terms in the LICENSE file found in the top-level directory
// of this distribution and at http://opencv.org/license.html

#include "test_precomp.hpp"

namespace opencv_test { namespace {

// OpenCV's own hue of a BGR colour (the definition ColorHue quantizes).
static int hueOf(const Vec3b& bgr)
{
    Mat px(1, 1, CV_8UC3, Scalar(bgr[0], bgr[1], bgr[2])), hsv;
    cvtColor(px, hsv, COLOR_BGR2HSV);
    return hsv.at<Vec3b>(0, 0)[0];
}

static uchar quantizeOne(const Vec3b& bgr, int smin = 50, int vmin = 40)
{
    Mat px(1, 1, CV_8UC3, Scalar(bgr[0], bgr[1], bgr[2])), q;
    quantizeHue(px, q, smin, vmin);
    return q.at<uchar>(0, 0);
}

TEST(Forestmod_Hue, bin_edges_on_both_sides)
{
    // bin i covers [22.5 i - 11.25, 22.5 i + 11.25): integer hues either side of each edge
    for (int i = 0; i < 8; ++i)
    {
        const double edge = 22.5 * i + 11.25;
        const int below = (int)std::floor(edge), above = (int)std::ceil(edge) % 180;
        EXPECT_EQ(i, hueBin(below)) << "h=" << below;
        EXPECT_EQ((i + 1) % 8, hueBin(above)) << "h=" << above;
    }
    EXPECT_EQ(0, hueBin(0));
    EXPECT_EQ(2, hueBin(45));
    EXPECT_THROW(hueBin(180), cv::Exception);
    EXPECT_THROW(hueBin(-1), cv::Exception);
}

TEST(Forestmod_Hue, colours_map_to_their_bins)
{
    // Walk the fully saturated colour circle; every colour must quantize to 1 << hueBin(its hue),
    // and we must see colours on both sides of every bin edge.
    std::vector<int> seen(180, 0);
    for (int k = 0; k < 6 * 255; ++k)
    {
        int seg = k / 255, t = k % 255;
        Vec3b c; // BGR
        switch (seg)
        {
        case 0: c = Vec3b(0, (uchar)t, 255); break;         // red -> yellow
        case 1: c = Vec3b(0, 255, (uchar)(255 - t)); break; // yellow -> green
        case 2: c = Vec3b((uchar)t, 255, 0); break;         // green -> cyan
        case 3: c = Vec3b(255, (uchar)(255 - t), 0); break; // cyan -> blue
        case 4: c = Vec3b(255, 0, (uchar)t); break;         // blue -> magenta
        default: c = Vec3b((uchar)(255 - t), 0, 255); break; // magenta -> red
        }
        const int h = hueOf(c);
        seen[h] = 1;
        ASSERT_EQ(1 << hueBin(h), (int)quantizeOne(c)) << "BGR=" << c << " h=" << h;
    }
    for (int i = 0; i < 8; ++i)
    {
        const double edge = 22.5 * i + 11.25;
        EXPECT_TRUE(seen[(int)std::floor(edge)] && seen[(int)std::ceil(edge) % 180]) << i;
    }
    // named colours
    EXPECT_EQ(1 << 0, quantizeOne(Vec3b(0, 0, 255)));   // red
    EXPECT_EQ(1 << 3, quantizeOne(Vec3b(0, 255, 0)));   // green: h = 60 -> bin 3
    EXPECT_EQ(1 << 5, quantizeOne(Vec3b(255, 0, 0)));   // blue: h = 120 -> bin 5
}

TEST(Forestmod_Hue, yellow_and_cyan)
{
    EXPECT_EQ(30, hueOf(Vec3b(0, 255, 255)));
    EXPECT_EQ(1 << 1, quantizeOne(Vec3b(0, 255, 255)));
    EXPECT_EQ(90, hueOf(Vec3b(255, 255, 0)));
    EXPECT_EQ(1 << 4, quantizeOne(Vec3b(255, 255, 0)));
}

TEST(Forestmod_Hue, grey_black_white_have_no_hue)
{
    for (int g = 0; g < 256; g += 5)
        EXPECT_EQ(0, quantizeOne(Vec3b((uchar)g, (uchar)g, (uchar)g))) << g;
    EXPECT_EQ(0, quantizeOne(Vec3b(0, 0, 0)));
    EXPECT_EQ(0, quantizeOne(Vec3b(255, 255, 255)));
    // slightly tinted grey (saturation ~ 10 %) and a dark red (value below threshold)
    EXPECT_EQ(0, quantizeOne(Vec3b(200, 200, 222)));
    EXPECT_EQ(0, quantizeOne(Vec3b(0, 0, 30)));
    // the thresholds are honoured on both sides
    EXPECT_EQ(0, quantizeOne(Vec3b(0, 0, 39), 50, 40));
    EXPECT_EQ(1, quantizeOne(Vec3b(0, 0, 40), 50, 40));
}

TEST(Forestmod_Hue, red_wraps_into_one_bin)
{
    // pinkish red (h ~ 175..179) and orange-red (h ~ 1..5) are the same colour family
    const Vec3b reds[] = { Vec3b(30, 0, 255), Vec3b(10, 0, 255), Vec3b(0, 10, 255),
                           Vec3b(0, 30, 255) };
    for (const Vec3b& c : reds)
    {
        const int h = hueOf(c);
        EXPECT_TRUE(h <= 11 || h >= 169) << h;
        EXPECT_EQ(1, quantizeOne(c)) << "h=" << h;
    }
    EXPECT_EQ(0, hueBin(179));
    EXPECT_EQ(0, hueBin(169));
    EXPECT_EQ(7, hueBin(168));
}

// A picture with a red / green / blue striped square on a grey, mask on the square.
static void stripedSquare(Mat& img, Mat& mask, Rect box)
{
    img.create(240, 320, CV_8UC3);
    img.setTo(Scalar(128, 128, 128));
    mask = Mat::zeros(img.size(), CV_8U);
    const Scalar colours[] = { Scalar(0, 0, 220), Scalar(0, 200, 0), Scalar(220, 0, 0) };
    for (int i = 0; i < 3; ++i)
    {
        Rect stripe(box.x + i * box.width / 3, box.y, box.width / 3, box.height);
        rectangle(img, stripe, colours[i], FILLED);
    }
    rectangle(mask, box, Scalar(255), FILLED);
}

TEST(Forestmod_Hue, extractTemplate_features_inside_mask_scattered)
{
    Mat img, mask;
    const Rect box(100, 60, 90, 90);
    stripedSquare(img, mask, box);
    Ptr<ColorHue> hue = ColorHue::create();
    Ptr<linemod::QuantizedPyramid> qp = hue->process(img, mask);
    linemod::Template templ;
    ASSERT_TRUE(qp->extractTemplate(templ));
    const int n = hue->getParams().num_features;
    ASSERT_GT((int)templ.features.size(), n / 2);
    ASSERT_LE((int)templ.features.size(), n);
    EXPECT_EQ(0, templ.pyramid_level);
    Mat quantized;
    qp->quantize(quantized);
    double min_d2 = 1e9;
    for (size_t i = 0; i < templ.features.size(); ++i)
    {
        const linemod::Feature& f = templ.features[i];
        ASSERT_TRUE(mask.at<uchar>(f.y, f.x) != 0) << f.x << "," << f.y;
        ASSERT_EQ(1 << f.label, (int)quantized.at<uchar>(f.y, f.x));
        for (size_t j = 0; j < i; ++j)
        {
            const linemod::Feature& g = templ.features[j];
            min_d2 = std::min(min_d2, double((f.x - g.x) * (f.x - g.x) + (f.y - g.y) * (f.y - g.y)));
        }
    }
    // evenly spread n points over the area would be sqrt(area / n) apart; ask for half of it
    const double spacing = std::sqrt(double(box.area()) / n);
    EXPECT_GE(std::sqrt(min_d2), 0.5 * spacing);
    // all three colours are represented
    std::set<int> labels;
    for (const linemod::Feature& f : templ.features)
        labels.insert(f.label);
    EXPECT_EQ(3u, labels.size());

    // fewer features asked: honoured
    ColorHue::Params p;
    p.num_features = 10;
    linemod::Template small;
    ASSERT_TRUE(ColorHue::create(p)->process(img, mask)->extractTemplate(small));
    EXPECT_EQ(10u, small.features.size());

    // the next pyramid level halves coordinates
    qp->pyrDown();
    linemod::Template t1;
    ASSERT_TRUE(qp->extractTemplate(t1));
    EXPECT_EQ(1, t1.pyramid_level);
    for (const linemod::Feature& f : t1.features)
        ASSERT_TRUE(mask.at<uchar>(2 * f.y, 2 * f.x) != 0);
}

TEST(Forestmod_Hue, extractTemplate_refuses_grey_object)
{
    Mat img(120, 160, CV_8UC3, Scalar(90, 90, 90)), mask = Mat::zeros(120, 160, CV_8U);
    rectangle(mask, Rect(40, 30, 60, 50), Scalar(255), FILLED);
    linemod::Template templ;
    EXPECT_FALSE(ColorHue::create()->process(img, mask)->extractTemplate(templ));
}

// Half of the object is a strong green (saturation 255), half a pale one (saturation 51,
// labelled in a scene): the template's features come from the strong half only, unless the
// feature threshold is that of the scene.
TEST(Forestmod_Hue, extractTemplate_takes_features_from_strongly_saturated_pixels)
{
    Mat img(120, 160, CV_8UC3, Scalar(90, 90, 90)), mask = Mat::zeros(120, 160, CV_8U);
    const Rect strong(40, 30, 40, 50), pale(80, 30, 40, 50);
    img(strong).setTo(Scalar(0, 200, 0));
    img(pale).setTo(Scalar(160, 200, 160));
    mask(strong | pale).setTo(255);
    Mat hsv;
    cvtColor(Mat(1, 1, CV_8UC3, Scalar(160, 200, 160)), hsv, COLOR_BGR2HSV);
    const int pale_saturation = hsv.at<Vec3b>(0, 0)[1]; // 51
    ColorHue::Params p;
    ASSERT_GE(pale_saturation, p.saturation_threshold);      // labelled in a scene
    ASSERT_LT(pale_saturation, p.feature_saturation_threshold); // not a template feature
    linemod::Template templ;
    ASSERT_TRUE(ColorHue::create(p)->process(img, mask)->extractTemplate(templ));
    ASSERT_FALSE(templ.features.empty());
    const Rect strong_blurred(strong.x, strong.y, strong.width + 1, strong.height); // 3x3 blur
    for (const linemod::Feature& f : templ.features)
        EXPECT_TRUE(strong_blurred.contains(Point(f.x, f.y))) << f.x << "," << f.y;

    p.feature_saturation_threshold = 0; // every labelled pixel
    ASSERT_TRUE(ColorHue::create(p)->process(img, mask)->extractTemplate(templ));
    int in_pale = 0;
    for (const linemod::Feature& f : templ.features)
        in_pale += pale.contains(Point(f.x, f.y));
    EXPECT_GT(in_pale, (int)templ.features.size() / 4);

    // an object whose only colour is pale has no hue features
    Mat pale_only = img.clone();
    pale_only(strong).setTo(Scalar(160, 200, 160));
    p = ColorHue::Params();
    EXPECT_FALSE(ColorHue::create(p)->process(pale_only, mask)->extractTemplate(templ));
}

// A grey object with a small coloured spot: the spot covers less than min_feature_area of the
// eroded mask, so the template has no hue features; a larger spot, or a smaller limit, gives some.
TEST(Forestmod_Hue, extractTemplate_refuses_a_few_coloured_spots)
{
    Mat img(120, 160, CV_8UC3, Scalar(90, 90, 90)), mask = Mat::zeros(120, 160, CV_8U);
    const Rect object(40, 30, 80, 60);
    mask(object).setTo(255);
    Mat eroded;
    erode(mask, eroded, Mat(), Point(-1, -1), ColorHue::Params().mask_erosion);
    const double area = countNonZero(eroded);
    const Rect spot(60, 50, 10, 10); // 100 pixels, within the eroded mask
    ASSERT_LT(spot.area(), 0.9 * ColorHue::Params().min_feature_area * area);
    img(spot).setTo(Scalar(0, 0, 220));
    linemod::Template templ;
    EXPECT_FALSE(ColorHue::create()->process(img, mask)->extractTemplate(templ));

    ColorHue::Params p;
    p.min_feature_area = 0.f;
    ASSERT_TRUE(ColorHue::create(p)->process(img, mask)->extractTemplate(templ));
    for (const linemod::Feature& f : templ.features)
        EXPECT_EQ(0, f.label); // red

    const Rect larger(50, 40, 40, 40); // 1600 pixels
    ASSERT_GT(larger.area(), 1.1 * ColorHue::Params().min_feature_area * area);
    img(larger).setTo(Scalar(0, 0, 220));
    EXPECT_TRUE(ColorHue::create()->process(img, mask)->extractTemplate(templ));
}

// The numbers of doc/detector.md, "Hue features of weakly saturated colours": each LM-O mesh drawn
// at its ground-truth pose in the frames 15-49 of ../shared (FORESTMOD_SHARED_DATA; frames that
// forestmod_eval's tables do not report), instances at least 90 % visible; the drawn pixels of the
// eroded mask that ColorHue labels, by the drawing's saturation, against the real frame's bin:
//   ./bin/opencv_test_forestmod --gtest_filter='*mesh_hue_on_real_frames' --gtest_also_run_disabled_tests
TEST(Forestmod_Hue, DISABLED_mesh_hue_on_real_frames)
{
    const std::string shared = sharedDataPath();
    if (shared.empty())
        throw SkipTestException("FORESTMOD_SHARED_DATA does not point to ../shared/data");
    const BopDataset ds = BopDataset::open(shared + "/lmo");
    const std::vector<Frame> frames = ds.frames(2);
    ASSERT_GE(frames.size(), (size_t)50);
    const ColorHue::Params hp;
    const int bands[] = { hp.saturation_threshold, 70, 100, 256 };
    const int n_bands = 3;
    Ptr<Renderer> renderer = Renderer::create(Size(640, 480));
    std::map<int, int> handle;
    // per object and band: drawn pixels, labelled in the frame too, same bin, next bin
    std::map<int, std::vector<Vec4i> > count;
    std::map<int, double> mask_area;
    for (size_t f = 15; f < 50; ++f)
    {
        Mat real_hsv;
        cvtColor(frames[f].rgb(), real_hsv, COLOR_BGR2HSV);
        for (size_t g = 0; g < frames[f].gt.size(); ++g)
        {
            const GroundTruth& gt = frames[f].gt[g];
            if (gt.visib_fract < 0.9)
                continue;
            if (!handle.count(gt.obj_id))
            {
                handle[gt.obj_id] = renderer->addMesh(Mesh::load(cv::format(
                    "%s/lmo/models/obj_%06d.ply", shared.c_str(), gt.obj_id)));
                count[gt.obj_id].assign(n_bands, Vec4i());
            }
            Mat color, mask, hsv;
            renderer->render(handle[gt.obj_id], gt.R, gt.t, frames[f].K, color, noArray(), mask);
            GaussianBlur(color, color, Size(hp.blur_size, hp.blur_size), 0, 0, BORDER_REPLICATE);
            cvtColor(color, hsv, COLOR_BGR2HSV);
            erode(mask, mask, Mat(), Point(-1, -1), hp.mask_erosion);
            mask_area[gt.obj_id] += countNonZero(mask);
            for (int y = 0; y < mask.rows; ++y)
                for (int x = 0; x < mask.cols; ++x)
                {
                    const Vec3b m = hsv.at<Vec3b>(y, x), r = real_hsv.at<Vec3b>(y, x);
                    if (!mask.at<uchar>(y, x) || m[1] < bands[0] || m[2] < hp.value_threshold)
                        continue;
                    const int b = m[1] < bands[1] ? 0 : m[1] < bands[2] ? 1 : 2;
                    Vec4i& c = count[gt.obj_id][b];
                    ++c[0];
                    if (r[1] < hp.saturation_threshold || r[2] < hp.value_threshold)
                        continue;
                    ++c[1];
                    const int d = std::abs(hueBin(m[0]) - hueBin(r[0]));
                    c[2] += d == 0;
                    c[3] += d == 1 || d == 7;
                }
        }
    }
    ASSERT_EQ((size_t)8, count.size());
    printf("| object | drawn saturation | labelled drawn pixels (share of the mask) | labelled in "
           "the frame | same bin | next bin |\n|---|---|---|---|---|---|\n");
    for (std::map<int, std::vector<Vec4i> >::const_iterator it = count.begin();
         it != count.end(); ++it)
    {
        int all = 0;
        for (int b = 0; b < n_bands; ++b)
            all += it->second[b][0];
        if (all == 0)
            printf("| %d | - | 0 | - | - | - |\n", it->first);
        for (int b = 0; b < n_bands && all > 0; ++b)
        {
            const Vec4i& c = it->second[b];
            if (c[0] == 0)
                continue;
            printf("| %d | %d-%d | %d (%.1f %%) | %.1f %% | %.1f %% | %.1f %% |\n", it->first,
                   bands[b], bands[b + 1] - 1, c[0], 100.0 * c[0] / mask_area[it->first],
                   100.0 * c[1] / c[0],
                   c[1] ? 100.0 * c[2] / c[1] : 0.0, c[1] ? 100.0 * c[3] / c[1] : 0.0);
        }
    }
}

TEST(Forestmod_Hue, quantize_respects_mask)
{
    Mat img, mask;
    stripedSquare(img, mask, Rect(100, 60, 90, 90));
    Mat full, masked;
    ColorHue::create()->process(img)->quantize(full);
    ColorHue::create()->process(img, mask)->quantize(masked);
    EXPECT_GT(countNonZero(full), 0);
    // the 3x3 blur spreads colour one pixel out of the square; the mask cuts that off
    EXPECT_GT(countNonZero(full), countNonZero(masked));
    EXPECT_GE(countNonZero(masked), (int)(0.9 * countNonZero(mask)));
    Mat outside;
    bitwise_not(mask, outside);
    Mat coloured(img.size(), CV_8UC3, Scalar(0, 180, 255));
    Mat q;
    ColorHue::create()->process(coloured, mask)->quantize(q);
    EXPECT_EQ(0, countNonZero(q & outside));
    EXPECT_EQ(countNonZero(mask), countNonZero(q));
}

// Smooth random colour texture: random colours on a coarse grid, upsampled, plus fine noise.
static Mat texturedBackground(Size size, RNG& rng)
{
    Mat coarse(size.height / 24 + 1, size.width / 24 + 1, CV_8UC3);
    rng.fill(coarse, RNG::UNIFORM, Scalar::all(0), Scalar::all(256));
    Mat img;
    resize(coarse, img, size, 0, 0, INTER_CUBIC);
    Mat noise(size, CV_8UC3);
    rng.fill(noise, RNG::NORMAL, Scalar::all(0), Scalar::all(6));
    img += noise;
    return img;
}

TEST(Forestmod_Hue, plain_linemod_detector_with_hue_alone)
{
    RNG rng(12345);
    const Size size(640, 480);
    // the object: a 96x96 square with stripes of three hues and a yellow disc in the middle
    Mat obj(96, 96, CV_8UC3, Scalar(0, 0, 220));
    rectangle(obj, Rect(32, 0, 32, 96), Scalar(0, 190, 0), FILLED);
    rectangle(obj, Rect(64, 0, 32, 96), Scalar(220, 60, 0), FILLED);
    circle(obj, Point(48, 48), 14, Scalar(0, 220, 230), FILLED);

    // template: the object on black
    Mat train = Mat::zeros(size, CV_8UC3), train_mask = Mat::zeros(size, CV_8U);
    const Rect tbox(200, 150, 96, 96);
    obj.copyTo(train(tbox));
    train_mask(tbox).setTo(255);

    std::vector<Ptr<linemod::Modality> > modalities(1, ColorHue::create());
    std::vector<int> T;
    T.push_back(4);
    T.push_back(8);
    linemod::Detector detector(modalities, T);
    Rect bb;
    std::vector<Mat> sources(1, train);
    ASSERT_EQ(0, detector.addTemplate(sources, "striped", train_mask, &bb));

    Mat scene = texturedBackground(size, rng);
    Mat with_object = scene.clone();
    const Point at(371, 213);
    obj.copyTo(with_object(Rect(at.x, at.y, 96, 96)));

    const float threshold = 85.f;
    std::vector<linemod::Match> matches;
    detector.match(std::vector<Mat>(1, with_object), threshold, matches);
    ASSERT_FALSE(matches.empty());
    const linemod::Match& best = matches[0];
    // the match position is the template's bounding box corner
    const Point expected = at + (bb.tl() - tbox.tl());
    EXPECT_LE(std::abs(best.x - expected.x), T[0]) << best.x << " vs " << expected.x;
    EXPECT_LE(std::abs(best.y - expected.y), T[0]) << best.y << " vs " << expected.y;

    std::vector<linemod::Match> none;
    detector.match(std::vector<Mat>(1, scene), threshold, none);
    EXPECT_TRUE(none.empty()) << none.size() << " matches, best " << none[0].similarity;
}

TEST(Forestmod_Hue, read_write_roundtrip)
{
    ColorHue::Params p;
    p.saturation_threshold = 77;
    p.feature_saturation_threshold = 99;
    p.min_feature_area = 0.25f;
    p.value_threshold = 12;
    p.num_features = 31;
    p.blur_size = 5;
    p.mask_erosion = 1;
    Ptr<ColorHue> hue = ColorHue::create(p);
    FileStorage fs(".yml", FileStorage::WRITE + FileStorage::MEMORY);
    fs << "modality" << "{";
    hue->write(fs);
    fs << "}";
    std::string text = fs.releaseAndGetString();

    FileStorage in(text, FileStorage::READ + FileStorage::MEMORY);
    Ptr<ColorHue> back = ColorHue::create();
    back->read(in["modality"]);
    EXPECT_EQ("ColorHue", back->name());
    EXPECT_EQ(77, back->getParams().saturation_threshold);
    EXPECT_EQ(99, back->getParams().feature_saturation_threshold);
    EXPECT_EQ(0.25f, back->getParams().min_feature_area);
    EXPECT_EQ(12, back->getParams().value_threshold);
    EXPECT_EQ(31, back->getParams().num_features);
    EXPECT_EQ(5, back->getParams().blur_size);
    EXPECT_EQ(1, back->getParams().mask_erosion);

    // a node of another modality is refused
    FileStorage fs2(".yml", FileStorage::WRITE + FileStorage::MEMORY);
    fs2 << "modality" << "{";
    linemod::Modality::create("ColorGradient")->write(fs2);
    fs2 << "}";
    FileStorage in2(fs2.releaseAndGetString(), FileStorage::READ + FileStorage::MEMORY);
    EXPECT_THROW(back->read(in2["modality"]), cv::Exception);
    // invalid values are refused
    const char* bad[] = { "saturation_threshold: 300", "feature_saturation_threshold: -1",
                          "min_feature_area: 1.5" };
    for (size_t i = 0; i < sizeof(bad) / sizeof(bad[0]); ++i)
    {
        FileStorage in3(std::string("%YAML:1.0\nm: { type: ColorHue, ") + bad[i] + " }\n",
                        FileStorage::READ + FileStorage::MEMORY);
        EXPECT_THROW(back->read(in3["m"]), cv::Exception) << bad[i];
    }
    // a file written before the field keeps the default
    FileStorage in5("%YAML:1.0\nm: { type: ColorHue, saturation_threshold: 60 }\n",
                    FileStorage::READ + FileStorage::MEMORY);
    Ptr<ColorHue> old = ColorHue::create();
    old->read(in5["m"]);
    EXPECT_EQ(60, old->getParams().saturation_threshold);
    EXPECT_EQ(ColorHue::Params().feature_saturation_threshold,
              old->getParams().feature_saturation_threshold);
    EXPECT_EQ(ColorHue::Params().min_feature_area, old->getParams().min_feature_area);
}

TEST(Forestmod_Hue, does_not_modify_its_input)
{
    RNG rng(2);
    Mat img(60, 80, CV_8UC3);
    rng.fill(img, RNG::UNIFORM, Scalar::all(0), Scalar::all(256));
    const Mat copy = img.clone();
    Mat q;
    Ptr<linemod::QuantizedPyramid> qp = ColorHue::create()->process(img);
    qp->quantize(q);
    qp->pyrDown();
    EXPECT_EQ(0, cvtest::norm(img, copy, NORM_INF));
}

TEST(Forestmod_Hue, bad_input_raises)
{
    Ptr<ColorHue> hue = ColorHue::create();
    EXPECT_THROW(hue->process(Mat()), cv::Exception);
    EXPECT_THROW(hue->process(Mat(10, 10, CV_8UC1, Scalar(3))), cv::Exception);
    EXPECT_THROW(hue->process(Mat(10, 10, CV_16UC3, Scalar::all(3))), cv::Exception);
    EXPECT_THROW(hue->process(Mat(10, 10, CV_8UC3, Scalar::all(3)), Mat(11, 10, CV_8U, Scalar(1))),
                 cv::Exception);
    EXPECT_THROW(hue->process(Mat(10, 10, CV_8UC3, Scalar::all(3)), Mat(10, 10, CV_16U, Scalar(1))),
                 cv::Exception);
    Mat q;
    EXPECT_THROW(quantizeHue(Mat(), q), cv::Exception);
    EXPECT_THROW(quantizeHue(Mat(4, 4, CV_8UC1), q), cv::Exception);
    try
    {
        hue->process(Mat(10, 10, CV_16UC3, Scalar::all(3)));
        FAIL() << "no exception";
    }
    catch (const cv::Exception& e)
    {
        EXPECT_NE(std::string::npos, e.err.find("CV_8UC3")) << e.err;
    }
    ColorHue::Params p;
    p.num_features = 0;
    EXPECT_THROW(ColorHue::create(p), cv::Exception);
}

}} // namespace
