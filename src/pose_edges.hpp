// This file is part of OpenCV project.
// It is subject to the license terms in the LICENSE file found in the top-level directory
// of this distribution and at http://opencv.org/license.html

// Internal: the edge refinement (refinePoseEdges) with the object drawn by any means, e.g. on the
// CPU by drawMesh() without the OSMesa Renderer's lock.

#ifndef OPENCV_FORESTMOD_POSE_EDGES_HPP
#define OPENCV_FORESTMOD_POSE_EDGES_HPP

#include "opencv2/forestmod/pose.hpp"

namespace cv {
namespace forestmod {
namespace detail {

/** How the edge refinement sees the object at a pose: its depth (CV_16U, mm, 0 off the object)
and mask (CV_8U) in the crop `rect` of the scene image (empty when nothing is drawn). */
class CV_EXPORTS ObjectDrawer
{
public:
    virtual ~ObjectDrawer() {}
    /** Size of the scene image (the edge maps' size). */
    virtual Size imageSize() const = 0;
    virtual void draw(const Matx33d& K, const Matx33d& R, const Vec3d& t, Rect& rect, Mat& depth,
                      Mat& mask) const = 0;
};

/** drawMesh() of a mesh (e.g. coarseMesh()) with its closedWinding(): no lock, so the
hypotheses of a frame refine in parallel. The mesh must outlive the drawer. */
class CV_EXPORTS MeshDrawer : public ObjectDrawer
{
public:
    MeshDrawer(const Mesh& mesh, int winding, Size image)
        : mesh_(mesh), winding_(winding), image_(image)
    {
    }
    Size imageSize() const CV_OVERRIDE { return image_; }
    void draw(const Matx33d& K, const Matx33d& R, const Vec3d& t, Rect& rect, Mat& depth,
              Mat& mask) const CV_OVERRIDE;

private:
    const Mesh& mesh_;
    const int winding_;
    const Size image_;
};

/** refinePoseEdges() with the object drawn by `drawer`. */
CV_EXPORTS EdgeRefineResult refinePoseEdges(const ObjectDrawer& drawer, const EdgeMaps& maps,
                                            const Matx33d& K, const Matx33d& R0, const Vec3d& t0,
                                            const EdgeRefineParams& params);

} // namespace detail
} // namespace forestmod
} // namespace cv

#endif
