// This file is part of OpenCV project.
// It is subject to the license terms in the LICENSE file found in the top-level directory
// of this distribution and at http://opencv.org/license.html

// Mesh: geometry helpers (bounding box, centre, diameter, normals) and the assimp loader.

#include "precomp.hpp"
#include "ply_check.hpp"

#ifdef HAVE_ASSIMP
#include <assimp/Importer.hpp>
#include <assimp/postprocess.h>
#include <assimp/scene.h>
#endif

#include <cstdlib>
#include <fstream>

namespace cv {
namespace forestmod {

static const double MAX_COORDINATE = Mesh::MAX_COORDINATE_MM;

bool Mesh::empty() const
{
    return vertices.empty() || faces.empty();
}

// The corner of the bounding box chosen by `pick` (std::min or std::max) per coordinate.
static Point3f bboxCorner(const std::vector<Point3f>& vertices, const char* who,
                          const float& (*pick)(const float&, const float&))
{
    if (vertices.empty())
        CV_Error_(Error::StsBadArg, ("%s: the mesh has no vertices", who));
    Point3f m = vertices[0];
    for (size_t i = 0; i < vertices.size(); ++i)
    {
        const Point3f& v = vertices[i];
        // a NaN would drop out of min / max unseen (the box, centre and diameter of the rest)
        if (!(std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z)))
            CV_Error_(Error::StsBadArg, ("%s: vertex %d is not finite", who, (int)i));
        m = Point3f(pick(m.x, v.x), pick(m.y, v.y), pick(m.z, v.z));
    }
    return m;
}

Point3f Mesh::bboxMin() const
{
    return bboxCorner(vertices, "Mesh::bboxMin", &std::min<float>);
}

Point3f Mesh::bboxMax() const
{
    return bboxCorner(vertices, "Mesh::bboxMax", &std::max<float>);
}

Point3f Mesh::center() const
{
    const Point3f a = bboxMin(), b = bboxMax();
    return Point3f(0.5f * (a.x + b.x), 0.5f * (a.y + b.y), 0.5f * (a.z + b.z));
}

double Mesh::diameter() const
{
    CV_Check(vertices.size(), !vertices.empty(), "Mesh::diameter: the mesh has no vertices");
    // Exact maximum pairwise distance with pruning: with r_i = |v_i - c| for any point c,
    // |v_i - v_j| <= r_i + r_j. Visit vertices by decreasing r; a pair whose bound cannot beat
    // the best distance so far ends the inner loop, and an i whose bound with the farthest
    // vertex cannot beat it ends the search.
    const Point3f c = center();
    const size_t n = vertices.size();
    std::vector<std::pair<double, int> > order(n);
    for (size_t i = 0; i < n; ++i)
    {
        const Point3d d(vertices[i].x - c.x, vertices[i].y - c.y, vertices[i].z - c.z);
        order[i] = std::make_pair(std::sqrt(d.dot(d)), (int)i);
    }
    std::sort(order.begin(), order.end(),
              [](const std::pair<double, int>& a, const std::pair<double, int>& b) {
                  return a.first > b.first || (a.first == b.first && a.second < b.second);
              });
    double best2 = 0.0, best = 0.0;
    for (size_t a = 0; a < n; ++a)
    {
        if (order[a].first + order[0].first <= best)
            break;
        const Point3d p(vertices[order[a].second]);
        for (size_t b = 0; b < a; ++b)
        {
            if (order[a].first + order[b].first <= best)
                break;
            const Point3d q(vertices[order[b].second]);
            const Point3d d = p - q;
            const double d2 = d.dot(d);
            if (d2 > best2)
            {
                best2 = d2;
                best = std::sqrt(d2);
            }
        }
    }
    return best;
}

void Mesh::computeNormals()
{
    std::vector<Vec3d> acc(vertices.size(), Vec3d(0, 0, 0));
    const int nv = (int)vertices.size();
    for (size_t f = 0; f < faces.size(); ++f)
    {
        const Vec3i& tri = faces[f];
        if (tri[0] < 0 || tri[1] < 0 || tri[2] < 0 || tri[0] >= nv || tri[1] >= nv || tri[2] >= nv)
            CV_Error_(Error::StsOutOfRange,
                      ("Mesh::computeNormals: face %d refers to a vertex outside [0, %d)", (int)f,
                       nv));
        const Point3d a(vertices[tri[0]]), b(vertices[tri[1]]), c(vertices[tri[2]]);
        const Point3d n = (b - a).cross(c - a); // length = 2 x area: area weighting
        for (int k = 0; k < 3; ++k)
            acc[tri[k]] += Vec3d(n.x, n.y, n.z);
    }
    normals.resize(vertices.size());
    for (size_t i = 0; i < acc.size(); ++i)
    {
        const double len = norm(acc[i]);
        normals[i] = len > 0 ? Vec3f(acc[i] * (1.0 / len)) : Vec3f(0.f, 0.f, 1.f);
    }
}

void Mesh::validate() const
{
    if (vertices.empty())
        CV_Error(Error::StsBadArg, "Mesh: no vertices");
    if (faces.empty())
        CV_Error(Error::StsBadArg, "Mesh: no faces (triangles)");
    if (!normals.empty() && normals.size() != vertices.size())
        CV_Error_(Error::StsBadSize, ("Mesh: %d normals for %d vertices", (int)normals.size(),
                                      (int)vertices.size()));
    if (!colors.empty() && colors.size() != vertices.size())
        CV_Error_(Error::StsBadSize, ("Mesh: %d colours for %d vertices", (int)colors.size(),
                                      (int)vertices.size()));
    const int nv = (int)vertices.size();
    for (size_t f = 0; f < faces.size(); ++f)
        for (int k = 0; k < 3; ++k)
            if (faces[f][k] < 0 || faces[f][k] >= nv)
                CV_Error_(Error::StsOutOfRange,
                          ("Mesh: face %d refers to vertex %d, outside [0, %d)", (int)f,
                           faces[f][k], nv));
    for (size_t i = 0; i < vertices.size(); ++i)
    {
        const Point3f& v = vertices[i];
        if (!std::isfinite(v.x) || !std::isfinite(v.y) || !std::isfinite(v.z))
            CV_Error_(Error::StsBadArg, ("Mesh: vertex %d is not finite", (int)i));
        if (std::abs(v.x) > MAX_COORDINATE || std::abs(v.y) > MAX_COORDINATE
            || std::abs(v.z) > MAX_COORDINATE)
            CV_Error_(Error::StsBadArg, ("Mesh: vertex %d at (%g, %g, %g) lies beyond +-%g mm "
                                         "(a wrong scale?)", (int)i, v.x, v.y, v.z,
                                         MAX_COORDINATE));
    }
    // degenerate: nothing to render (an empty mask in every view)
    double area2 = 0;
    for (size_t f = 0; f < faces.size() && area2 == 0; ++f)
    {
        const Point3d a(vertices[faces[f][0]]), b(vertices[faces[f][1]]), c(vertices[faces[f][2]]);
        area2 = norm((b - a).cross(c - a));
    }
    if (!(area2 > 0))
    {
        const Point3f lo = bboxMin(), hi = bboxMax();
        if (lo == hi)
            CV_Error_(Error::StsBadArg, ("Mesh: all %d vertices coincide at (%g, %g, %g): zero "
                                         "extent", (int)vertices.size(), lo.x, lo.y, lo.z));
        CV_Error_(Error::StsBadArg, ("Mesh: all %d triangles have zero area (degenerate mesh)",
                                     (int)faces.size()));
    }
}

#ifdef HAVE_ASSIMP

static uchar toByte(float c)
{
    return saturate_cast<uchar>(cvRound(255.0 * std::min(1.f, std::max(0.f, c))));
}

// Faces straight from the reader: every face has indices, all inside the mesh's vertices.
static void checkRawScene(const aiScene* scene, const String& path)
{
    for (unsigned m = 0; m < scene->mNumMeshes; ++m)
    {
        const aiMesh* am = scene->mMeshes[m];
        if (!am || (am->mNumFaces > 0 && (!am->mFaces || !am->mVertices)))
            CV_Error_(Error::StsParseError,
                      ("Mesh::load: '%s' is corrupt: mesh %u has faces but no vertex data",
                       path.c_str(), m));
        for (unsigned f = 0; f < am->mNumFaces; ++f)
        {
            const aiFace& face = am->mFaces[f];
            if (face.mNumIndices == 0 || !face.mIndices)
                CV_Error_(Error::StsParseError,
                          ("Mesh::load: '%s' is corrupt or truncated: face %u of mesh %u has no "
                           "vertex indices",
                           path.c_str(), f, m));
            for (unsigned k = 0; k < face.mNumIndices; ++k)
                if (face.mIndices[k] >= am->mNumVertices)
                    CV_Error_(Error::StsParseError,
                              ("Mesh::load: '%s' is corrupt: face %u of mesh %u refers to vertex "
                               "%u of %u",
                               path.c_str(), f, m, face.mIndices[k], am->mNumVertices));
        }
    }
}

// The file exists, can be read and is not empty.
static void checkMeshFile(const String& path)
{
    std::ifstream probe(path.c_str(), std::ios::binary);
    if (!probe.good())
        CV_Error_(Error::StsObjectNotFound,
                  ("Mesh::load: cannot open '%s' (missing or unreadable)", path.c_str()));
    probe.seekg(0, std::ios::end);
    if (probe.tellg() <= 0)
        CV_Error_(Error::StsParseError, ("Mesh::load: '%s' is empty", path.c_str()));
}

// The scene read by assimp, triangulated, its hierarchy flattened. Two steps: read without
// post-processing, check the raw faces, then post-process. Debian's libassimp is built with its
// internal assertions on, and some readers (PLY) turn a truncated file into faces without
// indices, on which aiProcess_Triangulate aborts the process instead of reporting an error.
static const aiScene* readScene(Assimp::Importer& importer, const String& path)
{
    // drop points and lines: we render triangles only
    importer.SetPropertyInteger(AI_CONFIG_PP_SBP_REMOVE, aiPrimitiveType_POINT | aiPrimitiveType_LINE);
    const unsigned flags = aiProcess_Triangulate | aiProcess_JoinIdenticalVertices
                           | aiProcess_PreTransformVertices | aiProcess_SortByPType;
    const aiScene* scene = importer.ReadFile(path.c_str(), 0);
    if (!scene)
        CV_Error_(Error::StsParseError, ("Mesh::load: assimp cannot read '%s': %s", path.c_str(),
                                         importer.GetErrorString()));
    if (scene->mFlags & AI_SCENE_FLAGS_INCOMPLETE)
        CV_Error_(Error::StsParseError,
                  ("Mesh::load: assimp read '%s' only partly (incomplete scene): %s", path.c_str(),
                   importer.GetErrorString()));
    checkRawScene(scene, path);
    scene = importer.ApplyPostProcessing(flags);
    if (!scene)
        CV_Error_(Error::StsParseError, ("Mesh::load: assimp cannot process '%s': %s",
                                         path.c_str(), importer.GetErrorString()));
    return scene;
}

// What appending the triangles of a scene saw that a sane mesh does not have.
struct FaceCounts
{
    size_t triangles = 0, collapsed = 0, repeated = 0;
};

// One assimp mesh's vertices (scaled, with unit normals when every mesh has them and BGR colours
// when any has them) and triangles, appended to `mesh`.
static void appendMesh(const aiMesh* am, double scale, bool all_normals, bool any_colors,
                       Mesh& mesh, FaceCounts& counts)
{
    const int base = (int)mesh.vertices.size();
    for (unsigned i = 0; i < am->mNumVertices; ++i)
    {
        const aiVector3D& v = am->mVertices[i];
        mesh.vertices.push_back(Point3f((float)(v.x * scale), (float)(v.y * scale),
                                        (float)(v.z * scale)));
        if (all_normals)
        {
            const aiVector3D& n = am->mNormals[i];
            Vec3f nn(n.x, n.y, n.z);
            const double len = norm(nn);
            mesh.normals.push_back(len > 0 && std::isfinite(len) ? Vec3f(nn * (1.0 / len))
                                                              : Vec3f(0.f, 0.f, 0.f));
        }
        if (any_colors)
        {
            if (am->HasVertexColors(0))
            {
                const aiColor4D& c = am->mColors[0][i];
                mesh.colors.push_back(Vec3b(toByte(c.b), toByte(c.g), toByte(c.r)));
            }
            else
                mesh.colors.push_back(Vec3b(128, 128, 128));
        }
    }
    for (unsigned f = 0; f < am->mNumFaces; ++f)
    {
        const aiFace& face = am->mFaces[f];
        if (face.mNumIndices != 3)
            continue;
        ++counts.triangles;
        const Vec3i tri(base + (int)face.mIndices[0], base + (int)face.mIndices[1],
                        base + (int)face.mIndices[2]);
        if (tri[0] == tri[1] && tri[1] == tri[2])
        {
            ++counts.collapsed; // a "triangle" on one vertex: dropped (or the sign of a bad file)
            continue;
        }
        if (!mesh.faces.empty() && mesh.faces.back() == tri)
            ++counts.repeated;
        mesh.faces.push_back(tri);
    }
}

// assimp's readers are lenient with truncated files (seen with PLY 5.2): missing vertices become
// zeros, so that many faces collapse onto one vertex after joining identical vertices, and
// missing faces repeat the last face read. Neither happens in a sane mesh.
static void checkNotTruncated(const Mesh& mesh, const FaceCounts& counts, const String& path)
{
    size_t trailing = 0; // faces at the end equal to their predecessor
    for (size_t f = mesh.faces.size(); f >= 2 && mesh.faces[f - 1] == mesh.faces[f - 2]; --f)
        ++trailing;
    if (trailing > 0 || (counts.repeated > 0 && counts.repeated * 100 > counts.triangles))
        CV_Error_(Error::StsParseError,
                  ("Mesh::load: '%s' looks corrupt or truncated: %d of %d triangles repeat the "
                   "previous one (%d at the end)",
                   path.c_str(), (int)counts.repeated, (int)counts.triangles, (int)trailing));
    if (counts.collapsed > 0 && counts.collapsed * 100 > counts.triangles)
        CV_Error_(Error::StsParseError,
                  ("Mesh::load: '%s' looks corrupt or truncated: %d of %d triangles collapse onto a "
                   "single vertex",
                   path.c_str(), (int)counts.collapsed, (int)counts.triangles));
}

// Colours and normals for every vertex: grey without colours; normals from the faces where the
// file has none or a zero normal.
static void completeAttributes(Mesh& mesh)
{
    if (mesh.colors.empty())
        mesh.colors.assign(mesh.vertices.size(), Vec3b(128, 128, 128));
    if (mesh.normals.empty())
    {
        mesh.computeNormals();
        return;
    }
    bool any_zero = false;
    for (size_t i = 0; i < mesh.normals.size() && !any_zero; ++i)
        any_zero = mesh.normals[i] == Vec3f(0.f, 0.f, 0.f);
    if (!any_zero)
        return;
    std::vector<Vec3f> from_file = mesh.normals;
    mesh.computeNormals();
    for (size_t i = 0; i < from_file.size(); ++i)
        if (from_file[i] != Vec3f(0.f, 0.f, 0.f))
            mesh.normals[i] = from_file[i];
}

Mesh Mesh::load(const String& path, double scale)
{
    if (!(scale > 0) || !std::isfinite(scale))
        CV_Error_(Error::StsBadArg, ("Mesh::load(%s): scale must be positive, got %g", path.c_str(),
                                     scale));
    checkMeshFile(path);
    detail::checkPly(path);
    Assimp::Importer importer;
    const aiScene* scene = readScene(importer, path);

    bool all_normals = true, any_colors = false;
    for (unsigned m = 0; m < scene->mNumMeshes; ++m)
    {
        const aiMesh* am = scene->mMeshes[m];
        if (!(am->mPrimitiveTypes & aiPrimitiveType_TRIANGLE))
            continue;
        all_normals = all_normals && am->HasNormals();
        any_colors = any_colors || am->HasVertexColors(0);
    }
    Mesh mesh;
    FaceCounts counts;
    for (unsigned m = 0; m < scene->mNumMeshes; ++m)
        if (scene->mMeshes[m]->mPrimitiveTypes & aiPrimitiveType_TRIANGLE)
            appendMesh(scene->mMeshes[m], scale, all_normals, any_colors, mesh, counts);
    checkNotTruncated(mesh, counts, path);
    if (mesh.faces.empty())
        CV_Error_(Error::StsParseError,
                  ("Mesh::load: '%s' has no triangles (%u meshes read by assimp)", path.c_str(),
                   scene->mNumMeshes));
    completeAttributes(mesh);
    try
    {
        mesh.validate();
    }
    catch (const cv::Exception& e)
    {
        CV_Error_(Error::StsParseError, ("Mesh::load(%s): %s", path.c_str(), e.err.c_str()));
    }
    return mesh;
}

#else

Mesh Mesh::load(const String& path, double)
{
    CV_Error_(Error::StsNotImplemented,
              ("Mesh::load(%s): forestmod was built without assimp", path.c_str()));
}

#endif

} // namespace forestmod
} // namespace cv
