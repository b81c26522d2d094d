// This file is part of OpenCV project.
// It is subject to the license terms in the LICENSE file found in the top-level directory
// of this distribution and at http://opencv.org/license.html

// Validation stage (paper: "Fast Breadth-first Leaf Validation"): LINEMOD's similarity, read in
// place from the frame's response maps, and the breadth-first preemptive scheme.

#include "precomp.hpp"
#include "validator.hpp"

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
    const std::vector<Mat>& resp = level.response[modality];
    const int W = level.size.width + level.pad, H = level.size.height + level.pad;
    int sum = 0;
    for (int i = begin; i < end; ++i)
    {
        const cv::linemod::Feature& f = templ.features[i];
        const int x = tl.x + f.x, y = tl.y + f.y;
        // LINEMOD skips features that fall outside the image
        if ((unsigned)x >= (unsigned)W || (unsigned)y >= (unsigned)H)
            continue;
        sum += resp[f.label].ptr<uchar>(y)[x];
    }
    return sum;
}

int similarityAll(const LevelMaps& level, const TemplatePyramid& tp, int level_index, Point tl,
                  int* num_features)
{
    const int M = static_cast<int>(level.response.size());
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

void DepthContext::set(const Mat& scene_depth, int radius)
{
    CV_Assert(scene_depth.type() == CV_16UC1 && radius >= 0);
    depth = scene_depth;
    pp = Point2f(0.5f * (scene_depth.cols - 1), 0.5f * (scene_depth.rows - 1));
    const Mat k = getStructuringElement(MORPH_RECT, Size(2 * radius + 1, 2 * radius + 1));
    dilate(scene_depth, zmax, k, Point(-1, -1), 1, BORDER_CONSTANT, Scalar(0));
    Mat holes_far = scene_depth.clone();
    holes_far.setTo(Scalar(65535), scene_depth == 0);
    erode(holes_far, zmin, k, Point(-1, -1), 1, BORDER_CONSTANT, Scalar(65535));
}

Vec3f depthRotationRow(const DepthContext& dc, const DepthTemplate& t, Point origin)
{
    if (t.fx <= 0 || t.fy <= 0)
        return Vec3f(0, 0, 1);
    // a: ray through the template's object centre (template camera), b: through the candidate's
    Vec3f a((t.centre.x - t.pp.x) / t.fx, (t.centre.y - t.pp.y) / t.fy, 1.f);
    Vec3f b((origin.x + t.centre.x - dc.pp.x) / t.fx, (origin.y + t.centre.y - dc.pp.y) / t.fy,
            1.f);
    a *= 1.f / (float)norm(a);
    b *= 1.f / (float)norm(b);
    // R = I + [v]x + [v]x^2 / (1 + c), v = a x b, c = a . b (takes a onto b); its third row
    const Vec3f v = a.cross(b);
    const float c = a.dot(b), k = 1.f / (1.f + c), v2 = v.dot(v);
    return Vec3f(-v[1] + k * v[2] * v[0], v[0] + k * v[2] * v[1], 1.f + k * (v[2] * v[2] - v2));
}

// the template's depth of sample i as seen along the candidate's ray
static inline int predictedDepth(const DepthTemplate& t, const Vec3f& row, const Point3i& s)
{
    if (t.fx <= 0)
        return s.z;
    const float z = (float)s.z;
    const float X = (s.x - t.pp.x) * z / t.fx, Y = (s.y - t.pp.y) * z / t.fy;
    return cvRound(row[0] * X + row[1] * Y + row[2] * z);
}

bool depthOffset(const DepthContext& dc, const DepthTemplate& t, const Vec3f& row, int n,
                 Point origin, int& offset)
{
    const Mat& d = dc.depth;
    const Point3i* samples = &(*t.samples)[0];
    int diff[256];
    int k = 0;
    n = std::min(n, 256);
    for (int i = 0; i < n; ++i)
    {
        const int x = origin.x + samples[i].x, y = origin.y + samples[i].y;
        if ((unsigned)x >= (unsigned)d.cols || (unsigned)y >= (unsigned)d.rows)
            continue;
        const int z = d.ptr<ushort>(y)[x];
        if (z > 0)
            diff[k++] = z - predictedDepth(t, row, samples[i]);
    }
    if (k == 0 || 4 * k < n)
        return false;
    std::nth_element(diff, diff + k / 2, diff + k);
    offset = diff[k / 2];
    return true;
}

int depthSimilarityRange(const DepthContext& dc, const DepthTemplate& t, const Vec3f& row,
                         Point origin, int offset, int begin, int end)
{
    const Mat& d = dc.depth;
    const Point3i* samples = &(*t.samples)[0];
    int sum = 0;
    for (int i = begin; i < end; ++i)
    {
        const int x = origin.x + samples[i].x, y = origin.y + samples[i].y;
        if ((unsigned)x >= (unsigned)d.cols || (unsigned)y >= (unsigned)d.rows)
            continue;
        if (d.ptr<ushort>(y)[x] == 0)
            continue; // no depth at the sample itself: like a feature without a value
        const int z = predictedDepth(t, row, samples[i]) + offset;
        const int lo = dc.zmin.ptr<ushort>(y)[x], hi = dc.zmax.ptr<ushort>(y)[x];
        sum += depthResponse(z < lo ? lo - z : z > hi ? z - hi : 0, dc.tolerance);
    }
    return sum;
}

int depthSimilarity(const DepthContext& dc, const DepthTemplate& t, Point origin, int count)
{
    int n = t.samples ? std::min(256, static_cast<int>(t.samples->size())) : 0;
    if (count >= 0)
        n = std::min(n, count);
    int offset = 0;
    if (n == 0)
        return 0;
    const Vec3f row = depthRotationRow(dc, t, origin);
    if (!depthOffset(dc, t, row, n, origin, offset))
        return 0;
    return depthSimilarityRange(dc, t, row, origin, offset, 0, n);
}

// level-0 position of a candidate's template top-left
static inline Point depthOrigin(const DepthContext& dc, Point tl)
{
    // tl may be negative (windows over the left / top border): multiply, do not shift
    return Point((tl.x + dc.shift.x) * (1 << dc.scale_shift),
                 (tl.y + dc.shift.y) * (1 << dc.scale_shift));
}

static inline int depthCount(const DepthContext* dc, const ValidationCandidate& c,
                             int level_index, int num_modalities)
{
    if (!dc || !c.depth || !c.depth->samples)
        return 0;
    int nf = 0;
    for (int m = 0; m < num_modalities; ++m)
        nf += static_cast<int>((*c.tp)[level_index * num_modalities + m].features.size());
    return depthSamplesAtLevel(static_cast<int>(c.depth->samples->size()), nf, num_modalities);
}

// the candidate's rotation row and offset, once
static void depthPrepare(const DepthContext& dc, ValidationCandidate& c, int ns)
{
    const Point o = depthOrigin(dc, c.tl);
    c.zrow = depthRotationRow(dc, *c.depth, o);
    c.zvalid = depthOffset(dc, *c.depth, c.zrow, ns, o, c.zoffset);
}

static int scoreAll(const LevelMaps& level, int level_index, ValidationCandidate& c,
                    const DepthContext* dc)
{
    int nf = 0;
    int raw = similarityAll(level, *c.tp, level_index, c.tl, &nf);
    const int M = static_cast<int>(level.response.size());
    const int ns = depthCount(dc, c, level_index, M);
    if (ns > 0)
    {
        if (!c.zvalid)
            depthPrepare(*dc, c, ns);
        if (c.zvalid)
            raw += depthSimilarityRange(*dc, *c.depth, c.zrow, depthOrigin(*dc, c.tl), c.zoffset,
                                        0, ns);
    }
    c.total = nf + ns;
    return raw;
}

void validateAll(const LevelMaps& level, int level_index, std::vector<ValidationCandidate>& cands,
                 const DepthContext* depth)
{
    for (size_t i = 0; i < cands.size(); ++i)
    {
        cands[i].zvalid = false;
        cands[i].raw = scoreAll(level, level_index, cands[i], depth);
        cands[i].scored = cands[i].total;
    }
}

void validateBreadthFirst(const LevelMaps& level, int level_index, int num_modalities,
                          std::vector<ValidationCandidate>& cands, int chunk_size, float alpha,
                          int max_survivors, std::vector<int>& survivors,
                          const DepthContext* depth, bool depth_in_chunks)
{
    CV_Assert(chunk_size > 0 && max_survivors > 0);
    const DepthContext* chunk_depth = depth_in_chunks ? depth : 0;
    survivors.clear();
    std::vector<int> alive(cands.size());
    for (size_t i = 0; i < cands.size(); ++i)
    {
        ValidationCandidate& c = cands[i];
        alive[i] = static_cast<int>(i);
        c.raw = 0;
        c.scored = 0;
        c.zvalid = false;
        c.total = 0;
        for (int m = 0; m < num_modalities; ++m)
            c.total += static_cast<int>((*c.tp)[level_index * num_modalities + m].features.size());
        // in the chunks, the depth offset needs all samples: once per candidate, before its
        // first chunk; otherwise the samples join the survivors' full score (scoreAll)
        const int ns = depthCount(chunk_depth, c, level_index, num_modalities);
        c.total += ns;
        if (ns > 0)
            depthPrepare(*chunk_depth, c, ns);
    }
    std::vector<float> scores;
    // chunk k of a candidate covers the fraction [k/K, (k+1)/K) of every modality's features, so
    // every chunk samples all modalities and the whole object (features are scattered)
    for (int k = 0; (int)alive.size() > max_survivors; ++k)
    {
        bool any = false;
        scores.clear();
        for (size_t a = 0; a < alive.size(); ++a)
        {
            ValidationCandidate& c = cands[alive[a]];
            const int K = std::max(1, (c.total + chunk_size - 1) / chunk_size);
            if (k < K)
            {
                any = true;
                for (int m = 0; m < num_modalities; ++m)
                {
                    const cv::linemod::Template& templ = (*c.tp)[level_index * num_modalities + m];
                    const int n = static_cast<int>(templ.features.size());
                    const int b = static_cast<int>((int64)n * k / K);
                    const int e = static_cast<int>((int64)n * (k + 1) / K);
                    c.raw += similarityRange(level, m, templ, c.tl, b, e);
                    c.scored += e - b;
                }
                const int ns = depthCount(chunk_depth, c, level_index, num_modalities);
                if (ns > 0)
                {
                    const int b = static_cast<int>((int64)ns * k / K);
                    const int e = static_cast<int>((int64)ns * (k + 1) / K);
                    if (c.zvalid)
                        c.raw += depthSimilarityRange(*depth, *c.depth, c.zrow,
                                                      depthOrigin(*depth, c.tl), c.zoffset, b, e);
                    c.scored += e - b;
                }

            }
            scores.push_back(c.scored ? c.raw / (4.f * c.scored) : 0.f);
        }
        if (!any)
            break;
        std::vector<float> sorted(scores);
        std::nth_element(sorted.begin(), sorted.begin() + sorted.size() / 2, sorted.end());
        const float median = sorted[sorted.size() / 2];
        std::vector<int> next;
        for (size_t a = 0; a < alive.size(); ++a)
            if (scores[a] >= median && scores[a] > alpha)
                next.push_back(alive[a]);
        alive.swap(next);
    }
    // the survivor(s) are scored on all their features
    for (size_t a = 0; a < alive.size(); ++a)
    {
        ValidationCandidate& c = cands[alive[a]];
        if (c.scored < c.total || depthCount(depth, c, level_index, num_modalities) > 0)
            c.raw = scoreAll(level, level_index, c, depth);
        c.scored = c.total;
        survivors.push_back(alive[a]);
    }
}

} // namespace detail
} // namespace forestmod
} // namespace cv
