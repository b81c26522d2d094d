// This file is part of OpenCV project.
// It is subject to the license terms in the LICENSE file found in the top-level directory
// of this distribution and at http://opencv.org/license.html

// What cv::linemod lacks: a 6-DoF pose per match. Initial pose from the matched template's label
// and the match location (+ scene depth), ICP refinement and the depth check (pose.cpp).

#include "precomp.hpp"
#include "detector_impl.hpp"
#include "validator.hpp"

#include "opencv2/calib3d.hpp"

namespace cv {
namespace forestmod {

PoseParams::PoseParams()
    : max_per_class(3), icp(true), icp_passes(2), depth_check_tolerance(0.05),
      min_depth_agreement(0.5), rgb_refine(true), rgb_hypotheses(8)
{
}

void PoseParams::read(const FileNode& fn)
{
    if (!fn["max_per_class"].empty())
        max_per_class = (int)fn["max_per_class"];
    if (!fn["icp"].empty())
        icp = (int)fn["icp"] != 0;
    if (!fn["icp_passes"].empty())
        icp_passes = (int)fn["icp_passes"];
    if (!fn["icp_params"].empty())
        icp_params.read(fn["icp_params"]);
    if (!fn["depth_check_tolerance"].empty())
        depth_check_tolerance = (double)fn["depth_check_tolerance"];
    if (!fn["min_depth_agreement"].empty())
        min_depth_agreement = (double)fn["min_depth_agreement"];
    if (!fn["rgb_refine"].empty())
        rgb_refine = (int)fn["rgb_refine"] != 0;
    if (!fn["edge_params"].empty())
        edge_params.read(fn["edge_params"]);
    if (!fn["rgb_hypotheses"].empty())
        rgb_hypotheses = (int)fn["rgb_hypotheses"];
}

void PoseParams::write(FileStorage& fs) const
{
    fs << "max_per_class" << max_per_class << "icp" << (int)icp << "icp_passes" << icp_passes;
    fs << "icp_params" << "{";
    icp_params.write(fs);
    fs << "}";
    fs << "depth_check_tolerance" << depth_check_tolerance << "min_depth_agreement"
       << min_depth_agreement << "rgb_refine" << (int)rgb_refine;
    fs << "edge_params" << "{";
    edge_params.write(fs);
    fs << "}";
    fs << "rgb_hypotheses" << rgb_hypotheses;
}

void Detector::setMesh(const String& class_id, const Mesh& mesh)
{
    mesh.validate();
    AutoLock lock(impl_->render_mutex);
    impl_->meshes[class_id] = mesh;
    impl_->diameters[class_id] = mesh.diameter();
    impl_->mesh_handles.erase(class_id); // uploaded again on the next use
}

bool Detector::hasMesh(const String& class_id) const
{
    AutoLock lock(impl_->render_mutex);
    return impl_->meshes.count(class_id) > 0;
}

// The renderer handle of a class's mesh for images of `size` (-1 without a mesh); the renderer is
// made again when the size changes. Call with impl.render_mutex held.
static int meshHandle(Detector::Impl& impl, const String& class_id, Size size)
{
    std::map<String, Mesh>::const_iterator mit = impl.meshes.find(class_id);
    if (mit == impl.meshes.end())
        return -1;
    if (impl.renderer.empty() || impl.renderer->size() != size)
    {
        impl.renderer = Renderer::create(size);
        impl.mesh_handles.clear();
    }
    std::map<String, int>::iterator hit = impl.mesh_handles.find(class_id);
    if (hit == impl.mesh_handles.end())
        hit = impl.mesh_handles.insert(std::make_pair(class_id,
                                                      impl.renderer->addMesh(mit->second))).first;
    return hit->second;
}

void Detector::estimatePoses(InputArray _depth, const Matx33d& K, std::vector<PoseMatch>& matches,
                             const PoseParams& params, InputArray color) const
{
    CV_CheckGT(params.icp_passes, 0, "PoseParams: icp_passes must be positive");
    CV_CheckGE(params.max_per_class, 0, "PoseParams: max_per_class must be >= 0");
    CV_CheckGE(params.rgb_hypotheses, 1, "PoseParams: rgb_hypotheses must be >= 1");
    CV_CheckGT(params.depth_check_tolerance, 0.0, "PoseParams: depth_check_tolerance must be > 0");
    Mat depth = _depth.getMat();
    if (!depth.empty() && depth.type() != CV_16UC1)
        CV_Error_(Error::StsUnsupportedFormat, ("forestmod::Detector::estimatePoses: depth must "
                                                "be CV_16UC1 in mm, got %s",
                                                typeToString(depth.type()).c_str()));
    if (K(0, 0) <= 0 || K(1, 1) <= 0)
        CV_Error(Error::StsBadArg, "forestmod::Detector::estimatePoses: K has no focal length");
    Impl& impl = *impl_;
    std::map<String, int> refined_per_class;
    Mat scene_color = color.getMat();
    if (!scene_color.empty() && scene_color.type() != CV_8UC3)
        CV_Error(Error::StsUnsupportedFormat, "forestmod::Detector::estimatePoses: color must be "
                                              "a CV_8UC3 BGR image");
    EdgeMaps edge_maps; // of the scene colour around the matches to refine, made on first use
    Rect edge_roi;
    if (depth.empty() && params.rgb_refine && !scene_color.empty())
    {
        std::map<String, int> count;
        const int margin = cvCeil(3 * params.edge_params.max_distance);
        for (size_t i = 0; i < matches.size(); ++i)
            if (matches[i].pose.valid && count[matches[i].class_id]++ < params.max_per_class)
            {
                const Rect b(matches[i].x - margin, matches[i].y - margin,
                             matches[i].pose.box.width + 2 * margin,
                             matches[i].pose.box.height + 2 * margin);
                edge_roi = edge_roi.area() > 0 ? (edge_roi | b) : b;
            }
        edge_roi &= Rect(0, 0, scene_color.cols, scene_color.rows);
    }
    std::vector<PoseMatch> kept;
    for (size_t i = 0; i < matches.size(); ++i)
    {
        PoseMatch m = matches[i];
        m.has_pose = m.refined = false;
        m.depth_agreement = -1;
        m.edge_fit = -1;
        if (!m.pose.valid)
        {
            kept.push_back(m);
            continue;
        }
        const TemplatePose& tp = m.pose;
        const Vec3d pt = tp.K * tp.t;
        const Point2d template_px(pt[0] / pt[2], pt[1] / pt[2]);
        const Point2d scene_px = Point2d(m.x, m.y) + (template_px - Point2d(tp.box.tl()));
        double z = 0;
        const std::map<String, std::vector<std::vector<Point3i> > >::const_iterator dit
            = impl.depth.find(m.class_id);
        if (!depth.empty() && dit != impl.depth.end()
            && m.template_id < (int)dit->second.size())
        {
            const std::vector<Point3i>& samples = dit->second[m.template_id];
            std::vector<Point> pos;
            std::vector<float> tz;
            for (size_t k = 0; k < samples.size(); ++k)
            {
                pos.push_back(Point(m.x + samples[k].x, m.y + samples[k].y));
                tz.push_back((float)samples[k].z);
            }
            if (!pos.empty())
                z = sceneDepthFromFeatures(depth, pos, tz, tp.t[2]);
        }
        initialPose(tp.R, tp.t, tp.K, template_px, K, scene_px, z, m.R, m.t);
        m.has_pose = true;

        bool drop = false;
        int& done = refined_per_class[m.class_id];
        if (!depth.empty() && params.icp && done < params.max_per_class)
        {
            AutoLock lock(impl.render_mutex);
            const int handle = meshHandle(impl, m.class_id, depth.size());
            if (handle >= 0)
            {
                m.icp = refinePose(*impl.renderer, handle, depth, K, m.R, m.t,
                                   params.icp_params, params.icp_passes);
                if (m.icp.fitness > 0)
                {
                    m.R = m.icp.R;
                    m.t = m.icp.t;
                    m.refined = true;
                }
                const double tol = params.depth_check_tolerance * impl.diameters[m.class_id];
                m.depth_agreement = depthCheck(*impl.renderer, handle, depth, K, m.R, m.t, tol);
                drop = m.depth_agreement < params.min_depth_agreement;
                ++done;
            }
        }
        if (depth.empty() && params.rgb_refine && done < params.max_per_class && !scene_color.empty())
        {
            AutoLock lock(impl.render_mutex);
            const int handle = meshHandle(impl, m.class_id, scene_color.size());
            if (handle >= 0)
            {
                if (edge_maps.distance.empty())
                    computeEdgeMaps(scene_color, edge_maps, params.edge_params, edge_roi);
                const EdgeRefineResult er = refinePoseEdges(*impl.renderer, handle, edge_maps, K,
                                                            m.R, m.t, params.edge_params);
                if (er.points > 0)
                {
                    m.R = er.R;
                    m.t = er.t;
                    m.refined = true;
                    m.edge_fit = er.inlier_ratio;
                }
                ++done;
            }
        }
        if (!drop)
            kept.push_back(m);
    }
    matches.swap(kept);
}

static PoseMatch toPoseMatch(const Detector& det, const linemod::Match& m)
{
    PoseMatch pm(m);
    const linemod::Template& t0 = det.getTemplates(m.class_id, m.template_id)[0];
    pm.box = Rect(m.x, m.y, t0.width, t0.height);
    pm.pose = det.getTemplatePose(m.class_id, m.template_id);
    return pm;
}

void Detector::detect(const std::vector<Mat>& sources, const Matx33d& K, float threshold,
                      std::vector<PoseMatch>& matches, const std::vector<String>& class_ids,
                      const PoseParams& params, DetectionStats* stats) const
{
    CV_CheckGE(params.rgb_hypotheses, 1, "PoseParams: rgb_hypotheses must be >= 1");
    Mat depth, color;
    for (size_t i = 0; i < modalities.size() && i < sources.size(); ++i)
    {
        if (modalities[i]->name() == "DepthNormal")
            depth = sources[i];
        else if (sources[i].type() == CV_8UC3 && color.empty())
            color = sources[i];
    }
    const float nms_iou = impl_->params.nms_iou;
    const bool choose = depth.empty() && !color.empty() && params.rgb_refine
        && params.rgb_hypotheses > 1 && nms_iou > 0.f && nms_iou < 1.f;
    if (!choose)
    {
        match(sources, threshold, matches, class_ids, std::vector<Mat>(), stats);
        estimatePoses(depth, K, matches, params, color);
        return;
    }
    // all matches, then non-maximum suppression that keeps each detection's group: the matches
    // of its class at overlapping locations (as nonMaximumSuppression() in detector.cpp)
    std::vector<linemod::Match> all;
    matchImpl(sources, threshold, all, class_ids, noArray(), std::vector<Mat>(), stats, false);
    std::vector<PoseMatch> leaders;
    std::vector<std::vector<PoseMatch> > groups;
    for (size_t i = 0; i < all.size(); ++i)
    {
        PoseMatch pm = toPoseMatch(*this, all[i]);
        const Rect box(pm.x, pm.y, std::max(1, pm.box.width), std::max(1, pm.box.height));
        int owner = -1;
        for (size_t j = 0; j < leaders.size() && owner < 0; ++j)
        {
            const Rect& lb = leaders[j].box;
            const Rect b2(lb.x, lb.y, std::max(1, lb.width), std::max(1, lb.height));
            const double inter = (box & b2).area();
            const double uni = box.area() + b2.area() - inter;
            if (uni > 0 && inter / uni > nms_iou)
                owner = (int)j;
        }
        if (owner < 0)
        {
            leaders.push_back(pm);
            groups.push_back(std::vector<PoseMatch>(1, pm));
        }
        else if (all[i].class_id == leaders[owner].class_id
                 && (int)groups[owner].size() < params.rgb_hypotheses)
            groups[owner].push_back(pm);
    }
    // the best max_per_class detections of each class: every hypothesis of the group refined,
    // the best edge fit kept; the other detections get their template's pose
    matches.clear();
    std::map<String, int> per_class;
    PoseParams one = params;
    one.max_per_class = params.rgb_hypotheses;
    PoseParams plain = params;
    plain.rgb_refine = false;
    for (size_t g = 0; g < groups.size(); ++g)
    {
        std::vector<PoseMatch>& hyps = groups[g];
        if (per_class[leaders[g].class_id]++ >= params.max_per_class)
        {
            hyps.resize(1);
            estimatePoses(noArray(), K, hyps, plain);
            matches.push_back(hyps[0]);
            continue;
        }
        estimatePoses(noArray(), K, hyps, one, color);
        size_t best = 0;
        for (size_t h = 1; h < hyps.size(); ++h)
            if (hyps[h].edge_fit > hyps[best].edge_fit)
                best = h;
        // the detection keeps its position, box and score (the ranking stays the matcher's);
        // template, pose label and pose come from the chosen hypothesis
        PoseMatch m = hyps[best];
        m.x = hyps[0].x;
        m.y = hyps[0].y;
        m.similarity = hyps[0].similarity;
        m.box = hyps[0].box;
        matches.push_back(m);
    }
}

} // namespace forestmod
} // namespace cv
