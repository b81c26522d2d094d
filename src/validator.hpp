// This file is part of OpenCV project.
// It is subject to the license terms in the LICENSE file found in the top-level directory
// of this distribution and at http://opencv.org/license.html

// Internal: the scene's quantized pyramid (computed once per frame) and LINEMOD's similarity read
// from it in place, with the paper's breadth-first preemptive validation.

#ifndef OPENCV_FORESTMOD_VALIDATOR_HPP
#define OPENCV_FORESTMOD_VALIDATOR_HPP

#include "opencv2/core.hpp"
#include "opencv2/rgbd/linemod.hpp"

#include <vector>

namespace cv {
namespace forestmod {
namespace detail {

typedef std::vector<cv::linemod::Template> TemplatePyramid;

/** One pyramid level of a frame: per modality the quantized and spread images and the 8 response
maps (LINEMOD section 2.4), each padded by `pad` zero pixels on the right and bottom so that a
template partly outside the image reads zeros instead of leaving the buffer. */
struct LevelMaps
{
    Size size; //!< image size at this level (without padding)
    int T;
    int pad;
    std::vector<Mat> quantized;             //!< [modality], size `size`
    std::vector<Mat> spread;                //!< [modality], padded
    std::vector<std::vector<Mat> > response; //!< [modality][label], CV_8U 0..4, padded
};

/** Spreads labels over a T x T window: dst(p) = OR of src over [p, p + T) (LINEMOD 2.3). */
void spreadLabels(const Mat& src, Mat& dst, int T, int pad);
/** 8 response maps of a spread image: response[o](p) = max similarity of orientation o to the
labels of p (LINEMOD 2.4: 4 same bin, 3, 2, 1, 0 opposite; circular). */
void computeResponseMaps(const Mat& spread, std::vector<Mat>& response);

/** Raw similarity (sum of responses, 0..4 per feature) of the features [begin, end) of one
modality's template with its top-left corner at `tl` (level pixels). */
int similarityRange(const LevelMaps& level, int modality, const cv::linemod::Template& templ,
                    Point tl, int begin, int end);

/** Raw similarity of all modalities of a template at one level (16/32-bit accumulation: any
number of features). num_features, when given, receives the feature count. */
int similarityAll(const LevelMaps& level, const TemplatePyramid& tp, int level_index,
                  Point tl, int* num_features = 0);

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

/** Depth as a validation modality (paper: "we add depth value as another modality in the
validation stage"), applied to a refined match: the share of the template's depth samples
(x, y relative to its top-left, z mm) whose scene depth, minus the template's, lies within
`tolerance` of the median offset. `valid` receives the number of samples with scene depth; the
share is 0 when fewer than half have it. */
double depthAgreement(const Mat& scene_depth, const std::vector<Point3i>& samples, Point tl,
                      int tolerance, int* valid = 0);

/** Scores every candidate on all its features (no pruning). */
void validateAll(const LevelMaps& level, int level_index, std::vector<ValidationCandidate>& cands);

/** Breadth-first preemptive validation (paper): features in chunks of chunk_size; after each
chunk keep the candidates whose normalised score raw / (4 scored) is >= the median of the
survivors and > alpha; stop when max_survivors (paper: 1) or fewer are left (or features run out). The survivors are
then scored on all their features. Returns the indices (into `cands`) of the survivors. */
void validateBreadthFirst(const LevelMaps& level, int level_index, int num_modalities,
                          std::vector<ValidationCandidate>& cands, int chunk_size, float alpha,
                          int max_survivors, std::vector<int>& survivors);

} // namespace detail
} // namespace forestmod
} // namespace cv

#endif
