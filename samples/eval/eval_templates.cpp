// This file is part of OpenCV project.
// It is subject to the license terms in the LICENSE file found in the top-level directory
// of this distribution and at http://opencv.org/license.html

// forestmod_eval: templates, rendered once and cached as an untrained forestmod model per object
// (and per subset of the sampler's poses, and per recoloured/rescaled variant of a mesh).

#include "eval_common.hpp"

#include <opencv2/calib3d.hpp>
#include <opencv2/core/utils/filesystem.hpp>
#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>

namespace fmeval {

cv::Ptr<fm::Detector> makeDetector(const EvalOptions& opt,
                                   const std::vector<std::string>& modalities)
{
    // LINEMOD's pyramid (T = 5, 8) with the modalities asked for
    std::vector<cv::Ptr<cv::linemod::Modality> > mods;
    for (size_t i = 0; i < modalities.size(); ++i)
        mods.push_back(modalities[i] == "ColorHue"
                           ? cv::Ptr<cv::linemod::Modality>(fm::ColorHue::create(hueParams(opt)))
                           : cv::linemod::Modality::create(modalities[i]));
    std::vector<int> T;
    T.push_back(5);
    T.push_back(8);
    return cv::makePtr<fm::Detector>(mods, T, experimentParams(opt));
}

std::vector<int> poseSubset(int total, int n)
{
    std::vector<int> idx;
    if (n <= 0 || n >= total)
    {
        for (int i = 0; i < total; ++i)
            idx.push_back(i);
        return idx;
    }
    for (int k = 0; k < n; ++k)
        idx.push_back((int)(((int64)2 * k + 1) * total / (2 * (int64)n)));
    return idx;
}

static bool fileHash(const std::string& path, uint64_t& hash, size_t& size)
{
    std::ifstream f(path.c_str(), std::ios::binary);
    if (!f)
        return false;
    std::vector<char> buf((std::istreambuf_iterator<char>(f)), std::istreambuf_iterator<char>());
    size = buf.size();
    hash = fnv1a(buf.empty() ? "" : &buf[0], buf.size());
    return true;
}

/** Templates are rendered in a square window around the principal point, large enough for the
object at the nearest distance, with the principal point moved accordingly: the same templates as
from the full image (the sampler's cameras look at the object's centre), at a fraction of the
pixels to render and quantize. */
static int renderWindow(const ObjectInfo& obj, const TemplateSetup& setup)
{
    const cv::Point3f c = obj.mesh.center();
    double rmax = 0;
    for (size_t i = 0; i < obj.mesh.vertices.size(); ++i)
    {
        const cv::Point3f d = obj.mesh.vertices[i] - c;
        rmax = std::max(rmax, std::sqrt(double(d.dot(d))));
    }
    double rmin_cam = 1e30;
    for (size_t i = 0; i < setup.sampler.params.radii.size(); ++i)
        rmin_cam = std::min(rmin_cam, setup.sampler.params.radii[i]);
    const double f = std::max(setup.K(0, 0), setup.K(1, 1));
    const double max_extent = rmin_cam > rmax ? f * rmax / (rmin_cam - rmax) : 1e4;
    const int margin = 24;
    int S = 2 * cvCeil(max_extent) + 2 * margin;
    S = (S + 7) / 8 * 8;
    return std::min(S, 2 * std::max(setup.size.width, setup.size.height));
}

static std::string cacheKey(const EvalOptions& opt, const ObjectInfo& obj,
                            const TemplateSetup& setup, int window)
{
    uint64_t mesh_hash = 0;
    size_t mesh_size = 0;
    if (!fileHash(obj.mesh_path, mesh_hash, mesh_size))
        CV_Error_(cv::Error::StsError, ("cannot read %s", obj.mesh_path.c_str()));
    cv::FileStorage fs(".yml", cv::FileStorage::WRITE | cv::FileStorage::MEMORY);
    fs << "version" << 1;
    fs << "modalities" << "[:";
    for (size_t i = 0; i < setup.modalities.size(); ++i)
        fs << setup.modalities[i];
    fs << "]";
    fs << "K" << cv::Mat(setup.K);
    fs << "window" << window;
    fs << "sampler" << "{";
    setup.sampler.params.write(fs);
    fs << "}";
    fs << "mesh_size" << (double)mesh_size;
    if (std::find(setup.modalities.begin(), setup.modalities.end(), std::string("ColorHue"))
        != setup.modalities.end())
    {
        fs << "hue" << "{"; // they choose the templates' hue features
        hueParams(opt).write(fs);
        fs << "}";
    }
    const int ds = experimentParams(opt).depth_samples;
    const bool has_depth = std::find(setup.modalities.begin(), setup.modalities.end(),
                                     std::string("DepthNormal")) != setup.modalities.end();
    if (ds > 0 && has_depth) // templates with depth samples (their selection as of this version)
        fs << "depth_samples" << ds << "depth_sampler" << 2;
    // keys that did not exist in version 1 only when used: older cache files stay valid
    if (setup.subset > 0 && setup.subset < setup.sampler.size())
        fs << "subset" << setup.subset;
    if (!obj.variant.empty())
        fs << "variant" << obj.variant;
    const std::string text = fs.releaseAndGetString();
    const uint64_t h = fnv1a(text.data(), text.size(), mesh_hash);
    return cv::format("%s_%016llx", obj.name.c_str(), (unsigned long long)h);
}

static void renderObjectTemplates(fm::Detector& det, const ObjectInfo& obj,
                                  const TemplateSetup& setup, int S, Progress& progress)
{
    // intrinsics of the window: the principal point at the window's centre
    cv::Matx33d Kw = setup.K;
    Kw(0, 2) = setup.K(0, 2) - (cvRound(setup.K(0, 2)) - S / 2);
    Kw(1, 2) = setup.K(1, 2) - (cvRound(setup.K(1, 2)) - S / 2);
    cv::Ptr<fm::Renderer> renderer = fm::Renderer::create(cv::Size(S, S));
    const int handle = renderer->addMesh(obj.mesh);
    const std::vector<cv::Ptr<cv::linemod::Modality> > mods = det.getModalities();
    const std::vector<fm::ViewPose> poses = setup.sampler.poses(cv::Point3d(obj.mesh.center()));
    const std::vector<int> idx = poseSubset((int)poses.size(), setup.subset);
    for (size_t i = 0; i < idx.size(); ++i)
    {
        const fm::ViewPose& p = poses[idx[i]];
        cv::Mat color, depth, mask;
        renderer->render(handle, p.R, p.t, Kw, color, depth, mask);
        if (cv::countNonZero(mask) > 0)
        {
            std::vector<cv::Mat> sources;
            for (size_t m = 0; m < mods.size(); ++m)
                sources.push_back(mods[m]->name() == "DepthNormal" ? depth : color);
            det.addTemplate(sources, obj.class_id, mask, p.R, p.t, Kw);
        }
        if ((i + 1) % 25 == 0 || i + 1 == idx.size())
            progress.show(cv::format("%s: rendering templates %d/%d", obj.name.c_str(),
                                     (int)i + 1, (int)idx.size()));
    }
    det.setMesh(obj.class_id, obj.mesh);
}

/** The parameters of a detector whose templates are made: the flags', depth validation off on
request (the depth samples stay with the templates). */
static fm::DetectorParams runParams(const EvalOptions& opt)
{
    fm::DetectorParams p = experimentParams(opt);
    if (!opt.depth_validation)
        p.depth_samples = 0;
    return p;
}

cv::Ptr<fm::Detector> objectTemplates(const EvalOptions& opt, ObjectInfo& obj,
                                      const TemplateSetup& setup, Progress& progress,
                                      double& render_s)
{
    render_s = 0;
    const int S = renderWindow(obj, setup);
    obj.cache_file = opt.cache_dir + "/" + cacheKey(opt, obj, setup, S) + ".yml.gz";
    cv::Ptr<fm::Detector> det = makeDetector(opt, setup.modalities);
    if (cv::utils::fs::exists(obj.cache_file))
    {
        try
        {
            progress.show(obj.name + ": loading cached templates");
            det->load(obj.cache_file);
            // the cache holds templates; the parameters are this build's defaults (and the
            // command's flags), not those saved with the cached model
            det->setParams(runParams(opt));
            det->setMesh(obj.class_id, obj.mesh);
            obj.templates = det->numTemplates(obj.class_id);
            return det;
        }
        catch (const cv::Exception& e)
        {
            fprintf(stderr, "\nforestmod_eval: cache file %s unreadable (%s); rendering again\n",
                    obj.cache_file.c_str(), e.err.c_str());
            det = makeDetector(opt, setup.modalities);
        }
    }
    const std::string none_file = obj.cache_file + ".none";
    if (cv::utils::fs::exists(none_file))
    {
        obj.templates = 0;
        return cv::Ptr<fm::Detector>();
    }
    cv::TickMeter tm;
    tm.start();
    renderObjectTemplates(*det, obj, setup, S, progress);
    tm.stop();
    render_s = tm.getTimeSec();
    obj.templates = det->numTemplates(obj.class_id);
    if (obj.templates == 0)
    {
        // every view lacks features of some modality (e.g. ColorHue on a white object)
        std::ofstream(none_file.c_str()) << "no template\n";
        return cv::Ptr<fm::Detector>();
    }
    det->save(obj.cache_file, true); // untrained: the forest is trained per experiment
    det->setParams(runParams(opt));
    return det;
}

cv::Ptr<fm::Detector> multiObjectDetector(const EvalOptions& opt,
                                          const std::vector<std::string>& modalities,
                                          const std::vector<ObjectInfo*>& objects)
{
    cv::Ptr<fm::Detector> det = makeDetector(opt, modalities);
    for (size_t o = 0; o < objects.size(); ++o)
    {
        cv::FileStorage fs(objects[o]->cache_file, cv::FileStorage::READ);
        if (!fs.isOpened())
            CV_Error_(cv::Error::StsError, ("cannot read %s", objects[o]->cache_file.c_str()));
        cv::FileNode classes = fs["classes"];
        for (cv::FileNodeIterator it = classes.begin(); it != classes.end(); ++it)
            det->readClass(*it);
        det->setMesh(objects[o]->class_id, objects[o]->mesh);
    }
    det->setParams(runParams(opt));
    return det;
}

ObjectInfo objectVariant(const ObjectInfo& obj, int k)
{
    if (k == 0)
        return obj;
    // scale and hue turn of the k-th copy; grey objects (no saturation) differ by size only
    static const double scales[] = { 1.0, 1.25, 0.8, 1.5, 0.7, 1.15, 0.9, 1.35 };
    const double s = scales[k % 8];
    const int hue_shift = (45 * k) % 180; // OpenCV's hue: 0..179 = 0..358 degrees
    ObjectInfo v = obj;
    v.variant = cv::format("scale %.2f, hue %+d deg", s, 2 * hue_shift);
    v.name = cv::format("%s_v%d", obj.name.c_str(), k);
    v.class_id = v.name;
    v.obj_id = obj.obj_id + 1000 * k;
    for (size_t i = 0; i < v.mesh.vertices.size(); ++i)
        v.mesh.vertices[i] *= (float)s;
    for (size_t i = 0; i < v.pts.size(); ++i)
        v.pts[i] *= (float)s;
    v.diameter *= s;
    if (!v.mesh.colors.empty())
    {
        cv::Mat bgr(1, (int)v.mesh.colors.size(), CV_8UC3, &v.mesh.colors[0]), hsv;
        cv::cvtColor(bgr, hsv, cv::COLOR_BGR2HSV);
        for (int i = 0; i < hsv.cols; ++i)
        {
            cv::Vec3b& h = hsv.at<cv::Vec3b>(i);
            h[0] = (uchar)((h[0] + hue_shift) % 180);
        }
        cv::cvtColor(hsv, bgr, cv::COLOR_HSV2BGR); // writes into v.mesh.colors
    }
    v.templates = 0;
    v.cache_file.clear();
    return v;
}

// The rotation that turns the line of sight through p (camera frame) onto the optical axis.
static cv::Matx33d alongOpticalAxis(const cv::Vec3d& p)
{
    const cv::Vec3d z = p * (1.0 / cv::norm(p));
    const cv::Vec3d axis = z.cross(cv::Vec3d(0, 0, 1));
    const double s = cv::norm(axis);
    if (s < 1e-12)
        return cv::Matx33d::eye();
    cv::Matx33d Rc;
    cv::Rodrigues(axis * (std::atan2(s, z[2]) / s), Rc);
    return Rc;
}

std::vector<double> templateCoverage(const fm::Detector& det, const ObjectInfo& obj,
                                     const std::vector<EvalFrame>& frames)
{
    std::vector<cv::Matx33d> views;
    const int n = det.numTemplates(obj.class_id);
    for (int i = 0; i < n; ++i)
    {
        const fm::TemplatePose tp = det.getTemplatePose(obj.class_id, i);
        if (tp.valid)
            views.push_back(tp.R);
    }
    std::vector<double> angles;
    const cv::Point3f c = obj.mesh.center();
    for (size_t f = 0; f < frames.size(); ++f)
        for (size_t g = 0; g < frames[f].gt.size(); ++g)
        {
            const fm::GroundTruth& gt = frames[f].gt[g];
            if (gt.obj_id != obj.obj_id || views.empty())
                continue;
            const cv::Matx33d Rc = alongOpticalAxis(gt.R * cv::Vec3d(c.x, c.y, c.z) + gt.t);
            std::vector<cv::Matx33d> truths(1, Rc * gt.R);
            for (size_t s = 0; s < obj.symmetries.size(); ++s)
                truths.push_back(Rc * gt.R * obj.symmetries[s].get_minor<3, 3>(0, 0));
            double best_cos = -1; // cos of the angle: (trace(A B^T) - 1) / 2
            for (size_t v = 0; v < views.size(); ++v)
                for (size_t t = 0; t < truths.size(); ++t)
                    best_cos = std::max(best_cos, (cv::trace(views[v] * truths[t].t()) - 1) / 2);
            angles.push_back(std::acos(std::min(1.0, best_cos)) * 180.0 / CV_PI);
        }
    return angles;
}

} // namespace fmeval
