// This file is part of OpenCV project.
// It is subject to the license terms in the LICENSE file found in the top-level directory
// of this distribution and at http://opencv.org/license.html

// The outer silhouette of a closed mesh from its silhouette edges: the edge alignment's points
// without drawing the faces (doc/pose.md, "Drawing at detection time").

#include "precomp.hpp"
#include "silhouette.hpp"
#include "draw_mesh.hpp"

#include "opencv2/core/hal/intrin.hpp"
#include "opencv2/imgproc.hpp"

#include <algorithm>
#include <map>

namespace cv {
namespace forestmod {
namespace detail {

SilhouetteEdges silhouetteEdges(const Mesh& mesh, int winding)
{
    SilhouetteEdges s;
    if (winding == 0 || mesh.faces.empty())
        return s;
    s.box_min = mesh.bboxMin();
    s.box_max = mesh.bboxMax();
    const int nf = (int)mesh.faces.size();
    s.plane.resize(4 * (size_t)nf);
    std::map<std::pair<int, int>, std::vector<int> > faces_of;
    for (int f = 0; f < nf; ++f)
    {
        const Vec3i& F = mesh.faces[f];
        const Point3f &p0 = mesh.vertices[F[0]], &p1 = mesh.vertices[F[1]],
                      &p2 = mesh.vertices[F[2]];
        const Point3f n = (p1 - p0).cross(p2 - p0) * (float)winding;
        s.plane[f] = n.x;
        s.plane[nf + f] = n.y;
        s.plane[2 * nf + f] = n.z;
        s.plane[3 * nf + f] = n.dot(p0);
        for (int k = 0; k < 3; ++k)
        {
            const int a = F[k], b = F[(k + 1) % 3];
            faces_of[std::make_pair(std::min(a, b), std::max(a, b))].push_back(f);
        }
    }
    std::vector<std::pair<Vec2i, Vec2i> > edges; // (faces, ends), ordered by the first face
    for (std::map<std::pair<int, int>, std::vector<int> >::const_iterator it = faces_of.begin();
         it != faces_of.end(); ++it)
    {
        const std::vector<int>& f = it->second;
        const Vec2i ends(it->first.first, it->first.second);
        if (f.size() == 2)
            edges.push_back(std::make_pair(Vec2i(f[0], f[1]), ends));
        else
            for (size_t k = 0; k < f.size(); ++k)
                edges.push_back(std::make_pair(Vec2i(f[k], -1), ends));
    }
    std::stable_sort(edges.begin(), edges.end(),
                     [](const std::pair<Vec2i, Vec2i>& x, const std::pair<Vec2i, Vec2i>& y) {
                         return x.first[0] < y.first[0];
                     });
    for (size_t e = 0; e < edges.size(); ++e)
    {
        s.faces.push_back(edges[e].first);
        s.ends.push_back(edges[e].second);
    }
    // the blocks' chunks (listSilhouetteEdges skips the blocks whose chunks are uniform)
    const int ne = (int)s.faces.size(), C = SilhouetteEdges::kChunkFaces;
    const int missing = (nf + C - 1) / C, mixed = missing + 1;
    s.block_start.push_back(0);
    for (int b = 0; b < ne; b += SilhouetteEdges::kBlockEdges)
    {
        std::vector<int> chunks;
        for (int e = b; e < std::min(ne, b + (int)SilhouetteEdges::kBlockEdges); ++e)
            for (int k = 0; k < 2; ++k)
            {
                const int f = s.faces[e][k], c = f >= 0 ? f / C : missing;
                if (std::find(chunks.begin(), chunks.end(), c) == chunks.end())
                    chunks.push_back(c);
            }
        if (chunks.size() > (size_t)SilhouetteEdges::kBlockChunks)
            chunks.assign(1, mixed);
        s.block_chunks.insert(s.block_chunks.end(), chunks.begin(), chunks.end());
        s.block_start.push_back((int)s.block_chunks.size());
    }
    return s;
}

namespace {

// A silhouette edge with its ends projected: (u, v) in the buffer and depth z.
struct ProjectedEdge
{
    int edge;
    Vec2f a, b;
    float za, zb;
};

// The silhouette edges projected into the buffer `lines` (1 on their pixels), each pixel with the
// index of the edge nearest in depth there (the depth and the index are read only where lines
// is set, so only lines is cleared).
class EdgeLines
{
public:
    explicit EdgeLines(Size size) : size_(size)
    {
        static thread_local std::vector<uchar> lines_data;
        static thread_local std::vector<float> w_data;
        static thread_local std::vector<int> edge_data;
        const size_t n = (size_t)size.area();
        lines_data.assign(n, 0);
        w_data.resize(n);
        edge_data.resize(n);
        lines = Mat(size, CV_8U, lines_data.data());
        w_ = w_data.data();
        edge_ = edge_data.data();
    }
    void draw(int e, const ProjectedEdge& p)
    {
        const int x0 = cvRound(p.a[0]), y0 = cvRound(p.a[1]);
        const int x1 = cvRound(p.b[0]), y1 = cvRound(p.b[1]);
        if (std::min(x0, x1) < 0 || std::min(y0, y1) < 0 || std::max(x0, x1) >= size_.width
            || std::max(y0, y1) >= size_.height)
            return; // not within the bounding box's projection: never on the outline
        // one pixel per step along the longer axis (8-connected); the inverse depth is linear
        // along the projected line, and the nearer edge has the larger one
        const int n = std::max(std::abs(x1 - x0), std::abs(y1 - y0));
        const float step = n ? 1.f / n : 0.f;
        const float dx = (x1 - x0) * step, dy = (y1 - y0) * step;
        const float w0 = 1.f / p.za, dw = (1.f / p.zb - w0) * step;
        uchar* l = lines.ptr<uchar>();
        for (int k = 0; k <= n; ++k)
        {
            const size_t i = (size_t)(y0 + cvRound(k * dy)) * size_.width + x0 + cvRound(k * dx);
            const float w = w0 + k * dw;
            if (!l[i] || w > w_[i])
            {
                l[i] = 1;
                w_[i] = w;
                edge_[i] = e;
            }
        }
    }
    int at(Point q) const { return edge_[(size_t)q.y * size_.width + q.x]; }

    Mat lines;

private:
    Size size_;
    float* w_; // inverse depth
    int* edge_;
};

// front[f] = 255 when face f looks towards a camera at `centre` (model frame), else 0: plane holds
// the faces' normals' x, y, z and offsets, n faces each. The vector path (16 faces at a time)
// makes the scalar path's operations in its order: the same bytes.
static void facingCamera(const float* plane, int n, const Vec3d& centre, uchar* front)
{
    const float cx = (float)centre[0], cy = (float)centre[1], cz = (float)centre[2];
    const float *nx = plane, *ny = plane + n, *nz = plane + 2 * n, *off = plane + 3 * n;
    int f = 0;
#if CV_SIMD128
    if (useOptimized())
    {
        const v_float32x4 vx = v_setall_f32(cx), vy = v_setall_f32(cy), vz = v_setall_f32(cz);
        for (; f + 16 <= n; f += 16)
        {
            v_uint32x4 m[4];
            for (int j = 0; j < 4; ++j)
            {
                const int i = f + 4 * j;
                const v_float32x4 dot = v_load(nx + i) * vx + v_load(ny + i) * vy
                    + v_load(nz + i) * vz;
                m[j] = v_reinterpret_as_u32(dot > v_load(off + i));
            }
            v_store(front + f, v_pack(v_pack(m[0], m[1]), v_pack(m[2], m[3])));
        }
    }
#endif
    for (; f < n; ++f)
        front[f] = nx[f] * cx + ny[f] * cy + nz[f] * cz > off[f] ? 255 : 0;
}

} // namespace

// Per chunk of SilhouetteEdges::kChunkFaces faces: 0 when none of them faces the camera, 255
// when all do, else 1; then 0 for the missing face of the edges without a second one and 1 for
// the blocks that are never uniform (silhouetteEdges()).
static void chunkStates(const uchar* front, int nf, std::vector<uchar>& state)
{
    const int C = SilhouetteEdges::kChunkFaces, nc = (nf + C - 1) / C;
    state.resize(nc + 2);
    int c = 0;
#if CV_SIMD128
    static_assert(SilhouetteEdges::kChunkFaces == 16, "a chunk is one 16-byte vector of flags");
    for (; (c + 1) * C <= nf; ++c)
    {
        const v_uint8x16 v = v_load(front + c * C);
        state[c] = !v_check_any(v != v_setzero_u8()) ? 0
            : v_check_all(v == v_setall_u8(255)) ? 255 : 1;
    }
#endif
    for (; c < nc; ++c)
    {
        const int end = std::min(nf, (c + 1) * C);
        int ones = 0;
        for (int f = c * C; f < end; ++f)
            ones += front[f] != 0;
        state[c] = ones == 0 ? 0 : ones == end - c * C ? 255 : 1;
    }
    state[nc] = 0;
    state[nc + 1] = 1;
}

// The edges of `s` where a face that looks towards the camera (front) meets one that does not, or
// that a front face shares with no other face or with several: their indices into listed, in
// order, without a branch per edge (a few per cent of them are listed); returns their number.
// With the blocks (useOptimized()), a block of edges whose faces' chunks all look the same way
// is passed over: none of its edges is listed either way.
static int listSilhouetteEdges(const SilhouetteEdges& s, const uchar* front, int nf, int* listed)
{
    const int ne = (int)s.faces.size();
    const Vec2i* faces = s.faces.data();
    const int B = SilhouetteEdges::kBlockEdges;
    const bool blocks = useOptimized() && s.block_start.size() == (size_t)(ne + B - 1) / B + 1;
    static thread_local std::vector<uchar> state;
    if (blocks)
        chunkStates(front, nf, state);
    int n = 0;
    for (int b = 0; b < ne; b += B)
    {
        if (blocks)
        {
            const int* c = s.block_chunks.data() + s.block_start[b / B];
            const int* c_end = s.block_chunks.data() + s.block_start[b / B + 1];
            const uchar first = state[*c];
            bool uniform = first != 1;
            for (++c; uniform && c < c_end; ++c)
                uniform = state[*c] == first;
            if (uniform)
                continue;
        }
        for (int e = b, end = std::min(ne, b + B); e < end; ++e)
        {
            listed[n] = e;
            n += front[faces[e][0]] != (faces[e][1] >= 0 ? front[faces[e][1]] : 0);
        }
    }
    return n;
}

// Up to max_points pixels of the outlines (cv::findContours) within `inside` (buffer
// coordinates), evenly spaced along them, each as the point of the edge drawn there whose
// projection is nearest the pixel, moved half a pixel into the outline (at its depth, across the
// line of sight), with the outline's normal (between the pixels 2 before and 2 after it). K, R:
// the camera and the model's rotation.
static void sampleOutlines(const std::vector<std::vector<Point> >& outlines, const Rect& inside,
                           const EdgeLines& lines, const std::vector<ProjectedEdge>& drawn,
                           const Mesh& mesh, const SilhouetteEdges& s, const Matx33d& K,
                           const Matx33d& R, int max_points, std::vector<SilhouettePoint>& pts)
{
    const int reach = 2;
    std::vector<Point> on_image, along;
    std::vector<float> turn; // +-1: the side of `along`'s perpendicular that the outline encloses
    for (size_t c = 0; c < outlines.size(); ++c)
    {
        const std::vector<Point>& o = outlines[c];
        const int m = (int)o.size();
        const float side = contourArea(o, true) > 0 ? 1.f : -1.f;
        for (int i = 0; i < m; ++i)
            if (inside.contains(o[i]))
            {
                on_image.push_back(o[i]);
                along.push_back(o[(i + reach) % m] - o[(i + m * reach - reach) % m]);
                turn.push_back(side);
            }
    }
    const Matx33f Rt = Matx33f(R.t());
    const float half_fx = 0.5f / (float)K(0, 0), half_fy = 0.5f / (float)K(1, 1);
    const size_t n = std::min(on_image.size(), (size_t)std::max(0, max_points));
    pts.resize(n);
    for (size_t i = 0; i < n; ++i)
    {
        const size_t k = i * on_image.size() / n;
        const Point q = on_image[k];
        const ProjectedEdge& p = drawn[lines.at(q)];
        // the nearest point of the projected edge, and the edge's point there (perspective)
        const Vec2f d = p.b - p.a;
        const float dd = d.dot(d);
        const float s2 = dd > 0 ? std::min(1.f, std::max(0.f, (Vec2f((float)q.x, (float)q.y)
                                                                - p.a).dot(d) / dd))
                                : 0.f;
        const float s3 = (s2 / p.zb) / ((1.f - s2) / p.za + s2 / p.zb);
        const Point3f &A = mesh.vertices[s.ends[p.edge][0]],
                      &B = mesh.vertices[s.ends[p.edge][1]];
        const Vec2f normal((float)-along[k].y, (float)along[k].x);
        const float length = std::sqrt(normal.dot(normal));
        Point3f point = A + (B - A) * s3;
        if (length > 0)
        {
            // half a pixel inwards at the point's depth: where the object's outermost drawn
            // pixels lie on average (their centres covered), and what the edge maps are fitted
            // to best (doc/pose.md, "Drawing at detection time")
            const float z = (1.f - s3) * p.za + s3 * p.zb, f = turn[k] * z / length;
            const Vec3f shift = Rt * Vec3f(normal[0] * f * half_fx, normal[1] * f * half_fy, 0.f);
            point += Point3f(shift[0], shift[1], shift[2]);
        }
        pts[i].model = point;
        pts[i].normal = normal;
    }
}

bool meshSilhouette(const Mesh& mesh, const SilhouetteEdges& s, const Matx33d& K,
                    const Matx33d& R, const Vec3d& t, Size image, int max_points,
                    std::vector<SilhouettePoint>& pts)
{
    pts.clear();
    CV_Assert(s.plane.size() == 4 * mesh.faces.size() && s.faces.size() == s.ends.size());
    // the buffer: the projected bounding box and 2 px around it (cv::findContours ignores a
    // buffer's outer pixels), not clipped to the image, so that the outline goes around the
    // whole object
    Rect2d box;
    if (!projectedBox(s.box_min, s.box_max, K, R, t, box))
        return true;
    if (!(box.br().x > 0 && box.br().y > 0 && box.x < image.width && box.y < image.height))
        return true; // not on the image
    if (!(box.width <= 2.0 * image.width && box.height <= 2.0 * image.height))
        return false; // its buffer would be larger than the drawing's crop, the image
    const Point origin(cvFloor(box.x) - 2, cvFloor(box.y) - 2);
    EdgeLines lines(Size(cvCeil(box.width) + 6, cvCeil(box.height) + 6));
    // faces that look towards the camera (its centre in the model frame: -R^T t)
    const int nf = (int)mesh.faces.size();
    static thread_local std::vector<uchar> front;
    front.resize(nf);
    facingCamera(s.plane.data(), nf, -(R.t() * t), front.data());
    static thread_local std::vector<int> listed;
    listed.resize(s.faces.size());
    const int nl = listSilhouetteEdges(s, front.data(), nf, listed.data());
    // the silhouette edges projected and drawn
    const Matx33f KR = Matx33f(K * R);
    const Vec3f Kt = Vec3f(K * t);
    static thread_local std::vector<ProjectedEdge> drawn;
    drawn.clear();
    for (int i = 0; i < nl; ++i)
    {
        const int e = listed[i];
        const Point3f &A = mesh.vertices[s.ends[e][0]], &B = mesh.vertices[s.ends[e][1]];
        const Vec3f qa = KR * Vec3f(A.x, A.y, A.z) + Kt, qb = KR * Vec3f(B.x, B.y, B.z) + Kt;
        if (!(qa[2] > 1.f && qb[2] > 1.f))
            continue;
        ProjectedEdge p;
        p.edge = e;
        p.a = Vec2f(qa[0] / qa[2] - origin.x, qa[1] / qa[2] - origin.y);
        p.b = Vec2f(qb[0] / qb[2] - origin.x, qb[1] / qb[2] - origin.y);
        p.za = qa[2];
        p.zb = qb[2];
        lines.draw((int)drawn.size(), p);
        drawn.push_back(p);
    }
    std::vector<std::vector<Point> > outlines;
    findContours(lines.lines, outlines, RETR_EXTERNAL, CHAIN_APPROX_NONE);
    // the image but its outermost pixels (there an edge's distance map has no neighbour)
    sampleOutlines(outlines, Rect(1 - origin.x, 1 - origin.y, image.width - 2, image.height - 2),
                   lines, drawn, mesh, s, K, R, max_points, pts);
    return true;
}

} // namespace detail
} // namespace forestmod
} // namespace cv
