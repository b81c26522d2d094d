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

/** LINEMOD's linearized memories of a level (Hinterstoisser et al., PAMI 2012, section 2.5): for
every modality, label and offset (dx, dy) in the T x T cell, the responses of the cells' pixels
(cx T + dx, cy T + dy) in one row-major array of `stride` x `rows` cells; pixels outside the
image read 0. A feature then adds one contiguous run to the scores of all positions (c T, r T)
of a template at once. The exhaustive path and the refinement build them on the level's T grid
(one cell more each way than the level's whole cells, for features on a template's far edge);
the forest path on its location grid (T = location step) with `border` cells of zeros on every
side, so that any feature of a candidate at any location is one read without bounds checks. */
struct CV_EXPORTS LinearMemories
{
    std::vector<uchar> data;   //!< the memories, then kSlack zero bytes (whole-vector reads)
    int T;
    int cells_x, cells_y;   //!< build: the level's whole cells (the positions); buildGrid: every
                            //!< cell touching the padded spread images
    int border;             //!< cells of zeros before cell (0, 0), each way
    int stride, rows;       //!< cells of a memory
    std::vector<ushort> div_T; //!< build only: x / T for x < max(stride, rows) T (no division
                               //!< per feature)

    /** Zero bytes after the memories: a run of up to kSlack cells can be read from any cell. */
    static const int kSlack = 64;

    LinearMemories() : T(1), cells_x(0), cells_y(0), border(0), stride(0), rows(0) {}
    /** On the level's T grid from its spread images (spreadResponses()); with `tiles` (a grid
    of `tile`-sized pixel tiles, nonzero where the maps are valid, ScenePyramid::tiles) only the
    cells touching a marked tile, the others 0. */
    void build(const LevelMaps& level, const Mat& tiles = Mat(), Size tile = Size());
    /** On a grid of `step` pixels (every cell touching the level's padded spread images) with
    `border` cells of zeros each way. */
    void buildGrid(const LevelMaps& level, int step, int border);
    size_t index(int modality, int label, int dx, int dy) const
    {
        return (size_t)linearMemory(modality, label, dx, dy, T) * (size_t)(stride * rows);
    }
    const uchar* memory(int modality, int label, int dx, int dy) const
    {
        return &data[index(modality, label, dx, dy)];
    }
    /** Offset of cell (cx, cy) in every memory (the border's cells have negative cx or cy). */
    int cell(int cx, int cy) const { return (cy + border) * stride + cx + border; }
    /** Offsets from cell(0, 0) of the features of a template whose top-left is `tl` pixels from
    the cell's corner (modality by modality, in the template's order): the response of feature
    i at cell c is data[cell(c) + offsets[i]]; `begin[m]` .. `begin[m + 1]` are modality m's. */
    void featureOffsets(const TemplatePyramid& tp, int level_index, int num_modalities,
                        Point tl, int* begin, std::vector<int>& offsets) const;
};

/** Raw scores of a template at every position (c T, r T) of the coarsest level where it fits
(c <= span_x, r <= span_y, LINEMOD's positions), vectorised as cv::linemod: one SIMD add per
feature and vector of positions, the positions in tiles whose sums stay in registers over all
features (8-bit sums of up to 63 features widened into 16-bit ones). `scores[r * stride + c]`;
returns false when the template fits nowhere. At most 16383 features (16-bit sums). */
CV_EXPORTS bool scoreEverywhere(const LinearMemories& lm, const TemplatePyramid& tp,
                                int level_index, int num_modalities, int& span_x, int& span_y,
                                std::vector<ushort>& scores);

/** LINEMOD's local search of the pyramid refinement, vectorised: raw scores of a template at the
16 x 16 positions (ox + c T, oy + r T), c, r = 0..15, of the level `lm` linearizes (ox, oy
multiples of T), scores[r * 16 + c]; the same sums as similarityAll there. Returns false (and
scores nothing) when a read would leave the memories: the caller then scores in place. */
CV_EXPORTS bool scoreLocal(const LinearMemories& lm, const TemplatePyramid& tp, int level_index,
                           int num_modalities, int ox, int oy, int* scores);

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

} // namespace detail
} // namespace forestmod
} // namespace cv

#endif
