// This file is part of OpenCV project.
// It is subject to the license terms in the LICENSE file found in the top-level directory
// of this distribution and at http://opencv.org/license.html

// Internal: the background similarity of matches, which orders a class's hypotheses before the
// pose stage (VerificationParams::background_weight).

#ifndef OPENCV_FORESTMOD_BACKGROUND_HPP
#define OPENCV_FORESTMOD_BACKGROUND_HPP

#include "scene_pyramid.hpp"
#include "template_store.hpp"

#include <vector>

namespace cv {
namespace forestmod {
namespace detail {

/** For every match, how well its template fits the frame anywhere: its similarity (percent, as
cv::linemod::Match::similarity on the coarsest level) at `quantile` of every position of the
coarsest level's T grid where it fits, read from the level's linearized memories (one SIMD add
per feature and 32 positions, as the exhaustive search). Each distinct template is scored once,
in parallel; `background[i]` is matches[i]'s, 0 for a template larger than the frame. A match of
a class or template the pyramids do not hold raises StsBadArg. */
void backgroundSimilarity(const ScenePyramid& scene, const ClassPyramids& pyramids,
                          const std::vector<cv::linemod::Match>& matches, double quantile,
                          std::vector<float>& background);

/** The order of the hypotheses before the pose stage: matches sorted (stably) by similarity -
weight x background, best first. */
void orderByDistinctiveness(std::vector<cv::linemod::Match>& matches,
                            const std::vector<float>& background, double weight);

} // namespace detail
} // namespace forestmod
} // namespace cv

#endif
