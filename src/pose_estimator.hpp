// This file is part of OpenCV project.
// It is subject to the license terms in the LICENSE file found in the top-level directory
// of this distribution and at http://opencv.org/license.html

// Internal: what cv::linemod lacks, a 6-DoF pose per match. Owns the classes' meshes and their
// coarse copies, which the refinements, the depth check and the verification draw with
// drawMesh() (no OSMesa at detection time).

#ifndef OPENCV_FORESTMOD_POSE_ESTIMATOR_HPP
#define OPENCV_FORESTMOD_POSE_ESTIMATOR_HPP

#include "template_store.hpp"
#include "draw_mesh.hpp"

#include <map>

namespace cv {
namespace forestmod {
namespace detail {

class SceneNormals; // pose_refine.hpp

/** A match with its template's box and pose label. */
PoseMatch toPoseMatch(const cv::linemod::Match& m, const ClassPyramids& pyramids,
                      const TemplateStore& store);

/** A class's mesh as the pose stage and the verification draw it: coarseMesh() (vertices
clustered on a grid of drawingCell(diameter) mm) with its faces in clusterFaces()' order, its
closedWinding() and face clusters, the full mesh's diameter (mm) and each face's colour in HSV
(faceColours(), for the verification's colour score). */
struct DrawnMesh
{
    uint64 id; //!< unique over the process (a mesh set again gets a new one): Drawing::source
    Mesh mesh;
    int winding;
    FaceClusters clusters;
    SilhouetteEdges silhouette; //!< of the mesh as clusterFaces() ordered it
    double diameter;
    Mat face_hsv; //!< CV_8UC3, one row per face
};

/** Detector::detect's locations: `all` are the matches before non-maximum suppression (best
first) and `leader` its result (nonMaximumSuppression); each kept detection, in their order,
with up to `per_location` matches of its class that it suppressed (itself first). */
std::vector<std::vector<PoseMatch> > suppressedLocations(const std::vector<PoseMatch>& all,
                                                         const std::vector<int>& leader,
                                                         size_t per_location);

class PoseEstimator
{
public:
    void setMesh(const String& class_id, const Mesh& mesh);
    bool hasMesh(const String& class_id) const;
    /** Exchanges the meshes with `other`'s (Detector::load keeps the meshes set before it). */
    void swapMeshes(PoseEstimator& other);

    PoseEstimator() {}
    /** A copy of the meshes (Detector's copy). */
    PoseEstimator(const PoseEstimator& other);
    PoseEstimator& operator=(const PoseEstimator& other) = delete;

    /** Detector::estimatePoses: initial pose from the template's label (and the scene depth under
    its depth samples), ICP with depth, edge alignment without; depth check and drop. The edge
    alignment reads edge_maps when they are not empty, else computes them around the refined
    matches into it. */
    void estimate(const TemplateStore& store, const Mat& depth, const Matx33d& K,
                  std::vector<PoseMatch>& matches, const PoseParams& params,
                  const Mat& color, EdgeMaps& edge_maps);

    /** Detector::choosePoses, Detector::detect: each location's pose chosen among its matches
    (`locations[g]`, one class, best first) for the first max_per_class locations per class; the
    others keep their first match's template pose. With depth (and params.icp): the first whose
    ICP pose passes the depth check (chooseWithDepth); without: the best edge fit. edge_maps as
    for estimate(). detections[g] is location g's. */
    void chooseAmong(const TemplateStore& store, std::vector<std::vector<PoseMatch> > locations,
                     const Mat& depth, const Matx33d& K, const PoseParams& params,
                     const Mat& color, std::vector<PoseMatch>& detections, EdgeMaps& edge_maps);

    /** What the verification and the refinements draw of a class; null without a mesh. The
    pointer stays valid until setMesh() is called again (which must not run concurrently with
    detection). */
    const DrawnMesh* drawnMesh(const String& class_id) const;
private:
    // the drawing of a class's coarse mesh for images of `size` (the class has a mesh) and the
    // full mesh's diameter
    MeshDrawer drawerOf(const String& class_id, Size size, double& diameter) const;
    // ICP and the depth check of matches[refine[k]] (classes with a mesh), drawn with drawMesh()
    // in parallel; drop[refine[k]] is set when the depth check fails
    void refineWithDepth(const Mat& depth, const Matx33d& K, const PoseParams& params,
                         std::vector<PoseMatch>& matches, const std::vector<size_t>& refine,
                         std::vector<char>& drop) const;
    // ICP from m's pose on the frame's normals and the depth check (m's class has a mesh); true
    // when m passes it (params.min_depth_agreement)
    bool refineOneWithDepth(const Mat& depth, const Matx33d& K, const PoseParams& params,
                            const detail::SceneNormals& normals, PoseMatch& m) const;
    // LINEMOD ACCV 2012's post-processing per location: of the first params.depth_hypotheses
    // matches of each of the first params.max_per_class locations per class, refined one after
    // the other, the first that passes the depth check gives the location's pose (position, box
    // and score stay its first match's); a location none of whose refined matches passes is
    // dropped. The locations are refined in parallel on one set of scene normals; the others
    // keep their first match's initial pose.
    void chooseWithDepth(const TemplateStore& store,
                         const std::vector<std::vector<PoseMatch> >& locations, const Mat& depth,
                         const Matx33d& K, const PoseParams& params,
                         std::vector<PoseMatch>& detections) const;
    // edge alignment of matches[refine[k]] (classes with a mesh), drawn with drawMesh() in
    // parallel, against one set of edge maps: edge_maps if not empty, else made around them.
    // With `location` (location[k]: the location of refine[k]), only the params.rgb_keep best
    // edge fits of each location after the first pass go on; the others keep their start pose
    void refineWithEdges(const Mat& color, const Matx33d& K, const PoseParams& params,
                         std::vector<PoseMatch>& matches, const std::vector<size_t>& refine,
                         EdgeMaps& edge_maps, const std::vector<int>* location = 0) const;
    std::map<String, DrawnMesh> drawn_; //!< drawnMesh()
    mutable Mutex mutex_;               //!< guards drawn_
};

} // namespace detail
} // namespace forestmod
} // namespace cv

#endif
