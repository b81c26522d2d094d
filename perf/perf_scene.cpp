// This file is part of OpenCV project.
// It is subject to the license terms in the LICENSE file found in the top-level directory
// of this distribution and at http://opencv.org/license.html

// The scene pyramid of a frame (every pyramid level quantized by every modality; then spread and
// response maps): forestmod's fast paths (src/quantize_fast.*) against cv::linemod's own
// quantization of the same modalities (process + quantize + pyrDown + quantize), VGA and 720p,
// RGB (ColorGradient + ColorHue) and RGB-D (+ DepthNormal), 1 and 2 threads. Two levels, as the
// detector's defaults (T = {5, 8}). `scene` is the pair of the issue: what match() computes of a
// frame before the forest (src/scene_pyramid.*) against cv::linemod's quantization;
// `refinement_tiles` is what it computes after validation, per refined match.

#include "perf_precomp.hpp"
#include "../src/quantize_fast.hpp"
#include "../src/scene_pyramid.hpp"

#include "opencv2/core/utils/filesystem.hpp"

namespace opencv_test { namespace {

using namespace cv::forestmod::detail;

enum { SCENE_RGB = 0, SCENE_RGBD = 1 };
CV_ENUM(SceneKind, SCENE_RGB, SCENE_RGBD)
// linemod: cv::linemod's quantization; fast: quantize_fast's
// reference: what the detector did before (virtual quantization + detail::spreadLabels /
// computeResponseMaps), fast: quantize_fast's quantization + spreadLabelsFast /
// computeResponseMapsFast
enum { IMPL_LINEMOD = 0, IMPL_FAST = 1 };
CV_ENUM(QuantImpl, IMPL_LINEMOD, IMPL_FAST)

struct Scene
{
    std::vector<Ptr<linemod::Modality> > modalities;
    std::vector<Mat> sources;
};

// A real LM-O colour frame (shipped) and, for RGB-D, a real depth frame of ../shared
// (FORESTMOD_SHARED_DATA/real_rgbd) or, without it, a tilted plane with boxes on it.
static Scene makeScene(Size size, int kind)
{
    Scene s;
    Mat rgb = imread(cvtest::findDataFile("lmo_mini/test/000002/rgb/000902.png"), IMREAD_COLOR);
    CV_Assert(!rgb.empty());
    if (rgb.size() != size)
        resize(rgb, rgb, size, 0, 0, INTER_LINEAR);
    s.modalities.push_back(linemod::Modality::create("ColorGradient"));
    s.modalities.push_back(ColorHue::create());
    s.sources.push_back(rgb);
    s.sources.push_back(rgb);
    if (kind == SCENE_RGBD)
    {
        Mat depth;
        const char* shared = getenv("FORESTMOD_SHARED_DATA");
        if (shared && *shared)
        {
            const std::string p = std::string(shared) + "/real_rgbd/linemod_scene_depth.png";
            if (utils::fs::exists(p))
                depth = imread(p, IMREAD_UNCHANGED);
        }
        if (depth.empty() || depth.type() != CV_16UC1)
        {
            depth.create(480, 640, CV_16U);
            for (int r = 0; r < depth.rows; ++r)
                for (int c = 0; c < depth.cols; ++c)
                    depth.at<ushort>(r, c) = (ushort)(900 + r / 2 + c / 8);
            rectangle(depth, Rect(200, 150, 120, 90), Scalar(820), FILLED);
            circle(depth, Point(450, 300), 60, Scalar(850), FILLED);
        }
        if (depth.size() != size)
            resize(depth, depth, size, 0, 0, INTER_NEAREST);
        s.modalities.push_back(linemod::Modality::create("DepthNormal"));
        s.sources.push_back(depth);
    }
    return s;
}

// cv::linemod's quantization of every modality of the scene: process, then quantize and pyrDown
// level by level (forestmod_eval's T_quant of cv::linemod).
static void linemodQuantize(const Scene& scene, int levels, std::vector<std::vector<Mat> >& q)
{
    for (size_t i = 0; i < scene.modalities.size(); ++i)
    {
        Ptr<linemod::QuantizedPyramid> qp = scene.modalities[i]->process(scene.sources[i]);
        for (int l = 0; l < levels; ++l)
        {
            if (l > 0)
                qp->pyrDown();
            qp->quantize(q[l][i]);
        }
    }
}

typedef tuple<Size, SceneKind, int, QuantImpl> SceneParams;
typedef TestBaseWithParam<SceneParams> Forestmod_ScenePyramid;

// Quantization of 2 levels by every modality.
PERF_TEST_P(Forestmod_ScenePyramid, quantize,
            Combine(Values(szVGA, sz720p), SceneKind::all(), Values(1, 2), QuantImpl::all()))
{
    const Size size = get<0>(GetParam());
    const int kind = get<1>(GetParam()), threads = get<2>(GetParam());
    const int impl = get<3>(GetParam());
    const Scene scene = makeScene(size, kind);
    const int M = (int)scene.modalities.size(), levels = 2;
    std::vector<ModalityInfo> infos;
    for (int i = 0; i < M; ++i)
        infos.push_back(classifyModality(scene.modalities[i]));
    const int old_threads = getNumThreads();
    setNumThreads(threads);
    std::vector<std::vector<Mat> > q(levels, std::vector<Mat>(M));
    TEST_CYCLE()
    {
        if (impl == IMPL_LINEMOD)
            linemodQuantize(scene, levels, q);
        else
            quantizeAllLevels(scene.modalities, infos, scene.sources, std::vector<Mat>(), levels,
                              q);
    }
    setNumThreads(old_threads);
    for (int i = 0; i < M; ++i)
    {
        ASSERT_EQ(size, q[0][i].size());
        ASSERT_GT(countNonZero(q[0][i]), 0);
    }
    SANITY_CHECK_NOTHING();
}

// The whole scene pyramid: quantization of 2 levels, spread (T = 5, 8) and the 8 response maps
// per modality and level. IMPL_LINEMOD here is the detector's path before the fast paths: the
// modalities' virtual calls and validator.cpp's spreadLabels / computeResponseMaps (cv::linemod's
// own spreading is not reachable from outside).
PERF_TEST_P(Forestmod_ScenePyramid, quantize_spread_response,
            Combine(Values(szVGA, sz720p), SceneKind::all(), Values(1, 2), QuantImpl::all()))
{
    const Size size = get<0>(GetParam());
    const int kind = get<1>(GetParam()), threads = get<2>(GetParam());
    const int impl = get<3>(GetParam());
    const Scene scene = makeScene(size, kind);
    const int M = (int)scene.modalities.size(), levels = 2;
    const int T[2] = { 5, 8 }, pad = 64;
    std::vector<ModalityInfo> infos;
    for (int i = 0; i < M; ++i)
        infos.push_back(classifyModality(scene.modalities[i]));
    const int old_threads = getNumThreads();
    setNumThreads(threads);
    std::vector<std::vector<Mat> > q(levels, std::vector<Mat>(M)), spread = q;
    std::vector<std::vector<std::vector<Mat> > > resp(
        levels, std::vector<std::vector<Mat> >(M));
    TEST_CYCLE()
    {
        if (impl == IMPL_LINEMOD)
        {
            for (int i = 0; i < M; ++i)
            {
                Ptr<linemod::QuantizedPyramid> qp = scene.modalities[i]->process(scene.sources[i]);
                for (int l = 0; l < levels; ++l)
                {
                    if (l > 0)
                        qp->pyrDown();
                    qp->quantize(q[l][i]);
                    spreadLabelsReference(q[l][i], spread[l][i], T[l], pad >> l);
                    computeResponseMapsReference(spread[l][i], resp[l][i]);
                }
            }
        }
        else
        {
            quantizeAllLevels(scene.modalities, infos, scene.sources, std::vector<Mat>(), levels,
                              q);
            for (int l = 0; l < levels; ++l)
                for (int i = 0; i < M; ++i)
                {
                    spreadLabelsFast(q[l][i], spread[l][i], T[l], pad >> l);
                    computeResponseMapsFast(spread[l][i], resp[l][i]);
                }
        }
    }
    setNumThreads(old_threads);
    for (int i = 0; i < M; ++i)
    {
        ASSERT_EQ(8u, resp[0][i].size());
        ASSERT_GT(countNonZero(resp[1][i][0]), 0);
    }
    SANITY_CHECK_NOTHING();
}

// What match() computes of a frame before the forest (T_quant without the refinement tiles):
// quantizeScene (the coarsest level quantized and spread; the finer
// levels of the colour modalities are left to the tiles, the depth normals quantized whole),
// forestPlanes, and for RGB-D depthContexts; IMPL_LINEMOD: cv::linemod's quantization of the same
// modalities (process + quantize + pyrDown + quantize: forestmod_eval's T_quant of cv::linemod).
PERF_TEST_P(Forestmod_ScenePyramid, scene,
            Combine(Values(szVGA, sz720p), SceneKind::all(), Values(1, 2), QuantImpl::all()))
{
    const Size size = get<0>(GetParam());
    const int kind = get<1>(GetParam()), threads = get<2>(GetParam());
    const int impl = get<3>(GetParam());
    const Scene s = makeScene(size, kind);
    const int M = (int)s.modalities.size(), levels = 2;
    const std::vector<int> T{ 5, 8 };
    const cv::forestmod::DetectorParams params;
    const ModalityRoles roles = ModalityRoles::of(s.modalities);
    const int old_threads = getNumThreads();
    setNumThreads(threads);
    std::vector<std::vector<Mat> > q(levels, std::vector<Mat>(M));
    ScenePyramid scene;
    TEST_CYCLE()
    {
        if (impl == IMPL_LINEMOD)
            linemodQuantize(s, levels, q);
        else
        {
            quantizeScene(s.modalities, roles, T, s.sources, std::vector<Mat>(), scene,
                          noArray());
            forestPlanes(params.dominant_window, 40, scene);
            if (kind == SCENE_RGBD)
                depthContexts(s.sources[2], T, params.depth_tolerance, scene);
        }
    }
    setNumThreads(old_threads);
    if (impl == IMPL_FAST)
    {
        ASSERT_EQ(2u, scene.levels.size());
        ASSERT_EQ((size_t)M, scene.planes.size());
        ASSERT_GT(countNonZero(scene.coarsest().spread[0]), 0);
    }
    else
    {
        ASSERT_GT(countNonZero(q[0][0]), 0);
    }
    SANITY_CHECK_NOTHING();
}

typedef tuple<Size, SceneKind, int, int> TileParams;
typedef TestBaseWithParam<TileParams> Forestmod_ScenePyramid_tiles;

// The level-0 quantized images (colour modalities) and spread images that refinement reads,
// computed on demand (the refinement's linearized memories are built from them: perf_validation):
// `regions`
// regions of 240 x 240 pixels (16 cells of T = 5 and a template of 160 pixels: one refined
// match) spread over the frame, or the whole frame (0).
PERF_TEST_P(Forestmod_ScenePyramid_tiles, refinement_tiles,
            Combine(Values(szVGA), SceneKind::all(), Values(1, 2), Values(1, 10, 0)))
{
    const Size size = get<0>(GetParam());
    const int kind = get<1>(GetParam()), threads = get<2>(GetParam());
    const int n = get<3>(GetParam());
    const Scene s = makeScene(size, kind);
    const std::vector<int> T{ 5, 8 };
    const ModalityRoles roles = ModalityRoles::of(s.modalities);
    std::vector<std::vector<Rect> > regions(1);
    if (n == 0)
        regions[0].push_back(Rect(Point(0, 0), size));
    RNG rng(3);
    for (int k = 0; k < n; ++k)
        regions[0].push_back(Rect(rng.uniform(0, size.width - 240),
                                  rng.uniform(0, size.height - 240), 240, 240));
    const int old_threads = getNumThreads();
    setNumThreads(threads);
    ScenePyramid scene;
    quantizeScene(s.modalities, roles, T, s.sources, std::vector<Mat>(), scene, noArray());
    const Mat untouched = scene.tiles[0].clone();
    const std::vector<std::vector<LevelSource> > deferred = scene.deferred;
    TEST_CYCLE()
    {
        untouched.copyTo(scene.tiles[0]); // every cycle computes the tiles again
        scene.deferred = deferred;         // (and the whole level, when it is chosen)
        prepareRefinementLevels(scene, regions);
    }
    setNumThreads(old_threads);
    ASSERT_GT(countNonZero(scene.tiles[0]), 0);
    SANITY_CHECK_NOTHING();
}

}} // namespace
