// This file is part of OpenCV project.
// It is subject to the license terms in the LICENSE file found in the top-level directory
// of this distribution and at http://opencv.org/license.html

// Persistence of forestmod::Detector: parameters, classes (cv::linemod's layout plus each
// template's record), whole model files with the trained forests.

#include "precomp.hpp"
#include "detector_impl.hpp"
#include "params_io.hpp"
#include "model_check.hpp"

#include "opencv2/core/utils/filesystem.hpp"
#include "opencv2/core/utils/logger.hpp"

namespace cv {
namespace forestmod {

using detail::TemplatePyramid;
using detail::TemplateRecord;
using linemod::Modality;

static const int MODEL_FORMAT_VERSION = 1;

DetectorParams::DetectorParams()
    : grid_size(12), dominant_window(3), group_size_ratio(1.3f), group_templates(true),
      auto_depth_leaf_samples(8.f), use_forest(true), location_step(0), min_window_labels(0.5f),
      depth_range_tolerance(0.25f), breadth_first(true), chunk_size(16), alpha(0.5f),
      max_survivors(2),
      exhaustive_ratio(0.01f), descent_cost(2.f), min_forest_templates(64), search_per_class(false),
      depth_samples(63), depth_tolerance(5), nms_iou(0.5f)
{
    forest.max_depth = 0; // chosen at train() per search group (auto_depth_leaf_samples)
    forest.rejector_coverage = 0.5f;
    forest.rejector_dims = 64;
}

void DetectorParams::read(const FileNode& fn)
{
    if (!fn["forest"].empty())
        forest.read(fn["forest"]);
    detail::readField(fn, "use_forest", use_forest);
    detail::readField(fn, "breadth_first", breadth_first);
    detail::readField(fn, "chunk_size", chunk_size);
    detail::readField(fn, "alpha", alpha);
    detail::readField(fn, "grid_size", grid_size);
    detail::readField(fn, "location_step", location_step);
    detail::readField(fn, "nms_iou", nms_iou);
    detail::readField(fn, "max_survivors", max_survivors);
    detail::readField(fn, "exhaustive_ratio", exhaustive_ratio);
    detail::readField(fn, "descent_cost", descent_cost);
    detail::readField(fn, "min_forest_templates", min_forest_templates);
    detail::readField(fn, "search_per_class", search_per_class);
    detail::readField(fn, "depth_samples", depth_samples);
    detail::readField(fn, "depth_tolerance", depth_tolerance);
    detail::readField(fn, "min_window_labels", min_window_labels);
    // files written before depth_range_tolerance had depth_range_margin (mm, 0: off, the
    // default): they keep matching as they did when it was off
    int margin = 0;
    if (fn["depth_range_tolerance"].empty() && !fn["depth_range_margin"].empty())
    {
        detail::readField(fn, "depth_range_margin", margin);
        if (margin == 0)
            depth_range_tolerance = -1.f;
    }
    detail::readField(fn, "depth_range_tolerance", depth_range_tolerance);
    detail::readField(fn, "dominant_window", dominant_window);
    detail::readField(fn, "group_size_ratio", group_size_ratio);
    detail::readField(fn, "auto_depth_leaf_samples", auto_depth_leaf_samples);
    detail::readField(fn, "group_templates", group_templates);
}

void DetectorParams::write(FileStorage& fs) const
{
    fs << "forest" << "{";
    forest.write(fs);
    fs << "}";
    fs << "use_forest" << (int)use_forest << "breadth_first" << (int)breadth_first;
    fs << "chunk_size" << chunk_size << "alpha" << alpha << "grid_size" << grid_size;
    fs << "location_step" << location_step << "nms_iou" << nms_iou;
    fs << "max_survivors" << max_survivors << "depth_samples" << depth_samples;
    fs << "exhaustive_ratio" << exhaustive_ratio << "min_forest_templates" << min_forest_templates;
    fs << "descent_cost" << descent_cost << "search_per_class" << (int)search_per_class;
    fs << "depth_tolerance" << depth_tolerance << "min_window_labels" << min_window_labels;
    fs << "depth_range_tolerance" << depth_range_tolerance << "dominant_window" << dominant_window;
    fs << "group_size_ratio" << group_size_ratio;
    fs << "auto_depth_leaf_samples" << auto_depth_leaf_samples;
    fs << "group_templates" << (int)group_templates;
}

namespace detail {

void checkParams(const DetectorParams& p)
{
    checkDetectorParams(p); // the ranges live in model_check.cpp with the model limits
}

} // namespace detail

Ptr<Modality> createModality(const FileNode& fn)
{
    if (fn.empty() || !fn.isMap())
        CV_Error(Error::StsParseError, "forestmod::createModality: expected a modality map node");
    const String type = fn["type"];
    if (type == "ColorHue")
    {
        Ptr<ColorHue> hue = ColorHue::create();
        hue->read(fn);
        return hue;
    }
    if (type == "ColorGradient" || type == "DepthNormal")
        return Modality::create(fn);
    CV_Error_(Error::StsParseError, ("forestmod::createModality: unknown modality type '%s'",
                                     type.c_str()));
}

// Parameters of a model file, with the defaults of the version that wrote it for keys it did not
// know: written before search groups existed, one window and one forest for all classes; before
// template-level groups, whole classes were grouped.
static DetectorParams readModelParams(const FileNode& fn)
{
    DetectorParams p;
    if (fn.empty())
        return p;
    p.read(fn);
    if (fn["group_size_ratio"].empty())
        p.group_size_ratio = 0.f;
    if (fn["group_templates"].empty())
        p.group_templates = false;
    if (fn["min_forest_templates"].empty())
        p.min_forest_templates = 0; // written before it: every group decided by the sample
    if (fn["descent_cost"].empty())
        p.descent_cost = 0.f; // written before it: the sample counted the pairs only
    return p;
}

void Detector::read(const FileNode& fn)
{
    if (fn.empty() || !fn.isMap())
        CV_Error(Error::StsParseError, "forestmod::Detector::read: expected a map node");
    FileNode mods = fn["modalities"];
    if (mods.empty() || !mods.isSeq() || mods.size() == 0)
        CV_Error(Error::StsParseError, "forestmod::Detector::read: no 'modalities' sequence");
    std::vector<Ptr<Modality> > new_modalities;
    for (FileNodeIterator it = mods.begin(); it != mods.end(); ++it)
        new_modalities.push_back(createModality(*it));
    std::vector<int> T;
    fn["T"] >> T;
    const int levels = (int)fn["pyramid_levels"];
    if (T.empty() || (int)T.size() != levels)
        CV_Error(Error::StsParseError, "forestmod::Detector::read: 'pyramid_levels' and 'T' "
                                       "are missing or disagree");
    detail::checkPyramidGeometry(T, levels);
    for (size_t i = 0; i < new_modalities.size(); ++i)
        detail::checkModality(new_modalities[i], (int)i);
    const DetectorParams p = readModelParams(fn["forestmod_params"]);
    detail::checkParams(p);
    AutoLock lock(impl_->mutex);
    modalities = new_modalities;
    pyramid_levels = levels;
    T_at_level = T;
    impl_->roles = detail::ModalityRoles::of(modalities);
    impl_->store.clear(class_templates);
    impl_->params = p;
    impl_->index.clear();
}

void Detector::write(FileStorage& fs) const
{
    if (modalities.empty())
        CV_Error(Error::StsError, "forestmod::Detector::write: the detector has no modalities "
                                  "(default-constructed and never read or loaded?)");
    fs << "pyramid_levels" << pyramid_levels;
    fs << "T" << T_at_level;
    fs << "modalities" << "[";
    for (size_t i = 0; i < modalities.size(); ++i)
    {
        fs << "{";
        modalities[i]->write(fs);
        fs << "}";
    }
    fs << "]";
    fs << "forestmod_params" << "{";
    impl_->params.write(fs);
    fs << "}";
}

static void writePose(FileStorage& fs, const TemplatePose& p)
{
    fs << "{";
    fs << "valid" << (int)p.valid;
    if (p.valid)
    {
        fs << "R" << Mat(p.R);
        fs << "t" << Mat(p.t);
        fs << "K" << Mat(p.K);
        fs << "box" << p.box;
    }
    fs << "}";
}

static TemplatePose readPose(const FileNode& fn)
{
    TemplatePose p;
    p.valid = !fn["valid"].empty() && (int)fn["valid"] != 0;
    if (p.valid)
    {
        Mat R, t, K;
        detail::readMat(fn["R"], R, 9, "template pose R");
        detail::readMat(fn["t"], t, 3, "template pose t");
        detail::readMat(fn["K"], K, 9, "template pose K");
        if (R.total() != 9 || t.total() != 3 || K.total() != 9)
            CV_Error(Error::StsParseError, "forestmod::Detector: corrupt template pose "
                                           "(R 3x3, t 3x1, K 3x3 expected)");
        R.convertTo(R, CV_64F);
        t.convertTo(t, CV_64F);
        K.convertTo(K, CV_64F);
        p.R = Matx33d(R.reshape(1, 3));
        p.t = Vec3d(t.reshape(1, 3));
        p.K = Matx33d(K.reshape(1, 3));
        fn["box"] >> p.box;
    }
    return p;
}

// A dense patch is the coarsest template's size + 1, one quantized plane per modality.
static void readPatch(const FileNode& fn, size_t num_modalities, const linemod::Template& coarsest,
                      const String& where, detail::DensePatch& patch)
{
    const int64 patch_size = (int64)(coarsest.width + 1) * (coarsest.height + 1);
    detail::readMat(fn["mask"], patch.mask, patch_size, "template patch mask");
    FileNode q = fn["quantized"];
    for (FileNodeIterator qi = q.begin(); qi != q.end(); ++qi)
    {
        Mat m;
        detail::readMat(*qi, m, patch_size, "template patch");
        patch.quantized.push_back(m);
    }
    if (!patch.mask.empty()
        && (patch.quantized.size() != num_modalities || patch.mask.type() != CV_8UC1))
        CV_Error(Error::StsParseError, "forestmod::Detector::readClass: corrupt template patch");
    detail::checkDensePatch(patch, coarsest, (int)num_modalities, where);
}

static void readDepthSamples(const FileNode& fn, const String& where,
                             std::vector<Point3i>& depth)
{
    Mat m;
    detail::readMat(fn, m, 256 * 3, "template depth samples");
    if (m.empty())
        return;
    if (m.type() != CV_32S || m.cols != 3 || m.rows > 256)
        CV_Error(Error::StsParseError, "forestmod::Detector::readClass: corrupt depth samples "
                                       "(CV_32S, 3 columns, at most 256 rows)");
    for (int j = 0; j < m.rows; ++j)
        depth.push_back(Point3i(m.at<int>(j, 0), m.at<int>(j, 1), m.at<int>(j, 2)));
    detail::checkDepthSamples(depth, where);
}

// The optional per-template sequences of a class (forestmod_poses, _patches, _depth): one entry
// per template when present.
static void readRecords(const FileNode& fn, size_t num_modalities, const String& class_id,
                        const std::vector<TemplatePyramid>& tps,
                        std::vector<TemplateRecord>& records)
{
    const char* keys[] = { "forestmod_poses", "forestmod_patches", "forestmod_depth" };
    for (int k = 0; k < 3; ++k)
    {
        FileNode seq = fn[keys[k]];
        if (seq.empty())
            continue;
        if (!seq.isSeq() || seq.size() != records.size())
            CV_Error_(Error::StsParseError, ("forestmod::Detector::readClass: '%s' does not hold "
                                             "one entry per template (corrupt file?)", keys[k]));
        size_t i = 0;
        for (FileNodeIterator it = seq.begin(); it != seq.end(); ++it, ++i)
        {
            const String where = cv::format("class '%s', template %d", class_id.c_str(), (int)i);
            if (k == 0)
            {
                records[i].pose = readPose(*it);
                detail::checkTemplatePose(records[i].pose, tps[i][0],
                                          "forestmod model: " + where);
            }
            else if (k == 1)
                readPatch(*it, num_modalities, tps[i].back(), where, records[i].patch);
            else
                readDepthSamples(*it, where, records[i].depth);
        }
    }
}

// The class header: same modalities and pyramid as this detector.
static void checkClassHeader(const FileNode& fn, const std::vector<Ptr<Modality> >& modalities,
                             int pyramid_levels)
{
    FileNode mod_fn = fn["modalities"];
    if (mod_fn.empty() || (int)mod_fn.size() != (int)modalities.size())
        CV_Error(Error::StsParseError, "forestmod::Detector::readClass: the class was written "
                                       "with another number of modalities");
    int i = 0;
    for (FileNodeIterator it = mod_fn.begin(); it != mod_fn.end(); ++it, ++i)
        if ((String)(*it) != modalities[i]->name())
            CV_Error_(Error::StsParseError,
                      ("forestmod::Detector::readClass: modality %d is '%s' in the file, '%s' "
                       "in the detector", i, ((String)(*it)).c_str(),
                       modalities[i]->name().c_str()));
    if ((int)fn["pyramid_levels"] != pyramid_levels)
        CV_Error(Error::StsParseError, "forestmod::Detector::readClass: the class was written "
                                       "with another number of pyramid levels");
}

static void readPyramids(const FileNode& fn, int num_modalities, int pyramid_levels,
                         const String& class_id, std::vector<TemplatePyramid>& tps)
{
    FileNode tps_fn = fn["template_pyramids"];
    if (tps_fn.empty() || !tps_fn.isSeq())
        CV_Error(Error::StsParseError, "forestmod::Detector::readClass: no template_pyramids");
    const int expected = num_modalities * pyramid_levels;
    int expected_id = 0;
    for (FileNodeIterator it = tps_fn.begin(); it != tps_fn.end(); ++it, ++expected_id)
    {
        if ((int)(*it)["template_id"] != expected_id)
            CV_Error(Error::StsParseError, "forestmod::Detector::readClass: template ids out of "
                                           "order (corrupt file?)");
        FileNode templates_fn = (*it)["templates"];
        if ((int)templates_fn.size() != expected)
            CV_Error(Error::StsParseError, "forestmod::Detector::readClass: wrong number of "
                                           "templates in a pyramid (corrupt file?)");
        const String where = cv::format("class '%s', template %d", class_id.c_str(), expected_id);
        TemplatePyramid tp(expected);
        int k = 0;
        for (FileNodeIterator t_it = templates_fn.begin(); t_it != templates_fn.end(); ++t_it, ++k)
        {
            detail::checkTemplateNode(*t_it, where);
            tp[k].read(*t_it);
        }
        detail::checkTemplatePyramid(tp, num_modalities, pyramid_levels,
                                     "forestmod model: " + where);
        tps.push_back(tp);
    }
}

String Detector::readClass(const FileNode& fn, const String& class_id_override)
{
    if (fn.empty() || !fn.isMap())
        CV_Error(Error::StsParseError, "forestmod::Detector::readClass: expected a map node");
    // same layout as cv::linemod::Detector::writeClass, plus the optional records
    checkClassHeader(fn, modalities, pyramid_levels);
    const String class_id = class_id_override.empty() ? (String)fn["class_id"]
                                                       : class_id_override;
    if (class_id.empty())
        CV_Error(Error::StsParseError, "forestmod::Detector::readClass: no class_id");
    std::vector<TemplatePyramid> tps;
    readPyramids(fn, static_cast<int>(modalities.size()), pyramid_levels, class_id, tps);
    std::vector<TemplateRecord> records(tps.size());
    readRecords(fn, modalities.size(), class_id, tps, records);
    AutoLock lock(impl_->mutex);
    impl_->store.setClass(class_templates, class_id, tps, records);
    impl_->index.clear();
    return class_id;
}

static void writeRecords(FileStorage& fs, const detail::TemplateStore& store,
                         const String& class_id, size_t n)
{
    fs << "forestmod_poses" << "[";
    for (size_t i = 0; i < n; ++i)
        writePose(fs, store.get(class_id, (int)i).pose);
    fs << "]";
    fs << "forestmod_patches" << "[";
    for (size_t i = 0; i < n; ++i)
    {
        const detail::DensePatch& patch = store.get(class_id, (int)i).patch;
        fs << "{";
        if (!patch.mask.empty())
        {
            fs << "mask" << patch.mask;
            fs << "quantized" << "[";
            for (size_t m = 0; m < patch.quantized.size(); ++m)
                fs << patch.quantized[m];
            fs << "]";
        }
        fs << "}";
    }
    fs << "]";
    fs << "forestmod_depth" << "[";
    for (size_t i = 0; i < n; ++i)
    {
        const std::vector<Point3i>& depth = store.get(class_id, (int)i).depth;
        fs << (depth.empty() ? Mat() : Mat(depth).reshape(1).clone());
    }
    fs << "]";
}

void Detector::writeClass(const String& class_id, FileStorage& fs) const
{
    std::map<String, std::vector<TemplatePyramid> >::const_iterator it
        = class_templates.find(class_id);
    if (it == class_templates.end())
        CV_Error_(Error::StsBadArg, ("forestmod::Detector::writeClass: no class '%s'",
                                     class_id.c_str()));
    const std::vector<TemplatePyramid>& tps = it->second;
    fs << "class_id" << it->first;
    fs << "modalities" << "[:";
    for (size_t i = 0; i < modalities.size(); ++i)
        fs << modalities[i]->name();
    fs << "]";
    fs << "pyramid_levels" << pyramid_levels;
    fs << "template_pyramids" << "[";
    for (size_t i = 0; i < tps.size(); ++i)
    {
        fs << "{";
        fs << "template_id" << int(i);
        fs << "templates" << "[";
        for (size_t j = 0; j < tps[i].size(); ++j)
        {
            fs << "{";
            tps[i][j].write(fs);
            fs << "}";
        }
        fs << "]";
        fs << "}";
    }
    fs << "]";
    writeRecords(fs, impl_->store, class_id, tps.size());
}

// Refuses a class files' format other than one %s (the class id) and %% (cv::linemod hands the
// format to sprintf, where another conversion reads an argument that is not there).
static void checkClassFormat(const String& format, const char* who)
{
    int ids = 0;
    bool ok = true;
    for (size_t i = 0; i < format.size() && ok; ++i)
        if (format[i] == '%')
        {
            const char next = i + 1 < format.size() ? format[i + 1] : 0;
            ids += next == 's';
            ok = next == 's' || next == '%';
            ++i;
        }
    if (!ok || ids != 1)
        CV_Error_(Error::StsBadArg, ("%s: the format '%s' must hold one %%s (the class id) and no "
                                     "other conversion (%%%% for a percent sign)", who,
                                     format.c_str()));
}

void Detector::readClasses(const std::vector<String>& class_ids, const String& format)
{
    checkClassFormat(format, "forestmod::Detector::readClasses");
    for (size_t i = 0; i < class_ids.size(); ++i)
    {
        const String filename = cv::format(format.c_str(), class_ids[i].c_str());
        FileStorage fs;
        detail::openModelText(fs, filename, "forestmod::Detector::readClasses");
        try
        {
            readClass(fs.root());
        }
        catch (const cv::Exception&)
        {
            throw;
        }
        catch (const std::exception& e)
        {
            CV_Error_(Error::StsParseError, ("forestmod::Detector::readClasses: '%s' is not a "
                                             "readable class file: %s", filename.c_str(),
                                             e.what()));
        }
    }
}

void Detector::writeClasses(const String& format) const
{
    checkClassFormat(format, "forestmod::Detector::writeClasses");
    for (std::map<String, std::vector<TemplatePyramid> >::const_iterator it = class_templates.begin();
         it != class_templates.end(); ++it)
    {
        const String filename = cv::format(format.c_str(), it->first.c_str());
        detail::checkOutputFile(filename, true, "forestmod::Detector::writeClasses");
        FileStorage fs(filename, FileStorage::WRITE);
        if (!fs.isOpened())
            CV_Error_(Error::StsError, ("forestmod::Detector::writeClasses: cannot write '%s'",
                                        filename.c_str()));
        writeClass(it->first, fs);
    }
}

void Detector::save(const String& filename, bool overwrite) const
{
    detail::checkOutputFile(filename, overwrite, "forestmod::Detector::save");
    // written in memory first: a model longer than load() reads is refused, not written
    FileStorage fs(filename, FileStorage::WRITE | FileStorage::MEMORY | FileStorage::BASE64
                                 | detail::modelFileFormat(filename));
    CV_Assert(fs.isOpened());
    fs << "forestmod_model_version" << MODEL_FORMAT_VERSION;
    fs << "detector" << "{";
    write(fs);
    fs << "}";
    fs << "classes" << "[";
    typedef std::map<String, std::vector<TemplatePyramid> >::const_iterator ClassIt;
    for (ClassIt it = class_templates.begin(); it != class_templates.end(); ++it)
    {
        fs << "{";
        writeClass(it->first, fs);
        fs << "}";
    }
    fs << "]";
    const detail::SearchIndex& index = impl_->index;
    if (index.trained && index.groups.size() == 1)
    {
        fs << "forest" << "{"; // one search group: the layout of files without groups
        index.groups[0].forest->write(fs);
        fs << "}";
    }
    else if (index.trained && !index.groups.empty())
    {
        fs << "forests" << "[";
        for (size_t g = 0; g < index.groups.size(); ++g)
        {
            fs << "{";
            index.groups[g].forest->write(fs);
            fs << "}";
        }
        fs << "]";
    }
    detail::writeModelText(filename, fs.releaseAndGetString());
}

static void openModel(FileStorage& fs, const String& filename)
{
    detail::openModelText(fs, filename, "forestmod::Detector::load"); // bounded, model_check.hpp
    FileNode v = fs["forestmod_model_version"];
    if (v.empty())
        CV_Error_(Error::StsParseError, ("forestmod::Detector::load: '%s' is not a forestmod "
                                         "model (no forestmod_model_version)", filename.c_str()));
    if ((int)v != MODEL_FORMAT_VERSION)
        CV_Error_(Error::StsParseError, ("forestmod::Detector::load: '%s' has model format %d, "
                                         "this build reads %d", filename.c_str(), (int)v,
                                         MODEL_FORMAT_VERSION));
}

// The trained forests of a model file (one per search group), or none. Files written with the
// experiment switches that are gone (grey_hue_label, max_group_classes; doc/experiments.md) hold
// forests of another layout: the templates are kept and trained again at the first match.
static std::vector<Ptr<TemplateForest> > readForests(const FileStorage& fs,
                                                      const String& filename,
                                                      const ForestParams& fp)
{
    std::vector<Ptr<TemplateForest> > forests;
    const FileNode params = fs["detector"]["forestmod_params"];
    if ((int)params["grey_hue_label"] != 0 || (int)params["max_group_classes"] != 0)
    {
        CV_LOG_WARNING(NULL, "forestmod::Detector::load: '" << filename << "' was trained with "
                       "grey_hue_label or max_group_classes, which this version no longer has: "
                       "its forests are trained again at the first match");
        return forests;
    }
    std::vector<FileNode> nodes;
    if (!fs["forest"].empty())
        nodes.push_back(fs["forest"]);
    FileNode seq = fs["forests"];
    if (!seq.empty() && !seq.isSeq())
        CV_Error_(Error::StsParseError, ("forestmod::Detector::load: 'forests' in '%s' is not a "
                                         "sequence (corrupt file?)", filename.c_str()));
    for (FileNodeIterator it = seq.begin(); !seq.empty() && it != seq.end(); ++it)
        nodes.push_back(*it);
    for (size_t g = 0; g < nodes.size(); ++g)
    {
        Ptr<TemplateForest> f = TemplateForest::create(fp);
        f->read(nodes[g]);
        forests.push_back(f);
    }
    return forests;
}

void Detector::load(const String& filename)
{
    // the file goes into a detector of its own, which replaces this one's contents only once it
    // is read whole: a file that fails leaves this detector as it was
    Detector loaded;
    try
    {
        FileStorage fs;
        openModel(fs, filename);
        loaded.read(fs["detector"]);
        FileNode classes = fs["classes"];
        if (classes.empty() || !classes.isSeq())
            CV_Error_(Error::StsParseError, ("forestmod::Detector::load: '%s' has no classes",
                                             filename.c_str()));
        for (FileNodeIterator it = classes.begin(); it != classes.end(); ++it)
            loaded.readClass(*it);
        // the trained forests are read as they are (training a large model takes minutes); the
        // groups, their windows and the rejection limits are functions of the templates and params
        detail::DetectorImpl& impl = *loaded.impl_;
        const std::vector<Ptr<TemplateForest> > forests = readForests(fs, filename,
                                                                      impl.params.forest);
        const int L = loaded.pyramid_levels - 1;
        if (!forests.empty())
            impl.index.attach(loaded.class_templates, impl.store, impl.params,
                              (int)loaded.modalities.size(), L, loaded.T_at_level[L], forests,
                              filename);
    }
    catch (const cv::Exception&)
    {
        throw;
    }
    catch (const std::exception& e)
    {
        // OpenCV's parsers let some standard exceptions through (std::length_error on a base64
        // block whose header declares an impossible size, found by fuzzing)
        CV_Error_(Error::StsParseError, ("forestmod::Detector::load: '%s' is not a readable "
                                         "model file: %s", filename.c_str(), e.what()));
    }
    AutoLock lock(impl_->mutex);
    impl_->poses.swapMeshes(loaded.impl_->poses); // the meshes set before load() stay
    modalities.swap(loaded.modalities);
    pyramid_levels = loaded.pyramid_levels;
    T_at_level.swap(loaded.T_at_level);
    class_templates.swap(loaded.class_templates);
    impl_.swap(loaded.impl_);
}

} // namespace forestmod
} // namespace cv
