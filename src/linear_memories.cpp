// This file is part of OpenCV project.
// It is subject to the license terms in the LICENSE file found in the top-level directory
// of this distribution and at http://opencv.org/license.html

// LINEMOD's linearized memories (PAMI 2012, 2.5) of a level's spread images, on the T grid (the
// exhaustive search, the refinement) or on the location grid (the forest path's validation), and
// the refinement's vectorised local search on them.

#include "precomp.hpp"
#include "linear_memories.hpp"
#include "score_kernels.hpp"
#include "quantize_fast.hpp"

namespace cv {
namespace forestmod {
namespace detail {

// The pixels of cells [c0, c1) of a row, T per cell, by their offset dx in the cell:
// gathered[dx * n + k] = src[(c0 + k) T + dx] (the cells' pixels read in order, T known to the
// compiler for LINEMOD's usual T).
template <int T>
static void gatherCellsT(const uchar* src, int c0, int c1, int n, uchar* gathered)
{
    for (int k = 0; k < c1 - c0; ++k)
    {
        const uchar* s = src + (c0 + k) * T;
        for (int dx = 0; dx < T; ++dx)
            gathered[dx * n + k] = s[dx];
    }
}

static void gatherCells(const uchar* src, int T, int c0, int c1, int n, uchar* gathered)
{
    switch (T)
    {
    case 4: gatherCellsT<4>(src, c0, c1, n, gathered); return;
    case 5: gatherCellsT<5>(src, c0, c1, n, gathered); return;
    case 8: gatherCellsT<8>(src, c0, c1, n, gathered); return;
    default:
        for (int dx = 0; dx < T; ++dx)
            for (int k = 0; k < c1 - c0; ++k)
                gathered[dx * n + k] = src[(c0 + k) * T + dx];
    }
}

// Cell columns [c0, c1] of cell row `cy` of one modality's memories (`row`: label 0, offset
// (0, 0), that cell row; `plane` between consecutive offsets): the responses of the spread
// pixels (cx T + dx, cy T + dy) inside the image; with `zero_outside` the bytes of the pixels
// outside it are written 0 too, else they are left as they are (zeroed before). One gather of
// the cells' pixels per row of pixels (`gathered`: T x (c1 - c0 + 1) bytes), then per offset dx
// the 8 responses of its gathered row at once.
static void linearizeCells(const Mat& spread, int T, int cy, int c0, int c1, uchar* row,
                           size_t plane, uchar* gathered, bool zero_outside)
{
    const int n = c1 - c0 + 1;
    // cells whose T pixels are all inside the image: [c0, whole)
    const int whole = std::max(c0, std::min(c1 + 1, spread.cols / T));
    for (int dy = 0; dy < T; ++dy)
    {
        const bool inside = cy * T + dy < spread.rows;
        if (!inside && !zero_outside)
            break;
        const uchar* src = inside ? spread.ptr<uchar>(cy * T + dy) : 0;
        if (inside)
            gatherCells(src, T, c0, whole, n, gathered);
        for (int dx = 0; dx < T; ++dx)
        {
            // the cells from `whole` on hold the pixel dx only while it is inside the image
            const int m = inside ? std::min(c1, (spread.cols - 1 - dx) / T) - c0 + 1 : 0;
            uchar* d[8];
            for (int o = 0; o < 8; ++o)
                d[o] = row + (size_t)linearMemory(0, o, dx, dy, T) * plane + c0;
            if (zero_outside && m < n)
                for (int o = 0; o < 8; ++o)
                    std::fill(d[o] + std::max(m, 0), d[o] + n, (uchar)0);
            if (m <= 0)
                continue;
            for (int k = whole - c0; k < m; ++k)
                gathered[dx * n + k] = src[(c0 + k) * T + dx];
            spreadResponses(gathered + dx * n, m, d);
        }
    }
}

// The image's cell rows of every modality's memories: cell row cy (0 = the image's first) from
// runs[run_begin[cy]] .. runs[run_begin[cy + 1]) (cell columns, inclusive), in parallel; the
// bytes of pixels outside the image written 0 with `zero_outside` (linearizeCells).
static void fillCells(const LevelMaps& level, const std::vector<Vec2i>& runs,
                      const std::vector<int>& run_begin, LinearMemories& lm, bool zero_outside)
{
    const size_t n = (size_t)lm.stride * lm.rows;
    for (int m = 0; m < level.modalities(); ++m)
        parallel_for_(Range(0, static_cast<int>(run_begin.size()) - 1), [&](const Range& range) {
            std::vector<uchar> gathered((size_t)lm.stride * lm.T);
            for (int cy = range.start; cy < range.end; ++cy)
                for (int k = run_begin[cy]; k < run_begin[cy + 1]; ++k)
                    linearizeCells(level.spread[m], lm.T, cy, runs[k][0], runs[k][1],
                                   &lm.data[lm.index(m, 0, 0, 0)] + lm.cell(0, cy), n,
                                   &gathered[0], zero_outside);
        });
}

void LinearMemories::build(const LevelMaps& level, const Mat& tiles, Size tile)
{
    T = level.T;
    border = 0;
    cells_x = level.size.width / T;
    cells_y = level.size.height / T;
    stride = cells_x + 1;
    rows = cells_y + 1;
    const int M = level.modalities();
    const size_t n = (size_t)stride * rows;
    div_T.resize((size_t)std::max(stride, rows) * T);
    for (size_t x = 0; x < div_T.size(); ++x)
        div_T[x] = static_cast<ushort>(x / T);
    // the runs of cells to fill, per cell row: every cell, or those touching a marked tile
    std::vector<Vec2i> runs;
    std::vector<int> run_begin(rows + 1, 0);
    std::vector<uchar> covered(stride);
    for (int cy = 0; cy < rows; ++cy)
    {
        run_begin[cy] = static_cast<int>(runs.size());
        if (tiles.empty())
        {
            runs.push_back(Vec2i(0, stride - 1));
            continue;
        }
        std::fill(covered.begin(), covered.end(), (uchar)0);
        const int ty0 = cy * T / tile.height;
        const int ty1 = std::min(tiles.rows - 1, (cy * T + T - 1) / tile.height);
        for (int ty = ty0; ty <= ty1; ++ty)
        {
            const uchar* g = tiles.ptr<uchar>(ty);
            for (int tx = 0; tx < tiles.cols; ++tx)
                if (g[tx])
                    for (int cx = tx * tile.width / T;
                         cx <= std::min(stride - 1, (tx * tile.width + tile.width - 1) / T); ++cx)
                        covered[cx] = 1;
        }
        for (int cx = 0; cx < stride;)
        {
            if (!covered[cx])
            {
                ++cx;
                continue;
            }
            const int c0 = cx;
            while (cx < stride && covered[cx])
                ++cx;
            runs.push_back(Vec2i(c0, cx - 1));
        }
    }
    run_begin[rows] = static_cast<int>(runs.size());
    // every cell with a pixel in the image (a whole level, the usual case): every row's run
    // widened to the row and the bytes outside the image written 0 by the fill, so that it
    // writes every byte (at VGA's level 0, 5 MB that one serial memset had zeroed first); else
    // the cells left out are zeroed first
    const int last_x = (level.size.width - 1) / T, last_y = (level.size.height - 1) / T;
    bool every_cell = true;
    for (int cy = 0; cy <= last_y && every_cell; ++cy)
        every_cell = run_begin[cy + 1] == run_begin[cy] + 1 && runs[run_begin[cy]][0] == 0
                     && runs[run_begin[cy]][1] >= last_x;
    if (every_cell)
    {
        runs.assign(rows, Vec2i(0, stride - 1));
        for (int cy = 0; cy <= rows; ++cy)
            run_begin[cy] = cy;
    }
    const size_t bytes = n * T * T * 8 * M;
    data.resize(bytes + kSlack);
    std::fill(data.begin() + (every_cell ? bytes : 0), data.end(), (uchar)0);
    fillCells(level, runs, run_begin, *this, every_cell);
}

void LinearMemories::buildGrid(const LevelMaps& level, int step, int border_cells)
{
    CV_Assert(step > 0 && border_cells >= 0);
    T = step;
    border = border_cells;
    const Size spread = level.spread.empty() ? level.size : level.spread[0].size();
    cells_x = (spread.width + T - 1) / T;
    cells_y = (spread.height + T - 1) / T;
    stride = cells_x + 2 * border;
    rows = cells_y + 2 * border;
    div_T.clear();
    data.assign((size_t)stride * rows * T * T * 8 * level.modalities() + kSlack, 0);
    std::vector<Vec2i> runs(cells_y, Vec2i(0, cells_x - 1));
    std::vector<int> run_begin(cells_y + 1);
    for (int cy = 0; cy <= cells_y; ++cy)
        run_begin[cy] = cy;
    fillCells(level, runs, run_begin, *this, false);
}

void LinearMemories::featureOffsets(const TemplatePyramid& tp, int level_index, int M, Point tl,
                                    int* begin, std::vector<int>& offsets) const
{
    offsets.clear();
    for (int m = 0; m < M; ++m)
    {
        begin[m] = static_cast<int>(offsets.size());
        const cv::linemod::Template& t = tp[level_index * M + m];
        for (size_t i = 0; i < t.features.size(); ++i)
        {
            const cv::linemod::Feature& f = t.features[i];
            const int x = tl.x + f.x, y = tl.y + f.y;
            const int qx = floorDiv(x, T), qy = floorDiv(y, T);
            offsets.push_back(static_cast<int>(index(m, f.label, x - qx * T, y - qy * T))
                              + qy * stride + qx);
        }
    }
    begin[M] = static_cast<int>(offsets.size());
}

// scoreLocal's raw sums into acc[256] and the template's feature count at the level into n;
// false when a read would leave the memories.
static bool localSums(const LinearMemories& lm, const TemplatePyramid& tp, int level_index,
                      int num_modalities, int ox, int oy, ushort* acc, int& n)
{
    const int T = lm.T, M = num_modalities;
    n = numFeatures(tp, level_index, M);
    if (ox < 0 || oy < 0 || ox % T || oy % T || n > kMaxSum16 || lm.data.empty())
        return false;
    const int cx = ox / T, cy = oy / T;
    // every feature's 16 x 16 block of cells, checked before anything is added (x / T from the
    // memories' table: no division per feature); the blocks on the stack for the usual
    // templates (a thread_local vector, read through the TLS look-up, had cost a call per
    // feature in a shared library)
    const int kOnStack = 512;
    const uchar* on_stack[kOnStack];
    static thread_local std::vector<const uchar*> on_heap;
    const uchar** blocks = on_stack;
    if (n > kOnStack)
    {
        on_heap.resize(n);
        blocks = &on_heap[0];
    }
    const int n_div = static_cast<int>(lm.div_T.size());
    const ushort* div_T = n_div ? &lm.div_T[0] : 0;
    const int last_qx = lm.stride - 16 - cx, last_qy = lm.rows - 16 - cy;
    const size_t plane = (size_t)lm.stride * lm.rows;
    const uchar* base = &lm.data[0] + (size_t)cy * lm.stride + cx;
    int k = 0;
    for (int m = 0; m < M; ++m)
    {
        const std::vector<cv::linemod::Feature>& features = tp[level_index * M + m].features;
        const cv::linemod::Feature* f = features.empty() ? 0 : &features[0];
        const int nf = static_cast<int>(features.size());
        for (int i = 0; i < nf; ++i)
        {
            const int x = f[i].x, y = f[i].y;
            if ((unsigned)x >= (unsigned)n_div || (unsigned)y >= (unsigned)n_div)
                return false;
            const int qx = div_T[x], qy = div_T[y];
            if (qx > last_qx || qy > last_qy)
                return false;
            blocks[k++] = base + (size_t)linearMemory(m, f[i].label, x - qx * T, y - qy * T, T)
                                     * plane
                          + (size_t)qy * lm.stride + qx;
        }
    }
    std::fill(acc, acc + 256, (ushort)0);
    if (k > 0)
        addBlocks16(acc, blocks, k, lm.stride);
    return true;
}

bool scoreLocal(const LinearMemories& lm, const TemplatePyramid& tp, int level_index,
                int num_modalities, int ox, int oy, int* scores)
{
    ushort acc[256];
    int n = 0;
    if (!localSums(lm, tp, level_index, num_modalities, ox, oy, acc, n))
        return false;
    for (int j = 0; j < 256; ++j)
        scores[j] = acc[j];
    return true;
}

bool bestLocal(const LinearMemories& lm, const TemplatePyramid& tp, int level_index,
               int num_modalities, int ox, int oy, int& best, int& index, int& num_features)
{
    ushort acc[256];
    if (!localSums(lm, tp, level_index, num_modalities, ox, oy, acc, num_features))
        return false;
    ushort b = 0;
    index = firstMax256(acc, b);
    best = b;
    return true;
}

} // namespace detail
} // namespace forestmod
} // namespace cv
