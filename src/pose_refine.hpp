// This file is part of OpenCV project.
// It is subject to the license terms in the LICENSE file found in the top-level directory
// of this distribution and at http://opencv.org/license.html

// Internal: the pose refinements (ICP with depth, edge alignment without) and the depth check
// with the object drawn by an ObjectDrawer, e.g. on the CPU by drawMesh() without the OSMesa
// Renderer's lock, so that a frame's hypotheses refine in parallel.

#ifndef OPENCV_FORESTMOD_POSE_REFINE_HPP
#define OPENCV_FORESTMOD_POSE_REFINE_HPP

#include "opencv2/forestmod/pose.hpp"
#include "draw_mesh.hpp"

namespace cv {
namespace forestmod {
namespace detail {

/** Throws a cv::Exception (its message starting with `who`) unless `maps` hold one CV_32FC1
distance map per orientation bin, each of size `image`: computeEdgeMaps() of that image with
`orientations` bins. */
void checkEdgeMaps(const EdgeMaps& maps, int orientations, Size image, const char* who);

/** refinePoseEdges() with the object drawn by `drawer`; `last` (when given) receives the drawing
at the returned pose (empty when no start was refined). */
CV_EXPORTS EdgeRefineResult refinePoseEdges(const ObjectDrawer& drawer, const EdgeMaps& maps,
                                            const Matx33d& K, const Matx33d& R0, const Vec3d& t0,
                                            const EdgeRefineParams& params,
                                            Ptr<Drawing>* last = 0);

/** refinePose() (render, back-project, ICP; `passes` times) with the object drawn by
`drawer`. */
CV_EXPORTS ICPResult refinePose(const ObjectDrawer& drawer, InputArray scene_depth,
                                const Matx33d& K, const Matx33d& R0, const Vec3d& t0,
                                const ICPParams& params, int passes, int step = 1);

/** depthCheck() with the object drawn by `drawer`; `drawn` (when given) receives the drawing. */
CV_EXPORTS double depthCheck(const ObjectDrawer& drawer, InputArray scene_depth, const Matx33d& K,
                             const Matx33d& R, const Vec3d& t, double tolerance_mm,
                             Ptr<Drawing>* drawn = 0);

} // namespace detail
} // namespace forestmod
} // namespace cv

#endif
