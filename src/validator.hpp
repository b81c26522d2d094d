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

/** Depth as a validation modality (paper: "we add depth value as another modality in the
validation stage to measure shape similarity"). A template keeps depth samples (x, y relative to
its top-left at level 0, z mm). With the template's top-left at `origin` (level 0) the offset
(scene minus template) is the median over the samples where the scene has depth; a sample then
scores like a LINEMOD feature, 0..4 (depthResponse), by how far z + offset lies outside the
range [zmin, zmax] of the scene depth around it: the *relative* depths are compared (shape, not
distance), and the range (the depth counterpart of LINEMOD's spreading) tolerates the position
error of a candidate. Samples without scene depth (holes, outside the image) score 0, like
features without a quantized value. */
struct DepthContext
{
    DepthContext() : tolerance(10), scale_shift(0) {}
    Mat depth;      //!< scene depth, level 0, CV_16UC1 mm (0: none)
    Mat zmin, zmax; //!< its minimum / maximum over a square around each pixel (holes left out:
                    //!< zmin 65535 and zmax 0 where the square has no depth)
    int tolerance;  //!< mm: a residual within it scores 4
    int scale_shift; //!< a level's pixel -> level 0: << scale_shift
    Point shift;    //!< added to a candidate's top-left (level pixels): the template's likely position
    Point2f pp;     //!< the scene's principal point, taken as the image centre

    /** depth, zmin, zmax of a scene depth with a square of (2 radius + 1)^2 pixels. */
    void set(const Mat& scene_depth, int radius);
};

/** A template's depth samples and the geometry that predicts them elsewhere in the image: an
object seen at another image position is seen along another ray, and its depths (z, not the
distance along the ray) tilt accordingly (up to +-15 mm over an LM-O object 20 degrees off the
axis). The template's camera points P_i = z_i K_t^-1 (u_i, v_i, 1) are turned by the rotation
that takes the ray through the template's object centre onto the ray through the candidate's
(the scene's focal length taken as the template's, its principal point as the image centre);
the predicted depth is the z of the turned point. */
struct DepthTemplate
{
    DepthTemplate() : samples(0), fx(0), fy(0) {}
    const std::vector<Point3i>* samples; //!< x, y relative to the top-left (level 0), z mm
    Point2f pp;     //!< the template's principal point relative to its top-left (level 0)
    Point2f centre; //!< its object centre (projection of t) relative to its top-left
    float fx, fy;   //!< its focal lengths; 0: no pose, depths compared as they are
};

/** Third row of that rotation for the template's top-left at `origin` (level 0); (0, 0, 1)
without a pose. */
Vec3f depthRotationRow(const DepthContext& dc, const DepthTemplate& t, Point origin);

/** 0..4 by the residual r (mm): 4 when r <= tol, 2 when r <= 2 tol, 1 when r <= 3 tol, else 0. */
static inline int depthResponse(int r, int tol)
{
    r = r < 0 ? -r : r;
    return r <= tol ? 4 : r <= 2 * tol ? 2 : r <= 3 * tol ? 1 : 0;
}

/** Median offset (scene minus predicted template depth, mm) of the first n <= 256 samples at
`origin` (level 0), with `row` from depthRotationRow(). Returns false (no offset: every sample then
scores 0) when fewer than a quarter of them have scene depth. */
bool depthOffset(const DepthContext& dc, const DepthTemplate& t, const Vec3f& row, int n,
                 Point origin, int& offset);

/** Sum of depthResponse() over the samples [begin, end) at `origin` with the given offset. */
int depthSimilarityRange(const DepthContext& dc, const DepthTemplate& t, const Vec3f& row,
                         Point origin, int offset, int begin, int end);

/** Rotation row, offset and the first `count` samples (all when count < 0): 0..4 per sample. */
int depthSimilarity(const DepthContext& dc, const DepthTemplate& t, Point origin, int count = -1);

/** Depth samples scored at a pyramid level: as many as the template has features per modality
there (at most `samples`, at most 256), so that depth weighs like one more modality at every
level (the coarsest level has fewer features than level 0). The samples are ordered (most
distinctive relief first, spread over the object), so a prefix is a sparser selection. */
static inline int depthSamplesAtLevel(int samples, int features, int num_modalities)
{
    const int per_modality = num_modalities > 0
        ? (features + num_modalities - 1) / num_modalities : features;
    return std::max(0, std::min(std::min(samples, 256), per_modality));
}

/** A candidate of validation: a template and where its top-left is at the coarsest level. */
struct ValidationCandidate
{
    int index;     //!< caller's index
    const TemplatePyramid* tp;
    const DepthTemplate* depth; //!< the template's depth samples, or null
    Point tl;
    int raw;       //!< accumulated raw score
    int scored;    //!< features (and depth samples) scored so far
    int total;     //!< features of the template (all modalities) + depth samples
    int zoffset;   //!< depth offset (scene minus template, mm)
    bool zvalid;   //!< zoffset is known
    Vec3f zrow;    //!< depthRotationRow() at the candidate
};

/** Scores every candidate on all its features (no pruning); depth samples join when `depth` is
given and a candidate has samples. */
void validateAll(const LevelMaps& level, int level_index, std::vector<ValidationCandidate>& cands,
                 const DepthContext* depth = 0);

/** Breadth-first preemptive validation (paper): features in chunks of chunk_size; after each
chunk keep the candidates whose normalised score raw / (4 scored) is >= the median of the
survivors and > alpha; stop when max_survivors (paper: 1) or fewer are left (or features run
out). Every chunk takes the same share of each modality's features and, when `depth` is given
and depth_in_chunks is true, of the candidate's depth samples. The survivors are then scored on
all their features and, when `depth` is given, on all their depth samples. Returns the indices
(into `cands`) of the survivors. */
void validateBreadthFirst(const LevelMaps& level, int level_index, int num_modalities,
                          std::vector<ValidationCandidate>& cands, int chunk_size, float alpha,
                          int max_survivors, std::vector<int>& survivors,
                          const DepthContext* depth = 0, bool depth_in_chunks = true);

} // namespace detail
} // namespace forestmod
} // namespace cv

#endif
