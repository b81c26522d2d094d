// This file is part of OpenCV project.
// It is subject to the license terms in the LICENSE file found in the top-level directory
// of this distribution and at http://opencv.org/license.html

// The search: rejections before the forest, then every search group's forest, per location.

#include "precomp.hpp"
#include "scan.hpp"
#include "score_kernels.hpp"
#include "opencv2/core/hal/intrin.hpp"

namespace cv {
namespace forestmod {
namespace detail {

namespace {

// A tree's root rejector as rowTests reads it: per dimension its pointer (as ScanContext::dim_ptr),
// accepted labels and whether the value 0 is accepted; min_accept 0 when the root has no
// rejector, or more dimensions than 8-bit counts hold (the tree then tests it, location by
// location).
struct RootTest
{
    std::vector<const uchar*> ptr;
    std::vector<uchar> labels, zero_ok;
    int min_accept;
};

// What every location of one scan reads: the groups that hold an asked-for class, with their
// window offsets in the bordered planes, and the rejection limits.
struct ScanContext
{
    const SearchIndex* index;
    const ScenePyramid* scene;
    std::vector<const SearchGroup*> groups;
    std::vector<int> group_index;          //!< [group]: in SearchIndex::groups
    std::vector<int> trees;                //!< [group]: trees of its forest
    std::vector<uchar> any_tree;           //!< [group]: its ForestParams::reject_any_tree
    std::vector<uchar> active;             //!< [group]: traversed (not searched exhaustively)
    /** [group][dim]: the dimension's plane + its window offset, for the location (0, 0) */
    std::vector<std::vector<const uchar*> > dim_ptr;
    std::vector<int> min_labels;           //!< [group]: flat-window limit, 0 = off
    /** [group]: the columns of the window's grid, a lattice (the x of a grid point depends on its
    column only, its y on its row only, points row by row: how the index makes it), so that the
    flat-window count is separable; grid_dx[group][column]: the column's x from the first's */
    std::vector<int> grid_cols;
    std::vector<std::vector<int> > grid_dx;
    std::vector<std::vector<RootTest> > roots; //!< [group][tree]
    int max_trees;
    const std::vector<uchar>* row_allowed;
    std::vector<int> group_of_row;         //!< [index row]: group (in `groups`) or -1
    int S, L, T;
    /** The scene depth per T-grid cell when the depth-range test runs, else null; [group]: the
    widened depth range of its templates (empty: no test) */
    const DepthCells* depth_cells;
    std::vector<DepthSpan> depth_span;
};

// Outcome of a location: candidates, or the reason it left (rejection map codes).
// NOT_SCANNED: no group to traverse (no asked-for class): -1 in the map, not counted as rejected.
// A group's own verdict on a location is ACCEPTED, FLAT, its deepest rejecting forest depth, or
// NOT_VISITED (not traversed there).
enum { ACCEPTED = -1, FLAT = -2, DEPTH_RANGE = -3, NOT_SCANNED = -4, NOT_VISITED = -5 };

struct RowOutput
{
    std::vector<Point> location;
    std::vector<int> count;
    std::vector<int> rows;
    MatchCounters counters;
};

// The sample's limits: a group leaves the scan (exhaustive search) once its cost on the sample,
// in validated pairs (its pairs plus descent_cost per tree node visited), extrapolated by
// `scale[g]`, passes `limit[g]` (exhaustive_ratio x templates x positions). Group g descends
// every stride[g]-th location of the sample (in row-major order), and its scale counts the
// frame's locations per location descended.
struct SampleCount
{
    int64 pairs = 0, nodes = 0;
    SampleCount& operator+=(const SampleCount& o)
    {
        pairs += o.pairs;
        nodes += o.nodes;
        return *this;
    }
};

struct SampleLimits
{
    std::vector<SampleCount> count; //!< [group]: counted on the sample rows scanned before
    std::vector<double> limit;      //!< [group]
    std::vector<double> scale;      //!< [group]
    std::vector<int> stride;        //!< [group]
    double node_cost;               //!< DetectorParams::descent_cost

    bool passed(int g, const SampleCount& more) const
    {
        const double pairs = (double)(count[g].pairs + more.pairs);
        const double nodes = (double)(count[g].nodes + more.nodes);
        return (pairs + node_cost * nodes) * scale[g] > limit[g];
    }
};

// Per worker: the candidates of a location as a bit set over the index rows (the leaves of every
// tree and group merged without sorting), the accepting leaves of a group, and the location's
// descriptor in a group's window (gathered once, read by every tree).
struct ScanScratch
{
    std::vector<uint64> bits;
    std::vector<std::pair<const int*, int> > leaves;
    std::vector<uchar> values;
    // rowTests: counts over the pixels of a row, and per location of the row whether a group's
    // window is flat ([group * W + c]) and whether a tree's root passes ([(group * max_trees +
    // tree) * W + c])
    std::vector<uchar> count8;
    std::vector<int> count32;
    std::vector<uchar> flat, root_ok;
    std::vector<short> verdict;    //!< [group]: the location's verdicts (visitGroups)
    // the windows of a row's locations gathered at once (gatherRowWindows): group g's window
    // of location c at windows[window_offset[g] + c * D_g]; row_windows[g]: 0 not decided for
    // the row, 1 gathered, 2 gathered location by location
    std::unique_ptr<uchar[]> windows;
    std::vector<size_t> window_offset;
    std::vector<uchar> row_windows;
};

} // namespace

// The columns of a group's window grid, checked to be a lattice whose dimensions are the grid's
// points per modality in the grid's order (ScanContext::grid_cols; the index makes no other).
static int latticeColumns(const SearchGroup& g)
{
    const int P = (int)g.grid.size();
    int cols = 0;
    while (cols < P && g.grid[cols].y == g.grid[0].y)
        ++cols;
    // the columns' counts are 8-bit (at most P / cols grid rows), their offsets from the first
    // non-negative
    bool lattice = P > 0 && P % cols == 0 && P / cols <= 255
        && g.dim_offset.size() == g.plane_of.size() && g.dim_offset.size() % P == 0;
    for (int k = 0; lattice && k < P; ++k)
        lattice = g.grid[k].x == g.grid[k % cols].x && g.grid[k].y == g.grid[k - k % cols].y
            && g.grid[k % cols].x >= g.grid[0].x;
    for (size_t j = 0; lattice && j < g.dim_offset.size(); ++j)
        lattice = g.dim_offset[j] == g.grid[j % P] && g.plane_of[j] == (int)(j / P);
    CV_Assert(lattice && "forestmod scan: a search group's window is not a lattice");
    return cols;
}

static ScanContext scanContext(const SearchIndex& index, const ScenePyramid& scene,
                               const DetectorParams& params, const std::vector<uchar>& allowed)
{
    ScanContext ctx;
    ctx.index = &index;
    ctx.scene = &scene;
    ctx.row_allowed = &allowed;
    ctx.L = scene.coarsestIndex();
    ctx.S = std::min(locationStep(params, scene.coarsest().T), scene.coarsest().T);
    ctx.group_of_row.assign(index.rows.size(), -1);
    for (size_t gi = 0; gi < index.groups.size(); ++gi)
    {
        const SearchGroup& g = index.groups[gi];
        bool any = false;
        for (size_t k = 0; k < g.rows.size() && !any; ++k)
            any = allowed[g.rows[k]] != 0;
        if (!any)
            continue;
        for (size_t k = 0; k < g.rows.size(); ++k)
            ctx.group_of_row[g.rows[k]] = (int)ctx.groups.size();
        ctx.groups.push_back(&g);
        ctx.group_index.push_back((int)gi);
        const ForestParams fp = g.forest->getParams();
        ctx.trees.push_back(fp.num_trees);
        ctx.any_tree.push_back(fp.reject_any_tree ? 1 : 0);
        std::vector<const uchar*> ptr(g.plane_of.size());
        const ptrdiff_t origin = (ptrdiff_t)scene.border * (ptrdiff_t)scene.plane_step
            + scene.border;
        for (size_t j = 0; j < ptr.size(); ++j)
            ptr[j] = scene.plane_ptr[g.plane_of[j]] + origin
                + (ptrdiff_t)g.dim_offset[j].y * (ptrdiff_t)scene.plane_step + g.dim_offset[j].x;
        ctx.dim_ptr.push_back(ptr);
        ctx.min_labels.push_back(params.min_window_labels > 0
                                     ? std::max(1, cvCeil(params.min_window_labels * g.min_labels))
                                     : 0);
        const int cols = latticeColumns(g);
        ctx.grid_cols.push_back(cols);
        std::vector<int> dx(cols);
        for (int k = 0; k < cols; ++k)
            dx[k] = g.grid[k].x - g.grid[0].x;
        ctx.grid_dx.push_back(dx);
        std::vector<RootTest> roots(fp.num_trees);
        for (int t = 0; t < fp.num_trees; ++t)
        {
            std::vector<int> dims;
            std::vector<ushort> lut;
            RootTest& rt = roots[t];
            rt.min_accept = 0;
            if (!g.forest->rootRejector(t, dims, lut, rt.min_accept) || dims.size() > 255)
            {
                rt.min_accept = 0;
                continue;
            }
            for (size_t k = 0; k < dims.size(); ++k)
            {
                rt.ptr.push_back(ptr[dims[k]]);
                rt.labels.push_back((uchar)(lut[k] & 255));
                rt.zero_ok.push_back((uchar)((lut[k] >> 8) & 1));
            }
        }
        ctx.roots.push_back(roots);
    }
    ctx.max_trees = 1;
    for (size_t g = 0; g < ctx.trees.size(); ++g)
        ctx.max_trees = std::max(ctx.max_trees, ctx.trees[g]);
    ctx.active.assign(ctx.groups.size(), 1);
    ctx.T = scene.coarsest().T;
    ctx.depth_cells = scene.depth_cells.empty() ? 0 : &scene.depth_cells;
    ctx.depth_span.assign(ctx.groups.size(), DepthSpan());
    for (size_t g = 0; g < ctx.groups.size() && ctx.depth_cells; ++g)
        ctx.depth_span[g] = widenedSpan(ctx.groups[g]->depth, params.depth_range_tolerance);
    return ctx;
}

// The flat-window test of group gi for a row of W locations (byte offset `row` in the planes)
// when its window is a lattice: per modality, the labelled values of each pixel's column of
// grid rows (one counting pass per grid row over the row's pixels and the window's width), then
// per location the sum of its grid columns' counts. The same counts as adding every dimension.
static void flatWindowsOfLattice(const ScanContext& ctx, int gi, ptrdiff_t row, int W,
                                 ScanScratch& s, uchar* flat)
{
    const int S = ctx.S, X = (W - 1) * S + 1;
    const int cols = ctx.grid_cols[gi];
    const std::vector<int>& dx = ctx.grid_dx[gi];
    const std::vector<const uchar*>& ptr = ctx.dim_ptr[gi];
    const int P = (int)ctx.groups[gi]->grid.size(), rows = P / cols;
    const int span = X + dx[cols - 1];
    uchar* colsum = &s.count8[0];
    std::vector<int>& count = s.count32;
    count.assign(W, 0);
    for (size_t m = 0; m * P < ptr.size(); ++m)
    {
        std::fill(colsum, colsum + span, (uchar)0); // at most `rows` (< 256) per pixel
        for (int gy = 0; gy < rows; ++gy)
            countLabels8(colsum, ptr[m * P + gy * cols] + row, span);
        for (int c = 0; c < W; ++c)
            for (int gx = 0; gx < cols; ++gx)
                count[c] += colsum[c * S + dx[gx]];
    }
    for (int c = 0; c < W; ++c)
        flat[c] = count[c] < ctx.min_labels[gi];
}

// The two tests that send most background locations out, for a row of W locations at once and
// every active group, vectorised over the row's pixels (every S-th is a location): the flat
// window (labelled values of the group's window) and the root rejector of every tree (accepted
// dimensions). The same counts as testing location by location.
static void rowTests(const ScanContext& ctx, int r, int W, ScanScratch& s)
{
    const int S = ctx.S;
    const int X = (W - 1) * S + 1;
    const ptrdiff_t row = (ptrdiff_t)r * S * (ptrdiff_t)ctx.scene->plane_step;
    uchar* count8 = &s.count8[0];
    for (size_t gi = 0; gi < ctx.groups.size(); ++gi)
    {
        if (!ctx.active[gi])
            continue;
        uchar* flat = &s.flat[gi * W];
        if (ctx.min_labels[gi] > 0)
            flatWindowsOfLattice(ctx, (int)gi, row, W, s, flat);
        else
            std::fill(flat, flat + W, (uchar)0);
        for (int t = 0; t < ctx.trees[gi]; ++t)
        {
            const RootTest& rt = ctx.roots[gi][t];
            uchar* ok = &s.root_ok[((size_t)gi * ctx.max_trees + t) * W];
            if (rt.min_accept <= 0)
            {
                std::fill(ok, ok + W, (uchar)1);
                continue;
            }
            std::fill(count8, count8 + X, (uchar)0);
            for (size_t k = 0; k < rt.ptr.size(); ++k)
                countAccepted8(count8, rt.ptr[k] + row, X, rt.labels[k], rt.zero_ok[k]);
            for (int c = 0; c < W; ++c)
                ok[c] = count8[c * S] >= rt.min_accept;
        }
    }
}

// Whether the scene depth around location (c, r) stays out of group g's widened depth range
// (false without a depth-range test).
static inline bool outOfDepthRange(const ScanContext& ctx, int g, int c, int r)
{
    return ctx.depth_cells && !ctx.depth_cells->reaches(c * ctx.S / ctx.T, r * ctx.S / ctx.T,
                                                        ctx.depth_span[g]);
}

// A location's code from its groups' verdicts: ACCEPTED when one group accepts it, else the
// deepest forest depth that rejected it, else FLAT when some visited group found its window
// flat, else DEPTH_RANGE (every visited group out of its depth range); NOT_SCANNED when no group
// was visited. A group searched exhaustively (inactive) scores the locations whose cell reaches
// its depth range (the forest path's test for the group; the exhaustive search makes it per
// template): it accepts those, so a location counts as rejected only where no group scores it.
static int locationCode(const ScanContext& ctx, const short* verdict, int c, int r)
{
    const int groups = (int)ctx.groups.size();
    int flat = 0, deepest = -1, visited = 0;
    for (int g = 0; g < groups; ++g)
    {
        int v = verdict[g];
        if (v == NOT_VISITED && !ctx.active[g])
            v = outOfDepthRange(ctx, g, c, r) ? DEPTH_RANGE : ACCEPTED;
        if (v == NOT_VISITED)
            continue;
        if (v == ACCEPTED)
            return ACCEPTED;
        ++visited;
        if (v == FLAT)
            ++flat;
        else if (v >= 0)
            deepest = std::max(deepest, v);
    }
    if (visited == 0)
        return NOT_SCANNED;
    return deepest >= 0 ? deepest : flat ? FLAT : DEPTH_RANGE;
}

// Gathers a window's values (one per dimension of its group) and counts the labelled ones. The
// pointers and their count are read once: a store through `values` (uchar) could alias them.
static int gatherWindow(const std::vector<const uchar*>& ptr, ptrdiff_t offset, uchar* values)
{
    const uchar* const* p = ptr.data();
    const size_t n = ptr.size();
    int labelled = 0;
    for (size_t j = 0; j < n; ++j)
    {
        const uchar v = p[j][offset];
        values[j] = v;
        labelled += v != 0;
    }
    return labelled;
}

// scan.hpp. With S == 4, 16 locations at a time: a dimension's 16 values with one load of 64
// bytes (every 4th byte), then a 16 x 16 transpose (four rounds of interleaving rows j and j + 8)
// gives 16 dimensions of each location; the last locations (whose 64-byte load would pass the
// last location's byte) and the dimensions past a multiple of 16 are gathered one by one.
void gatherRowWindows(const std::vector<const uchar*>& ptr, ptrdiff_t row, int W, int S,
                      uchar* win)
{
    const int D = (int)ptr.size();
    int c0 = 0;
#if CV_SIMD128
    const uchar* const* p = ptr.data();
    if (S == 4)
        for (; c0 + 16 <= W - 1; c0 += 16)
        {
            const ptrdiff_t at = row + (ptrdiff_t)c0 * S;
            uchar* out = win + (size_t)c0 * D;
            int j0 = 0;
            for (; j0 + 16 <= D; j0 += 16)
            {
                v_uint8x16 x[16], y[16], skip1, skip2, skip3;
                for (int k = 0; k < 16; ++k)
                    v_load_deinterleave(p[j0 + k] + at, x[k], skip1, skip2, skip3);
                for (int round = 0; round < 4; ++round)
                {
                    for (int k = 0; k < 8; ++k)
                        v_zip(x[k], x[k + 8], y[2 * k], y[2 * k + 1]);
                    for (int k = 0; k < 16; ++k)
                        x[k] = y[k];
                }
                for (int i = 0; i < 16; ++i)
                    v_store(out + (size_t)i * D + j0, x[i]);
            }
            for (int i = 0; i < 16; ++i)
                for (int j = j0; j < D; ++j)
                    out[(size_t)i * D + j] = p[j][at + i * S];
        }
#endif
    for (int c = c0; c < W; ++c)
        gatherWindow(ptr, row + (ptrdiff_t)c * S, win + (size_t)c * D);
}

// The window of location c of group gi (at byte `offset` of the planes) that passed its row's
// tests (s.flat, s.root_ok): gathered with the rest of the row's windows when half the row's
// locations pass them (made at the first such location), else on its own into s.values.
static const uchar* locationWindow(const ScanContext& ctx, int gi, int c, ptrdiff_t offset,
                                   int W, ScanScratch& s)
{
    const std::vector<const uchar*>& ptr = ctx.dim_ptr[gi];
    uchar& state = s.row_windows[gi];
    if (state == 0)
    {
        int passing = 0;
        for (int k = 0; k < W; ++k)
        {
            bool any_root = false;
            for (int t = 0; t < ctx.trees[gi] && !any_root; ++t)
                any_root = s.root_ok[((size_t)gi * ctx.max_trees + t) * W + k] != 0;
            passing += any_root && !s.flat[gi * W + k];
        }
        state = 2 * passing >= W ? 1 : 2;
        if (state == 1) // the row's first location: offset - c * S
            gatherRowWindows(ptr, offset - (ptrdiff_t)c * ctx.S, W, ctx.S,
                             s.windows.get() + s.window_offset[gi]);
    }
    if (state == 1)
        return s.windows.get() + s.window_offset[gi] + (size_t)c * ptr.size();
    gatherWindow(ptr, offset, &s.values[0]);
    return &s.values[0];
}

// Group gi's verdict on location (c, r): out of its depth range, a flat window, or its forest
// (every tree). An accepting group's leaves go to s.leaves. `row_tested`: the flat window and the
// roots were tested on the whole row (rowTests, in s); else they are tested here. `nodes`, if
// given, gains the tree nodes visited (the descents' cost, counted by the sample).
static short visitGroup(const ScanContext& ctx, int gi, int c, int r, int W, ScanScratch& s,
                        bool row_tested, int64* nodes = 0)
{
    const ScenePyramid& scene = *ctx.scene;
    const SearchGroup& grp = *ctx.groups[gi];
    if (outOfDepthRange(ctx, gi, c, r))
        return DEPTH_RANGE;
    if (row_tested && s.flat[gi * W + c])
        return FLAT;
    // the window's values, gathered for the first tree whose root passes, once for all trees
    const uchar* values = &s.values[0];
    bool gathered = false;
    const std::vector<const uchar*>& ptr = ctx.dim_ptr[gi];
    const ptrdiff_t offset = (ptrdiff_t)r * ctx.S * (ptrdiff_t)scene.plane_step + c * ctx.S;
    if (!row_tested)
    {
        gathered = true;
        if (gatherWindow(ptr, offset, &s.values[0]) < ctx.min_labels[gi])
            return FLAT;
    }
    // the trees (TemplateForest::query's rule): with reject_any_tree one rejecting tree
    // rejects, else the location stays while one tree accepts it
    s.leaves.clear();
    int rdepth = -1;
    for (int t = 0; t < ctx.trees[gi]; ++t)
    {
        const int* ids = 0;
        int n = 0, depth = 0, visited = 0; // a root rejector that fails rejects at depth 0
        const bool root_tested = row_tested && ctx.roots[gi][t].min_accept > 0;
        const bool root_ok = !row_tested
            || s.root_ok[((size_t)gi * ctx.max_trees + t) * W + c] != 0;
        if (root_ok && !gathered)
        {
            values = locationWindow(ctx, gi, c, offset, W, s);
            gathered = true;
        }
        const bool reached = root_ok
            && grp.forest->leaf(t, values, ids, n, &depth, root_tested, &visited);
        if (nodes)
            *nodes += visited;
        if (reached)
            s.leaves.push_back(std::make_pair(ids, n));
        else
        {
            rdepth = std::max(rdepth, depth);
            if (ctx.any_tree[gi])
                return (short)rdepth;
        }
    }
    return s.leaves.empty() ? (short)rdepth : (short)ACCEPTED;
}

// Every active search group's verdict (visitGroup) goes to s.verdict; the candidates of the
// accepting groups are the union of their accepting trees' leaves (as index rows, marked in
// s.bits). Returns whether one group accepted (marked rows).
static bool visitGroups(const ScanContext& ctx, int c, int r, int W, ScanScratch& s)
{
    const int NG = (int)ctx.groups.size();
    bool marked = false;
    for (int gi = 0; gi < NG; ++gi)
    {
        short& verdict = s.verdict[gi];
        verdict = ctx.active[gi] ? visitGroup(ctx, gi, c, r, W, s, true) : (short)NOT_VISITED;
        if (verdict != ACCEPTED)
            continue;
        marked = true;
        const int* rows = &ctx.groups[gi]->rows[0];
        uint64* bits = &s.bits[0];
        for (size_t k = 0; k < s.leaves.size(); ++k)
        {
            const int* ids = s.leaves[k].first;
            for (int i = 0; i < s.leaves[k].second; ++i)
            {
                const int row = rows[ids[i]];
                bits[row >> 6] |= (uint64)1 << (row & 63);
            }
        }
    }
    return marked;
}

// Counts a location's code (and writes it into the rejection map when asked).
static void countCode(int code, int c, int r, Mat* map, MatchCounters& counters)
{
    ++counters.locations;
    if (map)
        map->at<short>(r, c) = (short)(code == NOT_SCANNED ? ACCEPTED : code);
    if (code == DEPTH_RANGE)
        ++counters.rejected_depth_range;
    else if (code == FLAT)
        ++counters.rejected_flat;
    else if (code >= 0)
        counters.rejectedAtDepth(code);
}

static inline int lowestBit(uint64 w)
{
#if defined(__GNUC__)
    return __builtin_ctzll(w);
#else
    int k = 0;
    while (!(w & 1))
    {
        w >>= 1;
        ++k;
    }
    return k;
#endif
}

// One row of locations through the active groups: each location's code, and the candidates of
// those that a group accepts.
static void scanRow(const ScanContext& ctx, int r, int W, Mat* map, RowOutput& out,
                    ScanScratch& s)
{
    const std::vector<uchar>& allowed = *ctx.row_allowed;
    const int words = (int)s.bits.size();
    rowTests(ctx, r, W, s);
    std::fill(s.row_windows.begin(), s.row_windows.end(), (uchar)0);
    for (int c = 0; c < W; ++c)
    {
        const bool marked = visitGroups(ctx, c, r, W, s);
        countCode(marked ? ACCEPTED : locationCode(ctx, &s.verdict[0], c, r), c, r, map,
                  out.counters);
        if (!marked) // no group on the forest path accepted it: no candidates, no bit set
            continue;
        // the marked rows, ascending; the bit set is cleared for the next location
        int n = 0;
        for (int w = 0; w < words; ++w)
        {
            uint64 bw = s.bits[w];
            if (!bw)
                continue;
            s.bits[w] = 0;
            while (bw)
            {
                const int row = (w << 6) + lowestBit(bw);
                bw &= bw - 1;
                if (!allowed[row])
                    continue;
                out.rows.push_back(row);
                ++n;
            }
        }
        if (n == 0)
            continue;
        out.location.push_back(Point(c, r));
        out.count.push_back(n);
        ++out.counters.validated;
        out.counters.candidates += n;
    }
}

static ScanScratch scanScratch(const ScanContext& ctx, int W)
{
    ScanScratch s;
    s.bits.assign((ctx.index->rows.size() + 63) / 64, 0);
    size_t D = 1;
    for (size_t g = 0; g < ctx.dim_ptr.size(); ++g)
        D = std::max(D, ctx.dim_ptr[g].size());
    s.values.resize(D);
    const size_t X = (size_t)(W - 1) * ctx.S + 1;
    size_t span = X; // the flat-window test counts over the window's width too
    for (size_t g = 0; g < ctx.grid_dx.size(); ++g)
        span = std::max(span, X + (size_t)ctx.grid_dx[g].back());
    s.count8.resize(span);
    s.flat.resize(ctx.groups.size() * W + 1);
    s.root_ok.resize(ctx.groups.size() * ctx.max_trees * W + 1);
    s.verdict.resize(ctx.groups.size() + 1);
    size_t windows = 0;
    s.window_offset.resize(ctx.groups.size());
    for (size_t g = 0; g < ctx.groups.size(); ++g)
    {
        s.window_offset[g] = windows;
        windows += (size_t)W * ctx.dim_ptr[g].size();
    }
    s.windows.reset(new uchar[windows + 1]); // written before it is read (gatherRowWindows)
    s.row_windows.assign(ctx.groups.size(), 0);
    return s;
}

// Scans the given rows of locations in parallel.
static void scanRows(const ScanContext& ctx, const std::vector<int>& which, int W, Mat* map,
                     std::vector<RowOutput>& rows)
{
    parallel_for_(Range(0, (int)which.size()), [&](const Range& range) {
        ScanScratch s = scanScratch(ctx, W);
        for (int i = range.start; i < range.end; ++i)
            scanRow(ctx, which[i], W, map, rows[which[i]], s);
    });
}

// The asked-for candidates in the union of s.leaves (group gi's accepting trees); s.bits is
// left clear.
static int unionSize(const ScanContext& ctx, int gi, ScanScratch& s)
{
    const std::vector<uchar>& allowed = *ctx.row_allowed;
    const int* rows = &ctx.groups[gi]->rows[0];
    int n = 0;
    if (s.leaves.size() == 1)
    {
        for (int i = 0; i < s.leaves[0].second; ++i)
            n += allowed[rows[s.leaves[0].first[i]]] != 0;
        return n;
    }
    uint64* bits = &s.bits[0];
    for (size_t k = 0; k < s.leaves.size(); ++k)
        for (int i = 0; i < s.leaves[k].second; ++i)
        {
            const int row = rows[s.leaves[k].first[i]];
            const uint64 bit = (uint64)1 << (row & 63);
            if (!(bits[row >> 6] & bit) && allowed[row])
                ++n;
            bits[row >> 6] |= bit;
        }
    for (size_t k = 0; k < s.leaves.size(); ++k)
        for (int i = 0; i < s.leaves[k].second; ++i)
            s.bits[rows[s.leaves[k].first[i]] >> 6] = 0;
    return n;
}

// Sample row i (row r of locations): the cost of each active group at the sample's locations it
// descends (every stride-th, row-major over the sample: the nodes visited and the pairs let
// through), until the group passes its limit (the cost only grows, so it is searched
// exhaustively whatever the rest holds).
static void sampleRow(const ScanContext& ctx, int i, int r, int W, const SampleLimits& limits,
                      ScanScratch& s, SampleCount* count)
{
    for (int g = 0; g < (int)ctx.groups.size(); ++g)
    {
        if (!ctx.active[g])
            continue;
        const int stride = limits.stride[g];
        const int64 first = (int64)i * W;
        for (int c = (int)((stride - first % stride) % stride); c < W; c += stride)
        {
            if (visitGroup(ctx, g, c, r, W, s, false, &count[g].nodes) == ACCEPTED)
                count[g].pairs += unionSize(ctx, g, s);
            if (limits.passed(g, count[g]))
                break;
        }
    }
}

// The sample rows through the active groups, as many rows at a time as there are threads: a
// group that passes its limit on the rows sampled so far leaves the following ones and
// ctx.active. The decisions are those of the whole sample, whatever the threads.
static void sampleGroups(ScanContext& ctx, const std::vector<int>& sample, int W,
                         SampleLimits limits)
{
    const int NG = (int)ctx.groups.size();
    const int batch = std::max(1, getNumThreads());
    std::vector<SampleCount> count((size_t)batch * NG);
    for (int b = 0; b < (int)sample.size(); b += batch)
    {
        const int n = std::min((int)sample.size() - b, batch);
        std::fill(count.begin(), count.end(), SampleCount());
        parallel_for_(Range(0, n), [&](const Range& range) {
            ScanScratch s = scanScratch(ctx, W);
            for (int k = range.start; k < range.end; ++k)
                sampleRow(ctx, b + k, sample[b + k], W, limits, s, &count[(size_t)k * NG]);
        });
        for (int g = 0; g < NG; ++g)
        {
            for (int k = 0; k < n; ++k)
                limits.count[g] += count[(size_t)k * NG + g];
            if (ctx.active[g] && limits.passed(g, SampleCount()))
                ctx.active[g] = 0;
        }
    }
}

// Groups of several trees (a location stays while one tree accepts it) first go through the
// sample with their first tree only: the union of the trees' leaves holds the first tree's, so
// a group whose first tree alone passes its limit passes it with every tree, and leaves the scan
// without its other trees' root tests and descents (same decisions). With reject_any_tree one
// rejecting tree rejects, and the union may hold fewer: those groups are not tried.
static void sampleFirstTrees(ScanContext& ctx, const std::vector<int>& sample, int W,
                             const SampleLimits& limits)
{
    const int NG = (int)ctx.groups.size();
    std::vector<uchar> tried(NG);
    for (int g = 0; g < NG; ++g)
        tried[g] = ctx.active[g] && ctx.trees[g] > 1 && !ctx.any_tree[g];
    if (std::find(tried.begin(), tried.end(), (uchar)1) == tried.end())
        return;  // no group to try: the context is not copied
    ScanContext first = ctx;
    first.active = tried;
    std::fill(first.trees.begin(), first.trees.end(), 1);
    sampleGroups(first, sample, W, limits);
    for (int g = 0; g < NG; ++g)
        if (tried[g] && !first.active[g])
            ctx.active[g] = 0;
}

void scanLocations(const SearchIndex& index, const ScenePyramid& scene,
                   const DetectorParams& params, const std::vector<uchar>& row_allowed,
                   bool rejection_map, LocationCandidates& out)
{
    ScanContext ctx = scanContext(index, scene, params, row_allowed);
    const LevelMaps& top = scene.coarsest();
    const Size size = top.size;
    const int W = (size.width + ctx.S - 1) / ctx.S, H = (size.height + ctx.S - 1) / ctx.S;
    out = LocationCandidates();
    out.step = ctx.S;
    out.exhaustive.assign(index.groups.size(), 0);
    if (rejection_map)
        out.rejection_map.create(H, W, CV_16SC1);
    Mat* map = rejection_map ? &out.rejection_map : 0;
    std::vector<RowOutput> rows(H);
    const int NG = (int)ctx.groups.size();
    std::vector<int> templates(NG, 0);
    for (size_t r = 0; r < index.rows.size(); ++r)
        if (row_allowed[r] && ctx.group_of_row[r] >= 0)
            templates[ctx.group_of_row[r]]++;
    const double positions = (double)(size.width / top.T) * (size.height / top.T);
    const float ratio = params.exhaustive_ratio;

    // 1. the sample rows (every kSample-th) through every group; a group whose forest lets
    //    through more pairs than exhaustive_ratio x templates x positions (extrapolated to the
    //    frame) is searched exhaustively and leaves the scan. A group descends every stride-th
    //    location of the sample, the stride such that its limit stays kDecisionPairs pairs or
    //    more on the locations descended (large groups decide after a few dozen descents).
    const int kSample = 8, kDecisionPairs = 512;
    std::vector<int> sample, all(H);
    for (int r = 0; r < H; ++r)
    {
        all[r] = r;
        if (ratio > 0.f && (r % kSample == kSample / 2 || (H <= kSample / 2 && r == H / 2)))
            sample.push_back(r);
    }
    // with ratio 0 every group, with a positive ratio the groups of few templates
    // (min_forest_templates) are searched exhaustively without a sample
    for (int g = 0; g < NG; ++g)
        if (ratio == 0.f || (ratio > 0.f && templates[g] <= params.min_forest_templates))
            ctx.active[g] = 0;
    if (!sample.empty() && std::find(ctx.active.begin(), ctx.active.end(), 1) != ctx.active.end())
    {
        SampleLimits limits;
        limits.count.assign(NG, SampleCount());
        limits.node_cost = params.descent_cost;
        limits.limit.resize(NG);
        limits.scale.resize(NG);
        limits.stride.resize(NG);
        const double frame_per_sample = (double)H / sample.size();
        for (int g = 0; g < NG; ++g)
        {
            limits.limit[g] = ratio * (double)templates[g] * positions;
            const double on_sample = limits.limit[g] / frame_per_sample;
            limits.stride[g] = (int)std::max(1.0, std::min((double)W * sample.size(),
                                                            on_sample / kDecisionPairs));
            limits.scale[g] = frame_per_sample * limits.stride[g];
        }
        sampleFirstTrees(ctx, sample, W, limits);
        sampleGroups(ctx, sample, W, limits);
    }
    if (ratio >= 0.f)
        for (int g = 0; g < NG; ++g)
            out.exhaustive[ctx.group_index[g]] = !ctx.active[g] && templates[g] > 0;
    // 2. every row through the groups that stay
    scanRows(ctx, all, W, map, rows);

    out.begin.push_back(0);
    for (int r = 0; r < H; ++r)
    {
        const RowOutput& ro = rows[r];
        out.location.insert(out.location.end(), ro.location.begin(), ro.location.end());
        out.rows.insert(out.rows.end(), ro.rows.begin(), ro.rows.end());
        for (size_t k = 0; k < ro.count.size(); ++k)
            out.begin.push_back(out.begin.back() + ro.count[k]);
        out.counters += ro.counters;
    }
}

} // namespace detail
} // namespace forestmod
} // namespace cv
