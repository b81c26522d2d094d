// This file is part of OpenCV project.
// It is subject to the license terms in the LICENSE file found in the top-level directory
// of this distribution and at http://opencv.org/license.html

// Pyramid refinement (LINEMOD): each coarse match up the pyramid, by a local search on every
// finer level.

#include "precomp.hpp"
#include "refine.hpp"
#include "linear_memories.hpp"

#include <climits>
#include <unordered_map>

namespace cv {
namespace forestmod {
namespace detail {

// The best position of a template in the 16 x 16 cells of T pixels around (x, y) of level l; the
// raw score and the feature count at that position.
// With the level's linearized memories (`linear`, may be null) the 256 scores are vectorised
// (linear_memories.hpp, bestLocal), else read in place.
static Point bestPosition(const LevelMaps& lm, const TemplatePyramid& tp, int l, int x, int y,
                          int& best, int& num_features, const LinearMemories* linear)
{
    const int T = lm.T;
    int best_r = -1, best_c = -1;
    best = 0;
    num_features = 0;
    const int ox = (x / T - 8) * T, oy = (y / T - 8) * T;
    int index = -1;
    if (linear && bestLocal(*linear, tp, l, lm.modalities(), ox, oy, best, index, num_features))
    {
        if (index >= 0)
        {
            best_r = index / 16;
            best_c = index % 16;
        }
    }
    else
        for (int r = 0; r < 16; ++r)
            for (int c = 0; c < 16; ++c)
            {
                const int s = similarityAll(lm, tp, l, Point(ox + c * T, oy + r * T),
                                            &num_features);
                if (s > best)
                {
                    best = s;
                    best_r = r;
                    best_c = c;
                }
            }
    const int offset = matchOffset(T);
    return Point((x / T - 8 + best_c) * T + offset, (y / T - 8 + best_r) * T + offset);
}

// One match up the pyramid; false when it falls under the threshold at some level. `depth`:
// one context per level (null: no depth term), with the template's depth samples `dt`.
static bool refineOne(const std::vector<LevelMaps>& levels, const TemplatePyramid& tp,
                      float threshold, const DepthContext* depth, const DepthTemplate& dt,
                      cv::linemod::Match& m, const LinearMemories* linear = 0)
{
    const int M = levels[0].modalities();
    const int samples = depth && dt.samples ? (int)dt.samples->size() : 0;
    for (int l = static_cast<int>(levels.size()) - 2; l >= 0; --l)
    {
        const LevelMaps& lm = levels[l];
        const int border = 8 * lm.T;
        const int max_x = lm.size.width - tp[l * M].width - border;
        const int max_y = lm.size.height - tp[l * M].height - border;
        const int x = std::min(std::max(m.x * 2 + 1, border), max_x);
        const int y = std::min(std::max(m.y * 2 + 1, border), max_y);
        int best = 0, num_features = 0;
        const Point p = bestPosition(lm, tp, l, x, y, best, num_features,
                                     linear ? &linear[l] : 0);
        m.x = p.x;
        m.y = p.y;
        const int ns = depthSamplesAtLevel(samples, num_features, M);
        if (ns > 0)
        {
            best += depthSimilarity(depth[l], dt, Point(m.x << l, m.y << l), ns);
            num_features += ns;
        }
        m.similarity = num_features ? (best * 100.f) / (4 * num_features) : 0.f;
        if (m.similarity < threshold)
            return false;
    }
    return true;
}

// A template's feature offsets at one level: smallest and largest x (in .x, .y of lo / hi).
// One coordinate of one level of refineOne, for every coarser-level coordinate in [lo, hi]:
// the first and last pixel bestPosition reads (features at [f_lo, f_hi] from each of the 16
// positions), and the range of the coordinate it returns (one cell before the first position
// when nothing scores). Each step of refineOne is monotonic in the coordinate.
static void refineSpan(int lo, int hi, int border, int max_v, int T, int f_lo, int f_hi,
                       int& read_first, int& read_last, int& next_lo, int& next_hi)
{
    const int a = std::min(std::max(lo * 2 + 1, border), max_v);
    const int b = std::min(std::max(hi * 2 + 1, border), max_v);
    const int oa = (a / T - 8) * T, ob = (b / T - 8) * T;
    const int offset = matchOffset(T);
    read_first = oa + f_lo;
    read_last = ob + 15 * T + f_hi;
    next_lo = oa - T + offset;
    next_hi = ob + 15 * T + offset;
}

namespace {
// A coarse match's template pyramid and record.
struct MatchRefs
{
    const TemplatePyramid* tp;
    const TemplateRecord* record;
};

// The part of a template's record that a loop over the coarse matches reads.
enum RecordPart
{
    NO_RECORD,
    FEATURE_EXTENT,
    DEPTH_SAMPLES
};

// The templates and records of the coarse matches of `range`, looked up ahead of a loop that
// reads them in order (at(k), k ascending) and asked of the cache: a model's templates and
// records lie scattered over the heap, and a model of many templates misses the cache at every
// match. A match's pyramid and the record's `part` are asked for kAhead matches before it is
// read, what they point to kAhead / 2 before (the pyramid's templates, the part's data), and the
// first lines of the features of the first `refined_templates` templates (the refinement
// levels') kAhead / 4 before.
class MatchesAhead
{
public:
    MatchesAhead(const std::vector<cv::linemod::Match>& matches, const Range& range,
                 const ClassPyramids& pyramids, const TemplateStore& store, int refined_templates,
                 RecordPart part)
        : matches_(matches), end_(range.end), pyramids_(pyramids), store_(store),
          refined_(refined_templates), part_(part), last_(0), templates_(0), records_(0)
    {
        for (int j = range.start; j < std::min(end_, range.start + kAhead); ++j)
            look(j);
        for (int j = range.start; j < std::min(end_, range.start + kAhead / 2); ++j)
            pointed(j);
        for (int j = range.start; j < std::min(end_, range.start + kAhead / 4); ++j)
            featuresOf(j);
    }
    const MatchRefs& at(int k)
    {
        if (k + kAhead < end_)
            look(k + kAhead);
        if (k + kAhead / 2 < end_)
            pointed(k + kAhead / 2);
        if (k + kAhead / 4 < end_)
            featuresOf(k + kAhead / 4);
        return ring_[k % kRing];
    }

private:
    enum { kAhead = 16, kRing = 2 * kAhead };
    void look(int j)
    {
        const cv::linemod::Match& m = matches_[j];
        if (!last_ || *last_ != m.class_id)
        {
            templates_ = &pyramids_.find(m.class_id)->second;
            records_ = store_.classRecords(m.class_id);
            CV_Assert(records_ && records_->size() == templates_->size());
            last_ = &m.class_id;
        }
        CV_DbgAssert(m.template_id >= 0 && m.template_id < (int)templates_->size());
        MatchRefs& r = ring_[j % kRing];
        r.tp = &(*templates_)[m.template_id];
        r.record = &(*records_)[m.template_id];
        prefetchLine(r.tp);
        if (part_ == FEATURE_EXTENT)
            prefetchLine(&r.record->feature_extent);
        else if (part_ == DEPTH_SAMPLES)
            prefetchLine(&r.record->depth);
    }
    void pointed(int j)
    {
        const MatchRefs& r = ring_[j % kRing];
        prefetchLine(r.tp->data());
        if (part_ == FEATURE_EXTENT)
            prefetchLine(r.record->feature_extent.data());
        else if (part_ == DEPTH_SAMPLES)
            prefetchLine(r.record->depth.data());
    }
    void featuresOf(int j)
    {
        const TemplatePyramid& tp = *ring_[j % kRing].tp;
        for (int i = 0; i < refined_ && i < (int)tp.size(); ++i)
        {
            const char* f = reinterpret_cast<const char*>(tp[i].features.data());
            prefetchLine(f);
            prefetchLine(f + 64);
        }
    }

    const std::vector<cv::linemod::Match>& matches_;
    const int end_;
    const ClassPyramids& pyramids_;
    const TemplateStore& store_;
    const int refined_;
    const RecordPart part_;
    const std::string* last_;
    const std::vector<TemplatePyramid>* templates_;
    const std::vector<TemplateRecord>* records_;
    MatchRefs ring_[kRing];
};
} // namespace

void refinementRegions(const ScenePyramid& scene, const ClassPyramids& pyramids,
                       const TemplateStore& store,
                       const std::vector<cv::linemod::Match>& matches,
                       std::vector<std::vector<Rect> >& regions)
{
    const int L = scene.coarsestIndex();
    const int M = scene.coarsest().modalities();
    regions.assign(L, std::vector<Rect>(matches.size()));
    parallel_for_(Range(0, (int)matches.size()), [&](const Range& range) {
        MatchesAhead ahead(matches, range, pyramids, store, 0, FEATURE_EXTENT);
        for (int k = range.start; k < range.end; ++k)
        {
            const cv::linemod::Match& m = matches[k];
            const MatchRefs& refs = ahead.at(k);
            const TemplatePyramid& tp = *refs.tp;
            // the feature extents of each level: lo at [2 l], hi at [2 l + 1]
            const std::vector<Point>& ext = refs.record->feature_extent;
            CV_Assert((int)ext.size() >= 2 * L);
            int x_lo = m.x, x_hi = m.x, y_lo = m.y, y_hi = m.y;
            for (int l = L - 1; l >= 0; --l)
            {
                const LevelMaps& lm = scene.levels[l];
                const int border = 8 * lm.T;
                int x0, x1, y0, y1;
                refineSpan(x_lo, x_hi, border, lm.size.width - tp[l * M].width - border, lm.T,
                           ext[2 * l].x, ext[2 * l + 1].x, x0, x1, x_lo, x_hi);
                refineSpan(y_lo, y_hi, border, lm.size.height - tp[l * M].height - border,
                           lm.T, ext[2 * l].y, ext[2 * l + 1].y, y0, y1, y_lo, y_hi);
                regions[l][k] = Rect(x0, y0, x1 - x0 + 1, y1 - y0 + 1);
            }
        }
    });
}

void refineMatches(const ScenePyramid& scene, const ClassPyramids& pyramids,
                   const TemplateStore& store, float threshold,
                   std::vector<cv::linemod::Match>& matches)
{
    const bool use_depth = !scene.depth_ctx.empty();
    std::vector<uchar> keep(matches.size(), 0);
    // LINEMOD's linearized memories of the refinement levels (vectorised local search), level by
    // level, each built in parallel over its cell rows (a parallel loop over the levels would
    // make that one nested, and OpenCV runs nested loops serially)
    std::vector<LinearMemories> linear(scene.levels.size());
    if (!matches.empty())
        for (size_t l = 0; l + 1 < scene.levels.size(); ++l)
            linear[l].build(scene.levels[l], scene.tiles[l],
                            Size(ScenePyramid::TILE_W, ScenePyramid::TILE_H));
    const int refined_templates = (int)(scene.levels.size() - 1) * scene.coarsest().modalities();
    parallel_for_(Range(0, (int)matches.size()), [&](const Range& range) {
        MatchesAhead ahead(matches, range, pyramids, store, refined_templates,
                           use_depth ? DEPTH_SAMPLES : NO_RECORD);
        for (int k = range.start; k < range.end; ++k)
        {
            cv::linemod::Match& m = matches[k];
            const MatchRefs& refs = ahead.at(k);
            const TemplatePyramid& tp = *refs.tp;
            const DepthTemplate dt = use_depth ? depthTemplate(*refs.record) : DepthTemplate();
            keep[k] = refineOne(scene.levels, tp, threshold,
                                dt.samples ? &scene.depth_ctx[0] : 0, dt, m, &linear[0]);
        }
    });
    size_t n = 0;
    for (size_t k = 0; k < matches.size(); ++k)
        if (keep[k])
            matches[n++] = matches[k];
    matches.resize(n);
}

} // namespace detail
} // namespace forestmod
} // namespace cv
