// This file is part of OpenCV project.
// It is subject to the license terms in the LICENSE file found in the top-level directory
// of this distribution and at http://opencv.org/license.html

// Mesh: geometry helpers (bounding box, centre, diameter, normals) and the assimp loader.

#include "precomp.hpp"

#ifdef HAVE_ASSIMP
#include <assimp/Importer.hpp>
#include <assimp/postprocess.h>
#include <assimp/scene.h>
#endif

#include <cctype>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <sstream>

namespace cv {
namespace forestmod {

static const double MAX_COORDINATE = Mesh::MAX_COORDINATE_MM;

bool Mesh::empty() const
{
    return vertices.empty() || faces.empty();
}

Point3f Mesh::bboxMin() const
{
    CV_Check(vertices.size(), !vertices.empty(), "Mesh::bboxMin: the mesh has no vertices");
    Point3f m = vertices[0];
    for (size_t i = 1; i < vertices.size(); ++i)
    {
        m.x = std::min(m.x, vertices[i].x);
        m.y = std::min(m.y, vertices[i].y);
        m.z = std::min(m.z, vertices[i].z);
    }
    return m;
}

Point3f Mesh::bboxMax() const
{
    CV_Check(vertices.size(), !vertices.empty(), "Mesh::bboxMax: the mesh has no vertices");
    Point3f m = vertices[0];
    for (size_t i = 1; i < vertices.size(); ++i)
    {
        m.x = std::max(m.x, vertices[i].x);
        m.y = std::max(m.y, vertices[i].y);
        m.z = std::max(m.z, vertices[i].z);
    }
    return m;
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

// ---- PLY: header and data length checked before assimp reads (and allocates) anything ---------

namespace {

struct PlyProperty
{
    int size;       // bytes of a value
    bool integral;  // an integer type (list counts, indices)
    bool list;
    int count_size; // bytes of a list's count
};

struct PlyElement
{
    std::string name;
    int64 count;
    std::vector<PlyProperty> props;
};

} // namespace

// bytes of a PLY scalar type, 0 when unknown; *integral: an integer type
static int plyTypeSize(const std::string& t, bool* integral)
{
    *integral = true;
    if (t == "char" || t == "uchar" || t == "int8" || t == "uint8")
        return 1;
    if (t == "short" || t == "ushort" || t == "int16" || t == "uint16")
        return 2;
    if (t == "int" || t == "uint" || t == "int32" || t == "uint32")
        return 4;
    *integral = false;
    if (t == "float" || t == "float32")
        return 4;
    if (t == "double" || t == "float64")
        return 8;
    return 0;
}

static uint64 plyReadCount(const uchar* p, int size, bool big_endian)
{
    uint64 v = 0;
    for (int i = 0; i < size; ++i)
        v |= (uint64)p[big_endian ? i : size - 1 - i] << (8 * (size - 1 - i));
    return v;
}

// an ASCII PLY value: the whole token is a number (an integer for integer types)
static bool plyNumber(const std::string& tok, bool integral, long long* value)
{
    if (tok.empty())
        return false;
    char* end = 0;
    if (integral)
    {
        const long long v = std::strtoll(tok.c_str(), &end, 10);
        if (value)
            *value = v;
    }
    else
        (void)std::strtod(tok.c_str(), &end);
    return *end == '\0';
}

// Throws unless a file that starts with "ply" has a header this check understands, counts
// within Mesh's limits and data exactly as long as the header declares, every ASCII value a
// number; assimp then reads a well-formed file. Files that do not start with "ply" are left to
// assimp.
static void checkPly(const String& path)
{
    std::ifstream f(path.c_str(), std::ios::binary);
    char magic[4] = { 0, 0, 0, 0 };
    f.read(magic, 4);
    if (f.gcount() < 4 || std::memcmp(magic, "ply", 3) != 0 || !std::isspace((uchar)magic[3]))
        return;
    f.seekg(0);
    std::string line;
    if (!std::getline(f, line) || (line != "ply" && line != "ply\r"))
        CV_Error_(Error::StsParseError, ("Mesh::load: '%s': the first line of a PLY file must be "
                                         "'ply' (lines end with \\n or \\r\\n)", path.c_str()));
    const char* fmt_names[] = { "ascii", "binary_little_endian", "binary_big_endian" };
    int format = -1;
    std::vector<PlyElement> elements;
    bool end_header = false;
    for (int n = 0; n < 10000 && std::getline(f, line); ++n)
    {
        if (!line.empty() && line[line.size() - 1] == '\r')
            line.erase(line.size() - 1);
        std::istringstream ls(line);
        std::string key;
        ls >> key;
        if (key == "end_header")
        {
            end_header = true;
            break;
        }
        if (key == "comment" || key == "obj_info")
            continue;
        bool ok = true;
        if (key == "format")
        {
            std::string name, version;
            ls >> name >> version;
            for (int i = 0; i < 3; ++i)
                if (name == fmt_names[i])
                    format = i;
            ok = format >= 0 && version == "1.0";
        }
        else if (key == "element")
        {
            PlyElement e;
            std::string count;
            ls >> e.name >> count;
            long long c = -1;
            ok = !e.name.empty() && plyNumber(count, true, &c) && c >= 0;
            const int64 limit = e.name == "face" ? (int64)Mesh::MAX_FACES
                                                 : (int64)Mesh::MAX_VERTICES;
            if (ok && c > limit)
                CV_Error_(Error::StsOutOfRange, ("Mesh::load: '%s': the PLY header declares %lld "
                                                 "'%s' elements, more than the limit of %lld "
                                                 "(Mesh::MAX_VERTICES / MAX_FACES)",
                                                 path.c_str(), c, e.name.c_str(),
                                                 (long long)limit));
            e.count = c;
            elements.push_back(e);
        }
        else if (key == "property" && !elements.empty())
        {
            PlyProperty pr;
            std::string type, name;
            ls >> type;
            pr.list = type == "list";
            pr.count_size = 0;
            if (pr.list)
            {
                std::string count_type, item_type;
                ls >> count_type >> item_type;
                bool count_integral = false;
                pr.count_size = plyTypeSize(count_type, &count_integral);
                pr.size = plyTypeSize(item_type, &pr.integral);
                ok = count_integral && pr.count_size > 0 && pr.size > 0;
            }
            else
            {
                pr.size = plyTypeSize(type, &pr.integral);
                ok = pr.size > 0;
            }
            ls >> name;
            ok = ok && !name.empty();
            elements.back().props.push_back(pr);
        }
        else
            ok = false;
        if (!ok)
            CV_Error_(Error::StsParseError, ("Mesh::load: '%s': PLY header line %d not "
                                             "understood: '%s'", path.c_str(), n + 2,
                                             line.substr(0, 80).c_str()));
    }
    if (!end_header || format < 0)
        CV_Error_(Error::StsParseError, ("Mesh::load: '%s': PLY header without %s", path.c_str(),
                                         format < 0 ? "a format line" : "end_header"));
    const std::streamoff data_begin = f.tellg();
    f.seekg(0, std::ios::end);
    const std::streamoff data_size = f.tellg() - data_begin;
    f.seekg(data_begin);

    // Walk the data without keeping it. ASCII: whitespace-separated values, a list's count
    // first; binary: fixed sizes, list counts read in the file's byte order.
    const bool big_endian = format == 2;
    const size_t chunk = 1 << 20;
    std::vector<char> buf;
    size_t pos = 0, len = 0;
    bool eof = false;
    // next byte, refilling the buffer; -1 at the end
    auto next = [&]() -> int {
        if (pos == len)
        {
            if (eof)
                return -1;
            buf.resize(chunk);
            f.read(&buf[0], (std::streamsize)chunk);
            len = (size_t)f.gcount();
            pos = 0;
            eof = len < chunk;
            if (len == 0)
                return -1;
        }
        return (uchar)buf[pos++];
    };
    std::string tok;
    auto token = [&]() -> bool {
        tok.clear();
        int c = next();
        while (c >= 0 && std::isspace(c))
            c = next();
        while (c >= 0 && !std::isspace(c))
        {
            if (tok.size() < 64)
                tok += (char)c;
            c = next();
        }
        return !tok.empty();
    };
    uchar bytes[8];
    auto read = [&](int n) -> bool {
        for (int i = 0; i < n; ++i)
        {
            const int c = next();
            if (c < 0)
                return false;
            bytes[i] = (uchar)c;
        }
        return true;
    };
    for (size_t e = 0; e < elements.size(); ++e)
    {
        const PlyElement& el = elements[e];
        for (int64 r = 0; r < el.count; ++r)
            for (size_t k = 0; k < el.props.size(); ++k)
            {
                const PlyProperty& pr = el.props[k];
                bool ok = true;
                long long items = 1;
                if (format == 0)
                {
                    ok = token();
                    if (ok && !plyNumber(tok, pr.list || pr.integral, pr.list ? &items : 0))
                        CV_Error_(Error::StsParseError,
                                  ("Mesh::load: '%s': PLY '%s' %lld holds '%s' where a number "
                                   "is expected", path.c_str(), el.name.c_str(), (long long)r,
                                   tok.c_str()));
                }
                else if (pr.list)
                {
                    ok = read(pr.count_size);
                    items = ok ? (long long)plyReadCount(bytes, pr.count_size, big_endian) : 0;
                }
                if (ok && pr.list && (items < 0 || items > Mesh::MAX_FACE_INDICES))
                    CV_Error_(Error::StsOutOfRange,
                              ("Mesh::load: '%s': PLY '%s' %lld has a list of %lld values (at "
                               "most %d)", path.c_str(), el.name.c_str(), (long long)r, items,
                               (int)Mesh::MAX_FACE_INDICES));
                for (long long i = 0; ok && i < (pr.list ? items : (format == 0 ? 0 : 1)); ++i)
                {
                    if (format != 0)
                        ok = read(pr.size);
                    else
                    {
                        ok = token();
                        if (ok && !plyNumber(tok, pr.integral, 0))
                            CV_Error_(Error::StsParseError,
                                      ("Mesh::load: '%s': PLY '%s' %lld holds '%s' where a "
                                       "number is expected", path.c_str(), el.name.c_str(),
                                       (long long)r, tok.c_str()));
                    }
                }
                if (!ok)
                    CV_Error_(Error::StsParseError,
                              ("Mesh::load: '%s' is truncated: the PLY header declares %lld '%s' "
                               "elements, the data ends in element %lld (%lld bytes of data)",
                               path.c_str(), (long long)el.count, el.name.c_str(),
                               (long long)r, (long long)data_size));
            }
    }
    // what follows the declared elements: whitespace only
    for (int c = next(); c >= 0; c = next())
        if (!(format == 0 ? std::isspace(c) != 0 : (c == '\n' || c == '\r' || c == ' ')))
            CV_Error_(Error::StsParseError,
                      ("Mesh::load: '%s' holds more data than its PLY header declares (%s): "
                       "wrong element counts?", path.c_str(),
                       elements.empty() ? "no elements"
                                        : cv::format("last element '%s' x %lld",
                                                     elements.back().name.c_str(),
                                                     (long long)elements.back().count).c_str()));
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

Mesh Mesh::load(const String& path, double scale)
{
    if (!(scale > 0) || !std::isfinite(scale))
        CV_Error_(Error::StsBadArg, ("Mesh::load(%s): scale must be positive, got %g", path.c_str(),
                                     scale));
    {
        std::ifstream probe(path.c_str(), std::ios::binary);
        if (!probe.good())
            CV_Error_(Error::StsObjectNotFound,
                      ("Mesh::load: cannot open '%s' (missing or unreadable)", path.c_str()));
        probe.seekg(0, std::ios::end);
        if (probe.tellg() <= 0)
            CV_Error_(Error::StsParseError, ("Mesh::load: '%s' is empty", path.c_str()));
    }
    checkPly(path);

    Assimp::Importer importer;
    // drop points and lines: we render triangles only
    importer.SetPropertyInteger(AI_CONFIG_PP_SBP_REMOVE, aiPrimitiveType_POINT | aiPrimitiveType_LINE);
    const unsigned flags = aiProcess_Triangulate | aiProcess_JoinIdenticalVertices
                           | aiProcess_PreTransformVertices | aiProcess_SortByPType;
    // Two steps: read without post-processing, check the raw faces, then post-process.
    // Debian's libassimp is built with its internal assertions on, and some readers (PLY) turn a
    // truncated file into faces without indices, on which aiProcess_Triangulate aborts the
    // process instead of reporting an error.
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

    Mesh mesh;
    bool all_normals = true, any_colors = false;
    size_t num_triangles = 0, collapsed = 0, repeated = 0;
    for (unsigned m = 0; m < scene->mNumMeshes; ++m)
    {
        const aiMesh* am = scene->mMeshes[m];
        if (!(am->mPrimitiveTypes & aiPrimitiveType_TRIANGLE))
            continue;
        all_normals = all_normals && am->HasNormals();
        any_colors = any_colors || am->HasVertexColors(0);
    }
    for (unsigned m = 0; m < scene->mNumMeshes; ++m)
    {
        const aiMesh* am = scene->mMeshes[m];
        if (!(am->mPrimitiveTypes & aiPrimitiveType_TRIANGLE))
            continue;
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
            ++num_triangles;
            const Vec3i tri(base + (int)face.mIndices[0], base + (int)face.mIndices[1],
                            base + (int)face.mIndices[2]);
            if (tri[0] == tri[1] && tri[1] == tri[2])
            {
                ++collapsed; // a "triangle" on one vertex: dropped (or the sign of a bad file)
                continue;
            }
            if (!mesh.faces.empty() && mesh.faces.back() == tri)
                ++repeated;
            mesh.faces.push_back(tri);
        }
    }
    // assimp's readers are lenient with truncated files (seen with PLY 5.2): missing vertices
    // become zeros, so that many faces collapse onto one vertex after joining identical
    // vertices, and missing faces repeat the last face read. Neither happens in a sane mesh.
    size_t trailing = 0; // faces at the end equal to their predecessor
    for (size_t f = mesh.faces.size(); f >= 2 && mesh.faces[f - 1] == mesh.faces[f - 2]; --f)
        ++trailing;
    if (trailing > 0 || (repeated > 0 && repeated * 100 > num_triangles))
        CV_Error_(Error::StsParseError,
                  ("Mesh::load: '%s' looks corrupt or truncated: %d of %d triangles repeat the "
                   "previous one (%d at the end)",
                   path.c_str(), (int)repeated, (int)num_triangles, (int)trailing));
    if (collapsed > 0 && collapsed * 100 > num_triangles)
        CV_Error_(Error::StsParseError,
                  ("Mesh::load: '%s' looks corrupt or truncated: %d of %d triangles collapse onto a "
                   "single vertex",
                   path.c_str(), (int)collapsed, (int)num_triangles));
    if (mesh.faces.empty())
        CV_Error_(Error::StsParseError,
                  ("Mesh::load: '%s' has no triangles (%u meshes read by assimp)", path.c_str(),
                   scene->mNumMeshes));
    if (mesh.colors.empty())
        mesh.colors.assign(mesh.vertices.size(), Vec3b(128, 128, 128));
    if (mesh.normals.empty())
        mesh.computeNormals();
    else
    {
        // a file may carry zero normals for some vertices: fill those from the faces
        bool any_zero = false;
        for (size_t i = 0; i < mesh.normals.size() && !any_zero; ++i)
            any_zero = mesh.normals[i] == Vec3f(0.f, 0.f, 0.f);
        if (any_zero)
        {
            std::vector<Vec3f> from_file = mesh.normals;
            mesh.computeNormals();
            for (size_t i = 0; i < from_file.size(); ++i)
                if (from_file[i] != Vec3f(0.f, 0.f, 0.f))
                    mesh.normals[i] = from_file[i];
        }
    }
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
