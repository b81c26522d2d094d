// This file is part of OpenCV project.
// It is subject to the license terms in the LICENSE file found in the top-level directory
// of this distribution and at http://opencv.org/license.html

// Internal: a frame's maps at one pyramid level and LINEMOD's similarity read from them in place
// (Hinterstoisser et al., PAMI 2012, sections 2.3-2.4).

#ifndef OPENCV_FORESTMOD_SIMILARITY_HPP
#define OPENCV_FORESTMOD_SIMILARITY_HPP

#include "opencv2/core.hpp"
#include "opencv2/rgbd/linemod.hpp"

#include <vector>

namespace cv {
namespace forestmod {
namespace detail {

typedef std::vector<cv::linemod::Template> TemplatePyramid;

/** One pyramid level of a frame: per modality the quantized and spread images, the spread ones
padded by `pad` zero pixels on the right and bottom so that a template partly outside the image
reads zeros instead of leaving the buffer. The 8 response maps (LINEMOD section 2.4) are a
function of the spread image (responseOf()), computed by each reader in its own layout. */
struct LevelMaps
{
    Size size; //!< image size at this level (without padding)
    int T;
    int pad;
    std::vector<Mat> quantized;             //!< [modality], size `size`
    std::vector<Mat> spread;    //!< [modality], padded
    int modalities() const { return static_cast<int>(spread.size()); }
};

/** Spreads labels over a T x T window: dst(p) = OR of src over [p, p + T) (LINEMOD 2.3). */
void spreadLabels(const Mat& src, Mat& dst, int T, int pad);
/** 8 response maps of a spread image: response[o](p) = max similarity of orientation o to the
labels of p (LINEMOD 2.4: 4 same bin, 3, 2, 1, 0 opposite; circular). */
void computeResponseMaps(const Mat& spread, std::vector<Mat>& response);

/** Raw similarity (sum of responses, 0..4 per feature, read from the spread image) of the
features [begin, end) of one modality's template with its top-left corner at `tl` (level
pixels). */
int similarityRange(const LevelMaps& level, int modality, const cv::linemod::Template& templ,
                    Point tl, int begin, int end);

/** Raw similarity of all modalities of a template at one level (32-bit accumulation: any
number of features); the reference of the validator's fast paths (exported for the tests). num_features, when given, receives the feature count. */
CV_EXPORTS int similarityAll(const LevelMaps& level, const TemplatePyramid& tp, int level_index,
                             Point tl, int* num_features = 0);

/** The raw score (sum of responses) that a template of num_features features must exceed to
pass a threshold in percent: LINEMOD's rounding. */
static inline int rawThreshold(float threshold, int num_features)
{
    return static_cast<int>(2 * num_features + (threshold / 100.f) * (2 * num_features) + 0.5f);
}

/** Where cv::linemod reports a match found at cell (c, r) of a T grid: (c T + offset, r T +
offset), offset = T / 2 + (T % 2 - 1) pixels into the cell. */
static inline int matchOffset(int T)
{
    return T / 2 + (T % 2 - 1);
}

/** Number of features of a template over all modalities at one level. */
static inline int numFeatures(const TemplatePyramid& tp, int level_index, int num_modalities)
{
    int n = 0;
    for (int m = 0; m < num_modalities; ++m)
        n += static_cast<int>(tp[level_index * num_modalities + m].features.size());
    return n;
}

} // namespace detail
} // namespace forestmod
} // namespace cv

#endif
