// This file is part of OpenCV project.
// It is subject to the license terms in the LICENSE file found in the top-level directory
// of this distribution and at http://opencv.org/license.html

#include "precomp.hpp"
#include "match_stats.hpp"

namespace cv {
namespace forestmod {

void DetectionStats::reset()
{
    t_quantize_ms = t_tree_ms = t_valid_ms = t_total_ms = t_verify_ms = t_background_ms = 0;
    verified = 0;
    locations = rejected = rejected_flat = rejected_depth_range = validated = candidates = 0;
    rejected_at_depth.clear();
    rejection_map.release();
}

namespace detail {

static void addAtDepth(std::vector<int64>& dst, const std::vector<int64>& src)
{
    if (dst.size() < src.size())
        dst.resize(src.size(), 0);
    for (size_t d = 0; d < src.size(); ++d)
        dst[d] += src[d];
}

MatchCounters& MatchCounters::operator+=(const MatchCounters& b)
{
    locations += b.locations;
    rejected_forest += b.rejected_forest;
    rejected_flat += b.rejected_flat;
    rejected_depth_range += b.rejected_depth_range;
    validated += b.validated;
    candidates += b.candidates;
    addAtDepth(rejected_at_depth, b.rejected_at_depth);
    return *this;
}

void MatchCounters::rejectedAtDepth(int depth)
{
    ++rejected_forest;
    if ((int)rejected_at_depth.size() <= depth)
        rejected_at_depth.resize(depth + 1, 0);
    ++rejected_at_depth[depth];
}

void MatchCounters::addTo(DetectionStats& stats) const
{
    stats.locations += locations;
    stats.rejected += rejected_forest + rejected_flat + rejected_depth_range;
    stats.rejected_flat += rejected_flat;
    stats.rejected_depth_range += rejected_depth_range;
    stats.validated += validated;
    stats.candidates += candidates;
    addAtDepth(stats.rejected_at_depth, rejected_at_depth);
}

} // namespace detail
} // namespace forestmod
} // namespace cv
