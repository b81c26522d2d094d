// This file is part of OpenCV project.
// It is subject to the license terms in the LICENSE file found in the top-level directory
// of this distribution and at http://opencv.org/license.html

// Internal: the validation stage (paper: "Fast Breadth-first Leaf Validation"): the candidate
// templates of every location that left the forest are scored with LINEMOD's similarity,
// breadth-first; the best survivors over the threshold become coarse matches. A search group
// whose forest let through too many (location, candidate) pairs in a frame is searched
// exhaustively instead, with LINEMOD's linearized memories (DetectorParams::exhaustive_ratio):
// the frame then costs at most what cv::linemod's search of the same templates costs. The
// layouts and scoring functions are exported (CV_EXPORTS) for the tests and perf tests only;
// the header is not installed.

#ifndef OPENCV_FORESTMOD_VALIDATOR_HPP
#define OPENCV_FORESTMOD_VALIDATOR_HPP

#include "similarity.hpp"
#include "scan.hpp"

#include <vector>

namespace cv {
namespace forestmod {
namespace detail {

/** The coarsest level's response maps of every modality and label (computed from its spread
images, spreadResponses()) in one buffer with a zero
border, so that a feature is one read without bounds checks: the response of label o of
modality m at (x, y) is data[(m * 8 + o) * plane + (y + border) * width + x + border]. A read
in the border gives 0, as LINEMOD's skipping of features outside the image. */
struct CV_EXPORTS PaddedResponses
{
    std::vector<uchar> data;
    int border;
    int width, height;  //!< padded size
    int plane;          //!< width * height
    int modalities;

    PaddedResponses() : border(0), width(0), height(0), plane(0), modalities(0) {}
    /** The level's response maps with a border of `border` pixels. */
    void build(const LevelMaps& level, int border);
    /** Offset of (x, y) of the unpadded level in a plane. */
    int at(int x, int y) const { return (y + border) * width + x + border; }
    /** Offsets of a template's features (modality by modality, in the template's order) from
    its top-left corner; `begin[m]` .. `begin[m + 1]` are modality m's. */
    void featureOffsets(const TemplatePyramid& tp, int level_index, int* begin,
                        std::vector<int>& offsets) const;
};

/** LINEMOD's linearized memories of the coarsest level (Hinterstoisser et al., PAMI 2012,
section 2.5): for every modality, label and offset (dx, dy) in the T x T cell, the responses of
the cells' pixels (cx T + dx, cy T + dy) in one row-major array of `stride` x `rows` cells (one
cell more than the level's cells_x x cells_y each way, for features on a template's far edge;
pixels outside the image read 0). A feature then adds one contiguous run to the scores of all
positions (c T, r T) of a template at once. */
struct CV_EXPORTS LinearMemories
{
    std::vector<uchar> data;
    int T;
    int cells_x, cells_y;   //!< whole cells of the level: the positions
    int stride, rows;       //!< cells of a memory
    std::vector<ushort> div_T; //!< x / T for x < max(stride, rows) T (no division per feature)

    LinearMemories() : T(1), cells_x(0), cells_y(0), stride(0), rows(0) {}
    /** From the level's spread images (spreadResponses()); with `tiles` (a grid of `tile`-sized pixel tiles, nonzero
    where the maps are valid, ScenePyramid::tiles) only the cells touching a marked tile, the
    others 0. */
    void build(const LevelMaps& level, const Mat& tiles = Mat(), Size tile = Size());
    size_t index(int modality, int label, int dx, int dy) const
    {
        return ((size_t)(modality * 8 + label) * T * T + dy * T + dx) * (size_t)(stride * rows);
    }
    const uchar* memory(int modality, int label, int dx, int dy) const
    {
        return &data[index(modality, label, dx, dy)];
    }
};

/** Raw scores of a template at every position (c T, r T) of the coarsest level where it fits
(c <= span_x, r <= span_y, LINEMOD's positions), vectorised as cv::linemod: one SIMD add per
feature over all positions, 8-bit sums of up to 63 features widened into 16-bit ones.
`scores[r * stride + c]`; returns false when the template fits nowhere. `acc8` is scratch. At
most 16383 features (16-bit sums). */
CV_EXPORTS bool scoreEverywhere(const LinearMemories& lm, const TemplatePyramid& tp,
                                int level_index, int num_modalities, int& span_x, int& span_y,
                                std::vector<ushort>& scores, std::vector<uchar>& acc8);

/** LINEMOD's local search of the pyramid refinement, vectorised: raw scores of a template at the
16 x 16 positions (ox + c T, oy + r T), c, r = 0..15, of the level `lm` linearizes (ox, oy
multiples of T), scores[r * 16 + c]; the same sums as similarityAll there. Returns false (and
scores nothing) when a read would leave the memories: the caller then scores in place. */
CV_EXPORTS bool scoreLocal(const LinearMemories& lm, const TemplatePyramid& tp, int level_index,
                           int num_modalities, int ox, int oy, int* scores);

/** The forest path's scoring without its bookkeeping (tests, perf tests): raw[i] = the raw score
of all features of `templ` with its top-left at tls[i], read from `maps` (every tl within
maps.border of the level). */
CV_EXPORTS void scoreAt(const PaddedResponses& maps, const TemplatePyramid& templ,
                        int level_index, const std::vector<Point>& tls, std::vector<int>& raw);

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

} // namespace detail
} // namespace forestmod
} // namespace cv

#endif
