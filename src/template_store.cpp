// This file is part of OpenCV project.
// It is subject to the license terms in the LICENSE file found in the top-level directory
// of this distribution and at http://opencv.org/license.html

// The template store: LINEMOD's template extraction plus forestmod's record of each template.

#include "precomp.hpp"
#include "template_store.hpp"

namespace cv {
namespace forestmod {
namespace detail {

using linemod::Template;

// The smallest and largest feature coordinates per pyramid level (TemplateRecord).
static std::vector<Point> featureExtents(const TemplatePyramid& tp)
{
    int levels = 0;
    for (size_t i = 0; i < tp.size(); ++i)
        levels = std::max(levels, tp[i].pyramid_level + 1);
    std::vector<Point> ext(2 * levels);
    for (int l = 0; l < levels; ++l)
    {
        Point lo(INT_MAX, INT_MAX), hi(INT_MIN, INT_MIN);
        for (size_t i = 0; i < tp.size(); ++i)
        {
            if (tp[i].pyramid_level != l)
                continue;
            const std::vector<cv::linemod::Feature>& fs = tp[i].features;
            for (size_t k = 0; k < fs.size(); ++k)
            {
                lo.x = std::min(lo.x, fs[k].x);
                lo.y = std::min(lo.y, fs[k].y);
                hi.x = std::max(hi.x, fs[k].x);
                hi.y = std::max(hi.y, fs[k].y);
            }
        }
        if (lo.x > hi.x)
            lo = hi = Point(0, 0);
        ext[2 * l] = lo;
        ext[2 * l + 1] = hi;
    }
    return ext;
}

int TemplateStore::add(ClassPyramids& pyramids, const String& class_id, const TemplatePyramid& tp,
                       const TemplateRecord& record)
{
    std::vector<TemplatePyramid>& tps = pyramids[class_id];
    std::vector<TemplateRecord>& recs = records_[class_id];
    CV_Assert(tps.size() == recs.size());
    tps.push_back(tp);
    recs.push_back(record);
    recs.back().feature_extent = featureExtents(tp);
    sizes_[class_id].push_back(tp.empty() ? Size() : Size(tp[0].width, tp[0].height));
    return static_cast<int>(tps.size()) - 1;
}

void TemplateStore::setClass(ClassPyramids& pyramids, const String& class_id,
                             const std::vector<TemplatePyramid>& tps,
                             const std::vector<TemplateRecord>& records)
{
    CV_Assert(tps.size() == records.size());
    pyramids[class_id] = tps;
    std::vector<TemplateRecord>& recs = records_[class_id];
    recs = records;
    std::vector<Size>& sizes = sizes_[class_id];
    sizes.resize(tps.size());
    for (size_t k = 0; k < tps.size(); ++k)
    {
        recs[k].feature_extent = featureExtents(tps[k]);
        sizes[k] = tps[k].empty() ? Size() : Size(tps[k][0].width, tps[k][0].height);
    }
}

const std::vector<TemplateRecord>* TemplateStore::classRecords(const String& class_id) const
{
    std::map<String, std::vector<TemplateRecord> >::const_iterator it = records_.find(class_id);
    return it == records_.end() ? 0 : &it->second;
}

const std::vector<Size>* TemplateStore::classSizes(const String& class_id) const
{
    std::map<String, std::vector<Size> >::const_iterator it = sizes_.find(class_id);
    return it == sizes_.end() ? 0 : &it->second;
}

const TemplateRecord* TemplateStore::find(const String& class_id, int template_id) const
{
    std::map<String, std::vector<TemplateRecord> >::const_iterator it = records_.find(class_id);
    if (it == records_.end() || template_id < 0 || template_id >= (int)it->second.size())
        return 0;
    return &it->second[template_id];
}

const TemplateRecord& TemplateStore::get(const String& class_id, int template_id) const
{
    const TemplateRecord* r = find(class_id, template_id);
    if (!r)
        CV_Error_(Error::StsBadArg, ("forestmod::Detector: no template %d of class '%s'",
                                     template_id, class_id.c_str()));
    return *r;
}

void TemplateStore::clear(ClassPyramids& pyramids)
{
    pyramids.clear();
    records_.clear();
    sizes_.clear();
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
// the extreme points was worse (doc/experiments.md, "Choice of depth samples").
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

// LINEMOD's extraction per modality and level; the coarsest level's quantized images go to
// `coarse` (for the dense patch). False when a modality other than ColorHue finds no feature.
static bool extractPyramid(const std::vector<Ptr<cv::linemod::Modality> >& modalities,
                           const ModalityRoles& roles, int pyramid_levels,
                           const std::vector<Mat>& sources, const Mat& object_mask,
                           TemplatePyramid& tp, std::vector<Mat>& coarse)
{
    const int M = static_cast<int>(modalities.size());
    tp.assign(M * pyramid_levels, Template());
    coarse.assign(M, Mat());
    for (int i = 0; i < M; ++i)
    {
        Ptr<cv::linemod::QuantizedPyramid> qp = modalities[i]->process(sources[i], object_mask);
        for (int l = 0; l < pyramid_levels; ++l)
        {
            if (l > 0)
                qp->pyrDown();
            if (!qp->extractTemplate(tp[l * M + i]))
            {
                // a white, grey or black object has no hue: it is learned by the other
                // modalities (ColorHue alone refuses it, as cv::linemod expects)
                if (roles.role[i] != ROLE_HUE)
                    return false;
                tp[l * M + i].features.clear();
                tp[l * M + i].pyramid_level = l;
            }
        }
        qp->quantize(coarse[i]);
    }
    for (int l = 0; l < pyramid_levels; ++l)
        if (numFeatures(tp, l, M) == 0)
            return false; // no modality found features at this level
    return true;
}

// The template's dense quantized box at the coarsest level: its forest descriptor reads the same
// plain quantized values as the scene windows (doc/detector.md, "Search").
static DensePatch densePatch(const TemplatePyramid& tp, int M, int L, const Rect& bb,
                             const Mat& object_mask, const std::vector<Mat>& coarse)
{
    const Mat coarse_mask = downsampleNearest(object_mask, L);
    const Template& top = tp[L * M];
    const Point origin(bb.x >> L, bb.y >> L);
    Rect box(origin.x, origin.y, top.width + 1, top.height + 1);
    box &= Rect(0, 0, coarse_mask.cols, coarse_mask.rows);
    DensePatch patch;
    patch.mask = Mat::zeros(top.height + 1, top.width + 1, CV_8U);
    const Rect dst(box.x - origin.x, box.y - origin.y, box.width, box.height);
    coarse_mask(box).copyTo(patch.mask(dst));
    for (int i = 0; i < M; ++i)
    {
        Mat q = Mat::zeros(patch.mask.size(), CV_8U);
        coarse[i](box).copyTo(q(dst));
        patch.quantized.push_back(q);
    }
    return patch;
}

bool makeTemplate(const std::vector<Ptr<cv::linemod::Modality> >& modalities,
                  const ModalityRoles& roles, int pyramid_levels, const std::vector<Mat>& sources,
                  const Mat& object_mask, int depth_samples, TemplatePyramid& tp,
                  TemplateRecord& record, Rect& box)
{
    checkSources(modalities, roles, sources, std::vector<Mat>(), "addTemplate");
    if (object_mask.empty() || object_mask.type() != CV_8UC1
        || object_mask.size() != sources[0].size())
        CV_Error(Error::StsBadArg, "forestmod::Detector::addTemplate: object_mask must be a "
                                   "CV_8UC1 image of the sources' size");
    if (countNonZero(object_mask) == 0)
        CV_Error(Error::StsBadArg, "forestmod::Detector::addTemplate: object_mask is empty");
    std::vector<Mat> coarse;
    if (!extractPyramid(modalities, roles, pyramid_levels, sources, object_mask, tp, coarse))
        return false;
    box = cropTemplatePyramid(tp);
    const int M = static_cast<int>(modalities.size());
    record.patch = densePatch(tp, M, pyramid_levels - 1, box, object_mask, coarse);
    record.depth.clear();
    if (roles.depth >= 0 && depth_samples > 0)
        selectDepthSamples(sources[roles.depth], object_mask, box.tl(), depth_samples,
                           record.depth);
    record.pose.box = box;
    return true;
}

DepthTemplate depthTemplate(const TemplateRecord& record)
{
    DepthTemplate t;
    if (record.depth.empty())
        return t;
    t.samples = &record.depth;
    const TemplatePose& p = record.pose;
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

} // namespace detail
} // namespace forestmod
} // namespace cv
