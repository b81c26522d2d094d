// This file is part of OpenCV project.
// It is subject to the license terms in the LICENSE file found in the top-level directory
// of this distribution and at http://opencv.org/license.html

// Internal: bit-exact fast quantization of the standard modalities (cv::linemod::ColorGradient,
// cv::linemod::DepthNormal, forestmod::ColorHue) at every pyramid level, and vectorised spreading
// and response maps. "Bit-exact" means: equal, pixel for pixel, to what the modality's own
// process() + pyrDown() + quantize() give (test/test_quantize_fast.cpp). The functions are
// exported (CV_EXPORTS) for the tests and perf tests only; the header is not installed.

#ifndef OPENCV_FORESTMOD_QUANTIZE_FAST_HPP
#define OPENCV_FORESTMOD_QUANTIZE_FAST_HPP

#include "opencv2/core.hpp"
#include "opencv2/rgbd/linemod.hpp"

#include <vector>

namespace cv {
namespace forestmod {
namespace detail {

enum ModalityKind
{
    MODALITY_OTHER = 0,          //!< unknown: use the modality's own virtual calls
    MODALITY_COLOR_GRADIENT = 1, //!< exactly cv::linemod::ColorGradient (not a subclass)
    MODALITY_DEPTH_NORMAL = 2,   //!< exactly cv::linemod::DepthNormal (not a subclass)
    MODALITY_COLOR_HUE = 3       //!< exactly cv::forestmod::ColorHue (not a subclass)
};

/** What the fast paths need to know of a modality, read once (classifyModality()). */
struct ModalityInfo
{
    ModalityInfo()
        : kind(MODALITY_OTHER), weak_threshold(0.f), distance_threshold(0),
          difference_threshold(0), saturation_threshold(0), value_threshold(0), blur_size(0)
    {
    }
    ModalityKind kind;
    float weak_threshold;     //!< ColorGradient
    int distance_threshold;   //!< DepthNormal
    int difference_threshold; //!< DepthNormal
    int saturation_threshold; //!< ColorHue
    int value_threshold;      //!< ColorHue
    int blur_size;            //!< ColorHue
};

/** Recognises a modality by its dynamic type (a subclass is MODALITY_OTHER: it may override
processImpl) and reads its parameters. Call it again after changing the modality's parameters. */
CV_EXPORTS ModalityInfo classifyModality(const Ptr<cv::linemod::Modality>& modality);

/** True when fastQuantize() computes this kind itself. */
CV_EXPORTS bool hasFastPath(const ModalityInfo& info);

/** True when quantizeLevelRect() handles this kind (ColorGradient, ColorHue). */
CV_EXPORTS bool hasRectPath(const ModalityInfo& info);

/** The pixels `r` of one level's quantized image, written in place into `dst` (CV_8UC1 of the
image's size, allocated by the caller): equal there to what fastQuantize() gives for the whole
level from the same level image `src` (the pyramid's image of that level) and mask. The other
pixels are left as they are, so disjoint rectangles may be computed in parallel. */
CV_EXPORTS void quantizeLevelRect(const ModalityInfo& info, const Mat& src, const Mat& mask,
                                  Rect r, Mat& dst);

/** Quantized images of levels 0 .. levels-1 of one modality, equal to
`p = modality->process(src, mask); p->quantize(q0); p->pyrDown(); p->quantize(q1); ...`.
Returns false (and leaves `quantized` untouched) when the modality has no fast path; the caller
then uses the virtual calls. */
CV_EXPORTS bool fastQuantize(const ModalityInfo& info, const Mat& src, const Mat& mask, int levels,
                  std::vector<Mat>& quantized);
/** Same, classifying the modality first. */
CV_EXPORTS bool fastQuantize(const Ptr<cv::linemod::Modality>& modality, const Mat& src, const Mat& mask,
                  int levels, std::vector<Mat>& quantized);

/** What quantizeLevelRect() needs for one level of one modality, kept for later. */
struct LevelSource
{
    Mat image;          //!< the pyramid's image of the level (empty: quantized already)
    Mat mask;           //!< the pyramid's mask of the level (may be empty)
    ModalityInfo info;
};

/** Every modality at every level: quantized[l][i] for level l, modality i. Modalities with a
fast path share the pyramids (pyrDown of the source, INTER_NEAREST of the mask) when they are
given the same source or mask (same data); the others go through their virtual calls.
`infos` may be empty (then classified here); masks may be empty or hold empty Mats.
The Mats already in `quantized` are written in place when their size and type fit (as OpenCV's
outputs; no page faults for a new frame of the same size): pass a fresh vector to keep the
previous frame's images. The pyramids themselves live in buffers of the calling thread.
With `deferred`, the levels below the coarsest of the modalities with a rectangle path
(hasRectPath()) are not quantized: quantized[l][i] is allocated (CV_8UC1) but not computed, and
(*deferred)[l][i] holds its image and mask for quantizeLevelRect(); (*deferred)[l][i].image is
empty where the level was quantized. */
CV_EXPORTS void quantizeAllLevels(const std::vector<Ptr<cv::linemod::Modality> >& modalities,
                       const std::vector<ModalityInfo>& infos, const std::vector<Mat>& sources,
                       const std::vector<Mat>& masks, int levels,
                       std::vector<std::vector<Mat> >& quantized,
                       std::vector<std::vector<LevelSource> >* deferred = 0);


/** Vectorised, parallel detail::spreadLabels(): same signature, same output. */
CV_EXPORTS void spreadLabelsFast(const Mat& src, Mat& dst, int T, int pad);
/** Vectorised, parallel detail::computeResponseMaps(): same signature, same output (whole
response-map images, for the tests and the perf tests' full-frame pipeline; match() computes the
responses in its readers' layouts, spreadResponses()). */
CV_EXPORTS void computeResponseMapsFast(const Mat& spread, std::vector<Mat>& response);
/** Spread labels (pad 0) of the pixels of `tile` only, written in place into `spread` (CV_8UC1,
the size of `src`, allocated by the caller): there they equal spreadLabelsFast(src, spread, T,
0); the other pixels are left as they are. Tiles may be computed in parallel (disjoint tiles). */
CV_EXPORTS void spreadTile(const Mat& src, int T, Rect tile, Mat& spread);
/** LINEMOD's response (section 2.4) of label o (0..7) to a spread byte: 4 - the circular
distance from o to the nearest label set in it, 0 beyond 3 (detail::computeResponseMaps). */
CV_EXPORTS uchar responseOf(int o, uchar spread);
/** The 8 responses of n spread bytes, vectorised: dst[o][i] = responseOf(o, spread[i]). The
response maps are never kept whole: each reader (LinearMemories, on the T grid or the location grid) computes them
in its own layout from the spread images. */
CV_EXPORTS void spreadResponses(const uchar* spread, int n, uchar* const* dst);

/** Vectorised, parallel detail::dominantLabels() without a mask (the forest's label planes):
dst(p) = the label bit set most often in the k x k window of p (anchor k / 2, zeros outside;
ties: the lowest bit; 0 where no bit is set). k in [1, 15]. `dst` is written in place when it
already has src's size and type (a ROI of a bordered plane). */
CV_EXPORTS void dominantLabelsFast(const Mat& src, int k, Mat& dst);
/** detail::dominantLabels() without a mask (search_index.cpp), for the tests. */
CV_EXPORTS void dominantLabelsReference(const Mat& src, int k, Mat& dst);

/** detail::spreadLabels() and detail::computeResponseMaps() (similarity.cpp), exported for the
tests and the perf tests that compare the fast versions with them. */
CV_EXPORTS void spreadLabelsReference(const Mat& src, Mat& dst, int T, int pad);
CV_EXPORTS void computeResponseMapsReference(const Mat& spread, std::vector<Mat>& response);

} // namespace detail
} // namespace forestmod
} // namespace cv

#endif
