// This file is part of OpenCV project.
// It is subject to the license terms in the LICENSE file found in the top-level directory
// of this distribution and at http://opencv.org/license.html

// The scene pyramid: the frame's maps, computed once per frame.

#include "precomp.hpp"
#include "scene_pyramid.hpp"
#include "search_index.hpp"

namespace cv {
namespace forestmod {
namespace detail {

void quantizeScene(const std::vector<Ptr<cv::linemod::Modality> >& modalities,
                   const std::vector<int>& T_at_level, const std::vector<Mat>& sources,
                   const std::vector<Mat>& masks, ScenePyramid& scene,
                   OutputArrayOfArrays quantized_images)
{
    const int M = static_cast<int>(modalities.size());
    const int levels_n = static_cast<int>(T_at_level.size());
    scene.levels.assign(levels_n, LevelMaps());
    std::vector<Ptr<cv::linemod::QuantizedPyramid> > qps(M);
    for (int i = 0; i < M; ++i)
        qps[i] = modalities[i]->process(sources[i], masks.empty() ? Mat() : masks[i]);
    if (quantized_images.needed())
        quantized_images.create(1, levels_n * M, CV_8U);
    for (int l = 0; l < levels_n; ++l)
    {
        LevelMaps& lm = scene.levels[l];
        lm.T = T_at_level[l];
        lm.pad = 0;
        lm.quantized.resize(M);
        lm.spread.resize(M);
        lm.response.resize(M);
        for (int i = 0; i < M; ++i)
        {
            if (l > 0)
                qps[i]->pyrDown();
            qps[i]->quantize(lm.quantized[i]);
            lm.size = lm.quantized[i].size();
            spreadLabels(lm.quantized[i], lm.spread[i], lm.T, lm.pad);
            computeResponseMaps(lm.spread[i], lm.response[i]);
            if (quantized_images.needed())
                lm.quantized[i].copyTo(quantized_images.getMatRef(l * M + i));
        }
    }
}

void forestPlanes(int dominant_window, int border, ScenePyramid& scene)
{
    const LevelMaps& top = scene.coarsest();
    const size_t M = top.quantized.size();
    scene.planes.assign(M, Mat());
    scene.plane_ptr.assign(M, (const uchar*)0);
    scene.border = border;
    for (size_t m = 0; m < M; ++m)
    {
        // the forest reads the plain quantized images (one label per point, as the templates it
        // was trained on; spreading would add labels and mislead the splits: doc/forest.md)
        Mat dominant;
        dominantLabels(top.quantized[m], Mat(), dominant_window, dominant);
        copyMakeBorder(dominant, scene.planes[m], border, border, border, border, BORDER_CONSTANT,
                       Scalar(0));
        scene.plane_ptr[m] = scene.planes[m].ptr();
    }
    scene.plane_step = M ? scene.planes[0].step : 0;
}

void depthContexts(const Mat& depth, const std::vector<int>& T_at_level, int tolerance,
                   ScenePyramid& scene)
{
    const int L = static_cast<int>(T_at_level.size()) - 1;
    scene.depth_ctx.assign(L + 1, DepthContext());
    for (int l = 0; l < L; ++l)
    {
        scene.depth_ctx[l].set(depth, (T_at_level[l] / 2) << l);
        scene.depth_ctx[l].tolerance = tolerance;
        scene.depth_ctx[l].scale_shift = l;
    }
}

} // namespace detail
} // namespace forestmod
} // namespace cv
