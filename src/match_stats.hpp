// This file is part of OpenCV project.
// It is subject to the license terms in the LICENSE file found in the top-level directory
// of this distribution and at http://opencv.org/license.html

// Internal: the counters of one match() call, kept per worker and merged with +=, and the clock
// that times its stages.

#ifndef OPENCV_FORESTMOD_MATCH_STATS_HPP
#define OPENCV_FORESTMOD_MATCH_STATS_HPP

#include "opencv2/forestmod/detector.hpp"

#include <vector>

namespace cv {
namespace forestmod {
namespace detail {

struct MatchCounters
{
    int64 locations;            //!< visited on the coarsest level
    int64 rejected_forest;      //!< by a forest's rejectors (every search group)
    int64 rejected_flat;        //!< flat window in every search group
    int64 rejected_depth_range; //!< scene depth outside the templates' range
    int64 validated;            //!< locations validated with candidates
    int64 candidates;           //!< candidate templates validated, over locations
    std::vector<int64> rejected_at_depth; //!< forest rejections per depth

    MatchCounters()
        : locations(0), rejected_forest(0), rejected_flat(0), rejected_depth_range(0),
          validated(0), candidates(0)
    {
    }
    MatchCounters& operator+=(const MatchCounters& b);
    void rejectedAtDepth(int depth);
    /** Adds the counters to a DetectionStats. */
    void addTo(DetectionStats& stats) const;
};

/** Wall time of consecutive stages: lap() returns the milliseconds since the previous lap. */
class StageClock
{
public:
    StageClock() : start_(getTickCount()), last_(start_) {}
    double lap()
    {
        const int64 now = getTickCount();
        const double ms = (now - last_) * 1000.0 / getTickFrequency();
        last_ = now;
        return ms;
    }
    double total() const { return (getTickCount() - start_) * 1000.0 / getTickFrequency(); }

private:
    int64 start_, last_;
};

} // namespace detail
} // namespace forestmod
} // namespace cv

#endif
