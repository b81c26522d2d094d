// This file is part of OpenCV project.
// It is subject to the license terms in the LICENSE file found in the top-level directory
// of this distribution and at http://opencv.org/license.html

// Range checks of model files and DetectorParams (model_check.hpp).

#include "precomp.hpp"
#include "model_check.hpp"
#include "pose_refine.hpp"

#include "opencv2/core/utils/filesystem.hpp"
#include "opencv2/core/utils/logger.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstring>
#include <fstream>
#include <sstream>
#ifdef HAVE_FORESTMOD_ZLIB
#include <zlib.h>
#endif
#ifndef _WIN32
#include <sys/stat.h>
#endif

namespace cv {
namespace forestmod {
namespace detail {

using linemod::Feature;
using linemod::Template;

static bool finite(double v)
{
    return std::isfinite(v);
}

static bool isIntNodeOf(const FileNode& n)
{
    return !n.empty() && n.isInt();
}

void checkDetectorParams(const DetectorParams& p)
{
    CV_CheckGT(p.chunk_size, 0, "DetectorParams: chunk_size must be positive");
    CV_CheckGE(p.alpha, 0.f, "DetectorParams: alpha must be in [0, 1]");
    CV_CheckLE(p.alpha, 1.f, "DetectorParams: alpha must be in [0, 1]");
    CV_CheckGE(p.grid_size, 2, "DetectorParams: grid_size must be at least 2");
    CV_CheckLE(p.grid_size, 64, "DetectorParams: grid_size must be at most 64");
    CV_CheckGE(p.location_step, 0, "DetectorParams: location_step must be >= 0 (0: T / 2)");
    CV_CheckLE(p.location_step, (int)MAX_LOCATION_STEP,
               "DetectorParams: location_step must be at most 16 (the training shifts grow with "
               "its square)");
    CV_Check(p.nms_iou, p.nms_iou >= 0.f && p.nms_iou <= 1.f,
             "DetectorParams: nms_iou must be in [0, 1] (0 or 1: no suppression)");
    CV_CheckGT(p.max_survivors, 0, "DetectorParams: max_survivors must be positive");
    CV_CheckLE(p.max_survivors, (int)MAX_SURVIVORS,
               "DetectorParams: max_survivors must be at most 64 (exhaustive groups keep "
               "max_survivors x (T / location step)^2 matches per position)");
    CV_Check(p.exhaustive_ratio, finite(p.exhaustive_ratio),
             "DetectorParams: exhaustive_ratio must be finite (negative: never exhaustive)");
    CV_Check(p.descent_cost, finite(p.descent_cost) && p.descent_cost >= 0.f,
             "DetectorParams: descent_cost must be finite and not negative");
    CV_CheckGE(p.min_forest_templates, 0,
               "DetectorParams: min_forest_templates must not be negative");
    CV_CheckGE(p.depth_samples, 0, "DetectorParams: depth_samples must not be negative");
    CV_CheckLE(p.depth_samples, 256, "DetectorParams: depth_samples must be at most 256");
    CV_CheckGT(p.depth_tolerance, 0, "DetectorParams: depth_tolerance must be positive");
    CV_CheckLE(p.depth_tolerance, (int)MAX_DEPTH_SAMPLE_MM,
               "DetectorParams: depth_tolerance must be at most 65535 mm");
    CV_CheckGE(p.min_window_labels, 0.f, "DetectorParams: min_window_labels must be in [0, 1]");
    CV_CheckLE(p.min_window_labels, 1.f, "DetectorParams: min_window_labels must be in [0, 1]");
    CV_Check(p.depth_range_tolerance, finite(p.depth_range_tolerance),
             "DetectorParams: depth_range_tolerance must be finite (negative: off)");
    CV_CheckGE(p.dominant_window, 1, "DetectorParams: dominant_window must be in [1, 9]");
    CV_CheckLE(p.dominant_window, 9, "DetectorParams: dominant_window must be in [1, 9]");
    CV_Check(p.group_size_ratio, p.group_size_ratio >= 0.f && finite(p.group_size_ratio),
             "DetectorParams: group_size_ratio must be finite and >= 0 (0: no size limit)");
    CV_Check(p.auto_depth_leaf_samples,
             p.auto_depth_leaf_samples >= 0.f && finite(p.auto_depth_leaf_samples),
             "DetectorParams: auto_depth_leaf_samples must be finite and >= 0 (0: the paper's "
             "depth)");
    checkForestParams(p.forest);
    CV_Check(p.forest.num_trees, p.forest.num_trees >= 1 && p.forest.num_trees <= 1000,
             "DetectorParams: forest.num_trees must be in [1, 1000]");
    CV_Check(p.forest.max_depth, p.forest.max_depth >= 0 && p.forest.max_depth <= 30,
             "DetectorParams: forest.max_depth must be in [0, 30] (0: automatic)");
}

static int base64Value(char c)
{
    if (c >= 'A' && c <= 'Z')
        return c - 'A';
    if (c >= 'a' && c <= 'z')
        return c - 'a' + 26;
    if (c >= '0' && c <= '9')
        return c - '0' + 52;
    if (c == '+')
        return 62;
    if (c == '/')
        return 63;
    return -1;
}

// The 24-byte header of a base64 block starting at p as OpenCV's decoder reads it: the printable
// characters of its rows (a row ends at a line's end, in JSON at ',' or '"'; the next row starts
// after its indentation), characters outside the base64 alphabet counting as 0.
static std::string base64Header(const std::string& text, size_t p, bool json)
{
    std::vector<int> v;
    bool row_start = true;
    for (; p < text.size() && v.size() < 32; ++p)
    {
        const uchar c = (uchar)text[p];
        if (c == '\n' || c == '\r')
        {
            if (json)
                break;
            row_start = true;
            continue;
        }
        if (row_start && (c == ' ' || c == '\t'))
            continue;
        if (c < ' ' || (json && (c == ',' || c == '"')))
            break;
        row_start = false;
        v.push_back(std::max(0, base64Value((char)c)));
    }
    v.resize(32, 0);
    std::string h;
    for (size_t i = 0; i < 32; i += 4)
    {
        h.push_back((char)((v[i] << 2) | (v[i + 1] >> 4)));
        h.push_back((char)(((v[i + 1] << 4) | (v[i + 2] >> 2)) & 255));
        h.push_back((char)(((v[i + 2] << 6) | v[i + 3]) & 255));
    }
    return h;
}

// Every base64 block of the text starts with a type header ("3d", "1u" ...; see readModelText)
// that names at least one element type: OpenCV 4.6 loops forever on a header of only a count or
// an empty one (found by fuzzing).
static void checkBase64Blocks(const std::string& text, const String& filename)
{
    const char* markers[] = { "!!binary", "$base64$", "type_id=\"binary\"" };
    for (int mk = 0; mk < 3; ++mk)
    {
        const size_t mlen = std::strlen(markers[mk]);
        for (size_t at = text.find(markers[mk]); at != std::string::npos;
             at = text.find(markers[mk], at + mlen))
        {
            size_t p = at + mlen;
            bool ok = true;
            if (mk == 0) // YAML: "!!binary |" as cv::FileStorage writes it
            {
                while (p < text.size() && (text[p] == ' ' || text[p] == '\t'))
                    ++p;
                ok = p < text.size() && text[p] == '|';
                ++p;
            }
            else if (mk == 2) // XML: the element's content
            {
                p = text.find('>', p);
                ok = p != std::string::npos;
                ++p;
            }
            if (ok)
            {
                const std::string h = base64Header(text, p, mk == 1);
                // the type string: up to the first space or NUL, as OpenCV cuts it
                size_t n = 0;
                while (n < h.size() && h[n] != 0 && !std::isspace((uchar)h[n]))
                    ++n;
                ok = n > 0 && h.find_first_of("ucwsifdhr") < n;
            }
            if (!ok)
                CV_Error_(Error::StsParseError, ("forestmod model: '%s': a base64 block at byte %d "
                                                 "has no data type header (corrupt file?)",
                                                 filename.c_str(), (int)at));
        }
    }
}

// A YAML model's first line is the directive alone ("%YAML:1.0" as OpenCV writes it, or
// "%YAML 1.x"): OpenCV 4.6's parser loops forever on some files with more on that line (found by
// fuzzing).
static void checkYamlDirective(const std::string& text, const String& filename)
{
    if (text.compare(0, 5, "%YAML") != 0)
        return;
    const std::string line = text.substr(0, text.find_first_of("\r\n"));
    const size_t end = line.find_last_not_of(" \t");
    const std::string directive = line.substr(0, end + 1);
    const bool ok = directive.size() >= 9 && directive.size() <= 12
        && (directive[5] == ':' || directive[5] == ' ') && directive.compare(6, 2, "1.") == 0
        && directive.find_first_not_of("0123456789", 8) == std::string::npos;
    if (!ok)
        CV_Error_(Error::StsParseError, ("forestmod::Detector::load: '%s' is corrupt: its first "
                                         "line must be the YAML directive alone (\"%%YAML:1.0\")",
                                         filename.c_str()));
}

// Quoted strings of YAML and JSON text: the quote state after text[i], given the state before it
// (0: outside a string, else the quote character). A '"' opens a string, and in YAML a single
// quote where a scalar starts; inside a "..." string a backslash escapes the next character
// (i moves past it).
static char quoteState(const std::string& text, size_t& i, char quote, bool yaml)
{
    const char c = text[i];
    if (quote)
    {
        if (c == '\\' && quote == '"')
            ++i;
        else if (c == quote)
            return 0;
        return quote;
    }
    if (c == '"' || (yaml && c == '\'' && (i == 0 || std::strchr(" \t\n[{,:", text[i - 1]))))
        return c;
    return 0;
}

// YAML and JSON text: every '[' and '{' outside quoted strings and comments closed by its own
// bracket, none left open at the end (see readModelText). XML is left to its parser.
static void checkBrackets(const std::string& text, const String& filename)
{
    const size_t first = text.find_first_not_of(" \t\r\n");
    if (first == std::string::npos || text[first] == '<')
        return;
    const bool yaml = text[first] != '{';
    std::string open; // the brackets not yet closed
    char quote = 0;   // inside a string quoted by this character
    for (size_t i = first; i < text.size(); ++i)
    {
        const char c = text[i];
        const bool quoted = quote != 0;
        quote = quoteState(text, i, quote, yaml);
        if (quoted || quote)
            continue;
        if (yaml && c == '#' && (i == 0 || std::isspace((uchar)text[i - 1])))
            i = std::min(text.find('\n', i), text.size()); // a comment, to the end of its line
        else if (c == '[' || c == '{')
            open.push_back(c);
        else if (c == ']' || c == '}')
        {
            if (open.empty() || open[open.size() - 1] != (c == ']' ? '[' : '{'))
                CV_Error_(Error::StsParseError,
                          ("forestmod::Detector::load: '%s' is corrupt: '%c' at byte %lld closes "
                           "no open bracket", filename.c_str(), c, (long long)i));
            open.erase(open.size() - 1);
        }
    }
    if (!open.empty() || quote)
        CV_Error_(Error::StsParseError, ("forestmod::Detector::load: '%s' is corrupt or "
                                         "truncated: %s at the end", filename.c_str(),
                                         quote ? "a string is open" : "a bracket is open"));
}

// YAML block structure: a line indented less than the line before it returns to the indentation
// of a block still open (OpenCV 4.6's parser loops forever on a dedent to a level that no block
// opened: found by fuzzing). Block scalars ("|", the base64 data) and flow collections that span
// lines are skipped; XML and JSON are left to their parsers.
static void checkYamlIndentation(const std::string& text, const String& filename)
{
    const size_t first = text.find_first_not_of(" \t\r\n");
    if (first == std::string::npos || text[first] == '<' || text[first] == '{')
        return;
    std::vector<int> open;   // indentations of the blocks still open
    int scalar = -1;         // inside a block scalar opened at this indentation
    int flow = 0;            // brackets open at the start of the line
    int line_no = 0;
    for (size_t b = 0; b < text.size(); ++line_no)
    {
        size_t e = text.find('\n', b);
        if (e == std::string::npos)
            e = text.size();
        // a CR only as part of a line end (fuzz_model_load: OpenCV 4.6's parser looped forever on
        // a lone CR after a block scalar's '|' inside a flow sequence)
        const size_t cr = (size_t)(std::find(text.begin() + b, text.begin() + e, '\r')
                                   - text.begin());
        if (cr + 1 < e)
            CV_Error_(Error::StsParseError,
                      ("forestmod::Detector::load: '%s' is corrupt: line %d holds a carriage "
                       "return inside it (lines end with \\n or \\r\\n)", filename.c_str(),
                       line_no + 1));
        const size_t c = text.find_first_not_of(" ", b);
        const int indent = (int)(std::min(c, e) - b);
        const bool marker = c == b && (text.compare(c, 3, "---") == 0
                                       || text.compare(c, 3, "...") == 0);
        // a document marker stands alone, as cv::FileStorage writes it (fuzz_model_load: the
        // parser looped forever on a sequence after "..." on the same line)
        if (marker && text.find_first_not_of(" \r", c + 3) < e)
            CV_Error_(Error::StsParseError,
                      ("forestmod::Detector::load: '%s' is corrupt: line %d holds more than the "
                       "YAML document marker '%s'", filename.c_str(), line_no + 1,
                       text.substr(c, 3).c_str()));
        const bool blank = c >= e || text[c] == '\r' || text[c] == '#' || text[c] == '%' || marker;
        if (!blank && scalar >= 0 && indent <= scalar)
            scalar = -1;
        if (!blank && scalar < 0 && flow == 0)
        {
            bool closed = false;
            while (!open.empty() && open.back() > indent)
            {
                open.pop_back();
                closed = true;
            }
            if (open.empty() || open.back() < indent)
            {
                if (closed)
                    CV_Error_(Error::StsParseError,
                              ("forestmod::Detector::load: '%s' is corrupt: line %d is indented "
                               "to a level no enclosing YAML block has", filename.c_str(),
                               line_no + 1));
                open.push_back(indent);
            }
        }
        if (!blank && scalar < 0)
        {
            // brackets of the line outside quotes and comments; a block scalar starts after '|'
            char quote = 0;
            size_t last = e;
            for (size_t i = c; i < e; ++i)
            {
                const char ch = text[i];
                const bool quoted = quote != 0;
                quote = quoteState(text, i, quote, true);
                if (!quoted && !quote)
                {
                    if (ch == '#' && std::isspace((uchar)text[i - 1]))
                        break;
                    if (ch == '[' || ch == '{')
                        ++flow;
                    else if (ch == ']' || ch == '}')
                        flow = std::max(0, flow - 1);
                }
                if (!std::isspace((uchar)ch))
                    last = i;
            }
            if (last < e && text[last] == '|' && flow == 0)
                scalar = indent;
        }
        b = e + 1;
    }
}

String readModelText(const String& filename, const char* func)
{
    std::string text;
#ifdef HAVE_FORESTMOD_ZLIB
    gzFile f = gzopen(filename.c_str(), "rb"); // plain files pass through
    if (!f)
        CV_Error_(Error::StsError, ("%s: cannot open '%s'", func, filename.c_str()));
    std::vector<char> buf(1 << 16);
    for (;;)
    {
        const int got = gzread(f, &buf[0], (unsigned)buf.size());
        if (got < 0)
        {
            gzclose(f);
            CV_Error_(Error::StsParseError, ("%s: '%s' is not a readable (gzip) file", func,
                                             filename.c_str()));
        }
        if (got == 0)
            break;
        text.append(&buf[0], (size_t)got);
        if (text.size() > MAX_MODEL_TEXT_BYTES)
        {
            gzclose(f);
            CV_Error_(Error::StsOutOfRange, ("%s: '%s' holds more than 1 GiB of text", func,
                                             filename.c_str()));
        }
    }
    gzclose(f);
#else
    std::ifstream f(filename.c_str(), std::ios::binary);
    if (!f.good())
        CV_Error_(Error::StsError, ("%s: cannot open '%s'", func, filename.c_str()));
    std::ostringstream ss;
    ss << f.rdbuf();
    text = ss.str();
    if (text.size() > MAX_MODEL_TEXT_BYTES)
        CV_Error_(Error::StsOutOfRange, ("%s: '%s' holds more than 1 GiB of text", func,
                                         filename.c_str()));
    // a build without zlib cannot read gzip files (OpenCV's FileStorage reads them with it)
    if (text.size() >= 2 && (uchar)text[0] == 0x1f && (uchar)text[1] == 0x8b)
        CV_Error_(Error::StsUnsupportedFormat, ("%s: '%s' is compressed and this build has no "
                                                "zlib", func, filename.c_str()));
#endif
    if (text.empty())
        CV_Error_(Error::StsParseError, ("%s: '%s' is empty", func, filename.c_str()));
    checkBase64Blocks(text, filename);
    checkYamlDirective(text, filename);
    checkBrackets(text, filename);
    checkYamlIndentation(text, filename);
    return text;
}

void openModelText(FileStorage& fs, const String& filename, const char* func)
{
    const String text = readModelText(filename, func);
    try
    {
        fs.open(text, FileStorage::READ | FileStorage::MEMORY);
    }
    catch (const cv::Exception& e)
    {
        CV_Error_(Error::StsParseError, ("%s: '%s' is not a readable model file: %s", func,
                                         filename.c_str(), e.err.c_str()));
    }
    catch (const std::exception& e) // OpenCV's parsers let some through (std::length_error)
    {
        CV_Error_(Error::StsParseError, ("%s: '%s' is not a readable model file: %s", func,
                                         filename.c_str(), e.what()));
    }
    if (!fs.isOpened())
        CV_Error_(Error::StsError, ("%s: cannot open '%s'", func, filename.c_str()));
}

static bool endsWith(const String& s, const char* suffix)
{
    const size_t n = strlen(suffix);
    return s.size() >= n && s.compare(s.size() - n, n, suffix) == 0;
}

int modelFileFormat(const String& filename)
{
    const String name = endsWith(filename, ".gz") ? filename.substr(0, filename.size() - 3)
                                                  : filename;
    return endsWith(name, ".json") ? FileStorage::FORMAT_JSON
        : endsWith(name, ".xml") ? FileStorage::FORMAT_XML : FileStorage::FORMAT_YAML;
}

void writeModelText(const String& filename, const String& text, size_t max_bytes)
{
    if (text.size() > max_bytes)
        CV_Error_(Error::StsOutOfRange,
                  ("forestmod::Detector::save: the model holds %.1f MiB of text, more than the "
                   "%.1f MiB that load() reads; '%s' is not written (most of a large model is its "
                   "forests: fewer trees, DetectorParams::forest.num_trees, or fewer classes in "
                   "one model)", text.size() / 1048576.0, max_bytes / 1048576.0,
                   filename.c_str()));
    bool ok = false;
#ifdef HAVE_FORESTMOD_ZLIB
    const bool compress = endsWith(filename, ".gz");
#else
    // without zlib the text is written as it is: load() reads a plain file whatever its name
    // (with zlib too: gzread passes plain files through)
    const bool compress = false;
    if (endsWith(filename, ".gz"))
        CV_LOG_WARNING(NULL, "forestmod::Detector::save: this build has no zlib; '"
                                 << filename << "' is written uncompressed");
#endif
    if (compress)
    {
#ifdef HAVE_FORESTMOD_ZLIB
        gzFile f = gzopen(filename.c_str(), "wb");
        if (f)
        {
            ok = true;
            for (size_t at = 0; ok && at < text.size(); at += 1 << 20)
            {
                const unsigned n = (unsigned)std::min(text.size() - at, (size_t)1 << 20);
                ok = gzwrite(f, text.data() + at, n) == (int)n;
            }
            ok = gzclose(f) == Z_OK && ok;
        }
#endif
    }
    else
    {
        std::ofstream f(filename.c_str(), std::ios::binary);
        f.write(text.data(), (std::streamsize)text.size());
        f.close();
        ok = !f.fail();
    }
    if (!ok)
        CV_Error_(Error::StsError, ("forestmod::Detector::save: cannot write '%s'",
                                    filename.c_str()));
}

void readMat(const FileNode& fn, Mat& m, int64 max_elements, const String& where)
{
    m.release();
    if (fn.empty() || fn.isNone())
        return;
    if (!fn.isMap() || !fn["sizes"].empty())
        CV_Error_(Error::StsParseError, ("forestmod model: %s: not a 2-D matrix", where.c_str()));
    const FileNode rows = fn["rows"], cols = fn["cols"], dt = fn["dt"], data = fn["data"];
    if (!isIntNodeOf(rows) || !isIntNodeOf(cols) || !dt.isString())
        CV_Error_(Error::StsParseError, ("forestmod model: %s: a matrix needs integer rows, cols "
                                         "and a dt string", where.c_str()));
    const String type = dt;
    int cn = 1;
    if (!type.empty() && type[0] >= '1' && type[0] <= '4')
        cn = type[0] - '0';
    const int64 r = (int)rows, c = (int)cols, n = r * c * cn;
    if (r < 0 || c < 0 || n > max_elements)
        CV_Error_(Error::StsParseError, ("forestmod model: %s: a %lld x %lld matrix (%d channels), "
                                         "at most %lld values expected", where.c_str(),
                                         (long long)r, (long long)c, cn,
                                         (long long)max_elements));
    if (n == 0)
        return;
    if (!data.isSeq() || (int64)data.size() != n)
        CV_Error_(Error::StsParseError, ("forestmod model: %s: a %lld x %lld matrix (%d channels) "
                                         "whose data holds %d values", where.c_str(),
                                         (long long)r, (long long)c, cn, (int)data.size()));
    fn >> m;
}

void checkPyramidGeometry(const std::vector<int>& T, int levels, const char* who, int code)
{
    if (levels < 1 || levels > MAX_PYRAMID_LEVELS)
        CV_Error_(code, ("%s: pyramid_levels is %d, expected 1..%d", who, levels,
                         (int)MAX_PYRAMID_LEVELS));
    if ((int)T.size() != levels)
        CV_Error_(code, ("%s: %d values of T for %d pyramid levels", who, (int)T.size(),
                         levels));
    for (size_t i = 0; i < T.size(); ++i)
        if (T[i] < 1 || T[i] > MAX_T)
            CV_Error_(code, ("%s: T of pyramid level %d is %d, expected 1..%d", who, (int)i,
                             T[i], (int)MAX_T));
}

void checkModality(const Ptr<linemod::Modality>& modality, int index, const char* who, int code)
{
    if (modality.empty())
        CV_Error_(code, ("%s: modality %d is null", who, index));
    const linemod::ColorGradient* g = dynamic_cast<const linemod::ColorGradient*>(modality.get());
    if (g)
    {
        if (!finite(g->weak_threshold) || g->weak_threshold < 0
            || !finite(g->strong_threshold) || g->strong_threshold < 0)
            CV_Error_(code, ("%s: modality %d (ColorGradient): weak_threshold %g / "
                             "strong_threshold %g must be finite and >= 0", who, index,
                             g->weak_threshold, g->strong_threshold));
        if (g->num_features < 1 || g->num_features > (size_t)MAX_TEMPLATE_FEATURES)
            CV_Error_(code, ("%s: modality %d (ColorGradient): num_features must be in 1..%d",
                             who, index, (int)MAX_TEMPLATE_FEATURES));
    }
    const linemod::DepthNormal* d = dynamic_cast<const linemod::DepthNormal*>(modality.get());
    if (d)
    {
        if (d->distance_threshold < 1 || d->difference_threshold < 1 || d->extract_threshold < 0)
            CV_Error_(code, ("%s: modality %d (DepthNormal): distance_threshold %d and "
                             "difference_threshold %d must be positive, extract_threshold %d "
                             ">= 0", who, index, d->distance_threshold,
                             d->difference_threshold, d->extract_threshold));
        if (d->num_features < 1 || d->num_features > (size_t)MAX_TEMPLATE_FEATURES)
            CV_Error_(code, ("%s: modality %d (DepthNormal): num_features must be in 1..%d",
                             who, index, (int)MAX_TEMPLATE_FEATURES));
    }
}

static bool isIntNode(const FileNode& n)
{
    return !n.empty() && n.isInt();
}

void checkTemplateNode(const FileNode& fn, const String& where)
{
    if (fn.empty() || !fn.isMap())
        CV_Error_(Error::StsParseError, ("forestmod model: %s: a template must be a map",
                                         where.c_str()));
    const char* ints[] = { "width", "height", "pyramid_level" };
    for (int i = 0; i < 3; ++i)
        if (!isIntNode(fn[ints[i]]))
            CV_Error_(Error::StsParseError, ("forestmod model: %s: '%s' missing or not an "
                                             "integer", where.c_str(), ints[i]));
    const FileNode features = fn["features"];
    if (features.empty() || !features.isSeq())
        CV_Error_(Error::StsParseError, ("forestmod model: %s: 'features' missing or not a "
                                         "sequence", where.c_str()));
    if (features.size() > (size_t)MAX_TEMPLATE_FEATURES)
        CV_Error_(Error::StsParseError, ("forestmod model: %s: %d features, at most %d",
                                         where.c_str(), (int)features.size(),
                                         (int)MAX_TEMPLATE_FEATURES));
    int k = 0;
    for (FileNodeIterator it = features.begin(); it != features.end(); ++it, ++k)
    {
        const FileNode f = *it;
        if (!f.isSeq() || f.size() != 3 || !f[0].isInt() || !f[1].isInt() || !f[2].isInt())
            CV_Error_(Error::StsParseError, ("forestmod model: %s: feature %d is not an [x, y, "
                                             "label] triple of integers", where.c_str(), k));
    }
}

void checkTemplatePyramid(const TemplatePyramid& tp, int M, int levels, const String& where,
                          int code)
{
    if (M < 1 || levels < 1 || (int)tp.size() != M * levels)
        CV_Error_(code, ("%s: %d templates, %d modalities x %d levels expected",
                         where.c_str(), (int)tp.size(), M, levels));
    const int w0 = tp[0].width, h0 = tp[0].height;
    if (w0 < 1 || h0 < 1 || w0 > MAX_TEMPLATE_SIZE || h0 > MAX_TEMPLATE_SIZE)
        CV_Error_(code, ("%s: template size %d x %d, expected 1..%d pixels",
                         where.c_str(), w0, h0, (int)MAX_TEMPLATE_SIZE));
    for (int l = 0; l < levels; ++l)
    {
        size_t level_features = 0;
        for (int m = 0; m < M; ++m)
        {
            const Template& t = tp[l * M + m];
            if (t.pyramid_level != l)
                CV_Error_(code, ("%s: template %d has pyramid_level %d, expected %d",
                                 where.c_str(), l * M + m, t.pyramid_level, l));
            if (t.width != (w0 >> l) || t.height != (h0 >> l))
                CV_Error_(code, ("%s: template %d (level %d) is %d x %d, the level-0 size %d x %d "
                                 ">> %d expected", where.c_str(), l * M + m, l, t.width, t.height,
                                 w0, h0, l));
            if (t.features.size() > (size_t)MAX_TEMPLATE_FEATURES)
                CV_Error_(code, ("%s: template %d has %d features, at most %d",
                                 where.c_str(), l * M + m, (int)t.features.size(),
                                 (int)MAX_TEMPLATE_FEATURES));
            for (size_t j = 0; j < t.features.size(); ++j)
            {
                const Feature& f = t.features[j];
                if (f.label < 0 || f.label > 7)
                    CV_Error_(code, ("%s: template %d, feature %d: label %d, expected 0..7",
                                     where.c_str(), l * M + m, (int)j, f.label));
                if (f.x < 0 || f.y < 0 || f.x > t.width || f.y > t.height)
                    CV_Error_(code, ("%s: template %d, feature %d at (%d, %d) lies outside the "
                                     "template (%d x %d)", where.c_str(), l * M + m, (int)j, f.x,
                                     f.y, t.width, t.height));
            }
            level_features += t.features.size();
        }
        if (level_features == 0)
            CV_Error_(code, ("%s: no feature at pyramid level %d (empty 'features')",
                             where.c_str(), l));
    }
}

void checkTemplatePose(const TemplatePose& p, const Template& t0, const String& where, int code)
{
    if (!p.valid)
        return;
    bool ok = true;
    for (int i = 0; i < 9; ++i)
        ok = ok && finite(p.R.val[i]) && std::abs(p.R.val[i]) <= 1e6 && finite(p.K.val[i])
             && std::abs(p.K.val[i]) <= 1e6;
    for (int i = 0; i < 3; ++i)
        ok = ok && finite(p.t[i]) && std::abs(p.t[i]) <= 1e9;
    if (!ok)
        CV_Error_(code, ("%s: pose R, t or K not finite (or absurdly large)", where.c_str()));
    if (!(p.t[2] > 0))
        CV_Error_(code, ("%s: pose t_z is %g mm, the object must be in front of the camera",
                         where.c_str(), p.t[2]));
    if (!(p.K(0, 0) >= 1) || !(p.K(1, 1) >= 1))
        CV_Error_(code, ("%s: pose K has focal lengths %g, %g; they must be at least 1 pixel",
                         where.c_str(), p.K(0, 0), p.K(1, 1)));
    if (p.K(2, 0) != 0 || p.K(2, 1) != 0 || p.K(2, 2) != 1)
        CV_Error_(code, ("%s: pose K's last row is (%g, %g, %g), expected (0, 0, 1)",
                         where.c_str(), p.K(2, 0), p.K(2, 1), p.K(2, 2)));
    if (p.K(1, 0) != 0)
        CV_Error_(code, ("%s: pose K(1, 0) is %g, expected 0 (a pinhole matrix [fx s cx; 0 fy "
                         "cy; 0 0 1])", where.c_str(), p.K(1, 0)));
    checkPose(p.R, p.t, where.c_str(), "pose R", code); // a rotation, as initialPose takes it
    const Vec3d c = p.K * p.t; // the object centre's projection, used by the depth modality
    if (!(std::abs(c[0]) <= 1e6 * c[2]) || !(std::abs(c[1]) <= 1e6 * c[2]))
        CV_Error_(code, ("%s: the object centre projects to (%g, %g), beyond 1e6 pixels",
                         where.c_str(), c[0] / c[2], c[1] / c[2]));
    if (p.box.width != t0.width || p.box.height != t0.height)
        CV_Error_(code, ("%s: pose box %d x %d, the template is %d x %d",
                         where.c_str(), p.box.width, p.box.height, t0.width, t0.height));
    if (p.box.x < 0 || p.box.y < 0 || p.box.x > 65535 || p.box.y > 65535)
        CV_Error_(code, ("%s: pose box at (%d, %d), expected 0..65535",
                         where.c_str(), p.box.x, p.box.y));
}

void checkDensePatch(const DensePatch& patch, const Template& top, int M, const String& where)
{
    if (patch.mask.empty() && patch.quantized.empty())
        return;
    const Size size(top.width + 1, top.height + 1);
    if (patch.mask.type() != CV_8UC1 || patch.mask.size() != size)
        CV_Error_(Error::StsParseError, ("forestmod model: %s: patch mask must be CV_8UC1 of %d "
                                         "x %d (the coarsest template's size + 1)", where.c_str(),
                                         size.width, size.height));
    if ((int)patch.quantized.size() != M)
        CV_Error_(Error::StsParseError, ("forestmod model: %s: patch has %d quantized planes, %d "
                                         "modalities", where.c_str(),
                                         (int)patch.quantized.size(), M));
    for (int m = 0; m < M; ++m)
        if (patch.quantized[m].type() != CV_8UC1 || patch.quantized[m].size() != size)
            CV_Error_(Error::StsParseError, ("forestmod model: %s: patch plane %d must be "
                                             "CV_8UC1 of the mask's size", where.c_str(), m));
}

void checkDepthSamples(const std::vector<Point3i>& s, const String& where)
{
    if (s.size() > 256)
        CV_Error_(Error::StsParseError, ("forestmod model: %s: %d depth samples, at most 256",
                                         where.c_str(), (int)s.size()));
    for (size_t i = 0; i < s.size(); ++i)
        if (s[i].x < -MAX_TEMPLATE_SIZE || s[i].x > MAX_TEMPLATE_SIZE
            || s[i].y < -MAX_TEMPLATE_SIZE || s[i].y > MAX_TEMPLATE_SIZE || s[i].z < 1
            || s[i].z > MAX_DEPTH_SAMPLE_MM)
            CV_Error_(Error::StsParseError, ("forestmod model: %s: depth sample %d (%d, %d, %d) "
                                             "out of range (|x|, |y| <= %d, z in 1..%d mm)",
                                             where.c_str(), (int)i, s[i].x, s[i].y, s[i].z,
                                             (int)MAX_TEMPLATE_SIZE, (int)MAX_DEPTH_SAMPLE_MM));
}

void checkTemplateView(const Mat& mask, int view_id, double radius, const String& class_id)
{
    const int px = countNonZero(mask);
    if (px == 0)
        CV_Error_(Error::StsError, ("forestmod::Detector::addTemplates: class '%s', view %d "
                                    "(radius %g mm): no pixel of the object is visible (a "
                                    "degenerate mesh, or an object too small for the radius?)",
                                    class_id.c_str(), view_id, radius));
    if (px == (int)mask.total())
        CV_Error_(Error::StsError, ("forestmod::Detector::addTemplates: class '%s', view %d "
                                    "(radius %g mm): the object covers the whole %d x %d frame "
                                    "(a wrong mesh scale, or a radius too small for the mesh?)",
                                    class_id.c_str(), view_id, radius, mask.cols, mask.rows));
}

void checkViewsGaveTemplates(int added, int views, const String& class_id)
{
    if (added == 0 && views > 0)
        CV_Error_(Error::StsError, ("forestmod::Detector::addTemplates: class '%s': none of the "
                                    "%d rendered views gave a template (too few features: an "
                                    "object too small for the radii, or a degenerate mesh?)",
                                    class_id.c_str(), views));
}

static bool isDanglingSymlink(const String& path)
{
#ifndef _WIN32
    struct stat st;
    return ::lstat(path.c_str(), &st) == 0 && S_ISLNK(st.st_mode)
           && ::stat(path.c_str(), &st) != 0;
#else
    (void)path;
    return false;
#endif
}

void checkOutputFile(const String& filename, bool overwrite, const char* who)
{
    if (isDanglingSymlink(filename))
        CV_Error_(Error::StsError, ("%s: '%s' is a dangling symbolic link; it is not written "
                                    "through (remove it or choose another path)", who,
                                    filename.c_str()));
    if (!overwrite && utils::fs::exists(filename))
        CV_Error_(Error::StsError, ("%s: '%s' exists (pass overwrite = true to replace it)", who,
                                    filename.c_str()));
}

} // namespace detail
} // namespace forestmod
} // namespace cv
