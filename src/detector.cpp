// This file is part of OpenCV project.
// It is subject to the license terms in the LICENSE file found in the top-level directory
// of this distribution and at http://opencv.org/license.html

// forestmod::Detector, the API. A frame goes through the stages of the paper (doc/architecture.md):
// scene pyramid -> scan (rejections, forests) -> validation -> pyramid refinement -> NMS -> pose.

#include "precomp.hpp"
#include "detector_impl.hpp"
#include "model_check.hpp"
#include "scene_pyramid.hpp"
#include "scan.hpp"
#include "validator.hpp"
#include "exhaustive_search.hpp"
#include "refine.hpp"
#include "nms.hpp"
#include "match_stats.hpp"
#include "verification.hpp"
#include "background.hpp"

#include <set>
#include <tuple>

namespace cv {
namespace forestmod {

using detail::ClassPyramids;
using detail::DetectorImpl;
using linemod::Match;
using linemod::Modality;
using linemod::Template;

Detector::Detector() : impl_(makePtr<DetectorImpl>()) {}

Detector::Detector(const std::vector<Ptr<Modality> >& _modalities,
                   const std::vector<int>& T_pyramid, const DetectorParams& params)
    : cv::linemod::Detector(_modalities, T_pyramid), impl_(makePtr<DetectorImpl>())
{
    if (_modalities.empty())
        CV_Error(Error::StsBadArg, "forestmod::Detector: at least one modality is needed");
    if (T_pyramid.empty())
        CV_Error(Error::StsBadArg, "forestmod::Detector: T_pyramid must not be empty");
    if (_modalities.size() > (size_t)detail::MAX_MODALITIES)
        CV_Error_(Error::StsBadArg, ("forestmod::Detector: %d modalities, at most %d",
                                     (int)_modalities.size(), (int)detail::MAX_MODALITIES));
    // what load() accepts, so that every detector made can be saved and loaded again
    for (size_t i = 0; i < _modalities.size(); ++i)
        detail::checkModality(_modalities[i], (int)i, "forestmod::Detector", Error::StsBadArg);
    detail::checkPyramidGeometry(T_pyramid, (int)T_pyramid.size(), "forestmod::Detector",
                                 Error::StsBadArg);
    detail::checkParams(params);
    impl_->params = params;
    impl_->roles = detail::ModalityRoles::of(modalities);
}

Detector::~Detector() {}

Detector::Detector(const Detector& other)
    : cv::linemod::Detector(), impl_(makePtr<DetectorImpl>())
{
    *this = other;
}

Detector& Detector::operator=(const Detector& other)
{
    if (&other == this)
        return *this;
    // copied whole first (a consistent copy while other's match() trains), then swapped in: a
    // copy that fails leaves this detector as it was
    Detector copy;
    {
        AutoLock lock(other.impl_->mutex);
        copy.impl_ = makePtr<DetectorImpl>(*other.impl_);
        static_cast<cv::linemod::Detector&>(copy) = other;
    }
    modalities.swap(copy.modalities);
    pyramid_levels = copy.pyramid_levels;
    T_at_level.swap(copy.T_at_level);
    class_templates.swap(copy.class_templates);
    impl_.swap(copy.impl_);
    return *this;
}

DetectorParams Detector::getParams() const
{
    return impl_->params;
}

// ForestParams as written to a model file (every field, whatever fields it gains).
static String forestParamsText(const ForestParams& p)
{
    FileStorage fs(".yml", FileStorage::WRITE | FileStorage::MEMORY);
    fs << "forest" << "{";
    p.write(fs);
    fs << "}";
    return fs.releaseAndGetString();
}

// Whether two parameter sets train the same search index (train()'s section of DetectorParams:
// the groups, their windows, descriptors and forests); the others are read by match() only.
static bool sameSearchIndex(const DetectorParams& a, const DetectorParams& b)
{
    return a.grid_size == b.grid_size && a.dominant_window == b.dominant_window
           && a.group_size_ratio == b.group_size_ratio && a.group_templates == b.group_templates
           && a.auto_depth_leaf_samples == b.auto_depth_leaf_samples
           && a.location_step == b.location_step
           && forestParamsText(a.forest) == forestParamsText(b.forest);
}

void Detector::setParams(const DetectorParams& params)
{
    detail::checkParams(params);
    AutoLock lock(impl_->mutex);
    const bool same_index = sameSearchIndex(impl_->params, params);
    impl_->params = params;
    if (!same_index)
        impl_->index.clear();
}

Ptr<TemplateForest> Detector::getForest(int group) const
{
    const std::vector<detail::SearchGroup>& groups = impl_->index.groups;
    if (group == 0 && groups.empty())
        return Ptr<TemplateForest>(); // untrained
    if (group < 0 || group >= (int)groups.size())
        CV_Error_(Error::StsOutOfRange, ("forestmod::Detector::getForest: no search group %d "
                                         "(%d groups)", group, (int)groups.size()));
    return groups[group].forest;
}

int Detector::numSearchGroups() const
{
    return (int)impl_->index.groups.size();
}

std::vector<String> Detector::getSearchGroupClasses(int group) const
{
    const std::vector<detail::SearchGroup>& groups = impl_->index.groups;
    if (group < 0 || group >= (int)groups.size())
        CV_Error_(Error::StsOutOfRange, ("forestmod::Detector::getSearchGroupClasses: no search "
                                         "group %d (%d groups)", group, (int)groups.size()));
    return groups[group].classes;
}

bool Detector::isTrained() const
{
    AutoLock lock(impl_->mutex);
    return impl_->index.trained;
}

TemplatePose Detector::getTemplatePose(const String& class_id, int template_id) const
{
    return impl_->store.get(class_id, template_id).pose;
}

// ---------------------------------------------------------------------------------------------
// Templates

// a class id that a model file can hold (read() refuses a class without one)
static void checkClassId(const String& class_id, const char* who)
{
    if (class_id.empty())
        CV_Error_(Error::StsBadArg, ("%s: class_id must not be empty", who));
}

static int addOneTemplate(const std::vector<Ptr<Modality> >& modalities, int pyramid_levels,
                          ClassPyramids& pyramids, DetectorImpl& impl,
                          const std::vector<Mat>& sources, const String& class_id,
                          const Mat& object_mask, const TemplatePose& pose, Rect* bounding_box)
{
    checkClassId(class_id, "forestmod::Detector::addTemplate");
    detail::TemplatePyramid tp;
    detail::TemplateRecord record;
    record.pose = pose;
    Rect box;
    if (!detail::makeTemplate(modalities, impl.roles, pyramid_levels, sources, object_mask,
                              impl.params.depth_samples, tp, record, box))
        return -1;
    // what load() would refuse is refused here (a saved model must load)
    detail::checkTemplatePose(record.pose, tp[0],
                              "forestmod::Detector::addTemplate: class '" + class_id + "'",
                              Error::StsBadArg);
    if (bounding_box)
        *bounding_box = box;
    AutoLock lock(impl.mutex);
    impl.index.clear();
    return impl.store.add(pyramids, class_id, tp, record);
}

int Detector::addTemplate(const std::vector<Mat>& sources, const String& class_id,
                          const Mat& object_mask, Rect* bounding_box)
{
    return addOneTemplate(modalities, pyramid_levels, class_templates, *impl_, sources, class_id,
                          object_mask, TemplatePose(), bounding_box);
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
    return addOneTemplate(modalities, pyramid_levels, class_templates, *impl_, sources, class_id,
                          object_mask, pose, bounding_box);
}

int Detector::addTemplates(const Mesh& mesh, const String& class_id, const ViewSampler& sampler,
                           const Matx33d& K, Size size,
                           const std::function<bool(int, int)>& progress)
{
    if (modalities.empty())
        CV_Error(Error::StsError, "forestmod::Detector::addTemplates: no modalities");
    checkClassId(class_id, "forestmod::Detector::addTemplates");
    mesh.validate(); // before rendering; setMesh() takes it once it gave templates
    if (sampler.size() == 0)
        CV_Error_(Error::StsBadArg, ("forestmod::Detector::addTemplates: class '%s': the sampler "
                                     "gives no pose (its elevation range holds no view)",
                                     class_id.c_str()));
    int added = 0, views = 0;
    renderTemplates(mesh, sampler, K, size,
                    [&](const TemplateView& v, int done, int total) -> bool {
                        detail::checkTemplateView(v.mask, v.view_id, v.radius, class_id);
                        views = done;
                        if (countNonZero(v.mask) > 0
                            && addTemplate(detail::sourcesFor(modalities, impl_->roles, v.color,
                                                              v.depth),
                                           class_id, v.mask, v.R, v.t, v.K) >= 0)
                            ++added;
                        return progress ? progress(done, total) : true;
                    });
    detail::checkViewsGaveTemplates(added, views, class_id);
    if (added > 0) // the mesh of a class that has templates from it
        setMesh(class_id, mesh);
    return added;
}

int Detector::addSyntheticTemplate(const std::vector<Template>& templates, const String& class_id)
{
    checkClassId(class_id, "forestmod::Detector::addSyntheticTemplate");
    const int M = static_cast<int>(modalities.size());
    if (M == 0 || (int)templates.size() != M * pyramid_levels)
        CV_Error_(Error::StsBadArg, ("forestmod::Detector::addSyntheticTemplate: expected %d "
                                     "templates (modalities x pyramid levels), got %d",
                                     M * pyramid_levels, (int)templates.size()));
    // the checks of load(): labels, feature positions and sizes that the search can index
    detail::checkTemplatePyramid(templates, M, pyramid_levels,
                                 "forestmod::Detector::addSyntheticTemplate: class '" + class_id
                                     + "'",
                                 Error::StsBadArg);
    AutoLock lock(impl_->mutex);
    impl_->index.clear();
    // no pose, no dense patch (the descriptor comes from the features), no depth samples
    return impl_->store.add(class_templates, class_id, templates, detail::TemplateRecord());
}

void Detector::train()
{
    if (modalities.empty())
        CV_Error(Error::StsError, "forestmod::Detector::train: the detector has no modalities");
    if (numTemplates() == 0)
        CV_Error(Error::StsError, "forestmod::Detector::train: no templates (addTemplate first)");
    AutoLock lock(impl_->mutex);
    const int L = pyramid_levels - 1;
    impl_->index.train(class_templates, impl_->store, impl_->params, (int)modalities.size(), L,
                       T_at_level[L]);
}

// ---------------------------------------------------------------------------------------------
// Matching

namespace {
// What the stages of one match() call read of the detector.
struct DetectorView
{
    const std::vector<Ptr<Modality> >& modalities;
    const std::vector<int>& T;
    const ClassPyramids& pyramids;
    DetectorImpl& impl;
};
} // namespace

// Automatic training after templates or parameters changed, once, under the lock.
static void ensureTrained(const DetectorView& d)
{
    AutoLock lock(d.impl.mutex);
    if (d.impl.index.trained)
        return;
    const int L = static_cast<int>(d.T.size()) - 1;
    d.impl.index.train(d.pyramids, d.impl.store, d.impl.params, (int)d.modalities.size(), L,
                       d.T[L]);
}

static void checkMatchInputs(const DetectorView& d, const std::vector<Mat>& sources,
                             float threshold, const std::vector<Mat>& masks)
{
    detail::checkSources(d.modalities, d.impl.roles, sources, masks, "match");
    if (!(threshold >= 0.f && threshold <= 100.f))
        CV_Error_(Error::StsOutOfRange, ("forestmod::Detector::match: threshold must be in "
                                         "[0, 100] (percent), got %g", (double)threshold));
    size_t templates = 0;
    for (ClassPyramids::const_iterator it = d.pyramids.begin(); it != d.pyramids.end(); ++it)
        templates += it->second.size();
    if (templates == 0)
        CV_Error(Error::StsError, "forestmod::Detector::match: the detector has no templates");
    // every level of the pyramid must hold at least one cell of T pixels
    const int L = static_cast<int>(d.T.size()) - 1;
    const int min_side = d.T[L] << L;
    if (sources[0].cols < min_side || sources[0].rows < min_side)
        CV_Error_(Error::StsBadSize, ("forestmod::Detector::match: the images are %dx%d; with "
                                      "%d pyramid levels and T = %d at the coarsest they must be "
                                      "at least %dx%d", sources[0].cols, sources[0].rows, L + 1,
                                      d.T[L], min_side, min_side));
}

// Index rows whose class was asked for (all when class_ids is empty), and those classes.
static std::vector<uchar> allowedRows(const DetectorView& d, const std::vector<String>& class_ids,
                                      std::vector<String>& classes)
{
    classes.clear();
    for (ClassPyramids::const_iterator it = d.pyramids.begin(); it != d.pyramids.end(); ++it)
        if (class_ids.empty()
            || std::find(class_ids.begin(), class_ids.end(), it->first) != class_ids.end())
            classes.push_back(it->first);
    const std::vector<detail::TemplateRef>& rows = d.impl.index.rows;
    std::vector<uchar> allowed(rows.size(), 1);
    if (!class_ids.empty())
        for (size_t r = 0; r < rows.size(); ++r)
            allowed[r] = std::find(classes.begin(), classes.end(), rows[r].class_id)
                != classes.end();
    return allowed;
}

// With DetectorParams::search_per_class and several asked-for classes: per index row, the index
// of its class in `classes` (-1 when not asked for); else empty (the classes share the lists).
static std::vector<int> classOfRow(const DetectorView& d, const DetectorParams& params,
                                   const std::vector<uchar>& allowed,
                                   const std::vector<String>& classes)
{
    std::vector<int> class_of_row;
    if (!params.search_per_class || classes.size() < 2)
        return class_of_row;
    const std::vector<detail::TemplateRef>& rows = d.impl.index.rows;
    class_of_row.assign(rows.size(), -1);
    for (size_t r = 0; r < rows.size(); ++r)
        if (allowed[r])
            class_of_row[r] = static_cast<int>(
                std::find(classes.begin(), classes.end(), rows[r].class_id) - classes.begin());
    return class_of_row;
}

// The matches [b, e) best first by Match::operator< (similarity descending, then template id),
// equal ones in their order (as std::stable_sort): the order sorted as 64-bit keys with the
// indices, each match then moved once (std::sort of the matches themselves swaps their class
// strings at every step).
static void sortBestFirst(std::vector<Match>& matches, size_t b, size_t e)
{
    CV_DbgAssert(b <= e && e <= matches.size());
    std::vector<std::pair<uint64_t, int> > keys(e - b);
    for (size_t i = b; i < e; ++i)
    {
        // float -> unsigned integer of the same order, complemented: descending similarity
        Cv32suf u;
        u.f = matches[i].similarity;
        const uint32_t s = u.u ^ ((u.u >> 31) ? 0xFFFFFFFFu : 0x80000000u);
        const uint32_t t = (uint32_t)matches[i].template_id ^ 0x80000000u;
        keys[i - b] = std::make_pair(((uint64_t)~s << 32) | t, (int)(i - b));
    }
    std::sort(keys.begin(), keys.end());
    std::vector<Match> sorted(keys.size());
    for (size_t k = 0; k < keys.size(); ++k)
        sorted[k] = std::move(matches[b + keys[k].second]);
    std::move(sorted.begin(), sorted.end(), matches.begin() + b);
}

// 4. the finer levels' maps where the coarse matches will be refined (timed with the scene
// pyramid), then the pyramid refinement (with the depth samples when the forest is used); the
// matches sorted best first, repeats removed.
// With `per_class` the matches come class after class, and each class's are sorted on their own
// before the classes' are joined by a stable sort (the order of each class's matches is that of
// a search asked for it alone).
static void refineAndSort(const DetectorView& d, detail::ScenePyramid& scene, float threshold,
                          std::vector<Match>& matches, bool per_class, double& t_quant,
                          double& t_valid, detail::StageClock& clock)
{
    std::vector<std::vector<Rect> > regions;
    detail::refinementRegions(scene, d.pyramids, d.impl.store, matches, regions);
    detail::prepareRefinementLevels(scene, regions);
    t_quant += clock.lap();
    detail::refineMatches(scene, d.pyramids, d.impl.store, threshold, matches);
    if (!per_class)
    {
        sortBestFirst(matches, 0, matches.size());
        matches.erase(std::unique(matches.begin(), matches.end()), matches.end());
    }
    else
    {
        std::vector<Match> sorted;
        sorted.reserve(matches.size());
        for (size_t b = 0, e = 0; b < matches.size(); b = e)
        {
            while (e < matches.size() && matches[e].class_id == matches[b].class_id)
                ++e;
            sortBestFirst(matches, b, e);
            sorted.insert(sorted.end(), matches.begin() + b,
                          std::unique(matches.begin() + b, matches.begin() + e));
        }
        sortBestFirst(sorted, 0, sorted.size());
        matches.swap(sorted);
    }
    t_valid += clock.lap();
}

// The pipeline of one frame: every match over the threshold, sorted best first, before
// non-maximum suppression.
// `scene_out` (optional) receives the frame's scene pyramid for the stages after matching.
static void matchFrame(const DetectorView& d, const std::vector<Mat>& sources, float threshold,
                       std::vector<Match>& matches, const std::vector<String>& class_ids,
                       OutputArrayOfArrays quantized_images, const std::vector<Mat>& masks,
                       DetectionStats* stats, detail::ScenePyramid* scene_out = 0)
{
    checkMatchInputs(d, sources, threshold, masks);
    const DetectorParams& params = d.impl.params;
    if (params.use_forest)
        ensureTrained(d); // counted in t_total_ms only
    detail::StageClock clock;
    std::vector<String> classes;
    const std::vector<uchar> allowed = allowedRows(d, class_ids, classes);

    // 1. scene pyramid: the frame's maps, once (below the coarsest level: on demand, step 4)
    detail::ScenePyramid scene;
    detail::quantizeScene(d.modalities, d.impl.roles, d.T, sources, masks, scene,
                          quantized_images);
    const int L = scene.coarsestIndex();
    if (d.impl.roles.depth >= 0)
        scene.depth = sources[d.impl.roles.depth];
    if (params.use_forest)
    {
        detail::forestPlanes(params.dominant_window,
                             (d.impl.index.max_extent >> L) + 2 * d.T[L] + 2, scene);
        if (!scene.depth.empty() && params.depth_samples > 0)
            detail::depthContexts(scene.depth, d.T, params.depth_tolerance, scene);
        if (!scene.depth.empty() && params.depth_range_tolerance >= 0)
            scene.depth_cells.set(scene.depth, d.T[L] << L);
    }
    double t_quant = clock.lap();
    double t_tree = 0;
    detail::MatchCounters counters;
    Mat rejection_map;
    matches.clear();
    double t_valid = 0;
    if (params.use_forest)
    {
        // 2. scan: rejections and forests -> candidates per location
        detail::LocationCandidates cands;
        detail::scanLocations(d.impl.index, scene, params, allowed, stats != 0, cands);
        t_tree += clock.lap();
        counters += cands.counters;
        rejection_map = cands.rejection_map;
        // 3. validation: breadth-first, the best survivors of each location; the lists shared by
        // the asked-for classes, or each class's own (DetectorParams::search_per_class)
        const std::vector<int> class_of_row = classOfRow(d, params, allowed, classes);
        if (class_of_row.empty())
            detail::validateLocations(scene, cands, d.impl.index, d.pyramids, params, threshold,
                                      allowed, matches);
        else
        {
            std::vector<std::vector<Match> > per_class(classes.size());
            detail::validateLocationsPerClass(scene, cands, d.impl.index, d.pyramids, params,
                                              threshold, class_of_row, per_class);
            for (size_t c = 0; c < per_class.size(); ++c)
                matches.insert(matches.end(), per_class[c].begin(), per_class[c].end());
        }
        t_valid += clock.lap();
        // 4. refinement
        refineAndSort(d, scene, threshold, matches, !class_of_row.empty(), t_quant, t_valid,
                      clock);
    }
    else // exhaustive LINEMOD search of the same templates
    {
        detail::matchExhaustive(scene, d.pyramids, classes, threshold, matches, counters);
        t_valid += clock.lap();
        refineAndSort(d, scene, threshold, matches, false, t_quant, t_valid, clock);
    }
    if (stats)
    {
        counters.addTo(*stats);
        stats->rejection_map = rejection_map;
        stats->t_quantize_ms += t_quant;
        stats->t_tree_ms += t_tree;
        stats->t_valid_ms += t_valid;
    }
    if (scene_out)
        std::swap(*scene_out, scene);
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
    const DetectorView d = { modalities, T_at_level, class_templates, *impl_ };
    detail::StageClock clock;
    matchFrame(d, sources, threshold, matches, class_ids, quantized_images, masks, stats);
    // 5. non-maximum suppression over templates and classes
    const float iou = impl_->params.nms_iou;
    if (iou > 0.f && iou < 1.f)
    {
        std::vector<int> leader;
        detail::nonMaximumSuppression(matches, impl_->store, iou, leader);
        detail::keepLeaders(matches, leader);
    }
    if (stats)
        stats->t_total_ms += clock.total();
}

void Detector::match(const std::vector<Mat>& sources, float threshold,
                     std::vector<PoseMatch>& matches, const std::vector<String>& class_ids,
                     const std::vector<Mat>& masks, DetectionStats* stats) const
{
    std::vector<Match> plain;
    match(sources, threshold, plain, class_ids, noArray(), masks, stats);
    matches.clear();
    for (size_t i = 0; i < plain.size(); ++i)
        matches.push_back(detail::toPoseMatch(plain[i], class_templates, impl_->store));
}

// ---------------------------------------------------------------------------------------------
// Poses

void Detector::setMesh(const String& class_id, const Mesh& mesh)
{
    impl_->poses.setMesh(class_id, mesh);
}

bool Detector::hasMesh(const String& class_id) const
{
    return impl_->poses.hasMesh(class_id);
}

void Detector::estimatePoses(InputArray depth, const Matx33d& K, std::vector<PoseMatch>& matches,
                             const PoseParams& params, InputArray color) const
{
    EdgeMaps edge_maps;
    estimatePoses(depth, K, matches, params, color, edge_maps);
}

void Detector::estimatePoses(InputArray depth, const Matx33d& K, std::vector<PoseMatch>& matches,
                             const PoseParams& params, InputArray color,
                             EdgeMaps& edge_maps) const
{
    impl_->poses.estimate(impl_->store, depth.getMat(), K, matches, params, color.getMat(),
                          edge_maps);
}

void Detector::choosePoses(InputArray depth, const Matx33d& K,
                           const std::vector<std::vector<PoseMatch> >& locations,
                           const PoseParams& params, InputArray color,
                           std::vector<PoseMatch>& detections, EdgeMaps& edge_maps) const
{
    impl_->poses.chooseAmong(impl_->store, locations, depth.getMat(), K, params, color.getMat(),
                             detections, edge_maps);
}

void Detector::choosePoses(const Matx33d& K, const std::vector<std::vector<PoseMatch> >& locations,
                           const PoseParams& params, InputArray color,
                           std::vector<PoseMatch>& detections, EdgeMaps& edge_maps) const
{
    choosePoses(noArray(), K, locations, params, color, detections, edge_maps);
}

void Detector::verify(InputArray color, InputArray depth, const Matx33d& K,
                      std::vector<PoseMatch>& matches, const VerificationParams& params,
                      DetectionStats* stats) const
{
    detail::verifyHypotheses(impl_->poses, color.getMat(), depth.getMat(), K, matches, params, 0,
                             stats);
}

void Detector::verify(InputArray color, InputArray depth, const Matx33d& K,
                      std::vector<PoseMatch>& matches, const VerificationParams& params,
                      DetectionStats* stats, const EdgeMaps& edge_maps) const
{
    detail::verifyHypotheses(impl_->poses, color.getMat(), depth.getMat(), K, matches, params,
                             &edge_maps, stats);
}

void Detector::backgroundSimilarity(const std::vector<Mat>& sources,
                                    std::vector<PoseMatch>& matches, double quantile,
                                    DetectionStats* stats) const
{
    detail::checkBackgroundQuantile(quantile);
    const DetectorView d = { modalities, T_at_level, class_templates, *impl_ };
    checkMatchInputs(d, sources, 50.f, std::vector<Mat>());
    detail::StageClock clock;
    detail::ScenePyramid scene;
    detail::quantizeScene(d.modalities, d.impl.roles, d.T, sources, std::vector<Mat>(), scene,
                          noArray());
    std::vector<Match> plain(matches.begin(), matches.end());
    std::vector<float> background;
    detail::backgroundSimilarity(scene, class_templates, plain, quantile, background);
    for (size_t i = 0; i < matches.size(); ++i)
        matches[i].background = background[i];
    if (stats)
        stats->t_background_ms += clock.total();
}

// the verification reads the pose stage's edge maps when they were made with its edge parameters
static bool sameEdges(const EdgeRefineParams& a, const EdgeRefineParams& b)
{
    return a.orientations == b.orientations && a.canny_low == b.canny_low
        && a.canny_high == b.canny_high;
}

// detect() returns no drawings (the verification has used them; without it nothing reads them)
static void releaseDrawings(std::vector<PoseMatch>& matches)
{
    for (size_t i = 0; i < matches.size(); ++i)
        matches[i].drawing.release();
}

// the verification of detect(): with the frame's edge maps when the pose stage made usable ones
static void verifyDetections(const Detector& det, const Mat& color, const Mat& depth,
                             const Matx33d& K, std::vector<PoseMatch>& matches,
                             const PoseParams& params, const EdgeMaps& edge_maps,
                             DetectionStats* stats)
{
    const VerificationParams& vp = params.verification;
    if (!edge_maps.distance.empty() && sameEdges(params.edge_params, vp.edge_params)
        && edge_maps.max_distance >= vp.edge_distance)
        det.verify(color, depth, K, matches, vp, stats, edge_maps);
    else
        det.verify(color, depth, K, matches, vp, stats);
}

// VerificationParams::second_round_below: the classes whose best verified detection scores below
// it get their locations of `next` (each class's next top_k after the verified ones) posed and
// verified; matches (verified, best first, then the others) takes them in place of their
// first-round detections, all verified ones ranked together.
static void secondRound(const Detector& det, detail::PoseEstimator& poses,
                        const detail::TemplateStore& store,
                        const std::vector<std::vector<PoseMatch> >& next, const Mat& color,
                        const Matx33d& K, const PoseParams& params,
                        std::vector<PoseMatch>& matches, DetectionStats* stats)
{
    const VerificationParams& vp = params.verification;
    std::map<String, double> best; // per class: the best verification of the first round
    for (size_t i = 0; i < matches.size(); ++i)
        if (matches[i].verification >= 0)
        {
            double& b = best.emplace(matches[i].class_id, 0.0).first->second;
            b = std::max(b, matches[i].verification);
        }
    std::vector<std::vector<PoseMatch> > more;
    for (size_t k = 0; k < next.size(); ++k)
    {
        const std::map<String, double>::const_iterator b = best.find(next[k][0].class_id);
        if (b != best.end() && b->second < vp.second_round_below)
            more.push_back(next[k]);
    }
    if (more.empty())
        return;
    // the detections these locations had in the first round (template-posed, or posed but not
    // verified when max_per_class > top_k), by their first match's position and box (unique
    // among a class's detections, whose boxes overlap by at most nms_iou)
    typedef std::tuple<String, int, int, int, int> Key;
    const auto key = [](const PoseMatch& m) {
        return Key(m.class_id, m.x, m.y, m.box.width, m.box.height);
    };
    std::set<Key> replaced;
    for (size_t g = 0; g < more.size(); ++g)
        replaced.insert(key(more[g][0]));
    PoseParams p2 = params;
    p2.max_per_class = vp.top_k;
    std::vector<PoseMatch> second;
    EdgeMaps maps2; // around these locations
    poses.chooseAmong(store, more, Mat(), K, p2, color, second, maps2);
    verifyDetections(det, color, Mat(), K, second, p2, maps2, stats);
    std::vector<PoseMatch> verified, rest;
    for (size_t i = 0; i < matches.size(); ++i)
    {
        PoseMatch& m = matches[i];
        if (m.verification >= 0)
            verified.push_back(m);
        else if (!replaced.count(key(m)))
            rest.push_back(m);
    }
    const size_t n_first = verified.size();
    for (size_t i = 0; i < second.size(); ++i)
        (second[i].verification >= 0 ? verified : rest).push_back(second[i]);
    std::inplace_merge(verified.begin(), verified.begin() + n_first, verified.end(),
                       [](const PoseMatch& a, const PoseMatch& b) {
                           return a.verification > b.verification;
                       });
    verified.insert(verified.end(), rest.begin(), rest.end());
    matches.swap(verified);
}

void Detector::detect(const std::vector<Mat>& sources, const Matx33d& K, float threshold,
                      std::vector<PoseMatch>& matches, const std::vector<String>& class_ids,
                      const PoseParams& _params, DetectionStats* stats) const
{
    CV_CheckGE(_params.rgb_hypotheses, 1, "PoseParams: rgb_hypotheses must be >= 1");
    CV_CheckGE(_params.depth_hypotheses, 1, "PoseParams: depth_hypotheses must be >= 1");
    if (_params.verification.enabled)
        detail::checkVerificationParams(_params.verification);
    // with the verification, its top_k detections per class get a refined pose
    PoseParams params = _params;
    if (params.verification.enabled)
        params.max_per_class = std::max(params.max_per_class, params.verification.top_k);
    const DetectorView d = { modalities, T_at_level, class_templates, *impl_ };
    checkMatchInputs(d, sources, threshold, std::vector<Mat>());
    Mat depth, color;
    for (size_t i = 0; i < sources.size(); ++i)
    {
        if (impl_->roles.role[i] == detail::ROLE_NORMAL)
            depth = sources[i];
        else if (sources[i].type() == CV_8UC3 && color.empty())
            color = sources[i];
    }
    // each detection's pose is chosen among the matches non-maximum suppression merges into it
    const float iou = impl_->params.nms_iou;
    const bool icp = !depth.empty() && params.icp;
    const bool choose = iou > 0.f && iou < 1.f
        && (icp ? params.depth_hypotheses > 1
                : depth.empty() && !color.empty() && params.rgb_refine
                      && params.rgb_hypotheses > 1);
    detail::StageClock clock;
    std::vector<Match> all;
    detail::ScenePyramid scene;
    matchFrame(d, sources, threshold, all, class_ids, noArray(), std::vector<Mat>(), stats,
               &scene);
    if (stats)
        stats->t_total_ms += clock.lap();
    // the hypotheses that stand out from the frame first (VerificationParams::background_weight)
    std::vector<float> background;
    const VerificationParams& vp = params.verification;
    if (vp.enabled && vp.background_weight > 0)
    {
        detail::backgroundSimilarity(scene, class_templates, all, vp.background_quantile,
                                     background);
        detail::orderByDistinctiveness(all, background, vp.background_weight);
        if (stats)
            stats->t_background_ms += clock.lap();
    }
    // 5. non-maximum suppression, as match() (off: every match leads)
    std::vector<int> leader(all.size(), -1);
    if (iou > 0.f && iou < 1.f)
        detail::nonMaximumSuppression(all, impl_->store, iou, leader);
    if (stats)
        stats->t_total_ms += clock.lap();
    std::vector<PoseMatch> hypotheses;
    for (size_t i = 0; i < all.size(); ++i)
    {
        hypotheses.push_back(detail::toPoseMatch(all[i], class_templates, impl_->store));
        if (!background.empty())
            hypotheses.back().background = background[i];
    }
    if (!choose) // each detection with its own match's pose
    {
        matches.clear();
        for (size_t i = 0; i < hypotheses.size(); ++i)
            if (leader[i] < 0)
                matches.push_back(hypotheses[i]);
        EdgeMaps edge_maps;
        estimatePoses(depth, K, matches, params, color, edge_maps);
        if (params.verification.enabled && !color.empty())
            verifyDetections(*this, color, depth, K, matches, params, edge_maps, stats);
        releaseDrawings(matches);
        return;
    }
    const size_t per_location = (size_t)(icp ? params.depth_hypotheses : params.rgb_hypotheses);
    std::vector<std::vector<PoseMatch> > locations
        = detail::suppressedLocations(hypotheses, leader, per_location);
    // the locations of a possible second round (VerificationParams::second_round_below): each
    // class's next top_k
    const bool verify = params.verification.enabled && !color.empty();
    std::vector<std::vector<PoseMatch> > next;
    if (verify && depth.empty() && vp.second_round_below > 0)
    {
        std::map<String, int> rank;
        for (size_t g = 0; g < locations.size(); ++g)
        {
            const int r = rank[locations[g][0].class_id]++;
            if (r >= vp.top_k && r < 2 * vp.top_k)
                next.push_back(locations[g]);
        }
    }
    EdgeMaps edge_maps;
    impl_->poses.chooseAmong(impl_->store, std::move(locations), depth, K, params, color, matches,
                             edge_maps);
    if (verify)
    {
        verifyDetections(*this, color, depth, K, matches, params, edge_maps, stats);
        if (!next.empty())
            secondRound(*this, impl_->poses, impl_->store, next, color, K, params, matches,
                        stats);
    }
    releaseDrawings(matches);
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
