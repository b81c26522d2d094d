// This file is part of OpenCV project.
// It is subject to the license terms in the LICENSE file found in the top-level directory
// of this distribution and at http://opencv.org/license.html

// The exhaustive search of the search groups whose forest rejected too little in a frame
// (DetectorParams::exhaustive_ratio): every asked-for template at every position of the coarsest
// level's T grid, as cv::linemod, on the linearized memories; each position keeps its best
// templates over the threshold. And without a forest (DetectorParams::use_forest false) the
// linear LINEMOD search of every template, position by position (matchExhaustive).

#include "precomp.hpp"
#include "exhaustive_search.hpp"
#include "score_kernels.hpp"
#include <deque>

namespace cv {
namespace forestmod {
namespace detail {

bool scoreEverywhere(const LinearMemories& lm, const TemplatePyramid& tp, int level_index,
                     int num_modalities, int& span_x, int& span_y, std::vector<ushort>& scores)
{
    std::vector<CoarseFeature> f;
    const Size cells = coarseFeatures(tp, level_index, num_modalities, lm.T, f);
    span_x = lm.cells_x - cells.width;
    span_y = lm.cells_y - cells.height;
    if (span_x < 0 || span_y < 0)
        return false;
    // (cx <= cells.width <= cells_x: the offsets lie within the memories)
    std::vector<int> runs(f.size());
    for (size_t k = 0; k < f.size(); ++k)
        runs[k] = static_cast<int>(runOffset(f[k], lm.stride, lm.rows));
    // positions r * stride + c, the row ends included (they wrap); the kernel writes whole
    // vectors
    const int n = span_y * lm.stride + span_x + 1;
    scores.resize(n + LinearMemories::kSlack);
    sumRuns16(&scores[0], &lm.data[0], runs.empty() ? 0 : &runs[0], (int)runs.size(), n);
    scores.resize(n);
    return true;
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

// Inserts `s` into the best-first list `top` of k entries (empty entries have row -1); false
// when it does not enter.
static bool keepBest(Scored* top, int k, const Scored& s)
{
    if (top[k - 1].row >= 0 && !s.better(top[k - 1]))
        return false;
    int i = k - 1;
    while (i > 0 && (top[i - 1].row < 0 || s.better(top[i - 1])))
    {
        top[i] = top[i - 1];
        --i;
    }
    top[i] = s;
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
    // 65536 raw / (4 total) = 16384 raw / total: raw < 65536 keeps it in 32 bits
    const unsigned q = ((unsigned)last.raw << 14) / (unsigned)last.total;
    return static_cast<ushort>(std::min(q, 65535u));
}

// The rows of positions r0 .. r1 of a template whose depth span `z` (widened) the scene depth
// may reach around its centre (the centre `centre` cells from the position's cell); false when
// no row does. Every row without a depth test.
static bool rowsInDepthRange(const DepthCells* cells, const DepthSpan& z, Point centre,
                             int span_y, int& r0, int& r1)
{
    r0 = 0;
    r1 = span_y;
    if (!cells || z.empty())
        return true;
    while (r0 <= span_y && !cells->rowReaches(r0 + centre.y, z))
        ++r0;
    while (r1 >= r0 && !cells->rowReaches(r1 + centre.y, z))
        --r1;
    return r0 <= r1;
}

// Asks the cache for the runs of the template of index row `row`: the rows of a search group lie
// apart in the index (every class's templates, by size), and the first reads of each template's
// runs waited for memory (the 8 LM-O objects' model: 6.4 MB of them per frame).
static inline void prefetchRuns(const CoarseRuns& coarse, const int* offsets, int row)
{
    const char* p = reinterpret_cast<const char*>(offsets + coarse.begin[row]);
    const char* e = reinterpret_cast<const char*>(offsets + coarse.begin[row + 1]);
    for (; p < e; p += 64)
        prefetchLine(p);
}

namespace {
// The best lists a position keeps: one (list_of_row null), or one per class, each row's in
// (*of_row)[row] (searchExhaustive's list_of_row).
struct ListsOfRows
{
    int count;
    const std::vector<int>* of_row;
};

// searchTemplates' buffers, reused from template to template.
struct SearchBuffers
{
    std::vector<ushort> scores, need;
    std::vector<int> vectors, hits;
};
} // namespace

// The positions (r - r0) * stride + c where a template whose features sum beyond 16 bits
// (hostile model files only) passes the threshold and the entry bar, in buf.hits, its scores in
// buf.scores; LINEMOD's similarity at every position.
static int passingBySimilarity(const LevelMaps& top, int L, const LinearMemories& lm,
                               const TemplatePyramid& tp, int raw_thr, int total,
                               const ushort* bar, SearchBuffers& buf, int& span_x, int& r1)
{
    const cv::linemod::Template& t0 = tp[L * top.modalities()];
    const int T = top.T;
    span_x = lm.cells_x - ((t0.width - 1) / T + 1);
    r1 = lm.cells_y - ((t0.height - 1) / T + 1);
    if (span_x < 0 || r1 < 0)
        return 0;
    buf.scores.assign((size_t)r1 * lm.stride + span_x + 1, 0);
    buf.hits.clear();
    for (int r = 0; r <= r1; ++r)
        for (int c = 0; c <= span_x; ++c)
        {
            const int p = r * lm.stride + c;
            const int raw = std::min(65535, similarityAll(top, tp, L, Point(c * T, r * T)));
            buf.scores[p] = (ushort)raw;
            if (raw > raw_thr && (((uint64)bar[p] * (uint64)(4 * total)) >> 16) <= (uint64)raw)
                buf.hits.push_back(p);
        }
    return (int)buf.hits.size();
}

// The templates rows[i0 .. i1) at every position (with a depth test, at the positions where the
// scene depth reaches into their widened depth span): each position's best K of each list (of
// `lists`) in `best_all` (the T grid's cells row-major, a cell's lists one after the other), the
// list's entry bars at bar_all + list x bar_size (the scores' layout r * stride + c).
static void searchTemplates(const LevelMaps& top, int L, const LinearMemories& lm,
                            const SearchIndex& index, const int* offsets,
                            const ClassPyramids& pyramids, const std::vector<int>& rows, int i0,
                            int i1, float threshold, int K, const ListsOfRows& lists,
                            const DepthCells* cells, float tolerance, Scored* best_all,
                            ushort* bar_all, size_t bar_size)
{
    const CoarseRuns& coarse = index.coarse;
    SearchBuffers buf;
    for (int i = i0; i < i1; ++i)
    {
        if (i + 1 < i1)
            prefetchRuns(coarse, offsets, rows[i + 1]);
        Scored sc;
        sc.row = rows[i];
        // the lists (and so the entry bars) of the row's class, or the only ones
        const int list = lists.of_row ? (*lists.of_row)[sc.row] : 0;
        Scored* best = best_all + (size_t)list * K;
        ushort* bar = bar_all + (size_t)list * bar_size;
        const int stride_K = lists.count * K; // from one position's lists to the next's
        sc.total = coarse.total[sc.row];
        const int raw_thr = rawThreshold(threshold, sc.total);
        if (raw_thr >= 65535)
            continue;
        const DepthSpan z = cells ? widenedSpan(index.depth[sc.row], tolerance) : DepthSpan();
        const Point centre = coarse.centre[sc.row];
        int span_x = 0, span_y = 0, r0 = 0, r1 = 0, n_hits = 0;
        if (sc.total > kMaxSum16) // beyond 16-bit sums (hostile model files only)
        {
            const TemplateRef& ref = index.rows[sc.row];
            n_hits = passingBySimilarity(top, L, lm,
                                         pyramids.find(ref.class_id)->second[ref.template_id],
                                         raw_thr, sc.total, bar, buf, span_x, r1);
        }
        else
        {
            const Size box = coarse.cells[sc.row];
            span_x = lm.cells_x - box.width;
            span_y = lm.cells_y - box.height;
            if (span_x < 0 || span_y < 0
                || !rowsInDepthRange(cells, z, centre, span_y, r0, r1))
                continue;
            const int b = coarse.begin[sc.row], e = coarse.begin[sc.row + 1];
            // the positions (r - r0) * stride + c, the row ends (c > span_x) included: they
            // wrap, are scored and never reported; the runs of row r0 start r0 rows further
            const int n_pos = (r1 - r0) * lm.stride + span_x + 1;
            buf.scores.resize(n_pos + LinearMemories::kSlack);
            buf.need.resize(n_pos + LinearMemories::kSlack);
            buf.vectors.resize(n_pos / 16 + 1);
            buf.hits.resize(n_pos);
            n_hits = sumRunsPassing16(&buf.scores[0], &lm.data[0] + (size_t)r0 * lm.stride,
                                      b < e ? offsets + b : 0, e - b, n_pos,
                                      bar + (size_t)r0 * lm.stride, (ushort)raw_thr,
                                      (ushort)(4 * sc.total), &buf.need[0], &buf.vectors[0],
                                      &buf.hits[0]); // 4 total <= 65532
        }
        ushort* bar_r0 = bar + (size_t)r0 * lm.stride;
        // the hits ascend: their row follows them without a division
        for (int h = 0, r = r0, row_start = 0; h < n_hits; ++h)
        {
            const int p = buf.hits[h];
            while (p >= row_start + lm.stride)
            {
                row_start += lm.stride;
                ++r;
            }
            const int c = p - row_start;
            if (c > span_x || (cells && !cells->reaches(c + centre.x, r + centre.y, z)))
                continue;
            sc.raw = buf.scores[p];
            Scored* top_k = best + (size_t)(r * lm.cells_x + c) * stride_K;
            if (keepBest(top_k, K, sc)) // the bar only moves when the list changes
                bar_r0[p] = entryBar(top_k[K - 1]);
        }
    }
}

namespace {
// The best lists and entry bars of the exhaustive search's workers: a worker takes a slot for
// the blocks of one call and gives it back, so there are as many slots as calls at once (the
// threads), and a slot's bars rise with every template scored into it.
class WorkerLists
{
public:
    struct Slot
    {
        std::vector<Scored> best;
        std::vector<ushort> bar; //!< read in whole vectors by the additions' kernel
    };
    WorkerLists(size_t lists, size_t bars) : lists_(lists), bars_(bars) {}
    Slot& take()
    {
        AutoLock lock(mutex_);
        if (free_.empty())
        {
            const Scored none = { 0, 1, -1 };
            slots_.emplace_back();
            slots_.back().best.assign(lists_, none);
            slots_.back().bar.assign(bars_ + LinearMemories::kSlack, 0);
            free_.push_back(&slots_.back());
        }
        Slot* s = free_.back();
        free_.pop_back();
        return *s;
    }
    void give(Slot& s)
    {
        AutoLock lock(mutex_);
        free_.push_back(&s);
    }
    /** Every slot's lists of K merged into the first slot's (the slots are all given back). */
    std::vector<Scored>& merged(int K)
    {
        if (slots_.empty())
            give(take());
        std::deque<Slot>::iterator first = slots_.begin();
        for (std::deque<Slot>::iterator it = first + 1; it != slots_.end(); ++it)
            for (size_t p = 0; p < lists_; p += K)
                for (int k = 0; k < K && it->best[p + k].row >= 0; ++k)
                    keepBest(&first->best[p], K, it->best[p + k]);
        return first->best;
    }

private:
    size_t lists_, bars_;
    Mutex mutex_;
    std::deque<Slot> slots_; // stable addresses
    std::vector<Slot*> free_;
};
} // namespace

// keep: max_survivors for each of the (T / step)^2 locations of the forest path that a cell of
// the T grid holds (validateLocations).
void searchExhaustive(const ScenePyramid& scene, const SearchIndex& index,
                      const ClassPyramids& pyramids, const std::vector<int>& rows,
                      float threshold, int keep, float depth_tolerance,
                      const std::vector<std::vector<cv::linemod::Match>*>& out,
                      const std::vector<int>* list_of_row)
{
    const LevelMaps& top = scene.coarsest();
    const int L = scene.coarsestIndex();
    const int T = top.T;
    const int K = keep;
    const int offset = matchOffset(T);
    CV_Assert(index.coarse.begin.size() == index.rows.size() + 1);
    const DepthCells* cells = scene.depth_cells.empty() ? 0 : &scene.depth_cells;
    LinearMemories lm;
    lm.build(top);
    // the templates' runs in memories of this frame's size (kept by the index from frame to frame)
    const std::shared_ptr<const CoarseRuns::Offsets> runs = index.coarse.offsetsFor(lm.stride,
                                                                                    lm.rows);
    const int* offsets = runs->offsets.empty() ? 0 : &runs->offsets[0];
    const int P = lm.cells_x * lm.cells_y;
    const int n = static_cast<int>(rows.size());
    ListsOfRows lists;
    lists.count = static_cast<int>(out.size());
    lists.of_row = list_of_row;
    CV_Assert(lists.count >= 1 && (lists.count == 1 || list_of_row));
    // each list's bars padded for the kernel's whole-vector reads
    const size_t bar_size = (size_t)lm.stride * lm.cells_y + LinearMemories::kSlack;
    // templates in blocks taken by the threads as they free up, each thread's templates into
    // best lists (and so entry bars) of its own, which rise with every template it scores; the
    // lists are merged afterwards: a position's best K of a union are the best K of its parts'
    // best K, however the blocks fall to the threads (Scored::better is a total order)
    const int blocks = std::max(1, std::min(n, 16 * getNumThreads()));
    WorkerLists workers((size_t)P * lists.count * K, bar_size * lists.count);
    parallel_for_(Range(0, blocks), [&](const Range& range) {
        WorkerLists::Slot& slot = workers.take();
        for (int b = range.start; b < range.end; ++b)
            searchTemplates(top, L, lm, index, offsets, pyramids, rows,
                            (int)((int64)n * b / blocks), (int)((int64)n * (b + 1) / blocks),
                            threshold, K, lists, cells, depth_tolerance, &slot.best[0],
                            &slot.bar[0], bar_size);
        workers.give(slot);
    }, blocks);
    std::vector<Scored>& best = workers.merged(K);
    for (int p = 0; p < P; ++p)
        for (int l = 0; l < lists.count; ++l)
            for (int k = 0; k < K; ++k)
            {
                const Scored& sc = best[((size_t)p * lists.count + l) * K + k];
                if (sc.row < 0)
                    break;
                const TemplateRef& ref = index.rows[sc.row];
                const int c = p % lm.cells_x, r = p / lm.cells_x;
                out[l]->push_back(cv::linemod::Match(c * T + offset, r * T + offset,
                                                     (sc.raw * 100.f) / (4 * sc.total) + 0.5f,
                                                     ref.class_id, ref.template_id));
            }
}

// Every position of one template on the coarsest level.
static void searchTemplate(const ScenePyramid& scene, const TemplatePyramid& tp,
                           const String& class_id, int id, float threshold,
                           std::vector<cv::linemod::Match>& out)
{
    const LevelMaps& top = scene.coarsest();
    const int L = scene.coarsestIndex();
    const int M = top.modalities();
    const int T = top.T;
    const int offset = matchOffset(T);
    const cv::linemod::Template& t = tp[L * M];
    const int W = top.size.width / T, H = top.size.height / T;
    const int span_x = W - ((t.width - 1) / T + 1);
    const int span_y = H - ((t.height - 1) / T + 1);
    const int nf = numFeatures(tp, L, M);
    const int raw_thr = rawThreshold(threshold, nf);
    for (int r = 0; r <= span_y; ++r)
        for (int c = 0; c <= span_x; ++c)
        {
            const int raw = similarityAll(top, tp, L, Point(c * T, r * T));
            if (raw > raw_thr)
                out.push_back(cv::linemod::Match(c * T + offset, r * T + offset,
                                                 (raw * 100.f) / (4 * nf) + 0.5f, class_id, id));
        }
}

void matchExhaustive(const ScenePyramid& scene, const ClassPyramids& pyramids,
                     const std::vector<String>& classes, float threshold,
                     std::vector<cv::linemod::Match>& matches, MatchCounters& counters)
{
    for (size_t ci = 0; ci < classes.size(); ++ci)
    {
        const std::vector<TemplatePyramid>& tps = pyramids.find(classes[ci])->second;
        std::vector<std::vector<cv::linemod::Match> > per(tps.size());
        parallel_for_(Range(0, (int)tps.size()), [&](const Range& range) {
            for (int id = range.start; id < range.end; ++id)
                searchTemplate(scene, tps[id], classes[ci], id, threshold, per[id]);
        });
        for (size_t id = 0; id < per.size(); ++id)
            matches.insert(matches.end(), per[id].begin(), per[id].end());
    }
    const LevelMaps& top = scene.coarsest();
    counters.locations += (int64)(top.size.width / top.T) * (top.size.height / top.T);
    counters.validated += counters.locations;
}

} // namespace detail
} // namespace forestmod
} // namespace cv
