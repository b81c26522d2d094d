// This file is part of OpenCV project.
// It is subject to the license terms in the LICENSE file found in the top-level directory
// of this distribution and at http://opencv.org/license.html

// Internal: the search (paper: "Detection"): every location of the coarsest level on a grid of
// location_step pixels goes through the rejections before the forest (out of the templates' depth
// range, flat window) and through every search group's forest (rejectors, splits, all trees);
// the leaves' templates of the locations that stay are their candidates.

#ifndef OPENCV_FORESTMOD_SCAN_HPP
#define OPENCV_FORESTMOD_SCAN_HPP

#include "search_index.hpp"
#include "scene_pyramid.hpp"
#include "match_stats.hpp"

namespace cv {
namespace forestmod {
namespace detail {

/** The candidates of the locations that reached validation, in row-major location order. */
struct LocationCandidates
{
    int step;                      //!< the location grid's stride (coarsest level pixels)
    std::vector<Point> location;   //!< (column, row) on the location grid
    std::vector<int> begin;        //!< candidates of location i: rows[begin[i] .. begin[i + 1])
    std::vector<int> rows;         //!< index rows (SearchIndex::rows), ascending per location
    /** [search group of SearchIndex::groups]: searched exhaustively in this frame (its forest let
    too many pairs through on the sample rows, DetectorParams::exhaustive_ratio); its templates
    are in no location's candidates. */
    std::vector<uchar> exhaustive;
    MatchCounters counters;
    /** On request: the forest depth at which each location was rejected, -1 when it was not, -2
    when its window was flat, -3 when out of depth range (DetectionStats::rejection_map). */
    Mat rejection_map;

    LocationCandidates() : step(1) {}
    int size() const { return static_cast<int>(location.size()); }
};

/** Scans the coarsest level. row_allowed: per index row, whether its class was asked for;
the depth-range test runs per group when the scene has depth cells
(DetectorParams::depth_range_tolerance >= 0).
With DetectorParams::exhaustive_ratio > 0, every 8th row of locations is first a sample: each
group descends every k-th of its locations (k >= 1 such that its limit, scaled to the locations
descended, stays at least 512 pairs) until the (location, candidate) pairs it lets through,
extrapolated to the frame, pass the ratio's limit; such groups are marked `exhaustive` and left
out of the scan (they give no candidates; a location within such a group's depth range is not
counted as rejected, since the exhaustive search scores it). Then every row goes through the
groups that stay. 0: every group exhaustive, no forest. */
void scanLocations(const SearchIndex& index, const ScenePyramid& scene,
                   const DetectorParams& params, const std::vector<uchar>& row_allowed,
                   bool rejection_map, LocationCandidates& out);

/** The descriptor windows of a row of W locations, as the scan reads them: window c holds
ptr[j][row + c * S] for every dimension j (D = ptr.size() bytes), stored at win + c * D. With
S = 4 (the default location step) 16 locations at a time through a transpose; the same bytes as
one load per value. */
CV_EXPORTS void gatherRowWindows(const std::vector<const uchar*>& ptr, ptrdiff_t row, int W,
                                 int S, uchar* win);

} // namespace detail
} // namespace forestmod
} // namespace cv

#endif
