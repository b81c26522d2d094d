// This file is part of OpenCV project.
// It is subject to the license terms in the LICENSE file found in the top-level directory
// of this distribution and at http://opencv.org/license.html

// BOP-format dataset reader (JSON through cv::FileStorage) and BOP results CSV writer.

#include "precomp.hpp"
#include "opencv2/imgcodecs.hpp"
#include "opencv2/core/utils/filesystem.hpp"
#include "model_check.hpp"
#include "pose_refine.hpp"

#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <map>

namespace cv {
namespace forestmod {

namespace fs = cv::utils::fs;

GroundTruth::GroundTruth() : obj_id(-1), R(Matx33d::eye()), t(0, 0, 0), visib_fract(-1) {}

ModelInfo::ModelInfo() : obj_id(-1), diameter(0), symmetric(false), continuous_symmetry(false) {}

Frame::Frame() : scene_id(-1), im_id(-1), K(Matx33d::eye()), depth_scale(1.0) {}

Mat Frame::rgb() const
{
    if (rgb_path.empty())
        CV_Error_(Error::StsObjectNotFound,
                  ("Frame::rgb: scene %d image %d has no colour image", scene_id, im_id));
    Mat img = imread(rgb_path, IMREAD_COLOR);
    if (img.empty())
        CV_Error_(Error::StsError, ("Frame::rgb: cannot read '%s'", rgb_path.c_str()));
    return img;
}

Mat Frame::depth() const
{
    if (depth_path.empty())
        return Mat();
    Mat d = imread(depth_path, IMREAD_ANYDEPTH);
    if (d.empty())
        CV_Error_(Error::StsError, ("Frame::depth: cannot read '%s'", depth_path.c_str()));
    if (d.type() != CV_16UC1)
        CV_Error_(Error::StsUnsupportedFormat,
                  ("Frame::depth: '%s' is %s, expected a 16-bit single-channel PNG",
                   depth_path.c_str(), typeToString(d.type()).c_str()));
    if (!(depth_scale > 0) || !std::isfinite(depth_scale))
        CV_Error_(Error::StsBadArg, ("Frame::depth: depth_scale is %g, it must be positive and "
                                     "finite (mm per stored unit)", depth_scale));
    if (depth_scale != 1.0)
        d.convertTo(d, CV_16U, depth_scale); // rounds and saturates
    return d;
}

// ---- JSON helpers: every error names the file and the key ---------------------------------------

static FileStorage openJson(const String& path)
{
    if (!fs::exists(path))
        CV_Error_(Error::StsObjectNotFound, ("BopDataset: missing file '%s'", path.c_str()));
    FileStorage f;
    try
    {
        f.open(path, FileStorage::READ | FileStorage::FORMAT_JSON);
    }
    catch (const cv::Exception& e)
    {
        CV_Error_(Error::StsParseError,
                  ("BopDataset: '%s' is not valid JSON: %s", path.c_str(), e.err.c_str()));
    }
    if (!f.isOpened() || !f.root().isMap())
        CV_Error_(Error::StsParseError,
                  ("BopDataset: '%s' is not valid JSON (expected an object at the top)",
                   path.c_str()));
    return f;
}

static FileNode requireKey(const FileNode& parent, const String& key, const String& file,
                           const String& where)
{
    FileNode n = parent.isMap() ? parent[key] : FileNode();
    if (n.empty() || n.isNone())
        CV_Error_(Error::StsParseError,
                  ("BopDataset: '%s': %s has no key '%s'", file.c_str(), where.c_str(),
                   key.c_str()));
    return n;
}

static double toNumber(const FileNode& n, const String& key, const String& file,
                       const String& where)
{
    if (!n.isInt() && !n.isReal())
        CV_Error_(Error::StsParseError,
                  ("BopDataset: '%s': %s, key '%s' must be a number", file.c_str(), where.c_str(),
                   key.c_str()));
    return (double)n;
}

static double requireNumber(const FileNode& parent, const String& key, const String& file,
                            const String& where)
{
    return toNumber(requireKey(parent, key, file, where), key, file, where);
}

// Bounds of camera.json's and models_info.json's values: far beyond any real camera or object,
// they keep the conversions to int and the products of the evaluation finite.
static const double kMaxFocal = 1e7, kMaxSide = 1 << 16, kMaxDepthScale = 1e6, kMaxDiameter = 1e9;

// A number in (0, max]: focal lengths, image sizes, depth scales, diameters.
static double requirePositive(const FileNode& parent, const String& key, double max,
                              const String& file, const String& where)
{
    const double v = requireNumber(parent, key, file, where);
    if (!(v > 0 && v <= max))
        CV_Error_(Error::StsParseError,
                  ("BopDataset: '%s': %s, key '%s' must be in (0, %g], not %g", file.c_str(),
                   where.c_str(), key.c_str(), max, v));
    return v;
}

// An image side: a whole number of pixels in [1, kMaxSide].
static int requireSide(const FileNode& parent, const String& key, const String& file,
                       const String& where)
{
    const double v = requirePositive(parent, key, kMaxSide, file, where);
    if (v < 1 || v != std::floor(v))
        CV_Error_(Error::StsParseError,
                  ("BopDataset: '%s': %s, key '%s' must be a whole number of pixels, not %g",
                   file.c_str(), where.c_str(), key.c_str(), v));
    return (int)v;
}

// A pinhole camera matrix (what the detector and the pose stage accept), `key` its key or keys.
static void checkCameraMatrix(const Matx33d& K, const String& file, const String& where,
                              const String& key)
{
    const String place = cv::format("BopDataset: '%s': %s", file.c_str(), where.c_str());
    try
    {
        detail::checkIntrinsics(K, place.c_str(), key.c_str());
    }
    catch (const cv::Exception& e)
    {
        CV_Error(Error::StsParseError, e.err); // a file's content, not an argument
    }
}

static std::vector<double> requireNumbers(const FileNode& parent, const String& key, size_t count,
                                          const String& file, const String& where)
{
    FileNode n = requireKey(parent, key, file, where);
    if (!n.isSeq() || n.size() != count)
        CV_Error_(Error::StsParseError,
                  ("BopDataset: '%s': %s, key '%s' must be a list of %d numbers", file.c_str(),
                   where.c_str(), key.c_str(), (int)count));
    std::vector<double> v;
    for (size_t i = 0; i < count; ++i)
        v.push_back(toNumber(n[(int)i], key, file, where));
    return v;
}

static int parseId(const String& s, const String& file)
{
    char* end = 0;
    const long v = std::strtol(s.c_str(), &end, 10);
    if (s.empty() || *end != 0 || v < 0 || v > 100000000L)
        CV_Error_(Error::StsParseError,
                  ("BopDataset: '%s': key '%s' is not a non-negative integer id", file.c_str(),
                   s.c_str()));
    return (int)v;
}

static String idName(int id)
{
    return format("%06d", id);
}

static bool nonEmptySeq(const FileNode& n)
{
    return !n.empty() && n.isSeq() && n.size() > 0;
}

// ---- BopDataset ---------------------------------------------------------------------------------

BopDataset::BopDataset() : K_(Matx33d::eye()), depth_scale_(1.0) {}

std::vector<int> BopDataset::linemodSymmetricIds()
{
    std::vector<int> ids;
    ids.push_back(10); // eggbox
    ids.push_back(11); // glue
    return ids;
}

BopDataset BopDataset::open(const String& root, const String& split,
                            const std::vector<int>& symmetric_ids)
{
    if (root.empty() || !fs::isDirectory(root))
        CV_Error_(Error::StsObjectNotFound,
                  ("BopDataset::open: '%s' is not a folder", root.c_str()));
    BopDataset ds;
    ds.root_ = root;
    ds.split_ = split;

    const String cam_file = fs::join(root, "camera.json");
    {
        FileStorage f = openJson(cam_file);
        const FileNode r = f.root();
        const String w = "the top object";
        const double fx = requirePositive(r, "fx", kMaxFocal, cam_file, w);
        const double fy = requirePositive(r, "fy", kMaxFocal, cam_file, w);
        const double cx = requireNumber(r, "cx", cam_file, w);
        const double cy = requireNumber(r, "cy", cam_file, w);
        ds.K_ = Matx33d(fx, 0, cx, 0, fy, cy, 0, 0, 1);
        checkCameraMatrix(ds.K_, cam_file, w, "fx, fy, cx, cy");
        ds.size_ = Size(requireSide(r, "width", cam_file, w),
                        requireSide(r, "height", cam_file, w));
        if (!r["depth_scale"].empty())
            ds.depth_scale_ = requirePositive(r, "depth_scale", kMaxDepthScale, cam_file, w);
    }

    const String info_file = fs::join(fs::join(root, "models"), "models_info.json");
    {
        FileStorage f = openJson(info_file);
        const FileNode r = f.root();
        for (FileNodeIterator it = r.begin(); it != r.end(); ++it)
        {
            const FileNode e = *it;
            ModelInfo m;
            m.obj_id = parseId(e.name(), info_file);
            const String w = "object '" + e.name() + "'";
            if (!e.isMap())
                CV_Error_(Error::StsParseError, ("BopDataset: '%s': %s must be an object",
                                                 info_file.c_str(), w.c_str()));
            m.diameter = requirePositive(e, "diameter", kMaxDiameter, info_file, w);
            m.min = Point3d(requireNumber(e, "min_x", info_file, w),
                            requireNumber(e, "min_y", info_file, w),
                            requireNumber(e, "min_z", info_file, w));
            m.size = Point3d(requireNumber(e, "size_x", info_file, w),
                             requireNumber(e, "size_y", info_file, w),
                             requireNumber(e, "size_z", info_file, w));
            const FileNode sd = e["symmetries_discrete"];
            if (nonEmptySeq(sd))
                for (int k = 0; k < (int)sd.size(); ++k)
                {
                    const String wk = format("%s, symmetries_discrete[%d]", w.c_str(), k);
                    FileNode one = sd[k];
                    if (!one.isSeq() || one.size() != 16)
                        CV_Error_(Error::StsParseError,
                                  ("BopDataset: '%s': %s must be a list of 16 numbers",
                                   info_file.c_str(), wk.c_str()));
                    Matx44d T;
                    for (int j = 0; j < 16; ++j)
                        T.val[j] = toNumber(one[j], "symmetries_discrete", info_file, wk);
                    m.symmetries_discrete.push_back(T);
                }
            m.continuous_symmetry = nonEmptySeq(e["symmetries_continuous"]);
            m.symmetric = !m.symmetries_discrete.empty() || m.continuous_symmetry
                          || std::find(symmetric_ids.begin(), symmetric_ids.end(), m.obj_id)
                                 != symmetric_ids.end();
            m.mesh_path = ds.modelPath(m.obj_id);
            ds.models_.push_back(m);
        }
        struct ById
        {
            bool operator()(const ModelInfo& a, const ModelInfo& b) const
            {
                return a.obj_id < b.obj_id;
            }
        };
        std::sort(ds.models_.begin(), ds.models_.end(), ById());
    }
    return ds;
}

String BopDataset::modelPath(int obj_id) const
{
    return fs::join(fs::join(root_, "models"), "obj_" + idName(obj_id) + ".ply");
}

std::vector<ModelInfo> BopDataset::models() const
{
    return models_;
}

ModelInfo BopDataset::model(int obj_id) const
{
    for (size_t i = 0; i < models_.size(); ++i)
        if (models_[i].obj_id == obj_id)
            return models_[i];
    CV_Error_(Error::StsObjectNotFound,
              ("BopDataset::model: object %d is not in '%s'", obj_id,
               fs::join(fs::join(root_, "models"), "models_info.json").c_str()));
}

void BopDataset::setSymmetric(int obj_id, bool symmetric)
{
    for (size_t i = 0; i < models_.size(); ++i)
        if (models_[i].obj_id == obj_id)
        {
            models_[i].symmetric = symmetric;
            return;
        }
    CV_Error_(Error::StsObjectNotFound,
              ("BopDataset::setSymmetric: object %d is not in models_info.json", obj_id));
}

std::vector<int> BopDataset::sceneIds() const
{
    const String dir = fs::join(root_, split_);
    if (!fs::isDirectory(dir))
        CV_Error_(Error::StsObjectNotFound,
                  ("BopDataset::sceneIds: no split folder '%s'", dir.c_str()));
    std::vector<String> entries;
    fs::glob_relative(dir, "", entries, false, true);
    std::vector<int> ids;
    for (size_t i = 0; i < entries.size(); ++i)
    {
        const String& e = entries[i];
        if (e.empty() || e.find_first_not_of("0123456789") != String::npos)
            continue;
        const String sd = fs::join(dir, e);
        if (fs::isDirectory(sd)
            && (fs::exists(fs::join(sd, "scene_gt.json"))
                || fs::exists(fs::join(sd, "scene_camera.json"))))
            ids.push_back(std::atoi(e.c_str()));
    }
    std::sort(ids.begin(), ids.end());
    return ids;
}

static String findImage(const String& scene_dir, const char* const* folders, int im_id)
{
    static const char* const exts[] = { ".png", ".jpg", ".tif" };
    for (int f = 0; folders[f]; ++f)
        for (int e = 0; e < 3; ++e)
        {
            const String p = fs::join(fs::join(scene_dir, folders[f]), idName(im_id) + exts[e]);
            if (fs::exists(p))
                return p;
        }
    return String();
}

std::vector<Frame> BopDataset::frames(int scene_id) const
{
    const String scene_dir = fs::join(fs::join(root_, split_), idName(scene_id));
    if (!fs::isDirectory(scene_dir))
        CV_Error_(Error::StsObjectNotFound,
                  ("BopDataset::frames: no scene folder '%s'", scene_dir.c_str()));

    std::map<int, Frame> frames;
    const String cam_file = fs::join(scene_dir, "scene_camera.json");
    {
        FileStorage f = openJson(cam_file);
        const FileNode r = f.root();
        for (FileNodeIterator it = r.begin(); it != r.end(); ++it)
        {
            const FileNode e = *it;
            Frame fr;
            fr.scene_id = scene_id;
            fr.im_id = parseId(e.name(), cam_file);
            const String w = "image '" + e.name() + "'";
            const std::vector<double> k = requireNumbers(e, "cam_K", 9, cam_file, w);
            fr.K = Matx33d(&k[0]);
            checkCameraMatrix(fr.K, cam_file, w, "cam_K");
            fr.depth_scale = e["depth_scale"].empty()
                                 ? depth_scale_
                                 : requirePositive(e, "depth_scale", kMaxDepthScale, cam_file, w);
            frames[fr.im_id] = fr;
        }
    }

    const String gt_file = fs::join(scene_dir, "scene_gt.json");
    const String info_file = fs::join(scene_dir, "scene_gt_info.json");
    const bool has_info = fs::exists(info_file);
    {
        FileStorage f = openJson(gt_file);
        FileStorage fi;
        if (has_info)
            fi = openJson(info_file);
        const FileNode r = f.root();
        for (FileNodeIterator it = r.begin(); it != r.end(); ++it)
        {
            const FileNode e = *it;
            const int im_id = parseId(e.name(), gt_file);
            const String w = "image '" + e.name() + "'";
            std::map<int, Frame>::iterator fr = frames.find(im_id);
            if (fr == frames.end())
                CV_Error_(Error::StsParseError,
                          ("BopDataset: '%s': %s is not in '%s'", gt_file.c_str(), w.c_str(),
                           cam_file.c_str()));
            if (!e.isSeq())
                CV_Error_(Error::StsParseError, ("BopDataset: '%s': %s must be a list",
                                                 gt_file.c_str(), w.c_str()));
            FileNode info;
            if (has_info)
            {
                info = requireKey(fi.root(), e.name(), info_file, "the top object");
                if (!info.isSeq() || info.size() != e.size())
                    CV_Error_(Error::StsParseError,
                              ("BopDataset: '%s': %s must be a list of %d entries, as in '%s'",
                               info_file.c_str(), w.c_str(), (int)e.size(), gt_file.c_str()));
            }
            for (int i = 0; i < (int)e.size(); ++i)
            {
                const FileNode g = e[i];
                const String wi = format("%s, instance %d", w.c_str(), i);
                GroundTruth gt;
                gt.obj_id = (int)requireNumber(g, "obj_id", gt_file, wi);
                const std::vector<double> R = requireNumbers(g, "cam_R_m2c", 9, gt_file, wi);
                const std::vector<double> t = requireNumbers(g, "cam_t_m2c", 3, gt_file, wi);
                gt.R = Matx33d(&R[0]);
                gt.t = Vec3d(t[0], t[1], t[2]);
                if (has_info)
                {
                    const FileNode gi = info[i];
                    const std::vector<double> bo = requireNumbers(gi, "bbox_obj", 4, info_file, wi);
                    const std::vector<double> bv =
                        requireNumbers(gi, "bbox_visib", 4, info_file, wi);
                    gt.bbox_obj = Rect((int)bo[0], (int)bo[1], (int)bo[2], (int)bo[3]);
                    gt.bbox_visib = Rect((int)bv[0], (int)bv[1], (int)bv[2], (int)bv[3]);
                    gt.visib_fract = requireNumber(gi, "visib_fract", info_file, wi);
                }
                fr->second.gt.push_back(gt);
            }
        }
    }

    static const char* const rgb_folders[] = { "rgb", "gray", 0 };
    static const char* const depth_folders[] = { "depth", 0 };
    std::vector<Frame> out;
    out.reserve(frames.size());
    for (std::map<int, Frame>::iterator it = frames.begin(); it != frames.end(); ++it)
    {
        Frame& fr = it->second;
        fr.rgb_path = findImage(scene_dir, rgb_folders, fr.im_id);
        fr.depth_path = findImage(scene_dir, depth_folders, fr.im_id);
        out.push_back(fr);
    }
    return out;
}

// ---- BopResultWriter ----------------------------------------------------------------------------

struct BopResultWriter::Impl
{
    std::ofstream out;
};

BopResultWriter::BopResultWriter(const String& path, bool overwrite) : path_(path)
{
    if (path.empty())
        CV_Error(Error::StsBadArg, "BopResultWriter: empty path");
    // neither an existing file without overwrite nor through a dangling symbolic link
    detail::checkOutputFile(path, overwrite, "BopResultWriter");
    impl_ = makePtr<Impl>();
    impl_->out.open(path.c_str(), std::ios::out | std::ios::trunc);
    if (!impl_->out)
        CV_Error_(Error::StsError, ("BopResultWriter: cannot write '%s'", path.c_str()));
    impl_->out << "scene_id,im_id,obj_id,score,R,t,time\n";
    impl_->out.flush();
}

BopResultWriter::~BopResultWriter()
{
    if (impl_ && impl_->out.is_open())
        impl_->out.close();
}

void BopResultWriter::write(int scene_id, int im_id, int obj_id, double score, const Matx33d& R,
                            const Vec3d& t, double time_s)
{
    if (!impl_ || !impl_->out.is_open())
        CV_Error_(Error::StsError, ("BopResultWriter: '%s' is closed", path_.c_str()));
    bool finite = std::isfinite(score) && std::isfinite(time_s);
    for (int i = 0; i < 9; ++i)
        finite = finite && std::isfinite(R.val[i]);
    for (int i = 0; i < 3; ++i)
        finite = finite && std::isfinite(t[i]);
    if (!finite) // a BOP results file must parse: the line is not written
        CV_Error_(Error::StsBadArg, ("BopResultWriter: scene %d, image %d, object %d: score, R, t "
                                     "and time must be finite", scene_id, im_id, obj_id));
    String line = format("%d,%d,%d,%.9g,", scene_id, im_id, obj_id, score);
    for (int i = 0; i < 9; ++i)
        line += format(i ? " %.12g" : "%.12g", R.val[i]);
    line += format(",%.9g %.9g %.9g,%.6g\n", t[0], t[1], t[2], time_s);
    impl_->out << line;
    impl_->out.flush();
    if (!impl_->out)
        CV_Error_(Error::StsError, ("BopResultWriter: writing '%s' failed", path_.c_str()));
}

void BopResultWriter::close()
{
    if (impl_ && impl_->out.is_open())
        impl_->out.close();
}

} // namespace forestmod
} // namespace cv
