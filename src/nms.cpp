// This file is part of OpenCV project.
// It is subject to the license terms in the LICENSE file found in the top-level directory
// of this distribution and at http://opencv.org/license.html

#include "precomp.hpp"
#include "nms.hpp"

namespace cv {
namespace forestmod {
namespace detail {

Rect matchBox(const cv::linemod::Match& m, const ClassPyramids& pyramids)
{
    const cv::linemod::Template& t0 = pyramids.find(m.class_id)->second[m.template_id][0];
    return Rect(m.x, m.y, std::max(1, t0.width), std::max(1, t0.height));
}

void nonMaximumSuppression(const std::vector<cv::linemod::Match>& matches,
                           const ClassPyramids& pyramids, float iou, std::vector<int>& leader)
{
    leader.assign(matches.size(), -1);
    std::vector<int> kept;
    std::vector<Rect> boxes(matches.size());
    for (size_t i = 0; i < matches.size(); ++i)
    {
        boxes[i] = matchBox(matches[i], pyramids);
        for (size_t j = 0; j < kept.size() && leader[i] < 0; ++j)
        {
            const Rect& b = boxes[kept[j]];
            const double inter = (boxes[i] & b).area();
            const double uni = boxes[i].area() + b.area() - inter;
            if (uni > 0 && inter / uni > iou)
                leader[i] = kept[j];
        }
        if (leader[i] < 0)
            kept.push_back((int)i);
    }
}

void keepLeaders(std::vector<cv::linemod::Match>& matches, const std::vector<int>& leader)
{
    size_t n = 0;
    for (size_t i = 0; i < matches.size(); ++i)
        if (leader[i] < 0)
            matches[n++] = matches[i];
    matches.resize(n);
}

} // namespace detail
} // namespace forestmod
} // namespace cv
