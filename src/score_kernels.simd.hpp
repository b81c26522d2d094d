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
void addBlocks16(ushort* acc, const uchar* const* src, int n, size_t stride);
int firstMax256(const ushort* v, ushort& best);
void countLabels8(uchar* dst, const uchar* src, int n);
void countAccepted8(uchar* dst, const uchar* src, int n, uchar labels, uchar zero_ok);
int sumRunsPassing16(ushort* sums, const uchar* base, const int* off, int n_off, int n,
                     const ushort* bar, ushort threshold, ushort scale, ushort* need, int* vec,
                     int* hits);

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

int firstMax256(const ushort* v, ushort& best)
{
    ushort b = 0;
    int k = 0;
#if CV_SIMD
    const int w = v_uint16::nlanes;
    v_uint16 m = vx_load(v);
    for (k = w; k < 256; k += w)
        m = v_max(m, vx_load(v + k));
    b = v_reduce_max(m);
    best = b;
    if (b == 0)
        return -1;
    const v_uint16 vb = vx_setall_u16(b);
    for (k = 0; k < 256; k += w) // the first vector holding the largest value
        if (v_check_any(vx_load(v + k) == vb))
            break;
#else
    for (int j = 0; j < 256; ++j)
        b = v[j] > b ? v[j] : b;
    best = b;
    if (b == 0)
        return -1;
#endif
    while (v[k] != b)
        ++k;
    return k;
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

// Asks the cache for the 256 bytes from p (the next tile's part of a run, when its vectors
// follow this tile's: 2-3 % of the 8 LM-O objects' match(), where the runs are read from L3).
// A hint: never faults, wherever p points.
static inline void prefetchNextTile(const uchar* p)
{
#if defined(__GNUC__)
    for (int b = 0; b < 256; b += 64)
        __builtin_prefetch(p + b);
#else
    CV_UNUSED(p);
#endif
}

#if CV_SIMD
// sums[x .. x + w) += the runs off[k0 .. k1) from base + x, for the vectors of positions that
// start at x = vec[0 .. n_vec) (ascending multiples of the vector width; kGathered false: every
// vector from 0, vec unused): tiles of 8 of them, their 8-bit sums of up to 63 features in
// registers, then widened (stored without adding on the first features: `fresh`).
template <bool kGathered>
static void addRunsAt(ushort* sums, const uchar* base, const int* off, int k0, int k1,
                      const int* vec, int n_vec, bool fresh)
{
    const int w = v_uint8::nlanes;
    const int kTile = 8;
    for (int t = 0; t < n_vec; t += kTile)
    {
        const int nv = n_vec - t < kTile ? n_vec - t : kTile;
        const int* x = vec + t;
        const int x0 = t * w;
        // the first position of the tile's vector j
        auto at = [&](int j) { return kGathered ? x[j] : x0 + j * w; };
        for (int k = k0; k < k1;)
        {
            const bool first = fresh && k == k0;
            const int end = k1 - k < 63 ? k1 : k + 63;
            v_uint8 a[kTile];
            for (int j = 0; j < kTile; ++j)
                a[j] = vx_setzero_u8();
            if (nv == kTile)
                for (; k < end; ++k)
                {
                    const uchar* p = base + off[k];
                    prefetchNextTile(p + at(kTile - 1) + w);
                    for (int j = 0; j < kTile; ++j)
                        a[j] = v_add_wrap(a[j], vx_load(p + at(j)));
                }
            else
                for (; k < end; ++k)
                {
                    const uchar* p = base + off[k];
                    for (int j = 0; j < nv; ++j)
                        a[j] = v_add_wrap(a[j], vx_load(p + at(j)));
                }
            for (int j = 0; j < nv; ++j)
            {
                ushort* d = sums + at(j);
                v_uint16 lo, hi;
                v_expand(a[j], lo, hi);
                v_store(d, first ? lo : vx_load(d) + lo);
                v_store(d + w / 2, first ? hi : vx_load(d + w / 2) + hi);
            }
        }
    }
}
#endif

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
    addRunsAt<false>(out, base, off, 0, n_off, 0, (n + w - 1) / w, true);
#else
    for (int j = 0; j < n; ++j)
        out[j] = 0;
    for (int k = 0; k < n_off; ++k)
        for (int j = 0; j < n; ++j)
            out[j] = (ushort)(out[j] + base[off[k] + j]);
#endif
}

int sumRunsPassing16(ushort* sums, const uchar* base, const int* off, int n_off, int n,
                     const ushort* bar, ushort threshold, ushort scale, ushort* need, int* vec,
                     int* hits)
{
    if (n <= 0)
        return 0;
    if (n_off == 0) // every sum 0: none passes
    {
        for (int j = 0; j < n; ++j)
            sums[j] = 0;
        return 0;
    }
    int found = 0;
#if CV_SIMD
    const int w = v_uint8::nlanes, h = v_uint16::nlanes;
    int n_vec = (n + w - 1) / w;
    // a position passes where its sum reaches need = max(threshold + 1, (bar x scale) >> 16)
    const v_uint16 t1 = vx_setall_u16((ushort)(threshold + 1)), s = vx_setall_u16(scale);
    const v_uint16 z = vx_setzero_u16();
    for (int i = 0; i < n_vec; ++i)
    {
        vec[i] = i * w;
        v_store(need + i * w, v_max(t1, v_mul_hi(vx_load(bar + i * w), s)));
        v_store(need + i * w + h, v_max(t1, v_mul_hi(vx_load(bar + i * w + h), s)));
    }
    for (int k = 0;;)
    {
        // the next stage of kStage features, or every feature left if fewer than kLast would
        // follow it
        const int kStage = 24, kLast = 8;
        const int k1 = n_off - k < kStage + kLast ? n_off : k + kStage;
        addRunsAt<true>(sums, base, off, k, k1, vec, n_vec, k == 0);
        if (k1 == n_off)
            break;
        // a vector stays while one of its positions may pass with the largest response (4)
        // for every feature left
        const int left = 4 * (n_off - k1);
        const v_uint16 slack = vx_setall_u16((ushort)(left < 65535 ? left : 65535));
        // (a lane reaches need where need - sum, saturated at 0, is 0: unsigned comparisons
        // cost more)
        int kept = 0;
        for (int i = 0; i < n_vec; ++i)
        {
            const int x = vec[i];
            const v_uint16 a = vx_load(need + x) - (vx_load(sums + x) + slack);
            const v_uint16 b = vx_load(need + x + h) - (vx_load(sums + x + h) + slack);
            if (v_check_any(v_min(a, b) == z))
                vec[kept++] = x;
        }
        n_vec = kept;
        k = k1;
    }
    // the passing lanes as bits, lowest lane first; one index written per set bit
    for (int i = 0; i < n_vec; ++i)
    {
        const int x = vec[i];
        unsigned mask = (unsigned)v_signmask(vx_load(need + x) - vx_load(sums + x) == z) |
                        (unsigned)v_signmask(vx_load(need + x + h) - vx_load(sums + x + h) == z)
                            << h;
        if (n - x < w)
            mask &= (1u << (n - x)) - 1u;
        for (; mask; mask &= mask - 1)
            hits[found++] = x + lowestBit(mask);
    }
#else
    CV_UNUSED(vec);
    for (int j = 0; j < n; ++j)
    {
        unsigned sum = 0;
        for (int k = 0; k < n_off; ++k)
            sum += base[off[k] + j];
        sums[j] = (ushort)sum;
        const unsigned by_bar = (bar[j] * (unsigned)scale) >> 16;
        need[j] = (ushort)(by_bar > threshold ? by_bar : threshold + 1u);
        if (sums[j] >= need[j])
            hits[found++] = j;
    }
#endif
    return found;
}

#endif // FORESTMOD_KERNELS_DECLARATIONS_ONLY

} // namespace FORESTMOD_KERNELS_NAMESPACE
} // namespace detail
} // namespace forestmod
} // namespace cv
