// This file is part of OpenCV project.
// It is subject to the license terms in the LICENSE file found in the top-level directory
// of this distribution and at http://opencv.org/license.html

// Baseline build of the linearized memories' kernels and the choice of the instruction set.

#include "precomp.hpp"
#include "score_kernels.hpp"
#include "kernel_dispatch.hpp"
#define FORESTMOD_KERNELS_NAMESPACE cpu_baseline
#include "score_kernels.simd.hpp"
#undef FORESTMOD_KERNELS_NAMESPACE

#ifdef FORESTMOD_HAVE_AVX2 // declarations of the AVX2 build (avx2/score_kernels.avx2.cpp)
#define FORESTMOD_KERNELS_NAMESPACE opt_AVX2
#define FORESTMOD_KERNELS_DECLARATIONS_ONLY
#include "score_kernels.simd.hpp"
#undef FORESTMOD_KERNELS_DECLARATIONS_ONLY
#undef FORESTMOD_KERNELS_NAMESPACE
#endif

namespace cv {
namespace forestmod {
namespace detail {

void sumRuns16(ushort* out, const uchar* base, const int* off, int n_off, int n)
{
    FORESTMOD_DISPATCH(sumRuns16(out, base, off, n_off, n));
}

void addBlocks16(ushort* acc, const uchar* const* src, int n, size_t stride)
{
    FORESTMOD_DISPATCH(addBlocks16(acc, src, n, stride));
}

int firstMax256(const ushort* v, ushort& best)
{
#ifdef FORESTMOD_HAVE_AVX2
    if (useAVX2())
        return opt_AVX2::firstMax256(v, best);
#endif
    return cpu_baseline::firstMax256(v, best);
}

void countLabels8(uchar* dst, const uchar* src, int n)
{
    FORESTMOD_DISPATCH(countLabels8(dst, src, n));
}

void countAccepted8(uchar* dst, const uchar* src, int n, uchar labels, uchar zero_ok)
{
    FORESTMOD_DISPATCH(countAccepted8(dst, src, n, labels, zero_ok));
}

int sumRunsPassing16(ushort* sums, const uchar* base, const int* off, int n_off, int n,
                     const ushort* bar, ushort threshold, ushort scale, ushort* need, int* vec,
                     int* hits)
{
#ifdef FORESTMOD_HAVE_AVX2
    if (useAVX2())
        return opt_AVX2::sumRunsPassing16(sums, base, off, n_off, n, bar, threshold, scale, need,
                                          vec, hits);
#endif
    return cpu_baseline::sumRunsPassing16(sums, base, off, n_off, n, bar, threshold, scale, need,
                                          vec, hits);
}

const char* kernelsPath()
{
    return useAVX2() ? "AVX2" : "baseline";
}

} // namespace detail
} // namespace forestmod
} // namespace cv
