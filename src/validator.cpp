// This file is part of OpenCV project.
// It is subject to the license terms in the LICENSE file found in the top-level directory
// of this distribution and at http://opencv.org/license.html

// Validation stage (paper: "Fast Breadth-first Leaf Validation"): LINEMOD's similarity read from
// linearized memories of the frame's coarsest level on the location grid (offsets computed once
// per template and frame; a template's candidates at neighbouring locations scored together, one
// vector addition per feature), the breadth-first preemptive scheme; the groups whose forest
// rejected too little in this frame go to the exhaustive search (exhaustive_search.cpp).

#include "precomp.hpp"
#include "validator.hpp"
#include "exhaustive_search.hpp"
#include "score_kernels.hpp"

namespace cv {
namespace forestmod {
namespace detail {

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
    const int offset = matchOffset(T);
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

// The index rows of the groups the scan left to the exhaustive search whose class was asked for
// (marked in skip_row: they are in no location's candidates); returns the number of such groups.
static int exhaustiveRows(const LocationCandidates& cands, const SearchIndex& index,
                          const std::vector<uchar>& row_allowed, std::vector<uchar>& skip_row,
                          std::vector<int>& dense_rows)
{
    skip_row.assign(index.rows.size(), 0);
    dense_rows.clear();
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
    return dense_groups;
}

// The forest path's part of the validation: every location's candidates (those not in skip_row)
// validated, the best max_survivors of each over the threshold appended to `coarse`, in location
// order.
static void validateForestPath(const ScenePyramid& scene, const LocationCandidates& cands,
                               const SearchIndex& index, const ClassPyramids& pyramids,
                               const DetectorParams& params, float threshold,
                               const std::vector<uchar>& skip_row,
                               std::vector<cv::linemod::Match>& coarse)
{
    const LevelMaps& top = scene.coarsest();
    CV_Assert(params.chunk_size > 0);
    ValidationContext ctx;
    prepareContext(scene, cands, index, pyramids, skip_row, params.chunk_size, ctx);
    if (ctx.rows.empty())
        return;
    const int n = cands.size();
    // locations in blocks, each block's matches in order: the result does not depend on threads
    // (nor on the blocks: every location is validated on its own)
    const int block = 64;
    const int blocks = (n + block - 1) / block;
    std::vector<std::vector<cv::linemod::Match> > per_block(blocks);
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
}

// The exhaustive search's coarse matches per position: max_survivors for each of the forest
// path's locations that a cell of the T grid holds.
static int exhaustiveKeep(const ScenePyramid& scene, const LocationCandidates& cands,
                          const DetectorParams& params)
{
    const int T = scene.coarsest().T;
    const int per_cell = (T + cands.step - 1) / cands.step;
    return params.max_survivors * per_cell * per_cell;
}

void validateLocations(const ScenePyramid& scene, const LocationCandidates& cands,
                       const SearchIndex& index, const ClassPyramids& pyramids,
                       const DetectorParams& params, float threshold,
                       const std::vector<uchar>& row_allowed,
                       std::vector<cv::linemod::Match>& coarse, int* exhaustive_groups)
{
    coarse.clear();
    std::vector<uchar> skip_row;
    std::vector<int> dense_rows;
    const int dense_groups = exhaustiveRows(cands, index, row_allowed, skip_row, dense_rows);
    if (exhaustive_groups)
        *exhaustive_groups = dense_groups;
    validateForestPath(scene, cands, index, pyramids, params, threshold, skip_row, coarse);
    if (!dense_rows.empty())
        searchExhaustive(scene, index, pyramids, dense_rows, threshold,
                         exhaustiveKeep(scene, cands, params), params.depth_range_tolerance,
                         std::vector<std::vector<cv::linemod::Match>*>(1, &coarse));
}

// The candidates of `cands` whose class is `c` (class_of_row), the locations without one left
// out: what the scan gives when it is asked for that class alone.
static void candidatesOfClass(const LocationCandidates& cands,
                              const std::vector<int>& class_of_row, int c,
                              LocationCandidates& out)
{
    out = LocationCandidates();
    out.step = cands.step;
    out.exhaustive = cands.exhaustive;
    out.begin.push_back(0);
    for (int i = 0; i < cands.size(); ++i)
    {
        const size_t before = out.rows.size();
        for (int k = cands.begin[i]; k < cands.begin[i + 1]; ++k)
            if (class_of_row[cands.rows[k]] == c)
                out.rows.push_back(cands.rows[k]);
        if (out.rows.size() == before)
            continue;
        out.location.push_back(cands.location[i]);
        out.begin.push_back(static_cast<int>(out.rows.size()));
    }
}

void validateLocationsPerClass(const ScenePyramid& scene, const LocationCandidates& cands,
                               const SearchIndex& index, const ClassPyramids& pyramids,
                               const DetectorParams& params, float threshold,
                               const std::vector<int>& class_of_row,
                               std::vector<std::vector<cv::linemod::Match> >& coarse)
{
    CV_Assert(class_of_row.size() == index.rows.size() && !coarse.empty());
    const int classes = static_cast<int>(coarse.size());
    std::vector<uchar> allowed(index.rows.size());
    for (size_t r = 0; r < allowed.size(); ++r)
    {
        CV_Assert(class_of_row[r] < classes);
        allowed[r] = class_of_row[r] >= 0;
    }
    std::vector<uchar> skip_row;
    std::vector<int> dense_rows;
    exhaustiveRows(cands, index, allowed, skip_row, dense_rows);
    std::vector<std::vector<cv::linemod::Match>*> lists(classes);
    for (int c = 0; c < classes; ++c)
    {
        coarse[c].clear();
        lists[c] = &coarse[c];
        if (cands.size() == 0)
            continue;
        LocationCandidates mine;
        candidatesOfClass(cands, class_of_row, c, mine);
        validateForestPath(scene, mine, index, pyramids, params, threshold, skip_row, coarse[c]);
    }
    if (!dense_rows.empty())
        searchExhaustive(scene, index, pyramids, dense_rows, threshold,
                         exhaustiveKeep(scene, cands, params), params.depth_range_tolerance,
                         lists, &class_of_row);
}

} // namespace detail
} // namespace forestmod
} // namespace cv
