// This file is part of OpenCV project.
// It is subject to the license terms in the LICENSE file found in the top-level directory
// of this distribution and at http://opencv.org/license.html

// Bit-exact fast quantization of the standard modalities, vectorised spreading and response maps
// (quantize_fast.hpp). What each step must reproduce:
//
// ColorGradient (LINEMOD 2.2): 7x7 Gaussian blur (BORDER_REPLICATE), 3x3 Sobel per channel
// (16-bit, BORDER_REPLICATE), per pixel the channel of largest dx^2 + dy^2 (ties: the first),
// cv::phase in degrees of that channel's (dx, dy), rounded to 16 bins (x 16/360, round to
// nearest even) and folded to 8 (& 7), image border set to bin 0; a pixel keeps its bin
// (1 << bin) when its magnitude is above weak_threshold^2 and at least 5 of its 3x3 neighbours
// share a bin; the border rows and columns stay 0. The level's mask (INTER_NEAREST of the
// previous one) zeroes the rest.
//
// ColorHue: optional Gaussian blur (BORDER_REPLICATE), HSV (cv::cvtColor's 8-bit integer
// arithmetic, computed in the row kernel), 1 << hueBin(h) where s and v pass their thresholds,
// masked.
//
// The OpenCV functions used here are called on whole images or on images of whole rows that
// OpenCV treats exactly as the full image (the same code path for every pixel), so their
// results do not depend on how the frame is cut into stripes.

#include "precomp.hpp"
#include "quantize_fast.hpp"
#include "quantize_kernels.hpp"
#include "search_index.hpp"

#include "opencv2/core/hal/hal.hpp"
#include "opencv2/core/hal/intrin.hpp"

#include <atomic>
#include <mutex>
#include <typeinfo>

namespace cv {
namespace forestmod {
namespace detail {

using linemod::Modality;

namespace {
bool depthNormalReady(const ModalityInfo& info);
} // namespace

ModalityInfo classifyModality(const Ptr<Modality>& modality)
{
    ModalityInfo info;
    if (!modality)
        return info;
    const Modality& m = *modality;
    if (typeid(m) == typeid(linemod::ColorGradient))
    {
        const linemod::ColorGradient& g = static_cast<const linemod::ColorGradient&>(m);
        info.kind = MODALITY_COLOR_GRADIENT;
        info.weak_threshold = g.weak_threshold;
    }
    else if (typeid(m) == typeid(linemod::DepthNormal))
    {
        const linemod::DepthNormal& d = static_cast<const linemod::DepthNormal&>(m);
        info.kind = MODALITY_DEPTH_NORMAL;
        info.distance_threshold = d.distance_threshold;
        info.difference_threshold = d.difference_threshold;
        depthNormalReady(info); // reads cv::linemod's normal labels now, not at the first frame
    }
    else if (typeid(m) == typeid(ColorHue))
    {
        const ColorHue::Params& p = static_cast<const ColorHue&>(m).getParams();
        info.kind = MODALITY_COLOR_HUE;
        info.saturation_threshold = p.saturation_threshold;
        info.value_threshold = p.value_threshold;
        info.blur_size = p.blur_size;
    }
    return info;
}


namespace {

// Stripes for parallel_for_: one per thread is not enough to balance a shared machine; a stripe
// recomputes a few context rows, so not too many either; a multiple of the threads when there
// are that many (7 equal stripes on 2 threads keep one thread busy for 4 of them).
int stripesFor(int rows, int cols, int min_rows)
{
    const int threads = getNumThreads();
    if (threads <= 1 || cols < 32 || rows < 2 * min_rows)
        return 1;
    const int n = std::max(1, std::min(rows / min_rows, 4 * threads));
    return n >= threads ? n - n % threads : n;
}

// `n` stripes rounded up to a multiple of the threads.
int roundUpToThreads(int n)
{
    const int threads = std::max(1, getNumThreads());
    return (n + threads - 1) / threads * threads;
}

// Rows [a, b) of `src` as an image of its own (not a submatrix): OpenCV's filters then treat
// them exactly as a whole image, with `border` replicated at their first and last rows. When the
// source itself is a submatrix (a ROI the caller passed), a ROI of it keeps that behaviour.
Mat rowsAsImage(const Mat& src, int a, int b)
{
    if (src.isSubmatrix())
        return src.rowRange(a, b);
    return Mat(b - a, src.cols, src.type(), const_cast<uchar*>(src.ptr(a)), src.step);
}

// The same for a rectangle: pixels beyond it are never read, its edges replicated.
Mat rectAsImage(const Mat& src, const Rect& r)
{
    if (src.isSubmatrix())
        return src(r);
    return Mat(r.height, r.width, src.type(), const_cast<uchar*>(src.ptr(r.y, r.x)), src.step);
}

// ------------------------------------------------------------------------------------------
// ColorGradient

// Scratch memory of the calling thread, kept between calls (fresh buffers of a few MB per frame
// cost more in page faults than the work done in them). slot: one per buffer in use at a time.
enum { SCRATCH_SLOTS = 8 };
Mat scratch(int slot, int rows, int cols, int type)
{
    static thread_local std::vector<uchar> pool[SCRATCH_SLOTS];
    CV_DbgAssert(slot >= 0 && slot < SCRATCH_SLOTS);
    const size_t need = (size_t)rows * cols * CV_ELEM_SIZE(type) + CV_SIMD_WIDTH + 64;
    std::vector<uchar>& buf = pool[slot];
    if (buf.size() < need)
        buf.resize(need);
    return Mat(rows, cols, type, alignPtr(&buf[0], 64));
}

// Output pixels `out` of one level, in blocks of `block` rows: blur around the rectangle, then per
// block Sobel, strongest channel, phase, one-hot bins and the 3x3 vote. Equal there to the
// whole image's computation: the blur reads 3 real pixels beyond what the Sobel reads (or
// replicates the image's own edge), the Sobel and the vote 1. cv::phase must see at least 32
// values per call (see quantizeGradientLevel): whole-image stripes and tiles do.
void gradientRect(const Mat& src, const Mat& mask, int ithr, int block, Rect out, Mat& dst)
{
    const int rows = src.rows, cols = src.cols;
    const int a = out.y, b = out.y + out.height;
    // columns: Sobel and one-hot bins [kx0, kx1), smoothed [bx0, bx1), blurred from [gx0, gx1)
    const int kx0 = std::max(out.x - 1, 0), kx1 = std::min(out.x + out.width + 1, cols);
    const int bx0 = std::max(kx0 - 1, 0), bx1 = std::min(kx1 + 1, cols);
    const int gx0 = std::max(bx0 - 3, 0), gx1 = std::min(bx1 + 3, cols);
    const int kw = kx1 - kx0, bw = bx1 - bx0;
    // rows smoothed for the Sobel of rows [a - 1, b + 1), rows blurred from
    const int sa = std::max(a - 2, 0), sb = std::min(b + 2, rows);
    const int ga = std::max(sa - 3, 0), gb = std::min(sb + 3, rows);
    Mat blurred = scratch(0, gb - ga, gx1 - gx0, CV_8UC3);
    const uchar* blurred_data = blurred.data;
    GaussianBlur(rectAsImage(src, Rect(gx0, ga, gx1 - gx0, gb - ga)), blurred, Size(7, 7), 0, 0,
                 BORDER_REPLICATE);
    CV_Assert(blurred.data == blurred_data); // written in place, not reallocated
    // the three channels as planes of columns [bx0, bx1), the image's edge pixel replicated
    Mat planes = scratch(7, 3 * (sb - sa), bw + 2, CV_8U);
    for (int r = sa; r < sb; ++r)
    {
        uchar* p[3];
        for (int ch = 0; ch < 3; ++ch)
            p[ch] = planes.ptr<uchar>(3 * (r - sa) + ch) + 1;
        splitRow3(blurred.ptr<uchar>(r - ga) + 3 * (bx0 - gx0), bw, p[0], p[1], p[2]);
        for (int ch = 0; ch < 3; ++ch)
        {
            p[ch][-1] = p[ch][0];
            p[ch][bw] = p[ch][bw - 1];
        }
    }

    const int nmax = std::min(block, b - a) + 2;
    Mat fx = scratch(1, nmax, kw, CV_32F), fy = scratch(2, nmax, kw, CV_32F);
    Mat angle = scratch(3, nmax, kw, CV_32F);
    Mat strong = scratch(4, nmax, kw, CV_8U), onehot = scratch(5, nmax, kw, CV_8U);
    // output columns with a vote (the image's first and last columns are 0)
    const int vx0 = std::max(out.x, 1), vx1 = std::min(out.x + out.width, cols - 1);
    for (int ba = a; ba < b; ba += block)
    {
        const int bb = std::min(ba + block, b);
        // rows whose one-hot bins the vote of rows [ba, bb) reads
        const int la = std::max(ba - 1, 0), lb = std::min(bb + 1, rows);
        const int nl = lb - la;
        for (int r = la; r < lb; ++r)
        {
            const uchar* up[3];
            const uchar* mid[3];
            const uchar* dn[3];
            for (int ch = 0; ch < 3; ++ch)
            {
                const int off = 1 + kx0 - bx0;
                up[ch] = planes.ptr<uchar>(3 * (std::max(r - 1, 0) - sa) + ch) + off;
                mid[ch] = planes.ptr<uchar>(3 * (r - sa) + ch) + off;
                dn[ch] = planes.ptr<uchar>(3 * (std::min(r + 1, rows - 1) - sa) + ch) + off;
            }
            sobelStrongestPlanar(up, mid, dn, kw, ithr, fx.ptr<float>(r - la),
                                 fy.ptr<float>(r - la), strong.ptr<uchar>(r - la));
        }
        hal::fastAtan32f(fy.ptr<float>(), fx.ptr<float>(), angle.ptr<float>(), nl * kw, true);
        for (int r = la; r < lb; ++r)
        {
            uchar* oh = onehot.ptr<uchar>(r - la);
            if (r == 0 || r == rows - 1)
            {
                memset(oh, 1, kw);
                continue;
            }
            orientationRow(angle.ptr<float>(r - la), kw, oh);
            if (kx0 == 0)
                oh[0] = 1;
            if (kx1 == cols)
                oh[kw - 1] = 1;
        }
        for (int r = ba; r < bb; ++r)
        {
            uchar* d = dst.ptr<uchar>(r);
            if (r == 0 || r == rows - 1)
            {
                memset(d + out.x, 0, out.width);
                continue;
            }
            if (out.x == 0)
                d[0] = 0;
            if (out.x + out.width == cols)
                d[cols - 1] = 0;
            if (vx1 > vx0)
                majorityRow(onehot.ptr<uchar>(r - 1 - la) + vx0 - kx0,
                            onehot.ptr<uchar>(r - la) + vx0 - kx0,
                            onehot.ptr<uchar>(r + 1 - la) + vx0 - kx0,
                            strong.ptr<uchar>(r - la) + vx0 - kx0,
                            mask.empty() ? 0 : mask.ptr<uchar>(r) + vx0, vx1 - vx0, d + vx0);
        }
    }
}

// LINEMOD's threshold on the float magnitude (exact: below 2^24) as an integer.
static int gradientThreshold(float weak_threshold)
{
    const float thr = weak_threshold * weak_threshold;
    if (!(thr >= 0.f))
        return -1;
    if ((double)thr >= (double)INT_MAX)
        return INT_MAX;
    return (int)std::floor((double)thr);
}

void quantizeGradientLevel(const Mat& src, const Mat& mask, float weak_threshold, Mat& dst)
{
    CV_Assert(src.type() == CV_8UC3);
    const int rows = src.rows, cols = src.cols;
    dst.create(rows, cols, CV_8U);
    if (rows < 3 || cols < 3)
    {
        dst.setTo(Scalar::all(0));
        return;
    }
    const int ithr = gradientThreshold(weak_threshold);
    // cv::phase runs its scalar code on arrays shorter than 2 SIMD vectors (16 values with
    // AVX2, 32 with AVX-512) and SIMD code otherwise: blocks of whole rows of at least 32 pixels
    // keep every pixel on the path it takes in the whole image
    const int block = cols >= 32 ? 32 : rows;
    // stripes whose blurred rows stay in the cache (about 192 KB), at least as many as
    // stripesFor() gives the threads
    const int cache_rows = std::max(32, (192 << 10) / (3 * (cols + 2)));
    const int cache_stripes = roundUpToThreads((rows + cache_rows - 1) / cache_rows);
    const int nstripes = cols >= 32 ? std::max(stripesFor(rows, cols, 32), cache_stripes) : 1;
    parallel_for_(Range(0, rows), [&](const Range& range) {
        gradientRect(src, mask, ithr, block, Rect(0, range.start, cols, range.end - range.start),
                     dst);
    }, nstripes);
}

// ------------------------------------------------------------------------------------------
// ColorHue

// Output pixels `out` of one level in blocks of 32 rows: blur (k x k, 0: none) around the
// rectangle, HSV, bins. Equal there to the whole image's computation (the blur reads k / 2 real
// pixels beyond the rectangle or replicates the image's own edge; the rest is per pixel).
static void hueRect(const Mat& src, const Mat& mask, int smin, int vmin, int k, Rect out, Mat& dst)
{
    const int rows = src.rows, cols = src.cols, block = 32;
    const int gx0 = std::max(out.x - k / 2, 0);
    const int gx1 = std::min(out.x + out.width + k / 2, cols);
    for (int a = out.y; a < out.y + out.height; a += block)
    {
        const int b = std::min(a + block, out.y + out.height);
        Mat smoothed;
        if (k > 0)
        {
            const int ga = std::max(a - k / 2, 0), gb = std::min(b + k / 2, rows);
            Mat blurred = scratch(0, gb - ga, gx1 - gx0, CV_8UC3);
            const uchar* data = blurred.data;
            GaussianBlur(rectAsImage(src, Rect(gx0, ga, gx1 - gx0, gb - ga)), blurred, Size(k, k),
                         0, 0, BORDER_REPLICATE);
            CV_Assert(blurred.data == data);
            smoothed = blurred(Rect(out.x - gx0, a - ga, out.width, b - a));
        }
        else
        {
            smoothed = src(Rect(out.x, a, out.width, b - a));
        }
        for (int r = a; r < b; ++r)
            hueBinsRow(smoothed.ptr<uchar>(r - a), mask.empty() ? 0 : mask.ptr<uchar>(r) + out.x,
                       out.width, smin, vmin, dst.ptr<uchar>(r) + out.x);
    }
}

void quantizeHueLevel(const Mat& src, const Mat& mask, const ModalityInfo& info, Mat& dst)
{
    CV_Assert(src.type() == CV_8UC3);
    const int rows = src.rows, cols = src.cols;
    dst.create(rows, cols, CV_8U);
    const int smin = std::max(0, info.saturation_threshold);
    const int vmin = std::max(0, info.value_threshold);
    if (smin > 255 || vmin > 255) // no pixel passes
    {
        dst.setTo(Scalar::all(0));
        return;
    }
    const int k = info.blur_size > 1 ? info.blur_size : 0;
    parallel_for_(Range(0, rows), [&](const Range& range) {
        hueRect(src, mask, smin, vmin, k, Rect(0, range.start, cols, range.end - range.start),
                dst);
    }, stripesFor(rows, cols, 32));
}

// ------------------------------------------------------------------------------------------
// DepthNormal (LINEMOD 2.6): per pixel at least 5 pixels inside the image border, a plane fit to
// the 8 depths at +-5 pixels whose difference to the centre is below difference_threshold
// (integer normal equations), the normal (1150 ddx, 1150 ddy, -det d) normalised in float and
// mapped to a cell (i1, i2, i3) of a G x G x G grid, the cell's label from a table; pixels at
// or beyond distance_threshold and degenerate normals get 0; then a 5x5 median (a bit-sliced
// row kernel when every label of the frame is 0 or a single bit, as cv::linemod's table holds;
// cv::medianBlur otherwise). The next levels are INTER_NEAREST reductions of the labels.
//
// The cell -> label table is data of cv::linemod, not part of its API: it is read out of the
// installed cv::linemod::DepthNormal once, by quantizing planes of known normals
// (normalLabelTable()). A pixel that falls into a cell the read-out did not reach makes the
// fast path give up for that frame (the caller then uses the virtual calls), so the output is
// exact either way.

enum { NORMAL_G = 20, NORMAL_CELLS = NORMAL_G + 1, NORMAL_R = 5 };
// beyond it 1150 * ddx can leave 32 bits in the vectorised path
enum { NORMAL_MAX_DIFFERENCE = 240 };

// The cell of one normal, as cv::linemod computes it (float arithmetic, truncation).
static inline bool normalCell(int64 ddx, int64 ddy, int64 det, int64 d, int& i1, int& i2, int& i3)
{
    float nx = static_cast<float>(1150 * ddx);
    float ny = static_cast<float>(1150 * ddy);
    float nz = static_cast<float>(-det * d);
    const float norm = std::sqrt(nx * nx + ny * ny + nz * nz);
    if (!(norm > 0))
        return false;
    const float inv = 1.0f / norm;
    nx *= inv;
    ny *= inv;
    nz *= inv;
    const int half = NORMAL_G / 2;
    i1 = static_cast<int>(nx * half + half);
    i2 = static_cast<int>(ny * half + half);
    i3 = static_cast<int>(nz * NORMAL_G + NORMAL_G);
    return true;
}

// Plane fit to the 8 neighbours (depths v[k] at (i, j) = (-R,-R) (0,-R) (R,-R) (-R,0) (R,0)
// (-R,R) (0,R) (R,R)) of a pixel of depth d: false when the pixel has no normal.
static inline bool neighboursCell(int64 d, const int64* v, int distance_threshold,
                                  int difference_threshold, int& i1, int& i2, int& i3)
{
    if (d >= distance_threshold)
        return false;
    int64 A0 = 0, A1 = 0, A3 = 0, b0 = 0, b1 = 0;
    for (int k = 0; k < 8; ++k)
    {
        const int kk = k < 4 ? k : k + 1; // skip the centre of the 3x3 layout
        const int64 i = (kk % 3 - 1) * NORMAL_R, j = (kk / 3 - 1) * NORMAL_R;
        const int64 delta = v[k] - d;
        if (!((delta < 0 ? -delta : delta) < difference_threshold))
            continue;
        A0 += i * i;
        A1 += i * j;
        A3 += j * j;
        b0 += i * delta;
        b1 += j * delta;
    }
    const int64 det = A0 * A3 - A1 * A1;
    const int64 ddx = A3 * b0 - A1 * b1;
    const int64 ddy = -A1 * b0 + A0 * b1;
    return normalCell(ddx, ddy, det, d, i1, i2, i3);
}

// The same for a pixel of a CV_16U image (p points to it, step in elements).
static inline bool pixelNormalCell(const ushort* p, size_t step, int distance_threshold,
                                   int difference_threshold, int& i1, int& i2, int& i3)
{
    const ptrdiff_t s = (ptrdiff_t)step * NORMAL_R, R = NORMAL_R;
    const int64 v[8] = { p[-s - R], p[-s], p[-s + R], p[-R], p[R], p[s - R], p[s], p[s + R] };
    return neighboursCell(p[0], v, distance_threshold, difference_threshold, i1, i2, i3);
}

static inline int cellIndex(int i1, int i2, int i3)
{
    return (i3 * NORMAL_CELLS + i2) * NORMAL_CELLS + i1;
}

// A neighbourhood: the centre's depth and its 8 neighbours' (layout of neighboursCell()).
struct NormalConfig
{
    int64 d;
    int64 v[8];
};

enum { NORMAL_TABLE_SIZE = NORMAL_CELLS * NORMAL_CELLS * NORMAL_CELLS };
// the read-out's thresholds: every depth counts as a pixel, every difference as a neighbour
static const int PROBE_DISTANCE = 65536, PROBE_DIFFERENCE = 20000;

class NormalLabelTable
{
public:
    /** An entry of a cell whose label is not known yet (a label is a byte). */
    enum { UNKNOWN = 0x100 };

    NormalLabelTable() : usable_(false)
    {
        entry_[0].store(0, std::memory_order_relaxed); // no normal: label 0
        for (int i = 1; i <= NORMAL_TABLE_SIZE; ++i)
            entry_[i].store(UNKNOWN, std::memory_order_relaxed);
    }

    bool usable() const { return usable_; }

    /** Label of a cell index; false when it is not known yet. */
    bool lookup(int cell, uchar& label) const
    {
        if ((unsigned)cell >= (unsigned)NORMAL_TABLE_SIZE)
            return false;
        const unsigned e = entry(cell + 1);
        label = (uchar)e;
        return e != UNKNOWN;
    }

    /** The entry of cell index `cell` at `cell + 1` (0: no normal, label 0), for any index in
    [0, NORMAL_TABLE_SIZE]: the label, or UNKNOWN. One atomic word per cell: a reader meets the
    label or UNKNOWN, never half of an update. */
    unsigned entry(unsigned index) const { return entry_[index].load(std::memory_order_relaxed); }

    /** Reads the labels of the cells of these neighbourhoods (computed with the probe's
    thresholds) out of cv::linemod::DepthNormal. False when its output contradicts the layout
    this code assumes (then the fast path stays off). */
    bool learn(const std::vector<NormalConfig>& configs);

    void setUsable(bool u) { usable_ = u; }

private:
    bool usable_;
    std::atomic<ushort> entry_[NORMAL_TABLE_SIZE + 1];
    std::mutex mutex_;
};

// Neighbourhoods quantized by cv::linemod::DepthNormal, one per 16 x 16 tile. In a tile, every
// pixel within 7 of its centre is either in the 5x5 window around the centre (depth d) or the
// neighbour at (i, j) of window pixels in one role only (depth v(i, j)): the 25 window pixels see
// the same neighbourhood, have the same normal, and the 5x5 median at the centre keeps their
// label. Cells of a coordinate 20 are beyond cv::linemod's table: it reads the bytes after it,
// which are whatever they are but the same in every call; they are read out like the others.
bool NormalLabelTable::learn(const std::vector<NormalConfig>& configs_in)
{
    std::lock_guard<std::mutex> lock(mutex_);
    std::vector<NormalConfig> configs;
    std::vector<int> cells;
    std::vector<uchar> queued(NORMAL_TABLE_SIZE, 0);
    for (size_t k = 0; k < configs_in.size(); ++k)
    {
        int i1, i2, i3;
        if (!neighboursCell(configs_in[k].d, configs_in[k].v, PROBE_DISTANCE, PROBE_DIFFERENCE,
                            i1, i2, i3))
            continue;
        const int cell = cellIndex(i1, i2, i3);
        if (i1 < 0 || i1 >= NORMAL_CELLS || i2 < 0 || i2 >= NORMAL_CELLS || i3 < 0
            || i3 >= NORMAL_CELLS || entry(cell + 1) != UNKNOWN || queued[cell])
            continue;
        queued[cell] = 1;
        configs.push_back(configs_in[k]);
        cells.push_back(cell);
    }
    if (configs.empty())
        return true;
    const int TS = 16;
    const int NT = (int)std::ceil(std::sqrt((double)configs.size()));
    // one empty tile row and column at the end: LINEMOD leaves the last 6 rows / columns out
    Mat depth((NT + 1) * TS, (NT + 1) * TS, CV_16U, Scalar(0));
    for (size_t k = 0; k < configs.size(); ++k)
    {
        const NormalConfig& c = configs[k];
        const int cy = (int)(k / NT) * TS + TS / 2, cx = (int)(k % NT) * TS + TS / 2;
        for (int oy = -7; oy <= 7; ++oy)
            for (int ox = -7; ox <= 7; ++ox)
            {
                const int i = ox >= 3 ? 1 : ox <= -3 ? -1 : 0;
                const int j = oy >= 3 ? 1 : oy <= -3 ? -1 : 0;
                int64 v = c.d;
                if (i != 0 || j != 0)
                {
                    const int kk = (j + 1) * 3 + (i + 1);
                    v = c.v[kk < 4 ? kk : kk - 1];
                }
                depth.at<ushort>(cy + oy, cx + ox) = (ushort)v;
            }
    }
    Ptr<linemod::DepthNormal> probe
        = makePtr<linemod::DepthNormal>(PROBE_DISTANCE, PROBE_DIFFERENCE, 63, 2);
    Mat labels;
    probe->process(depth, Mat())->quantize(labels);
    for (size_t k = 0; k < configs.size(); ++k)
    {
        const int cy = (int)(k / NT) * TS + TS / 2, cx = (int)(k % NT) * TS + TS / 2;
        // the tile really holds the configuration (checks the layout above)
        int j1, j2, j3;
        if (!pixelNormalCell(depth.ptr<ushort>(cy) + cx, depth.step1(), PROBE_DISTANCE,
                             PROBE_DIFFERENCE, j1, j2, j3)
            || cellIndex(j1, j2, j3) != cells[k])
            return false;
        entry_[cells[k] + 1].store(labels.at<uchar>(cy, cx), std::memory_order_relaxed);
    }
    return true;
}

// The same neighbourhood with the probe's thresholds: a neighbour the pixel's own threshold
// leaves out is moved far away.
static NormalConfig probeConfig(const ushort* p, size_t step, int difference_threshold)
{
    const ptrdiff_t s = (ptrdiff_t)step * NORMAL_R, R = NORMAL_R;
    const ptrdiff_t offs[8] = { -s - R, -s, -s + R, -R, R, s - R, s, s + R };
    NormalConfig c;
    c.d = p[0];
    for (int k = 0; k < 8; ++k)
    {
        const int64 v = p[offs[k]], delta = v - c.d;
        if ((delta < 0 ? -delta : delta) < difference_threshold)
            c.v[k] = v;
        else
            c.v[k] = c.d + PROBE_DIFFERENCE <= 65535 ? c.d + PROBE_DIFFERENCE
                                                     : c.d - PROBE_DIFFERENCE;
    }
    return c;
}

// Initial read-out: random neighbourhoods (planes of random normals; random depths around
// random centres, neighbours left out, holes) give the common cells; the rare ones are read out
// when a frame meets them (depthNormalLevel0).
static void readNormalLabels(NormalLabelTable& t)
{
    std::vector<NormalConfig> configs;
    std::vector<uchar> seen(NORMAL_TABLE_SIZE, 0);
    RNG rng(0x5eed);
    for (int n = 0; n < 200000; ++n)
    {
        NormalConfig c;
        const int kind = n % 3;
        if (kind == 0)
        {
            const double phi = rng.uniform(0., 2 * CV_PI);
            const double rho = std::sqrt(rng.uniform(0., 1.));
            const double nx = rho * std::cos(phi), ny = rho * std::sin(phi);
            const double nz = std::sqrt(std::max(1e-12, 1 - nx * nx - ny * ny));
            c.d = rng.uniform(1, 60000);
            const double a = nx / nz * (double)c.d / 1150., b = ny / nz * (double)c.d / 1150.;
            if (std::abs(a) > 3000 || std::abs(b) > 3000)
                continue;
            const int64 ia = cvRound(a), ib = cvRound(b);
            bool in_range = true;
            for (int k = 0; k < 8; ++k)
            {
                const int kk = k < 4 ? k : k + 1;
                c.v[k] = c.d + ia * (kk % 3 - 1) * NORMAL_R + ib * (kk / 3 - 1) * NORMAL_R;
                in_range = in_range && c.v[k] >= 0 && c.v[k] <= 65535;
            }
            if (!in_range)
                continue;
        }
        else
        {
            // like a depth camera: centre below 4 m (or a hole), small differences, some
            // neighbours left out
            c.d = kind == 1 ? rng.uniform(1, 4000) : rng.uniform(0, 100);
            const int spread = 1 << rng.uniform(0, 9);
            const int out_of = rng.uniform(2, 9);
            for (int k = 0; k < 8; ++k)
            {
                int64 v = c.d + rng.uniform(-spread, spread + 1);
                if (rng.uniform(0, out_of) == 0)
                    v = c.d + PROBE_DIFFERENCE;
                c.v[k] = std::min<int64>(65535, std::max<int64>(0, v));
            }
        }
        int i1, i2, i3;
        if (!neighboursCell(c.d, c.v, PROBE_DISTANCE, PROBE_DIFFERENCE, i1, i2, i3))
            continue;
        if (i1 < 0 || i1 >= NORMAL_CELLS || i2 < 0 || i2 >= NORMAL_CELLS || i3 < 0
            || i3 >= NORMAL_CELLS || seen[cellIndex(i1, i2, i3)])
            continue;
        seen[cellIndex(i1, i2, i3)] = 1;
        configs.push_back(c);
    }
    t.setUsable(t.learn(configs));
}

static NormalLabelTable& normalLabelTable()
{
    static NormalLabelTable table;
    static std::once_flag once;
    std::call_once(once, [] { readNormalLabels(table); });
    return table;
}

bool depthNormalReady(const ModalityInfo& info)
{
    return info.kind == MODALITY_DEPTH_NORMAL && info.difference_threshold <= NORMAL_MAX_DIFFERENCE
           && normalLabelTable().usable();
}

// Labels (before the median) of rows [a, b) of a CV_16U depth image; the pixels whose cell has
// no known label yet are appended to `unknown` (label 0 for now). `other_labels` is set when a
// label is neither 0 nor a single bit (cv::linemod's table holds single bits; the bytes it reads
// beyond it, for cells of a coordinate 20, need not).
static void normalRows(const Mat& depth, const ModalityInfo& info, const NormalLabelTable& t,
                       int a, int b, Mat& dst, std::vector<Point>& unknown, bool& other_labels)
{
    uchar multi = 0; // OR of label & (label - 1)
    const int rows = depth.rows, cols = depth.cols, R = NORMAL_R;
    const int x0 = R, x1 = cols - R - 1; // LINEMOD's loop bounds
    const size_t step = depth.step1();
    const int dist = info.distance_threshold, diff = info.difference_threshold;
    for (int y = a; y < b; ++y)
    {
        uchar* out = dst.ptr<uchar>(y);
        if (y < R || y >= rows - R - 1 || x1 <= x0)
        {
            memset(out, 0, cols);
            continue;
        }
        memset(out, 0, x0);
        memset(out + x1, 0, cols - x1);
        const ushort* row = depth.ptr<ushort>(y);
        // the cells of a vector's worth of pixels at a time (quantize_kernels), then the table
        int x = x0;
        int ids[256];
        while (x < x1)
        {
            const int done = normalCellsRow(row + x, step, std::min(x1 - x, 256), dist, diff, ids);
            if (done == 0)
                break;
            unsigned any = 0; // OR of the entries: UNKNOWN when a cell was not known
            for (int k = 0; k < done; ++k)
            {
                const unsigned index = (unsigned)(ids[k] + 1); // -1 (no normal): entry 0
                const unsigned e = index <= (unsigned)NORMAL_TABLE_SIZE
                    ? t.entry(index) : (unsigned)NormalLabelTable::UNKNOWN;
                const uchar v = (uchar)e;
                any |= e;
                multi |= v & (v - 1);
                out[x + k] = v;
            }
            // again for the chunk's cells (another thread may have learned one since: its
            // label is taken, the others are left for depthNormalLevel0)
            if (any & NormalLabelTable::UNKNOWN)
                for (int k = 0; k < done; ++k)
                {
                    uchar v;
                    if (ids[k] < 0)
                        continue;
                    if (t.lookup(ids[k], v))
                    {
                        multi |= v & (v - 1);
                        out[x + k] = v;
                    }
                    else
                    {
                        unknown.push_back(Point(x + k, y));
                    }
                }
            x += done;
        }
        for (; x < x1; ++x)
        {
            int i1, i2, i3;
            uchar v = 0;
            if (pixelNormalCell(row + x, step, dist, diff, i1, i2, i3))
            {
                const bool in_grid = i1 >= 0 && i2 >= 0 && i3 >= 0 && i1 < NORMAL_CELLS
                                     && i2 < NORMAL_CELLS && i3 < NORMAL_CELLS;
                if (!in_grid || !t.lookup(cellIndex(i1, i2, i3), v))
                    unknown.push_back(Point(x, y));
            }
            multi |= v & (v - 1);
            out[x] = v;
        }
    }
    if (multi)
        other_labels = true;
}

// Level 0 of DepthNormal without its mask; false when cv::linemod contradicted the read-out.
static bool depthNormalLevel0(const Mat& depth, const ModalityInfo& info, Mat& labels)
{
    NormalLabelTable& t = normalLabelTable();
    const int rows = depth.rows, cols = depth.cols;
    Mat raw(rows, cols, CV_8U);
    std::vector<Point> unknown;
    std::mutex unknown_mutex;
    std::atomic<bool> other_labels(false);
    const int nstripes = stripesFor(rows, cols, 32);
    parallel_for_(Range(0, rows), [&](const Range& r) {
        std::vector<Point> mine;
        bool other = false;
        normalRows(depth, info, t, r.start, r.end, raw, mine, other);
        if (other)
            other_labels = true;
        if (!mine.empty())
        {
            std::lock_guard<std::mutex> lock(unknown_mutex);
            unknown.insert(unknown.end(), mine.begin(), mine.end());
        }
    }, nstripes);
    if (!unknown.empty())
    {
        // cells the read-out has not met yet: read them out now, then label those pixels
        std::vector<NormalConfig> configs;
        configs.reserve(unknown.size());
        for (size_t k = 0; k < unknown.size(); ++k)
            configs.push_back(probeConfig(depth.ptr<ushort>(unknown[k].y) + unknown[k].x,
                                          depth.step1(), info.difference_threshold));
        if (!t.learn(configs))
            return false;
        for (size_t k = 0; k < unknown.size(); ++k)
        {
            int i1, i2, i3;
            uchar v = 0;
            if (!neighboursCell(configs[k].d, configs[k].v, PROBE_DISTANCE, PROBE_DIFFERENCE, i1,
                                i2, i3)
                || !t.lookup(cellIndex(i1, i2, i3), v))
                return false;
            if (v & (v - 1))
                other_labels = true;
            raw.at<uchar>(unknown[k]) = v;
        }
    }
    labels.create(rows, cols, CV_8U);
    if (!other_labels)
    {
        // LINEMOD's 5x5 median (cv::medianBlur, BORDER_REPLICATE) of labels that are single bits
        parallel_for_(Range(0, rows), [&](const Range& r) {
            Mat planes = scratch(0, 1, 3 * (cols + 4), CV_8U);
            for (int y = r.start; y < r.end; ++y)
            {
                const uchar* around[5];
                for (int k = 0; k < 5; ++k)
                    around[k] = raw.ptr<uchar>(std::min(std::max(y - 2 + k, 0), rows - 1));
                medianOneHotRow(around, cols, planes.ptr<uchar>(), labels.ptr<uchar>(y));
            }
        }, nstripes);
        return true;
    }
    // other labels: cv::medianBlur in stripes of whole rows (each an image of its own: the same
    // code on every pixel as on the whole image)
    parallel_for_(Range(0, rows), [&](const Range& r) {
        const int ga = std::max(r.start - 2, 0), gb = std::min(r.end + 2, rows);
        Mat part;
        medianBlur(rowsAsImage(raw, ga, gb), part, 5);
        part.rowRange(r.start - ga, r.end - ga).copyTo(labels.rowRange(r.start, r.end));
    }, nstripes);
    return true;
}

void checkInputs(const ModalityInfo& info, const Mat& src, const Mat& mask)
{
    if (src.empty())
        CV_Error(Error::StsBadArg, "fastQuantize: the source image is empty");
    if (info.kind == MODALITY_COLOR_GRADIENT || info.kind == MODALITY_COLOR_HUE)
    {
        if (src.type() != CV_8UC3)
            CV_Error_(Error::StsUnsupportedFormat,
                      ("fastQuantize: a colour modality needs a CV_8UC3 image, got %s",
                       typeToString(src.type()).c_str()));
    }
    if (!mask.empty() && (mask.type() != CV_8UC1 || mask.size() != src.size()))
        CV_Error_(Error::StsBadArg,
                  ("fastQuantize: the mask must be CV_8UC1 of the image's size %dx%d, got %s %dx%d",
                   src.cols, src.rows, typeToString(mask.type()).c_str(), mask.cols, mask.rows));
}

void quantizeLevel(const ModalityInfo& info, const Mat& src, const Mat& mask, Mat& dst)
{
    if (info.kind == MODALITY_COLOR_GRADIENT)
        quantizeGradientLevel(src, mask, info.weak_threshold, dst);
    else
        quantizeHueLevel(src, mask, info, dst);
}

// The next level of an image (the modalities' pyrDown) or of a mask (INTER_NEAREST).
// `down`, when given, is reused when its size fits (pyramids of the calling thread, kept between
// frames).
Mat nextImage(const Mat& img, Mat* down = 0)
{
    Mat local;
    Mat& out = down ? *down : local;
    pyrDown(img, out, Size(img.cols / 2, img.rows / 2));
    return out;
}

Mat nextMask(const Mat& mask, Mat* down = 0)
{
    if (mask.empty())
        return Mat();
    Mat local;
    Mat& out = down ? *down : local;
    resize(mask, out, Size(mask.cols / 2, mask.rows / 2), 0.0, 0.0, INTER_NEAREST);
    return out;
}

// A buffer of the calling thread for level l of pyramid j, kept between calls.
Mat* pyramidBuffer(int kind, size_t j, int l)
{
    static thread_local std::vector<std::vector<Mat> > buffers[2];
    std::vector<std::vector<Mat> >& b = buffers[kind];
    if (b.size() <= j)
        b.resize(j + 1);
    if ((int)b[j].size() <= l)
        b[j].resize(l + 1);
    return &b[j][l];
}

bool sameData(const Mat& a, const Mat& b)
{
    return a.data == b.data && a.size() == b.size() && a.type() == b.type() && a.step == b.step;
}

// What QuantizedPyramid::quantize gives: the labels where the mask is set (all without mask).
void applyMask(const Mat& labels, const Mat& mask, Mat& dst)
{
    if (mask.empty())
    {
        labels.copyTo(dst);
        return;
    }
    dst = Mat::zeros(labels.size(), CV_8U);
    labels.copyTo(dst, mask);
}

// DepthNormal: level 0 from the depth, the others INTER_NEAREST of the labels (not of the depth).
bool depthNormalLevels(const ModalityInfo& info, const Mat& depth, const Mat& mask, int levels,
                       std::vector<Mat>& quantized)
{
    if (depth.type() != CV_16UC1)
        return false; // what cv::linemod does with other types is its own business
    // cv::linemod reads the depth as a continuous array of rows x cols from its first pixel, so
    // a ROI of a wider image gives it other rows than the ROI's; here the ROI's own rows (the
    // same images as cv::linemod's for a continuous depth, and for a copy of the ROI)
    const Mat flat = depth.isContinuous() ? depth : depth.clone();
    Mat labels;
    if (!depthNormalLevel0(flat, info, labels))
        return false;
    quantized.resize(levels);
    Mat m = mask;
    for (int l = 0; l < levels; ++l)
    {
        if (l > 0)
        {
            labels = nextMask(labels);
            m = nextMask(m);
        }
        applyMask(labels, m, quantized[l]);
    }
    return true;
}

} // namespace

bool hasRectPath(const ModalityInfo& info)
{
    return info.kind == MODALITY_COLOR_GRADIENT || info.kind == MODALITY_COLOR_HUE;
}

void quantizeLevelRect(const ModalityInfo& info, const Mat& src, const Mat& mask, Rect r, Mat& dst)
{
    CV_Assert(hasRectPath(info));
    checkInputs(info, src, mask);
    CV_Assert(dst.type() == CV_8UC1 && dst.size() == src.size());
    r &= Rect(0, 0, src.cols, src.rows);
    if (r.empty())
        return;
    if (info.kind == MODALITY_COLOR_HUE)
    {
        const int smin = std::max(0, info.saturation_threshold);
        const int vmin = std::max(0, info.value_threshold);
        if (smin > 255 || vmin > 255) // no pixel passes
            dst(r).setTo(Scalar::all(0));
        else
            hueRect(src, mask, smin, vmin, info.blur_size > 1 ? info.blur_size : 0, r, dst);
        return;
    }
    const int ithr = gradientThreshold(info.weak_threshold);
    if (src.rows < 3 || src.cols < 3)
    {
        dst(r).setTo(Scalar::all(0));
        return;
    }
    // one block: cv::phase sees (rows + 2) x (columns + 2) values, clipped at the image's edges;
    // at least 32 when the rectangle holds 32 pixels (see quantizeGradientLevel)
    if (r.area() >= 32 || (r.height == src.rows && r.width == src.cols))
    {
        gradientRect(src, mask, ithr, r.height, r, dst);
        return;
    }
    // a sliver: its full-width rows (or the whole image) in a buffer of this thread, then copied
    static thread_local Mat wide;
    wide.create(src.size(), CV_8U);
    Rect w(0, r.y, src.cols, r.height);
    if (w.area() < 32)
        w = Rect(0, 0, src.cols, src.rows);
    gradientRect(src, mask, ithr, w.height, w, wide);
    wide(r).copyTo(dst(r));
}

bool hasFastPath(const ModalityInfo& info)
{
    return info.kind == MODALITY_COLOR_GRADIENT || info.kind == MODALITY_COLOR_HUE
           || depthNormalReady(info);
}

bool fastQuantize(const ModalityInfo& info, const Mat& src, const Mat& mask, int levels,
                  std::vector<Mat>& quantized)
{
    if (!hasFastPath(info))
        return false;
    CV_Assert(levels >= 1);
    checkInputs(info, src, mask);
    if (info.kind == MODALITY_DEPTH_NORMAL)
        return depthNormalLevels(info, src, mask, levels, quantized);
    quantized.resize(levels);
    Mat img = src, m = mask;
    for (int l = 0; l < levels; ++l)
    {
        if (l > 0)
        {
            img = nextImage(img);
            m = nextMask(m);
        }
        quantizeLevel(info, img, m, quantized[l]);
    }
    return true;
}

bool fastQuantize(const Ptr<Modality>& modality, const Mat& src, const Mat& mask, int levels,
                  std::vector<Mat>& quantized)
{
    return fastQuantize(classifyModality(modality), src, mask, levels, quantized);
}

void quantizeAllLevels(const std::vector<Ptr<Modality> >& modalities,
                       const std::vector<ModalityInfo>& infos_in, const std::vector<Mat>& sources,
                       const std::vector<Mat>& masks, int levels,
                       std::vector<std::vector<Mat> >& quantized,
                       std::vector<std::vector<LevelSource> >* deferred)
{
    const int M = (int)modalities.size();
    CV_Assert(levels >= 1 && (int)sources.size() == M);
    CV_Assert(masks.empty() || (int)masks.size() == M);
    CV_Assert(infos_in.empty() || (int)infos_in.size() == M);
    std::vector<ModalityInfo> infos = infos_in;
    if (infos.empty())
    {
        infos.resize(M);
        for (int i = 0; i < M; ++i)
            infos[i] = classifyModality(modalities[i]);
    }
    // the caller's Mats are written in place when their size fits (as OpenCV's outputs)
    quantized.resize(levels);
    for (int l = 0; l < levels; ++l)
        quantized[l].resize(M);
    if (deferred)
        deferred->assign(levels, std::vector<LevelSource>(M));

    // pyramids of the images and masks, shared by the modalities given the same data
    std::vector<int> img_of(M, -1), mask_of(M, -1);
    std::vector<std::vector<Mat> > imgs, msks;
    for (int i = 0; i < M; ++i)
    {
        if (infos[i].kind == MODALITY_DEPTH_NORMAL && hasFastPath(infos[i]))
        {
            std::vector<Mat> q;
            if (fastQuantize(infos[i], sources[i], masks.empty() ? Mat() : masks[i], levels, q))
            {
                for (int l = 0; l < levels; ++l)
                    quantized[l][i] = q[l];
                continue;
            }
        }
        if (!hasFastPath(infos[i]) || infos[i].kind == MODALITY_DEPTH_NORMAL)
        {
            Ptr<linemod::QuantizedPyramid> qp
                = modalities[i]->process(sources[i], masks.empty() ? Mat() : masks[i]);
            for (int l = 0; l < levels; ++l)
            {
                if (l > 0)
                    qp->pyrDown();
                qp->quantize(quantized[l][i]);
            }
            continue;
        }
        const Mat mask = masks.empty() ? Mat() : masks[i];
        checkInputs(infos[i], sources[i], mask);
        for (int j = 0; j < (int)imgs.size() && img_of[i] < 0; ++j)
            if (sameData(imgs[j][0], sources[i]))
                img_of[i] = j;
        if (img_of[i] < 0)
        {
            img_of[i] = (int)imgs.size();
            imgs.push_back(std::vector<Mat>(1, sources[i]));
        }
        for (int j = 0; j < (int)msks.size() && mask_of[i] < 0; ++j)
            if (sameData(msks[j][0], mask))
                mask_of[i] = j;
        if (mask_of[i] < 0)
        {
            mask_of[i] = (int)msks.size();
            msks.push_back(std::vector<Mat>(1, mask));
        }
    }
    for (int l = 0; l < levels; ++l)
    {
        if (l > 0)
        {
            for (size_t j = 0; j < imgs.size(); ++j)
                imgs[j].push_back(nextImage(imgs[j][l - 1], pyramidBuffer(0, j, l)));
            for (size_t j = 0; j < msks.size(); ++j)
                msks[j].push_back(nextMask(msks[j][l - 1], pyramidBuffer(1, j, l)));
        }
        for (int i = 0; i < M; ++i)
        {
            if (img_of[i] < 0)
                continue;
            const Mat& img = imgs[img_of[i]][l];
            if (deferred && l < levels - 1 && hasRectPath(infos[i]))
            {
                // levels above 0 live in this thread's pyramid buffers, which the next call
                // overwrites: the caller gets its own copy (a quarter of the frame or less)
                LevelSource& d = (*deferred)[l][i];
                d.image = l > 0 ? img.clone() : img;
                d.mask = l > 0 ? msks[mask_of[i]][l].clone() : msks[mask_of[i]][l];
                d.info = infos[i];
                quantized[l][i].create(img.size(), CV_8U);
                continue;
            }
            quantizeLevel(infos[i], img, msks[mask_of[i]][l], quantized[l][i]);
        }
    }
}

// ------------------------------------------------------------------------------------------
// Spreading and response maps

namespace {

// response[o] = 4 - (circular distance from o to the nearest label present), 0 beyond 3: the
// number of the nested label sets {o}, {o, o+-1}, {o..o+-2}, {o..o+-3} that meet the pixel.
struct ResponseTables
{
    uchar within[8][4]; //!< the labels at circular distance <= d of o
    uchar lut[8][256];  //!< the response itself, for the scalar path
    ResponseTables()
    {
        for (int o = 0; o < 8; ++o)
        {
            uchar m = 0;
            for (int d = 0; d < 4; ++d)
            {
                m |= (uchar)((1 << ((o + d) & 7)) | (1 << ((o - d + 8) & 7)));
                within[o][d] = m;
            }
        }
        for (int o = 0; o < 8; ++o)
            for (int x = 0; x < 256; ++x)
            {
                int v = 0;
                for (int d = 0; d < 4; ++d)
                    v += (x & within[o][d]) ? 1 : 0;
                lut[o][x] = (uchar)v;
            }
    }
};

} // namespace

static const ResponseTables& responseTables()
{
    static const ResponseTables tables;
    return tables;
}

uchar responseOf(int o, uchar spread)
{
    return responseTables().lut[o & 7][spread];
}

void spreadResponses(const uchar* s, int cols, uchar* const* d)
{
    const ResponseTables& t = responseTables();
    responsesRow(s, cols, &t.within[0][0], &t.lut[0][0], d);
}

void spreadLabelsFast(const Mat& src, Mat& dst, int T, int pad)
{
    CV_Assert(src.type() == CV_8UC1 && T > 0 && pad >= 0);
    const int srows = src.rows, scols = src.cols;
    const int rows = srows + pad, cols = scols + pad;
    dst.create(rows, cols, CV_8U);
    const int nstripes = stripesFor(rows, cols, 32);
    parallel_for_(Range(0, rows), [&](const Range& range) {
        // OR along rows for the source rows this stripe reads, then along columns
        const int h0 = std::min(range.start, srows);
        const int h1 = std::min(range.end + T - 1, srows);
        Mat horiz(std::max(h1 - h0, 1), cols, CV_8U);
        std::vector<uchar> line(cols + T + 16, 0);
        for (int r = h0; r < h1; ++r)
        {
            memcpy(&line[0], src.ptr<uchar>(r), scols);
            orRows(&line[0], 1, T, cols, horiz.ptr<uchar>(r - h0)); // along the row
        }
        for (int r = range.start; r < range.end; ++r)
        {
            uchar* d = dst.ptr<uchar>(r);
            const int n = std::min(T, srows - r); // source rows [r, r + n)
            if (n <= 0)
                memset(d, 0, cols);
            else
                orRows(horiz.ptr<uchar>(r - h0), horiz.step, n, cols, d);
        }
    }, nstripes);
}

void computeResponseMapsFast(const Mat& spread, std::vector<Mat>& response)
{
    CV_Assert(spread.type() == CV_8UC1);
    response.resize(8);
    for (int o = 0; o < 8; ++o)
        response[o].create(spread.size(), CV_8U);
    const int rows = spread.rows, cols = spread.cols;
    const int nstripes = stripesFor(rows, cols, 32);
    parallel_for_(Range(0, rows), [&](const Range& range) {
        for (int r = range.start; r < range.end; ++r)
        {
            uchar* d[8];
            for (int o = 0; o < 8; ++o)
                d[o] = response[o].ptr<uchar>(r);
            spreadResponses(spread.ptr<uchar>(r), cols, d);
        }
    }, nstripes);
}

void spreadTile(const Mat& src, int T, Rect tile, Mat& spread)
{
    CV_Assert(src.type() == CV_8UC1 && T > 0 && spread.type() == CV_8UC1
              && spread.size() == src.size());
    tile &= Rect(0, 0, src.cols, src.rows);
    if (tile.empty())
        return;
    const int x0 = tile.x, y0 = tile.y, w = tile.width;
    // the source pixels the tile's windows [p, p + T) read: T - 1 more on the right and below
    const int sx1 = std::min(x0 + w + T - 1, src.cols);
    const int sy1 = std::min(tile.y + tile.height + T - 1, src.rows);
    static thread_local std::vector<uchar> line_buf, horiz_buf;
    line_buf.assign(w + T + 16, 0);
    const size_t hstep = (size_t)w;
    if (horiz_buf.size() < hstep * (sy1 - y0) + 16)
        horiz_buf.resize(hstep * (sy1 - y0) + 16);
    for (int r = y0; r < sy1; ++r)
    {
        memcpy(&line_buf[0], src.ptr<uchar>(r) + x0, sx1 - x0);
        orRows(&line_buf[0], 1, T, w, &horiz_buf[(r - y0) * hstep]); // along the row
    }
    for (int r = y0; r < tile.y + tile.height; ++r)
        orRows(&horiz_buf[(r - y0) * hstep], hstep, std::min(T, src.rows - r), w,
               spread.ptr<uchar>(r) + x0);
}

void dominantLabelsFast(const Mat& src, int k, Mat& dst)
{
    CV_Assert(src.type() == CV_8UC1 && k >= 1 && k <= 15); // counts of k^2 fit in a byte
    dst.create(src.size(), CV_8U); // in place when dst already fits (a ROI of a bordered plane)
    CV_Assert(dst.data != src.data);
    if (k == 1)
    {
        src.copyTo(dst);
        return;
    }
    const int rows = src.rows, cols = src.cols, a = k / 2; // window [y - a, y - a + k)
    const int nstripes = stripesFor(rows, cols, 16);
    parallel_for_(Range(0, rows), [&](const Range& range) {
        // per bit: the column sums of the window's rows, with zero columns around
        std::vector<uchar> colsum_buf((size_t)cols + k + a, 0), best_buf((size_t)cols);
        std::vector<const uchar*> window(k);
        for (int y = range.start; y < range.end; ++y)
        {
            const int r0 = std::max(0, y - a), r1 = std::min(rows, y - a + k);
            for (int r = r0; r < r1; ++r)
                window[r - r0] = src.ptr<uchar>(r);
            dominantLabelsRow(&window[0], r1 - r0, cols, k, &colsum_buf[a], &best_buf[0],
                              dst.ptr<uchar>(y));
        }
    }, nstripes);
}

void dominantLabelsReference(const Mat& src, int k, Mat& dst)
{
    dominantLabels(src, Mat(), k, dst);
}

void spreadLabelsReference(const Mat& src, Mat& dst, int T, int pad)
{
    spreadLabels(src, dst, T, pad);
}

void computeResponseMapsReference(const Mat& spread, std::vector<Mat>& response)
{
    computeResponseMaps(spread, response);
}

} // namespace detail
} // namespace forestmod
} // namespace cv
