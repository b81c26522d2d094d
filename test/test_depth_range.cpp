// This file is part of OpenCV project.
// It is subject to the license terms in the LICENSE file found in the top-level directory
// of this distribution and at http://opencv.org/license.html

// The out-of-depth-range rejection's frame side (src/depth_range.hpp): the scene depth's minimum
// and maximum per cell over its 3 x 3 neighbourhood, against a direct computation; the widened
// template range. The detector's use of it: Forestmod_Detector.depth_range_* and the golden
// test's 1tree_depth_range cases.

#include "test_precomp.hpp"
#include "../src/depth_range.hpp"

namespace opencv_test { namespace {

using namespace cv::forestmod::detail;

TEST(Forestmod_DepthRange, cells_hold_the_depth_range_of_their_neighbourhood)
{
    RNG rng(11);
    const Size sizes[] = { Size(640, 480), Size(101, 67), Size(16, 16), Size(7, 3) };
    const int cells[] = { 16, 16, 5, 4 };
    for (int s = 0; s < 4; ++s)
    {
        const Size size = sizes[s];
        const int cell = cells[s];
        Mat depth(size, CV_16UC1);
        rng.fill(depth, RNG::UNIFORM, Scalar(1), Scalar(65536));
        depth.setTo(0, depth < 20000); // holes, some cells without any depth
        depth(Rect(0, 0, std::min(size.width, 2 * cell), std::min(size.height, 2 * cell)))
            .setTo(0);
        depth.at<ushort>(size.height - 1, size.width - 1) = 65535;
        DepthCells dc;
        dc.set(depth, cell);
        const int cols = (size.width + cell - 1) / cell, rows = (size.height + cell - 1) / cell;
        ASSERT_EQ(Size(cols, rows), dc.zmin.size());
        ASSERT_EQ(Size(cols, rows), dc.zmax.size());
        ASSERT_EQ((size_t)rows, dc.row_min.size());
        for (int cy = 0; cy < rows; ++cy)
        {
            int row_lo = 65535, row_hi = 0, row_unknown = 0;
            for (int cx = 0; cx < cols; ++cx)
            {
                int lo = 65535, hi = 0;
                for (int y = std::max(0, (cy - 1) * cell);
                     y < std::min(size.height, (cy + 2) * cell); ++y)
                    for (int x = std::max(0, (cx - 1) * cell);
                         x < std::min(size.width, (cx + 2) * cell); ++x)
                    {
                        const int z = depth.at<ushort>(y, x);
                        if (z)
                        {
                            lo = std::min(lo, z);
                            hi = std::max(hi, z);
                        }
                    }
                ASSERT_EQ(hi, dc.zmax.at<ushort>(cy, cx)) << s << " " << cx << "," << cy;
                ASSERT_EQ(lo, dc.zmin.at<ushort>(cy, cx)) << s << " " << cx << "," << cy;
                if (!hi)
                    row_unknown = 1;
                else
                {
                    row_lo = std::min(row_lo, lo);
                    row_hi = std::max(row_hi, hi);
                }
                // reaches(): every span that meets [lo, hi], and any span where nothing is known
                EXPECT_TRUE(dc.reaches(cx, cy, DepthSpan(hi, hi + 10)));
                if (hi)
                {
                    EXPECT_FALSE(dc.reaches(cx, cy, DepthSpan(hi + 1, hi + 10)) && hi < 65535);
                    EXPECT_EQ(lo > 1, !dc.reaches(cx, cy, DepthSpan(0, lo - 1)));
                }
                else
                    EXPECT_TRUE(dc.reaches(cx, cy, DepthSpan(1, 2)));
            }
            EXPECT_EQ(row_lo, dc.row_min[cy]);
            EXPECT_EQ(row_hi, dc.row_max[cy]);
            EXPECT_EQ(row_unknown, dc.row_unknown[cy]);
        }
        EXPECT_TRUE(dc.reaches(-1, 0, DepthSpan(1, 2))) << "outside the grid: no test";
        EXPECT_TRUE(dc.reaches(cols, rows, DepthSpan(1, 2)));
        EXPECT_TRUE(dc.reaches(cols - 1, rows - 1, DepthSpan())) << "empty span: no test";
    }
    DepthCells dc;
    EXPECT_THROW(dc.set(Mat(), 16), cv::Exception);
    EXPECT_THROW(dc.set(Mat(4, 4, CV_32F, Scalar(1)), 16), cv::Exception);
    EXPECT_THROW(dc.set(Mat(4, 4, CV_16U, Scalar(1)), 0), cv::Exception);
}

TEST(Forestmod_DepthRange, widened_span)
{
    const DepthSpan s = widenedSpan(DepthSpan(1000, 1100), 0.25f);
    EXPECT_EQ(800, s.lo);
    EXPECT_EQ(1375, s.hi);
    EXPECT_TRUE(widenedSpan(DepthSpan(1000, 1100), -1.f).empty()) << "negative: off";
    EXPECT_TRUE(widenedSpan(DepthSpan(), 0.25f).empty()) << "no depth samples: no test";
    const DepthSpan big = widenedSpan(DepthSpan(1000, 60000), 1e30f);
    EXPECT_EQ(0, big.lo);
    EXPECT_EQ(65535, big.hi);
}

}} // namespace
