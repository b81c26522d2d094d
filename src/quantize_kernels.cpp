// This file is part of OpenCV project.
// It is subject to the license terms in the LICENSE file found in the top-level directory
// of this distribution and at http://opencv.org/license.html

// Baseline build of the fast quantization's row kernels and the choice of the instruction set.

#include "precomp.hpp"
#include "quantize_kernels.hpp"
#include "kernel_dispatch.hpp"
#define FORESTMOD_KERNELS_NAMESPACE cpu_baseline
#include "quantize_kernels.simd.hpp"
#undef FORESTMOD_KERNELS_NAMESPACE

#ifdef FORESTMOD_HAVE_AVX2 // declarations of the AVX2 build (avx2/quantize_kernels.avx2.cpp)
#define FORESTMOD_KERNELS_NAMESPACE opt_AVX2
#define FORESTMOD_KERNELS_DECLARATIONS_ONLY
#include "quantize_kernels.simd.hpp"
#undef FORESTMOD_KERNELS_DECLARATIONS_ONLY
#undef FORESTMOD_KERNELS_NAMESPACE
#endif

namespace cv {
namespace forestmod {
namespace detail {

void splitRow3(const uchar* src, int n, uchar* p0, uchar* p1, uchar* p2)
{
    FORESTMOD_DISPATCH(splitRow3(src, n, p0, p1, p2));
}

void sobelStrongestPlanar(const uchar* const* up, const uchar* const* mid,
                          const uchar* const* dn, int cols, int ithr, float* fx, float* fy,
                          uchar* strong)
{
    FORESTMOD_DISPATCH(sobelStrongestPlanar(up, mid, dn, cols, ithr, fx, fy, strong));
}

void orientationRow(const float* angle, int cols, uchar* onehot)
{
    FORESTMOD_DISPATCH(orientationRow(angle, cols, onehot));
}

void majorityRow(const uchar* up, const uchar* mid, const uchar* dn, const uchar* strong,
                 const uchar* mask, int n, uchar* dst)
{
    FORESTMOD_DISPATCH(majorityRow(up, mid, dn, strong, mask, n, dst));
}

namespace {
// The divisors of OpenCV's 8-bit BGR -> HSV (imgproc's color_hsv, hsv_shift 12):
// sdiv[v] = round(255 * 2^12 / v), hdiv[d] = round(180 * 2^12 / (6 d)), both 0 at 0.
struct HsvDivisors
{
    int sdiv[256], hdiv[256];
    HsvDivisors()
    {
        sdiv[0] = hdiv[0] = 0;
        for (int i = 1; i < 256; ++i)
        {
            sdiv[i] = saturate_cast<int>((255 << 12) / (1. * i));
            hdiv[i] = saturate_cast<int>((180 << 12) / (6. * i));
        }
    }
};
} // namespace

void hueBinsRow(const uchar* bgr, const uchar* mask, int cols, int smin, int vmin, uchar* dst)
{
    static const HsvDivisors t;
    FORESTMOD_DISPATCH(hueBinsRow(bgr, mask, cols, smin, vmin, t.sdiv, t.hdiv, dst));
}

void orRows(const uchar* first, size_t step, int n, int cols, uchar* d)
{
    FORESTMOD_DISPATCH(orRows(first, step, n, cols, d));
}

void responsesRow(const uchar* s, int cols, const uchar* within, const uchar* lut,
                  uchar* const* d)
{
    FORESTMOD_DISPATCH(responsesRow(s, cols, within, lut, d));
}

void dominantLabelsRow(const uchar* const* rows, int nrows, int cols, int k, uchar* colsum,
                       uchar* best, uchar* d)
{
    FORESTMOD_DISPATCH(dominantLabelsRow(rows, nrows, cols, k, colsum, best, d));
}

void medianOneHotRow(const uchar* const* rows, int cols, uchar* planes, uchar* dst)
{
    FORESTMOD_DISPATCH(medianOneHotRow(rows, cols, planes, dst));
}

int normalCellsRow(const ushort* row, size_t step, int n, int distance_threshold,
                   int difference_threshold, int* cells)
{
#ifdef FORESTMOD_HAVE_AVX2
    if (useAVX2())
        return opt_AVX2::normalCellsRow(row, step, n, distance_threshold, difference_threshold,
                                        cells);
#endif
    return cpu_baseline::normalCellsRow(row, step, n, distance_threshold, difference_threshold,
                                        cells);
}

} // namespace detail
} // namespace forestmod
} // namespace cv
