// This file is part of OpenCV project.
// It is subject to the license terms in the LICENSE file found in the top-level directory
// of this distribution and at http://opencv.org/license.html

#ifndef OPENCV_FORESTMOD_SCORE_KERNELS_HPP
#define OPENCV_FORESTMOD_SCORE_KERNELS_HPP

// The vectorised kernels of the search: the additions of LINEMOD's linearized memories
// (exhaustive_search.cpp, validator.cpp, linear_memories.cpp) and the scan's tests over a row of
// locations (scan.cpp). OpenCV universal intrinsics, compiled for the baseline and, on x86-64,
// once more for AVX2 (src/avx2/); the AVX2 code runs when cv::checkHardwareSupport(CV_CPU_AVX2)
// (false after cv::setUseOptimized(false)).
// Integer additions: every path gives the same bits. sumRuns16 and the scan's kernels are
// exported for the tests.

#include "opencv2/core.hpp"

namespace cv {
namespace forestmod {
namespace detail {

/** out[0 .. n) = the sum over k < n_off of base[off[k] + 0 .. n): a template's features over a
run of positions of linearized memories (the exhaustive search: all positions of the T grid; the
forest path: a template's candidates at neighbouring locations). Tiles of 8 vectors of positions
whose 8-bit sums of up to 63 features stay in registers, then widened. Writes whole vectors (out
must hold n rounded up to 64) and reads as far from every base + off[k]
(LinearMemories::kSlack). */
CV_EXPORTS void sumRuns16(ushort* out, const uchar* base, const int* off, int n_off, int n);
/** dst[0 .. n) += src[0 .. n), widened to 16 bits. */
void widenAdd(ushort* dst, const uchar* src, int n);
/** acc[r * 16 + c] += sum over k of src[k][r * stride + c]: n 16 x 16 blocks of responses
(values <= 4; summed in 8 bits, 63 blocks at a time, in registers). */
void addBlocks16(ushort* acc, const uchar* const* src, int n, size_t stride);
/** dst[0 .. n) += 1 where src != 0, 8-bit with wrap-around (the caller keeps the counts under
256): the scan's flat-window test over a row of locations. */
CV_EXPORTS void countLabels8(uchar* dst, const uchar* src, int n);
/** dst[0 .. n) += 1 where a rejector dimension accepts src: (src & labels) != 0 for a label,
zero_ok for the value 0 (rejector.hpp's look-up); 8-bit with wrap-around as countLabels8. */
CV_EXPORTS void countAccepted8(uchar* dst, const uchar* src, int n, uchar labels,
                               uchar zero_ok);
/** The indices i in [0, n) where src[i] > threshold and src[i] >= (bar[i] x scale) >> 16,
ascending, into out (room for n); returns their number: the exhaustive search's scan of a
template's scores against the threshold and each position's entry bar (most positions stay
under them: one vector comparison per 8 or 16 of them). bar[i] = 0 tests the threshold alone. */
CV_EXPORTS int positionsPassing16(const ushort* src, const ushort* bar, int n, ushort threshold,
                                  ushort scale, int* out);

} // namespace detail
} // namespace forestmod
} // namespace cv

#endif
