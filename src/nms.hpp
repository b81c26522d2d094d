// This file is part of OpenCV project.
// It is subject to the license terms in the LICENSE file found in the top-level directory
// of this distribution and at http://opencv.org/license.html

// Internal: non-maximum suppression over matches of all templates and classes.

#ifndef OPENCV_FORESTMOD_NMS_HPP
#define OPENCV_FORESTMOD_NMS_HPP

#include "template_store.hpp"

namespace cv {
namespace forestmod {
namespace detail {

/** The box of a match: its template's level-0 extent at the match (at least 1 x 1). */
Rect matchBox(const cv::linemod::Match& m, const ClassPyramids& pyramids);

/** Greedy non-maximum suppression of matches sorted best first: leader[i] = -1 when match i is
kept (no kept match before it overlaps its box by more than `iou`, intersection over union),
else the index of the first kept match that does. */
void nonMaximumSuppression(const std::vector<cv::linemod::Match>& matches,
                           const ClassPyramids& pyramids, float iou, std::vector<int>& leader);

/** The kept matches only (leader -1), in order. */
void keepLeaders(std::vector<cv::linemod::Match>& matches, const std::vector<int>& leader);

} // namespace detail
} // namespace forestmod
} // namespace cv

#endif
