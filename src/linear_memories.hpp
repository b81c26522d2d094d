// This file is part of OpenCV project.
// It is subject to the license terms in the LICENSE file found in the top-level directory
// of this distribution and at http://opencv.org/license.html

// Internal: LINEMOD's linearized memories, the layout that the exhaustive search, the forest
// path's validation and the refinement read the response maps in. Exported (CV_EXPORTS) for the
// tests and perf tests only; the header is not installed.

#ifndef OPENCV_FORESTMOD_LINEAR_MEMORIES_HPP
#define OPENCV_FORESTMOD_LINEAR_MEMORIES_HPP

#include "similarity.hpp"
#include "search_index.hpp"

#include <memory>
#include <utility>
#include <vector>

namespace cv {
namespace forestmod {
namespace detail {

/** An allocator whose resize() leaves new bytes as they are (default-initialised): buffers that
their builder writes whole need no zeroing first. */
template <typename T>
struct UninitAllocator : std::allocator<T>
{
    template <typename U>
    struct rebind
    {
        typedef UninitAllocator<U> other;
    };
    UninitAllocator() {}
    template <typename U>
    UninitAllocator(const UninitAllocator<U>&) {}
    template <typename U>
    void construct(U* p)
    {
        ::new (static_cast<void*>(p)) U;
    }
    template <typename U, typename... Args>
    void construct(U* p, Args&&... args)
    {
        ::new (static_cast<void*>(p)) U(std::forward<Args>(args)...);
    }
};

/** 16-bit sums: at most this many features (4 each). */
const int kMaxSum16 = 65535 / 4;

/** x / T rounded down, also for negative x (T > 0). */
static inline int floorDiv(int x, int T)
{
    return x >= 0 ? x / T : -((T - 1 - x) / T);
}

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
    /** The memories, then kSlack zero bytes (whole-vector reads). Not zeroed when resized:
    build() writes every byte (the zeros outside the image too) or zeroes them first. */
    std::vector<uchar, UninitAllocator<uchar> > data;
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

/** LINEMOD's local search of the pyramid refinement, vectorised: raw scores of a template at the
16 x 16 positions (ox + c T, oy + r T), c, r = 0..15, of the level `lm` linearizes (ox, oy
multiples of T), scores[r * 16 + c]; the same sums as similarityAll there. Returns false (and
scores nothing) when a read would leave the memories: the caller then scores in place. */
CV_EXPORTS bool scoreLocal(const LinearMemories& lm, const TemplatePyramid& tp, int level_index,
                           int num_modalities, int ox, int oy, int* scores);
/** scoreLocal's best position only: `best` = the largest of the 256 raw scores and `index` =
r * 16 + c of the first position (row by row) that reaches it, -1 when every score is 0 (the
refinement's choice, without writing the 256 scores out); `num_features` = the template's
features at the level (the score's denominator). False as scoreLocal. */
CV_EXPORTS bool bestLocal(const LinearMemories& lm, const TemplatePyramid& tp, int level_index,
                          int num_modalities, int ox, int oy, int& best, int& index,
                          int& num_features);

} // namespace detail
} // namespace forestmod
} // namespace cv

#endif
