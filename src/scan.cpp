// This file is part of OpenCV project.
// It is subject to the license terms in the LICENSE file found in the top-level directory
// of this distribution and at http://opencv.org/license.html

// The search: rejections before the forest, then every search group's forest, per location.

#include "precomp.hpp"
#include "scan.hpp"

namespace cv {
namespace forestmod {
namespace detail {

namespace {

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
    std::vector<std::vector<int> > deltas; //!< [group][dim]: offset in the planes
    std::vector<int> min_labels;           //!< [group]: flat-window limit, 0 = off
    const std::vector<uchar>* row_allowed;
    std::vector<int> group_of_row;         //!< [index row]: group (in `groups`) or -1
    int S, L;
    bool check_depth;
    int z_lo, z_hi;
};

// Outcome of a location: candidates, or the reason it left (rejection map codes).
// NOT_SCANNED: no group left to traverse (all searched exhaustively): -1 in the map, not counted.
enum { ACCEPTED = -1, FLAT = -2, DEPTH_RANGE = -3, NOT_SCANNED = -4 };

struct RowOutput
{
    std::vector<Point> location;
    std::vector<int> count;
    std::vector<int> rows;
    MatchCounters counters;
};

// Per worker: the candidates of a location as a bit set over the index rows (the leaves of every
// tree and group merged without sorting), and the accepting leaves of a group.
struct ScanScratch
{
    std::vector<uint64> bits;
    std::vector<std::pair<const int*, int> > leaves;
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
        std::vector<int> delta(g.plane_of.size());
        for (size_t j = 0; j < delta.size(); ++j)
            delta[j] = g.dim_offset[j].y * (int)scene.plane_step + g.dim_offset[j].x;
        ctx.deltas.push_back(delta);
        ctx.min_labels.push_back(params.min_window_labels > 0
                                     ? std::max(1, cvCeil(params.min_window_labels * g.min_labels))
                                     : 0);
    }
    ctx.active.assign(ctx.groups.size(), 1);
    ctx.check_depth = !scene.depth.empty() && params.depth_range_margin > 0 && index.z_max > 0;
    ctx.z_lo = index.z_min - params.depth_range_margin;
    ctx.z_hi = index.z_max + params.depth_range_margin;
    return ctx;
}

// Out of the templates' depth range: the scene depth is known at some probes around the location
// and none of them lies inside.
static bool outOfDepthRange(const ScanContext& ctx, int c, int r)
{
    const Mat& depth = ctx.scene->depth;
    int known = 0, inside = 0;
    for (size_t k = 0; k < ctx.index->depth_probe.size() && !inside; ++k)
    {
        // probes left of / above the frame are negative: a left shift would be undefined
        const int x = (c * ctx.S + ctx.index->depth_probe[k].x) * (1 << ctx.L);
        const int y = (r * ctx.S + ctx.index->depth_probe[k].y) * (1 << ctx.L);
        if (x < 0 || y < 0 || x >= depth.cols || y >= depth.rows)
            continue;
        const int z = depth.at<ushort>(y, x);
        if (!z)
            continue;
        ++known;
        inside += z >= ctx.z_lo && z <= ctx.z_hi;
    }
    return known && !inside;
}

// Every active search group: a flat window, or its forest (every tree); the location leaves when
// every group rejects it, its candidates are the union of the accepting trees' leaves (as index
// rows, marked in s.bits). Returns ACCEPTED, FLAT or the deepest rejecting forest depth.
static int visitGroups(const ScanContext& ctx, int c, int r, ScanScratch& s)
{
    const ScenePyramid& scene = *ctx.scene;
    const int NG = (int)ctx.groups.size();
    int flat = 0, deepest = -1, visited = 0;
    bool accepted = false;
    for (int gi = 0; gi < NG; ++gi)
    {
        if (!ctx.active[gi])
            continue;
        ++visited;
        const SearchGroup& grp = *ctx.groups[gi];
        LocationView view;
        view.planes = &scene.plane_ptr[0];
        view.plane_of = &grp.plane_of[0];
        view.delta = &ctx.deltas[gi][0];
        view.offset = (ptrdiff_t)(r * ctx.S + scene.border) * (ptrdiff_t)scene.plane_step
            + (c * ctx.S + scene.border);
        if (ctx.min_labels[gi] > 0)
        {
            const int D = (int)grp.plane_of.size();
            int labels = 0;
            for (int j = 0; j < D; ++j)
                labels += view.value(j) != 0;
            if (labels < ctx.min_labels[gi])
            {
                ++flat;
                continue;
            }
        }
        // the trees (TemplateForest::query's rule): with reject_any_tree one rejecting tree
        // rejects, else the location stays while one tree accepts it
        s.leaves.clear();
        int rdepth = -1;
        bool rejected_any = false;
        for (int t = 0; t < ctx.trees[gi]; ++t)
        {
            const int* ids = 0;
            int n = 0, depth = -1;
            if (grp.forest->leaf(t, view, ids, n, &depth))
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
            deepest = std::max(deepest, rdepth);
            continue;
        }
        accepted = true;
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
    if (accepted)
        return ACCEPTED;
    if (visited == 0)
        return NOT_SCANNED;
    return flat == visited ? FLAT : deepest;
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

// One row of locations. `pairs` (size of ctx.groups), when given, counts the candidates of each
// group.
static void scanRow(const ScanContext& ctx, int r, int W, Mat* map, RowOutput& out,
                    ScanScratch& s, std::vector<int64>* pairs)
{
    const std::vector<uchar>& allowed = *ctx.row_allowed;
    const int words = (int)s.bits.size();
    for (int c = 0; c < W; ++c)
    {
        ++out.counters.locations;
        int code = DEPTH_RANGE;
        if (!ctx.check_depth || !outOfDepthRange(ctx, c, r))
            code = visitGroups(ctx, c, r, s);
        if (map)
            map->at<short>(r, c) = (short)(code == NOT_SCANNED ? ACCEPTED : code);
        if (code == DEPTH_RANGE)
            ++out.counters.rejected_depth_range;
        else if (code == FLAT)
            ++out.counters.rejected_flat;
        else if (code >= 0)
            out.counters.rejectedAtDepth(code);
        if (code != ACCEPTED)
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
                if (pairs)
                    (*pairs)[ctx.group_of_row[row]]++;
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

// Scans the given rows of locations in parallel; `pairs` per row when given.
static void scanRows(const ScanContext& ctx, const std::vector<int>& which, int W, Mat* map,
                     std::vector<RowOutput>& rows, std::vector<std::vector<int64> >* pairs)
{
    parallel_for_(Range(0, (int)which.size()), [&](const Range& range) {
        ScanScratch s;
        s.bits.assign((ctx.index->rows.size() + 63) / 64, 0);
        for (int i = range.start; i < range.end; ++i)
        {
            const int r = which[i];
            if (pairs)
                (*pairs)[r].assign(ctx.groups.size(), 0);
            scanRow(ctx, r, W, map, rows[r], s, pairs ? &(*pairs)[r] : 0);
        }
    });
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
    std::vector<std::vector<int64> > pairs(H);
    if (ratio == 0.f)
    {
        for (int g = 0; g < NG; ++g)
            ctx.active[g] = 0;
    }
    else if (!sample.empty())
    {
        scanRows(ctx, sample, W, map, rows, &pairs);
        const double scale = (double)H / sample.size();
        for (int g = 0; g < NG; ++g)
        {
            int64 p = 0;
            for (size_t i = 0; i < sample.size(); ++i)
                p += pairs[sample[i]][g];
            if (p * scale > ratio * (double)templates[g] * positions)
                ctx.active[g] = 0;
        }
    }
    if (ratio >= 0.f)
        for (int g = 0; g < NG; ++g)
            out.exhaustive[ctx.group_index[g]] = !ctx.active[g] && templates[g] > 0;
    // the sample rows lose the candidates of the groups searched exhaustively
    for (size_t i = 0; i < sample.size(); ++i)
    {
        RowOutput& ro = rows[sample[i]];
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
