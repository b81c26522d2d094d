// This file is part of OpenCV project.
// It is subject to the license terms in the LICENSE file found in the top-level directory
// of this distribution and at http://opencv.org/license.html

// Internal: the verification stage. Pose hypotheses are rendered at their pose and scored on
// colour, contour edges, occlusion and depth, then re-ranked (doc/verification.md).

#ifndef OPENCV_FORESTMOD_VERIFICATION_HPP
#define OPENCV_FORESTMOD_VERIFICATION_HPP

#include "pose_estimator.hpp"
#include "draw_mesh.hpp"

namespace cv {
namespace forestmod {
namespace detail {

/** Throws a cv::Exception naming the first bad field of p. */
void checkVerificationParams(const VerificationParams& p);
/** Throws StsOutOfRange unless q is in (0, 1] (a background quantile). */
void checkBackgroundQuantile(double q);

/** Detector::verify: scores the first p.top_k hypotheses with a pose of every class whose mesh
`poses` holds, fills their verification fields and moves them to the front of `matches`, best
first. color: CV_8UC3; depth: CV_16UC1 or empty; maps: the frame's edge maps (computeEdgeMaps()
with p.edge_params) or null, then each crop's edges are found with Canny. */
void verifyHypotheses(PoseEstimator& poses, const Mat& color, const Mat& depth, const Matx33d& K,
                      std::vector<PoseMatch>& matches, const VerificationParams& p,
                      const EdgeMaps* maps, DetectionStats* stats);

} // namespace detail
} // namespace forestmod
} // namespace cv

#endif
