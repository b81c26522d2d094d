// This file is part of OpenCV project.
// It is subject to the license terms in the LICENSE file found in the top-level directory
// of this distribution and at http://opencv.org/license.html

// The out-of-depth-range rejection: the scene depth per cell of the coarsest level's T grid, and
// the templates' widened depth ranges (depth_range.hpp).

#include "precomp.hpp"
#include "depth_range.hpp"

namespace cv {
namespace forestmod {
namespace detail {

DepthSpan widenedSpan(const DepthSpan& samples, float tolerance)
{
    if (samples.empty() || tolerance < 0)
        return DepthSpan();
    const double f = 1.0 + tolerance;
    return DepthSpan(cvFloor(samples.lo / f), cvCeil(std::min(samples.hi * f, 65535.0)));
}

void DepthCells::set(const Mat& depth, int cell_size)
{
    CV_Assert(depth.type() == CV_16UC1 && !depth.empty() && cell_size > 0);
    cell = cell_size;
    const int cols = (depth.cols + cell - 1) / cell, rows = (depth.rows + cell - 1) / cell;
    Mat lo(rows, cols, CV_16UC1, Scalar(65535)), hi(rows, cols, CV_16UC1, Scalar(0));
    // per band of `cell` rows: the columns' minimum of depth - 1 (a hole, 0, wraps to 65535 and
    // never lowers it) and maximum, element by element (vectorised by the compiler), then each
    // cell's over its columns
    std::vector<ushort> col_lo(depth.cols), col_hi(depth.cols);
    for (int cy = 0; cy < rows; ++cy)
    {
        std::fill(col_lo.begin(), col_lo.end(), (ushort)65535);
        std::fill(col_hi.begin(), col_hi.end(), (ushort)0);
        ushort* cl = &col_lo[0];
        ushort* ch = &col_hi[0];
        for (int y = cy * cell; y < std::min(depth.rows, (cy + 1) * cell); ++y)
        {
            const ushort* d = depth.ptr<ushort>(y);
            for (int x = 0; x < depth.cols; ++x)
            {
                cl[x] = std::min(cl[x], (ushort)(d[x] - 1));
                ch[x] = std::max(ch[x], d[x]);
            }
        }
        ushort* l = lo.ptr<ushort>(cy);
        ushort* h = hi.ptr<ushort>(cy);
        for (int c = 0; c < cols; ++c)
        {
            const int x1 = std::min(depth.cols, (c + 1) * cell);
            ushort a = 65535, b = 0;
            for (int x = c * cell; x < x1; ++x)
            {
                a = std::min(a, cl[x]);
                b = std::max(b, ch[x]);
            }
            l[c] = b ? (ushort)(a + 1) : (ushort)65535; // no depth: 65535, as erode's border
            h[c] = b;
        }
    }
    const Mat k = getStructuringElement(MORPH_RECT, Size(3, 3));
    erode(lo, zmin, k, Point(-1, -1), 1, BORDER_CONSTANT, Scalar(65535));
    dilate(hi, zmax, k, Point(-1, -1), 1, BORDER_CONSTANT, Scalar(0));
    row_min.assign(rows, 65535);
    row_max.assign(rows, 0);
    row_unknown.assign(rows, 0);
    for (int y = 0; y < rows; ++y)
        for (int x = 0; x < cols; ++x)
        {
            const ushort a = zmin.at<ushort>(y, x), b = zmax.at<ushort>(y, x);
            if (!b)
                row_unknown[y] = 1;
            else
            {
                row_min[y] = std::min(row_min[y], a);
                row_max[y] = std::max(row_max[y], b);
            }
        }
}

} // namespace detail
} // namespace forestmod
} // namespace cv
