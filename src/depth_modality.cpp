// This file is part of OpenCV project.
// It is subject to the license terms in the LICENSE file found in the top-level directory
// of this distribution and at http://opencv.org/license.html

// Depth as a validation modality (paper: "we add depth value as another modality in the
// validation stage to measure shape similarity"): a template's depth samples, predicted for the
// candidate's image position, scored against the scene's depth range like LINEMOD features.

#include "precomp.hpp"
#include "depth_modality.hpp"

namespace cv {
namespace forestmod {
namespace detail {

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

// Third row of the rotation that turns the template's ray onto the candidate's, for the
// template's top-left at `origin` (level 0); (0, 0, 1) without a pose.
static Vec3f depthRotationRow(const DepthContext& dc, const DepthTemplate& t, Point origin)
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
    // clamped (NaN: the upper end): scene minus predicted depth stays an int for any pose
    const float d = row[0] * X + row[1] * Y + row[2] * z;
    return cvRound(std::max(-1e7f, std::min(1e7f, d)));
}

// 0..4 by the residual r (mm): 4 when r <= tol, 2 when r <= 2 tol, 1 when r <= 3 tol, else 0.
static inline int depthResponse(int r, int tol)
{
    r = r < 0 ? -r : r;
    return r <= tol ? 4 : r <= 2 * tol ? 2 : r <= 3 * tol ? 1 : 0;
}

int depthSimilarity(const DepthContext& dc, const DepthTemplate& t, Point origin, int count)
{
    int n = t.samples ? std::min(256, static_cast<int>(t.samples->size())) : 0;
    if (count >= 0)
        n = std::min(n, count);
    if (n == 0)
        return 0;
    const Vec3f row = depthRotationRow(dc, t, origin);
    // one pass over the samples: those with scene depth (a sample without, or outside the
    // image, scores 0 like a feature without a value), their predicted depth and the offset
    // (scene minus predicted) of each
    const Mat& d = dc.depth;
    const Point3i* samples = &(*t.samples)[0];
    int pred[256], diff[256];
    Point at[256];
    int k = 0;
    for (int i = 0; i < n; ++i)
    {
        const int x = origin.x + samples[i].x, y = origin.y + samples[i].y;
        if ((unsigned)x >= (unsigned)d.cols || (unsigned)y >= (unsigned)d.rows)
            continue;
        const int z = d.ptr<ushort>(y)[x];
        if (z == 0)
            continue;
        pred[k] = predictedDepth(t, row, samples[i]);
        diff[k] = z - pred[k];
        at[k++] = Point(x, y);
    }
    // fewer than a quarter of the samples with depth: every sample scores 0
    if (k == 0 || 4 * k < n)
        return 0;
    // the median offset; each sample then scores by how far its predicted depth plus the
    // offset lies outside the scene's range around it
    std::nth_element(diff, diff + k / 2, diff + k);
    const int offset = diff[k / 2];
    int sum = 0;
    for (int j = 0; j < k; ++j)
    {
        const int z = pred[j] + offset;
        const int lo = dc.zmin.ptr<ushort>(at[j].y)[at[j].x];
        const int hi = dc.zmax.ptr<ushort>(at[j].y)[at[j].x];
        sum += depthResponse(z < lo ? lo - z : z > hi ? z - hi : 0, dc.tolerance);
    }
    return sum;
}

} // namespace detail
} // namespace forestmod
} // namespace cv
