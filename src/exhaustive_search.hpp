// This file is part of OpenCV project.
// It is subject to the license terms in the LICENSE file found in the top-level directory
// of this distribution and at http://opencv.org/license.html

// Internal: the exhaustive search of the search groups whose forest rejected too little in a
// frame (DetectorParams::exhaustive_ratio), as cv::linemod on the coarsest level's T grid: the
// frame then costs at most what cv::linemod's search of the same templates costs; and the linear
// search of DetectorParams::use_forest false. scoreEverywhere is exported (CV_EXPORTS) for the
// tests and perf tests only; the header is not installed.

#ifndef OPENCV_FORESTMOD_EXHAUSTIVE_SEARCH_HPP
#define OPENCV_FORESTMOD_EXHAUSTIVE_SEARCH_HPP

#include "linear_memories.hpp"
#include "scene_pyramid.hpp"
#include "match_stats.hpp"

#include <vector>

namespace cv {
namespace forestmod {
namespace detail {

/** The exhaustive search's scoring without its bookkeeping (tests, perf tests): raw scores of a
template at every position (c T, r T) of the coarsest level where it fits (c <= span_x,
r <= span_y, LINEMOD's positions), vectorised as cv::linemod: one SIMD add per
feature and vector of positions, the positions in tiles whose sums stay in registers over all
features (8-bit sums of up to 63 features widened into 16-bit ones). `scores[r * stride + c]`;
returns false when the template fits nowhere. At most 16383 features (16-bit sums). */
CV_EXPORTS bool scoreEverywhere(const LinearMemories& lm, const TemplatePyramid& tp,
                                int level_index, int num_modalities, int& span_x, int& span_y,
                                std::vector<ushort>& scores);

/** Every template of `rows` (index rows of the groups searched exhaustively, asked for) at every
position of the coarsest level's T grid where it fits (cv::linemod's positions and scores) and,
when the scene has depth cells (ScenePyramid::depth_cells), where the scene depth around its
centre reaches into its depth samples' range widened by `depth_tolerance`; each
position keeps its best `keep` templates over the threshold as coarse matches, appended to
`*out[0]` (row-major positions, best first). With `list_of_row` (per index row, an index into
`out`; DetectorParams::search_per_class) a position keeps the best `keep` of each list, with entry
bars of its own, appended to `*out[list]`: what a search of that list's rows alone gives.
The templates are scored in blocks that the threads take as they free up, each thread into best
lists of its own, merged afterwards: the result does not depend on the threads. */
void searchExhaustive(const ScenePyramid& scene, const SearchIndex& index,
                      const ClassPyramids& pyramids, const std::vector<int>& rows,
                      float threshold, int keep, float depth_tolerance,
                      const std::vector<std::vector<cv::linemod::Match>*>& out,
                      const std::vector<int>* list_of_row = 0);

/** Exhaustive LINEMOD search of the given classes: every template at every position of the
coarsest level where it fits, class by class, template by template; the coarse matches over the
threshold (refined by refineMatches, without depth: the scene has no depth contexts then). */
void matchExhaustive(const ScenePyramid& scene, const ClassPyramids& pyramids,
                     const std::vector<String>& classes, float threshold,
                     std::vector<cv::linemod::Match>& matches, MatchCounters& counters);

} // namespace detail
} // namespace forestmod
} // namespace cv

#endif
