// This file is part of OpenCV project.
// It is subject to the license terms in the LICENSE file found in the top-level directory
// of this distribution and at http://opencv.org/license.html

// Drawing a mesh without OpenGL: vertex clustering, the closed-mesh test and a small z-buffered
// rasterizer into the crop around the object's projection. The verification and the edge
// refinement draw their hypotheses with it, in parallel (the OSMesa Renderer needs a lock).

#include "precomp.hpp"
#include "draw_mesh.hpp"

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

// The nearest face of every pixel (z-buffer and face index); p receives the projected vertices
// (u, v in the crop, z), from which the colour of the nearest faces only is interpolated
// afterwards (colourVisibleFaces), so that the faces drawn over do not cost their colours.
static void rasterize(const Mesh& mesh, int winding, const Matx33d& K, const Matx33d& R,
                      const Vec3d& t, Size image, int margin, Drawing& d, std::vector<Vec3f>& p)
{
    d = Drawing();
    d.K = K;
    d.R = R;
    d.t = t;
    d.image = image;
    d.margin = margin;
    const Point3f lo = mesh.bboxMin(), hi = mesh.bboxMax();
    double x0 = 1e30, y0 = 1e30, x1 = -1e30, y1 = -1e30;
    for (int c = 0; c < 8; ++c)
    {
        const Vec3d X = R * Vec3d(c & 1 ? hi.x : lo.x, c & 2 ? hi.y : lo.y, c & 4 ? hi.z : lo.z)
            + t;
        if (!(X[2] > 1.0))
            return;
        const Vec3d q = K * X;
        x0 = std::min(x0, q[0] / q[2]);
        y0 = std::min(y0, q[1] / q[2]);
        x1 = std::max(x1, q[0] / q[2]);
        y1 = std::max(y1, q[1] / q[2]);
    }
    if (!(x1 - x0 < 4.0 * image.width && y1 - y0 < 4.0 * image.height && x0 > -1e6
          && y0 > -1e6 && x1 < 1e6 && y1 < 1e6)) // far off the image (and int-safe)
        return;
    const Rect rect = Rect(cvFloor(x0) - margin, cvFloor(y0) - margin,
                           cvCeil(x1 - x0) + 2 * margin + 2, cvCeil(y1 - y0) + 2 * margin + 2)
        & Rect(0, 0, image.width, image.height);
    if (rect.area() == 0)
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
    Mat zbuf(sz, CV_32F, Scalar(FLT_MAX));
    Mat& face_of = d.face;
    face_of.create(sz, CV_32S);
    face_of.setTo(Scalar(-1));
    for (size_t f = 0; f < mesh.faces.size(); ++f)
    {
        const Vec3i& F = mesh.faces[f];
        const Vec3f &a = p[F[0]], &b = p[F[1]], &c = p[F[2]];
        const float area = signedArea(a, b, c);
        if (std::abs(area) < 1e-12f || area * inside_sign > 0)
            continue;
        const int ux0 = std::max(0, cvCeil(std::min(a[0], std::min(b[0], c[0]))));
        const int ux1 = std::min(sz.width - 1,
                                 cvFloor(std::max(a[0], std::max(b[0], c[0]))));
        const int vy0 = std::max(0, cvCeil(std::min(a[1], std::min(b[1], c[1]))));
        const int vy1 = std::min(sz.height - 1,
                                 cvFloor(std::max(a[1], std::max(b[1], c[1]))));
        if (ux0 > ux1 || vy0 > vy1)
            continue;
        const float inv = 1.f / area;
        for (int y = vy0; y <= vy1; ++y)
        {
            float* zr = zbuf.ptr<float>(y);
            int* fr = face_of.ptr<int>(y);
            for (int x = ux0; x <= ux1; ++x)
            {
                float w0, w1, w2;
                barycentric(a, b, c, inv, x, y, w0, w1, w2);
                if (w0 < 0 || w1 < 0 || w2 < 0)
                    continue;
                const float z = w0 * a[2] + w1 * b[2] + w2 * c[2];
                if (!(z < zr[x]))
                    continue;
                zr[x] = z;
                fr[x] = (int)f;
            }
        }
    }
    d.mask = face_of >= 0;
    zbuf.setTo(0, ~d.mask);
    zbuf.convertTo(d.depth, CV_16U);
    d.depth.setTo(1, d.mask & (d.depth == 0));
}

void drawMesh(const Mesh& mesh, int winding, const Matx33d& K, const Matx33d& R, const Vec3d& t,
              Size image, int margin, Drawing& drawing)
{
    std::vector<Vec3f> p;
    rasterize(mesh, winding, K, R, t, image, margin, drawing, p);
}

void drawMesh(const Mesh& mesh, int winding, const Matx33d& K, const Matx33d& R, const Vec3d& t,
              Size image, int margin, Rect& rect, OutputArray color, Mat& depth, Mat& mask)
{
    Drawing d;
    std::vector<Vec3f> p;
    rasterize(mesh, winding, K, R, t, image, margin, d, p);
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
    drawMesh(mesh_, winding_, K, R, t, image_, kDrawMargin, *d);
    d->source = source_;
    return d;
}

void MeshDrawer::draw(const Matx33d& K, const Matx33d& R, const Vec3d& t, Rect& rect, Mat& depth,
                      Mat& mask) const
{
    drawMesh(mesh_, winding_, K, R, t, image_, kDrawMargin, rect, noArray(), depth, mask);
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
