// This file is part of OpenCV project.
// It is subject to the license terms in the LICENSE file found in the top-level directory
// of this distribution and at http://opencv.org/license.html

// Drawing a mesh without OpenGL: vertex clustering, the closed-mesh test and a small z-buffered
// rasterizer into the crop around the object's projection. The verification and the edge
// refinement draw their hypotheses with it, in parallel (the OSMesa Renderer needs a lock).

#include "precomp.hpp"
#include "draw_mesh.hpp"

#include "opencv2/core/hal/intrin.hpp"

#include <map>

namespace cv {
namespace forestmod {
namespace detail {

double drawingCell(double diameter)
{
    return std::min(diameter / 64, 2.5);
}

Mesh coarseMesh(const Mesh& mesh, double cell)
{
    if (!(cell > 0) || mesh.vertices.empty())
        return mesh;
    const Point3f lo = mesh.bboxMin();
    const bool has_colors = mesh.colors.size() == mesh.vertices.size();
    std::map<int64, int> cell_index;
    std::vector<int> remap(mesh.vertices.size());
    std::vector<Vec3d> sum;
    std::vector<Vec3d> colour;
    std::vector<int> count;
    for (size_t i = 0; i < mesh.vertices.size(); ++i)
    {
        const Point3f& v = mesh.vertices[i];
        const int64 ix = (int64)((v.x - lo.x) / cell), iy = (int64)((v.y - lo.y) / cell),
                    iz = (int64)((v.z - lo.z) / cell);
        const int64 key = (ix * 1000003 + iy) * 1000003 + iz;
        std::map<int64, int>::iterator it = cell_index.find(key);
        if (it == cell_index.end())
        {
            it = cell_index.insert(std::make_pair(key, (int)sum.size())).first;
            sum.push_back(Vec3d::all(0));
            colour.push_back(Vec3d::all(0));
            count.push_back(0);
        }
        const int k = it->second;
        remap[i] = k;
        sum[k] += Vec3d(v.x, v.y, v.z);
        if (has_colors)
            colour[k] += Vec3d(mesh.colors[i][0], mesh.colors[i][1], mesh.colors[i][2]);
        ++count[k];
    }
    Mesh out;
    for (size_t k = 0; k < sum.size(); ++k)
    {
        const Vec3d p = sum[k] * (1.0 / count[k]);
        out.vertices.push_back(Point3f((float)p[0], (float)p[1], (float)p[2]));
        if (has_colors)
        {
            const Vec3d c = colour[k] * (1.0 / count[k]);
            out.colors.push_back(Vec3b(saturate_cast<uchar>(c[0]), saturate_cast<uchar>(c[1]),
                                       saturate_cast<uchar>(c[2])));
        }
    }
    for (size_t f = 0; f < mesh.faces.size(); ++f)
    {
        const Vec3i& F = mesh.faces[f];
        const Vec3i G(remap[F[0]], remap[F[1]], remap[F[2]]);
        if (G[0] != G[1] && G[1] != G[2] && G[0] != G[2])
            out.faces.push_back(G);
    }
    return out;
}

int closedWinding(const Mesh& mesh)
{
    const size_t nf = mesh.faces.size();
    if (nf == 0)
        return 0;
    const uint64 nv = mesh.vertices.size();
    std::vector<uint64> edges;
    edges.reserve(3 * nf);
    double volume = 0;
    for (size_t f = 0; f < nf; ++f)
    {
        const Vec3i& F = mesh.faces[f];
        for (int k = 0; k < 3; ++k)
            edges.push_back((uint64)F[k] * nv + (uint64)F[(k + 1) % 3]);
        const Point3f &a = mesh.vertices[F[0]], &b = mesh.vertices[F[1]], &c = mesh.vertices[F[2]];
        volume += (double)a.dot(b.cross(c));
    }
    std::sort(edges.begin(), edges.end());
    // a directed edge is paired when it occurs once and its reverse once
    size_t paired = 0;
    for (size_t i = 0; i < edges.size(); ++i)
    {
        const bool repeated = (i > 0 && edges[i - 1] == edges[i])
            || (i + 1 < edges.size() && edges[i + 1] == edges[i]);
        if (repeated)
            continue;
        const uint64 reverse = (edges[i] % nv) * nv + edges[i] / nv;
        const std::pair<std::vector<uint64>::const_iterator, std::vector<uint64>::const_iterator>
            r = std::equal_range(edges.begin(), edges.end(), reverse);
        paired += r.second - r.first == 1;
    }
    if (paired < 0.99 * edges.size() || volume == 0)
        return 0;
    return volume > 0 ? 1 : -1;
}

// Key of a unit vector on a 16 x 16 octahedral grid of directions (0 .. 255).
static int directionCell(const Vec3d& n)
{
    const double s = std::abs(n[0]) + std::abs(n[1]) + std::abs(n[2]);
    double u = n[0] / s, v = n[1] / s;
    if (n[2] < 0)
    {
        const double fu = (1 - std::abs(v)) * (u >= 0 ? 1 : -1);
        v = (1 - std::abs(u)) * (v >= 0 ? 1 : -1);
        u = fu;
    }
    const int bu = std::min(15, std::max(0, (int)((u + 1) * 8)));
    const int bv = std::min(15, std::max(0, (int)((v + 1) * 8)));
    return bu * 16 + bv;
}

// Z-order code of a cell (x, y, z in 0 .. 31).
static int zOrder(int x, int y, int z)
{
    int code = 0;
    for (int b = 0; b < 5; ++b)
        code |= (((x >> b) & 1) << (3 * b + 2)) | (((y >> b) & 1) << (3 * b + 1))
            | (((z >> b) & 1) << (3 * b));
    return code;
}

// The faces in their new order, renumbered vertices first used in that order.
static void reorderMesh(Mesh& mesh, const std::vector<int>& order)
{
    const size_t nv = mesh.vertices.size();
    std::vector<int> new_index(nv, -1), old_index;
    old_index.reserve(nv);
    std::vector<Vec3i> faces(order.size());
    for (size_t i = 0; i < order.size(); ++i)
        for (int k = 0; k < 3; ++k)
        {
            int& n = new_index[mesh.faces[order[i]][k]];
            if (n < 0)
            {
                n = (int)old_index.size();
                old_index.push_back(mesh.faces[order[i]][k]);
            }
            faces[i][k] = n;
        }
    for (size_t v = 0; v < nv; ++v) // vertices of no face keep their place after the others
        if (new_index[v] < 0)
            old_index.push_back((int)v);
    Mesh out;
    out.faces.swap(faces);
    for (size_t i = 0; i < nv; ++i)
    {
        out.vertices.push_back(mesh.vertices[old_index[i]]);
        if (mesh.normals.size() == nv)
            out.normals.push_back(mesh.normals[old_index[i]]);
        if (mesh.colors.size() == nv)
            out.colors.push_back(mesh.colors[old_index[i]]);
    }
    mesh = out;
}

FaceClusters clusterFaces(Mesh& mesh, int winding)
{
    FaceClusters clusters;
    const size_t nf = mesh.faces.size();
    if (winding == 0 || nf == 0)
        return clusters;
    const int kMaxFaces = 16;
    const Point3f lo = mesh.bboxMin(), hi = mesh.bboxMax();
    const double side = std::max(std::max(hi.x - lo.x, hi.y - lo.y), std::max(hi.z - lo.z, 1e-6f));
    // outward unit normals; faces too thin for a reliable normal go last, never skipped
    std::vector<Vec3d> normal(nf);
    std::vector<std::pair<int64, int> > key(nf);
    for (size_t f = 0; f < nf; ++f)
    {
        const Vec3i& F = mesh.faces[f];
        const Point3f &a = mesh.vertices[F[0]], &b = mesh.vertices[F[1]], &c = mesh.vertices[F[2]];
        const Vec3d e1(b.x - a.x, b.y - a.y, b.z - a.z), e2(c.x - a.x, c.y - a.y, c.z - a.z);
        const Vec3d n = e1.cross(e2) * (double)winding;
        const double len = cv::norm(n), edge = std::max(e1.dot(e1), e2.dot(e2));
        const bool thin = !(len > 1e-6 * edge);
        normal[f] = thin ? Vec3d() : n / len;
        const Point3f m = (a + b + c) * (1.f / 3);
        const int cell = zOrder(std::min(31, (int)((m.x - lo.x) / side * 32)),
                                std::min(31, (int)((m.y - lo.y) / side * 32)),
                                std::min(31, (int)((m.z - lo.z) / side * 32)));
        key[f] = std::make_pair((int64)(thin ? 256 : directionCell(normal[f])) << 16 | cell,
                                (int)f);
    }
    std::sort(key.begin(), key.end());
    std::vector<int> order(nf);
    for (size_t i = 0; i < nf; ++i)
        order[i] = key[i].second;
    for (size_t i = 0; i < nf;)
    {
        size_t e = i + 1;
        while (e < nf && e - i < (size_t)kMaxFaces && key[e].first >> 16 == key[i].first >> 16)
            ++e;
        Vec3d axis, lo3(DBL_MAX, DBL_MAX, DBL_MAX), hi3(-DBL_MAX, -DBL_MAX, -DBL_MAX);
        bool thin = false;
        for (size_t j = i; j < e; ++j)
        {
            axis += normal[order[j]];
            thin = thin || normal[order[j]] == Vec3d();
            for (int k = 0; k < 3; ++k)
            {
                const Point3f& v = mesh.vertices[mesh.faces[order[j]][k]];
                lo3 = Vec3d(std::min(lo3[0], (double)v.x), std::min(lo3[1], (double)v.y),
                            std::min(lo3[2], (double)v.z));
                hi3 = Vec3d(std::max(hi3[0], (double)v.x), std::max(hi3[1], (double)v.y),
                            std::max(hi3[2], (double)v.z));
            }
        }
        FaceClusters::Bound c;
        const double len = cv::norm(axis);
        c.cos_half = thin || !(len > 0) ? -1 : 1;
        if (c.cos_half > 0)
        {
            c.axis = axis / len;
            for (size_t j = i; j < e; ++j)
                c.cos_half = std::min(c.cos_half, normal[order[j]].dot(c.axis));
        }
        c.sin_half = std::sqrt(std::max(0.0, 1 - c.cos_half * c.cos_half));
        c.centre = (lo3 + hi3) * 0.5;
        c.radius = cv::norm(hi3 - lo3) * 0.5;
        clusters.begin.push_back((int)i);
        clusters.bound.push_back(c);
        i = e;
    }
    clusters.begin.push_back((int)nf);
    clusters.box_min = lo;
    clusters.box_max = hi;
    reorderMesh(mesh, order);
    return clusters;
}

bool FaceClusters::facesAway(int k, const Vec3d& centre) const
{
    const Bound& c = bound[k];
    if (!(c.cos_half > 0))
        return false;
    const Vec3d v = c.centre - centre;
    const double dist2 = v.dot(v);
    if (!(dist2 > c.radius * c.radius))
        return false;
    const double dist = std::sqrt(dist2), cos_phi = c.axis.dot(v) / dist;
    const double sin_phi = std::sqrt(std::max(0.0, 1 - cos_phi * cos_phi));
    // cos(phi + half angle) > sin(the ball's angle), with a margin of 1e-3 for faces nearly
    // edge-on, whose projected area's sign the float projection decides
    return cos_phi * c.cos_half - sin_phi * c.sin_half > c.radius / dist + 1e-3;
}

// twice the signed area of a projected face (u, v, z corners)
static inline float signedArea(const Vec3f& a, const Vec3f& b, const Vec3f& c)
{
    return (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]);
}

// barycentric weights of pixel (x, y) in a face (signed areas of the sub-triangles times inv =
// 1 / signedArea)
static inline void barycentric(const Vec3f& a, const Vec3f& b, const Vec3f& c, float inv, int x,
                               int y, float& w0, float& w1, float& w2)
{
    w0 = ((b[0] - x) * (c[1] - y) - (b[1] - y) * (c[0] - x)) * inv;
    w1 = ((c[0] - x) * (a[1] - y) - (c[1] - y) * (a[0] - x)) * inv;
    w2 = 1.f - w0 - w1;
}

// vertex colours interpolated on the visible faces (face_of: the nearest face of each pixel, -1
// for none); grey without colours
static void colourVisibleFaces(const Mesh& mesh, const std::vector<Vec3f>& p, const Mat& face_of,
                               OutputArray _color)
{
    const Size sz = face_of.size();
    const size_t nv = mesh.vertices.size();
    _color.create(sz, CV_8UC3);
    Mat color = _color.getMat();
    color.setTo(Scalar::all(0));
    const bool has_colors = mesh.colors.size() == nv;
    for (int y = 0; y < sz.height; ++y)
    {
        const int* fr = face_of.ptr<int>(y);
        Vec3b* cr = color.ptr<Vec3b>(y);
        for (int x = 0; x < sz.width; ++x)
        {
            if (fr[x] < 0)
                continue;
            if (!has_colors)
            {
                cr[x] = Vec3b(128, 128, 128);
                continue;
            }
            const Vec3i& F = mesh.faces[fr[x]];
            const Vec3f &a = p[F[0]], &b = p[F[1]], &c = p[F[2]];
            float w0, w1, w2;
            barycentric(a, b, c, 1.f / signedArea(a, b, c), x, y, w0, w1, w2);
            const Vec3b &ca = mesh.colors[F[0]], &cb = mesh.colors[F[1]], &cc = mesh.colors[F[2]];
            for (int k = 0; k < 3; ++k)
                cr[x][k] = saturate_cast<uchar>(w0 * ca[k] + w1 * cb[k] + w2 * cc[k]);
        }
    }
}

Mat faceColours(const Mesh& mesh)
{
    const size_t nf = mesh.faces.size();
    Mat colours((int)nf, 1, CV_8UC3, Scalar::all(128));
    if (mesh.colors.size() != mesh.vertices.size())
        return colours;
    for (size_t f = 0; f < nf; ++f)
    {
        const Vec3i& F = mesh.faces[f];
        Vec3b& c = colours.at<Vec3b>((int)f);
        for (int k = 0; k < 3; ++k)
            c[k] = saturate_cast<uchar>((mesh.colors[F[0]][k] + mesh.colors[F[1]][k]
                                         + mesh.colors[F[2]][k]) / 3.0);
    }
    return colours;
}

// The pixels of one face (corners a, b, c in the crop, inv = 1 / signedArea, pixel bounds x0..x1,
// y0..y1 inside the crop) that lie inside it and nearer than the z-buffer take its depth and index.
// A pixel is inside when its three barycentric weights are >= 0. The vector path computes every
// pixel with the scalar path's operations in the same order (no fused multiply-add in either), so
// both draw the same image (Forestmod_Verification.drawing_vector_path_draws_as_the_scalar_one).
static void drawFace(const Vec3f& a, const Vec3f& b, const Vec3f& c, float inv, int f, int x0,
                     int x1, int y0, int y1, Mat& zbuf, Mat& face_of, bool vector_path)
{
#if CV_SIMD128
    const v_float32x4 va0 = v_setall_f32(a[0]), vb0 = v_setall_f32(b[0]),
                      vc0 = v_setall_f32(c[0]), va2 = v_setall_f32(a[2]),
                      vb2 = v_setall_f32(b[2]), vc2 = v_setall_f32(c[2]),
                      vinv = v_setall_f32(inv), one = v_setall_f32(1.f), zero = v_setall_f32(0.f);
    const v_int32x4 lane(0, 1, 2, 3), last = v_setall_s32(x1), vf = v_setall_s32(f);
    const int width = zbuf.cols;
#else
    CV_UNUSED(vector_path);
#endif
    for (int y = y0; y <= y1; ++y)
    {
        float* zr = zbuf.ptr<float>(y);
        int* fr = face_of.ptr<int>(y);
        int x = x0;
#if CV_SIMD128
        if (vector_path)
        {
            const float fy = (float)y;
            const v_float32x4 a1y = v_setall_f32(a[1] - fy), b1y = v_setall_f32(b[1] - fy),
                              c1y = v_setall_f32(c[1] - fy);
            for (; x <= x1 && x + 4 <= width; x += 4)
            {
                const v_int32x4 xi = v_setall_s32(x) + lane;
                const v_float32x4 xs = v_cvt_f32(xi);
                const v_float32x4 w0 = ((vb0 - xs) * c1y - b1y * (vc0 - xs)) * vinv;
                const v_float32x4 w1 = ((vc0 - xs) * a1y - c1y * (va0 - xs)) * vinv;
                const v_float32x4 w2 = one - w0 - w1;
                const v_float32x4 z = w0 * va2 + w1 * vb2 + w2 * vc2;
                const v_float32x4 old = v_load(zr + x);
                const v_float32x4 nearer = (w0 >= zero) & (w1 >= zero) & (w2 >= zero)
                    & (z < old) & v_reinterpret_as_f32(xi <= last);
                v_store(zr + x, v_select(nearer, z, old));
                v_store(fr + x, v_select(v_reinterpret_as_s32(nearer), vf, v_load(fr + x)));
            }
        }
#endif
        for (; x <= x1; ++x)
        {
            float w0, w1, w2;
            barycentric(a, b, c, inv, x, y, w0, w1, w2);
            if (w0 < 0 || w1 < 0 || w2 < 0)
                continue;
            const float z = w0 * a[2] + w1 * b[2] + w2 * c[2];
            if (!(z < zr[x]))
                continue;
            zr[x] = z;
            fr[x] = f;
        }
    }
}

// A face is drawn when it faces the camera (the sign of its signed area against inside_sign, the
// winding's sign; every face when 0) and its box holds a pixel centre of the crop.
static inline bool faceBounds(const Vec3f& a, const Vec3f& b, const Vec3f& c, float inside_sign,
                              Size sz, float& area, int& x0, int& x1, int& y0, int& y1)
{
    area = signedArea(a, b, c);
    if (std::abs(area) < 1e-12f || area * inside_sign > 0)
        return false;
    x0 = std::max(0, cvCeil(std::min(a[0], std::min(b[0], c[0]))));
    x1 = std::min(sz.width - 1, cvFloor(std::max(a[0], std::max(b[0], c[0]))));
    y0 = std::max(0, cvCeil(std::min(a[1], std::min(b[1], c[1]))));
    y1 = std::min(sz.height - 1, cvFloor(std::max(a[1], std::max(b[1], c[1]))));
    return x0 <= x1 && y0 <= y1;
}

#if CV_SIMD128
// faceBounds of faces f .. f + 3 at once (the same operations); returns a bit per drawn face
static inline int faceBounds4(const Vec3i* faces, const float* p, float inside_sign, Size sz,
                              float area[4], int x0[4], int x1[4], int y0[4], int y1[4])
{
    v_int32x4 i0, i1, i2;
    v_load_deinterleave((const int*)faces, i0, i1, i2);
    i0 = i0 + i0 + i0; // offsets of (u, v, z) in p
    i1 = i1 + i1 + i1;
    i2 = i2 + i2 + i2;
    const v_float32x4 au = v_lut(p, i0), av = v_lut(p + 1, i0), bu = v_lut(p, i1),
                      bv = v_lut(p + 1, i1), cu = v_lut(p, i2), cv = v_lut(p + 1, i2);
    const v_float32x4 s = (bu - au) * (cv - av) - (bv - av) * (cu - au);
    const v_int32x4 zero = v_setzero_s32();
    const v_int32x4 vx0 = v_max(zero, v_ceil(v_min(au, v_min(bu, cu))));
    const v_int32x4 vx1 = v_min(v_setall_s32(sz.width - 1), v_floor(v_max(au, v_max(bu, cu))));
    const v_int32x4 vy0 = v_max(zero, v_ceil(v_min(av, v_min(bv, cv))));
    const v_int32x4 vy1 = v_min(v_setall_s32(sz.height - 1), v_floor(v_max(av, v_max(bv, cv))));
    const v_float32x4 skip = (v_abs(s) < v_setall_f32(1e-12f))
        | (s * v_setall_f32(inside_sign) > v_setall_f32(0.f));
    const v_int32x4 drawn = ~v_reinterpret_as_s32(skip) & (vx0 <= vx1) & (vy0 <= vy1);
    v_store(area, s);
    v_store(x0, vx0);
    v_store(x1, vx1);
    v_store(y0, vy0);
    v_store(y1, vy1);
    return v_signmask(drawn);
}
#endif

bool projectedBox(const Point3f& lo, const Point3f& hi, const Matx33d& K, const Matx33d& R,
                  const Vec3d& t, Rect2d& box)
{
    double x0 = 1e30, y0 = 1e30, x1 = -1e30, y1 = -1e30;
    for (int c = 0; c < 8; ++c)
    {
        const Vec3d X = R * Vec3d(c & 1 ? hi.x : lo.x, c & 2 ? hi.y : lo.y, c & 4 ? hi.z : lo.z)
            + t;
        if (!(X[2] > 1.0))
            return false;
        const Vec3d q = K * X;
        x0 = std::min(x0, q[0] / q[2]);
        y0 = std::min(y0, q[1] / q[2]);
        x1 = std::max(x1, q[0] / q[2]);
        y1 = std::max(y1, q[1] / q[2]);
    }
    box = Rect2d(x0, y0, x1 - x0, y1 - y0);
    return true;
}

// The crop around the projection of the mesh's bounding box (lo, hi), widened by margin and
// clipped to the image; false when a corner is behind the camera, the box lies far off the image
// or the crop is empty.
static bool cropOf(const Point3f& lo, const Point3f& hi, const Matx33d& K, const Matx33d& R,
                   const Vec3d& t, Size image, int margin, Rect& rect)
{
    Rect2d box;
    if (!projectedBox(lo, hi, K, R, t, box))
        return false;
    const double x0 = box.x, y0 = box.y, x1 = box.x + box.width, y1 = box.y + box.height;
    if (!(x1 - x0 < 4.0 * image.width && y1 - y0 < 4.0 * image.height && x0 > -1e6
          && y0 > -1e6 && x1 < 1e6 && y1 < 1e6)) // far off the image (and int-safe)
        return false;
    rect = Rect(cvFloor(x0) - margin, cvFloor(y0) - margin, cvCeil(x1 - x0) + 2 * margin + 2,
                cvCeil(y1 - y0) + 2 * margin + 2)
        & Rect(0, 0, image.width, image.height);
    return rect.area() > 0;
}

// Faces begin .. end - 1 into the z-buffer, four at a time on the vector path.
static void drawFaces(const Vec3i* faces, int begin, int end, const std::vector<Vec3f>& p,
                      float inside_sign, Mat& zbuf, Mat& face_of, bool vector_path)
{
    const Size sz = zbuf.size();
    int f = begin;
#if CV_SIMD128
    if (vector_path)
    {
        float area[4];
        int bx0[4], bx1[4], by0[4], by1[4];
        for (; f + 4 <= end; f += 4)
        {
            int drawn = faceBounds4(faces + f, (const float*)p.data(), inside_sign, sz, area,
                                    bx0, bx1, by0, by1);
            for (int k = 0; drawn; ++k, drawn >>= 1)
                if (drawn & 1)
                {
                    const Vec3i& F = faces[f + k];
                    drawFace(p[F[0]], p[F[1]], p[F[2]], 1.f / area[k], f + k, bx0[k], bx1[k],
                             by0[k], by1[k], zbuf, face_of, true);
                }
        }
    }
#endif
    for (; f < end; ++f)
    {
        const Vec3i& F = faces[f];
        float area;
        int bx0, bx1, by0, by1;
        if (faceBounds(p[F[0]], p[F[1]], p[F[2]], inside_sign, sz, area, bx0, bx1, by0, by1))
            drawFace(p[F[0]], p[F[1]], p[F[2]], 1.f / area, f, bx0, bx1, by0, by1, zbuf, face_of,
                     vector_path);
    }
}

// The nearest face of every pixel (z-buffer and face index); p receives the projected vertices
// (u, v in the crop, z), from which the colour of the nearest faces only is interpolated
// afterwards (colourVisibleFaces), so that the faces drawn over do not cost their colours.
// Faces are drawn in index order (the clusters that face away skipped); a pixel keeps the first
// of equally near faces.
static void rasterize(const Mesh& mesh, int winding, const FaceClusters* clusters,
                      const Matx33d& K, const Matx33d& R, const Vec3d& t, Size image, int margin,
                      Drawing& d, std::vector<Vec3f>& p)
{
    d = Drawing();
    d.K = K;
    d.R = R;
    d.t = t;
    d.image = image;
    d.margin = margin;
    const int nf = (int)mesh.faces.size();
    if (clusters && (winding == 0 || clusters->begin.empty() || clusters->begin.back() != nf))
        clusters = 0; // not this mesh's
    Rect rect;
    if (!cropOf(clusters ? clusters->box_min : mesh.bboxMin(),
                clusters ? clusters->box_max : mesh.bboxMax(), K, R, t, image, margin, rect))
        return;
    d.rect = rect;
    const Size sz = rect.size();
    // vertices in the crop: (u, v, z)
    const size_t nv = mesh.vertices.size();
    p.resize(nv);
    const Matx33d KR = K * R;
    const Vec3d Kt = K * t;
    for (size_t i = 0; i < nv; ++i)
    {
        const Point3f& v = mesh.vertices[i];
        const Vec3d q = KR * Vec3d(v.x, v.y, v.z) + Kt;
        const double z = (R(2, 0) * v.x + R(2, 1) * v.y + R(2, 2) * v.z) + t[2];
        p[i] = Vec3f((float)(q[0] / q[2] - rect.x), (float)(q[1] / q[2] - rect.y), (float)z);
    }
    // The signed area of a projected face has the sign of n . a (n its normal, a a corner, in
    // the camera's frame): negative when an outward normal faces the camera.
    const float inside_sign = (float)winding;
    // the z-buffer is the thread's own, reused from drawing to drawing (the face index goes
    // with the drawing); both filled in one pass over their continuous buffers
    static thread_local std::vector<float> zbuf_data;
    zbuf_data.resize((size_t)sz.area());
    Mat zbuf(sz, CV_32F, zbuf_data.data());
    std::fill(zbuf_data.begin(), zbuf_data.end(), FLT_MAX);
    Mat& face_of = d.face;
    face_of.create(sz, CV_32S);
    std::fill_n(face_of.ptr<int>(), (size_t)sz.area(), -1);
    const bool vector_path = useOptimized();
    if (clusters)
    {
        // runs of clusters that do not face away from the camera (centre -R^T t)
        const Vec3d centre = -(R.t() * t);
        const int nc = (int)clusters->bound.size();
        int run = 0;
        for (int k = 0; k <= nc; ++k)
            if (k == nc || clusters->facesAway(k, centre))
            {
                const int end = clusters->begin[k];
                if (end > run)
                    drawFaces(mesh.faces.data(), run, end, p, inside_sign, zbuf, face_of,
                              vector_path);
                run = k < nc ? clusters->begin[k + 1] : nf;
            }
    }
    else
        drawFaces(mesh.faces.data(), 0, nf, p, inside_sign, zbuf, face_of, vector_path);
    // mask and depth (mm, rounded as convertTo does; at least 1 on the object, 0 off it)
    d.mask.create(sz, CV_8U);
    d.depth.create(sz, CV_16U);
    for (int y = 0; y < sz.height; ++y)
    {
        const float* zr = zbuf.ptr<float>(y);
        const int* fr = face_of.ptr<int>(y);
        uchar* mr = d.mask.ptr<uchar>(y);
        ushort* dr = d.depth.ptr<ushort>(y);
        for (int x = 0; x < sz.width; ++x)
        {
            const bool on = fr[x] >= 0;
            mr[x] = on ? 255 : 0;
            dr[x] = on ? std::max<ushort>(saturate_cast<ushort>(zr[x]), 1) : 0;
        }
    }
}

void drawMesh(const Mesh& mesh, int winding, const Matx33d& K, const Matx33d& R, const Vec3d& t,
              Size image, int margin, Drawing& drawing, const FaceClusters* clusters)
{
    std::vector<Vec3f> p;
    rasterize(mesh, winding, clusters, K, R, t, image, margin, drawing, p);
}

void drawMesh(const Mesh& mesh, int winding, const Matx33d& K, const Matx33d& R, const Vec3d& t,
              Size image, int margin, Rect& rect, OutputArray color, Mat& depth, Mat& mask,
              const FaceClusters* clusters)
{
    Drawing d;
    std::vector<Vec3f> p;
    rasterize(mesh, winding, clusters, K, R, t, image, margin, d, p);
    rect = d.rect;
    depth = d.depth;
    mask = d.mask;
    if (!color.needed())
        return;
    if (d.rect.area() == 0)
        color.release();
    else
        colourVisibleFaces(mesh, p, d.face, color);
}

bool Drawing::isOf(uint64 source_, const Matx33d& K_, const Matx33d& R_, const Vec3d& t_,
                   Size image_, int margin_) const
{
    return source != 0 && source == source_ && K == K_ && R == R_ && t == t_ && image == image_
        && margin == margin_;
}

Ptr<Drawing> ObjectDrawer::drawing(const Matx33d& K, const Matx33d& R, const Vec3d& t) const
{
    Ptr<Drawing> d = makePtr<Drawing>();
    draw(K, R, t, d->rect, d->depth, d->mask);
    d->K = K;
    d->R = R;
    d->t = t;
    d->image = imageSize();
    return d;
}

Ptr<Drawing> MeshDrawer::drawing(const Matx33d& K, const Matx33d& R, const Vec3d& t) const
{
    Ptr<Drawing> d = makePtr<Drawing>();
    drawMesh(mesh_, winding_, K, R, t, image_, kDrawMargin, *d, clusters_);
    d->source = source_;
    return d;
}

bool MeshDrawer::silhouette(const Matx33d& K, const Matx33d& R, const Vec3d& t, int max_points,
                            std::vector<SilhouettePoint>& pts) const
{
    if (!silhouette_ || silhouette_->plane.size() != 4 * mesh_.faces.size())
        return false; // none, or not this mesh's
    return meshSilhouette(mesh_, *silhouette_, K, R, t, image_, max_points, pts);
}

void MeshDrawer::draw(const Matx33d& K, const Matx33d& R, const Vec3d& t, Rect& rect, Mat& depth,
                      Mat& mask) const
{
    drawMesh(mesh_, winding_, K, R, t, image_, kDrawMargin, rect, noArray(), depth, mask,
             clusters_);
}

void RendererDrawer::draw(const Matx33d& K, const Matx33d& R, const Vec3d& t, Rect& rect,
                          Mat& depth, Mat& mask) const
{
    renderer_.render(handle_, R, t, K, noArray(), depth, mask);
    rect = Rect(Point(), mask.size());
}

} // namespace detail
} // namespace forestmod
} // namespace cv
