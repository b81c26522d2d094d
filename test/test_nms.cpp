// This file is part of OpenCV project.
// It is subject to the license terms in the LICENSE file found in the top-level directory
// of this distribution and at http://opencv.org/license.html

// Non-maximum suppression: the grid of kept boxes gives the leaders of the greedy definition
// (each box against every kept box before it, in order).

#include "test_precomp.hpp"
#include "../src/nms.hpp"

namespace opencv_test { namespace {

using namespace cv::forestmod::detail;

// The definition: box i's leader is the first kept box before it that overlaps it by more
// than iou.
static std::vector<int> greedyLeaders(const std::vector<Rect>& boxes, float iou)
{
    std::vector<int> leader(boxes.size(), -1), kept;
    for (size_t i = 0; i < boxes.size(); ++i)
    {
        for (size_t k = 0; k < kept.size() && leader[i] < 0; ++k)
        {
            const Rect& b = boxes[kept[k]];
            const double inter = (boxes[i] & b).area();
            const double uni = boxes[i].area() + b.area() - inter;
            if (uni > 0 && inter / uni > iou)
                leader[i] = kept[k];
        }
        if (leader[i] < 0)
            kept.push_back((int)i);
    }
    return leader;
}

TEST(Forestmod_NMS, grid_of_kept_boxes_gives_the_greedy_leaders)
{
    RNG rng(5);
    for (int trial = 0; trial < 20; ++trial)
    {
        // boxes of two sizes, some partly outside the image (negative corners), many in
        // clusters so that boxes are suppressed by a kept box other than the first they meet
        std::vector<Rect> boxes;
        const int n = rng.uniform(0, 600);
        for (int i = 0; i < n; ++i)
        {
            const int side = rng.uniform(0, 3) ? rng.uniform(20, 60) : rng.uniform(100, 300);
            const int cx = rng.uniform(0, 4) ? rng.uniform(100, 140) : rng.uniform(-50, 690);
            const int cy = rng.uniform(0, 4) ? rng.uniform(100, 140) : rng.uniform(-50, 530);
            boxes.push_back(Rect(cx - side / 2, cy - side / 2, side, side + rng.uniform(0, 9)));
        }
        for (float iou : { 0.05f, 0.3f, 0.5f, 0.9f })
        {
            const std::vector<int> expect = greedyLeaders(boxes, iou);
            std::vector<int> leader;
            suppressOverlaps(boxes, iou, leader);
            ASSERT_EQ(expect, leader) << "trial " << trial << " iou " << iou;
            if (n > 100)
            {
                // not trivial: some boxes kept, some suppressed by a kept box other than box 0
                const int kept = (int)std::count(leader.begin(), leader.end(), -1);
                EXPECT_GT(kept, 1);
                EXPECT_LT(kept, n);
                EXPECT_TRUE(std::any_of(leader.begin(), leader.end(), [](int l) {
                    return l > 0;
                }));
            }
        }
    }
    // small boxes over a range thousands of times their size, in pairs that overlap: cells of
    // (1 - iou) x the largest side would number millions; the grid keeps about 4 per box
    for (float iou : { 0.5f, 0.9f })
    {
        std::vector<Rect> boxes;
        for (int i = 0; i < 300; ++i)
        {
            const Rect r(rng.uniform(-20000, 20000), rng.uniform(-20000, 20000),
                         rng.uniform(4, 11), rng.uniform(4, 11));
            boxes.push_back(r);
            boxes.push_back(rng.uniform(0, 2) ? r : r + Point(1, 0));
        }
        const std::vector<int> expect = greedyLeaders(boxes, iou);
        std::vector<int> leader;
        suppressOverlaps(boxes, iou, leader);
        ASSERT_EQ(expect, leader) << "iou " << iou;
        // a pair shifted by a pixel overlaps by (w - 1) / (w + 1) = 0.6-0.82
        const int kept = (int)std::count(leader.begin(), leader.end(), -1);
        if (iou < 0.6f)
            EXPECT_EQ(300, kept);
        else
            EXPECT_GT(kept, 300);
    }
    std::vector<int> leader;
    EXPECT_THROW(suppressOverlaps(std::vector<Rect>(2, Rect(0, 0, 5, 5)), 0.f, leader),
                 cv::Exception);
}

}} // namespace
