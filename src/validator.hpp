// This file is part of OpenCV project.
// It is subject to the license terms in the LICENSE file found in the top-level directory
// of this distribution and at http://opencv.org/license.html

// Internal: the validation stage (paper: "Fast Breadth-first Leaf Validation"): the candidate
// templates of every location that left the forest are scored with LINEMOD's similarity,
// breadth-first; the best survivors over the threshold become coarse matches.

#ifndef OPENCV_FORESTMOD_VALIDATOR_HPP
#define OPENCV_FORESTMOD_VALIDATOR_HPP

#include "similarity.hpp"
#include "scan.hpp"

#include <vector>

namespace cv {
namespace forestmod {
namespace detail {

/** A candidate of validation: a template and where its top-left is at the coarsest level. */
struct ValidationCandidate
{
    int index;     //!< caller's index
    const TemplatePyramid* tp;
    Point tl;
    int raw;       //!< accumulated raw score
    int scored;    //!< features scored so far
    int total;     //!< features of the template (all modalities)
};

/** Scores every candidate on all its features (no pruning). */
void validateAll(const LevelMaps& level, int level_index, std::vector<ValidationCandidate>& cands);

/** Breadth-first preemptive validation (paper): features in chunks of chunk_size; after each
chunk keep the candidates whose normalised score raw / (4 scored) is >= the median of the
survivors and > alpha; stop when max_survivors (paper: 1) or fewer are left (or features run
out). Every chunk takes the same share of each modality's features. The survivors are then scored
on all their features. Returns the indices (into `cands`) of the survivors. */
void validateBreadthFirst(const LevelMaps& level, int level_index, int num_modalities,
                          std::vector<ValidationCandidate>& cands, int chunk_size, float alpha,
                          int max_survivors, std::vector<int>& survivors);

/** The validation stage: every location's candidates validated (breadth_first or all), the best
max_survivors of each over the threshold as coarse matches (positions of the coarsest level as
cv::linemod reports them), in location order. */
void validateLocations(const ScenePyramid& scene, const LocationCandidates& cands,
                       const SearchIndex& index, const ClassPyramids& pyramids,
                       const DetectorParams& params, float threshold,
                       std::vector<cv::linemod::Match>& coarse);

} // namespace detail
} // namespace forestmod
} // namespace cv

#endif
