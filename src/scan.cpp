// This file is part of OpenCV project.
// It is subject to the license terms in the LICENSE file found in the top-level directory
// of this distribution and at http://opencv.org/license.html

// The search: rejections before the forest, then every search group's forest, per location.

#include "precomp.hpp"
#include "scan.hpp"
#include "score_kernels.hpp"

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
    std::vector<int64> pairs;      //!< sample rows: [group] candidates counted
    /** Sample rows: per location of the row the verdict of every group ([c * groups + g]);
    its code is known once the exhaustive groups are. */
    std::vector<short> verdicts;
};

// The sample rows' limits: a group leaves the scan (exhaustive search) once its pairs on the
// sample, extrapolated by `scale`, pass `limit[g]` (exhaustive_ratio x templates x positions).
struct SampleLimits
{
    std::vector<int64> pairs;      //!< [group]: counted on the sample rows scanned before
    std::vector<double> limit;     //!< [group]
    double scale;

    bool passed(int g, int64 more) const { return (double)(pairs[g] + more) * scale > limit[g]; }
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
    std::vector<ushort> count16;
    std::vector<uchar> flat, root_ok;
    std::vector<short> verdict;    //!< [group]: the location's verdicts (visitGroups)
    std::vector<uchar> cut;        //!< [group]: passed its sample limit within this row
};

} // namespace

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
    ushort* count16 = &s.count16[0];
    for (size_t gi = 0; gi < ctx.groups.size(); ++gi)
    {
        if (!ctx.active[gi])
            continue;
        uchar* flat = &s.flat[gi * W];
        if (ctx.min_labels[gi] > 0)
        {
            const std::vector<const uchar*>& ptr = ctx.dim_ptr[gi];
            std::fill(count16, count16 + X, (ushort)0);
            std::fill(count8, count8 + X, (uchar)0);
            for (size_t j = 0; j < ptr.size(); ++j)
            {
                countLabels8(count8, ptr[j] + row, X);
                if (j % 255 == 254 || j + 1 == ptr.size()) // 8-bit counts stay under 256
                {
                    widenAdd(count16, count8, X);
                    std::fill(count8, count8 + X, (uchar)0);
                }
            }
            for (int c = 0; c < W; ++c)
                flat[c] = count16[c * S] < ctx.min_labels[gi];
        }
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

// Every active search group (not cut in this row): out of its depth range, a flat window, or its
// forest (every tree);
// each group's verdict goes to s.verdict, the candidates of the accepting groups are the union
// of their accepting trees' leaves (as index rows, marked in s.bits). Returns whether one group
// accepted (marked rows).
static bool visitGroups(const ScanContext& ctx, int c, int r, int W, ScanScratch& s)
{
    const ScenePyramid& scene = *ctx.scene;
    const int NG = (int)ctx.groups.size();
    bool marked = false;
    for (int gi = 0; gi < NG; ++gi)
    {
        short& verdict = s.verdict[gi];
        verdict = NOT_VISITED;
        if (!ctx.active[gi] || s.cut[gi])
            continue;
        const SearchGroup& grp = *ctx.groups[gi];
        if (outOfDepthRange(ctx, gi, c, r))
        {
            verdict = DEPTH_RANGE;
            continue;
        }
        if (s.flat[gi * W + c])
        {
            verdict = FLAT;
            continue;
        }
        // the trees (TemplateForest::query's rule): with reject_any_tree one rejecting tree
        // rejects, else the location stays while one tree accepts it. The window's values are
        // gathered for the first tree whose root passes, once for all trees.
        s.leaves.clear();
        int rdepth = -1;
        bool rejected_any = false, gathered = false;
        uchar* values = &s.values[0];
        for (int t = 0; t < ctx.trees[gi]; ++t)
        {
            const int* ids = 0;
            int n = 0, depth = 0; // a root rejector that fails rejects at depth 0
            const bool root_ok = s.root_ok[((size_t)gi * ctx.max_trees + t) * W + c] != 0;
            if (root_ok && !gathered)
            {
                const ptrdiff_t offset = (ptrdiff_t)r * ctx.S * (ptrdiff_t)scene.plane_step
                    + c * ctx.S;
                const std::vector<const uchar*>& ptr = ctx.dim_ptr[gi];
                for (size_t j = 0; j < ptr.size(); ++j)
                    values[j] = ptr[j][offset];
                gathered = true;
            }
            if (root_ok && grp.forest->leaf(t, values, ids, n, &depth,
                                            ctx.roots[gi][t].min_accept > 0))
                s.leaves.push_back(std::make_pair(ids, n));
            else
            {
                rdepth = std::max(rdepth, depth);
                if (ctx.any_tree[gi])
                {
                    rejected_any = true;
                    break;
                }
            }
        }
        if (rejected_any || s.leaves.empty())
        {
            verdict = (short)rdepth;
            continue;
        }
        verdict = ACCEPTED;
        marked = true;
        const int* rows = &grp.rows[0];
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

// One row of locations. A sample row (`sample` given) counts the candidates of each group in
// out.pairs, leaves a group out of the rest of the row once it passes its limit (it is searched
// exhaustively whatever the other locations hold) and keeps the groups' verdicts for the
// location codes, which wait for the exhaustive groups to be known.
static void scanRow(const ScanContext& ctx, int r, int W, Mat* map, RowOutput& out,
                    ScanScratch& s, const SampleLimits* sample)
{
    const std::vector<uchar>& allowed = *ctx.row_allowed;
    const int words = (int)s.bits.size();
    const int NG = (int)ctx.groups.size();
    std::fill(s.cut.begin(), s.cut.end(), (uchar)0);
    if (sample)
    {
        out.pairs.assign(NG, 0);
        out.verdicts.resize((size_t)W * NG);
    }
    rowTests(ctx, r, W, s);
    for (int c = 0; c < W; ++c)
    {
        const bool marked = visitGroups(ctx, c, r, W, s);
        if (sample)
            std::copy(s.verdict.begin(), s.verdict.begin() + NG, &out.verdicts[(size_t)c * NG]);
        else
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
                if (sample)
                    out.pairs[ctx.group_of_row[row]]++;
            }
        }
        if (sample)
            for (int g = 0; g < NG; ++g)
                if (ctx.active[g] && !s.cut[g] && sample->passed(g, out.pairs[g]))
                    s.cut[g] = 1;
        if (n == 0)
            continue;
        out.location.push_back(Point(c, r));
        out.count.push_back(n);
        ++out.counters.validated;
        out.counters.candidates += n;
    }
}

// Scans the given rows of locations in parallel (as sample rows when `sample` is given).
static void scanRows(const ScanContext& ctx, const std::vector<int>& which, int W, Mat* map,
                     std::vector<RowOutput>& rows, const SampleLimits* sample)
{
    parallel_for_(Range(0, (int)which.size()), [&](const Range& range) {
        ScanScratch s;
        s.bits.assign((ctx.index->rows.size() + 63) / 64, 0);
        size_t D = 1;
        for (size_t g = 0; g < ctx.dim_ptr.size(); ++g)
            D = std::max(D, ctx.dim_ptr[g].size());
        s.values.resize(D);
        const size_t X = (size_t)(W - 1) * ctx.S + 1;
        s.count8.resize(X);
        s.count16.resize(X);
        s.flat.resize(ctx.groups.size() * W + 1);
        s.root_ok.resize(ctx.groups.size() * ctx.max_trees * W + 1);
        s.verdict.resize(ctx.groups.size() + 1);
        s.cut.resize(ctx.groups.size() + 1);
        for (int i = range.start; i < range.end; ++i)
            scanRow(ctx, which[i], W, map, rows[which[i]], s, sample);
    });
}

// The sample rows once the exhaustive groups are known: their locations' codes and counters from
// the groups that stay (as the other rows'), and they lose the candidates of the groups searched
// exhaustively.
static void finishSampleRows(const ScanContext& ctx, const std::vector<int>& sample, int W,
                             Mat* map, std::vector<RowOutput>& rows)
{
    const int NG = (int)ctx.groups.size();
    for (size_t i = 0; i < sample.size(); ++i)
    {
        const int r = sample[i];
        RowOutput& ro = rows[r];
        for (int c = 0; c < W; ++c)
        {
            short* v = &ro.verdicts[(size_t)c * NG];
            for (int g = 0; g < NG; ++g)
                if (!ctx.active[g])
                    v[g] = NOT_VISITED;
            countCode(locationCode(ctx, v, c, r), c, r, map, ro.counters);
        }
        size_t k = 0, j = 0, kept_locations = 0;
        for (size_t l = 0; l < ro.location.size(); ++l)
        {
            int n = 0;
            for (int e = 0; e < ro.count[l]; ++e, ++j)
                if (ctx.active[ctx.group_of_row[ro.rows[j]]])
                {
                    ro.rows[k++] = ro.rows[j];
                    ++n;
                }
            ro.counters.candidates -= ro.count[l] - n;
            if (n == 0)
            {
                --ro.counters.validated;
                continue;
            }
            ro.location[kept_locations] = ro.location[l];
            ro.count[kept_locations++] = n;
        }
        ro.rows.resize(k);
        ro.location.resize(kept_locations);
        ro.count.resize(kept_locations);
    }
}

// The sample rows through the active groups, as many rows at a time as there are threads: a
// group that passes its limit on the rows scanned so far leaves the following ones (and the rest
// of a row as soon as that row alone passes it: its count only grows) and ctx.active. The
// decisions are those of the whole sample, whatever the threads.
static void sampleGroups(ScanContext& ctx, const std::vector<int>& sample, int W, Mat* map,
                         std::vector<RowOutput>& rows, SampleLimits limits)
{
    const int NG = (int)ctx.groups.size();
    const size_t batch = (size_t)std::max(1, getNumThreads());
    for (size_t b = 0; b < sample.size(); b += batch)
    {
        const std::vector<int> part(sample.begin() + b,
                                    sample.begin() + std::min(sample.size(), b + batch));
        scanRows(ctx, part, W, map, rows, &limits);
        for (int g = 0; g < NG; ++g)
        {
            for (size_t i = 0; i < part.size(); ++i)
                limits.pairs[g] += rows[part[i]].pairs[g];
            if (ctx.active[g] && limits.passed(g, 0))
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
    std::vector<RowOutput> rows(*std::max_element(sample.begin(), sample.end()) + 1);
    sampleGroups(first, sample, W, 0, rows, limits);
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
    //    frame) is searched exhaustively and leaves the scan
    const int kSample = 8;
    std::vector<int> sample, rest;
    for (int r = 0; r < H; ++r)
        (ratio > 0.f && (r % kSample == kSample / 2 || (H <= kSample / 2 && r == H / 2))
             ? sample : rest).push_back(r);
    if (ratio == 0.f)
    {
        for (int g = 0; g < NG; ++g)
            ctx.active[g] = 0;
    }
    else if (!sample.empty())
    {
        SampleLimits limits;
        limits.scale = (double)H / sample.size();
        limits.pairs.assign(NG, 0);
        limits.limit.resize(NG);
        for (int g = 0; g < NG; ++g)
            limits.limit[g] = ratio * (double)templates[g] * positions;
        sampleFirstTrees(ctx, sample, W, limits);
        sampleGroups(ctx, sample, W, map, rows, limits);
    }
    if (ratio >= 0.f)
        for (int g = 0; g < NG; ++g)
            out.exhaustive[ctx.group_index[g]] = !ctx.active[g] && templates[g] > 0;
    finishSampleRows(ctx, sample, W, map, rows);
    // 2. the other rows through the groups that stay
    scanRows(ctx, rest, W, map, rows, 0);

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
