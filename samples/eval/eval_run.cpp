// This file is part of OpenCV project.
// It is subject to the license terms in the LICENSE file found in the top-level directory
// of this distribution and at http://opencv.org/license.html

// forestmod_eval: running the detectors on the frames (best of N match() calls per frame) and
// scoring the best hypothesis of every object.

#include "eval_common.hpp"

#include <algorithm>
#include <limits>

namespace fmeval {

static cv::Rect2d projectedBox(const std::vector<cv::Point3f>& pts, const cv::Matx33d& K,
                               const cv::Matx33d& R, const cv::Vec3d& t)
{
    double x0 = 1e30, y0 = 1e30, x1 = -1e30, y1 = -1e30;
    for (size_t i = 0; i < pts.size(); ++i)
    {
        const cv::Vec3d p = R * cv::Vec3d(pts[i].x, pts[i].y, pts[i].z) + t;
        if (p[2] <= 0)
            continue;
        const double u = K(0, 0) * p[0] / p[2] + K(0, 2), v = K(1, 1) * p[1] / p[2] + K(1, 2);
        x0 = std::min(x0, u);
        y0 = std::min(y0, v);
        x1 = std::max(x1, u);
        y1 = std::max(y1, v);
    }
    return x1 < x0 ? cv::Rect2d() : cv::Rect2d(x0, y0, x1 - x0, y1 - y0);
}

// The ground truth's box of the whole object, or its projection when the dataset has none.
static cv::Rect2d groundTruthBox(const fm::GroundTruth& gt, const EvalFrame& f,
                                 const ObjectInfo& obj)
{
    const cv::Rect2d box = gt.bbox_obj;
    return box.area() > 0 ? box : projectedBox(obj.pts, f.K, gt.R, gt.t);
}

/** Scores one hypothesis (or none) of an object against its ground truth (gt_box: its box,
groundTruthBox) into res and rec. top: the hypotheses in rank order, the first `at` of them for
recall@10 (after a second round of the verification there are more). record: their features
into rec.hyps. */
static void scoreHypotheses(const std::vector<fm::PoseMatch>& top, const fm::GroundTruth& gt,
                            const cv::Rect2d& gt_box, const EvalFrame& f, const ObjectInfo& obj,
                            bool use_depth, Result& res, FrameRecord& rec, bool record = false,
                            size_t at = std::numeric_limits<size_t>::max())
{
    ++res.n2d;
    if (use_depth)
        ++res.nadd;
    bool hit2d = false, hitproj = false;
    for (size_t k = 0; k < top.size(); ++k)
    {
        const fm::PoseMatch& h = top[k];
        const double iou = fm::boxIoU(projectedBox(obj.pts, f.K, h.R, h.t), gt_box);
        // 2D projection error, the smallest over the object's discrete symmetries
        double proj = fm::projectionError2D(obj.pts, f.K, h.R, h.t, gt.R, gt.t);
        for (size_t s = 0; s < obj.symmetries.size(); ++s)
        {
            const cv::Matx44d& S = obj.symmetries[s];
            const cv::Matx33d SR = S.get_minor<3, 3>(0, 0);
            const cv::Vec3d St(S(0, 3), S(1, 3), S(2, 3));
            proj = std::min(proj, fm::projectionError2D(obj.pts, f.K, h.R, h.t, gt.R * SR,
                                                        gt.R * St + gt.t));
        }
        if (record)
            rec.hyps.push_back(cv::Vec<double, 9>(h.similarity, h.color_score, h.edge_score,
                                                  h.depth_score, h.occlusion, iou, proj,
                                                  h.region_score, h.background));
        hit2d = hit2d || (k < at && iou >= 0.5);
        hitproj = hitproj || (k < at && proj < 5.0);
        if (k > 0)
            continue;
        // the first hypothesis is the detector's answer
        rec.template_id = h.template_id;
        rec.similarity = h.similarity;
        rec.pos = cv::Point(h.x, h.y);
        rec.iou = iou;
        rec.proj = proj;
        rec.verification = h.verification;
        res.ok2d += iou >= 0.5;
        res.okproj += proj < 5.0;
        if (use_depth)
        {
            const double err = obj.symmetric ? fm::adiError(obj.pts, h.R, h.t, gt.R, gt.t)
                                             : fm::addError(obj.pts, h.R, h.t, gt.R, gt.t);
            rec.add = err / obj.diameter;
            if (fm::isCorrect(err, obj.diameter, 0.1))
                ++res.okadd;
        }
    }
    res.ok2d_at10 += hit2d;
    res.okproj_at10 += hitproj;
    res.per_frame.push_back(rec);
}

double GroundTruthTemplates::similarity(const fm::Detector& like, const ObjectInfo& obj,
                                        const EvalFrame& f, const fm::GroundTruth& gt,
                                        const cv::Rect2d& gt_box)
{
    const std::tuple<int, int, int> key(f.scene_id, f.im_id, obj.obj_id);
    const std::map<std::tuple<int, int, int>, double>::const_iterator known = measured_.find(key);
    if (known != measured_.end())
        return known->second;
    if (!renderer_ || renderer_->size() != f.rgb.size())
    {
        renderer_ = fm::Renderer::create(f.rgb.size());
        handles_.clear();
    }
    if (!handles_.count(obj.obj_id))
        handles_[obj.obj_id] = renderer_->addMesh(obj.mesh);
    cv::Mat color, depth, mask;
    renderer_->render(handles_[obj.obj_id], gt.R, gt.t, f.K, color, depth, mask);
    const std::vector<cv::Ptr<cv::linemod::Modality> > mods = like.getModalities();
    std::vector<int> T;
    for (int l = 0; l < like.pyramidLevels(); ++l)
        T.push_back(like.getT(l));
    fm::DetectorParams exhaustive; // every position scored: the similarity itself
    exhaustive.exhaustive_ratio = 0.f;
    fm::Detector one(mods, T, exhaustive);
    double best = std::numeric_limits<double>::quiet_NaN();
    if (cv::countNonZero(mask) > 0
        && one.addTemplate(sourcesOf(mods, color, depth), "gt", mask, gt.R, gt.t, f.K) >= 0)
    {
        std::vector<cv::linemod::Match> matches;
        one.match(sourcesOf(mods, f.rgb, f.depth), 50.f, matches);
        const cv::linemod::Template& t0 = one.getTemplates("gt", 0)[0];
        for (size_t i = 0; i < matches.size(); ++i)
            if (fm::boxIoU(cv::Rect2d(matches[i].x, matches[i].y, t0.width, t0.height), gt_box)
                    >= 0.5
                && !(matches[i].similarity <= best))
                best = matches[i].similarity;
    }
    measured_[key] = best;
    return best;
}

// The best similarity of the class's matches whose template box lies on the object (box IoU >= 0.5
// with on_object) and of the others, into rec (NaN without one).
static void bestOnAndOff(const std::vector<cv::linemod::Match>& matches,
                         const fm::Detector& posedet, const ObjectInfo& obj,
                         const cv::Rect2d& on_object, FrameRecord& rec)
{
    rec.correct_similarity = rec.off_similarity = std::numeric_limits<double>::quiet_NaN();
    for (size_t i = 0; i < matches.size(); ++i)
    {
        if (matches[i].class_id != obj.class_id)
            continue;
        const cv::linemod::Template& t0 = posedet.getTemplates(matches[i].class_id,
                                                               matches[i].template_id)[0];
        double& best = fm::boxIoU(cv::Rect2d(matches[i].x, matches[i].y, t0.width, t0.height),
                                  on_object) >= 0.5 ? rec.correct_similarity
                                                    : rec.off_similarity;
        if (!(matches[i].similarity <= best))
            best = matches[i].similarity;
    }
}

/** The hypotheses of an object in a frame, as Detector::detect() makes them: the class's
matches (in the order given) grouped by location (greedy, box IoU > 0.5 with a group's first
match), the ctx.verify.top_k locations after the first `skip`, each with its pose (RGB, refined:
the best edge fit of its first rgb_hypotheses matches; RGB-D: the first of depth_hypotheses
whose ICP pose passes the depth check). edge_maps: the frame's, made around the groups (RGB,
refined). Returns the time taken (ms). */
static double poseHypotheses(const std::vector<fm::PoseMatch>& matches,
                             const fm::Detector& posedet, const EvalFrame& f,
                             const RunContext& ctx, std::vector<fm::PoseMatch>& top,
                             fm::EdgeMaps& edge_maps, size_t skip = 0)
{
    const bool use_depth = ctx.use_depth;
    fm::PoseParams pp;
    pp.rgb_refine = ctx.rgb_refine;
    if (ctx.rgb_grid)
        pp.edge_params.search_angle = 12;
    pp.rgb_hypotheses = ctx.rgb_hypotheses;
    pp.rgb_keep = ctx.rgb_keep;
    // the pose of a location is chosen among the matches of the class overlapping its first, as
    // Detector::detect() chooses it (both detectors' matches come here before any NMS)
    const bool choose = use_depth || ctx.rgb_refine;
    const size_t keep = use_depth ? (size_t)pp.depth_hypotheses
                                  : choose ? (size_t)pp.rgb_hypotheses : 1;
    const size_t K = skip + (size_t)std::max(1, ctx.verify.top_k);
    std::vector<std::vector<fm::PoseMatch> > groups;
    for (size_t i = 0; i < matches.size(); ++i)
    {
        const fm::PoseMatch& pm = matches[i];
        size_t g = 0;
        while (g < groups.size() && fm::boxIoU(pm.box, groups[g][0].box) <= 0.5)
            ++g;
        if (g == groups.size())
        {
            if (groups.size() < K)
                groups.push_back(std::vector<fm::PoseMatch>(1, pm));
        }
        else if (groups[g].size() < keep)
            groups[g].push_back(pm);
    }
    groups.erase(groups.begin(), groups.begin() + std::min(skip, groups.size()));
    top.clear(); // one hypothesis per location, in the order given
    const int64 t_pose = cv::getTickCount();
    // one set of edge maps for the frame, around every group (as detect() makes them around its
    // refined matches), read by the refinement and the verification
    edge_maps = fm::EdgeMaps();
    if (choose && !use_depth && !groups.empty())
    {
        const int margin = cvCeil(3 * pp.edge_params.max_distance);
        cv::Rect roi;
        for (size_t g = 0; g < groups.size(); ++g)
            for (size_t h = 0; h < groups[g].size(); ++h)
            {
                const cv::Rect b = groups[g][h].box;
                roi |= cv::Rect(b.x - margin, b.y - margin, b.width + 2 * margin,
                                b.height + 2 * margin);
            }
        fm::computeEdgeMaps(f.rgb, edge_maps, pp.edge_params, roi);
    }
    if (choose)
    {
        // every location refined, its pose chosen as Detector::detect() chooses it
        pp.max_per_class = (int)groups.size();
        std::vector<fm::PoseMatch> chosen;
        posedet.choosePoses(use_depth ? f.depth : cv::Mat(), f.K, groups, pp, f.rgb, chosen,
                            edge_maps);
        for (size_t g = 0; g < chosen.size(); ++g)
            if (chosen[g].has_pose)
                top.push_back(chosen[g]);
    }
    for (size_t g = 0; g < groups.size() && !choose; ++g)
    {
        std::vector<fm::PoseMatch>& hyp = groups[g];
        posedet.estimatePoses(cv::Mat(), f.K, hyp, pp, cv::Mat(), edge_maps);
        if (hyp[0].has_pose) // the template's pose
            top.push_back(hyp[0]);
    }
    return (cv::getTickCount() - t_pose) * 1000.0 / cv::getTickFrequency();
}

/** Detector::verify() of an object's hypotheses, on the refinement's edge maps where there are
any (RGB). */
static void verifyHypotheses(const fm::Detector& posedet, const EvalFrame& f,
                             const RunContext& ctx, std::vector<fm::PoseMatch>& top,
                             const fm::EdgeMaps& edge_maps, fm::DetectionStats& stats)
{
    if (top.empty())
        return;
    if (!edge_maps.distance.empty()) // the refinement's maps (RGB)
        posedet.verify(f.rgb, cv::Mat(), f.K, top, ctx.verify, &stats, edge_maps);
    else
        posedet.verify(f.rgb, ctx.use_depth ? f.depth : cv::Mat(), f.K, top, ctx.verify, &stats);
}

/** Scores the hypotheses of an object in a frame. matches: the detector's output (sorted, best
first, before non-maximum suppression); posedet: a forestmod::Detector with the same templates
(pose labels, meshes). res gets the first of the hypotheses made in the matcher's order
(recall@1) and any of them (recall@10); verified (optional) the first after Detector::verify()
re-ranked the hypotheses that detect() makes: with VerificationParams::background_weight > 0
those of the matches ordered by similarity - background_weight x background
(Detector::backgroundSimilarity), as detect() orders them, else the same as res's. */
static void scoreFrame(const std::vector<cv::linemod::Match>& matches, const fm::Detector& posedet,
                       const EvalFrame& f, const ObjectInfo& obj, const RunContext& ctx,
                       Result& res, Result* verified)
{
    const fm::GroundTruth* gt = 0;
    for (size_t i = 0; i < f.gt.size(); ++i)
        if (f.gt[i].obj_id == obj.obj_id)
        {
            gt = &f.gt[i];
            break;
        }
    if (!gt)
        return;
    const bool use_depth = ctx.use_depth;
    std::vector<fm::PoseMatch> ordered; // the class's matches, with pose labels and boxes
    for (size_t i = 0; i < matches.size(); ++i)
    {
        if (matches[i].class_id != obj.class_id)
            continue;
        fm::PoseMatch pm(matches[i]);
        pm.pose = posedet.getTemplatePose(matches[i].class_id, matches[i].template_id);
        const cv::linemod::Template& t0 = posedet.getTemplates(matches[i].class_id,
                                                               matches[i].template_id)[0];
        pm.box = cv::Rect(matches[i].x, matches[i].y, t0.width, t0.height);
        ordered.push_back(pm);
    }
    std::vector<fm::PoseMatch> top;
    fm::EdgeMaps edge_maps;
    res.pose.push_back(poseHypotheses(ordered, posedet, f, ctx, top, edge_maps));
    const double nan = std::numeric_limits<double>::quiet_NaN();
    FrameRecord rec;
    rec.scene_id = f.scene_id;
    rec.im_id = f.im_id;
    rec.t_ms = res.total.empty() ? nan : res.total.back();
    rec.template_id = -1;
    rec.similarity = 0.f;
    rec.iou = rec.proj = rec.add = rec.verification = nan;
    for (size_t i = 0; i < matches.size() && rec.top.size() < 5; ++i)
        if (matches[i].class_id == obj.class_id)
            rec.top.push_back(matches[i]);
    const cv::Rect2d on_object = groundTruthBox(*gt, f, obj);
    bestOnAndOff(matches, posedet, obj, on_object, rec);
    rec.gt_similarity = nan;
    if (ctx.gt)
        rec.gt_similarity = ctx.gt->similarity(posedet, obj, f, *gt, on_object);
    scoreHypotheses(top, *gt, on_object, f, obj, use_depth, res, rec);
    if (!verified)
        return;
    fm::DetectionStats stats;
    std::vector<fm::PoseMatch> by_background;
    if (ctx.verify.background_weight > 0 && !ordered.empty())
    {
        // detect()'s order: the matches that stand out from the frame first
        posedet.backgroundSimilarity(sourcesOf(posedet.getModalities(), f.rgb,
                                               use_depth ? f.depth : cv::Mat()),
                                     ordered, ctx.verify.background_quantile, &stats);
        by_background = ordered;
        fm::orderByBackground(by_background, ctx.verify.background_weight);
        verified->pose.push_back(poseHypotheses(by_background, posedet, f, ctx, top, edge_maps));
    }
    else // the plain row's hypotheses, posed above
        verified->pose.push_back(res.pose.back());
    verifyHypotheses(posedet, f, ctx, top, edge_maps, stats);
    // detect()'s second round (VerificationParams::second_round_below, RGB): the next top_k
    // locations when the first top_k hold no convincing hypothesis, all of them ranked together
    double best = -1;
    for (size_t k = 0; k < top.size(); ++k)
        best = std::max(best, top[k].verification);
    if (!use_depth && ctx.rgb_refine && best >= 0 && best < ctx.verify.second_round_below)
    {
        std::vector<fm::PoseMatch> more;
        fm::EdgeMaps maps2; // around these locations, as detect() makes them
        const double ms = poseHypotheses(by_background.empty() ? ordered : by_background,
                                         posedet, f, ctx, more, maps2, (size_t)ctx.verify.top_k);
        verified->pose.back() += ms;
        verifyHypotheses(posedet, f, ctx, more, maps2, stats);
        const size_t n_first = top.size();
        top.insert(top.end(), more.begin(), more.end());
        std::inplace_merge(top.begin(), top.begin() + (std::ptrdiff_t)n_first, top.end(),
                           [](const fm::PoseMatch& a, const fm::PoseMatch& b) {
                               return a.verification > b.verification;
                           });
    }
    verified->verify.push_back(stats.t_verify_ms);
    if (stats.verified > 0)
        verified->verify_per10.push_back(stats.t_verify_ms * 10.0 / stats.verified);
    verified->background.push_back(stats.t_background_ms);
    scoreHypotheses(top, *gt, on_object, f, obj, use_depth, *verified, rec, true,
                    (size_t)ctx.verify.top_k);
}

// the matcher's times and counters of a result, for its verified twin
static void copyTimes(const Result& r, Result& v)
{
    v.has_forest = r.has_forest;
    v.with_depth = r.with_depth;
    v.total = r.total;
    v.tree = r.tree;
    v.valid = r.valid;
    v.quant = r.quant;
    v.locations = r.locations;
    v.rejected = r.rejected;
}

static bool frameFor(const EvalFrame& f, int object_index)
{
    return f.owner < 0 || object_index < 0 || f.owner == object_index;
}

void runForestmod(const fm::Detector& det, const std::vector<ObjectInfo*>& objs,
                  int object_index, const RunContext& ctx, const std::string& label,
                  std::vector<Result>& res, std::vector<std::pair<int, cv::Mat> >* heat,
                  int heat_frames, std::vector<Result>* verified)
{
    CV_Assert(res.size() >= std::max<size_t>(1, objs.size()));
    const std::vector<cv::Ptr<cv::linemod::Modality> > mods = det.getModalities();
    int k = 0;
    for (size_t i = 0; i < ctx.frames->size(); ++i)
    {
        const EvalFrame& f = (*ctx.frames)[i];
        if (!frameFor(f, object_index))
            continue;
        const std::vector<cv::Mat> sources = sourcesOf(mods, f.rgb, f.depth);
        fm::DetectionStats best;
        double best_ms = std::numeric_limits<double>::infinity();
        std::vector<cv::linemod::Match> matches;
        for (int rep = 0; rep < ctx.repeat; ++rep)
        {
            fm::DetectionStats stats;
            matches.clear();
            cv::TickMeter tm;
            tm.start();
            det.match(sources, ctx.threshold, matches, std::vector<cv::String>(), cv::noArray(),
                      std::vector<cv::Mat>(), &stats);
            tm.stop();
            if (tm.getTimeMilli() < best_ms)
            {
                best_ms = tm.getTimeMilli();
                best = stats;
            }
        }
        if (heat && k < heat_frames)
            heat->push_back(std::make_pair((int)i, best.rejection_map.clone()));
        for (size_t o = 0; o < std::max<size_t>(1, objs.size()); ++o)
        {
            Result& r = res[o];
            r.has_forest = true;
            r.with_depth = ctx.use_depth;
            r.total.push_back(best_ms);
            r.tree.push_back(best.t_tree_ms);
            r.valid.push_back(best.t_valid_ms);
            r.quant.push_back(best.t_quantize_ms);
            r.locations += best.locations;
            r.rejected += best.rejected;
            if (verified)
                copyTimes(r, (*verified)[o]);
            if (o < objs.size())
                scoreFrame(matches, det, f, *objs[o], ctx, r, verified ? &(*verified)[o] : 0);
        }
        ++k;
        ctx.progress->step(cv::format("%s, frame %d", label.c_str(), k));
    }
}

/** cv::linemod's front end on one frame, as its match() runs it: every modality's process(),
then quantize() on every pyramid level (pyrDown() between levels). ms. */
static double linemodQuantizeMs(const cv::linemod::Detector& lm,
                                const std::vector<cv::Mat>& sources)
{
    const std::vector<cv::Ptr<cv::linemod::Modality> > mods = lm.getModalities();
    cv::TickMeter tm;
    tm.start();
    for (size_t m = 0; m < mods.size(); ++m)
    {
        cv::Ptr<cv::linemod::QuantizedPyramid> qp = mods[m]->process(sources[m]);
        for (int l = 0; l < lm.pyramidLevels(); ++l)
        {
            if (l > 0)
                qp->pyrDown();
            cv::Mat quantized;
            qp->quantize(quantized);
        }
    }
    tm.stop();
    return tm.getTimeMilli();
}

void runLinemod(const cv::linemod::Detector& lm, const fm::Detector* posedet,
                const std::vector<ObjectInfo*>& objs, int object_index, const RunContext& ctx,
                const std::string& label, std::vector<Result>& res,
                std::vector<Result>* verified)
{
    CV_Assert(res.size() >= std::max<size_t>(1, objs.size()));
    CV_Assert(posedet || objs.empty());
    const std::vector<cv::Ptr<cv::linemod::Modality> > mods = lm.getModalities();
    int k = 0;
    for (size_t i = 0; i < ctx.frames->size(); ++i)
    {
        const EvalFrame& f = (*ctx.frames)[i];
        if (!frameFor(f, object_index))
            continue;
        const std::vector<cv::Mat> sources = sourcesOf(mods, f.rgb, f.depth);
        std::vector<cv::linemod::Match> matches;
        double best_ms = std::numeric_limits<double>::infinity();
        double quant_ms = best_ms;
        for (int rep = 0; rep < ctx.repeat; ++rep)
        {
            matches.clear();
            cv::TickMeter tm;
            tm.start();
            lm.match(sources, ctx.threshold, matches);
            tm.stop();
            best_ms = std::min(best_ms, tm.getTimeMilli());
            quant_ms = std::min(quant_ms, linemodQuantizeMs(lm, sources));
        }
        for (size_t o = 0; o < std::max<size_t>(1, objs.size()); ++o)
        {
            Result& r = res[o];
            r.with_depth = ctx.use_depth;
            r.total.push_back(best_ms);
            r.quant.push_back(quant_ms);
            if (verified)
                copyTimes(r, (*verified)[o]);
            if (o < objs.size())
                scoreFrame(matches, *posedet, f, *objs[o], ctx, r,
                           verified ? &(*verified)[o] : 0);
        }
        ++k;
        ctx.progress->step(cv::format("%s, frame %d", label.c_str(), k));
    }
}

double trainDetector(fm::Detector& det, const EvalOptions& opt)
{
    cv::setNumThreads(opt.train_threads);
    cv::TickMeter tm;
    tm.start();
    det.train();
    tm.stop();
    cv::setNumThreads(opt.threads);
    return tm.getTimeSec();
}

RunContext runContext(const EvalOptions& opt, const std::vector<EvalFrame>& frames, bool use_depth,
                      Progress& progress)
{
    RunContext ctx;
    ctx.frames = &frames;
    ctx.threshold = opt.threshold;
    ctx.use_depth = use_depth;
    ctx.rgb_refine = opt.rgb_refine;
    ctx.rgb_grid = opt.rgb_grid;
    ctx.rgb_hypotheses = opt.rgb_hypotheses;
    ctx.rgb_keep = opt.rgb_keep;
    if (opt.gt_similarity)
        ctx.gt = std::make_shared<GroundTruthTemplates>();
    ctx.repeat = opt.repeat;
    ctx.progress = &progress;
    ctx.verify.top_k = opt.verify_k;
    if (opt.background_weight >= 0)
        ctx.verify.background_weight = opt.background_weight;
    if (opt.second_round >= 0)
        ctx.verify.second_round_below = opt.second_round;
    if (!opt.verify_weights.empty())
    {
        ctx.verify.w_similarity = opt.verify_weights[0];
        ctx.verify.w_color = opt.verify_weights[1];
        ctx.verify.w_edges = opt.verify_weights[2];
        ctx.verify.w_depth = opt.verify_weights[3];
        if (opt.verify_weights.size() > 4)
            ctx.verify.w_region = opt.verify_weights[4];
    }
    return ctx;
}

} // namespace fmeval
