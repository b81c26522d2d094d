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
    std::vector<std::vector<int> > deltas; //!< [group][dim]: offset in the planes
    std::vector<int> min_labels;           //!< [group]: flat-window limit, 0 = off
    const std::vector<uchar>* row_allowed;
    int S, L;
    bool check_depth;
    int z_lo, z_hi;
};

// Outcome of a location: candidates, or the reason it left (rejection map codes).
enum { ACCEPTED = -1, FLAT = -2, DEPTH_RANGE = -3 };

struct RowOutput
{
    std::vector<Point> location;
    std::vector<int> count;
    std::vector<int> rows;
    MatchCounters counters;
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
    for (size_t gi = 0; gi < index.groups.size(); ++gi)
    {
        const SearchGroup& g = index.groups[gi];
        bool any = false;
        for (size_t k = 0; k < g.rows.size() && !any; ++k)
            any = allowed[g.rows[k]] != 0;
        if (!any)
            continue;
        ctx.groups.push_back(&g);
        std::vector<int> delta(g.plane_of.size());
        for (size_t j = 0; j < delta.size(); ++j)
            delta[j] = g.dim_offset[j].y * (int)scene.plane_step + g.dim_offset[j].x;
        ctx.deltas.push_back(delta);
        ctx.min_labels.push_back(params.min_window_labels > 0
                                     ? std::max(1, cvCeil(params.min_window_labels * g.min_labels))
                                     : 0);
    }
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

// Every search group: a flat window, or its forest; the location leaves when every group rejects
// it, its candidates are the union of the groups' leaves (as index rows). Returns ACCEPTED, FLAT
// or the deepest rejecting forest depth.
static int visitGroups(const ScanContext& ctx, int c, int r, std::vector<int>& group_cands,
                       std::vector<int>& cands)
{
    const ScenePyramid& scene = *ctx.scene;
    const int NG = (int)ctx.groups.size();
    int flat = 0, deepest = -1;
    bool accepted = false;
    cands.clear();
    for (int gi = 0; gi < NG; ++gi)
    {
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
        int depth = -1;
        if (!grp.forest->query(view, group_cands, &depth))
        {
            deepest = std::max(deepest, depth);
            continue;
        }
        accepted = true;
        for (size_t k = 0; k < group_cands.size(); ++k)
            cands.push_back(grp.rows[group_cands[k]]);
    }
    if (accepted)
    {
        if (NG > 1)
            std::sort(cands.begin(), cands.end());
        return ACCEPTED;
    }
    return flat == NG ? FLAT : deepest;
}

static void scanRow(const ScanContext& ctx, int r, int W, Mat* map, RowOutput& out)
{
    std::vector<int> cands, group_cands;
    for (int c = 0; c < W; ++c)
    {
        ++out.counters.locations;
        int code = DEPTH_RANGE;
        if (!ctx.check_depth || !outOfDepthRange(ctx, c, r))
            code = visitGroups(ctx, c, r, group_cands, cands);
        if (map)
            map->at<short>(r, c) = (short)code;
        if (code == DEPTH_RANGE)
            ++out.counters.rejected_depth_range;
        else if (code == FLAT)
            ++out.counters.rejected_flat;
        else if (code >= 0)
            out.counters.rejectedAtDepth(code);
        if (code != ACCEPTED)
            continue;
        int n = 0;
        for (size_t k = 0; k < cands.size(); ++k)
            if ((*ctx.row_allowed)[cands[k]])
            {
                out.rows.push_back(cands[k]);
                ++n;
            }
        if (n == 0)
            continue;
        out.location.push_back(Point(c, r));
        out.count.push_back(n);
        ++out.counters.validated;
        out.counters.candidates += n;
    }
}

void scanLocations(const SearchIndex& index, const ScenePyramid& scene,
                   const DetectorParams& params, const std::vector<uchar>& row_allowed,
                   bool rejection_map, LocationCandidates& out)
{
    const ScanContext ctx = scanContext(index, scene, params, row_allowed);
    const Size size = scene.coarsest().size;
    const int W = (size.width + ctx.S - 1) / ctx.S, H = (size.height + ctx.S - 1) / ctx.S;
    out = LocationCandidates();
    out.step = ctx.S;
    if (rejection_map)
        out.rejection_map.create(H, W, CV_16SC1);
    Mat* map = rejection_map ? &out.rejection_map : 0;
    std::vector<RowOutput> rows(H);
    parallel_for_(Range(0, H), [&](const Range& range) {
        for (int r = range.start; r < range.end; ++r)
            scanRow(ctx, r, W, map, rows[r]);
    });
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
