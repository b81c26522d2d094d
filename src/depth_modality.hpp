// This file is part of OpenCV project.
// It is subject to the license terms in the LICENSE file found in the top-level directory
// of this distribution and at http://opencv.org/license.html

// Internal: depth as a validation modality (paper: "we add depth value as another modality in the
// validation stage to measure shape similarity"), scored at the pyramid refinement levels.

#ifndef OPENCV_FORESTMOD_DEPTH_MODALITY_HPP
#define OPENCV_FORESTMOD_DEPTH_MODALITY_HPP

#include "opencv2/core.hpp"

#include <vector>

namespace cv {
namespace forestmod {
namespace detail {

/** The scene side. A template keeps depth samples (x, y relative to its top-left at level 0,
z mm). With the template's top-left at `origin` (level 0) the offset (scene minus template) is
the median over the samples where the scene has depth; a sample then scores like a LINEMOD
feature, 0..4, by how far z + offset lies outside the range [zmin, zmax] of the scene depth
around it: the *relative* depths are compared (shape, not distance), and the range (the depth
counterpart of LINEMOD's spreading) tolerates the position error of a candidate. Samples without
scene depth (holes, outside the image) score 0, like features without a quantized value. */
struct DepthContext
{
    DepthContext() : tolerance(10), scale_shift(0) {}
    Mat depth;      //!< scene depth, level 0, CV_16UC1 mm (0: none)
    Mat zmin, zmax; //!< its minimum / maximum over a square around each pixel (holes left out:
                    //!< zmin 65535 and zmax 0 where the square has no depth)
    int tolerance;  //!< mm: a residual within it scores 4
    int scale_shift; //!< a level's pixel -> level 0: << scale_shift
    Point2f pp;     //!< the scene's principal point, taken as the image centre

    /** depth, zmin, zmax of a scene depth with a square of (2 radius + 1)^2 pixels. */
    void set(const Mat& scene_depth, int radius);
};

/** The template side: its depth samples and the geometry that predicts them elsewhere in the
image. An object seen at another image position is seen along another ray, and its depths (z,
not the distance along the ray) tilt accordingly (up to +-15 mm over an LM-O object 20 degrees
off the axis). The template's camera points P_i = z_i K_t^-1 (u_i, v_i, 1) are turned by the
rotation that takes the ray through the template's object centre onto the ray through the
candidate's (the scene's focal length taken as the template's, its principal point as the image
centre); the predicted depth is the z of the turned point. */
struct DepthTemplate
{
    DepthTemplate() : samples(0), fx(0), fy(0) {}
    const std::vector<Point3i>* samples; //!< x, y relative to the top-left (level 0), z mm
    Point2f pp;     //!< the template's principal point relative to its top-left (level 0)
    Point2f centre; //!< its object centre (projection of t) relative to its top-left
    float fx, fy;   //!< its focal lengths; 0: no pose, depths compared as they are
};

/** Rotation, offset and the first `count` samples (all when count < 0) of a template whose
top-left is at `origin` (level 0): the sum of 0..4 per sample. */
int depthSimilarity(const DepthContext& dc, const DepthTemplate& t, Point origin, int count = -1);

/** Depth samples scored at a pyramid level: as many as the template has features per modality
there (at most `samples`, at most 256), so that depth weighs like one more modality at every
level (the coarsest level has fewer features than level 0). The samples are ordered (most
distinctive relief first, spread over the object), so a prefix is a sparser selection. */
static inline int depthSamplesAtLevel(int samples, int features, int num_modalities)
{
    const int per_modality = num_modalities > 0
        ? (features + num_modalities - 1) / num_modalities : features;
    return std::max(0, std::min(std::min(samples, 256), per_modality));
}

} // namespace detail
} // namespace forestmod
} // namespace cv

#endif
