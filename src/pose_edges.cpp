// This file is part of OpenCV project.
// It is subject to the license terms in the LICENSE file found in the top-level directory
// of this distribution and at http://opencv.org/license.html

// Pose refinement without depth: directional chamfer alignment of the rendered object's edges
// with the scene's edges (Liu et al. CVPR 2010; D2CO, Imperoli and Pretto, ICVS 2015), solved
// with Levenberg-Marquardt over the 6 DoF. See doc/pose.md, "Refinement without depth".

#include "precomp.hpp"
#include "params_io.hpp"
#include "edge_gradient.hpp"
#include "pose_refine.hpp"
#include "opencv2/calib3d.hpp"
#include "opencv2/core/hal/intrin.hpp"

namespace cv {
namespace forestmod {

EdgeRefineParams::EdgeRefineParams()
    : orientations(16), canny_low(30), canny_high(80), max_distance(15), passes(4),
      iterations(15), max_points(400), huber(2), inlier_distance(2), inner_edges(false),
      search_angle(0), search_steps(3), hypotheses(3)
{
}

void EdgeRefineParams::read(const FileNode& fn)
{
    detail::readField(fn, "orientations", orientations);
    detail::readField(fn, "canny_low", canny_low);
    detail::readField(fn, "canny_high", canny_high);
    detail::readField(fn, "max_distance", max_distance);
    detail::readField(fn, "passes", passes);
    detail::readField(fn, "iterations", iterations);
    detail::readField(fn, "max_points", max_points);
    detail::readField(fn, "huber", huber);
    detail::readField(fn, "inlier_distance", inlier_distance);
    detail::readField(fn, "inner_edges", inner_edges);
    detail::readField(fn, "search_angle", search_angle);
    detail::readField(fn, "search_steps", search_steps);
    detail::readField(fn, "hypotheses", hypotheses);
}

void EdgeRefineParams::write(FileStorage& fs) const
{
    fs << "orientations" << orientations << "canny_low" << canny_low << "canny_high" << canny_high
       << "max_distance" << max_distance << "passes" << passes << "iterations" << iterations
       << "max_points" << max_points << "huber" << huber << "inlier_distance" << inlier_distance
       << "inner_edges" << (int)inner_edges << "search_angle" << search_angle << "search_steps"
       << search_steps << "hypotheses" << hypotheses;
}

EdgeRefineResult::EdgeRefineResult()
    : R(Matx33d::eye()), t(0, 0, 0), inlier_ratio(0), mean_distance(0), points(0), iterations(0),
      center(0, 0, 0)
{
}

static void checkEdgeParams(const EdgeRefineParams& p, const char* func)
{
    if (p.orientations < 2 || p.orientations > 32)
        CV_Error_(Error::StsOutOfRange, ("%s: EdgeRefineParams::orientations must be in [2, 32], "
                                         "got %d", func, p.orientations));
    if (!(p.canny_low >= 0 && p.canny_high >= p.canny_low))
        CV_Error_(Error::StsOutOfRange, ("%s: EdgeRefineParams needs 0 <= canny_low <= canny_high",
                                         func));
    if (!(p.max_distance > 1) || !std::isfinite(p.max_distance))
        CV_Error_(Error::StsOutOfRange, ("%s: EdgeRefineParams::max_distance must be finite and "
                                         "> 1 px, got %g", func, p.max_distance));
    // the grid search tries (2 search_steps + 1)^3 rotations
    if (!(p.search_angle >= 0 && p.search_angle <= 180) || p.search_steps < 0
        || p.search_steps > 20)
        CV_Error_(Error::StsOutOfRange, ("%s: EdgeRefineParams needs search_angle in [0, 180] "
                                         "degrees and search_steps in [0, 20], got %g and %d",
                                         func, p.search_angle, p.search_steps));
    if (p.passes < 1 || p.iterations < 1 || p.max_points < 6)
        CV_Error_(Error::StsOutOfRange, ("%s: EdgeRefineParams needs passes >= 1, iterations >= "
                                         "1 and max_points >= 6", func));
    if (!(p.huber > 0 && p.inlier_distance > 0))
        CV_Error_(Error::StsOutOfRange, ("%s: EdgeRefineParams::huber and inlier_distance must be "
                                         "positive", func));
}

namespace detail {

// Per column, the distance (px) to the nearest nonzero pixel of edges in that column, at most cap:
// a pass down and a pass up (each row from the previous one, all columns at once).
static void columnDistance(const Mat& edges, int cap, Mat& col)
{
    const int W = edges.cols, H = edges.rows;
    col.create(edges.size(), CV_8UC1);
    const bool vector_path = useOptimized();
    for (int y = 0; y < H; ++y)
    {
        const uchar* e = edges.ptr<uchar>(y);
        const uchar* above = y > 0 ? col.ptr<uchar>(y - 1) : 0;
        uchar* c = col.ptr<uchar>(y);
        int x = 0;
#if CV_SIMD128
        if (vector_path && above)
        {
            const v_uint8x16 z = v_setzero_u8(), one = v_setall_u8(1), vcap = v_setall_u8(
                (uchar)cap);
            for (; x + 16 <= W; x += 16)
            {
                const v_uint8x16 d = v_min(v_load(above + x) + one, vcap); // saturating add
                v_store(c + x, v_select(v_load(e + x) == z, d, z));
            }
        }
#endif
        for (; x < W; ++x)
            c[x] = e[x] ? 0 : (uchar)std::min(above ? above[x] + 1 : cap, cap);
    }
    for (int y = H - 2; y >= 0; --y)
    {
        const uchar* below = col.ptr<uchar>(y + 1);
        uchar* c = col.ptr<uchar>(y);
        int x = 0;
#if CV_SIMD128
        if (vector_path)
        {
            const v_uint8x16 one = v_setall_u8(1);
            for (; x + 16 <= W; x += 16)
                v_store(c + x, v_min(v_load(c + x), v_load(below + x) + one));
        }
#endif
        for (; x < W; ++x)
            c[x] = (uchar)std::min<int>(c[x], below[x] + 1);
    }
}

void truncatedDistance(const Mat& edges, double max_distance, Mat& dist)
{
    CV_Assert(edges.type() == CV_8UC1 && max_distance > 0);
    const int W = edges.cols, H = edges.rows;
    dist.create(edges.size(), CV_32FC1);
    if (max_distance > 100) // beyond the 16-bit sums below
    {
        Mat free_of = edges == 0, d;
        distanceTransform(free_of, d, DIST_L2, DIST_MASK_PRECISE);
        min(d, max_distance, dist);
        return;
    }
    // r: the reach (an edge within max_distance lies within r rows and r columns); a column
    // distance of cap = r + 1 stands for "none within reach": cap^2 > r^2 >= max_distance^2
    const int r = cvCeil(max_distance), cap = r + 1;
    Mat col;
    columnDistance(edges, cap, col);
    // per row: d^2(x) = min over |k| <= r of k^2 + col(x + k)^2, the row padded with cap
    std::vector<ushort> sq(W + 2 * r, (ushort)(cap * cap)); // the padding stays cap^2
    std::vector<ushort> best(W);
    const bool vector_path = useOptimized();
    const float top = (float)max_distance;
    for (int y = 0; y < H; ++y)
    {
        const uchar* c = col.ptr<uchar>(y);
        for (int x = 0; x < W; ++x)
            best[x] = sq[x + r] = (ushort)(c[x] * c[x]);
        for (int k = 1; k <= r; ++k)
        {
            const ushort kk = (ushort)(k * k);
            const ushort* left = &sq[r - k];
            const ushort* right = &sq[r + k];
            int x = 0;
#if CV_SIMD128
            if (vector_path)
            {
                const v_uint16x8 vkk = v_setall_u16(kk);
                for (; x + 8 <= W; x += 8)
                    v_store(&best[x], v_min(v_load(&best[x]),
                                            v_min(v_load(left + x), v_load(right + x)) + vkk));
            }
#endif
            for (; x < W; ++x)
                best[x] = std::min<ushort>(best[x], (ushort)(std::min(left[x], right[x]) + kk));
        }
        float* out = dist.ptr<float>(y);
        int x = 0;
#if CV_SIMD128
        if (vector_path)
        {
            const v_float32x4 vtop = v_setall_f32(top);
            for (; x + 8 <= W; x += 8)
            {
                v_uint32x4 lo, hi;
                v_expand(v_load(&best[x]), lo, hi);
                v_store(out + x, v_min(v_sqrt(v_cvt_f32(v_reinterpret_as_s32(lo))), vtop));
                v_store(out + x + 4, v_min(v_sqrt(v_cvt_f32(v_reinterpret_as_s32(hi))), vtop));
            }
        }
#endif
        for (; x < W; ++x)
            out[x] = std::min(std::sqrt((float)best[x]), top);
    }
}

void strongestGradient(const Mat& img, Mat& dx, Mat& dy)
{
    Mat sx, sy;
    Sobel(img, sx, CV_32F, 1, 0, 3);
    Sobel(img, sy, CV_32F, 0, 1, 3);
    const int cn = img.channels();
    dx.create(img.size(), CV_32FC1);
    dy.create(img.size(), CV_32FC1);
    for (int y = 0; y < img.rows; ++y)
    {
        const float* px = sx.ptr<float>(y);
        const float* py = sy.ptr<float>(y);
        float* ox = dx.ptr<float>(y);
        float* oy = dy.ptr<float>(y);
        for (int x = 0; x < img.cols; ++x)
        {
            int best = 0;
            float m = -1;
            for (int c = 0; c < cn; ++c)
            {
                const float v = px[x * cn + c] * px[x * cn + c] + py[x * cn + c] * py[x * cn + c];
                if (v > m)
                {
                    m = v;
                    best = c;
                }
            }
            ox[x] = px[x * cn + best];
            oy[x] = py[x * cn + best];
        }
    }
}

} // namespace detail

using detail::orientationBin;
using detail::strongestGradient;

void computeEdgeMaps(InputArray _image, EdgeMaps& maps, const EdgeRefineParams& params,
                     const Rect& _roi)
{
    checkEdgeParams(params, "computeEdgeMaps");
    Mat img = _image.getMat();
    if (img.empty())
        CV_Error(Error::StsBadArg, "computeEdgeMaps: the image is empty");
    if (img.type() != CV_8UC3 && img.type() != CV_8UC1)
        CV_Error_(Error::StsUnsupportedFormat, ("computeEdgeMaps: the image must be CV_8UC3 (BGR) "
                                                "or CV_8UC1, got %s",
                                                typeToString(img.type()).c_str()));
    const Rect full(0, 0, img.cols, img.rows);
    const Rect roi = _roi.area() > 0 ? (_roi & full) : full;
    if (roi.area() == 0)
        CV_Error(Error::StsBadArg, "computeEdgeMaps: the roi lies outside the image");
    // edges and distances inside the roi only; outside, the distance is max_distance
    maps.edges = Mat::zeros(img.size(), CV_8UC1);
    const Rect ext = Rect(roi.x - 1, roi.y - 1, roi.width + 2, roi.height + 2) & full;
    Mat sub = img(ext), sub_edges;
    Canny(sub, sub_edges, params.canny_low, params.canny_high, 3, true);
    sub_edges(Rect(roi.tl() - ext.tl(), roi.size())).copyTo(maps.edges(roi));
    Mat dx, dy;
    strongestGradient(sub, dx, dy);
    const int B = params.orientations;
    std::vector<Mat> near_bin(B); // 255 on edges of bin b or its neighbours, 0 elsewhere
    for (int b = 0; b < B; ++b)
        near_bin[b] = Mat::zeros(roi.size(), CV_8UC1);
    for (int y = 0; y < roi.height; ++y)
    {
        const uchar* e = maps.edges.ptr<uchar>(y + roi.y) + roi.x;
        const float* gx = dx.ptr<float>(y + roi.y - ext.y) + (roi.x - ext.x);
        const float* gy = dy.ptr<float>(y + roi.y - ext.y) + (roi.x - ext.x);
        for (int x = 0; x < roi.width; ++x)
        {
            if (!e[x])
                continue;
            const int b = orientationBin(gx[x], gy[x], B);
            near_bin[b].ptr<uchar>(y)[x] = 255;
            near_bin[(b + 1) % B].ptr<uchar>(y)[x] = 255;
            near_bin[(b + B - 1) % B].ptr<uchar>(y)[x] = 255;
        }
    }
    maps.distance.resize(B);
    parallel_for_(Range(0, B), [&](const Range& r) {
        for (int b = r.start; b < r.end; ++b)
        {
            Mat& d = maps.distance[b];
            d.create(img.size(), CV_32FC1);
            // max_distance outside the roi; inside, truncatedDistance writes every pixel
            const float far_away = (float)params.max_distance;
            for (int y = 0; y < d.rows; ++y)
            {
                float* row = d.ptr<float>(y);
                if (y < roi.y || y >= roi.br().y)
                    std::fill(row, row + d.cols, far_away);
                else
                {
                    std::fill(row, row + roi.x, far_away);
                    std::fill(row + roi.br().x, row + d.cols, far_away);
                }
            }
            Mat inside = d(roi);
            detail::truncatedDistance(near_bin[b], params.max_distance, inside);
        }
    });
    maps.max_distance = params.max_distance;
}

namespace {

using detail::EdgePoint;

// bilinear sample of a CV_32F map; false outside (1 px margin for the differences)
static inline bool sampleMap(const Mat& m, double u, double v, double& val, double& gu, double& gv)
{
    if (!(u >= 1 && v >= 1 && u < m.cols - 2 && v < m.rows - 2))
        return false;
    const int x = (int)u, y = (int)v;
    const double fx = u - x, fy = v - y;
    const float* r0 = m.ptr<float>(y);
    const float* r1 = m.ptr<float>(y + 1);
    const double a = r0[x], b = r0[x + 1], c = r1[x], d = r1[x + 1];
    val = (1 - fy) * ((1 - fx) * a + fx * b) + fy * ((1 - fx) * c + fx * d);
    gu = (1 - fy) * (b - a) + fy * (d - c);
    gv = (1 - fx) * (c - a) + fx * (d - b);
    return true;
}

// model edge points of the object at (R, t): its silhouette (the drawer's own when it has one,
// else the drawn mask's boundary) and, with inner_edges, the depth discontinuities inside it;
// *made receives the drawing when one was made, and is released otherwise
static void extractEdgePoints(const detail::ObjectDrawer& drawer, const Matx33d& K,
                              const Matx33d& R, const Vec3d& t, const EdgeRefineParams& p,
                              std::vector<EdgePoint>& pts, Ptr<detail::Drawing>* made = 0)
{
    pts.clear();
    if (made)
        made->release();
    static thread_local std::vector<detail::SilhouettePoint> outline;
    if (!p.inner_edges && drawer.silhouette(K, R, t, p.max_points, outline))
    {
        pts.resize(outline.size());
        for (size_t i = 0; i < outline.size(); ++i)
        {
            pts[i].model = Point3d(outline[i].model);
            pts[i].bin = orientationBin(outline[i].normal[0], outline[i].normal[1],
                                        p.orientations);
        }
        return;
    }
    const Ptr<detail::Drawing> drawn = drawer.drawing(K, R, t);
    if (made)
        *made = drawn;
    const Rect crop = drawn->rect;
    const Mat &depth = drawn->depth, &mask = drawn->mask;
    if (mask.empty())
        return;
    const Rect box = boundingRect(mask);
    if (box.area() < 16)
        return;
    const int margin = 3;
    const Rect roi = Rect(box.x - margin, box.y - margin, box.width + 2 * margin,
                          box.height + 2 * margin) & Rect(0, 0, mask.cols, mask.rows);
    Mat m = mask(roi), d = depth(roi);
    Mat inner;
    erode(m, inner, Mat(), Point(-1, -1), 1);
    Mat edge = m - inner; // silhouette: object pixels with a background neighbour
    Mat mdx, mdy;
    Mat mf;
    GaussianBlur(m, mf, Size(5, 5), 0);
    Sobel(mf, mdx, CV_32F, 1, 0, 3);
    Sobel(mf, mdy, CV_32F, 0, 1, 3);
    Mat cedges, ddx, ddy;
    if (p.inner_edges)
    {
        // depth discontinuities (self-occlusion) inside the object: geometric edges that the
        // scene shows whatever the lighting; the rendered colour's edges are not used (its
        // shading does not match the scene's, measured in doc/pose.md)
        Mat core;
        erode(m, core, Mat(), Point(-1, -1), 2);
        cedges = Mat::zeros(m.size(), CV_8UC1);
        Mat df;
        d.convertTo(df, CV_32F);
        Sobel(df, ddx, CV_32F, 1, 0, 3);
        Sobel(df, ddy, CV_32F, 0, 1, 3);
        for (int y = 0; y < d.rows; ++y)
        {
            const uchar* k = core.ptr<uchar>(y);
            const float* gx = ddx.ptr<float>(y);
            const float* gy = ddy.ptr<float>(y);
            uchar* ce = cedges.ptr<uchar>(y);
            for (int x = 0; x < d.cols; ++x)
                if (k[x] && gx[x] * gx[x] + gy[x] * gy[x] > 80.f * 80.f) // > ~10 mm per pixel
                    ce[x] = 128;
        }
    }
    struct Cand
    {
        int x, y, bin;
    };
    std::vector<Cand> cands;
    for (int y = 0; y < m.rows; ++y)
    {
        const uchar* e = edge.ptr<uchar>(y);
        const uchar* ce = cedges.empty() ? 0 : cedges.ptr<uchar>(y);
        for (int x = 0; x < m.cols; ++x)
        {
            if (e[x])
            {
                Cand k = { x, y, orientationBin(mdx.at<float>(y, x), mdy.at<float>(y, x),
                                                p.orientations) };
                cands.push_back(k);
            }
            else if (ce && ce[x] == 128)
            {
                Cand k = { x, y, orientationBin(ddx.at<float>(y, x), ddy.at<float>(y, x),
                                                p.orientations) };
                cands.push_back(k);
            }
        }
    }
    const size_t n = std::min(cands.size(), (size_t)p.max_points);
    const Matx33d Kinv = K.inv(), Rt = R.t();
    for (size_t i = 0; i < n; ++i)
    {
        const Cand& k = cands[i * cands.size() / n];
        const ushort z = d.at<ushort>(k.y, k.x);
        if (z == 0)
            continue;
        const Vec3d ray = Kinv * Vec3d(k.x + roi.x + crop.x, k.y + roi.y + crop.y, 1.0);
        const Vec3d pc = ray * (double)z;
        EdgePoint e;
        const Vec3d pm = Rt * (pc - t);
        e.model = Point3d(pm[0], pm[1], pm[2]);
        e.bin = k.bin;
        pts.push_back(e);
    }
}

// robust cost and normal equations at the pose (R, t); rotation about c (camera frame)
static double edgeCost(const std::vector<EdgePoint>& pts, const EdgeMaps& maps, double dmax,
                       const Matx33d& K, const Matx33d& R, const Vec3d& t, double huber,
                       const Vec3d& c,
                       Matx66d* JtJ, Vec6d* Jtr, int* inliers, double inlier_distance,
                       double* mean_distance)
{
    const double fx = K(0, 0), fy = K(1, 1), cx = K(0, 2), cy = K(1, 2), s = K(0, 1);
    double cost = 0, dsum = 0;
    int in = 0;
    if (JtJ)
    {
        *JtJ = Matx66d::zeros();
        *Jtr = Vec6d::all(0);
    }
    // The points in the camera's frame and their projections first, the map rows that their
    // samples read fetched meanwhile (sampled one point after another, they missed the cache),
    // then the samples and sums in the points' order.
    const size_t n = pts.size();
    AutoBuffer<double, 5 * 512> projected(5 * n);
    for (size_t i = 0; i < n; ++i)
    {
        const Vec3d X = R * Vec3d(pts[i].model.x, pts[i].model.y, pts[i].model.z) + t;
        double* q = projected.data() + 5 * i;
        q[0] = X[0];
        q[1] = X[1];
        q[2] = X[2];
        if (!(X[2] > 1e-6))
            continue;
        q[3] = fx * X[0] / X[2] + s * X[1] / X[2] + cx;
        q[4] = fy * X[1] / X[2] + cy;
        const Mat& m = maps.distance[pts[i].bin];
        if (q[3] >= 1 && q[4] >= 1 && q[3] < m.cols - 2 && q[4] < m.rows - 2)
        {
            detail::prefetchLine(m.ptr<float>((int)q[4]) + (int)q[3]);
            detail::prefetchLine(m.ptr<float>((int)q[4] + 1) + (int)q[3]);
        }
    }
    for (size_t i = 0; i < n; ++i)
    {
        const double* P = projected.data() + 5 * i;
        const Vec3d X(P[0], P[1], P[2]);
        double r = dmax, gu = 0, gv = 0;
        bool inside = X[2] > 1e-6;
        if (inside)
        {
            inside = sampleMap(maps.distance[pts[i].bin], P[3], P[4], r, gu, gv);
            if (!inside || r >= dmax)
            {
                r = dmax;
                inside = false;
            }
        }
        dsum += r;
        in += r <= inlier_distance;
        // Huber
        const double ar = std::abs(r);
        cost += ar <= huber ? 0.5 * r * r : huber * (ar - 0.5 * huber);
        if (!JtJ || !inside)
            continue;
        const double w = ar <= huber ? 1.0 : huber / ar;
        // d(u, v)/dX
        const double iz = 1.0 / X[2];
        const double du_dx = fx * iz, du_dy = s * iz, du_dz = -(fx * X[0] + s * X[1]) * iz * iz;
        const double dv_dy = fy * iz, dv_dz = -fy * X[1] * iz * iz;
        const Vec3d g(gu * du_dx, gu * du_dy + gv * dv_dy, gu * du_dz + gv * dv_dz); // dr/dX
        // X' = exp(w)(X - c) + c + v: dX/dw = -[X - c]x, dX/dv = I
        const Vec3d q = X - c;
        const Vec3d gw = q.cross(g); // g^T (-[q]x) = (q x g)^T
        Vec6d J(gw[0], gw[1], gw[2], g[0], g[1], g[2]);
        for (int a = 0; a < 6; ++a)
        {
            (*Jtr)[a] += w * J[a] * r;
            for (int b = a; b < 6; ++b)
                (*JtJ)(a, b) += w * J[a] * J[b];
        }
    }
    if (JtJ)
        for (int a = 0; a < 6; ++a)
            for (int b = 0; b < a; ++b)
                (*JtJ)(a, b) = (*JtJ)(b, a);
    if (inliers)
        *inliers = in;
    if (mean_distance)
        *mean_distance = pts.empty() ? dmax : dsum / pts.size();
    return cost;
}

} // namespace

static EdgeRefineResult refineFrom(const detail::ObjectDrawer& drawer, const EdgeMaps& maps,
                                   const Matx33d& K, const Matx33d& R0, const Vec3d& t0,
                                   const EdgeRefineParams& params, Ptr<detail::Drawing>* last);

EdgeRefineResult refinePoseEdges(Renderer& renderer, int handle, const EdgeMaps& maps,
                                 const Matx33d& K, const Matx33d& R0, const Vec3d& t0,
                                 const EdgeRefineParams& params)
{
    return detail::refinePoseEdges(detail::RendererDrawer(renderer, handle), maps, K, R0, t0,
                                   params);
}

namespace detail {

void checkEdgeMaps(const EdgeMaps& maps, int orientations, Size image, const char* who)
{
    if ((int)maps.distance.size() != orientations)
        CV_Error_(Error::StsBadArg, ("%s: the edge maps have %d orientation bins but "
                                     "the params' orientations are %d (computeEdgeMaps() with the "
                                     "same params)", who, (int)maps.distance.size(),
                                     orientations));
    for (size_t b = 0; b < maps.distance.size(); ++b)
        if (maps.distance[b].type() != CV_32FC1 || maps.distance[b].size() != image)
            CV_Error_(Error::StsBadSize, ("%s: the edge maps must be CV_32FC1 of the image's size "
                                          "%dx%d (computeEdgeMaps() of that image); map %d is %s "
                                          "%dx%d", who, image.width, image.height, (int)b,
                                          typeToString(maps.distance[b].type()).c_str(),
                                          maps.distance[b].cols, maps.distance[b].rows));
}

EdgeRefineResult refinePoseEdges(const ObjectDrawer& drawer, const EdgeMaps& maps,
                                 const Matx33d& K, const Matx33d& R0, const Vec3d& t0,
                                 const EdgeRefineParams& params, Ptr<Drawing>* last)
{
    checkEdgeParams(params, "refinePoseEdges");
    checkEdgeMaps(maps, params.orientations, drawer.imageSize(), "refinePoseEdges");
    checkIntrinsics(K, "refinePoseEdges", "K");
    if (!(params.search_angle >= 0) || params.search_steps < 0 || params.hypotheses < 1)
        CV_Error(Error::StsOutOfRange, "refinePoseEdges: EdgeRefineParams needs search_angle >= "
                                       "0, search_steps >= 0 and hypotheses >= 1");
    std::vector<std::pair<double, Matx33d> > starts; // (mean distance, rotation increment)
    Vec3d c(0, 0, 0);
    if (params.search_angle > 0 && params.search_steps > 0)
    {
        // coarse search over rotations about the object's centre: the model edge points of the
        // start pose, turned on a grid of +-search_angle about the camera axes, scored without
        // rendering again (the silhouette changes little within a few degrees)
        std::vector<EdgePoint> pts;
        extractEdgePoints(drawer, K, R0, t0, params, pts);
        if (pts.size() >= 6)
        {
            for (size_t i = 0; i < pts.size(); ++i)
                c += R0 * Vec3d(pts[i].model.x, pts[i].model.y, pts[i].model.z) + t0;
            c *= 1.0 / pts.size();
            const int S = params.search_steps;
            const double step = params.search_angle / S * CV_PI / 180;
            for (int i = -S; i <= S; ++i)
                for (int j = -S; j <= S; ++j)
                    for (int k = -S; k <= S; ++k)
                    {
                        Matx33d dR;
                        Rodrigues(Vec3d(i * step, j * step, k * step), dR);
                        double mean = 0;
                        edgeCost(pts, maps, maps.max_distance, K, dR * R0, dR * (t0 - c) + c,
                                 params.huber, c, 0, 0, 0, params.inlier_distance, &mean);
                        starts.push_back(std::make_pair(mean, dR));
                    }
            std::stable_sort(starts.begin(), starts.end(),
                             [](const std::pair<double, Matx33d>& a,
                                const std::pair<double, Matx33d>& b) { return a.first < b.first; });
        }
    }
    // the start itself is always refined first (the grid's scores are biased: its silhouette is
    // the start's, turned, not the one rendered at the turned pose)
    starts.insert(starts.begin(), std::make_pair(0.0, Matx33d::eye()));
    // the best few starts refined (render + Levenberg-Marquardt); the one with the most inliers
    EdgeRefineResult best;
    best.R = R0;
    best.t = t0;
    int iterations = 0;
    bool any = false;
    for (size_t h = 0; h < starts.size() && (int)h <= params.hypotheses; ++h)
    {
        const Matx33d& dR = starts[h].second;
        Ptr<Drawing> drawn;
        const EdgeRefineResult r = refineFrom(drawer, maps, K, dR * R0,
                                              dR * (t0 - c) + c, params, last ? &drawn : 0);
        iterations += r.iterations;
        if (r.points > 0 && (!any || r.inlier_ratio > best.inlier_ratio))
        {
            best = r;
            any = true;
            if (last)
                *last = drawn;
        }
    }
    best.iterations = iterations;
    return best;
}

} // namespace detail

namespace detail {

EdgeFit::EdgeFit(const ObjectDrawer& drawer, const EdgeMaps& maps, const Matx33d& K,
                 const Matx33d& R0, const Vec3d& t0, const EdgeRefineParams& params)
    : drawer_(&drawer), maps_(&maps), K_(K), params_(params), pass_(0), drawn_(false)
{
    res_.R = R0;
    res_.t = t0;
}

void EdgeFit::run(int end)
{
    const EdgeRefineParams& params = params_;
    EdgeRefineResult& res = res_;
    std::vector<EdgePoint>& pts = pts_;
    end = std::min(end, params.passes);
    for (; pass_ < end; ++pass_)
    {
        if (!drawn_)
            extractEdgePoints(*drawer_, K_, res.R, res.t, params, pts);
        drawn_ = false;
        drawing_.release();
        if (pts.size() < 6)
        {
            pass_ = params.passes; // nothing to fit: the quality says so
            break;
        }
        // rotation centre: centroid of the edge points in the camera frame
        Vec3d c(0, 0, 0);
        for (size_t i = 0; i < pts.size(); ++i)
            c += res.R * Vec3d(pts[i].model.x, pts[i].model.y, pts[i].model.z) + res.t;
        c *= 1.0 / pts.size();
        // coarse to fine: the truncation shrinks from max_distance to a third of it
        const double top = std::min(params.max_distance, maps_->max_distance);
        const double dmax = params.passes == 1 ? top
            : top * (1.0 - (2.0 / 3.0) * pass_ / (params.passes - 1));
        levenbergMarquardt(pts, dmax, c);
    }
}

void EdgeFit::levenbergMarquardt(const std::vector<EdgePoint>& pts, double dmax, Vec3d c)
{
    const EdgeRefineParams& params = params_;
    EdgeRefineResult& res = res_;
    const EdgeMaps& maps = *maps_;
    const Matx33d& K = K_;
    double lambda = 1e-3;
    Matx66d A;
    Vec6d b;
    double cost = edgeCost(pts, maps, dmax, K, res.R, res.t, params.huber, c, &A, &b, 0, 0, 0);
    for (int it = 0; it < params.iterations; ++it)
    {
        ++res.iterations;
        bool accepted = false, converged = false;
        const double before = cost;
        for (int tries = 0; tries < 6 && !accepted; ++tries)
        {
            Matx66d H = A;
            for (int k = 0; k < 6; ++k)
                H(k, k) += lambda * (A(k, k) + 1e-9);
            Vec6d delta;
            if (!solve(H, -b, delta, DECOMP_CHOLESKY))
            {
                lambda *= 10;
                continue;
            }
            Matx33d dR;
            Rodrigues(Vec3d(delta[0], delta[1], delta[2]), dR);
            const Matx33d R2 = dR * res.R;
            const Vec3d t2 = dR * (res.t - c) + c + Vec3d(delta[3], delta[4], delta[5]);
            // the rotation centre moves with the object; the normal equations at the step's pose
            // are summed with its cost, ready for the next iteration when the step is accepted
            const Vec3d c2 = c + Vec3d(delta[3], delta[4], delta[5]);
            Matx66d A2;
            Vec6d b2;
            const double cost2 = edgeCost(pts, maps, dmax, K, R2, t2, params.huber, c2, &A2, &b2,
                                          0, 0, 0);
            if (cost2 < cost)
            {
                c = c2;
                res.R = R2;
                res.t = t2;
                lambda = std::max(lambda * 0.3, 1e-7);
                cost = cost2;
                A = A2;
                b = b2;
                accepted = true;
                // converged: the step lowered the cost by less than 0.1 %
                converged = before - cost < 1e-3 * before;
            }
            else
                lambda *= 10;
        }
        if (!accepted || converged)
            break;
    }
}

double EdgeFit::inlierRatio()
{
    std::vector<EdgePoint>& pts = pts_;
    if (!drawn_)
        extractEdgePoints(*drawer_, K_, res_.R, res_.t, params_, pts, &drawing_);
    drawn_ = true; // the next pass (or finish(), after the last) starts from these points
    int in = 0;
    edgeCost(pts, *maps_, maps_->max_distance, K_, res_.R, res_.t, params_.huber, Vec3d(), 0, 0,
             &in, params_.inlier_distance, 0);
    return pts.size() < 6 ? 0.0 : double(in) / pts.size();
}

EdgeRefineResult EdgeFit::finish(Ptr<Drawing>* last)
{
    run(params_.passes);
    // quality at the final pose, with its own points (drawn already when inlierRatio() was asked
    // after the last pass); *last gets a drawing at that pose
    EdgeRefineResult res = res_;
    std::vector<EdgePoint>& pts = pts_;
    if (!drawn_)
        extractEdgePoints(*drawer_, K_, res.R, res.t, params_, pts, &drawing_);
    if (last) // the points' drawing, or one made for it (the points came without drawing)
        *last = drawing_.empty() ? drawer_->drawing(K_, res.R, res.t) : drawing_;
    res.points = (int)pts.size();
    int in = 0;
    edgeCost(pts, *maps_, maps_->max_distance, K_, res.R, res.t, params_.huber, Vec3d(), 0, 0,
             &in, params_.inlier_distance, &res.mean_distance);
    res.inlier_ratio = pts.empty() ? 0.0 : double(in) / pts.size();
    Vec3d c(0, 0, 0);
    for (size_t i = 0; i < pts.size(); ++i)
        c += Vec3d(pts[i].model.x, pts[i].model.y, pts[i].model.z);
    res.center = pts.empty() ? c : c * (1.0 / pts.size());
    return res;
}

} // namespace detail

static EdgeRefineResult refineFrom(const detail::ObjectDrawer& drawer, const EdgeMaps& maps,
                                   const Matx33d& K, const Matx33d& R0, const Vec3d& t0,
                                   const EdgeRefineParams& params, Ptr<detail::Drawing>* last)
{
    detail::EdgeFit fit(drawer, maps, K, R0, t0, params);
    return fit.finish(last);
}

} // namespace forestmod
} // namespace cv
