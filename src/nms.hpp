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

/** Greedy non-maximum suppression of boxes sorted best first, iou in (0, 1): leader[i] = -1
when box i is kept (no kept box before it overlaps it by more than `iou`, intersection over
union), else the index of the first kept box that does. */
CV_EXPORTS void suppressOverlaps(const std::vector<Rect>& boxes, float iou,
                                 std::vector<int>& leader);

/** suppressOverlaps() of the matches' boxes: each its template's level-0 extent at the match
(at least 1 x 1), read from the store's flat sizes (TemplateStore::classSizes). */
void nonMaximumSuppression(const std::vector<cv::linemod::Match>& matches,
                           const TemplateStore& store, float iou, std::vector<int>& leader);

/** The kept matches only (leader -1), in order. */
void keepLeaders(std::vector<cv::linemod::Match>& matches, const std::vector<int>& leader);

} // namespace detail
} // namespace forestmod
} // namespace cv

#endif
