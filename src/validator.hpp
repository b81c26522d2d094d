// This file is part of OpenCV project.
// It is subject to the license terms in the LICENSE file found in the top-level directory
// of this distribution and at http://opencv.org/license.html

// Internal: the validation stage (paper: "Fast Breadth-first Leaf Validation"): the candidate
// templates of every location that left the forest are scored with LINEMOD's similarity,
// breadth-first; the best survivors over the threshold become coarse matches. A search group
// whose forest let through too many (location, candidate) pairs in a frame is searched
// exhaustively instead (exhaustive_search.hpp, DetectorParams::exhaustive_ratio). scoreAt is
// exported (CV_EXPORTS) for the tests and perf tests only; the header is not installed.

#ifndef OPENCV_FORESTMOD_VALIDATOR_HPP
#define OPENCV_FORESTMOD_VALIDATOR_HPP

#include "linear_memories.hpp"
#include "scan.hpp"

#include <vector>

namespace cv {
namespace forestmod {
namespace detail {

/** The forest path's scoring without its bookkeeping (tests, perf tests): raw[i] = the raw score
of all features of `templ` with its top-left at tls[i] (any pixel whose features stay within
the memories' border), read from memories built with buildGrid. */
CV_EXPORTS void scoreAt(const LinearMemories& lm, const TemplatePyramid& templ, int level_index,
                        int num_modalities, const std::vector<Point>& tls,
                        std::vector<int>& raw);

/** The validation stage: every location's candidates validated (breadth_first or all), the best
max_survivors of each over the threshold as coarse matches (positions of the coarsest level as
cv::linemod reports them), in location order; then the coarse matches of the search groups
searched exhaustively in this frame (DetectorParams::exhaustive_ratio), group by group, template
by template, in LINEMOD's order. row_allowed: per index row, whether its class was asked for.
`exhaustive_groups`, when given, receives the number of groups searched exhaustively. */
CV_EXPORTS void validateLocations(const ScenePyramid& scene, const LocationCandidates& cands,
                                  const SearchIndex& index, const ClassPyramids& pyramids,
                                  const DetectorParams& params, float threshold,
                                  const std::vector<uchar>& row_allowed,
                                  std::vector<cv::linemod::Match>& coarse,
                                  int* exhaustive_groups = 0);

/** validateLocations for each class on its own (DetectorParams::search_per_class): class_of_row
holds, per index row, the class's index into `coarse` (one list per class), -1 for a class not
asked for. A location's survivors are chosen among its candidates of one class, and the
exhaustive search's positions keep the best of each class, with entry bars of their own: coarse[c]
is what validateLocations gives with the same candidates and groups asked for class c alone. */
void validateLocationsPerClass(const ScenePyramid& scene, const LocationCandidates& cands,
                               const SearchIndex& index, const ClassPyramids& pyramids,
                               const DetectorParams& params, float threshold,
                               const std::vector<int>& class_of_row,
                               std::vector<std::vector<cv::linemod::Match> >& coarse);

} // namespace detail
} // namespace forestmod
} // namespace cv

#endif
