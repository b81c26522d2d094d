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
/** acc[r * 16 + c] += sum over k of src[k][r * stride + c]: n 16 x 16 blocks of responses
(values <= 4; summed in 8 bits, 63 blocks at a time, in registers). */
void addBlocks16(ushort* acc, const uchar* const* src, int n, size_t stride);
/** The index of the first of v[0 .. 256) equal to their largest value, stored in `best`; -1
when every value is 0. */
CV_EXPORTS int firstMax256(const ushort* v, ushort& best);
/** dst[0 .. n) += 1 where src != 0, 8-bit with wrap-around (the caller keeps the counts under
256): the scan's flat-window test over a row of locations. */
CV_EXPORTS void countLabels8(uchar* dst, const uchar* src, int n);
/** dst[0 .. n) += 1 where a rejector dimension accepts src: (src & labels) != 0 for a label,
zero_ok for the value 0 (rejector.hpp's look-up); 8-bit with wrap-around as countLabels8. */
CV_EXPORTS void countAccepted8(uchar* dst, const uchar* src, int n, uchar labels,
                               uchar zero_ok);
/** The exhaustive search's additions and scan of one template (sumRuns16 and a test against
the threshold and each position's entry bar): the indices i in [0, n) where the sum s of the runs
off[0 .. n_off) at position i (as sumRuns16's out[i]) passes, s > threshold and
s >= (bar[i] x scale) >> 16, ascending into `hits` (room for n); returns their number, and
sums[i] = s at those positions. Preemptive: the features are added in stages of 24, and after
each stage a vector of positions none of which could pass with the largest response (4) for
every feature left gets no more of them (most do not on cluttered frames, where the entry bars are
high), so elsewhere sums[i] may hold a partial sum. bar[i] = 0 tests the threshold alone. Writes
and reads whole vectors: sums and the scratch `need` hold n rounded up to 64, bar is readable
that far, `vec` has room for n / 16 + 1 ints; reads as sumRuns16 does. */
CV_EXPORTS int sumRunsPassing16(ushort* sums, const uchar* base, const int* off, int n_off, int n,
                                const ushort* bar, ushort threshold, ushort scale, ushort* need,
                                int* vec, int* hits);

} // namespace detail
} // namespace forestmod
} // namespace cv

#endif
