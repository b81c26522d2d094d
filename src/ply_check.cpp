// This file is part of OpenCV project.
// It is subject to the license terms in the LICENSE file found in the top-level directory
// of this distribution and at http://opencv.org/license.html

// The PLY check of Mesh::load: the header parsed strictly, then the data walked without being
// kept, so that a file whose data disagrees with its header never reaches assimp.

#include "precomp.hpp"
#include "ply_check.hpp"

#include <cctype>
#include <cerrno>
#include <cfloat>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <sstream>

namespace cv {
namespace forestmod {
namespace detail {

namespace {

enum PlyFormat
{
    PLY_ASCII = 0,
    PLY_BINARY_LITTLE_ENDIAN = 1,
    PLY_BINARY_BIG_ENDIAN = 2
};

struct PlyProperty
{
    int size;       // bytes of a value
    bool integral;  // an integer type (list counts, indices)
    bool list;
    int count_size; // bytes of a list's count
};

// |value| of every real (float, double) as the file holds it (before Mesh::load's scale): assimp
// 5.2 used over 2 GB on a vertex property of 2.4e27 (fuzzing)
static const double MAX_PLY_REAL = 1e12;

struct PlyElement
{
    std::string name;
    int64 count;
    std::vector<PlyProperty> props;
};

struct PlyHeader
{
    int format = -1; // PlyFormat
    std::vector<PlyElement> elements;
};

// The data after the header, read in chunks of 1 MiB: bytes, or whitespace-separated tokens.
class PlyData
{
public:
    explicit PlyData(std::ifstream& f) : f_(f) {}

    // next byte, -1 at the end
    int next()
    {
        if (pos_ == len_)
        {
            if (eof_)
                return -1;
            buf_.resize(CHUNK);
            f_.read(&buf_[0], (std::streamsize)CHUNK);
            len_ = (size_t)f_.gcount();
            pos_ = 0;
            eof_ = len_ < CHUNK;
            if (len_ == 0)
                return -1;
        }
        return (uchar)buf_[pos_++];
    }

    // the next whitespace-separated token (its first 64 characters); false at the end.
    // newlineBefore(): a line ended between it and the previous token (or the header).
    bool token(std::string& tok)
    {
        tok.clear();
        newline_before_ = newline_pending_;
        int c = next();
        while (c >= 0 && std::isspace(c))
        {
            newline_before_ = newline_before_ || c == '\n';
            c = next();
        }
        while (c >= 0 && !std::isspace(c))
        {
            if (tok.size() < 64)
                tok += (char)c;
            c = next();
        }
        newline_pending_ = c == '\n';
        return !tok.empty();
    }
    bool newlineBefore() const { return newline_before_; }

    // the next n <= 8 bytes into bytes(); false at the end
    bool read(int n)
    {
        for (int i = 0; i < n; ++i)
        {
            const int c = next();
            if (c < 0)
                return false;
            bytes_[i] = (uchar)c;
        }
        return true;
    }
    const uchar* bytes() const { return bytes_; }

private:
    static const size_t CHUNK = 1 << 20;
    std::ifstream& f_;
    std::vector<char> buf_;
    size_t pos_ = 0, len_ = 0;
    bool eof_ = false;
    bool newline_pending_ = true, newline_before_ = false; // the header ends with its line
    uchar bytes_[8] = { 0, 0, 0, 0, 0, 0, 0, 0 };
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

// an ASCII PLY value: the whole token is a number (an integer for integer types, within 64
// bits); a NUL byte inside ends no number (assimp 5.2 reads the data otherwise: fuzzing); a real
// bits); a real of `size` 4 or 8 bytes must be finite in that type (assimp 5.2 allocated 7.6 GB
// for a vertex at infinity: fuzzing)
static bool plyNumber(const std::string& tok, bool integral, long long* value, int size = 0)
{
    if (tok.empty())
        return false;
    char* end = 0;
    errno = 0;
    bool in_range = true;
    if (integral)
    {
        const long long v = std::strtoll(tok.c_str(), &end, 10);
        if (value)
            *value = v;
        in_range = errno != ERANGE;
    }
    else
    {
        const double v = std::strtod(tok.c_str(), &end);
        in_range = size == 4 ? std::abs(v) <= FLT_MAX : size != 8 || std::isfinite(v);
    }
    return end == tok.c_str() + tok.size() && in_range;
}

// a binary real (4 or 8 bytes, the file's byte order) is finite
static bool plyFiniteReal(const uchar* b, int size, bool big_endian)
{
    const ushort one = 1;
    const bool swap = big_endian == (*(const uchar*)&one == 1);
    uchar t[8] = { 0 };
    for (int i = 0; i < size && i < 8; ++i)
        t[i] = swap ? b[size - 1 - i] : b[i];
    if (size == 4)
    {
        float f;
        std::memcpy(&f, t, 4);
        return std::isfinite(f);
    }
    double d;
    std::memcpy(&d, t, 8);
    return size != 8 || std::isfinite(d);
}

// an element's or property's name: a letter or '_' first, then letters, digits, '_' or '-', at
// most 64 characters (assimp 5.2 reads other names its own way: fuzzing)
static bool plyName(const std::string& name)
{
    if (name.empty() || name.size() > 64 || !(std::isalpha((uchar)name[0]) || name[0] == '_'))
        return false;
    for (size_t i = 1; i < name.size(); ++i)
        if (!std::isalnum((uchar)name[i]) && name[i] != '_' && name[i] != '-')
            return false;
    return true;
}

// "element <name> <count>", the count within Mesh's limits
static bool parseElement(std::istringstream& ls, const String& path, PlyHeader& h)
{
    PlyElement e;
    std::string count;
    ls >> e.name >> count;
    long long c = -1;
    const bool ok = plyName(e.name) && plyNumber(count, true, &c) && c >= 0;
    const int64 limit = e.name == "face" ? (int64)Mesh::MAX_FACES : (int64)Mesh::MAX_VERTICES;
    if (ok && c > limit)
        CV_Error_(Error::StsOutOfRange, ("Mesh::load: '%s': the PLY header declares %lld '%s' "
                                         "elements, more than the limit of %lld "
                                         "(Mesh::MAX_VERTICES / MAX_FACES)",
                                         path.c_str(), c, e.name.c_str(), (long long)limit));
    e.count = c;
    h.elements.push_back(e);
    return ok;
}

// "property <type> <name>" or "property list <count type> <item type> <name>"
static bool parseProperty(std::istringstream& ls, PlyHeader& h)
{
    PlyProperty pr;
    std::string type, name;
    ls >> type;
    pr.list = type == "list";
    pr.count_size = 0;
    bool ok;
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
    h.elements.back().props.push_back(pr);
    return ok && plyName(name);
}

// The header up to end_header (at most 10000 lines); the stream is left at the data.
static PlyHeader parseHeader(std::ifstream& f, const String& path)
{
    std::string line;
    if (!std::getline(f, line) || (line != "ply" && line != "ply\r"))
        CV_Error_(Error::StsParseError, ("Mesh::load: '%s': the first line of a PLY file must be "
                                         "'ply' (lines end with \\n or \\r\\n)", path.c_str()));
    const char* fmt_names[] = { "ascii", "binary_little_endian", "binary_big_endian" };
    PlyHeader h;
    bool end_header = false;
    for (int n = 0; n < 10000 && !end_header && std::getline(f, line); ++n)
    {
        if (!line.empty() && line[line.size() - 1] == '\r')
            line.erase(line.size() - 1);
        // a CR or another control character inside a line: assimp 5.2 hangs on some (fuzzing)
        for (size_t i = 0; i < line.size(); ++i)
            if ((uchar)line[i] < ' ' && line[i] != '\t')
                CV_Error_(Error::StsParseError, ("Mesh::load: '%s': PLY header line %d holds the "
                                                 "control character %d (lines end with \\n or "
                                                 "\\r\\n)", path.c_str(), n + 2, (int)line[i]));
        std::istringstream ls(line);
        std::string key;
        ls >> key;
        bool ok = true;
        if (key == "end_header")
            end_header = true;
        else if (key == "comment" || key == "obj_info")
            continue;
        else if (key == "format")
        {
            std::string name, version;
            ls >> name >> version;
            for (int i = 0; i < 3; ++i)
                if (name == fmt_names[i])
                    h.format = i;
            ok = h.format >= 0 && version == "1.0";
        }
        else if (key == "element")
            ok = parseElement(ls, path, h);
        else if (key == "property" && !h.elements.empty())
            ok = parseProperty(ls, h);
        else
            ok = false;
        std::string extra; // nothing after a line's fields (assimp reads such lines otherwise)
        if (ok && (ls >> extra))
            ok = false;
        if (!ok)
            CV_Error_(Error::StsParseError, ("Mesh::load: '%s': PLY header line %d not "
                                             "understood: '%s'", path.c_str(), n + 2,
                                             line.substr(0, 80).c_str()));
    }
    if (!end_header || h.format < 0)
        CV_Error_(Error::StsParseError, ("Mesh::load: '%s': PLY header without %s", path.c_str(),
                                         h.format < 0 ? "a format line" : "end_header"));
    // assimp 5.2 reads forever when a header with a property-less element ends the file without
    // a line end (fuzzing): end_header needs its line end, an element a property
    if (f.eof())
        CV_Error_(Error::StsParseError, ("Mesh::load: '%s': the PLY header's end_header line "
                                         "ends without a line break", path.c_str()));
    for (size_t i = 0; i < h.elements.size(); ++i)
        if (h.elements[i].props.empty())
            CV_Error_(Error::StsParseError, ("Mesh::load: '%s': PLY element '%s' declares no "
                                             "property", path.c_str(),
                                             h.elements[i].name.c_str()));
    return h;
}

static void notANumber(const String& path, const PlyElement& el, int64 r, const std::string& tok)
{
    CV_Error_(Error::StsParseError, ("Mesh::load: '%s': PLY '%s' %lld holds '%s' where a number "
                                     "is expected", path.c_str(), el.name.c_str(), (long long)r,
                                     tok.c_str()));
}

// One property of element `r` walked; false when the data ended first. ASCII: whitespace-
// separated values, a list's count first; binary: fixed sizes, list counts in the file's byte
// order.
static void notOneLine(const String& path, const PlyElement& el, int64 r)
{
    CV_Error_(Error::StsParseError, ("Mesh::load: '%s': PLY '%s' %lld is not one line of its "
                                     "values (an ASCII element is a line: assimp reads line by "
                                     "line)", path.c_str(), el.name.c_str(), (long long)r));
}

static bool walkProperty(PlyData& data, int format, const PlyElement& el, const PlyProperty& pr,
                         int64 r, bool first, const String& path)
{
    std::string tok;
    long long items = 1;
    if (format == PLY_ASCII)
    {
        if (!data.token(tok))
            return false;
        // one line per element (fuzz_mesh_load: vertices spread over lines made assimp 5.2 read
        // a face's count of -23 and allocate 32 GB)
        if (data.newlineBefore() != first)
            notOneLine(path, el, r);
        if (!plyNumber(tok, pr.list || pr.integral, pr.list ? &items : 0, pr.list ? 0 : pr.size))
            notANumber(path, el, r, tok);
        if (!pr.list && !pr.integral && !(std::abs(std::strtod(tok.c_str(), 0)) <= MAX_PLY_REAL))
            CV_Error_(Error::StsOutOfRange, ("Mesh::load: '%s': PLY '%s' %lld: value %s lies "
                                             "beyond +-1e12 (the file's units)", path.c_str(),
                                             el.name.c_str(), (long long)r, tok.c_str()));
    }
    else if (pr.list)
    {
        if (!data.read(pr.count_size))
            return false;
        items = (long long)plyReadCount(data.bytes(), pr.count_size,
                                        format == PLY_BINARY_BIG_ENDIAN);
    }
    if (pr.list && (items < 0 || items > Mesh::MAX_FACE_INDICES))
        CV_Error_(Error::StsOutOfRange, ("Mesh::load: '%s': PLY '%s' %lld has a list of %lld "
                                         "values (at most %d)", path.c_str(), el.name.c_str(),
                                         (long long)r, items, (int)Mesh::MAX_FACE_INDICES));
    // the values after a list's count; a binary scalar is its one value
    const long long values = pr.list ? items : (format == PLY_ASCII ? 0 : 1);
    for (long long i = 0; i < values; ++i)
    {
        if (format != PLY_ASCII)
        {
            if (!data.read(pr.size))
                return false;
            if (!pr.integral && !plyFiniteReal(data.bytes(), pr.size,
                                               format == PLY_BINARY_BIG_ENDIAN))
                notANumber(path, el, r, "(a binary inf or nan)");
        }
        else if (!data.token(tok))
            return false;
        else if (data.newlineBefore())
            notOneLine(path, el, r);
        else if (!plyNumber(tok, pr.integral, 0, pr.size))
            notANumber(path, el, r, tok);
    }
    return true;
}

void checkPly(const String& path)
{
    std::ifstream f(path.c_str(), std::ios::binary);
    char magic[4] = { 0, 0, 0, 0 };
    f.read(magic, 4);
    if (f.gcount() < 4 || std::memcmp(magic, "ply", 3) != 0 || !std::isspace((uchar)magic[3]))
        return;
    f.seekg(0);
    const PlyHeader h = parseHeader(f, path);
    const std::streamoff data_begin = f.tellg();
    f.seekg(0, std::ios::end);
    const std::streamoff data_size = f.tellg() - data_begin;
    f.seekg(data_begin);

    PlyData data(f);
    for (size_t e = 0; e < h.elements.size(); ++e)
    {
        const PlyElement& el = h.elements[e];
        for (int64 r = 0; r < el.count; ++r)
            for (size_t k = 0; k < el.props.size(); ++k)
                if (!walkProperty(data, h.format, el, el.props[k], r, k == 0, path))
                    CV_Error_(Error::StsParseError,
                              ("Mesh::load: '%s' is truncated: the PLY header declares %lld "
                               "'%s' elements, the data ends in element %lld (%lld bytes of "
                               "data)", path.c_str(), (long long)el.count, el.name.c_str(),
                               (long long)r, (long long)data_size));
    }
    // what follows the declared elements: whitespace only
    for (int c = data.next(); c >= 0; c = data.next())
        if (!(h.format == PLY_ASCII ? std::isspace(c) != 0
                                    : (c == '\n' || c == '\r' || c == ' ')))
            CV_Error_(Error::StsParseError,
                      ("Mesh::load: '%s' holds more data than its PLY header declares (%s): "
                       "wrong element counts?", path.c_str(),
                       h.elements.empty() ? "no elements"
                                          : cv::format("last element '%s' x %lld",
                                                       h.elements.back().name.c_str(),
                                                       (long long)h.elements.back().count)
                                                .c_str()));
}

} // namespace detail
} // namespace forestmod
} // namespace cv
