// This file is part of OpenCV project.
// It is subject to the license terms in the LICENSE file found in the top-level directory
// of this distribution and at http://opencv.org/license.html

// Validation stage (paper: "Fast Breadth-first Leaf Validation"): LINEMOD's similarity read from
// linearized memories of the frame's coarsest level on the location grid (offsets computed once
// per template and frame; a template's candidates at neighbouring locations scored together, one
// vector addition per feature), the breadth-first preemptive scheme; and the exhaustive
// vectorised search of the groups whose forest rejected too little in this frame.

#include "precomp.hpp"
#include "validator.hpp"
#include "score_kernels.hpp"
#include "quantize_fast.hpp"


namespace cv {
namespace forestmod {
namespace detail {

// ------------------------------------------------------------------------------------------------
// Layouts

// Cell columns [c0, c1] of cell row `cy` of one modality's memories (`row`: label 0, offset
// (0, 0), that cell row; `plane` between consecutive offsets): the responses of the spread
// pixels (cx T + dx, cy T + dy) inside the image (the memories stay 0 outside). One gather of
// the cells' pixels, then the 8 responses of the gathered row at once.
static void linearizeCells(const Mat& spread, int T, int cy, int c0, int c1, uchar* row,
                           size_t plane, uchar* gathered)
{
    for (int dy = 0; dy < T && cy * T + dy < spread.rows; ++dy)
    {
        const uchar* src = spread.ptr<uchar>(cy * T + dy);
        for (int dx = 0; dx < T; ++dx)
        {
            const int n = std::min(c1, (spread.cols - 1 - dx) / T) - c0 + 1;
            if (n <= 0)
                continue;
            for (int k = 0; k < n; ++k)
                gathered[k] = src[(c0 + k) * T + dx];
            uchar* d[8];
            for (int o = 0; o < 8; ++o)
                d[o] = row + (size_t)linearMemory(0, o, dx, dy, T) * plane + c0;
            spreadResponses(gathered, n, d);
        }
    }
}

// x / T rounded down, also for negative x (T > 0).
static inline int floorDiv(int x, int T)
{
    return x >= 0 ? x / T : -((T - 1 - x) / T);
}

// The image's cell rows of every modality's memories: cell row cy (0 = the image's first) from
// runs[run_begin[cy]] .. runs[run_begin[cy + 1]) (cell columns, inclusive), in parallel.
static void fillCells(const LevelMaps& level, const std::vector<Vec2i>& runs,
                      const std::vector<int>& run_begin, LinearMemories& lm)
{
    const size_t n = (size_t)lm.stride * lm.rows;
    for (int m = 0; m < level.modalities(); ++m)
        parallel_for_(Range(0, static_cast<int>(run_begin.size()) - 1), [&](const Range& range) {
            std::vector<uchar> gathered(lm.stride);
            for (int cy = range.start; cy < range.end; ++cy)
                for (int k = run_begin[cy]; k < run_begin[cy + 1]; ++k)
                    linearizeCells(level.spread[m], lm.T, cy, runs[k][0], runs[k][1],
                                   &lm.data[lm.index(m, 0, 0, 0)] + lm.cell(0, cy), n,
                                   &gathered[0]);
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
    data.assign(n * T * T * 8 * M + kSlack, 0);
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
    fillCells(level, runs, run_begin, *this);
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
    fillCells(level, runs, run_begin, *this);
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

// ------------------------------------------------------------------------------------------------
// The exhaustive path: one template at every position, as cv::linemod

// 16-bit sums: at most this many features (4 each)
static const int kMaxSum16 = 65535 / 4;

// The raw scores of a template given by its coarsest-level features `f` (CoarseRuns) at every
// position of the T grid where its box of `cells` fits.
static bool scoreRuns(const LinearMemories& lm, const CoarseFeature* f, int n_f, Size cells,
                      int& span_x, int& span_y, std::vector<ushort>& scores)
{
    span_x = lm.cells_x - cells.width;
    span_y = lm.cells_y - cells.height;
    if (span_x < 0 || span_y < 0)
        return false;
    // every feature's run of the memories (cx <= cells.width <= cells_x: no overflow)
    static thread_local std::vector<int> runs;
    runs.resize(n_f);
    const int plane = lm.stride * lm.rows;
    for (int k = 0; k < n_f; ++k)
        runs[k] = f[k].memory * plane + f[k].cy * lm.stride + f[k].cx;
    // positions r * stride + c, the row ends included (they wrap: scored, never reported); the
    // kernel writes whole vectors
    const int n = span_y * lm.stride + span_x + 1;
    scores.resize(n + LinearMemories::kSlack);
    sumRuns16(&scores[0], &lm.data[0], runs.empty() ? 0 : &runs[0], n_f, n);
    scores.resize(n);
    return true;
}

bool scoreEverywhere(const LinearMemories& lm, const TemplatePyramid& tp, int level_index,
                     int num_modalities, int& span_x, int& span_y, std::vector<ushort>& scores)
{
    std::vector<CoarseFeature> f;
    const Size cells = coarseFeatures(tp, level_index, num_modalities, lm.T, f);
    return scoreRuns(lm, f.empty() ? 0 : &f[0], static_cast<int>(f.size()), cells, span_x,
                     span_y, scores);
}

namespace {
// A template at a position of the T grid: ranked by raw / total, then by index row (a total
// order: the best ones of a position do not depend on the order templates are scored in).
struct Scored
{
    int raw, total, row;
    bool better(const Scored& o) const
    {
        const int64 a = (int64)raw * o.total, b = (int64)o.raw * total;
        return a != b ? a > b : row < o.row;
    }
};
} // namespace

// Inserts `s` into the best-first list `top` of k entries (empty entries have row -1).
static void keepBest(Scored* top, int k, const Scored& s)
{
    if (top[k - 1].row >= 0 && !s.better(top[k - 1]))
        return;
    int i = k - 1;
    while (i > 0 && (top[i - 1].row < 0 || s.better(top[i - 1])))
    {
        top[i] = top[i - 1];
        --i;
    }
    top[i] = s;
}

bool scoreLocal(const LinearMemories& lm, const TemplatePyramid& tp, int level_index,
                int num_modalities, int ox, int oy, int* scores)
{
    const int T = lm.T, M = num_modalities;
    if (ox < 0 || oy < 0 || ox % T || oy % T || numFeatures(tp, level_index, M) > kMaxSum16)
        return false;
    const int cx = ox / T, cy = oy / T;
    // every feature's 16 x 16 block of cells, checked before anything is added (x / T from the
    // memories' table: no division per feature)
    static thread_local std::vector<const uchar*> blocks;
    blocks.clear();
    const int n_div = static_cast<int>(lm.div_T.size());
    for (int m = 0; m < M; ++m)
    {
        const cv::linemod::Template& t = tp[level_index * M + m];
        for (size_t i = 0; i < t.features.size(); ++i)
        {
            const cv::linemod::Feature& f = t.features[i];
            if (f.x < 0 || f.y < 0 || f.x >= n_div || f.y >= n_div)
                return false;
            const int qx = lm.div_T[f.x], qy = lm.div_T[f.y];
            if (cx + qx + 16 > lm.stride || cy + qy + 16 > lm.rows)
                return false;
            blocks.push_back(lm.memory(m, f.label, f.x - qx * T, f.y - qy * T)
                             + (size_t)(cy + qy) * lm.stride + cx + qx);
        }
    }
    ushort acc[256];
    std::fill(acc, acc + 256, (ushort)0);
    if (!blocks.empty())
        addBlocks16(acc, &blocks[0], static_cast<int>(blocks.size()), lm.stride);
    for (int k = 0; k < 256; ++k)
        scores[k] = acc[k];
    return true;
}

// A position's entry bar once its list of k best is full: a template can then only enter with
// raw / total >= last.raw / last.total, which implies raw >= (bar x 4 total) >> 16 for
// bar = floor(65536 last.raw / (4 last.total)). A filter that never refuses an entrant (the
// exact comparison is keepBest's); 0 while the list has room.
static inline ushort entryBar(const Scored& last)
{
    if (last.row < 0)
        return 0;
    const int64 q = ((int64)last.raw << 16) / (4 * (int64)last.total);
    return static_cast<ushort>(std::min<int64>(q, 65535));
}

// The templates rows[i0 .. i1) at every position: each position's best K in `best` (lists of
// the T grid's cells, row-major), its entry bar in `bar` (the scores' layout r * stride + c).
static void searchTemplates(const LevelMaps& top, int L, const LinearMemories& lm,
                            const SearchIndex& index, const ClassPyramids& pyramids,
                            const std::vector<int>& rows, int i0, int i1, float threshold, int K,
                            Scored* best, ushort* bar)
{
    const int M = top.modalities(), T = top.T;
    const CoarseRuns& coarse = index.coarse;
    std::vector<ushort> scores;
    std::vector<int> hits;
    for (int i = i0; i < i1; ++i)
    {
        int span_x = 0, span_y = 0;
        Scored sc;
        sc.total = coarse.total[rows[i]];
        if (sc.total > kMaxSum16) // beyond 16-bit sums (hostile model files only)
        {
            const TemplateRef& ref = index.rows[rows[i]];
            const TemplatePyramid& tp = pyramids.find(ref.class_id)->second[ref.template_id];
            const cv::linemod::Template& t0 = tp[L * M];
            span_x = lm.cells_x - ((t0.width - 1) / T + 1);
            span_y = lm.cells_y - ((t0.height - 1) / T + 1);
            if (span_x < 0 || span_y < 0)
                continue;
            scores.assign((size_t)(span_y + 1) * lm.stride, 0);
            for (int r = 0; r <= span_y; ++r)
                for (int c = 0; c <= span_x; ++c)
                    scores[(size_t)r * lm.stride + c] = (ushort)std::min(
                        65535, similarityAll(top, tp, L, Point(c * T, r * T)));
        }
        else
        {
            const int b = coarse.begin[rows[i]], e = coarse.begin[rows[i] + 1];
            if (!scoreRuns(lm, b < e ? &coarse.features[b] : 0, e - b, coarse.cells[rows[i]],
                           span_x, span_y, scores))
                continue;
        }
        sc.row = rows[i];
        const int raw_thr = rawThreshold(threshold, sc.total);
        if (raw_thr >= 65535)
            continue;
        // one scan over the positions r * stride + c; the row ends (c > span_x) wrap
        const int n_pos = span_y * lm.stride + span_x + 1;
        hits.resize(n_pos);
        const int n_hits = positionsPassing16(&scores[0], bar, n_pos, (ushort)raw_thr,
                                              (ushort)(4 * sc.total), &hits[0]); // <= 65532
        for (int h = 0; h < n_hits; ++h)
        {
            const int p = hits[h];
            const int r = p / lm.stride, c = p - r * lm.stride;
            if (c > span_x)
                continue;
            sc.raw = scores[p];
            Scored* list = best + (size_t)(r * lm.cells_x + c) * K;
            keepBest(list, K, sc);
            bar[p] = entryBar(list[K - 1]);
        }
    }
}

// Every asked-for template of the exhaustive groups at every position of the T grid (cv::linemod's
// positions and scores); each position keeps its best `keep` templates over the threshold as
// coarse matches (row-major positions, best first): max_survivors for each of the (T / step)^2
// locations of the forest path that a cell of the T grid holds.
static void searchExhaustive(const ScenePyramid& scene, const SearchIndex& index,
                             const ClassPyramids& pyramids, const std::vector<int>& rows,
                             float threshold, int keep, std::vector<cv::linemod::Match>& out)
{
    const LevelMaps& top = scene.coarsest();
    const int L = scene.coarsestIndex();
    const int T = top.T;
    const int K = keep;
    const int offset = T / 2 + (T % 2 - 1);
    CV_Assert(index.coarse.begin.size() == index.rows.size() + 1);
    LinearMemories lm;
    lm.build(top);
    const int P = lm.cells_x * lm.cells_y;
    const int n = static_cast<int>(rows.size());
    // templates in a fixed number of blocks, each with its own best lists, merged afterwards
    const int blocks = std::max(1, std::min(n, 4 * getNumThreads()));
    Scored none = { 0, 1, -1 };
    std::vector<std::vector<Scored> > best(blocks, std::vector<Scored>((size_t)P * K, none));
    parallel_for_(Range(0, blocks), [&](const Range& range) {
        std::vector<ushort> bar((size_t)lm.stride * lm.cells_y);
        for (int b = range.start; b < range.end; ++b)
        {
            std::fill(bar.begin(), bar.end(), (ushort)0);
            searchTemplates(top, L, lm, index, pyramids, rows, (int)((int64)n * b / blocks),
                            (int)((int64)n * (b + 1) / blocks), threshold, K, &best[b][0],
                            &bar[0]);
        }
    });
    for (int b = 1; b < blocks; ++b)
        for (int p = 0; p < P; ++p)
            for (int k = 0; k < K && best[b][(size_t)p * K + k].row >= 0; ++k)
                keepBest(&best[0][(size_t)p * K], K, best[b][(size_t)p * K + k]);
    for (int p = 0; p < P; ++p)
        for (int k = 0; k < K; ++k)
        {
            const Scored& sc = best[0][(size_t)p * K + k];
            if (sc.row < 0)
                break;
            const TemplateRef& ref = index.rows[sc.row];
            const int c = p % lm.cells_x, r = p / lm.cells_x;
            out.push_back(cv::linemod::Match(c * T + offset, r * T + offset,
                                             (sc.raw * 100.f) / (4 * sc.total) + 0.5f,
                                             ref.class_id, ref.template_id));
        }
}

// ------------------------------------------------------------------------------------------------
// The forest path: breadth-first validation of every location's candidates, template by template

namespace {

// What validation reads, prepared once per frame: the linearized memories on the location grid
// and, per candidate template, its feature offsets from a location's cell in chunk order (chunk
// k of template t: offsets[chunk_begin[chunks[t] + k] .. chunk_begin[chunks[t] + k + 1]),
// every chunk the same share of each modality's features) and its anchor shift.
struct ValidationContext
{
    LinearMemories mem;
    std::vector<int> first;       //!< [index row]: its template t, or -1
    std::vector<int> chunks;      //!< [t]: into chunk_begin
    std::vector<int> num_chunks;  //!< [t]
    std::vector<int> chunk_begin; //!< into offsets
    std::vector<int> offsets;
    std::vector<Point> half;      //!< [t]: top-left of the template from its location
    std::vector<int> rows;        //!< [t]: index row
};

// The (location, candidate) pairs of a block of locations, structure of arrays, with the
// locations' alive lists and the pairs in template order: per-worker scratch, allocated once
// per block range, never per location.
struct PairBlock
{
    std::vector<int> t, raw, scored, loc;  //!< per pair
    std::vector<int> base;  //!< per pair: its location's cell in the memories
    std::vector<uchar> dead;                     //!< per pair
    std::vector<int> begin, alive_n;             //!< per location of the block
    std::vector<uchar> active;                   //!< per location: still in the rounds
    std::vector<int> alive;      //!< [begin[i] .. begin[i] + alive_n[i]): location i's alive pairs
    std::vector<int> by_template;  //!< every pair, sorted by template, then location
    std::vector<int> order;        //!< those still in the breadth-first rounds, in that order
    std::vector<int> local, used, count; //!< counting sort: [t] -> block id (-1), ids' t, counts
    std::vector<float> scores, sorted;
};

} // namespace

static inline int sumAt(const uchar* p, const int* off, int n)
{
    int s0 = 0, s1 = 0, i = 0;
    for (; i <= n - 2; i += 2)
    {
        s0 += p[off[i]];
        s1 += p[off[i + 1]];
    }
    if (i < n)
        s0 += p[off[i]];
    return s0 + s1;
}

void scoreAt(const LinearMemories& lm, const TemplatePyramid& templ, int level_index,
             int num_modalities, const std::vector<Point>& tls, std::vector<int>& raw)
{
    // the offsets of each phase of the top-left in a cell, computed when first needed
    const int T = lm.T;
    std::vector<std::vector<int> > offsets(T * T);
    std::vector<int> begin(num_modalities + 1);
    // the cell of every coordinate the memories reach (no division per top-left)
    const int lo = -lm.border * T, hi = (std::max(lm.stride, lm.rows) - lm.border) * T;
    std::vector<int> cell_of(hi - lo);
    for (int x = lo; x < hi; ++x)
        cell_of[x - lo] = floorDiv(x, T);
    raw.resize(tls.size());
    for (size_t i = 0; i < tls.size(); ++i)
    {
        CV_Assert(tls[i].x >= lo && tls[i].x < hi && tls[i].y >= lo && tls[i].y < hi);
        const int qx = cell_of[tls[i].x - lo], qy = cell_of[tls[i].y - lo];
        const Point phase(tls[i].x - qx * T, tls[i].y - qy * T);
        std::vector<int>& off = offsets[phase.y * T + phase.x];
        if (off.empty())
            lm.featureOffsets(templ, level_index, num_modalities, phase, &begin[0], off);
        const int n = static_cast<int>(off.size());
        raw[i] = n ? sumAt(&lm.data[0] + lm.cell(qx, qy), &off[0], n) : 0;
    }
}

// The pairs of locations [i0, i1) (those of the groups not searched exhaustively), each
// location's alive list all its pairs, and the pairs sorted by template (a counting sort over
// the templates the block uses), each template's in location order.
static void collectPairs(const ValidationContext& ctx, const LocationCandidates& cands, int i0,
                         int i1, const std::vector<uchar>& skip_row, PairBlock& s)
{
    const size_t most = cands.begin[i1] - cands.begin[i0];
    s.t.resize(most); s.base.resize(most); s.loc.resize(most);
    s.used.clear(); s.count.clear();
    s.begin.resize(i1 - i0 + 1);
    int n = 0;
    for (int i = i0; i < i1; ++i)
    {
        s.begin[i - i0] = n;
        const int cell = ctx.mem.cell(cands.location[i].x, cands.location[i].y);
        for (int k = cands.begin[i]; k < cands.begin[i + 1]; ++k)
        {
            const int row = cands.rows[k];
            if (skip_row[row])
                continue;
            const int t = ctx.first[row];
            s.t[n] = t;
            s.base[n] = cell;
            s.loc[n] = i - i0;
            ++n;
            if (s.local[t] < 0)
            {
                s.local[t] = static_cast<int>(s.used.size());
                s.used.push_back(t);
                s.count.push_back(0);
            }
            ++s.count[s.local[t]];
        }
    }
    s.begin[i1 - i0] = n;
    s.raw.assign(n, 0);
    s.scored.assign(n, 0);
    s.dead.assign(n, 0);
    s.alive.resize(n);
    for (int j = 0; j < n; ++j)
        s.alive[j] = j;
    s.alive_n.resize(i1 - i0);
    for (int i = 0; i < i1 - i0; ++i)
        s.alive_n[i] = s.begin[i + 1] - s.begin[i];
    int acc = 0;
    for (size_t u = 0; u < s.count.size(); ++u)
    {
        const int c = s.count[u];
        s.count[u] = acc;
        acc += c;
    }
    s.by_template.resize(n);
    for (int j = 0; j < n; ++j)
        s.by_template[s.count[s.local[s.t[j]]]++] = j;
    for (size_t u = 0; u < s.used.size(); ++u)
        s.local[s.used[u]] = -1;
}

// Pairs of one template whose cells lie within this many cells of the first are scored
// together, as one run of the memories (score_kernels.hpp's sumRuns16).
static const int kRunCells = 64;

// Round k of the breadth-first validation, template by template: chunk k of every pair in
// `order` (whose template has more than k chunks). A template's pairs in one run of kRunCells
// cells (in location order: ascending cells) are scored as LINEMOD scores: one vector addition
// per feature over the whole run, when they fill enough of it (one pair per 16 cells); the
// others feature by feature, one read each.
static void scoreChunks(const ValidationContext& ctx, int k, PairBlock& s)
{
    const uchar* P = &ctx.mem.data[0];
    const int* order = s.order.empty() ? 0 : &s.order[0];
    const size_t n = s.order.size();
    ushort run[kRunCells];
    for (size_t a = 0; a < n;)
    {
        const int t = s.t[order[a]];
        const int* cb = &ctx.chunk_begin[ctx.chunks[t] + k];
        const int* off = &ctx.offsets[cb[0]];
        const int len = cb[1] - cb[0];
        while (a < n && s.t[order[a]] == t)
        {
            const int first = s.base[order[a]];
            size_t e = a + 1;
            while (e < n && s.t[order[e]] == t && s.base[order[e]] - first < kRunCells)
                ++e;
            const int width = s.base[order[e - 1]] - first + 1;
            if ((int)(e - a) * 16 > width && e - a > 1)
            {
                sumRuns16(run, P + first, off, len, width);
                for (; a < e; ++a)
                {
                    const int j = order[a];
                    s.raw[j] += run[s.base[j] - first];
                    s.scored[j] += len;
                }
            }
            else
                for (; a < e; ++a)
                {
                    const int j = order[a];
                    s.raw[j] += sumAt(P + s.base[j], off, len);
                    s.scored[j] += len;
                }
        }
    }
}

// The element of rank n / 2 of the scores in [0, 1] (what std::nth_element puts there):
// counted into 128 bins first, then selected among those of its bin only.
static float medianOf(const std::vector<float>& scores, std::vector<float>& bin)
{
    const int B = 128;
    int hist[B] = {0};
    const int n = static_cast<int>(scores.size());
    for (int a = 0; a < n; ++a)
        ++hist[std::min(B - 1, static_cast<int>(scores[a] * B))];
    int below = 0, b = 0;
    while (below + hist[b] <= n / 2)
        below += hist[b++];
    bin.clear();
    for (int a = 0; a < n; ++a)
        if (std::min(B - 1, static_cast<int>(scores[a] * B)) == b)
            bin.push_back(scores[a]);
    std::nth_element(bin.begin(), bin.begin() + (n / 2 - below), bin.end());
    return bin[n / 2 - below];
}

// After round k: every location still in the rounds keeps the alive pairs whose normalised
// score raw / (4 scored) is >= the median of its alive pairs and > alpha (in their order); it
// leaves the rounds with max_survivors or fewer, or when none of its pairs had a chunk k. Then
// `order` keeps the pairs that go on to round k + 1.
static void pruneRound(const ValidationContext& ctx, int k, float alpha, int max_survivors,
                       PairBlock& s)
{
    const int L = static_cast<int>(s.alive_n.size());
    for (int i = 0; i < L; ++i)
    {
        if (!s.active[i])
            continue;
        int* al = &s.alive[s.begin[i]];
        const int n = s.alive_n[i];
        bool any = false;
        s.scores.resize(n);
        for (int a = 0; a < n; ++a)
        {
            const int j = al[a];
            any = any || k < ctx.num_chunks[s.t[j]];
            s.scores[a] = s.scored[j] ? s.raw[j] / (4.f * s.scored[j]) : 0.f;
        }
        if (!any)
        {
            s.active[i] = 0;
            continue;
        }
        const float median = medianOf(s.scores, s.sorted);
        int kept = 0;
        for (int a = 0; a < n; ++a)  // without branches: half of them go either way
        {
            const int keep = (s.scores[a] >= median) & (s.scores[a] > alpha);
            const int j = al[a];
            al[kept] = j;
            s.dead[j] = static_cast<uchar>(1 - keep);
            kept += keep;
        }
        s.alive_n[i] = kept;
        s.active[i] = kept > max_survivors;
    }
    size_t kept = 0;
    for (size_t a = 0; a < s.order.size(); ++a)
    {
        const int j = s.order[a];
        s.order[kept] = j;
        kept += (1 - s.dead[j]) & s.active[s.loc[j]] & (k + 1 < ctx.num_chunks[s.t[j]]);
    }
    s.order.resize(kept);
}

// Breadth-first preemptive validation (paper) of a block's pairs: features in chunks of
// chunk_size; after each chunk every location keeps its candidates whose normalised score is
// >= the median of its survivors and > alpha, until max_survivors (paper: 1) or fewer are left
// (or features run out). Every chunk takes the same share of each modality's features. Each
// round scores template by template (a template's offsets and the map rows it reads stay in
// cache across the block's locations). The survivors are then scored on all their features;
// without breadth_first every pair is.
static void validatePairs(const ValidationContext& ctx, const DetectorParams& params,
                          PairBlock& s)
{
    const int L = static_cast<int>(s.alive_n.size());
    s.active.assign(L, 0);
    if (params.breadth_first)
    {
        CV_Assert(params.max_survivors > 0);
        for (int i = 0; i < L; ++i)
            s.active[i] = s.alive_n[i] > params.max_survivors;
        s.order.clear();
        for (size_t a = 0; a < s.by_template.size(); ++a)
            if (s.active[s.loc[s.by_template[a]]])
                s.order.push_back(s.by_template[a]);
        for (int k = 0; !s.order.empty(); ++k)
        {
            scoreChunks(ctx, k, s);
            pruneRound(ctx, k, params.alpha, params.max_survivors, s);
        }
    }
    // the survivors (every pair without breadth_first) on all their features
    const uchar* P = &ctx.mem.data[0];
    for (size_t a = 0; a < s.by_template.size(); ++a)
    {
        const int j = s.by_template[a];
        const int t = s.t[j];
        const int* cb = &ctx.chunk_begin[ctx.chunks[t]];
        const int total = cb[ctx.num_chunks[t]] - cb[0];
        if (s.dead[j] || s.scored[j] == total)
            continue;
        s.raw[j] = sumAt(P + s.base[j], &ctx.offsets[cb[0]], total);
        s.scored[j] = total;
    }
}

// Location i of the block: its best survivors over the threshold appended to `out`.
static void emitLocation(const ValidationContext& ctx, const LocationCandidates& cands, int i0,
                         int i, const SearchIndex& index, const DetectorParams& params,
                         float threshold, int T, PairBlock& s,
                         std::vector<cv::linemod::Match>& out)
{
    int* al = &s.alive[s.begin[i - i0]];
    const int n = s.alive_n[i - i0];
    const std::vector<int>& raw = s.raw;
    const std::vector<int>& total = s.scored;  // all features scored by now
    std::sort(al, al + n, [&](int a, int b) {
        return raw[a] * (int64)total[b] > raw[b] * (int64)total[a];
    });
    const int S = cands.step;
    const Point loc = cands.location[i];
    const int offset = T / 2 + (T % 2 - 1);
    for (int k = 0; k < n && k < params.max_survivors; ++k)
    {
        const int j = al[k];
        if (raw[j] <= rawThreshold(threshold, total[j]))
            continue;
        const int t = s.t[j];
        const TemplateRef& ref = index.rows[ctx.rows[t]];
        const Point tl = Point(loc.x * S, loc.y * S) - ctx.half[t];
        out.push_back(cv::linemod::Match(tl.x + offset, tl.y + offset,
                                         (raw[j] * 100.f) / (4 * total[j]) + 0.5f,
                                         ref.class_id, ref.template_id));
    }
}

// A template's feature offsets (`offs`, modality m's at b[m] .. b[m + 1]) appended to the
// context in chunk order: K = ceil(features / chunk_size) chunks, chunk k the fraction [k/K,
// (k+1)/K) of every modality's features, so that every chunk samples all modalities and the
// whole object (features are scattered).
static void addChunks(const std::vector<int>& offs, const int* b, int M, int chunk_size,
                      ValidationContext& ctx)
{
    const int total = b[M] - b[0];
    const int K = std::max(1, (total + chunk_size - 1) / chunk_size);
    ctx.chunks.push_back(static_cast<int>(ctx.chunk_begin.size()));
    ctx.num_chunks.push_back(K);
    for (int k = 0; k < K; ++k)
    {
        ctx.chunk_begin.push_back(static_cast<int>(ctx.offsets.size()));
        for (int m = 0; m < M; ++m)
        {
            const int n = b[m + 1] - b[m];
            const int s = static_cast<int>((int64)n * k / K);
            const int e = static_cast<int>((int64)n * (k + 1) / K);
            ctx.offsets.insert(ctx.offsets.end(), offs.begin() + b[m] + s,
                               offs.begin() + b[m] + e);
        }
    }
    ctx.chunk_begin.push_back(static_cast<int>(ctx.offsets.size()));
}

// The templates that are candidates somewhere (and not searched exhaustively): their offsets,
// and the border that keeps every read of theirs inside the memories.
static void prepareContext(const ScenePyramid& scene, const LocationCandidates& cands,
                           const SearchIndex& index, const ClassPyramids& pyramids,
                           const std::vector<uchar>& skip_row, int chunk_size,
                           ValidationContext& ctx)
{
    const LevelMaps& top = scene.coarsest();
    const int L = scene.coarsestIndex();
    const int M = top.modalities();
    const int S = cands.step;
    ctx.first.assign(index.rows.size(), -1);
    std::vector<const TemplatePyramid*> tps;
    // the border: a location lies inside the level, a template's top-left `half` before it
    int border = 0;
    for (size_t k = 0; k < cands.rows.size(); ++k)
    {
        const int row = cands.rows[k];
        if (skip_row[row] || ctx.first[row] >= 0)
            continue;
        ctx.first[row] = static_cast<int>(ctx.rows.size());
        ctx.rows.push_back(row);
        const TemplateRef& ref = index.rows[row];
        const TemplatePyramid& tp = pyramids.find(ref.class_id)->second[ref.template_id];
        tps.push_back(&tp);
        const cv::linemod::Template& t = tp[L * M];
        const Point half(t.width / 2 + S / 2, t.height / 2 + S / 2);
        ctx.half.push_back(half);
        for (int m = 0; m < M; ++m)
        {
            const std::vector<cv::linemod::Feature>& fs = tp[L * M + m].features;
            for (size_t i = 0; i < fs.size(); ++i)
                border = std::max(border, std::max(std::max(half.x - fs[i].x, fs[i].x - half.x),
                                                   std::max(half.y - fs[i].y, fs[i].y - half.y)));
        }
    }
    if (ctx.rows.empty())
        return;
    // a feature lies at most `border` pixels from its location's pixel (the cell's corner)
    ctx.mem.buildGrid(top, S, border / S + 2);
    std::vector<int> offs, b(M + 1);
    for (size_t t = 0; t < tps.size(); ++t)
    {
        ctx.mem.featureOffsets(*tps[t], L, M, -ctx.half[t], &b[0], offs);
        addChunks(offs, &b[0], M, chunk_size, ctx);
    }
}

void validateLocations(const ScenePyramid& scene, const LocationCandidates& cands,
                       const SearchIndex& index, const ClassPyramids& pyramids,
                       const DetectorParams& params, float threshold,
                       const std::vector<uchar>& row_allowed,
                       std::vector<cv::linemod::Match>& coarse, int* exhaustive_groups)
{
    const LevelMaps& top = scene.coarsest();
    coarse.clear();
    // the groups the scan left to the exhaustive search: all their asked-for templates
    std::vector<uchar> skip_row(index.rows.size(), 0);
    std::vector<int> dense_rows;
    int dense_groups = 0;
    for (size_t g = 0; g < cands.exhaustive.size(); ++g)
    {
        if (!cands.exhaustive[g])
            continue;
        ++dense_groups;
        const SearchGroup& grp = index.groups[g];
        for (size_t k = 0; k < grp.rows.size(); ++k)
            if (row_allowed[grp.rows[k]])
            {
                skip_row[grp.rows[k]] = 1;
                dense_rows.push_back(grp.rows[k]);
            }
    }
    if (exhaustive_groups)
        *exhaustive_groups = dense_groups;

    CV_Assert(params.chunk_size > 0);
    ValidationContext ctx;
    prepareContext(scene, cands, index, pyramids, skip_row, params.chunk_size, ctx);
    const int n = cands.size();
    // locations in blocks, each block's matches in order: the result does not depend on threads
    // (nor on the blocks: every location is validated on its own)
    const int block = 64;
    const int blocks = (n + block - 1) / block;
    std::vector<std::vector<cv::linemod::Match> > per_block(blocks);
    if (!ctx.rows.empty())
        parallel_for_(Range(0, blocks), [&](const Range& range) {
            PairBlock s;
            s.local.assign(ctx.rows.size(), -1);
            for (int b = range.start; b < range.end; ++b)
            {
                const int i0 = b * block, i1 = std::min(n, (b + 1) * block);
                collectPairs(ctx, cands, i0, i1, skip_row, s);
                validatePairs(ctx, params, s);
                for (int i = i0; i < i1; ++i)
                    emitLocation(ctx, cands, i0, i, index, params, threshold, top.T, s,
                                 per_block[b]);
            }
        });
    for (int b = 0; b < blocks; ++b)
        coarse.insert(coarse.end(), per_block[b].begin(), per_block[b].end());
    if (!dense_rows.empty())
    {
        const int per_cell = (top.T + cands.step - 1) / cands.step;
        searchExhaustive(scene, index, pyramids, dense_rows, threshold,
                         params.max_survivors * per_cell * per_cell, coarse);
    }
}

} // namespace detail
} // namespace forestmod
} // namespace cv
