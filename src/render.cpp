// This file is part of OpenCV project.
// It is subject to the license terms in the LICENSE file found in the top-level directory
// of this distribution and at http://opencv.org/license.html

// ViewSampler (upper-hemisphere viewpoints from a subdivided icosahedron, radii, in-plane
// rotations; LINEMOD ACCV 2012's training views) and renderTemplates.

#include "precomp.hpp"
#include "params_io.hpp"

#include <climits>
#include <map>

namespace cv {
namespace forestmod {

ViewPose::ViewPose()
    : R(Matx33d::eye()), t(0, 0, 0), view_index(-1), radius_index(-1), inplane_index(-1),
      radius(0), elevation(0), azimuth(0), inplane(0)
{
}

TemplateView::TemplateView()
    : R(Matx33d::eye()), t(0, 0, 0), K(Matx33d::eye()), view_id(-1), view_index(-1),
      radius_index(-1), inplane_index(-1), radius(0), elevation(0), azimuth(0), inplane(0)
{
}

// ---- ViewSampler::Params --------------------------------------------------------------------------

ViewSampler::Params::Params()
    : level(2), min_elevation(0.0), max_elevation(90.0), inplane_min(-45.0), inplane_max(45.0),
      inplane_step(15.0)
{
    for (int r = 650; r <= 1150; r += 100)
        radii.push_back(r);
}

ViewSampler::Params ViewSampler::Params::coarse()
{
    Params p;
    p.level = 0;
    p.radii.assign(1, 800.0);
    p.inplane_min = p.inplane_max = 0.0;
    return p;
}

void ViewSampler::Params::read(const FileNode& fn)
{
    detail::readField(fn, "level", level);
    detail::readField(fn, "min_elevation", min_elevation);
    detail::readField(fn, "max_elevation", max_elevation);
    if (!fn["radii"].empty())
    {
        radii.clear();
        fn["radii"] >> radii;
    }
    detail::readField(fn, "inplane_min", inplane_min);
    detail::readField(fn, "inplane_max", inplane_max);
    detail::readField(fn, "inplane_step", inplane_step);
}

void ViewSampler::Params::write(FileStorage& fs) const
{
    fs << "level" << level;
    fs << "min_elevation" << min_elevation;
    fs << "max_elevation" << max_elevation;
    fs << "radii" << radii;
    fs << "inplane_min" << inplane_min;
    fs << "inplane_max" << inplane_max;
    fs << "inplane_step" << inplane_step;
}

// ---- ViewSampler ----------------------------------------------------------------------------------

ViewSampler::ViewSampler()
{
}

ViewSampler::ViewSampler(const Params& p) : params(p)
{
    validate();
}

void ViewSampler::validate() const
{
    CV_CheckGE(params.level, 0, "ViewSampler: level must be >= 0");
    CV_CheckLE(params.level, 6, "ViewSampler: level must be <= 6 (40962 directions)");
    CV_Check(params.min_elevation,
             params.min_elevation >= -90 && params.min_elevation <= params.max_elevation
                 && params.max_elevation <= 90,
             "ViewSampler: need -90 <= min_elevation <= max_elevation <= 90 (degrees)");
    CV_Check(params.radii.size(), !params.radii.empty(), "ViewSampler: radii must not be empty");
    for (size_t i = 0; i < params.radii.size(); ++i)
        CV_Check(params.radii[i], params.radii[i] > 0 && std::isfinite(params.radii[i]),
                 "ViewSampler: every radius must be positive (mm)");
    CV_Check(params.inplane_max, params.inplane_min <= params.inplane_max,
             "ViewSampler: inplane_min must not exceed inplane_max");
    CV_Check(params.inplane_step,
             params.inplane_step > 0 || params.inplane_min == params.inplane_max,
             "ViewSampler: inplane_step must be positive (unless inplane_min == inplane_max)");
    if (params.inplane_step > 0)
        CV_Check(params.inplane_step,
                 (params.inplane_max - params.inplane_min) / params.inplane_step <= 3600,
                 "ViewSampler: too many in-plane angles (more than 3600)");
}

std::vector<Vec3d> ViewSampler::icosphere(int level)
{
    CV_CheckGE(level, 0, "ViewSampler::icosphere: level must be >= 0");
    CV_CheckLE(level, 8, "ViewSampler::icosphere: level must be <= 8");
    // icosahedron with vertices at the poles: two rings of five at elevation +-atan(1/2), the
    // lower ring turned by 36 degrees
    std::vector<Vec3d> v;
    v.push_back(Vec3d(0, 0, 1));
    const double el = std::atan(0.5), ce = std::cos(el), se = std::sin(el);
    for (int k = 0; k < 5; ++k)
    {
        const double a = 2.0 * CV_PI * k / 5.0;
        v.push_back(Vec3d(ce * std::cos(a), ce * std::sin(a), se));
    }
    for (int k = 0; k < 5; ++k)
    {
        const double a = 2.0 * CV_PI * k / 5.0 + CV_PI / 5.0;
        v.push_back(Vec3d(ce * std::cos(a), ce * std::sin(a), -se));
    }
    v.push_back(Vec3d(0, 0, -1));
    std::vector<Vec3i> faces;
    for (int k = 0; k < 5; ++k)
    {
        const int u0 = 1 + k, u1 = 1 + (k + 1) % 5, l0 = 6 + k, l1 = 6 + (k + 1) % 5;
        faces.push_back(Vec3i(0, u0, u1));
        faces.push_back(Vec3i(u0, l0, u1));
        faces.push_back(Vec3i(u1, l0, l1));
        faces.push_back(Vec3i(11, l1, l0));
    }
    for (int s = 0; s < level; ++s)
    {
        std::map<std::pair<int, int>, int> mid;
        std::vector<Vec3i> next;
        next.reserve(faces.size() * 4);
        for (size_t f = 0; f < faces.size(); ++f)
        {
            int m[3];
            for (int e = 0; e < 3; ++e)
            {
                const int a = faces[f][e], b = faces[f][(e + 1) % 3];
                const std::pair<int, int> key(std::min(a, b), std::max(a, b));
                std::map<std::pair<int, int>, int>::const_iterator it = mid.find(key);
                if (it != mid.end())
                    m[e] = it->second;
                else
                {
                    Vec3d p = v[key.first] + v[key.second];
                    p *= 1.0 / norm(p);
                    v.push_back(p);
                    m[e] = (int)v.size() - 1;
                    mid[key] = m[e];
                }
            }
            // m[0] = mid(a, b), m[1] = mid(b, c), m[2] = mid(c, a)
            next.push_back(Vec3i(faces[f][0], m[0], m[2]));
            next.push_back(Vec3i(faces[f][1], m[1], m[0]));
            next.push_back(Vec3i(faces[f][2], m[2], m[1]));
            next.push_back(Vec3i(m[0], m[1], m[2]));
        }
        faces.swap(next);
    }
    return v;
}

std::vector<Vec3d> ViewSampler::viewpoints() const
{
    validate();
    const std::vector<Vec3d> all = icosphere(params.level);
    std::vector<Vec3d> out;
    const double eps = 1e-9;
    for (size_t i = 0; i < all.size(); ++i)
    {
        const double el = std::asin(std::max(-1.0, std::min(1.0, all[i][2]))) * 180.0 / CV_PI;
        if (el >= params.min_elevation - eps && el <= params.max_elevation + eps)
            out.push_back(all[i]);
    }
    return out;
}

std::vector<double> ViewSampler::inplaneAngles() const
{
    validate();
    std::vector<double> a;
    if (params.inplane_step <= 0)
    {
        a.push_back(params.inplane_min);
        return a;
    }
    const int n = (int)std::floor((params.inplane_max - params.inplane_min) / params.inplane_step
                                  + 1e-9);
    for (int i = 0; i <= n; ++i)
        a.push_back(params.inplane_min + i * params.inplane_step);
    return a;
}

// radii x viewpoints x in-plane angles, raising beyond an int
static int countPoses(size_t radii, size_t viewpoints, size_t angles)
{
    const double n = (double)radii * (double)viewpoints * (double)angles;
    if (n > INT_MAX)
        CV_Error_(Error::StsOutOfRange, ("ViewSampler: %.0f poses (radii x viewpoints x in-plane "
                                         "angles), more than an int counts", n));
    return (int)n;
}

int ViewSampler::size() const
{
    return countPoses(params.radii.size(), viewpoints().size(), inplaneAngles().size());
}

void ViewSampler::lookAt(const Point3d& center, const Vec3d& direction, double radius,
                         double inplane_deg, Matx33d& R, Vec3d& t)
{
    const double len = norm(direction);
    CV_Check(len, len > 0 && std::isfinite(len), "ViewSampler::lookAt: direction must be non-zero");
    CV_Check(radius, radius > 0 && std::isfinite(radius),
             "ViewSampler::lookAt: radius must be positive and finite");
    CV_Check(inplane_deg, std::isfinite(inplane_deg),
             "ViewSampler::lookAt: inplane_deg must be finite");
    if (!(std::isfinite(center.x) && std::isfinite(center.y) && std::isfinite(center.z)))
        CV_Error(Error::StsBadArg, "ViewSampler::lookAt: center must be finite");
    const Vec3d d = direction * (1.0 / len);
    const double el = std::asin(std::max(-1.0, std::min(1.0, d[2])));
    // azimuth: at the poles take 0 (x axis), a fixed and documented choice
    const double horiz = std::sqrt(d[0] * d[0] + d[1] * d[1]);
    const double az = horiz > 1e-12 ? std::atan2(d[1], d[0]) : 0.0;
    // tangent "up" on the sphere: direction of increasing elevation at this azimuth
    const Vec3d up(-std::sin(el) * std::cos(az), -std::sin(el) * std::sin(az), std::cos(el));
    const Vec3d z = -d;            // optical axis: camera -> centre
    const Vec3d y = -up;           // image y points down
    const Vec3d x = y.cross(z);    // right-handed: x = y x z
    const Matx33d R0(x[0], x[1], x[2], y[0], y[1], y[2], z[0], z[1], z[2]);
    const double a = inplane_deg * CV_PI / 180.0, ca = std::cos(a), sa = std::sin(a);
    const Matx33d Rz(ca, -sa, 0, sa, ca, 0, 0, 0, 1);
    R = Rz * R0;
    t = -(R * Vec3d(center.x, center.y, center.z)) + Vec3d(0, 0, radius);
}

std::vector<ViewPose> ViewSampler::poses(const Point3d& center) const
{
    const std::vector<Vec3d> dirs = viewpoints();
    const std::vector<double> angles = inplaneAngles();
    std::vector<ViewPose> out;
    out.reserve(countPoses(params.radii.size(), dirs.size(), angles.size()));
    for (size_t r = 0; r < params.radii.size(); ++r)
        for (size_t v = 0; v < dirs.size(); ++v)
            for (size_t a = 0; a < angles.size(); ++a)
            {
                ViewPose p;
                lookAt(center, dirs[v], params.radii[r], angles[a], p.R, p.t);
                p.view_index = (int)v;
                p.radius_index = (int)r;
                p.inplane_index = (int)a;
                p.radius = params.radii[r];
                p.elevation = std::asin(std::max(-1.0, std::min(1.0, dirs[v][2]))) * 180.0 / CV_PI;
                const double horiz = std::sqrt(dirs[v][0] * dirs[v][0] + dirs[v][1] * dirs[v][1]);
                p.azimuth = horiz > 1e-12 ? std::atan2(dirs[v][1], dirs[v][0]) * 180.0 / CV_PI
                                          : 0.0;
                p.inplane = angles[a];
                out.push_back(p);
            }
    return out;
}

// ---- renderTemplates ------------------------------------------------------------------------------

typedef std::function<bool(const TemplateView&, int, int)> TemplateSink;

void renderTemplates(Renderer& renderer, int handle, const Point3d& center,
                     const ViewSampler& sampler, const Matx33d& K, const TemplateSink& sink)
{
    const std::vector<ViewPose> poses = sampler.poses(center);
    const int total = (int)poses.size();
    for (int i = 0; i < total; ++i)
    {
        const ViewPose& p = poses[i];
        TemplateView v;
        renderer.render(handle, p.R, p.t, K, v.color, v.depth, v.mask);
        v.R = p.R;
        v.t = p.t;
        v.K = K;
        v.view_id = i;
        v.view_index = p.view_index;
        v.radius_index = p.radius_index;
        v.inplane_index = p.inplane_index;
        v.radius = p.radius;
        v.elevation = p.elevation;
        v.azimuth = p.azimuth;
        v.inplane = p.inplane;
        v.bbox = boundingRect(v.mask);
        if (sink && !sink(v, i + 1, total))
            break;
    }
}

void renderTemplates(const Mesh& mesh, const ViewSampler& sampler, const Matx33d& K, Size size,
                     const TemplateSink& sink)
{
    mesh.validate();
    sampler.validate();
    Ptr<Renderer> renderer = Renderer::create(size);
    const int handle = renderer->addMesh(mesh);
    const Point3f c = mesh.center();
    renderTemplates(*renderer, handle, Point3d(c.x, c.y, c.z), sampler, K, sink);
}

namespace {
struct CollectTemplates
{
    std::vector<TemplateView>* out;
    const std::function<bool(int, int)>* progress;
    bool operator()(const TemplateView& v, int done, int total) const
    {
        out->push_back(v);
        return !*progress || (*progress)(done, total);
    }
};
} // namespace

void renderTemplates(const Mesh& mesh, const ViewSampler& sampler, const Matx33d& K, Size size,
                     std::vector<TemplateView>& out, const std::function<bool(int, int)>& progress)
{
    out.clear();
    out.reserve(sampler.size());
    CollectTemplates collect;
    collect.out = &out;
    collect.progress = &progress;
    renderTemplates(mesh, sampler, K, size, TemplateSink(collect));
}

} // namespace forestmod
} // namespace cv
