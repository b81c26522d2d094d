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

void suppressOverlaps(const std::vector<Rect>& boxes, float iou, std::vector<int>& leader)
{
    CV_Assert(iou > 0.f && iou < 1.f);
    const int n = static_cast<int>(boxes.size());
    leader.assign(n, -1);
    if (n == 0)
        return;
    // The kept boxes in a grid of cells of half the largest side: boxes overlap by iou > 0 only
    // when they intersect, so a box is compared with the kept boxes of the cells it covers
    // (a few each), not with every kept box. The first kept box in order is the one of lowest
    // index: the same leaders as comparing with all of them in order.
    Rect all = boxes[0];
    int side = 1;
    for (int i = 0; i < n; ++i)
    {
        all |= boxes[i];
        side = std::max(side, std::max(boxes[i].width, boxes[i].height));
    }
    const int cell = std::max(16, side / 2);
    const int gx = all.width / cell + 1, gy = all.height / cell + 1;
    std::vector<std::vector<int> > grid((size_t)gx * gy);
    std::vector<int> seen(n, -1);
    for (int i = 0; i < n; ++i)
    {
        const Rect& a = boxes[i];
        const int x0 = (a.x - all.x) / cell, x1 = (a.x + a.width - 1 - all.x) / cell;
        const int y0 = (a.y - all.y) / cell, y1 = (a.y + a.height - 1 - all.y) / cell;
        for (int cy = y0; cy <= y1; ++cy)
            for (int cx = x0; cx <= x1; ++cx)
            {
                // a cell's kept boxes ascend: past the leader found so far, none can lead
                const std::vector<int>& kept = grid[(size_t)cy * gx + cx];
                for (size_t k = 0; k < kept.size(); ++k)
                {
                    const int j = kept[k];
                    if (leader[i] >= 0 && j > leader[i])
                        break;
                    if (seen[j] == i)
                        continue;
                    seen[j] = i;
                    const Rect& b = boxes[j];
                    const double inter = (a & b).area();
                    const double uni = a.area() + b.area() - inter;
                    if (uni > 0 && inter / uni > iou)
                        leader[i] = j;
                }
            }
        if (leader[i] < 0)
            for (int cy = y0; cy <= y1; ++cy)
                for (int cx = x0; cx <= x1; ++cx)
                    grid[(size_t)cy * gx + cx].push_back(i);
    }
}

void nonMaximumSuppression(const std::vector<cv::linemod::Match>& matches,
                           const ClassPyramids& pyramids, float iou, std::vector<int>& leader)
{
    std::vector<Rect> boxes(matches.size());
    for (size_t i = 0; i < matches.size(); ++i)
        boxes[i] = matchBox(matches[i], pyramids);
    suppressOverlaps(boxes, iou, leader);
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
