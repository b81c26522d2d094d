// This file is part of OpenCV project.
// It is subject to the license terms in the LICENSE file found in the top-level directory
// of this distribution and at http://opencv.org/license.html

// Non-maximum suppression (suppressOverlaps) of a frame's refined matches: boxes of the sizes of
// LM-O's objects at 650-1150 mm on a VGA frame, a few to a dozen around each of many places, as
// match() hands them over (about 2 700 per frame, 600 kept, for the 8 LM-O objects in one model).

#include "perf_precomp.hpp"
#include "../src/nms.hpp"

namespace opencv_test { namespace {

typedef TestBaseWithParam<int> Forestmod_NMS;

PERF_TEST_P(Forestmod_NMS, suppressOverlaps_vga, Values(700, 2700))
{
    const int n = GetParam();
    RNG rng(3);
    std::vector<Rect> boxes;
    while ((int)boxes.size() < n)
    {
        // a place: one template size, then its boxes shifted by a few pixels
        const int w = rng.uniform(20, 120), h = rng.uniform(w / 2, 2 * w);
        const Point c(rng.uniform(0, 640), rng.uniform(0, 480));
        for (int k = rng.uniform(1, 12); k > 0 && (int)boxes.size() < n; --k)
        {
            const int s = rng.uniform(0, 3) ? 0 : rng.uniform(-w / 4, w / 4);
            boxes.push_back(Rect(c.x - (w + s) / 2 + rng.uniform(-6, 7),
                                 c.y - (h + s) / 2 + rng.uniform(-6, 7), w + s, h + s));
        }
    }
    // the matches come best first; their places interleave
    for (int i = n - 1; i > 0; --i)
        std::swap(boxes[i], boxes[rng.uniform(0, i + 1)]);
    std::vector<int> leader;
    TEST_CYCLE() cv::forestmod::detail::suppressOverlaps(boxes, 0.5f, leader);
    const int kept = (int)std::count(leader.begin(), leader.end(), -1);
    EXPECT_GT(kept, n / 20);
    EXPECT_LT(kept, n / 2);
    SANITY_CHECK_NOTHING();
}

}} // namespace
