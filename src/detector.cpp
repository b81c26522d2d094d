// This file is part of OpenCV project.
// It is subject to the license terms in the LICENSE file found in the top-level directory
// of this distribution and at http://opencv.org/license.html

// The detector (paper: the whole pipeline): quantize once per frame, visit every location of the
// coarsest pyramid level through the template forest (rejectors, splits, all trees), validate the
// leaf candidates breadth-first, refine survivors up the pyramid as LINEMOD does.

#include "precomp.hpp"
#include "validator.hpp"
#include "detector_impl.hpp"
#include "model_check.hpp"

#include "opencv2/core/utils/filesystem.hpp"
#include "opencv2/forestmod/detector.hpp"

#include <map>

namespace cv {
namespace forestmod {

using linemod::Feature;
using linemod::Match;
using linemod::Modality;
using linemod::QuantizedPyramid;
using linemod::Template;
using detail::LevelMaps;
using detail::TemplatePyramid;

static const int MODEL_FORMAT_VERSION = 1;

// ---------------------------------------------------------------------------------------------
DetectorParams::DetectorParams()
    : use_forest(true), breadth_first(true), chunk_size(16), alpha(0.5f), max_survivors(1),
      grid_size(12), location_step(0), nms_iou(0.5f), depth_samples(63), depth_tolerance(5),
      min_window_labels(0.5f), depth_range_margin(0), dominant_window(3),
      group_size_ratio(1.3f), max_group_classes(0), auto_depth_leaf_samples(8.f),
      grey_hue_label(false), depth_coarse(0), group_templates(true)
{
    forest.max_depth = 0; // chosen at train() per search group (auto_depth_leaf_samples)
    // rejectors over dims that half the node's templates cover, and more of them: measured on
    // rendered LM-O scenes (doc/detector.md), the forest's defaults reject less background
    forest.rejector_coverage = 0.5f;
    forest.rejector_dims = 64;
}

void DetectorParams::read(const FileNode& fn)
{
    if (!fn["forest"].empty())
        forest.read(fn["forest"]);
    if (!fn["use_forest"].empty())
        use_forest = (int)fn["use_forest"] != 0;
    if (!fn["breadth_first"].empty())
        breadth_first = (int)fn["breadth_first"] != 0;
    if (!fn["chunk_size"].empty())
        chunk_size = (int)fn["chunk_size"];
    if (!fn["alpha"].empty())
        alpha = (float)fn["alpha"];
    if (!fn["grid_size"].empty())
        grid_size = (int)fn["grid_size"];
    if (!fn["location_step"].empty())
        location_step = (int)fn["location_step"];
    if (!fn["nms_iou"].empty())
        nms_iou = (float)fn["nms_iou"];
    if (!fn["max_survivors"].empty())
        max_survivors = (int)fn["max_survivors"];
    if (!fn["depth_samples"].empty())
        depth_samples = (int)fn["depth_samples"];
    if (!fn["depth_tolerance"].empty())
        depth_tolerance = (int)fn["depth_tolerance"];
    if (!fn["min_window_labels"].empty())
        min_window_labels = (float)fn["min_window_labels"];
    if (!fn["depth_range_margin"].empty())
        depth_range_margin = (int)fn["depth_range_margin"];
    if (!fn["dominant_window"].empty())
        dominant_window = (int)fn["dominant_window"];
    if (!fn["group_size_ratio"].empty())
        group_size_ratio = (float)fn["group_size_ratio"];
    if (!fn["max_group_classes"].empty())
        max_group_classes = (int)fn["max_group_classes"];
    if (!fn["auto_depth_leaf_samples"].empty())
        auto_depth_leaf_samples = (float)fn["auto_depth_leaf_samples"];
    if (!fn["grey_hue_label"].empty())
        grey_hue_label = (int)fn["grey_hue_label"] != 0;
    if (!fn["depth_coarse"].empty())
        depth_coarse = (int)fn["depth_coarse"];
    if (!fn["group_templates"].empty())
        group_templates = (int)fn["group_templates"] != 0;
}

void DetectorParams::write(FileStorage& fs) const
{
    fs << "forest" << "{";
    forest.write(fs);
    fs << "}";
    fs << "use_forest" << (int)use_forest;
    fs << "breadth_first" << (int)breadth_first;
    fs << "chunk_size" << chunk_size;
    fs << "alpha" << alpha;
    fs << "grid_size" << grid_size;
    fs << "location_step" << location_step;
    fs << "nms_iou" << nms_iou;
    fs << "max_survivors" << max_survivors;
    fs << "depth_samples" << depth_samples;
    fs << "depth_tolerance" << depth_tolerance;
    fs << "min_window_labels" << min_window_labels;
    fs << "depth_range_margin" << depth_range_margin;
    fs << "dominant_window" << dominant_window;
    fs << "group_size_ratio" << group_size_ratio;
    fs << "max_group_classes" << max_group_classes;
    fs << "auto_depth_leaf_samples" << auto_depth_leaf_samples;
    fs << "grey_hue_label" << (int)grey_hue_label;
    fs << "depth_coarse" << depth_coarse;
    fs << "group_templates" << (int)group_templates;
}

static void checkParams(const DetectorParams& p)
{
    detail::checkDetectorParams(p); // issue 18: ranges in model_check.cpp
}

// stride (coarsest level pixels) of forest queries: location_step, or T / 2 when 0
static int locationStep(const DetectorParams& p, int T)
{
    return p.location_step > 0 ? p.location_step : std::max(1, T / 2);
}

static int depthModality(const std::vector<Ptr<Modality> >& modalities)
{
    for (size_t i = 0; i < modalities.size(); ++i)
        if (modalities[i]->name() == "DepthNormal")
            return static_cast<int>(i);
    return -1;
}

// Dominant label of each k x k neighbourhood (only where mask, if given, is set): a single-label
// image that tolerates a misalignment of about k / 2 pixels, for the forest's descriptors of the
// templates and the scene alike (doc/detector.md, "Search"). k <= 1: a copy.
static void dominantLabels(const Mat& quantized, const Mat& mask, int k, Mat& dst)
{
    if (k <= 1)
    {
        dst = quantized.clone();
        return;
    }
    Mat best_count = Mat::zeros(quantized.size(), CV_32S);
    dst = Mat::zeros(quantized.size(), CV_8U);
    Mat ind, cnt;
    for (int b = 0; b < 8; ++b)
    {
        const uchar bit = (uchar)(1 << b);
        ind = Mat::zeros(quantized.size(), CV_8U);
        ind.setTo(1, (quantized & bit) != 0);
        if (!mask.empty())
            ind.setTo(0, mask == 0);
        boxFilter(ind, cnt, CV_32S, Size(k, k), Point(-1, -1), false, BORDER_CONSTANT);
        for (int y = 0; y < cnt.rows; ++y)
        {
            const int* c = cnt.ptr<int>(y);
            int* bc = best_count.ptr<int>(y);
            uchar* d = dst.ptr<uchar>(y);
            for (int x = 0; x < cnt.cols; ++x)
                if (c[x] > bc[x])
                {
                    bc[x] = c[x];
                    d[x] = bit;
                }
        }
    }
}

// The forest's view of a ColorHue plane with grey_hue_label: the 8 hue bins merged into 7 (bits
// 0..6) and "no reliable hue" (0) as a label of its own (bit 7, GREY_BIT), for the templates (on
// their mask) and the scene alike: a white or grey surface is then evidence (doc/detector.md,
// "Colourless objects"). The flat-window count ignores GREY_BIT.
static const uchar GREY_BIT = 0x80;

static void greyHueLabels(const Mat& quantized, const Mat& mask, Mat& dst)
{
    uchar lut[256];
    for (int v = 0; v < 256; ++v)
    {
        int b = -1;
        for (int k = 0; k < 8; ++k)
            if (v & (1 << k))
            {
                b = k;
                break;
            }
        lut[v] = b < 0 ? GREY_BIT : (uchar)(1 << (b * 7 / 8));
    }
    LUT(quantized, Mat(1, 256, CV_8U, lut), dst);
    if (!mask.empty())
        dst.setTo(0, mask == 0);
}

static std::vector<int> hueModalities(const std::vector<Ptr<Modality> >& modalities,
                                      const DetectorParams& p)
{
    std::vector<int> hue(modalities.size(), 0);
    if (p.grey_hue_label)
        for (size_t i = 0; i < modalities.size(); ++i)
            hue[i] = modalities[i]->name() == "ColorHue";
    return hue;
}

static Mat downsampleNearest(const Mat& img, int levels)
{
    Mat out = img;
    for (int l = 0; l < levels; ++l)
    {
        Mat m;
        resize(out, m, Size(out.cols / 2, out.rows / 2), 0, 0, INTER_NEAREST);
        out = m;
    }
    return out;
}

void DetectionStats::reset()
{
    t_quantize_ms = t_tree_ms = t_valid_ms = t_total_ms = 0;
    locations = rejected = rejected_flat = rejected_depth_range = validated = candidates = 0;
    rejected_at_depth.clear();
    rejection_map.release();
}

// ---------------------------------------------------------------------------------------------
// ---------------------------------------------------------------------------------------------
Detector::Detector() : impl_(makePtr<Impl>()) {}

Detector::Detector(const std::vector<Ptr<Modality> >& _modalities,
                   const std::vector<int>& T_pyramid, const DetectorParams& params)
    : cv::linemod::Detector(_modalities, T_pyramid), impl_(makePtr<Impl>())
{
    if (_modalities.empty())
        CV_Error(Error::StsBadArg, "forestmod::Detector: at least one modality is needed");
    if (T_pyramid.empty())
        CV_Error(Error::StsBadArg, "forestmod::Detector: T_pyramid must not be empty");
    for (size_t i = 0; i < _modalities.size(); ++i)
        CV_Assert(!_modalities[i].empty() && "forestmod::Detector: null modality");
    for (size_t i = 0; i < T_pyramid.size(); ++i)
        CV_CheckGT(T_pyramid[i], 0, "forestmod::Detector: every T must be positive");
    checkParams(params);
    impl_->params = params;
}

Detector::~Detector() {}

DetectorParams Detector::getParams() const
{
    return impl_->params;
}

void Detector::setParams(const DetectorParams& params)
{
    checkParams(params);
    AutoLock lock(impl_->mutex);
    impl_->params = params;
    impl_->trained = false;
    impl_->groups.clear();
}

Ptr<TemplateForest> Detector::getForest(int group) const
{
    if (group < 0 || group >= (int)impl_->groups.size())
    {
        if (group == 0)
            return Ptr<TemplateForest>(); // untrained
        CV_Error_(Error::StsOutOfRange, ("forestmod::Detector::getForest: no search group %d "
                                         "(%d groups)", group, (int)impl_->groups.size()));
    }
    return impl_->groups[group].forest;
}

int Detector::numSearchGroups() const
{
    return (int)impl_->groups.size();
}

std::vector<String> Detector::getSearchGroupClasses(int group) const
{
    if (group < 0 || group >= (int)impl_->groups.size())
        CV_Error_(Error::StsOutOfRange, ("forestmod::Detector::getSearchGroupClasses: no search "
                                         "group %d (%d groups)", group,
                                         (int)impl_->groups.size()));
    return impl_->groups[group].classes;
}

bool Detector::isTrained() const
{
    return impl_->trained;
}

TemplatePose Detector::getTemplatePose(const String& class_id, int template_id) const
{
    std::map<String, std::vector<TemplatePose> >::const_iterator it = impl_->poses.find(class_id);
    if (it == impl_->poses.end() || template_id < 0 || template_id >= (int)it->second.size())
        CV_Error_(Error::StsBadArg, ("forestmod::Detector: no template %d of class '%s'",
                                     template_id, class_id.c_str()));
    return it->second[template_id];
}

// ---------------------------------------------------------------------------------------------
static void checkSources(const std::vector<Ptr<Modality> >& modalities,
                         const std::vector<Mat>& sources, const std::vector<Mat>& masks,
                         const char* where)
{
    if (modalities.empty())
        CV_Error_(Error::StsError, ("forestmod::Detector::%s: the detector has no modalities "
                                    "(default-constructed? use a factory or read a model)",
                                    where));
    if (sources.size() != modalities.size())
        CV_Error_(Error::StsBadArg, ("forestmod::Detector::%s: %d sources for %d modalities",
                                     where, (int)sources.size(), (int)modalities.size()));
    for (size_t i = 0; i < sources.size(); ++i)
    {
        if (sources[i].empty())
            CV_Error_(Error::StsBadArg, ("forestmod::Detector::%s: source %d (%s) is empty",
                                         where, (int)i, modalities[i]->name().c_str()));
        const String name = modalities[i]->name();
        if (name == "DepthNormal" && sources[i].type() != CV_16UC1)
            CV_Error_(Error::StsUnsupportedFormat,
                      ("forestmod::Detector::%s: source %d (DepthNormal) must be CV_16UC1 depth "
                       "in mm, got %s", where, (int)i, typeToString(sources[i].type()).c_str()));
        if ((name == "ColorGradient" || name == "ColorHue") && sources[i].type() != CV_8UC3)
            CV_Error_(Error::StsUnsupportedFormat,
                      ("forestmod::Detector::%s: source %d (%s) must be a CV_8UC3 BGR image, "
                       "got %s", where, (int)i, name.c_str(),
                       typeToString(sources[i].type()).c_str()));
        if (sources[i].size() != sources[0].size())
            CV_Error_(Error::StsUnmatchedSizes,
                      ("forestmod::Detector::%s: source %d is %dx%d, source 0 is %dx%d", where,
                       (int)i, sources[i].cols, sources[i].rows, sources[0].cols,
                       sources[0].rows));
    }
    if (!masks.empty())
    {
        if (masks.size() != sources.size())
            CV_Error_(Error::StsBadArg, ("forestmod::Detector::%s: %d masks for %d sources",
                                         where, (int)masks.size(), (int)sources.size()));
        for (size_t i = 0; i < masks.size(); ++i)
            if (!masks[i].empty() && (masks[i].size() != sources[i].size()
                                      || masks[i].type() != CV_8UC1))
                CV_Error_(Error::StsUnmatchedSizes,
                          ("forestmod::Detector::%s: mask %d must be CV_8UC1 of the source's "
                           "size", where, (int)i));
    }
}

// LINEMOD's cropTemplates: box over the features of all levels and modalities, features
// shifted to it. Returns the box in level-0 pixels.
static Rect cropTemplatePyramid(TemplatePyramid& templates)
{
    int min_x = INT_MAX, min_y = INT_MAX, max_x = INT_MIN, max_y = INT_MIN;
    for (size_t i = 0; i < templates.size(); ++i)
        for (size_t j = 0; j < templates[i].features.size(); ++j)
        {
            const int x = templates[i].features[j].x << templates[i].pyramid_level;
            const int y = templates[i].features[j].y << templates[i].pyramid_level;
            min_x = std::min(min_x, x);
            min_y = std::min(min_y, y);
            max_x = std::max(max_x, x);
            max_y = std::max(max_y, y);
        }
    if (min_x % 2 == 1)
        --min_x;
    if (min_y % 2 == 1)
        --min_y;
    for (size_t i = 0; i < templates.size(); ++i)
    {
        Template& t = templates[i];
        t.width = (max_x - min_x) >> t.pyramid_level;
        t.height = (max_y - min_y) >> t.pyramid_level;
        const int ox = min_x >> t.pyramid_level, oy = min_y >> t.pyramid_level;
        for (size_t j = 0; j < t.features.size(); ++j)
        {
            t.features[j].x -= ox;
            t.features[j].y -= oy;
        }
    }
    return Rect(min_x, min_y, max_x - min_x, max_y - min_y);
}

// Up to n depth samples of a template (x, y relative to `tl`, z mm) on the object eroded by 2 px
// (no mixed depth at the rim), spread evenly: taken greedily at least d pixels apart, d from the
// spacing of n points over the object (shrinking until n are chosen), in order of distance from
// the template's median depth, so that of each neighbourhood the point with more relief is taken
// (a point at the median agrees with a flat picture as well as with the object). Taking only
// the extreme points was worse (doc/detector.md, "Depth").
static void selectDepthSamples(const Mat& depth, const Mat& mask, Point tl, int n,
                               std::vector<Point3i>& samples)
{
    samples.clear();
    Mat on = (mask > 0) & (depth > 0);
    Mat inner;
    erode(on, inner, Mat(), Point(-1, -1), 2, BORDER_CONSTANT, Scalar(0));
    if (countNonZero(inner) < n) // small or thin object: less margin
        inner = on;
    std::vector<Point> all;
    findNonZero(inner, all);
    if (all.empty())
        return;
    std::vector<int> z(all.size());
    for (size_t i = 0; i < all.size(); ++i)
        z[i] = depth.at<ushort>(all[i]);
    std::vector<int> sorted(z);
    std::nth_element(sorted.begin(), sorted.begin() + sorted.size() / 2, sorted.end());
    const int zmed = sorted[sorted.size() / 2];
    std::vector<int> order(all.size());
    for (size_t i = 0; i < order.size(); ++i)
        order[i] = (int)i;
    std::stable_sort(order.begin(), order.end(), [&](int a, int b) {
        return std::abs(z[a] - zmed) > std::abs(z[b] - zmed);
    });
    std::vector<Point> chosen;
    for (int d = std::max(1, cvRound(std::sqrt((double)all.size() / n))); d >= 1; --d)
    {
        chosen.clear();
        const int d2 = d * d;
        for (size_t k = 0; k < order.size() && (int)chosen.size() < n; ++k)
        {
            const Point p = all[order[k]];
            bool far_enough = true;
            for (size_t j = 0; j < chosen.size() && far_enough; ++j)
            {
                const Point q = p - chosen[j];
                far_enough = q.x * q.x + q.y * q.y >= d2;
            }
            if (far_enough)
                chosen.push_back(p);
        }
        if ((int)chosen.size() >= n)
            break;
    }
    for (size_t i = 0; i < chosen.size(); ++i)
        samples.push_back(Point3i(chosen[i].x - tl.x, chosen[i].y - tl.y,
                                  depth.at<ushort>(chosen[i])));
}

static int templateAddImpl(Detector& self, std::vector<Ptr<Modality> >& modalities,
                           int pyramid_levels, std::map<String, std::vector<TemplatePyramid> >& ct,
                           Detector::Impl& impl, const std::vector<Mat>& sources,
                           const String& class_id, const Mat& object_mask, const TemplatePose& pose,
                           Rect* bounding_box)
{
    (void)self;
    std::vector<Mat> masks;
    checkSources(modalities, sources, masks, "addTemplate");
    if (object_mask.empty() || object_mask.type() != CV_8UC1
        || object_mask.size() != sources[0].size())
        CV_Error(Error::StsBadArg, "forestmod::Detector::addTemplate: object_mask must be a "
                                   "CV_8UC1 image of the sources' size");
    if (countNonZero(object_mask) == 0)
        CV_Error(Error::StsBadArg, "forestmod::Detector::addTemplate: object_mask is empty");

    const int M = static_cast<int>(modalities.size());
    TemplatePyramid tp(M * pyramid_levels);
    DensePatch patch;
    std::vector<Mat> coarse_quantized(M);
    for (int i = 0; i < M; ++i)
    {
        Ptr<QuantizedPyramid> qp = modalities[i]->process(sources[i], object_mask);
        for (int l = 0; l < pyramid_levels; ++l)
        {
            if (l > 0)
                qp->pyrDown();
            if (!qp->extractTemplate(tp[l * M + i]))
            {
                // a white, grey or black object has no hue: it is learned by the other
                // modalities (ColorHue alone refuses it, as cv::linemod expects)
                if (modalities[i]->name() != "ColorHue")
                    return -1;
                tp[l * M + i].features.clear();
                tp[l * M + i].pyramid_level = l;
            }
        }
        qp->quantize(coarse_quantized[i]);
    }
    for (int l = 0; l < pyramid_levels; ++l)
    {
        size_t n = 0;
        for (int i = 0; i < M; ++i)
            n += tp[l * M + i].features.size();
        if (n == 0)
            return -1; // no modality found features at this level
    }
    const Rect bb = cropTemplatePyramid(tp);
    if (bounding_box)
        *bounding_box = bb;

    const int L = pyramid_levels - 1;
    const Mat coarse_mask = downsampleNearest(object_mask, L);
    const Template& top = tp[L * M];
    const Point origin(bb.x >> L, bb.y >> L);
    Rect box(origin.x, origin.y, top.width + 1, top.height + 1);
    box &= Rect(0, 0, coarse_mask.cols, coarse_mask.rows);
    // the template's dense quantized box at the coarsest level: its forest descriptor reads the
    // same plain quantized values as the scene windows (doc/detector.md, "Search")
    {
        patch.mask = Mat::zeros(top.height + 1, top.width + 1, CV_8U);
        const Rect dst(box.x - origin.x, box.y - origin.y, box.width, box.height);
        coarse_mask(box).copyTo(patch.mask(dst));
        for (int i = 0; i < M; ++i)
        {
            Mat q = Mat::zeros(patch.mask.size(), CV_8U);
            coarse_quantized[i](box).copyTo(q(dst));
            patch.quantized.push_back(q);
        }
    }

    // depth samples (depth as a validation modality, detail::DepthContext)
    std::vector<Point3i> depth_samples;
    const int dm = depthModality(modalities);
    if (dm >= 0 && impl.params.depth_samples > 0)
        selectDepthSamples(sources[dm], object_mask, bb.tl(), impl.params.depth_samples,
                           depth_samples);

    std::vector<TemplatePyramid>& pyramids = ct[class_id];
    const int template_id = static_cast<int>(pyramids.size());
    pyramids.push_back(tp);
    std::vector<TemplatePose>& poses = impl.poses[class_id];
    poses.resize(template_id);
    poses.push_back(pose);
    poses.back().box = bb;
    std::vector<DensePatch>& patches = impl.patches[class_id];
    patches.resize(template_id);
    patches.push_back(patch);
    std::vector<std::vector<Point3i> >& depth = impl.depth[class_id];
    depth.resize(template_id);
    depth.push_back(depth_samples);
    impl.trained = false;
    return template_id;
}

int Detector::addTemplate(const std::vector<Mat>& sources, const String& class_id,
                          const Mat& object_mask, Rect* bounding_box)
{
    AutoLock lock(impl_->mutex);
    return templateAddImpl(*this, modalities, pyramid_levels, class_templates, *impl_, sources,
                           class_id, object_mask, TemplatePose(), bounding_box);
}

int Detector::addTemplate(const std::vector<Mat>& sources, const String& class_id,
                          const Mat& object_mask, const Matx33d& R, const Vec3d& t,
                          const Matx33d& K, Rect* bounding_box)
{
    TemplatePose pose;
    pose.R = R;
    pose.t = t;
    pose.K = K;
    pose.valid = true;
    AutoLock lock(impl_->mutex);
    return templateAddImpl(*this, modalities, pyramid_levels, class_templates, *impl_, sources,
                           class_id, object_mask, pose, bounding_box);
}

static std::vector<Mat> sourcesFor(const std::vector<Ptr<Modality> >& modalities,
                                   const Mat& color, const Mat& depth)
{
    std::vector<Mat> sources;
    for (size_t i = 0; i < modalities.size(); ++i)
    {
        const String name = modalities[i]->name();
        if (name == "DepthNormal")
            sources.push_back(depth);
        else if (name == "ColorGradient" || name == "ColorHue")
            sources.push_back(color);
        else
            CV_Error_(Error::StsNotImplemented,
                      ("forestmod::Detector::addTemplates: no rendered source for modality '%s'",
                       name.c_str()));
    }
    return sources;
}

int Detector::addTemplates(const Mesh& mesh, const String& class_id, const ViewSampler& sampler,
                           const Matx33d& K, Size size,
                           const std::function<bool(int, int)>& progress)
{
    if (modalities.empty())
        CV_Error(Error::StsError, "forestmod::Detector::addTemplates: no modalities");
    setMesh(class_id, mesh);
    int added = 0, views = 0;
    renderTemplates(mesh, sampler, K, size,
                    [&](const TemplateView& v, int done, int total) -> bool {
                        detail::checkTemplateView(v.mask, v.view_id, v.radius, class_id); // 18
                        views = done;
                        if (countNonZero(v.mask) > 0)
                        {
                            const std::vector<Mat> sources = sourcesFor(modalities, v.color,
                                                                        v.depth);
                            if (addTemplate(sources, class_id, v.mask, v.R, v.t, v.K) >= 0)
                                ++added;
                        }
                        return progress ? progress(done, total) : true;
                    });
    detail::checkViewsGaveTemplates(added, views, class_id); // issue 18 (model_check)
    return added;
}

int Detector::addSyntheticTemplate(const std::vector<Template>& templates, const String& class_id)
{
    const int M = static_cast<int>(modalities.size());
    if (M == 0 || (int)templates.size() != M * pyramid_levels)
        CV_Error_(Error::StsBadArg, ("forestmod::Detector::addSyntheticTemplate: expected %d "
                                     "templates (modalities x pyramid levels), got %d",
                                     M * pyramid_levels, (int)templates.size()));
    AutoLock lock(impl_->mutex);
    std::vector<TemplatePyramid>& pyramids = class_templates[class_id];
    const int template_id = static_cast<int>(pyramids.size());
    pyramids.push_back(templates);
    impl_->poses[class_id].resize(template_id + 1);
    impl_->patches[class_id].resize(template_id + 1); // empty: descriptor from the features
    impl_->depth[class_id].resize(template_id + 1);
    impl_->trained = false;
    return template_id;
}

// ---------------------------------------------------------------------------------------------
// Descriptor of one template under the window geometry (paper: v_T = {Psi(O, r)}): its quantized
// value at every grid point and modality; foreground where the grid point is on its mask.
static void templateDescriptor(const TemplatePyramid& tp, const DensePatch& patch, int M, int L,
                               const std::vector<Point>& grid, int grid_step, Point shift,
                               const std::vector<int>& grey_planes, uchar* desc, uchar* fg)
{
    const Template& top = tp[L * M];
    const Point anchor = Point(top.width / 2, top.height / 2) + shift;
    const int G = static_cast<int>(grid.size());
    if (!patch.mask.empty())
    {
        for (int m = 0; m < M; ++m)
            for (int g = 0; g < G; ++g)
            {
                const Point p = anchor + grid[g];
                const int j = m * G + g;
                desc[j] = 0;
                fg[j] = 0;
                if (p.x >= 0 && p.y >= 0 && p.x < patch.mask.cols && p.y < patch.mask.rows
                    && patch.mask.at<uchar>(p))
                {
                    desc[j] = patch.quantized[m].at<uchar>(p);
                    fg[j] = 1;
                }
            }
        return;
    }
    // synthetic template (features only): a grid point takes the label of a feature within half
    // a grid step, and is foreground when it does
    const int r2 = std::max(1, (grid_step * grid_step) / 4);
    for (int m = 0; m < M; ++m)
    {
        const Template& t = tp[L * M + m];
        // a grey group's hue plane: the 8 hue bins merged into 7, as greyHueLabels() does for
        // the scene and the dense patches
        const bool grey = m < (int)grey_planes.size() && grey_planes[m] != 0;
        for (int g = 0; g < G; ++g)
        {
            const Point p = anchor + grid[g];
            const int j = m * G + g;
            desc[j] = 0;
            fg[j] = 0;
            int best = INT_MAX;
            for (size_t k = 0; k < t.features.size(); ++k)
            {
                const int dx = t.features[k].x - p.x, dy = t.features[k].y - p.y;
                const int d2 = dx * dx + dy * dy;
                if (d2 <= r2 && d2 < best)
                {
                    best = d2;
                    const int label = t.features[k].label;
                    desc[j] = static_cast<uchar>(1 << (grey ? label * 7 / 8 : label));
                    fg[j] = 1;
                }
            }
        }
    }
}

// The search groups (DetectorParams::group_size_ratio, max_group_classes): classes sorted by
// the size of their largest template at the coarsest level, grouped greedily. Also the global
// forest row -> template table.
static void buildGroups(Detector::Impl& impl,
                        const std::map<String, std::vector<TemplatePyramid> >& class_templates,
                        int M, int L, const std::vector<int>& grey_hue)
{
    impl.rows.clear();
    // (colourless, size), class: with grey_hue_label, classes without hue (most of their
    // templates have no hue feature) form groups of their own, whose forests read the grey label
    std::vector<std::pair<std::pair<int, int>, String> > by_size;
    std::map<String, int> first_row;
    for (std::map<String, std::vector<TemplatePyramid> >::const_iterator it = class_templates.begin();
         it != class_templates.end(); ++it)
    {
        if (it->second.empty())
            continue;
        int extent = 1;
        first_row[it->first] = (int)impl.rows.size();
        for (size_t i = 0; i < it->second.size(); ++i)
        {
            const Template& top = it->second[i][L * M];
            extent = std::max(extent, std::max(top.width, top.height) + 1);
            TemplateRef ref;
            ref.class_id = it->first;
            ref.template_id = static_cast<int>(i);
            impl.rows.push_back(ref);
        }
        int colourless = 0;
        bool has_hue = false;
        for (int m = 0; m < M && m < (int)grey_hue.size(); ++m)
            if (grey_hue[m])
            {
                has_hue = true;
                int without = 0;
                for (size_t i = 0; i < it->second.size(); ++i)
                    without += it->second[i][L * M + m].features.empty();
                colourless = 2 * without > (int)it->second.size();
            }
        if (!has_hue)
            colourless = 0;
        by_size.push_back(std::make_pair(std::make_pair(colourless, extent), it->first));
    }
    std::sort(by_size.begin(), by_size.end());
    const float ratio = impl.params.group_size_ratio;
    const int max_classes = impl.params.max_group_classes;
    // the units grouped by size: whole classes, or (group_templates) every template on its own,
    // so that the views of one class at different distances get windows of their own
    struct Unit
    {
        bool grey;
        int extent;
        String class_id;
        int row; //!< first row of the unit
        int n;   //!< rows of the unit
        bool operator<(const Unit& b) const
        {
            if (grey != b.grey)
                return !grey;
            if (extent != b.extent)
                return extent < b.extent;
            if (class_id != b.class_id)
                return class_id < b.class_id;
            return row < b.row;
        }
    };
    std::vector<Unit> units;
    for (size_t k = 0; k < by_size.size(); ++k)
    {
        const String& cls = by_size[k].second;
        const std::vector<TemplatePyramid>& tps = class_templates.find(cls)->second;
        const bool grey = by_size[k].first.first != 0;
        if (!impl.params.group_templates)
        {
            Unit u = { grey, by_size[k].first.second, cls, first_row[cls], (int)tps.size() };
            units.push_back(u);
            continue;
        }
        for (size_t i = 0; i < tps.size(); ++i)
        {
            const Template& top = tps[i][L * M];
            Unit u = { grey, std::max(top.width, top.height) + 1, cls,
                       first_row[cls] + (int)i, 1 };
            units.push_back(u);
        }
    }
    if (impl.params.group_templates)
        std::sort(units.begin(), units.end());
    impl.groups.clear();
    int group_extent = 0;
    for (size_t k = 0; k < units.size(); ++k)
    {
        const Unit& u = units[k];
        bool fits = !impl.groups.empty() && impl.groups.back().grey == u.grey
            && (ratio <= 0.f || u.extent <= ratio * group_extent);
        if (fits && max_classes > 0)
        {
            const std::vector<String>& cl = impl.groups.back().classes;
            fits = std::find(cl.begin(), cl.end(), u.class_id) != cl.end()
                || (int)cl.size() < max_classes;
        }
        if (!fits)
        {
            impl.groups.push_back(SearchGroup());
            impl.groups.back().grey = u.grey;
            group_extent = u.extent;
        }
        SearchGroup& g = impl.groups.back();
        if (std::find(g.classes.begin(), g.classes.end(), u.class_id) == g.classes.end())
            g.classes.push_back(u.class_id);
        for (int i = 0; i < u.n; ++i)
            g.rows.push_back(u.row + i);
    }
}

// The descriptor geometry of a group (paper: the sample locations r of the templates): a
// grid_size x grid_size grid over the group's largest template at the coarsest level, for every
// modality. Returns the grid step (pixels).
static double buildGeometry(const Detector::Impl& impl, SearchGroup& group,
                            const std::map<String, std::vector<TemplatePyramid> >& class_templates,
                            int M, int L)
{
    int half = 1;
    for (size_t r = 0; r < group.rows.size(); ++r)
    {
        const TemplateRef& ref = impl.rows[group.rows[r]];
        const Template& top = class_templates.find(ref.class_id)->second[ref.template_id][L * M];
        half = std::max(half, (std::max(top.width, top.height) + 1) / 2);
    }
    const int G = impl.params.grid_size;
    const double step = 2.0 * half / G;
    group.grid.clear();
    for (int gy = 0; gy < G; ++gy)
        for (int gx = 0; gx < G; ++gx)
            group.grid.push_back(Point(cvFloor(-half + (gx + 0.5) * step),
                                       cvFloor(-half + (gy + 0.5) * step)));
    const int P = static_cast<int>(group.grid.size());
    group.plane_of.resize(M * P);
    group.dim_offset.resize(M * P);
    for (int m = 0; m < M; ++m)
        for (int g = 0; g < P; ++g)
        {
            group.plane_of[m * P + g] = m;
            group.dim_offset[m * P + g] = group.grid[g];
        }
    return step;
}

// Everything training derives from the templates besides the forests themselves: the search
// groups, their descriptor geometry, every template's descriptors (with shifted samples) per
// group, the flat-window and depth-range rejection limits. Deterministic; load() runs it too and
// reads the trained forests. desc / fg / ids: one matrix per group; ids are group rows.
static void prepareTraining(Detector::Impl& impl,
                            std::map<String, std::vector<TemplatePyramid> >& class_templates,
                            int M, int L, int T, const std::vector<int>& grey_hue,
                            std::vector<Mat>& descs, std::vector<Mat>& fgs, std::vector<Mat>& idss)
{
    buildGroups(impl, class_templates, M, L, grey_hue);

    // each template also as seen from locations up to `a` pixels off its anchor (the scene is
    // queried every location_step pixels): doc/forest.md, "Misaligned windows"
    const int S = locationStep(impl.params, T);
    const int a = S / 2;
    std::vector<Point> shifts;
    // in strides of dominant_window - 1: the dominant labels absorb the pixel in between
    // (doc/detector.md: 9 instead of 25 samples per template, fewer candidates, more rejection)
    const int sstride = std::max(1, impl.params.dominant_window - 1);
    for (int dy = -a; dy <= a; dy += sstride)
        for (int dx = -a; dx <= a; dx += sstride)
            shifts.push_back(Point(dx, dy));
    const int R = static_cast<int>(shifts.size());
    const int NG = (int)impl.groups.size();
    descs.assign(NG, Mat());
    fgs.assign(NG, Mat());
    idss.assign(NG, Mat());
    for (int gi = 0; gi < NG; ++gi)
    {
        SearchGroup& group = impl.groups[gi];
        const double step = buildGeometry(impl, group, class_templates, M, L);
        const int P = static_cast<int>(group.grid.size());
        const int N = (int)group.rows.size();
        Mat& desc = descs[gi];
        Mat& fg = fgs[gi];
        Mat& ids = idss[gi];
        desc.create(N * R, M * P, CV_8U);
        fg.create(N * R, M * P, CV_8U);
        ids.create(N * R, 1, CV_32S);
        for (int r = 0; r < N; ++r)
        {
            const TemplateRef& ref = impl.rows[group.rows[r]];
            const TemplatePyramid& tp = class_templates[ref.class_id][ref.template_id];
            const std::vector<DensePatch>& patches = impl.patches[ref.class_id];
            DensePatch patch;
            if (ref.template_id < (int)patches.size() && !patches[ref.template_id].mask.empty())
            {
                // the descriptor reads the dominant labels, as the scene's windows (match())
                const DensePatch& raw = patches[ref.template_id];
                patch.mask = raw.mask;
                patch.quantized.resize(raw.quantized.size());
                for (size_t m = 0; m < raw.quantized.size(); ++m)
                {
                    Mat q = raw.quantized[m];
                    if (group.grey && m < grey_hue.size() && grey_hue[m])
                        greyHueLabels(raw.quantized[m], raw.mask, q);
                    dominantLabels(q, raw.mask, impl.params.dominant_window, patch.quantized[m]);
                }
            }
            for (int k = 0; k < R; ++k)
            {
                templateDescriptor(tp, patch, M, L, group.grid, std::max(1, cvRound(step)),
                                   shifts[k], group.grey ? grey_hue : std::vector<int>(),
                                   desc.ptr(r * R + k), fg.ptr(r * R + k));
                ids.at<int>(r * R + k) = r;
            }
        }
        // flat-window rejection: the fewest labelled values any training descriptor has (the
        // grey hue label does not count: a uniform grey window stays flat)
        group.flat_mask.assign(M * P, 0xFF);
        for (int m = 0; m < M; ++m)
            if (group.grey && m < (int)grey_hue.size() && grey_hue[m])
                for (int g = 0; g < P; ++g)
                {
                    group.flat_mask[m * P + g] = (uchar)~GREY_BIT;
                    group.plane_of[m * P + g] = M + m; // the scene's grey-labelled hue plane
                }
        group.min_labels = M * P;
        for (int i = 0; i < desc.rows; ++i)
        {
            const uchar* d = desc.ptr(i);
            int labels = 0;
            for (int j = 0; j < M * P; ++j)
                labels += (d[j] & group.flat_mask[j]) != 0;
            group.min_labels = std::min(group.min_labels, labels);
        }
    }
    // out-of-depth-range rejection: the templates' depth range, probed at the anchor and around
    // it within a third of the smallest template
    impl.z_min = INT_MAX;
    impl.z_max = INT_MIN;
    int min_half = INT_MAX;
    for (size_t r = 0; r < impl.rows.size(); ++r)
    {
        const TemplateRef& ref = impl.rows[r];
        const Template& top = class_templates[ref.class_id][ref.template_id][L * M];
        min_half = std::min(min_half, std::max(1, std::min(top.width, top.height) / 2));
        const std::vector<std::vector<Point3i> >& dz = impl.depth[ref.class_id];
        if (ref.template_id < (int)dz.size())
            for (size_t k = 0; k < dz[ref.template_id].size(); ++k)
            {
                impl.z_min = std::min(impl.z_min, dz[ref.template_id][k].z);
                impl.z_max = std::max(impl.z_max, dz[ref.template_id][k].z);
            }
    }
    if (impl.z_min > impl.z_max)
        impl.z_min = impl.z_max = 0; // no depth samples: no range check
    impl.depth_probe.clear();
    const int h3 = std::max(1, min_half / 3);
    for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx)
            impl.depth_probe.push_back(Point(dx * h3, dy * h3));
}

void Detector::train()
{
    AutoLock lock(impl_->mutex);
    Impl& impl = *impl_;
    const int M = static_cast<int>(modalities.size());
    if (M == 0)
        CV_Error(Error::StsError, "forestmod::Detector::train: the detector has no modalities");
    const int N = numTemplates();
    if (N == 0)
        CV_Error(Error::StsError, "forestmod::Detector::train: no templates (addTemplate first)");
    const int L = pyramid_levels - 1;

    std::vector<Mat> descs, fgs, idss;
    impl.trained = false;
    prepareTraining(impl, class_templates, M, L, T_at_level[L],
                    hueModalities(modalities, impl.params), descs, fgs, idss);

    for (size_t gi = 0; gi < impl.groups.size(); ++gi)
    {
        SearchGroup& group = impl.groups[gi];
        ForestParams fp = impl.params.forest;
        if (fp.max_depth <= 0)
        {
            // paper: 8 for one object, 9 for several. Here: 8, deeper when the group has more
            // samples (templates x shifts) than that gives leaves for, plus one level per
            // doubling of the detector's classes: a location leaves only when every group
            // rejects it, so each group must accept less background the more classes there are
            // (the paper's +1 for several objects, generalised; doc/detector.md)
            const int C = (int)class_templates.size();
            const int paper = C > 1 ? 9 : 8;
            int depth = paper;
            // never deeper than log2(samples) + 1: the splits have nothing left to separate
            // and only overfit (LM-O can alone, 432 samples: depth 11 lost 3 of 10 rendered
            // scenes that depth 8 finds)
            if (impl.params.auto_depth_leaf_samples > 0.f)
            {
                const double samples = std::max(1, descs[gi].rows);
                const int by_samples = (int)std::ceil(std::log2(std::max(
                    1.0, samples / (double)impl.params.auto_depth_leaf_samples)));
                depth = std::max(8, by_samples) + (int)std::ceil(std::log2((double)C));
                depth = std::min(depth, (int)std::ceil(std::log2(samples)) + 1);
                depth = std::max(depth, 8); // the paper's depth for one object is the floor
            }
            fp.max_depth = std::min(depth, 20);
        }
        Ptr<TemplateForest> forest = TemplateForest::create(fp);
        forest->train(descs[gi], fgs[gi], idss[gi]);
        group.forest = forest;
    }
    impl.trained = true;
}

// ---------------------------------------------------------------------------------------------
// Frame quantization: once per frame, every later stage reads these maps in place.
static void quantizeFrame(const std::vector<Ptr<Modality> >& modalities,
                          const std::vector<int>& T_at_level, const std::vector<Mat>& sources,
                          const std::vector<Mat>& masks, int pad0,
                          std::vector<LevelMaps>& levels, OutputArrayOfArrays quantized_images)
{
    const int M = static_cast<int>(modalities.size());
    const int levels_n = static_cast<int>(T_at_level.size());
    levels.assign(levels_n, LevelMaps());
    std::vector<Ptr<QuantizedPyramid> > qps(M);
    for (int i = 0; i < M; ++i)
        qps[i] = modalities[i]->process(sources[i], masks.empty() ? Mat() : masks[i]);
    if (quantized_images.needed())
        quantized_images.create(1, levels_n * M, CV_8U);
    for (int l = 0; l < levels_n; ++l)
    {
        LevelMaps& lm = levels[l];
        lm.T = T_at_level[l];
        lm.pad = pad0;
        lm.quantized.resize(M);
        lm.spread.resize(M);
        lm.response.resize(M);
        for (int i = 0; i < M; ++i)
        {
            if (l > 0)
                qps[i]->pyrDown();
            qps[i]->quantize(lm.quantized[i]);
            lm.size = lm.quantized[i].size();
            detail::spreadLabels(lm.quantized[i], lm.spread[i], lm.T, lm.pad);
            detail::computeResponseMaps(lm.spread[i], lm.response[i]);
            if (quantized_images.needed())
                lm.quantized[i].copyTo(quantized_images.getMatRef(l * M + i));
        }
    }
}

namespace {
struct MatchLess
{
    bool operator()(const Match& a, const Match& b) const { return a < b; }
};
} // namespace

// A template's depth samples with its pose geometry (detail::DepthTemplate); no samples: null
// samples, no pose: focal lengths 0.
static detail::DepthTemplate depthTemplate(const Detector::Impl& impl, const String& class_id,
                                           int template_id)
{
    detail::DepthTemplate t;
    const std::map<String, std::vector<std::vector<Point3i> > >::const_iterator dit
        = impl.depth.find(class_id);
    if (dit == impl.depth.end() || template_id >= (int)dit->second.size()
        || dit->second[template_id].empty())
        return t;
    t.samples = &dit->second[template_id];
    const std::map<String, std::vector<TemplatePose> >::const_iterator pit
        = impl.poses.find(class_id);
    if (pit == impl.poses.end() || template_id >= (int)pit->second.size())
        return t;
    const TemplatePose& p = pit->second[template_id];
    const Vec3d c = p.K * p.t;
    // c[2] > 0 also refuses a K whose last row is not (0, 0, 1) (a corrupt model file)
    if (!p.valid || p.K(0, 0) <= 0 || p.K(1, 1) <= 0 || p.t[2] <= 0 || !(c[2] > 0))
        return t;
    t.fx = (float)p.K(0, 0);
    t.fy = (float)p.K(1, 1);
    t.pp = Point2f((float)(p.K(0, 2) - p.box.x), (float)(p.K(1, 2) - p.box.y));
    t.centre = Point2f((float)(c[0] / c[2] - p.box.x), (float)(c[1] / c[2] - p.box.y));
    return t;
}

// LINEMOD's pyramid refinement of coarse matches (identical arithmetic). With `depth` and the
// template's depth samples, the samples join the score at every level like the features of one
// more modality, at the position the features chose (`depth`: one detail::DepthContext per
// pyramid level).
static void refineMatches(const std::vector<LevelMaps>& levels, const TemplatePyramid& tp, int M,
                          float threshold, std::vector<Match>& cands,
                          const detail::DepthContext* depth = 0,
                          const detail::DepthTemplate* dt = 0)
{
    const int samples = depth && dt && dt->samples ? (int)dt->samples->size() : 0;
    const int levels_n = static_cast<int>(levels.size());
    for (int l = levels_n - 2; l >= 0; --l)
    {
        const LevelMaps& lm = levels[l];
        const int T = lm.T;
        const int border = 8 * T;
        const int offset = T / 2 + (T % 2 - 1);
        const int max_x = lm.size.width - tp[l * M].width - border;
        const int max_y = lm.size.height - tp[l * M].height - border;
        for (size_t k = 0; k < cands.size(); ++k)
        {
            Match& m = cands[k];
            int x = m.x * 2 + 1, y = m.y * 2 + 1;
            x = std::max(x, border);
            y = std::max(y, border);
            x = std::min(x, max_x);
            y = std::min(y, max_y);
            int num_features = 0, best = 0, best_r = -1, best_c = -1;
            const int ox = (x / T - 8) * T, oy = (y / T - 8) * T;
            for (int r = 0; r < 16; ++r)
                for (int c = 0; c < 16; ++c)
                {
                    const int s = detail::similarityAll(lm, tp, l, Point(ox + c * T, oy + r * T),
                                                        &num_features);
                    if (s > best)
                    {
                        best = s;
                        best_r = r;
                        best_c = c;
                    }
                }
            m.x = (x / T - 8 + best_c) * T + offset;
            m.y = (y / T - 8 + best_r) * T + offset;
            const int ns = detail::depthSamplesAtLevel(samples, num_features, M);
            if (ns > 0)
            {
                best += detail::depthSimilarity(depth[l], *dt, Point(m.x << l, m.y << l), ns);
                num_features += ns;
            }
            m.similarity = num_features ? (best * 100.f) / (4 * num_features) : 0.f;
        }
        std::vector<Match> kept;
        for (size_t k = 0; k < cands.size(); ++k)
            if (!(cands[k].similarity < threshold))
                kept.push_back(cands[k]);
        cands.swap(kept);
    }
}

static int rawThreshold(float threshold, int num_features)
{
    return static_cast<int>(2 * num_features + (threshold / 100.f) * (2 * num_features) + 0.5f);
}

static void nonMaximumSuppression(std::vector<Match>& matches,
                                  const std::map<String, std::vector<TemplatePyramid> >& ct,
                                  float iou)
{
    std::vector<Match> kept;
    std::vector<Rect> boxes;
    for (size_t i = 0; i < matches.size(); ++i)
    {
        const Template& t0 = ct.find(matches[i].class_id)->second[matches[i].template_id][0];
        const Rect box(matches[i].x, matches[i].y, std::max(1, t0.width), std::max(1, t0.height));
        bool keep = true;
        for (size_t j = 0; j < boxes.size() && keep; ++j)
        {
            const double inter = (box & boxes[j]).area();
            const double uni = box.area() + boxes[j].area() - inter;
            keep = uni <= 0 || inter / uni <= iou;
        }
        if (keep)
        {
            kept.push_back(matches[i]);
            boxes.push_back(box);
        }
    }
    matches.swap(kept);
}

void Detector::match(const std::vector<Mat>& sources, float threshold, std::vector<Match>& matches,
                     const std::vector<String>& class_ids, OutputArrayOfArrays quantized_images,
                     const std::vector<Mat>& masks) const
{
    match(sources, threshold, matches, class_ids, quantized_images, masks, 0);
}

void Detector::match(const std::vector<Mat>& sources, float threshold, std::vector<Match>& matches,
                     const std::vector<String>& class_ids, OutputArrayOfArrays quantized_images,
                     const std::vector<Mat>& masks, DetectionStats* stats) const
{
    matchImpl(sources, threshold, matches, class_ids, quantized_images, masks, stats, true);
}

void Detector::matchImpl(const std::vector<Mat>& sources, float threshold,
                         std::vector<Match>& matches, const std::vector<String>& class_ids,
                         OutputArrayOfArrays quantized_images, const std::vector<Mat>& masks,
                         DetectionStats* stats, bool nms) const
{
    const int64 t0 = getTickCount();
    matches.clear();
    checkSources(modalities, sources, masks, "match");
    if (numTemplates() == 0)
        CV_Error(Error::StsError, "forestmod::Detector::match: the detector has no templates");
    Impl& impl = *impl_;
    const DetectorParams& params = impl.params;
    if (params.use_forest && !impl.trained)
        const_cast<Detector*>(this)->train(); // automatic training after templates changed

    const int M = static_cast<int>(modalities.size());
    const int L = pyramid_levels - 1;

    // which classes
    std::vector<String> classes;
    if (class_ids.empty())
        classes = classIds();
    else
        for (size_t i = 0; i < class_ids.size(); ++i)
            if (class_templates.count(class_ids[i]))
                classes.push_back(class_ids[i]);

    int max_extent = 0;
    for (std::map<String, std::vector<TemplatePyramid> >::const_iterator it = class_templates.begin();
         it != class_templates.end(); ++it)
        for (size_t i = 0; i < it->second.size(); ++i)
            max_extent = std::max(max_extent, std::max(it->second[i][0].width,
                                                       it->second[i][0].height));

    std::vector<LevelMaps> levels;
    quantizeFrame(modalities, T_at_level, sources, masks, 0, levels, quantized_images);
    const int dm = depthModality(modalities);
    // depth as a validation modality (forest search only: the exhaustive mode is plain LINEMOD)
    // per pyramid level: a candidate's position there is known to +-T / 2 pixels (to +-S / 2 at
    // the coarsest level, below), so the scene's depth range is taken over squares of that
    // radius (level 0 pixels)
    std::vector<detail::DepthContext> depth_ctx;
    const bool use_depth = dm >= 0 && params.depth_samples > 0 && params.use_forest;
    if (use_depth)
    {
        depth_ctx.resize(pyramid_levels);
        // the coarsest level only when depth is scored there (depth_coarse)
        const int last = params.depth_coarse > 0 ? L : L - 1;
        for (int l = 0; l <= last; ++l)
        {
            const int step = l == L ? std::min(locationStep(params, T_at_level[L]), T_at_level[L])
                                    : T_at_level[l];
            depth_ctx[l].set(sources[dm], (step / 2) << l);
            depth_ctx[l].tolerance = params.depth_tolerance;
            depth_ctx[l].scale_shift = l;
        }
    }
    const int64 t1 = getTickCount();
    const LevelMaps& top = levels[L];
    const int T = top.T;
    const int offsetL = T / 2 + (T % 2 - 1);

    std::vector<Match> coarse; // (class, template) coarse matches, x/y as LINEMOD reports them
    double t_tree = 0, t_valid = 0;
    if (!params.use_forest)
    {
        // exhaustive: every template at every grid position where it fits (LINEMOD)
        for (size_t ci = 0; ci < classes.size(); ++ci)
        {
            const std::vector<TemplatePyramid>& tps = class_templates.find(classes[ci])->second;
            std::vector<std::vector<Match> > per(tps.size());
            parallel_for_(Range(0, (int)tps.size()), [&](const Range& range) {
                for (int id = range.start; id < range.end; ++id)
                {
                    const TemplatePyramid& tp = tps[id];
                    const Template& t = tp[L * M];
                    const int W = top.size.width / T, H = top.size.height / T;
                    const int span_x = W - ((t.width - 1) / T + 1);
                    const int span_y = H - ((t.height - 1) / T + 1);
                    int nf = 0;
                    for (int m = 0; m < M; ++m)
                        nf += (int)tp[L * M + m].features.size();
                    const int raw_thr = rawThreshold(threshold, nf);
                    for (int r = 0; r <= span_y; ++r)
                        for (int c = 0; c <= span_x; ++c)
                        {
                            const int raw = detail::similarityAll(top, tp, L, Point(c * T, r * T));
                            if (raw > raw_thr)
                                per[id].push_back(Match(c * T + offsetL, r * T + offsetL,
                                                        (raw * 100.f) / (4 * nf) + 0.5f,
                                                        classes[ci], id));
                        }
                    refineMatches(levels, tp, M, threshold, per[id]);
                }
            });
            for (size_t id = 0; id < per.size(); ++id)
                matches.insert(matches.end(), per[id].begin(), per[id].end());
        }
        t_valid = (getTickCount() - t1) * 1000.0 / getTickFrequency();
        if (stats)
        {
            stats->locations += (int64)(top.size.width / T) * (top.size.height / T);
            stats->validated += stats->locations;
        }
    }
    else
    {
        std::vector<uchar> class_allowed(impl.rows.size(), 1);
        if (!class_ids.empty())
            for (size_t r = 0; r < impl.rows.size(); ++r)
                class_allowed[r] = std::find(classes.begin(), classes.end(),
                                             impl.rows[r].class_id) != classes.end();
        // the search groups that hold an allowed class (each: its window, forest, flat limit)
        std::vector<const SearchGroup*> groups;
        for (size_t gi = 0; gi < impl.groups.size(); ++gi)
        {
            bool any = false;
            for (size_t k = 0; k < impl.groups[gi].rows.size() && !any; ++k)
                any = class_allowed[impl.groups[gi].rows[k]] != 0;
            if (any)
                groups.push_back(&impl.groups[gi]);
        }
        const int NG = (int)groups.size();
        const int S = std::min(locationStep(params, T), T);
        const int W = (top.size.width + S - 1) / S, H = (top.size.height + S - 1) / S;
        // planes M + m: the grey-labelled view of hue plane m, for the colourless groups
        std::vector<const uchar*> planes(2 * M, (const uchar*)0);
        // the forest reads the plain quantized images (one label per point, as the templates it
        // was trained on; spreading would add labels and mislead the splits: doc/forest.md) up to
        // half a template around a location: a zero border of that size keeps every read inside
        // the buffer without a bounds check per value
        std::vector<Mat> bordered(2 * M);
        const std::vector<int> grey_hue = hueModalities(modalities, params);
        bool any_grey = false;
        for (int gi = 0; gi < NG; ++gi)
            any_grey = any_grey || groups[gi]->grey;
        const int B = (max_extent >> L) + 2 * T + 2;
        for (int m = 0; m < M; ++m)
        {
            Mat dominant;
            dominantLabels(top.quantized[m], Mat(), params.dominant_window, dominant);
            copyMakeBorder(dominant, bordered[m], B, B, B, B, BORDER_CONSTANT, Scalar(0));
            planes[m] = bordered[m].ptr();
            if (any_grey && grey_hue[m])
            {
                Mat q;
                greyHueLabels(top.quantized[m], Mat(), q);
                dominantLabels(q, Mat(), params.dominant_window, dominant);
                copyMakeBorder(dominant, bordered[M + m], B, B, B, B, BORDER_CONSTANT, Scalar(0));
                planes[M + m] = bordered[M + m].ptr();
            }
        }
        const size_t step = bordered[0].step;
        std::vector<std::vector<int> > deltas(NG);
        std::vector<int> min_labels(NG, 0);
        for (int gi = 0; gi < NG; ++gi)
        {
            const int D = static_cast<int>(groups[gi]->plane_of.size());
            deltas[gi].resize(D);
            for (int j = 0; j < D; ++j)
                deltas[gi][j] = groups[gi]->dim_offset[j].y * (int)step
                    + groups[gi]->dim_offset[j].x;
            if (params.min_window_labels > 0)
                min_labels[gi] = std::max(1, cvCeil(params.min_window_labels
                                                    * groups[gi]->min_labels));
        }

        Mat rejection_map;
        if (stats)
            rejection_map.create(H, W, CV_16SC1);
        // per location: forest -> candidates -> breadth-first validation -> best survivor
        std::vector<std::vector<Match> > per_row(H);
        std::vector<std::vector<int64> > row_at_depth(H);
        std::vector<double> row_tree(H, 0), row_valid(H, 0);
        std::vector<int64> row_validated(H, 0), row_cands(H, 0), row_flat(H, 0),
            row_deprange(H, 0), row_forest_rej(H, 0), row_locations(H, 0);
        const bool check_depth = dm >= 0 && params.depth_range_margin > 0
            && impl.z_max > 0;
        const Mat scene_depth = dm >= 0 ? sources[dm] : Mat();
        // a coarse candidate's template lies within [tl, tl + S] (its location misses the
        // anchor by up to S / 2): its depth samples are read at the middle
        // (at the coarsest level only with depth_coarse; the refinement levels below read the
        // samples of the few refined matches)
        const bool coarse_depth = use_depth && params.depth_coarse > 0;
        std::vector<detail::DepthTemplate> row_depth;
        if (coarse_depth)
        {
            depth_ctx[L].shift = Point(S / 2, S / 2);
            row_depth.resize(impl.rows.size());
            for (size_t r = 0; r < impl.rows.size(); ++r)
                row_depth[r] = depthTemplate(impl, impl.rows[r].class_id,
                                             impl.rows[r].template_id);
        }
        const detail::DepthContext* dctx = coarse_depth ? &depth_ctx[L] : 0;
        const int z_lo = impl.z_min - params.depth_range_margin;
        const int z_hi = impl.z_max + params.depth_range_margin;
        parallel_for_(Range(0, H), [&](const Range& range) {
            std::vector<int> cands, group_cands;
            std::vector<detail::ValidationCandidate> vc;
            std::vector<int> survivors;
            for (int r = range.start; r < range.end; ++r)
            {
                for (int c = 0; c < W; ++c)
                {
                    const int64 q0 = getTickCount();
                    ++row_locations[r];
                    // before the forest: out of the templates' depth range
                    if (check_depth)
                    {
                        int known = 0, inside = 0;
                        for (size_t k = 0; k < impl.depth_probe.size() && !inside; ++k)
                        {
                            // issue 18: probes left of / above the frame are negative:
                            // multiply, a left shift of a negative value is undefined
                            const int x = (c * S + impl.depth_probe[k].x) * (1 << L);
                            const int y = (r * S + impl.depth_probe[k].y) * (1 << L);
                            if (x < 0 || y < 0 || x >= scene_depth.cols || y >= scene_depth.rows)
                                continue;
                            const int z = scene_depth.at<ushort>(y, x);
                            if (!z)
                                continue;
                            ++known;
                            inside += z >= z_lo && z <= z_hi;
                        }
                        if (known && !inside)
                        {
                            ++row_deprange[r];
                            if (stats)
                                rejection_map.at<short>(r, c) = -3;
                            row_tree[r] += (double)(getTickCount() - q0);
                            continue;
                        }
                    }
                    // every search group: a flat window, or its forest (rejectors, splits, all
                    // trees); the location leaves when every group rejects it, the candidates
                    // are the union of the groups' leaves (as global rows)
                    cands.clear();
                    int flat = 0, deepest = -1;
                    bool accepted = false;
                    for (int gi = 0; gi < NG; ++gi)
                    {
                        const SearchGroup& grp = *groups[gi];
                        LocationView view;
                        view.planes = &planes[0];
                        view.plane_of = &grp.plane_of[0];
                        view.delta = &deltas[gi][0];
                        view.offset = (ptrdiff_t)(r * S + B) * (ptrdiff_t)step + (c * S + B);
                        if (min_labels[gi] > 0)
                        {
                            const int D = (int)grp.plane_of.size();
                            int labels = 0;
                            for (int j = 0; j < D; ++j)
                                labels += (view.value(j) & grp.flat_mask[j]) != 0;
                            if (labels < min_labels[gi])
                            {
                                ++flat;
                                continue;
                            }
                        }
                        int depth = -1;
                        if (!grp.forest->query(view, group_cands, &depth))
                        {
                            deepest = std::max(deepest, depth);
                            continue;
                        }
                        accepted = true;
                        for (size_t k = 0; k < group_cands.size(); ++k)
                            cands.push_back(grp.rows[group_cands[k]]);
                    }
                    const int64 q1 = getTickCount();
                    row_tree[r] += (double)(q1 - q0);
                    if (!accepted)
                    {
                        if (flat == NG)
                            ++row_flat[r];
                        else
                        {
                            ++row_forest_rej[r];
                            if ((int)row_at_depth[r].size() <= deepest)
                                row_at_depth[r].resize(deepest + 1, 0);
                            ++row_at_depth[r][deepest];
                        }
                        if (stats)
                            rejection_map.at<short>(r, c) = (short)(flat == NG ? -2 : deepest);
                        continue;
                    }
                    if (stats)
                        rejection_map.at<short>(r, c) = -1;
                    if (cands.empty())
                        continue;
                    if (NG > 1)
                        std::sort(cands.begin(), cands.end());
                    vc.clear();
                    for (size_t k = 0; k < cands.size(); ++k)
                    {
                        const int row = cands[k];
                        if (!class_allowed[row])
                            continue;
                        const TemplateRef& ref = impl.rows[row];
                        const TemplatePyramid& tp
                            = class_templates.find(ref.class_id)->second[ref.template_id];
                        const Template& t = tp[L * M];
                        detail::ValidationCandidate v;
                        v.index = row;
                        v.tp = &tp;
                        v.depth = coarse_depth && row_depth[row].samples ? &row_depth[row] : 0;
                        v.zoffset = 0;
                        v.zvalid = false;
                        // the true anchor lies within S/2 of the location; spread responses
                        // cover [p, p + T): start S/2 before
                        v.tl = Point(c * S - t.width / 2 - S / 2, r * S - t.height / 2 - S / 2);
                        v.raw = v.scored = 0;
                        v.total = 0;
                        for (int m = 0; m < M; ++m)
                            v.total += (int)tp[L * M + m].features.size();
                        vc.push_back(v);
                    }
                    if (vc.empty())
                        continue;
                    ++row_validated[r];
                    row_cands[r] += (int64)vc.size();
                    if (params.breadth_first)
                        detail::validateBreadthFirst(top, L, M, vc, params.chunk_size,
                                                     params.alpha, params.max_survivors,
                                                     survivors, dctx, params.depth_coarse >= 2);
                    else
                    {
                        detail::validateAll(top, L, vc, dctx);
                        survivors.clear();
                        for (size_t k = 0; k < vc.size(); ++k)
                            survivors.push_back((int)k);
                    }
                    // the survivors over the detection threshold go on to pyramid refinement
                    std::sort(survivors.begin(), survivors.end(), [&](int a, int b) {
                        return vc[a].raw * (int64)vc[b].total > vc[b].raw * (int64)vc[a].total;
                    });
                    for (size_t k = 0; k < survivors.size() && (int)k < params.max_survivors; ++k)
                    {
                        const detail::ValidationCandidate& v = vc[survivors[k]];
                        if (v.raw <= rawThreshold(threshold, v.total))
                            continue;
                        const TemplateRef& ref = impl.rows[v.index];
                        per_row[r].push_back(Match(v.tl.x + offsetL, v.tl.y + offsetL,
                                                   (v.raw * 100.f) / (4 * v.total) + 0.5f,
                                                   ref.class_id, ref.template_id));
                    }
                    row_valid[r] += (double)(getTickCount() - q1);
                }
            }
        });
        // refinement up the pyramid, per template
        const int64 r0 = getTickCount();
        for (int r = 0; r < H; ++r)
            coarse.insert(coarse.end(), per_row[r].begin(), per_row[r].end());
        parallel_for_(Range(0, (int)coarse.size()), [&](const Range& range) {
            for (int k = range.start; k < range.end; ++k)
            {
                std::vector<Match> one(1, coarse[k]);
                const TemplatePyramid& tp
                    = class_templates.find(coarse[k].class_id)->second[coarse[k].template_id];
                const detail::DepthTemplate dt = use_depth
                    ? depthTemplate(impl, coarse[k].class_id, coarse[k].template_id)
                    : detail::DepthTemplate();
                refineMatches(levels, tp, M, threshold, one, dt.samples ? &depth_ctx[0] : 0, &dt);
                if (one.empty())
                    coarse[k].similarity = -1.f;
                else
                    coarse[k] = one[0];
            }
        });
        for (size_t k = 0; k < coarse.size(); ++k)
            if (coarse[k].similarity >= 0.f)
                matches.push_back(coarse[k]);
        const double tick_ms = 1000.0 / getTickFrequency();
        double tree = 0, valid = 0;
        for (int r = 0; r < H; ++r)
        {
            tree += row_tree[r];
            valid += row_valid[r];
        }
        // per-row times are summed over threads: scale to the wall time of the whole stage
        const double wall = (double)(r0 - t1);
        const double busy = tree + valid;
        t_tree = busy > 0 ? wall * (tree / busy) * tick_ms : 0;
        t_valid = (busy > 0 ? wall * (valid / busy) : 0) * tick_ms
            + (getTickCount() - r0) * tick_ms;
        if (stats)
        {
            for (int r = 0; r < H; ++r)
            {
                const std::vector<int64>& at_depth = row_at_depth[r];
                stats->locations += row_locations[r];
                stats->rejected += row_forest_rej[r];
                if (stats->rejected_at_depth.size() < at_depth.size())
                    stats->rejected_at_depth.resize(at_depth.size(), 0);
                for (size_t d = 0; d < at_depth.size(); ++d)
                    stats->rejected_at_depth[d] += at_depth[d];
                stats->validated += row_validated[r];
                stats->candidates += row_cands[r];
                stats->rejected += row_flat[r] + row_deprange[r];
                stats->rejected_flat += row_flat[r];
                stats->rejected_depth_range += row_deprange[r];
            }
            stats->rejection_map = rejection_map;
        }
    }

    std::sort(matches.begin(), matches.end(), MatchLess());
    matches.erase(std::unique(matches.begin(), matches.end()), matches.end());
    if (nms && params.nms_iou > 0.f && params.nms_iou < 1.f)
        nonMaximumSuppression(matches, class_templates, params.nms_iou);
    if (stats)
    {
        const double tick_ms = 1000.0 / getTickFrequency();
        stats->t_quantize_ms += (t1 - t0) * tick_ms;
        stats->t_tree_ms += t_tree;
        stats->t_valid_ms += t_valid;
        stats->t_total_ms += (getTickCount() - t0) * tick_ms;
    }
}

void Detector::match(const std::vector<Mat>& sources, float threshold,
                     std::vector<PoseMatch>& matches, const std::vector<String>& class_ids,
                     const std::vector<Mat>& masks, DetectionStats* stats) const
{
    std::vector<Match> plain;
    match(sources, threshold, plain, class_ids, noArray(), masks, stats);
    matches.clear();
    for (size_t i = 0; i < plain.size(); ++i)
    {
        PoseMatch pm(plain[i]);
        const Template& t0 = class_templates.find(plain[i].class_id)->second[plain[i].template_id][0];
        pm.box = Rect(plain[i].x, plain[i].y, t0.width, t0.height);
        pm.pose = getTemplatePose(plain[i].class_id, plain[i].template_id);
        matches.push_back(pm);
    }
}

// ---------------------------------------------------------------------------------------------
// Persistence

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
    detail::checkPyramidGeometry(T, levels); // issue 18 (model_check)
    for (size_t i = 0; i < new_modalities.size(); ++i)
        detail::checkModality(new_modalities[i], (int)i); // issue 18 (model_check)
    DetectorParams p;
    if (!fn["forestmod_params"].empty())
    {
        p.read(fn["forestmod_params"]);
        // written before search groups existed: one window and one forest for all classes
        if (fn["forestmod_params"]["group_size_ratio"].empty())
        {
            p.group_size_ratio = 0.f;
            p.max_group_classes = 0;
        }
        // written before the grey hue label existed: the forests read the plain hue
        if (fn["forestmod_params"]["grey_hue_label"].empty())
            p.grey_hue_label = false;
        // written before template-level groups: whole classes were grouped
        if (fn["forestmod_params"]["group_templates"].empty())
            p.group_templates = false;
    }
    checkParams(p);
    AutoLock lock(impl_->mutex);
    modalities = new_modalities;
    pyramid_levels = levels;
    T_at_level = T;
    class_templates.clear();
    impl_->poses.clear();
    impl_->patches.clear();
    impl_->depth.clear();
    impl_->params = p;
    impl_->trained = false;
    impl_->groups.clear();
}

void Detector::write(FileStorage& fs) const
{
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
        detail::readMat(fn["R"], R, 9, "template pose R"); // issue 18 (model_check)
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

String Detector::readClass(const FileNode& fn, const String& class_id_override)
{
    if (fn.empty() || !fn.isMap())
        CV_Error(Error::StsParseError, "forestmod::Detector::readClass: expected a map node");
    // same layout as cv::linemod::Detector::writeClass, plus optional poses and patches
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
    const String class_id = class_id_override.empty() ? (String)fn["class_id"]
                                                       : class_id_override;
    if (class_id.empty())
        CV_Error(Error::StsParseError, "forestmod::Detector::readClass: no class_id");
    FileNode tps_fn = fn["template_pyramids"];
    if (tps_fn.empty() || !tps_fn.isSeq())
        CV_Error(Error::StsParseError, "forestmod::Detector::readClass: no template_pyramids");
    std::vector<TemplatePyramid> tpyramids;
    const int expected = pyramid_levels * static_cast<int>(modalities.size());
    int expected_id = 0;
    for (FileNodeIterator tps_it = tps_fn.begin(); tps_it != tps_fn.end(); ++tps_it, ++expected_id)
    {
        const int template_id = (*tps_it)["template_id"];
        if (template_id != expected_id)
            CV_Error(Error::StsParseError, "forestmod::Detector::readClass: template ids out of "
                                           "order (corrupt file?)");
        FileNode templates_fn = (*tps_it)["templates"];
        if ((int)templates_fn.size() != expected)
            CV_Error(Error::StsParseError, "forestmod::Detector::readClass: wrong number of "
                                           "templates in a pyramid (corrupt file?)");
        TemplatePyramid tp(expected);
        int k = 0;
        const String where = cv::format("class '%s', template %d", class_id.c_str(), expected_id);
        for (FileNodeIterator t_it = templates_fn.begin(); t_it != templates_fn.end(); ++t_it, ++k)
        {
            detail::checkTemplateNode(*t_it, where); // issue 18 (model_check)
            tp[k].read(*t_it);
        }
        detail::checkTemplatePyramid(tp, (int)modalities.size(), pyramid_levels, where); // issue 18
        tpyramids.push_back(tp);
    }
    std::vector<TemplatePose> poses(tpyramids.size());
    FileNode poses_fn = fn["forestmod_poses"];
    if (!poses_fn.empty())
    {
        if ((int)poses_fn.size() != (int)tpyramids.size())
            CV_Error(Error::StsParseError, "forestmod::Detector::readClass: number of poses and "
                                           "templates differ (corrupt file?)");
        int k = 0;
        for (FileNodeIterator it = poses_fn.begin(); it != poses_fn.end(); ++it, ++k)
        {
            poses[k] = readPose(*it);
            detail::checkTemplatePose(poses[k], tpyramids[k][0], cv::format(
                "class '%s', template %d", class_id.c_str(), k)); // issue 18 (model_check)
        }
    }
    std::vector<DensePatch> patches(tpyramids.size());
    FileNode patches_fn = fn["forestmod_patches"];
    if (!patches_fn.empty())
    {
        if ((int)patches_fn.size() != (int)tpyramids.size())
            CV_Error(Error::StsParseError, "forestmod::Detector::readClass: number of patches "
                                           "and templates differ (corrupt file?)");
        int k = 0;
        for (FileNodeIterator it = patches_fn.begin(); it != patches_fn.end(); ++it, ++k)
        {
            // issue 18 (model_check): the patch is the coarsest template's size + 1
            const Template& top = tpyramids[k].back();
            const int64 patch_size = (int64)(top.width + 1) * (top.height + 1);
            detail::readMat((*it)["mask"], patches[k].mask, patch_size, "template patch mask");
            FileNode q = (*it)["quantized"];
            for (FileNodeIterator qi = q.begin(); qi != q.end(); ++qi)
            {
                Mat m;
                detail::readMat(*qi, m, patch_size, "template patch"); // issue 18
                patches[k].quantized.push_back(m);
            }
            if (!patches[k].mask.empty()
                && (patches[k].quantized.size() != modalities.size()
                    || patches[k].mask.type() != CV_8UC1))
                CV_Error(Error::StsParseError, "forestmod::Detector::readClass: corrupt template "
                                               "patch");
            // issue 18 (model_check)
            detail::checkDensePatch(patches[k], tpyramids[k].back(), (int)modalities.size(),
                                    cv::format("class '%s', template %d", class_id.c_str(), k));
        }
    }
    std::vector<std::vector<Point3i> > depth(tpyramids.size());
    FileNode depth_fn = fn["forestmod_depth"];
    if (!depth_fn.empty())
    {
        if ((int)depth_fn.size() != (int)tpyramids.size())
            CV_Error(Error::StsParseError, "forestmod::Detector::readClass: number of depth "
                                           "sample sets and templates differ (corrupt file?)");
        int k = 0;
        for (FileNodeIterator it = depth_fn.begin(); it != depth_fn.end(); ++it, ++k)
        {
            Mat m;
            detail::readMat(*it, m, 256 * 3, "template depth samples"); // issue 18
            if (m.empty())
                continue;
            if (m.type() != CV_32S || m.cols != 3 || m.rows > 256)
                CV_Error(Error::StsParseError, "forestmod::Detector::readClass: corrupt depth "
                                               "samples (CV_32S, 3 columns, at most 256 rows)");
            for (int j = 0; j < m.rows; ++j)
                depth[k].push_back(Point3i(m.at<int>(j, 0), m.at<int>(j, 1), m.at<int>(j, 2)));
            detail::checkDepthSamples(depth[k], cv::format("class '%s', template %d",
                                      class_id.c_str(), k)); // issue 18 (model_check)
        }
    }
    AutoLock lock(impl_->mutex);
    class_templates[class_id] = tpyramids;
    impl_->poses[class_id] = poses;
    impl_->patches[class_id] = patches;
    impl_->depth[class_id] = depth;
    impl_->trained = false;
    return class_id;
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
    std::map<String, std::vector<TemplatePose> >::const_iterator pit = impl_->poses.find(class_id);
    fs << "forestmod_poses" << "[";
    for (size_t i = 0; i < tps.size(); ++i)
        writePose(fs, pit != impl_->poses.end() && i < pit->second.size() ? pit->second[i]
                                                                          : TemplatePose());
    fs << "]";
    std::map<String, std::vector<DensePatch> >::const_iterator dit = impl_->patches.find(class_id);
    fs << "forestmod_patches" << "[";
    for (size_t i = 0; i < tps.size(); ++i)
    {
        fs << "{";
        if (dit != impl_->patches.end() && i < dit->second.size() && !dit->second[i].mask.empty())
        {
            fs << "mask" << dit->second[i].mask;
            fs << "quantized" << "[";
            for (size_t m = 0; m < dit->second[i].quantized.size(); ++m)
                fs << dit->second[i].quantized[m];
            fs << "]";
        }
        fs << "}";
    }
    fs << "]";
    std::map<String, std::vector<std::vector<Point3i> > >::const_iterator zit
        = impl_->depth.find(class_id);
    fs << "forestmod_depth" << "[";
    for (size_t i = 0; i < tps.size(); ++i)
    {
        Mat m;
        if (zit != impl_->depth.end() && i < zit->second.size() && !zit->second[i].empty())
            m = Mat(zit->second[i]).reshape(1).clone();
        fs << m;
    }
    fs << "]";
}

void Detector::readClasses(const std::vector<String>& class_ids, const String& format)
{
    for (size_t i = 0; i < class_ids.size(); ++i)
    {
        const String filename = cv::format(format.c_str(), class_ids[i].c_str());
        FileStorage fs(filename, FileStorage::READ);
        if (!fs.isOpened())
            CV_Error_(Error::StsError, ("forestmod::Detector::readClasses: cannot open '%s'",
                                        filename.c_str()));
        readClass(fs.root());
    }
}

void Detector::writeClasses(const String& format) const
{
    for (std::map<String, std::vector<TemplatePyramid> >::const_iterator it = class_templates.begin();
         it != class_templates.end(); ++it)
    {
        const String filename = cv::format(format.c_str(), it->first.c_str());
        FileStorage fs(filename, FileStorage::WRITE);
        if (!fs.isOpened())
            CV_Error_(Error::StsError, ("forestmod::Detector::writeClasses: cannot write '%s'",
                                        filename.c_str()));
        writeClass(it->first, fs);
    }
}

void Detector::save(const String& filename, bool overwrite) const
{
    detail::checkOutputFile(filename, overwrite, "forestmod::Detector::save"); // issue 18
    FileStorage fs(filename, FileStorage::WRITE | FileStorage::BASE64);
    if (!fs.isOpened())
        CV_Error_(Error::StsError, ("forestmod::Detector::save: cannot write '%s'",
                                    filename.c_str()));
    fs << "forestmod_model_version" << MODEL_FORMAT_VERSION;
    fs << "detector" << "{";
    write(fs);
    fs << "}";
    fs << "classes" << "[";
    for (std::map<String, std::vector<TemplatePyramid> >::const_iterator it = class_templates.begin();
         it != class_templates.end(); ++it)
    {
        fs << "{";
        writeClass(it->first, fs);
        fs << "}";
    }
    fs << "]";
    if (impl_->trained && impl_->groups.size() == 1)
    {
        fs << "forest" << "{"; // one search group: the layout of files without groups
        impl_->groups[0].forest->write(fs);
        fs << "}";
    }
    else if (impl_->trained && !impl_->groups.empty())
    {
        fs << "forests" << "[";
        for (size_t g = 0; g < impl_->groups.size(); ++g)
        {
            fs << "{";
            impl_->groups[g].forest->write(fs);
            fs << "}";
        }
        fs << "]";
    }
}

void Detector::load(const String& filename)
{
    FileStorage fs;
    const String text = detail::readModelText(filename); // issue 18 (model_check)
    try
    {
        fs.open(text, FileStorage::READ | FileStorage::MEMORY);
    }
    catch (const cv::Exception& e)
    {
        CV_Error_(Error::StsParseError, ("forestmod::Detector::load: '%s' is not a readable "
                                         "model file: %s", filename.c_str(), e.err.c_str()));
    }
    if (!fs.isOpened())
        CV_Error_(Error::StsError, ("forestmod::Detector::load: cannot open '%s'",
                                    filename.c_str()));
    FileNode v = fs["forestmod_model_version"];
    if (v.empty())
        CV_Error_(Error::StsParseError, ("forestmod::Detector::load: '%s' is not a forestmod "
                                         "model (no forestmod_model_version)", filename.c_str()));
    if ((int)v != MODEL_FORMAT_VERSION)
        CV_Error_(Error::StsParseError, ("forestmod::Detector::load: '%s' has model format %d, "
                                         "this build reads %d", filename.c_str(), (int)v,
                                         MODEL_FORMAT_VERSION));
    read(fs["detector"]);
    FileNode classes = fs["classes"];
    if (classes.empty() || !classes.isSeq())
        CV_Error_(Error::StsParseError, ("forestmod::Detector::load: '%s' has no classes",
                                         filename.c_str()));
    for (FileNodeIterator it = classes.begin(); it != classes.end(); ++it)
        readClass(*it);
    // the trained forests (one per search group) are read as they are (training a large model
    // takes minutes); the groups, their descriptor geometry and the rejection limits are
    // functions of the templates and parameters
    std::vector<FileNode> forest_fns;
    if (!fs["forest"].empty())
        forest_fns.push_back(fs["forest"]);
    FileNode forests_fn = fs["forests"];
    if (!forests_fn.empty())
    {
        if (!forests_fn.isSeq())
            CV_Error_(Error::StsParseError, ("forestmod::Detector::load: 'forests' in '%s' is "
                                             "not a sequence (corrupt file?)", filename.c_str()));
        for (FileNodeIterator it = forests_fn.begin(); it != forests_fn.end(); ++it)
            forest_fns.push_back(*it);
    }
    if (!forest_fns.empty())
    {
        std::vector<Ptr<TemplateForest> > forests;
        for (size_t g = 0; g < forest_fns.size(); ++g)
        {
            Ptr<TemplateForest> f = TemplateForest::create(impl_->params.forest);
            f->read(forest_fns[g]);
            forests.push_back(f);
        }
        AutoLock lock(impl_->mutex);
        std::vector<Mat> desc, fg, ids;
        prepareTraining(*impl_, class_templates, (int)modalities.size(), pyramid_levels - 1,
                        T_at_level.back(), hueModalities(modalities, impl_->params), desc, fg,
                        ids);
        if (forests.size() != impl_->groups.size())
            CV_Error_(Error::StsParseError, ("forestmod::Detector::load: '%s' holds %d forests, "
                                             "its templates and parameters make %d search groups "
                                             "(corrupt file?)", filename.c_str(),
                                             (int)forests.size(), (int)impl_->groups.size()));
        for (size_t g = 0; g < forests.size(); ++g)
        {
            const Ptr<TemplateForest>& f = forests[g];
            if (f->empty() || f->numTemplates() != (int)impl_->groups[g].rows.size()
                || f->dims() != (int)impl_->groups[g].plane_of.size())
                CV_Error_(Error::StsParseError, ("forestmod::Detector::load: forest %d in '%s' "
                                                 "does not fit its templates (corrupt file?)",
                                                 (int)g, filename.c_str()));
            impl_->groups[g].forest = f;
        }
        impl_->trained = true;
    }
}

// ---------------------------------------------------------------------------------------------
static const int T_DEFAULTS[] = { 5, 8 };

Ptr<Detector> getDefaultForestLINE()
{
    std::vector<Ptr<Modality> > modalities;
    modalities.push_back(Modality::create("ColorGradient"));
    modalities.push_back(ColorHue::create());
    return makePtr<Detector>(modalities, std::vector<int>(T_DEFAULTS, T_DEFAULTS + 2));
}

Ptr<Detector> getDefaultForestLINEMOD()
{
    std::vector<Ptr<Modality> > modalities;
    modalities.push_back(Modality::create("ColorGradient"));
    modalities.push_back(Modality::create("DepthNormal"));
    modalities.push_back(ColorHue::create());
    return makePtr<Detector>(modalities, std::vector<int>(T_DEFAULTS, T_DEFAULTS + 2));
}

} // namespace forestmod
} // namespace cv
