// This file is part of OpenCV project.
// It is subject to the license terms in the LICENSE file found in the top-level directory
// of this distribution and at http://opencv.org/license.html

// The row kernels of quantize_kernels.hpp, compiled once per instruction set as
// score_kernels.simd.hpp (OpenCV's .simd.hpp scheme): in namespace cpu_baseline by
// quantize_kernels.cpp, in opt_AVX2 by avx2/quantize_kernels.avx2.cpp. The including file
// defines FORESTMOD_KERNELS_NAMESPACE, and FORESTMOD_KERNELS_DECLARATIONS_ONLY to declare another
// build's functions. Width-agnostic universal intrinsics (16 pixels per vector of bytes with
// SSE2, 32 with AVX2); a row of at least one vector ends with a vector that overlaps the one
// before it (every kernel writes a function of its inputs only, or, for dominantLabelsRow, an
// update that a second pass leaves as it is), a shorter row takes the scalar path. Integer
// arithmetic and exact conversions: every path gives the same bits.

#include "opencv2/core/hal/intrin.hpp"

#include <math.h> // nearbyintf: a libm function, not an inline one of a C++ header

#ifndef FORESTMOD_KERNELS_NAMESPACE
#error "define FORESTMOD_KERNELS_NAMESPACE (cpu_baseline or opt_AVX2) before including this file"
#endif

namespace cv {
namespace forestmod {
namespace detail {
namespace FORESTMOD_KERNELS_NAMESPACE {

void splitRow3(const uchar* src, int n, uchar* p0, uchar* p1, uchar* p2);
void sobelStrongestPlanar(const uchar* const* up, const uchar* const* mid,
                          const uchar* const* dn, int cols, int ithr, float* fx, float* fy,
                          uchar* strong);
void orientationRow(const float* angle, int cols, uchar* onehot);
void majorityRow(const uchar* up, const uchar* mid, const uchar* dn, const uchar* strong,
                 const uchar* mask, int n, uchar* dst);
void hueBinsRow(const uchar* bgr, const uchar* mask, int cols, int smin, int vmin,
                const int* sdiv, const int* hdiv, uchar* dst);
void orRows(const uchar* first, size_t step, int n, int cols, uchar* d);
void responsesRow(const uchar* s, int cols, const uchar* within, const uchar* lut,
                  uchar* const* d);
void dominantLabelsRow(const uchar* const* rows, int nrows, int cols, int k, uchar* colsum,
                       uchar* best, uchar* d);
int normalCellsRow(const ushort* row, size_t step, int n, int distance_threshold,
                   int difference_threshold, int* cells);
void medianOneHotRow(const uchar* const* rows, int cols, uchar* planes, uchar* dst);

#ifndef FORESTMOD_KERNELS_DECLARATIONS_ONLY

// Calls body(c) for the vectors of a row of n >= w elements: c = 0, w, 2 w, ... and n - w last.
template <typename Body> static inline void overlappingVectors(int n, int w, const Body& body)
{
    for (int c = 0;; c += w)
    {
        if (c > n - w)
            c = n - w;
        body(c);
        if (c == n - w)
            break;
    }
}

void splitRow3(const uchar* src, int n, uchar* p0, uchar* p1, uchar* p2)
{
#if CV_SIMD
    if (n >= v_uint8::nlanes)
    {
        overlappingVectors(n, v_uint8::nlanes, [&](int c) {
            v_uint8 a, b, d;
            v_load_deinterleave(src + 3 * c, a, b, d);
            v_store(p0 + c, a);
            v_store(p1 + c, b);
            v_store(p2 + c, d);
        });
        return;
    }
#endif
    for (int c = 0; c < n; ++c)
    {
        p0[c] = src[3 * c];
        p1[c] = src[3 * c + 1];
        p2[c] = src[3 * c + 2];
    }
}

#if CV_SIMD
// Sobel dx, dy (16 bits) of one vector of bytes of one plane, as two halves; rows above, at,
// below; [-1] readable.
static inline void sobelVector(const uchar* up, const uchar* mid, const uchar* dn, v_int16& dx0,
                               v_int16& dx1, v_int16& dy0, v_int16& dy1)
{
    v_uint16 a0, a1, b0, b1, c0, c1;
    v_expand(vx_load(up - 1), a0, a1);
    v_expand(vx_load(up), b0, b1);
    v_expand(vx_load(up + 1), c0, c1);
    const v_int16 ul0 = v_reinterpret_as_s16(a0), ul1 = v_reinterpret_as_s16(a1);
    const v_int16 ur0 = v_reinterpret_as_s16(c0), ur1 = v_reinterpret_as_s16(c1);
    const v_int16 us0 = ul0 + ur0 + v_reinterpret_as_s16(b0 + b0);
    const v_int16 us1 = ul1 + ur1 + v_reinterpret_as_s16(b1 + b1);
    dx0 = ur0 - ul0;
    dx1 = ur1 - ul1;
    v_expand(vx_load(mid - 1), a0, a1);
    v_expand(vx_load(mid + 1), c0, c1);
    const v_int16 m0 = v_reinterpret_as_s16(c0) - v_reinterpret_as_s16(a0);
    const v_int16 m1 = v_reinterpret_as_s16(c1) - v_reinterpret_as_s16(a1);
    dx0 += m0 + m0;
    dx1 += m1 + m1;
    v_expand(vx_load(dn - 1), a0, a1);
    v_expand(vx_load(dn), b0, b1);
    v_expand(vx_load(dn + 1), c0, c1);
    const v_int16 dl0 = v_reinterpret_as_s16(a0), dl1 = v_reinterpret_as_s16(a1);
    const v_int16 dr0 = v_reinterpret_as_s16(c0), dr1 = v_reinterpret_as_s16(c1);
    dx0 += dr0 - dl0;
    dx1 += dr1 - dl1;
    dy0 = (dl0 + dr0 + v_reinterpret_as_s16(b0 + b0)) - us0;
    dy1 = (dl1 + dr1 + v_reinterpret_as_s16(b1 + b1)) - us1;
}

// One vector of 16-bit pixels: the channel of largest dx^2 + dy^2 (ties: the first), its dx, dy
// as float and whether its magnitude passes the threshold (0xFF / 0).
static inline void selectStrongest(const v_int16* x, const v_int16* y, const v_int32& vthr,
                                   float* fx, float* fy, uchar* strong)
{
    v_int32 ml[3], mh[3];
    for (int ch = 0; ch < 3; ++ch)
    {
        v_int16 z0, z1;
        v_zip(x[ch], y[ch], z0, z1);
        ml[ch] = v_dotprod(z0, z0);
        mh[ch] = v_dotprod(z1, z1);
    }
    const v_int32 s0l = (ml[0] >= ml[1]) & (ml[0] >= ml[2]);
    const v_int32 s0h = (mh[0] >= mh[1]) & (mh[0] >= mh[2]);
    const v_int32 s1l = (ml[1] >= ml[0]) & (ml[1] >= ml[2]);
    const v_int32 s1h = (mh[1] >= mh[0]) & (mh[1] >= mh[2]);
    const v_int32 mlow = v_select(s0l, ml[0], v_select(s1l, ml[1], ml[2]));
    const v_int32 mhigh = v_select(s0h, mh[0], v_select(s1h, mh[1], mh[2]));
    const v_int16 s0 = v_pack(s0l, s0h), s1 = v_pack(s1l, s1h);
    const v_int16 xs = v_select(s0, x[0], v_select(s1, x[1], x[2]));
    const v_int16 ys = v_select(s0, y[0], v_select(s1, y[1], y[2]));
    const int h = v_float32::nlanes;
    v_int32 lo, hi;
    v_expand(xs, lo, hi);
    v_store(fx, v_cvt_f32(lo));
    v_store(fx + h, v_cvt_f32(hi));
    v_expand(ys, lo, hi);
    v_store(fy, v_cvt_f32(lo));
    v_store(fy + h, v_cvt_f32(hi));
    v_pack_store(reinterpret_cast<schar*>(strong), v_pack(mlow > vthr, mhigh > vthr));
}
#endif

void sobelStrongestPlanar(const uchar* const* up, const uchar* const* mid,
                          const uchar* const* dn, int cols, int ithr, float* fx, float* fy,
                          uchar* strong)
{
#if CV_SIMD
    const int w = v_uint8::nlanes;
    if (cols >= w)
    {
        const v_int32 vthr = vx_setall_s32(ithr);
        overlappingVectors(cols, w, [&](int c) {
            v_int16 x0[3], x1[3], y0[3], y1[3];
            for (int ch = 0; ch < 3; ++ch)
                sobelVector(up[ch] + c, mid[ch] + c, dn[ch] + c, x0[ch], x1[ch], y0[ch], y1[ch]);
            selectStrongest(x0, y0, vthr, fx + c, fy + c, strong + c);
            selectStrongest(x1, y1, vthr, fx + c + w / 2, fy + c + w / 2, strong + c + w / 2);
        });
        return;
    }
#endif
    for (int c = 0; c < cols; ++c)
    {
        int best_m = -1, bx = 0, by = 0;
        for (int ch = 0; ch < 3; ++ch)
        {
            const uchar* u = up[ch] + c;
            const uchar* m = mid[ch] + c;
            const uchar* d = dn[ch] + c;
            const int dx = (u[1] - u[-1]) + 2 * (m[1] - m[-1]) + (d[1] - d[-1]);
            const int dy = (d[-1] + 2 * d[0] + d[1]) - (u[-1] + 2 * u[0] + u[1]);
            const int mag = dx * dx + dy * dy;
            if (mag > best_m) // strictly greater: ties keep the first channel
            {
                best_m = mag;
                bx = dx;
                by = dy;
            }
        }
        fx[c] = (float)bx;
        fy[c] = (float)by;
        strong[c] = best_m > ithr ? 255 : 0;
    }
}

void orientationRow(const float* angle, int cols, uchar* onehot)
{
    const float scale = (float)(16.0 / 360.0); // what convertTo(CV_8U, 16.0 / 360.0) uses
#if CV_SIMD
    const int w = v_uint8::nlanes, q = v_float32::nlanes;
    if (cols >= w)
    {
        const v_float32 vs = vx_setall_f32(scale);
        const v_uint8 seven = vx_setall_u8(7);
        overlappingVectors(cols, w, [&](int c) {
            const v_int32 i0 = v_round(vx_load(angle + c) * vs);
            const v_int32 i1 = v_round(vx_load(angle + c + q) * vs);
            const v_int32 i2 = v_round(vx_load(angle + c + 2 * q) * vs);
            const v_int32 i3 = v_round(vx_load(angle + c + 3 * q) * vs);
            const v_uint8 bin = v_pack_u(v_pack(i0, i1), v_pack(i2, i3)) & seven;
            v_uint8 oh = vx_setzero_u8();
            for (int k = 0; k < 8; ++k)
                oh |= (bin == vx_setall_u8((uchar)k)) & vx_setall_u8((uchar)(1 << k));
            v_store(onehot + c, oh);
        });
        return;
    }
#endif
    for (int c = 0; c < cols; ++c)
    {
        // saturate_cast<uchar>: rounded to nearest even (as cvRound), then clamped; no inline
        // function of OpenCV's headers here (see score_kernels.simd.hpp)
        const float r = nearbyintf(angle[c] * scale);
        const int bin = r < 0.f ? 0 : (r > 255.f ? 255 : (int)r);
        onehot[c] = (uchar)(1 << (bin & 7));
    }
}

// 1 << bin where at least 5 of the 3x3 one-hot labels around a pixel share the bin, else 0:
// per bit, a bit-sliced count of the 9 neighbours (full adders on bytes), >= 5 when
// bit3 | (bit2 & (bit1 | bit0)). At most one bin can reach 5 of 9.
template <typename V> static inline V majority9(const V& a0, const V& a1, const V& a2,
                                                 const V& b0, const V& b1, const V& b2,
                                                 const V& c0, const V& c1, const V& c2)
{
    // each row: 2-bit count (s weight 1, k weight 2)
    const V xa = a0 ^ a1, xb = b0 ^ b1, xc = c0 ^ c1;
    const V sa = xa ^ a2, ka = (a0 & a1) | (a2 & xa);
    const V sb = xb ^ b2, kb = (b0 & b1) | (b2 & xb);
    const V sc = xc ^ c2, kc = (c0 & c1) | (c2 & xc);
    // sum of the rows
    const V xs = sa ^ sb, xk = ka ^ kb;
    const V bit0 = xs ^ sc;
    const V c1w2 = (sa & sb) | (sc & xs); // weight 2
    const V s2 = xk ^ kc;                  // weight 2
    const V c2w4 = (ka & kb) | (kc & xk);  // weight 4
    const V bit1 = c1w2 ^ s2;
    const V t = c1w2 & s2; // weight 4
    const V bit2 = c2w4 ^ t;
    const V bit3 = c2w4 & t;
    return bit3 | (bit2 & (bit1 | bit0));
}

void majorityRow(const uchar* up, const uchar* mid, const uchar* dn, const uchar* strong,
                 const uchar* mask, int n, uchar* dst)
{
#if CV_SIMD
    if (n >= v_uint8::nlanes)
    {
        const v_uint8 z = vx_setzero_u8();
        overlappingVectors(n, v_uint8::nlanes, [&](int c) {
            v_uint8 v = majority9(vx_load(up + c - 1), vx_load(up + c), vx_load(up + c + 1),
                                  vx_load(mid + c - 1), vx_load(mid + c), vx_load(mid + c + 1),
                                  vx_load(dn + c - 1), vx_load(dn + c), vx_load(dn + c + 1));
            v &= vx_load(strong + c);
            if (mask)
                v = v_select(vx_load(mask + c) == z, z, v);
            v_store(dst + c, v);
        });
        return;
    }
#endif
    for (int c = 0; c < n; ++c)
    {
        uchar v = majority9<uchar>(up[c - 1], up[c], up[c + 1], mid[c - 1], mid[c], mid[c + 1],
                                   dn[c - 1], dn[c], dn[c + 1]);
        v &= strong[c];
        if (mask && !mask[c])
            v = 0;
        dst[c] = v;
    }
}

// OpenCV's 8-bit HSV of a pixel as its color_hsv code computes it (hsv_shift 12): v the largest
// channel, diff = v - the smallest, the sector's numerator (red first, then green, then blue),
// h = round(numerator * hdiv[diff]), s = round(diff * sdiv[v]).
static inline int hsvNumerator(int b, int g, int r, int v, int diff)
{
    return v == r ? g - b : v == g ? b - r + 2 * diff : r - g + 4 * diff;
}

#if CV_SIMD
// h and s of 8 / 16 pixels (32-bit lanes) from their numerators, diffs and values. The divisors
// are the float quotients rounded to nearest, not table reads (gathers): equal to the tables'
// for every divisor 1..255 (test hue_bins_equal_cvtColor_on_every_colour); a divisor 0 comes
// with a numerator 0, and the product is 0 whatever the quotient.
static inline void hsvQuarter(const v_int32& num, const v_int32& diff, const v_int32& v,
                              v_int32& h, v_int32& s)
{
    const v_int32 half = vx_setall_s32(1 << 11), z = vx_setzero_s32();
    const v_int32 hd = v_round(vx_setall_f32(180 * 4096 / 6.f) / v_cvt_f32(diff));
    const v_int32 sd = v_round(vx_setall_f32(255 * 4096.f) / v_cvt_f32(v));
    h = (num * hd + half) >> 12;
    h += (h < z) & vx_setall_s32(180);
    s = (diff * sd + half) >> 12;
}

// The sector numerators of a half vector of pixels (16-bit lanes; isr, isg: 0 / -1).
static inline v_int16 hsvNumerators(const v_uint16& b, const v_uint16& g, const v_uint16& r,
                                    const v_uint16& diff, const v_int16& isr, const v_int16& isg)
{
    const v_int16 B = v_reinterpret_as_s16(b), G = v_reinterpret_as_s16(g);
    const v_int16 R = v_reinterpret_as_s16(r), D = v_reinterpret_as_s16(diff);
    const v_int16 D2 = D + D;
    return v_select(isr, G - B, v_select(isg, B - R + D2, R - G + (D2 + D2)));
}

// 1 << hueBin(h) where h < 180, s >= smin, v >= vmin, else 0 (bytes).
static inline v_uint8 hueLabels(const v_uint8& h, const v_uint8& s, const v_uint8& v, int smin,
                                int vmin)
{
    // hueBin(h) = ((4 h + 45) / 90) & 7 changes at h = 12, 34, 57, 79, 102, 124, 147, 169; bin 0
    // also covers [169, 180)
    static const uchar edges[9] = { 0, 12, 34, 57, 79, 102, 124, 147, 169 };
    v_uint8 oh = (h >= vx_setall_u8(edges[8])) & (h < vx_setall_u8(180)) & vx_setall_u8(1);
    for (int k = 0; k < 8; ++k)
    {
        const v_uint8 in = (h >= vx_setall_u8(edges[k])) & (h < vx_setall_u8(edges[k + 1]));
        oh |= in & vx_setall_u8((uchar)(1 << k));
    }
    const v_uint8 vs = vx_setall_u8((uchar)(smin < 255 ? smin : 255));
    const v_uint8 vv = vx_setall_u8((uchar)(vmin < 255 ? vmin : 255));
    return oh & (s >= vs) & (v >= vv);
}
#endif

void hueBinsRow(const uchar* bgr, const uchar* mask, int cols, int smin, int vmin,
                const int* sdiv, const int* hdiv, uchar* dst)
{
#if CV_SIMD
    if (cols >= v_uint8::nlanes)
    {
        const v_uint8 z = vx_setzero_u8();
        overlappingVectors(cols, v_uint8::nlanes, [&](int c) {
            v_uint8 b, g, r;
            v_load_deinterleave(bgr + 3 * c, b, g, r);
            const v_uint8 v = v_max(v_max(b, g), r);
            const v_uint8 diff = v - v_min(v_min(b, g), r);
            const v_uint8 isr = v == r, isg = (v == g) & ~isr;
            v_uint16 b16[2], g16[2], r16[2], d16[2], v16[2];
            v_int16 isr16[2], isg16[2];
            v_expand(b, b16[0], b16[1]);
            v_expand(g, g16[0], g16[1]);
            v_expand(r, r16[0], r16[1]);
            v_expand(diff, d16[0], d16[1]);
            v_expand(v, v16[0], v16[1]);
            v_expand(v_reinterpret_as_s8(isr), isr16[0], isr16[1]); // sign-extended: 0 / -1
            v_expand(v_reinterpret_as_s8(isg), isg16[0], isg16[1]);
            v_int16 h16[2], s16[2];
            for (int half = 0; half < 2; ++half)
            {
                const v_int16 num = hsvNumerators(b16[half], g16[half], r16[half], d16[half],
                                                  isr16[half], isg16[half]);
                v_int32 n32[2];
                v_uint32 d32[2], v32[2];
                v_expand(num, n32[0], n32[1]);
                v_expand(d16[half], d32[0], d32[1]);
                v_expand(v16[half], v32[0], v32[1]);
                v_int32 h[2], s[2];
                for (int q = 0; q < 2; ++q)
                    hsvQuarter(n32[q], v_reinterpret_as_s32(d32[q]), v_reinterpret_as_s32(v32[q]),
                               h[q], s[q]);
                h16[half] = v_pack(h[0], h[1]);
                s16[half] = v_pack(s[0], s[1]);
            }
            v_uint8 oh = hueLabels(v_pack_u(h16[0], h16[1]), v_pack_u(s16[0], s16[1]), v, smin,
                                   vmin);
            if (mask)
                oh = v_select(vx_load(mask + c) == z, z, oh);
            v_store(dst + c, oh);
        });
        return;
    }
#endif
    static const uchar edges[9] = { 0, 12, 34, 57, 79, 102, 124, 147, 169 };
    for (int c = 0; c < cols; ++c)
    {
        const int b = bgr[3 * c], g = bgr[3 * c + 1], r = bgr[3 * c + 2];
        const int bg_max = b > g ? b : g, bg_min = b < g ? b : g;
        const int v = bg_max > r ? bg_max : r;
        const int diff = v - (bg_min < r ? bg_min : r);
        int h = (hsvNumerator(b, g, r, v, diff) * hdiv[diff] + (1 << 11)) >> 12;
        if (h < 0)
            h += 180;
        const int s = (diff * sdiv[v] + (1 << 11)) >> 12;
        uchar q = 0;
        if (h < 180 && s >= smin && v >= vmin)
        {
            int bin = 0;
            for (int k = 1; k < 8; ++k)
                if (h >= edges[k] && h < edges[k + 1])
                    bin = k;
            q = (uchar)(1 << bin);
        }
        if (mask && !mask[c])
            q = 0;
        dst[c] = q;
    }
}

void orRows(const uchar* first, size_t step, int n, int cols, uchar* d)
{
#if CV_SIMD
    if (cols >= v_uint8::nlanes)
    {
        overlappingVectors(cols, v_uint8::nlanes, [&](int c) {
            v_uint8 acc = vx_load(first + c);
            for (int k = 1; k < n; ++k)
                acc |= vx_load(first + k * step + c);
            v_store(d + c, acc);
        });
        return;
    }
#endif
    for (int c = 0; c < cols; ++c)
    {
        uchar acc = 0;
        for (int k = 0; k < n; ++k)
            acc |= first[k * step + c];
        d[c] = acc;
    }
}

void responsesRow(const uchar* s, int cols, const uchar* within, const uchar* lut,
                  uchar* const* d)
{
#if CV_SIMD
    if (cols >= v_uint8::nlanes)
    {
        const v_uint8 z = vx_setzero_u8(), four = vx_setall_u8(4);
        overlappingVectors(cols, v_uint8::nlanes, [&](int c) {
            const v_uint8 x = vx_load(s + c);
            for (int o = 0; o < 8; ++o)
            {
                // each empty set adds 0xFF (-1)
                const uchar* wo = within + 4 * o;
                v_uint8 v = v_add_wrap(four, (x & vx_setall_u8(wo[0])) == z);
                v = v_add_wrap(v, (x & vx_setall_u8(wo[1])) == z);
                v = v_add_wrap(v, (x & vx_setall_u8(wo[2])) == z);
                v = v_add_wrap(v, (x & vx_setall_u8(wo[3])) == z);
                v_store(d[o] + c, v);
            }
        });
        return;
    }
#endif
    for (int c = 0; c < cols; ++c)
        for (int o = 0; o < 8; ++o)
            d[o][c] = lut[256 * o + s[c]];
}

void dominantLabelsRow(const uchar* const* rows, int nrows, int cols, int k, uchar* colsum,
                       uchar* best, uchar* d)
{
    const int a = k / 2;
    const uchar* first = colsum - a; // the window of x: colsum[x - a, x - a + k)
    for (int c = 0; c < cols; ++c)
        best[c] = d[c] = 0;
    for (int b = 0; b < 8; ++b)
    {
        const uchar bit = (uchar)(1 << b);
#if CV_SIMD
        if (cols >= v_uint8::nlanes)
        {
            const v_uint8 vbit = vx_setall_u8(bit);
            // per column: how many of the window's rows have the bit (a set bit gives 0xFF:
            // subtracting adds 1)
            overlappingVectors(cols, v_uint8::nlanes, [&](int c) {
                v_uint8 acc = vx_setzero_u8();
                for (int r = 0; r < nrows; ++r)
                    acc = v_sub_wrap(acc, (vx_load(rows[r] + c) & vbit) == vbit);
                v_store(colsum + c, acc);
            });
            // the window's count; a larger count than the bits before takes the pixel
            overlappingVectors(cols, v_uint8::nlanes, [&](int c) {
                v_uint8 cnt = vx_load(first + c);
                for (int j = 1; j < k; ++j)
                    cnt += vx_load(first + c + j);
                const v_uint8 bc = vx_load(best + c);
                const v_uint8 gt = cnt > bc;
                v_store(best + c, v_select(gt, cnt, bc));
                v_store(d + c, v_select(gt, vbit, vx_load(d + c)));
            });
            continue;
        }
#endif
        for (int c = 0; c < cols; ++c)
        {
            int acc = 0;
            for (int r = 0; r < nrows; ++r)
                acc += (rows[r][c] & bit) ? 1 : 0;
            colsum[c] = (uchar)acc;
        }
        for (int c = 0; c < cols; ++c)
        {
            int cnt = 0;
            for (int j = 0; j < k; ++j)
                cnt += first[c + j];
            if (cnt > best[c])
            {
                best[c] = (uchar)cnt;
                d[c] = bit;
            }
        }
    }
}

int normalCellsRow(const ushort* row, size_t step, int n, int distance_threshold,
                   int difference_threshold, int* cells)
{
    int x = 0;
#if CV_SIMD
    enum { R = 5, G = 20, CELLS = 21 }; // quantize_fast.cpp's NORMAL_R, NORMAL_G, NORMAL_CELLS
    // a vector of pixels in 16 bits (differences that count are below 240, counts and sums stay
    // below 2^15), products in 32 bits, the normal in float as cv::linemod
    const int w = v_uint16::nlanes, h4 = v_int32::nlanes;
    const v_uint16 vdiff = vx_setall_u16((ushort)difference_threshold);
    const bool all_near = distance_threshold > 65535;
    const v_uint16 vdist = vx_setall_u16((ushort)(all_near ? 65535 : distance_threshold));
    const v_int16 z16 = vx_setzero_s16();
    const v_int32 z = vx_setzero_s32();
    const v_float32 half = vx_setall_f32((float)(G / 2));
    const v_float32 g = vx_setall_f32((float)G), fone = vx_setall_f32(1.f);
    const v_float32 fz = vx_setzero_f32();
    const v_int32 cells_v = vx_setall_s32(CELLS), k1150 = vx_setall_s32(1150);
    const ptrdiff_t up = -(ptrdiff_t)(R * step), dn = (ptrdiff_t)(R * step);
    const ptrdiff_t offs[8] = { up - R, up, up + R, -R, R, dn - R, dn, dn + R };
    for (; x <= n - w; x += w)
    {
        const ushort* p = row + x;
        const v_uint16 d = vx_load(p);
        // the 8 neighbours: f (0 / -1) where |depth difference| < threshold, fd = f delta
        v_int16 f[8], fd[8];
        for (int k = 0; k < 8; ++k)
        {
            const v_uint16 nb = vx_load(p + offs[k]);
            const v_uint16 pos = nb - d, neg = d - nb; // saturating
            f[k] = v_reinterpret_as_s16((pos | neg) < vdiff);
            fd[k] = f[k] & v_sub_wrap(v_reinterpret_as_s16(pos), v_reinterpret_as_s16(neg));
        }
        // neighbours: 0 (-R,-R) 1 (0,-R) 2 (R,-R) 3 (-R,0) 4 (R,0) 5 (-R,R) 6 (0,R) 7 (R,R)
        const v_int16 nx_count = z16 - (f[0] + f[3] + f[5] + f[2] + f[4] + f[7]);
        const v_int16 ny_count = z16 - (f[0] + f[1] + f[2] + f[5] + f[6] + f[7]);
        const v_int16 A0 = v_mul_wrap(vx_setall_s16(R * R), nx_count);
        const v_int16 A3 = v_mul_wrap(vx_setall_s16(R * R), ny_count);
        const v_int16 A1 = v_mul_wrap(vx_setall_s16(R * R), (f[2] + f[5]) - (f[0] + f[7]));
        const v_int16 b0
            = v_mul_wrap(vx_setall_s16(R), (fd[2] + fd[4] + fd[7]) - (fd[0] + fd[3] + fd[5]));
        const v_int16 b1
            = v_mul_wrap(vx_setall_s16(R), (fd[5] + fd[6] + fd[7]) - (fd[0] + fd[1] + fd[2]));
        const v_int16 det = v_sub_wrap(v_mul_wrap(A0, A3), v_mul_wrap(A1, A1)); // <= 22500
        v_int32 p0, p1, q0, q1;
        v_mul_expand(A3, b0, p0, p1);
        v_mul_expand(A1, b1, q0, q1);
        const v_int32 ddx0 = p0 - q0, ddx1 = p1 - q1;
        v_mul_expand(A0, b1, p0, p1);
        v_mul_expand(A1, b0, q0, q1);
        const v_int32 ddy0 = p0 - q0, ddy1 = p1 - q1;
        v_uint32 dd0, dd1; // det * d < 22500 * 65536
        v_mul_expand(v_reinterpret_as_u16(det), d, dd0, dd1);
        const v_uint16 valid16 = all_near ? vx_setall_u16(0xffff) : (d < vdist);
        v_int32 valid0, valid1; // sign-extended: all ones stay all ones
        v_expand(v_reinterpret_as_s16(valid16), valid0, valid1);
        for (int h = 0; h < 2; ++h)
        {
            // separate multiplications and additions: built with -ffp-contract=off, no FMA
            v_float32 nx = v_cvt_f32(k1150 * (h ? ddx1 : ddx0));
            v_float32 ny = v_cvt_f32(k1150 * (h ? ddy1 : ddy0));
            v_float32 nzv = v_cvt_f32(z - v_reinterpret_as_s32(h ? dd1 : dd0));
            const v_float32 norm = v_sqrt(nx * nx + ny * ny + nzv * nzv);
            const v_float32 ok = (norm > fz) & v_reinterpret_as_f32(h ? valid1 : valid0);
            const v_float32 inv = fone / v_select(ok, norm, fone);
            nx = nx * inv;
            ny = ny * inv;
            nzv = nzv * inv;
            const v_int32 i1 = v_trunc(nx * half + half);
            const v_int32 i2 = v_trunc(ny * half + half);
            const v_int32 i3 = v_trunc(nzv * g + g);
            v_int32 idx = (i3 * cells_v + i2) * cells_v + i1;
            idx = v_select(v_reinterpret_as_s32(ok), idx, vx_setall_s32(-1));
            v_store(cells + x + h * h4, idx);
        }
    }
#else
    (void)row; (void)step; (void)n; (void)distance_threshold; (void)difference_threshold;
    (void)cells;
#endif
    return x;
}

// The 5x5 median of one-hot labels (0 or 1 << j), bit-sliced: a label's byte of "below" bits
// (bit k set when label < 1 << k) is summed over the window per bit position with full adders
// (column sums of 5 rows in 3 bit planes, then 5 columns), bit k of the result tells whether at
// least 13 of the 25 labels are below 1 << k, and the median is the label just under the lowest
// such bit. Bitwise operations only: the same code serves vectors and single bytes.
template <typename T> static inline void fullAdd(const T& a, const T& b, const T& c, T& sum,
                                                 T& carry)
{
    const T t = a ^ b;
    sum = t ^ c;
    carry = (a & b) | (t & c);
}

// bit k of the result: at least 13 of the 25 labels of the window below 1 << k. a..e: the
// 3-bit column counts (planes [0], [1], [2]) of the window's 5 columns.
template <typename T> static inline T atLeast13(const T* a, const T* b, const T* c, const T* d,
                                               const T* e)
{
    T s, k0a, t0, k0b;
    fullAdd(a[0], b[0], c[0], s, k0a);
    fullAdd(s, d[0], e[0], t0, k0b);
    T s1, k1a, s2, k1b, t1, k1c;
    fullAdd(a[1], b[1], c[1], s1, k1a);
    fullAdd(d[1], e[1], k0a, s2, k1b);
    fullAdd(s1, s2, k0b, t1, k1c);
    T u1, m1, u2, m2, u3, m3;
    fullAdd(a[2], b[2], c[2], u1, m1);
    fullAdd(d[2], e[2], k1a, u2, m2);
    fullAdd(k1b, k1c, u1, u3, m3);
    const T t2 = u2 ^ u3, m4 = u2 & u3;
    T v1, n1;
    fullAdd(m1, m2, m3, v1, n1);
    const T t3 = v1 ^ m4, t4 = n1 | (v1 & m4); // the count: t4 t3 t2 t1 t0 in binary
    return t4 | (t3 & t2 & (t1 | t0));
}

void medianOneHotRow(const uchar* const* rows, int cols, uchar* planes, uchar* dst)
{
    // column counts of "below" bits, 3 bit planes of cols + 4 bytes (2 replicated each side)
    const int W = cols + 4;
    uchar* p[3] = { planes, planes + W, planes + 2 * W };
#if CV_SIMD
    const bool vectors = cols >= v_uint8::nlanes;
    const v_uint8 z = vx_setzero_u8(), one = vx_setall_u8(1);
    if (vectors)
        overlappingVectors(cols, v_uint8::nlanes, [&](int c) {
            v_uint8 below[5];
            for (int k = 0; k < 5; ++k)
            {
                const v_uint8 x = vx_load(rows[k] + c);
                below[k] = (x == z) | ~v_sub_wrap(v_add_wrap(x, x), one);
            }
            v_uint8 s, c1, b0, c2;
            fullAdd(below[0], below[1], below[2], s, c1);
            fullAdd(s, below[3], below[4], b0, c2);
            v_store(p[0] + c + 2, b0);
            v_store(p[1] + c + 2, c1 ^ c2);
            v_store(p[2] + c + 2, c1 & c2);
        });
#else
    const bool vectors = false;
#endif
    for (int c = 0; c < (vectors ? 0 : cols); ++c)
    {
        int below[5];
        for (int k = 0; k < 5; ++k)
        {
            const int x = rows[k][c];
            below[k] = x == 0 ? 0xFF : ~(2 * x - 1) & 0xFF;
        }
        int s, c1, b0, c2;
        fullAdd(below[0], below[1], below[2], s, c1);
        fullAdd(s, below[3], below[4], b0, c2);
        p[0][c + 2] = (uchar)b0;
        p[1][c + 2] = (uchar)(c1 ^ c2);
        p[2][c + 2] = (uchar)(c1 & c2);
    }
    for (int k = 0; k < 3; ++k)
    {
        p[k][0] = p[k][1] = p[k][2];
        p[k][cols + 2] = p[k][cols + 3] = p[k][cols + 1];
    }
#if CV_SIMD
    if (vectors)
    {
        const v_uint8 lo7 = vx_setall_u8(0x7F), top = vx_setall_u8(0x80);
        overlappingVectors(cols, v_uint8::nlanes, [&](int c) {
            v_uint8 w[5][3];
            for (int i = 0; i < 5; ++i)
                for (int k = 0; k < 3; ++k)
                    w[i][k] = vx_load(p[k] + c + i);
            const v_uint8 r = atLeast13(w[0], w[1], w[2], w[3], w[4]);
            // the lowest set bit of r, halved; 128 where no bit is set
            const v_uint8 low = r & v_sub_wrap(z, r);
            const v_uint8 half = v_reinterpret_as_u8(v_reinterpret_as_u16(low) >> 1) & lo7;
            v_store(dst + c, half | ((r == z) & top));
        });
        return;
    }
#endif
    for (int c = 0; c < cols; ++c)
    {
        int w[5][3];
        for (int i = 0; i < 5; ++i)
            for (int k = 0; k < 3; ++k)
                w[i][k] = p[k][c + i];
        const int r = atLeast13(w[0], w[1], w[2], w[3], w[4]) & 0xFF;
        dst[c] = (uchar)(r ? (r & -r) >> 1 : 0x80);
    }
}

#endif // FORESTMOD_KERNELS_DECLARATIONS_ONLY

} // namespace FORESTMOD_KERNELS_NAMESPACE
} // namespace detail
} // namespace forestmod
} // namespace cv
