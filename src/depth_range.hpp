// This file is part of OpenCV project.
// It is subject to the license terms in the LICENSE file found in the top-level directory
// of this distribution and at http://opencv.org/license.html

// Internal: the out-of-depth-range rejection (paper: "out-of-depth-range"). A template shows its
// object at the image size it was rendered at only where the object lies at about the template's
// distance; with a scene depth, a template (a search group) is searched only at the positions
// where the scene depth around its centre reaches into its depth samples' range, widened by
// DetectorParams::depth_range_tolerance. The frame side: the scene depth's minimum and maximum
// per cell of the coarsest level's T grid, over the cell and its 8 neighbours.

#ifndef OPENCV_FORESTMOD_DEPTH_RANGE_HPP
#define OPENCV_FORESTMOD_DEPTH_RANGE_HPP

#include "opencv2/core.hpp"
#include <vector>

namespace cv {
namespace forestmod {
namespace detail {

/** A depth range [lo, hi] in mm; empty (lo > hi) when nothing is known. */
struct DepthSpan
{
    int lo, hi;
    DepthSpan() : lo(INT_MAX), hi(INT_MIN) {}
    DepthSpan(int lo_, int hi_) : lo(lo_), hi(hi_) {}
    bool empty() const { return lo > hi; }
    void add(const DepthSpan& o)
    {
        lo = std::min(lo, o.lo);
        hi = std::max(hi, o.hi);
    }
};

/** The range a template's object may span in a scene where it is searched: its depth samples'
[z_min, z_max] widened to [z_min / (1 + tolerance), z_max x (1 + tolerance)]; empty stays empty
(no samples: no test). */
CV_EXPORTS DepthSpan widenedSpan(const DepthSpan& samples, float tolerance);

/** The scene depth per cell of `cell` x `cell` pixels (level 0; T << L for the coarsest level's
T grid): its known depths' minimum and maximum over the 3 x 3 cells around each cell (holes left
out; zmin 65535 and zmax 0 where none is known). */
struct CV_EXPORTS DepthCells
{
    Mat zmin, zmax;                  //!< CV_16UC1, ceil(rows / cell) x ceil(cols / cell)
    std::vector<ushort> row_min, row_max; //!< [cell row]: over the whole row of cells
    std::vector<uchar> row_unknown;  //!< [cell row]: some cell of the row has no depth
    int cell;

    DepthCells() : cell(0) {}
    bool empty() const { return zmin.empty(); }
    /** Made from a CV_16UC1 depth image (mm, 0: unknown). */
    void set(const Mat& depth, int cell_size);
    /** Whether the scene depth around cell (cx, cy) reaches into `span`: true outside the grid,
    where no depth is known, and for an empty span. */
    bool reaches(int cx, int cy, const DepthSpan& span) const
    {
        if (span.empty() || cx < 0 || cy < 0 || cx >= zmin.cols || cy >= zmin.rows)
            return true;
        const int hi = zmax.at<ushort>(cy, cx);
        return hi == 0 || (hi >= span.lo && zmin.at<ushort>(cy, cx) <= span.hi);
    }
    /** Whether some cell of row cy may reach into `span` (reaches() of a cell implies it). */
    bool rowReaches(int cy, const DepthSpan& span) const
    {
        if (span.empty() || cy < 0 || cy >= zmin.rows)
            return true;
        return row_unknown[cy] || (row_max[cy] >= span.lo && row_min[cy] <= span.hi);
    }
};

} // namespace detail
} // namespace forestmod
} // namespace cv

#endif
