// This file is part of OpenCV project.
// It is subject to the license terms in the LICENSE file found in the top-level directory
// of this distribution and at http://opencv.org/license.html

// What cv::linemod lacks: a 6-DoF pose per match. Initial pose from the matched template's label
// and the match location (+ scene depth), ICP refinement and the depth check with depth, edge
// alignment without (pose.cpp, icp.cpp, pose_edges.cpp).

#include "precomp.hpp"
#include "params_io.hpp"
#include "pose_estimator.hpp"
#include "pose_refine.hpp"

#include <atomic>

namespace cv {
namespace forestmod {

PoseParams::PoseParams()
    : max_per_class(3), icp(true), icp_passes(2), depth_check_tolerance(0.05),
      min_depth_agreement(0.5), depth_hypotheses(3), rgb_refine(true), rgb_hypotheses(24),
      rgb_keep(4)
{
}

void PoseParams::read(const FileNode& fn)
{
    detail::readField(fn, "max_per_class", max_per_class);
    detail::readField(fn, "icp", icp);
    detail::readField(fn, "icp_passes", icp_passes);
    if (!fn["icp_params"].empty())
        icp_params.read(fn["icp_params"]);
    detail::readField(fn, "depth_check_tolerance", depth_check_tolerance);
    detail::readField(fn, "min_depth_agreement", min_depth_agreement);
    detail::readField(fn, "depth_hypotheses", depth_hypotheses);
    detail::readField(fn, "rgb_refine", rgb_refine);
    if (!fn["edge_params"].empty())
        edge_params.read(fn["edge_params"]);
    detail::readField(fn, "rgb_hypotheses", rgb_hypotheses);
    detail::readField(fn, "rgb_keep", rgb_keep);
    if (!fn["verification"].empty())
        verification.read(fn["verification"]);
}

void PoseParams::write(FileStorage& fs) const
{
    fs << "max_per_class" << max_per_class << "icp" << (int)icp << "icp_passes" << icp_passes;
    fs << "icp_params" << "{";
    icp_params.write(fs);
    fs << "}";
    fs << "depth_check_tolerance" << depth_check_tolerance << "min_depth_agreement"
       << min_depth_agreement << "depth_hypotheses" << depth_hypotheses << "rgb_refine"
       << (int)rgb_refine;
    fs << "edge_params" << "{";
    edge_params.write(fs);
    fs << "}";
    fs << "rgb_hypotheses" << rgb_hypotheses << "rgb_keep" << rgb_keep;
    fs << "verification" << "{";
    verification.write(fs);
    fs << "}";
}

namespace detail {

PoseMatch toPoseMatch(const cv::linemod::Match& m, const ClassPyramids& pyramids,
                      const TemplateStore& store)
{
    PoseMatch pm(m);
    const cv::linemod::Template& t0 = pyramids.find(m.class_id)->second[m.template_id][0];
    pm.box = Rect(m.x, m.y, t0.width, t0.height);
    pm.pose = store.get(m.class_id, m.template_id).pose;
    return pm;
}

PoseEstimator::PoseEstimator(const PoseEstimator& other)
{
    AutoLock lock(other.mutex_);
    drawn_ = other.drawn_;
}

void PoseEstimator::swapMeshes(PoseEstimator& other)
{
    if (&other == this)
        return;
    AutoLock lock(mutex_), other_lock(other.mutex_);
    drawn_.swap(other.drawn_);
}

void PoseEstimator::setMesh(const String& class_id, const Mesh& mesh)
{
    mesh.validate();
    static std::atomic<uint64> next_id(1);
    DrawnMesh d;
    d.id = next_id++;
    d.diameter = mesh.diameter();
    d.mesh = coarseMesh(mesh, drawingCell(d.diameter));
    d.winding = closedWinding(d.mesh);
    d.clusters = clusterFaces(d.mesh, d.winding);
    d.silhouette = silhouetteEdges(d.mesh, d.winding);
    cvtColor(faceColours(d.mesh), d.face_hsv, COLOR_BGR2HSV);
    AutoLock lock(mutex_);
    drawn_[class_id] = d;
}

bool PoseEstimator::hasMesh(const String& class_id) const
{
    AutoLock lock(mutex_);
    return drawn_.count(class_id) > 0;
}

const DrawnMesh* PoseEstimator::drawnMesh(const String& class_id) const
{
    AutoLock lock(mutex_);
    std::map<String, DrawnMesh>::const_iterator it = drawn_.find(class_id);
    return it == drawn_.end() ? 0 : &it->second;
}

static void checkPoseInputs(const Mat& depth, const Matx33d& K, const PoseParams& params,
                            const Mat& color, const std::vector<PoseMatch>& matches)
{
    CV_CheckGT(params.icp_passes, 0, "PoseParams: icp_passes must be positive");
    CV_CheckGE(params.max_per_class, 0, "PoseParams: max_per_class must be >= 0");
    CV_CheckGE(params.depth_hypotheses, 1, "PoseParams: depth_hypotheses must be >= 1");
    CV_CheckGE(params.rgb_hypotheses, 1, "PoseParams: rgb_hypotheses must be >= 1");
    CV_CheckGE(params.rgb_keep, 1, "PoseParams: rgb_keep must be >= 1");
    CV_CheckGT(params.depth_check_tolerance, 0.0, "PoseParams: depth_check_tolerance must be > 0");
    if (!(params.min_depth_agreement >= 0 && params.min_depth_agreement <= 1))
        CV_Error_(Error::StsOutOfRange, ("PoseParams: min_depth_agreement is %g, it must be in "
                                         "[0, 1] (a share of the drawn pixels)",
                                         params.min_depth_agreement));
    if (!depth.empty() && depth.type() != CV_16UC1)
        CV_Error_(Error::StsUnsupportedFormat, ("forestmod::Detector::estimatePoses: depth must "
                                                "be CV_16UC1 in mm, got %s",
                                                typeToString(depth.type()).c_str()));
    detail::checkIntrinsics(K, "forestmod::Detector::estimatePoses", "K");
    if (!color.empty() && color.type() != CV_8UC3)
        CV_Error(Error::StsUnsupportedFormat, "forestmod::Detector::estimatePoses: color must be "
                                              "a CV_8UC3 BGR image");
    if (!depth.empty() && !color.empty() && depth.size() != color.size())
        CV_Error_(Error::StsUnmatchedSizes, ("forestmod::Detector::estimatePoses: depth is %dx%d, "
                                             "color %dx%d: both must be the matched frame's size",
                                             depth.cols, depth.rows, color.cols, color.rows));
    const Mat& frame = depth.empty() ? color : depth;
    for (size_t i = 0; i < matches.size() && !frame.empty(); ++i)
        if ((matches[i].box & Rect(0, 0, frame.cols, frame.rows)).area() <= 0)
            CV_Error_(Error::StsUnmatchedSizes,
                      ("forestmod::Detector::estimatePoses: match %d at (%d, %d) lies outside the "
                       "%s image (%dx%d): depth and color must be the matched frame's size",
                       (int)i, matches[i].x, matches[i].y, depth.empty() ? "color" : "depth",
                       frame.cols, frame.rows));
}

// The part of the colour image whose edges the refinement of the matches `refine` reads.
static Rect edgeRoi(const std::vector<PoseMatch>& matches, const std::vector<size_t>& refine,
                    const PoseParams& params, Size image)
{
    Rect roi;
    const int margin = cvCeil(3 * params.edge_params.max_distance);
    for (size_t k = 0; k < refine.size(); ++k)
    {
        const PoseMatch& m = matches[refine[k]];
        const Rect b(m.x - margin, m.y - margin, m.pose.box.width + 2 * margin,
                     m.pose.box.height + 2 * margin);
        roi = roi.area() > 0 ? (roi | b) : b;
    }
    return roi & Rect(0, 0, image.width, image.height);
}

// Initial pose of a match: the template's rotation corrected for the off-axis ray, at the
// template's distance or at the one the scene depth implies under its depth samples.
static void initialPoseOf(const TemplateStore& store, const Mat& depth, const Matx33d& K,
                          PoseMatch& m)
{
    const TemplatePose& tp = m.pose;
    const Vec3d pt = tp.K * tp.t;
    const Point2d template_px(pt[0] / pt[2], pt[1] / pt[2]);
    const Point2d scene_px = Point2d(m.x, m.y) + (template_px - Point2d(tp.box.tl()));
    double z = 0;
    const TemplateRecord* rec = store.find(m.class_id, m.template_id);
    if (!depth.empty() && rec && !rec->depth.empty())
    {
        std::vector<Point> pos;
        std::vector<float> tz;
        for (size_t k = 0; k < rec->depth.size(); ++k)
        {
            pos.push_back(Point(m.x + rec->depth[k].x, m.y + rec->depth[k].y));
            tz.push_back((float)rec->depth[k].z);
        }
        z = sceneDepthFromFeatures(depth, pos, tz, tp.t[2]);
    }
    initialPose(tp.R, tp.t, tp.K, template_px, K, scene_px, z, m.R, m.t);
    m.has_pose = true;
}

// The match's pose fields reset and its initial pose set; false when its template has no pose.
static bool startPose(const TemplateStore& store, const Mat& depth, const Matx33d& K,
                      PoseMatch& m)
{
    m.has_pose = m.refined = false;
    m.drawing.release();
    m.depth_agreement = -1;
    m.edge_fit = -1;
    if (m.pose.valid)
        initialPoseOf(store, depth, K, m);
    return m.pose.valid;
}

MeshDrawer PoseEstimator::drawerOf(const String& class_id, Size size, double& diameter) const
{
    const DrawnMesh* d = drawnMesh(class_id);
    CV_Assert(d);
    diameter = d->diameter;
    return MeshDrawer(d->mesh, d->winding, size, d->id, &d->clusters, &d->silhouette);
}

bool PoseEstimator::refineOneWithDepth(const Mat& depth, const Matx33d& K,
                                       const PoseParams& params,
                                       const detail::SceneNormals& normals, PoseMatch& m) const
{
    double diameter = 0;
    const MeshDrawer drawer = drawerOf(m.class_id, depth.size(), diameter);
    m.icp = refinePose(drawer, depth, K, m.R, m.t, params.icp_params, params.icp_passes, 1,
                       &normals);
    if (m.icp.fitness > 0)
    {
        m.R = m.icp.R;
        m.t = m.icp.t;
        m.refined = true;
    }
    const double tol = params.depth_check_tolerance * diameter;
    m.depth_agreement = depthCheck(drawer, depth, K, m.R, m.t, tol, &m.drawing);
    return m.depth_agreement >= params.min_depth_agreement;
}

void PoseEstimator::refineWithDepth(const Mat& depth, const Matx33d& K, const PoseParams& params,
                                    std::vector<PoseMatch>& matches,
                                    const std::vector<size_t>& refine,
                                    std::vector<char>& drop) const
{
    if (refine.empty())
        return;
    // drawn on the CPU (drawMesh, no lock): the hypotheses refine in parallel, on the frame's
    // normals (each computed once, where the first ICP asks for it)
    const detail::SceneNormals normals(depth, K, params.icp_params);
    parallel_for_(Range(0, (int)refine.size()), [&](const Range& r) {
        for (int k = r.start; k < r.end; ++k)
            drop[refine[k]] = !refineOneWithDepth(depth, K, params, normals, matches[refine[k]]);
    });
}

void PoseEstimator::chooseWithDepth(const TemplateStore& store,
                                    const std::vector<std::vector<PoseMatch> >& locations,
                                    const Mat& depth, const Matx33d& K, const PoseParams& params,
                                    std::vector<PoseMatch>& detections) const
{
    const int n = (int)locations.size();
    std::vector<int> tries(n, 0); // matches that may be refined, per location
    std::map<String, int> per_class;
    for (int g = 0; g < n; ++g)
    {
        const String& id = locations[g][0].class_id;
        if (per_class[id]++ < params.max_per_class && hasMesh(id))
            tries[g] = std::min((int)locations[g].size(), params.depth_hypotheses);
    }
    // the locations in parallel, each one's matches one after the other until one passes
    const detail::SceneNormals normals(depth, K, params.icp_params);
    std::vector<PoseMatch> chosen(n);
    std::vector<char> keep(n, 1);
    parallel_for_(Range(0, n), [&](const Range& r) {
        for (int g = r.start; g < r.end; ++g)
        {
            bool refined = false, passed = false;
            for (int h = 0; h < tries[g] && !passed; ++h)
            {
                PoseMatch m = locations[g][h];
                if (!startPose(store, depth, K, m))
                    continue;
                refined = true;
                passed = refineOneWithDepth(depth, K, params, normals, m);
                if (passed)
                    chosen[g] = m;
            }
            if (!refined) // not refined, or no match with a pose: the first as estimate() does
            {
                chosen[g] = locations[g][0];
                startPose(store, depth, K, chosen[g]);
            }
            keep[g] = passed || !refined;
        }
    });
    detections.clear();
    for (int g = 0; g < n; ++g)
    {
        if (!keep[g])
            continue;
        PoseMatch m = chosen[g]; // position, box and score stay the location's
        m.x = locations[g][0].x;
        m.y = locations[g][0].y;
        m.similarity = locations[g][0].similarity;
        m.background = locations[g][0].background;
        m.box = locations[g][0].box;
        detections.push_back(m);
    }
}

// The fits that go on after the first pass: all of them, or with `location` the `keep` best of
// each location (by inlier ratio after the first pass, the earlier hypothesis on a tie).
static std::vector<int> fitsToFinish(std::vector<EdgeFit>& fits, const std::vector<int>* location,
                                     int keep)
{
    const int n = (int)fits.size();
    std::vector<int> go;
    std::map<int, int> per_location;
    bool crowded = false;
    for (int k = 0; location && k < n; ++k)
        crowded |= ++per_location[(*location)[k]] > keep;
    if (!crowded)
    {
        for (int k = 0; k < n; ++k)
            go.push_back(k);
        return go;
    }
    std::vector<double> ratio(n, 0.0);
    parallel_for_(Range(0, n), [&](const Range& r) {
        for (int k = r.start; k < r.end; ++k)
        {
            fits[k].run(1);
            ratio[k] = fits[k].inlierRatio();
        }
    });
    std::vector<int> order(n);
    for (int k = 0; k < n; ++k)
        order[k] = k;
    std::sort(order.begin(), order.end(), [&](int a, int b) {
        const int la = (*location)[a], lb = (*location)[b];
        return la != lb ? la < lb : ratio[a] != ratio[b] ? ratio[a] > ratio[b] : a < b;
    });
    for (int k = 0, rank = 0; k < n; ++k)
    {
        rank = k > 0 && (*location)[order[k]] == (*location)[order[k - 1]] ? rank + 1 : 0;
        if (rank < keep)
            go.push_back(order[k]);
    }
    std::sort(go.begin(), go.end());
    return go;
}

void PoseEstimator::refineWithEdges(const Mat& color, const Matx33d& K, const PoseParams& params,
                                    std::vector<PoseMatch>& matches,
                                    const std::vector<size_t>& refine, EdgeMaps& edge_maps,
                                    const std::vector<int>* location) const
{
    if (refine.empty())
        return;
    if (edge_maps.distance.empty()) // one set for all of them
        computeEdgeMaps(color, edge_maps, params.edge_params,
                        edgeRoi(matches, refine, params, color.size()));
    else // checked here, not in the parallel loop
        checkEdgeMaps(edge_maps, params.edge_params.orientations, color.size(),
                      "forestmod::Detector::estimatePoses");
    const int n = (int)refine.size();
    std::vector<MeshDrawer> drawers;
    std::vector<EdgeFit> fits;
    drawers.reserve(n); // the fits keep pointers to them
    fits.reserve(n);
    for (int k = 0; k < n; ++k)
    {
        const PoseMatch& m = matches[refine[k]];
        double diameter = 0;
        drawers.push_back(drawerOf(m.class_id, color.size(), diameter));
        fits.push_back(EdgeFit(drawers.back(), edge_maps, K, m.R, m.t, params.edge_params));
    }
    const std::vector<int> go = fitsToFinish(fits, location, params.rgb_keep);
    // drawn on the CPU (drawMesh, no lock): the hypotheses refine in parallel
    parallel_for_(Range(0, (int)go.size()), [&](const Range& r) {
        for (int j = r.start; j < r.end; ++j)
        {
            PoseMatch& m = matches[refine[go[j]]];
            Ptr<Drawing> drawn; // at er's pose, for the verification
            const EdgeRefineResult er = fits[go[j]].finish(&drawn);
            if (er.points > 0)
            {
                m.R = er.R;
                m.t = er.t;
                m.refined = true;
                m.edge_fit = er.inlier_ratio;
                m.drawing = drawn;
            }
        }
    });
}

void PoseEstimator::estimate(const TemplateStore& store, const Mat& depth, const Matx33d& K,
                             std::vector<PoseMatch>& matches, const PoseParams& params,
                             const Mat& color, EdgeMaps& edge_maps)
{
    checkPoseInputs(depth, K, params, color, matches);
    const bool icp = !depth.empty() && params.icp;
    const bool edges = depth.empty() && params.rgb_refine && !color.empty();
    // initial poses; the first max_per_class matches of each class with a mesh are refined
    std::map<String, int> refined_per_class;
    std::vector<size_t> refine;
    for (size_t i = 0; i < matches.size(); ++i)
        if (startPose(store, depth, K, matches[i]) && (icp || edges)
            && hasMesh(matches[i].class_id)
            && refined_per_class[matches[i].class_id]++ < params.max_per_class)
            refine.push_back(i);
    if (edges)
        refineWithEdges(color, K, params, matches, refine, edge_maps);
    if (!icp)
        return;
    std::vector<char> drop(matches.size(), 0);
    refineWithDepth(depth, K, params, matches, refine, drop);
    std::vector<PoseMatch> kept;
    for (size_t i = 0; i < matches.size(); ++i)
        if (!drop[i])
            kept.push_back(matches[i]);
    matches.swap(kept);
}

std::vector<std::vector<PoseMatch> > suppressedLocations(const std::vector<PoseMatch>& all,
                                                         const std::vector<int>& leader,
                                                         size_t per_location)
{
    CV_Assert(leader.size() == all.size());
    std::vector<int> group_of(all.size(), -1);
    std::vector<std::vector<PoseMatch> > groups;
    for (size_t i = 0; i < all.size(); ++i)
    {
        if (leader[i] < 0)
        {
            group_of[i] = (int)groups.size();
            groups.push_back(std::vector<PoseMatch>(1, all[i]));
            continue;
        }
        std::vector<PoseMatch>& g = groups[group_of[leader[i]]];
        if (all[i].class_id == g[0].class_id && g.size() < per_location)
            g.push_back(all[i]);
    }
    return groups;
}

void PoseEstimator::chooseAmong(const TemplateStore& store,
                                std::vector<std::vector<PoseMatch> > groups, const Mat& depth,
                                const Matx33d& K, const PoseParams& params, const Mat& color,
                                std::vector<PoseMatch>& detections, EdgeMaps& edge_maps)
{
    std::vector<PoseMatch> flat; // every group's hypotheses, for the input checks
    for (size_t g = 0; g < groups.size(); ++g)
    {
        if (groups[g].empty())
            CV_Error_(Error::StsBadArg, ("forestmod::Detector::choosePoses: location %d holds no "
                                         "match", (int)g));
        for (size_t h = 0; h < groups[g].size(); ++h)
        {
            if (groups[g][h].class_id != groups[g][0].class_id)
                CV_Error_(Error::StsBadArg, ("forestmod::Detector::choosePoses: location %d "
                                             "mixes the classes %s and %s", (int)g,
                                             groups[g][0].class_id.c_str(),
                                             groups[g][h].class_id.c_str()));
            flat.push_back(groups[g][h]);
        }
    }
    checkPoseInputs(depth, K, params, color, flat);
    if (!depth.empty() && params.icp)
    {
        chooseWithDepth(store, groups, depth, K, params, detections);
        return;
    }
    // the hypotheses of the first max_per_class groups per class, refined together (one set of
    // edge maps, in parallel, the rgb_keep best of each group after the first pass); the other
    // groups keep their first match's template pose
    std::map<String, int> per_class;
    flat.clear();
    std::vector<size_t> first(groups.size() + 1, 0), refine;
    std::vector<int> location;
    for (size_t g = 0; g < groups.size(); ++g)
    {
        const bool refined = per_class[groups[g][0].class_id]++ < params.max_per_class;
        groups[g].resize(refined ? std::min(groups[g].size(), (size_t)params.rgb_hypotheses) : 1);
        for (size_t h = 0; h < groups[g].size(); ++h)
        {
            flat.push_back(groups[g][h]);
            if (startPose(store, Mat(), K, flat.back()) && refined && params.rgb_refine
                && !color.empty() && hasMesh(flat.back().class_id))
            {
                refine.push_back(flat.size() - 1);
                location.push_back((int)g);
            }
        }
        first[g + 1] = flat.size();
    }
    refineWithEdges(color, K, params, flat, refine, edge_maps, &location);
    detections.clear();
    for (size_t g = 0; g < groups.size(); ++g)
    {
        size_t best = first[g];
        for (size_t h = first[g] + 1; h < first[g + 1]; ++h)
            if (flat[h].edge_fit > flat[best].edge_fit)
                best = h;
        // the detection keeps its position, box, score and background (the ranking stays the
        // matcher's, or the background's order of detect());
        // template, pose label and pose come from the chosen hypothesis
        PoseMatch m = flat[best];
        m.x = flat[first[g]].x;
        m.y = flat[first[g]].y;
        m.similarity = flat[first[g]].similarity;
        m.background = flat[first[g]].background;
        m.box = flat[first[g]].box;
        detections.push_back(m);
    }
}

} // namespace detail
} // namespace forestmod
} // namespace cv
