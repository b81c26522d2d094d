// This file is part of OpenCV project.
// It is subject to the license terms in the LICENSE file found in the top-level directory
// of this distribution and at http://opencv.org/license.html

// LINEMOD's similarity (Hinterstoisser et al., PAMI 2012, sections 2.3-2.4): spreading, response
// maps, and the sum of responses of a template's features read in place from a frame's maps.

#include "precomp.hpp"
#include "similarity.hpp"
#include "quantize_fast.hpp"

#include "opencv2/core/hal/intrin.hpp"

namespace cv {
namespace forestmod {
namespace detail {

void spreadLabels(const Mat& src, Mat& dst, int T, int pad)
{
    CV_Assert(src.type() == CV_8UC1 && T > 0 && pad >= 0);
    // separable: OR over [c, c + T) along rows, then over [r, r + T) along columns (2T passes
    // instead of T^2); outside the image counts as 0
    const int rows = src.rows + pad, cols = src.cols + pad;
    Mat padded;
    copyMakeBorder(src, padded, 0, pad + T, 0, pad + T, BORDER_CONSTANT, Scalar(0));
    Mat horiz = Mat::zeros(rows + T, cols, CV_8U);
    for (int r = 0; r < rows + T; ++r)
    {
        const uchar* s = padded.ptr<uchar>(r);
        uchar* d = horiz.ptr<uchar>(r);
        for (int dc = 0; dc < T; ++dc)
        {
            int c = 0;
#if CV_SIMD128
            for (; c <= cols - 16; c += 16)
                v_store(d + c, v_load(d + c) | v_load(s + c + dc));
#endif
            for (; c < cols; ++c)
                d[c] |= s[c + dc];
        }
    }
    dst = Mat::zeros(rows, cols, CV_8U);
    for (int r = 0; r < rows; ++r)
    {
        uchar* d = dst.ptr<uchar>(r);
        for (int dr = 0; dr < T; ++dr)
        {
            const uchar* s = horiz.ptr<uchar>(r + dr);
            int c = 0;
#if CV_SIMD128
            for (; c <= cols - 16; c += 16)
                v_store(d + c, v_load(d + c) | v_load(s + c));
#endif
            for (; c < cols; ++c)
                d[c] |= s[c];
        }
    }
}

// similarity of orientation o to a single label l: 4 - circular distance, clamped at 0
static uchar labelSimilarity(int o, int l)
{
    int d = std::abs(o - l);
    d = std::min(d, 8 - d);
    return static_cast<uchar>(std::max(0, 4 - d));
}

void computeResponseMaps(const Mat& spread, std::vector<Mat>& response)
{
    CV_Assert(spread.type() == CV_8UC1);
    response.resize(8);
    for (int o = 0; o < 8; ++o)
    {
        uchar lut[256];
        for (int b = 0; b < 256; ++b)
        {
            uchar best = 0;
            for (int l = 0; l < 8; ++l)
                if (b & (1 << l))
                    best = std::max(best, labelSimilarity(o, l));
            lut[b] = best;
        }
        Mat lutm(1, 256, CV_8U, lut);
        LUT(spread, lutm, response[o]);
    }
}

int similarityRange(const LevelMaps& level, int modality, const cv::linemod::Template& templ,
                    Point tl, int begin, int end)
{
    const Mat& spread = level.spread[modality];
    const int W = level.size.width + level.pad, H = level.size.height + level.pad;
    int sum = 0;
    for (int i = begin; i < end; ++i)
    {
        const cv::linemod::Feature& f = templ.features[i];
        const int x = tl.x + f.x, y = tl.y + f.y;
        // LINEMOD skips features that fall outside the image
        if ((unsigned)x >= (unsigned)W || (unsigned)y >= (unsigned)H)
            continue;
        sum += responseOf(f.label, spread.ptr<uchar>(y)[x]);
    }
    return sum;
}

int similarityAll(const LevelMaps& level, const TemplatePyramid& tp, int level_index, Point tl,
                  int* num_features)
{
    const int M = level.modalities();
    int sum = 0, n = 0;
    for (int m = 0; m < M; ++m)
    {
        const cv::linemod::Template& templ = tp[level_index * M + m];
        const int nf = static_cast<int>(templ.features.size());
        sum += similarityRange(level, m, templ, tl, 0, nf);
        n += nf;
    }
    if (num_features)
        *num_features = n;
    return sum;
}

} // namespace detail
} // namespace forestmod
} // namespace cv
