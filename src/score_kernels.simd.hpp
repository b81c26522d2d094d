// This file is part of OpenCV project.
// It is subject to the license terms in the LICENSE file found in the top-level directory
// of this distribution and at http://opencv.org/license.html

// The kernels of score_kernels.hpp, compiled once per instruction set (OpenCV's .simd.hpp
// scheme): in namespace cpu_baseline by score_kernels.cpp, in opt_AVX2 by
// avx2/score_kernels.avx2.cpp (-mavx2, CV_CPU_DISPATCH_MODE=AVX2 and CV_AVX2=1: OpenCV's
// installed headers do not derive them from the compiler outside OpenCV's own build). The
// including file defines FORESTMOD_KERNELS_NAMESPACE, and FORESTMOD_KERNELS_DECLARATIONS_ONLY to
// declare another build's functions (OpenCV's CV_CPU_OPTIMIZATION_DECLARATIONS_ONLY). Raw
// pointers only: this header must not
// pull inline code of other headers into the AVX2 translation unit.

#include "opencv2/core/hal/intrin.hpp"

#ifndef FORESTMOD_KERNELS_NAMESPACE
#error "define FORESTMOD_KERNELS_NAMESPACE (cpu_baseline or opt_AVX2) before including this file"
#endif

namespace cv {
namespace forestmod {
namespace detail {
namespace FORESTMOD_KERNELS_NAMESPACE {

void sumRuns16(ushort* out, const uchar* base, const int* off, int n_off, int n);
void widenAdd(ushort* dst, const uchar* src, int n);
void addBlocks16(ushort* acc, const uchar* const* src, int n, size_t stride);
void countLabels8(uchar* dst, const uchar* src, int n);
void countAccepted8(uchar* dst, const uchar* src, int n, uchar labels, uchar zero_ok);
int positionsPassing16(const ushort* src, const ushort* bar, int n, ushort threshold,
                       ushort scale, int* out);

#ifndef FORESTMOD_KERNELS_DECLARATIONS_ONLY

// The index of the lowest set bit of m != 0.
static inline int lowestBit(unsigned m)
{
#if defined(__GNUC__)
    return __builtin_ctz(m);
#else
    int i = 0;
    while (!(m & 1u))
    {
        m >>= 1;
        ++i;
    }
    return i;
#endif
}

void sumRuns16(ushort* out, const uchar* base, const int* off, int n_off, int n)
{
    if (n_off == 0)
    {
        for (int j = 0; j < n; ++j)
            out[j] = 0;
        return;
    }
#if CV_SIMD
    const int w = v_uint8::nlanes;
    const int kTile = 8;  // vectors of positions per tile: 8 accumulators in registers
    for (int x = 0; x < n; x += kTile * w)
    {
        const int left = (n - x + w - 1) / w;
        const int nv = left < kTile ? left : kTile;
        const uchar* b = base + x;
        for (int k = 0; k < n_off;)
        {
            const bool first = k == 0;
            const int end = n_off - k < 63 ? n_off : k + 63;
            v_uint8 a[kTile];
            for (int j = 0; j < kTile; ++j)
                a[j] = vx_setzero_u8();
            if (nv == kTile)
                for (; k < end; ++k)
                {
                    const uchar* p = b + off[k];
                    for (int j = 0; j < kTile; ++j)
                        a[j] = v_add_wrap(a[j], vx_load(p + j * w));
                }
            else
                for (; k < end; ++k)
                {
                    const uchar* p = b + off[k];
                    for (int j = 0; j < nv; ++j)
                        a[j] = v_add_wrap(a[j], vx_load(p + j * w));
                }
            for (int j = 0; j < nv; ++j)
            {
                ushort* d = out + x + j * w;
                v_uint16 lo, hi;
                v_expand(a[j], lo, hi);
                v_store(d, first ? lo : vx_load(d) + lo);
                v_store(d + w / 2, first ? hi : vx_load(d + w / 2) + hi);
            }
        }
    }
#else
    for (int j = 0; j < n; ++j)
        out[j] = 0;
    for (int k = 0; k < n_off; ++k)
        for (int j = 0; j < n; ++j)
            out[j] = (ushort)(out[j] + base[off[k] + j]);
#endif
}

void widenAdd(ushort* dst, const uchar* src, int n)
{
    int k = 0;
#if CV_SIMD
    const int w = v_uint8::nlanes;
    for (; k <= n - w; k += w)
    {
        v_uint16 lo, hi;
        v_expand(vx_load(src + k), lo, hi);
        v_store(dst + k, vx_load(dst + k) + lo);
        v_store(dst + k + w / 2, vx_load(dst + k + w / 2) + hi);
    }
#endif
    for (; k < n; ++k)
        dst[k] = (ushort)(dst[k] + src[k]);
}

void addBlocks16(ushort* acc, const uchar* const* src, int n, size_t stride)
{
    // 8-bit sums of up to 63 blocks (responses <= 4) in registers, then widened into acc
    for (int k = 0; k < n;)
    {
        const int end = n - k < 63 ? n : k + 63;
#if CV_SIMD256
        // two rows per vector
        v_uint8x32 a[8];
        for (int j = 0; j < 8; ++j)
            a[j] = v256_setzero_u8();
        for (; k < end; ++k)
        {
            const uchar* s = src[k];
            for (int j = 0; j < 8; ++j)
                a[j] = v_add_wrap(a[j], v256_load_halves(s + 2 * j * stride,
                                                         s + (2 * j + 1) * stride));
        }
        for (int j = 0; j < 8; ++j)
        {
            v_uint16x16 lo, hi;
            v_expand(a[j], lo, hi);
            v_store(acc + 32 * j, v256_load(acc + 32 * j) + lo);
            v_store(acc + 32 * j + 16, v256_load(acc + 32 * j + 16) + hi);
        }
#elif CV_SIMD128
        v_uint8x16 a[16];
        for (int j = 0; j < 16; ++j)
            a[j] = v_setzero_u8();
        for (; k < end; ++k)
        {
            const uchar* s = src[k];
            for (int j = 0; j < 16; ++j)
                a[j] = v_add_wrap(a[j], v_load(s + j * stride));
        }
        for (int j = 0; j < 16; ++j)
        {
            v_uint16x8 lo, hi;
            v_expand(a[j], lo, hi);
            v_store(acc + 16 * j, v_load(acc + 16 * j) + lo);
            v_store(acc + 16 * j + 8, v_load(acc + 16 * j + 8) + hi);
        }
#else
        for (; k < end; ++k)
            for (int r = 0; r < 16; ++r)
                for (int c = 0; c < 16; ++c)
                    acc[r * 16 + c] = (ushort)(acc[r * 16 + c] + src[k][r * stride + c]);
#endif
    }
}

void countLabels8(uchar* dst, const uchar* src, int n)
{
    int k = 0;
#if CV_SIMD
    const int w = v_uint8::nlanes;
    const v_uint8 z = vx_setzero_u8();
    for (; k <= n - w; k += w) // a lane of all ones (-1) where src != 0: subtracting it adds 1
        v_store(dst + k, v_sub_wrap(vx_load(dst + k), vx_load(src + k) != z));
#endif
    for (; k < n; ++k)
        dst[k] = (uchar)(dst[k] + (src[k] != 0));
}

void countAccepted8(uchar* dst, const uchar* src, int n, uchar labels, uchar zero_ok)
{
    int k = 0;
#if CV_SIMD
    const int w = v_uint8::nlanes;
    const v_uint8 z = vx_setzero_u8(), m = vx_setall_u8(labels);
    const v_uint8 zm = vx_setall_u8(zero_ok ? (uchar)255 : (uchar)0);
    for (; k <= n - w; k += w)
    {
        const v_uint8 v = vx_load(src + k);
        // (v & labels) != 0 is false where v == 0: there the value 0's entry decides
        const v_uint8 acc = ((v & m) != z) | ((v == z) & zm);
        v_store(dst + k, v_sub_wrap(vx_load(dst + k), acc));
    }
#endif
    for (; k < n; ++k)
        dst[k] = (uchar)(dst[k] + (src[k] ? (src[k] & labels) != 0 : zero_ok != 0));
}

int positionsPassing16(const ushort* src, const ushort* bar, int n, ushort threshold,
                       ushort scale, int* out)
{
    int k = 0, found = 0;
#if CV_SIMD
    const int w = v_uint16::nlanes;
    const v_uint16 t = vx_setall_u16(threshold), s = vx_setall_u16(scale);
    for (; k <= n - w; k += w)
    {
        const v_uint16 v = vx_load(src + k);
        // the passing lanes as bits, lowest lane first; one index written per set bit
        unsigned mask = (unsigned)v_signmask((v > t) & (v >= v_mul_hi(vx_load(bar + k), s)));
        for (; mask; mask &= mask - 1)
            out[found++] = k + lowestBit(mask);
    }
#endif
    for (; k < n; ++k)
        if (src[k] > threshold && src[k] >= (bar[k] * (unsigned)scale) >> 16)
            out[found++] = k;
    return found;
}

#endif // FORESTMOD_KERNELS_DECLARATIONS_ONLY

} // namespace FORESTMOD_KERNELS_NAMESPACE
} // namespace detail
} // namespace forestmod
} // namespace cv
