// This file is part of OpenCV project.
// It is subject to the license terms in the LICENSE file found in the top-level directory
// of this distribution and at http://opencv.org/license.html

#ifndef OPENCV_FORESTMOD_QUANTIZE_KERNELS_HPP
#define OPENCV_FORESTMOD_QUANTIZE_KERNELS_HPP

// The row kernels of the scene pyramid's fast quantization (quantize_fast.cpp): OpenCV universal
// intrinsics, compiled for the baseline and, on x86-64, once more for AVX2 (src/avx2/), chosen
// at each call (kernel_dispatch.hpp). Integer arithmetic and exact conversions: every path gives
// the same bits (tests Forestmod_QuantizeFast.*, run with and without cv::setUseOptimized).
// hueBinsRow and medianOneHotRow are exported for their tests only (the header is not installed).

#include "opencv2/core.hpp"

namespace cv {
namespace forestmod {
namespace detail {

/** n interleaved BGR pixels split into three planes. */
void splitRow3(const uchar* src, int n, uchar* p0, uchar* p1, uchar* p2);
/** Per-channel 3x3 Sobel (16 bits) of three planes (rows above, at, below; [-1] and [cols]
readable) and per pixel the channel of largest dx^2 + dy^2 (ties: the first): its dx and dy as
float, and 255 where dx^2 + dy^2 > ithr (else 0) in `strong`. */
void sobelStrongestPlanar(const uchar* const* up, const uchar* const* mid,
                          const uchar* const* dn, int cols, int ithr, float* fx, float* fy,
                          uchar* strong);
/** One-hot orientation 1 << (round(angle * 16 / 360) & 7) of a row of angles in degrees. */
void orientationRow(const float* angle, int cols, uchar* onehot);
/** LINEMOD's 3x3 vote of n pixels: the bin that at least 5 of the 9 one-hot labels around a
pixel share (rows readable at [-1] and [n]), kept where `strong` and the mask (may be null)
are set, else 0. */
void majorityRow(const uchar* up, const uchar* mid, const uchar* dn, const uchar* strong,
                 const uchar* mask, int n, uchar* dst);
/** ColorHue's label of a row of BGR pixels: 1 << hueBin(h) where s >= smin and v >= vmin and
the mask (may be null) is set, else 0; h, s, v as cv::cvtColor(COLOR_BGR2HSV) computes them
(its 8-bit integer arithmetic, no HSV image in between). */
CV_EXPORTS void hueBinsRow(const uchar* bgr, const uchar* mask, int cols, int smin, int vmin,
                           uchar* dst);
/** d[c] = OR of the n >= 1 rows first[k * step + c], c < cols (step 1: the OR of a window of
n bytes along a row). */
void orRows(const uchar* first, size_t step, int n, int cols, uchar* d);
/** The 8 LINEMOD responses of a row of spread bytes: d[o][c] = 4 - the number of the label
sets within[4 o + 0 .. 3] (the labels at circular distance <= 0 .. 3 of o) that miss s[c]
(lut[256 o + s]: the same, for the scalar path). */
void responsesRow(const uchar* s, int cols, const uchar* within, const uchar* lut,
                  uchar* const* d);
/** One row of the forest's label planes: d[c] = the bit set most often in the k x k window
(the `nrows` rows of the window, clipped to the image, given in `rows`; columns
[c - k / 2, c - k / 2 + k), zeros outside; ties: the lowest bit; 0 where no bit is set).
colsum: cols bytes with k / 2 zero bytes before and k zero bytes after; best: cols bytes. */
void dominantLabelsRow(const uchar* const* rows, int nrows, int cols, int k, uchar* colsum,
                       uchar* best, uchar* d);
/** DepthNormal's quantization cell ((i3 * 21 + i2) * 21 + i1, -1 where LINEMOD gives no
normal) of the pixels [0, x) of a depth row, x returned (a multiple of the vector size; the
caller does the rest in scalar code): the plane fit to the 8 depths at +-5 pixels (rows
row - 5 step, row + 5 step and columns -5, +5 readable) with cv::linemod's integer and float
arithmetic, no fused multiply-add. */
int normalCellsRow(const ushort* row, size_t step, int n, int distance_threshold,
                   int difference_threshold, int* cells);

/** One row of the 5x5 median (cv::medianBlur, BORDER_REPLICATE) of an image of one-hot labels
(every pixel 0 or 1 << j): rows = the 5 rows around it (clamped to the image), planes: scratch of
3 * (cols + 4) bytes. */
CV_EXPORTS void medianOneHotRow(const uchar* const* rows, int cols, uchar* planes, uchar* dst);

} // namespace detail
} // namespace forestmod
} // namespace cv

#endif
