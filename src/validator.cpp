// This file is part of OpenCV project.
// It is subject to the license terms in the LICENSE file found in the top-level directory
// of this distribution and at http://opencv.org/license.html

// Validation stage (paper: "Fast Breadth-first Leaf Validation"): LINEMOD's similarity, read in
// place from the frame's response maps, and the breadth-first preemptive scheme.

#include "precomp.hpp"
#include "validator.hpp"

namespace cv {
namespace forestmod {
namespace detail {

void validateAll(const LevelMaps& level, int level_index, std::vector<ValidationCandidate>& cands)
{
    for (size_t i = 0; i < cands.size(); ++i)
    {
        ValidationCandidate& c = cands[i];
        c.raw = similarityAll(level, *c.tp, level_index, c.tl, &c.total);
        c.scored = c.total;
    }
}

// Adds chunk k of K of a candidate: the fraction [k/K, (k+1)/K) of every modality's features, so
// that every chunk samples all modalities and the whole object (features are scattered).
static void scoreChunk(const LevelMaps& level, int level_index, int num_modalities,
                       ValidationCandidate& c, int k, int K)
{
    for (int m = 0; m < num_modalities; ++m)
    {
        const cv::linemod::Template& templ = (*c.tp)[level_index * num_modalities + m];
        const int n = static_cast<int>(templ.features.size());
        const int b = static_cast<int>((int64)n * k / K);
        const int e = static_cast<int>((int64)n * (k + 1) / K);
        c.raw += similarityRange(level, m, templ, c.tl, b, e);
        c.scored += e - b;
    }
}

void validateBreadthFirst(const LevelMaps& level, int level_index, int num_modalities,
                          std::vector<ValidationCandidate>& cands, int chunk_size, float alpha,
                          int max_survivors, std::vector<int>& survivors)
{
    CV_Assert(chunk_size > 0 && max_survivors > 0);
    survivors.clear();
    std::vector<int> alive(cands.size());
    for (size_t i = 0; i < cands.size(); ++i)
    {
        ValidationCandidate& c = cands[i];
        alive[i] = static_cast<int>(i);
        c.raw = 0;
        c.scored = 0;
        c.total = numFeatures(*c.tp, level_index, num_modalities);
    }
    std::vector<float> scores, sorted;
    std::vector<int> next;
    for (int k = 0; (int)alive.size() > max_survivors; ++k)
    {
        bool any = false;
        scores.clear();
        for (size_t a = 0; a < alive.size(); ++a)
        {
            ValidationCandidate& c = cands[alive[a]];
            const int K = std::max(1, (c.total + chunk_size - 1) / chunk_size);
            if (k < K)
            {
                any = true;
                scoreChunk(level, level_index, num_modalities, c, k, K);
            }
            scores.push_back(c.scored ? c.raw / (4.f * c.scored) : 0.f);
        }
        if (!any)
            break;
        sorted = scores;
        std::nth_element(sorted.begin(), sorted.begin() + sorted.size() / 2, sorted.end());
        const float median = sorted[sorted.size() / 2];
        next.clear();
        for (size_t a = 0; a < alive.size(); ++a)
            if (scores[a] >= median && scores[a] > alpha)
                next.push_back(alive[a]);
        alive.swap(next);
    }
    // the survivor(s) are scored on all their features
    for (size_t a = 0; a < alive.size(); ++a)
    {
        ValidationCandidate& c = cands[alive[a]];
        if (c.scored < c.total)
            c.raw = similarityAll(level, *c.tp, level_index, c.tl, &c.total);
        c.scored = c.total;
        survivors.push_back(alive[a]);
    }
}

// One location: its candidates scored, the best survivors over the threshold appended to `out`.
static void validateLocation(const ScenePyramid& scene, const LocationCandidates& cands, int i,
                             const SearchIndex& index, const ClassPyramids& pyramids,
                             const DetectorParams& params, float threshold,
                             std::vector<ValidationCandidate>& vc, std::vector<int>& survivors,
                             std::vector<cv::linemod::Match>& out)
{
    const LevelMaps& top = scene.coarsest();
    const int L = scene.coarsestIndex();
    const int M = static_cast<int>(top.response.size());
    const int S = cands.step;
    const Point loc = cands.location[i];
    vc.clear();
    for (int k = cands.begin[i]; k < cands.begin[i + 1]; ++k)
    {
        const TemplateRef& ref = index.rows[cands.rows[k]];
        const TemplatePyramid& tp = pyramids.find(ref.class_id)->second[ref.template_id];
        const cv::linemod::Template& t = tp[L * M];
        ValidationCandidate v;
        v.index = cands.rows[k];
        v.tp = &tp;
        // the true anchor lies within S/2 of the location; spread responses cover [p, p + T):
        // start S/2 before
        v.tl = Point(loc.x * S - t.width / 2 - S / 2, loc.y * S - t.height / 2 - S / 2);
        v.raw = v.scored = v.total = 0;
        vc.push_back(v);
    }
    if (params.breadth_first)
        validateBreadthFirst(top, L, M, vc, params.chunk_size, params.alpha, params.max_survivors,
                             survivors);
    else
    {
        validateAll(top, L, vc);
        survivors.resize(vc.size());
        for (size_t k = 0; k < vc.size(); ++k)
            survivors[k] = (int)k;
    }
    std::sort(survivors.begin(), survivors.end(), [&](int a, int b) {
        return vc[a].raw * (int64)vc[b].total > vc[b].raw * (int64)vc[a].total;
    });
    const int offset = top.T / 2 + (top.T % 2 - 1);
    for (size_t k = 0; k < survivors.size() && (int)k < params.max_survivors; ++k)
    {
        const ValidationCandidate& v = vc[survivors[k]];
        if (v.raw <= rawThreshold(threshold, v.total))
            continue;
        const TemplateRef& ref = index.rows[v.index];
        out.push_back(cv::linemod::Match(v.tl.x + offset, v.tl.y + offset,
                                         (v.raw * 100.f) / (4 * v.total) + 0.5f, ref.class_id,
                                         ref.template_id));
    }
}

void validateLocations(const ScenePyramid& scene, const LocationCandidates& cands,
                       const SearchIndex& index, const ClassPyramids& pyramids,
                       const DetectorParams& params, float threshold,
                       std::vector<cv::linemod::Match>& coarse)
{
    const int n = cands.size();
    // locations in blocks, each block's matches in order: the result does not depend on threads
    const int block = 64;
    const int blocks = (n + block - 1) / block;
    std::vector<std::vector<cv::linemod::Match> > per_block(blocks);
    parallel_for_(Range(0, blocks), [&](const Range& range) {
        std::vector<ValidationCandidate> vc;
        std::vector<int> survivors;
        for (int b = range.start; b < range.end; ++b)
            for (int i = b * block; i < std::min(n, (b + 1) * block); ++i)
                validateLocation(scene, cands, i, index, pyramids, params, threshold, vc,
                                 survivors, per_block[b]);
    });
    coarse.clear();
    for (int b = 0; b < blocks; ++b)
        coarse.insert(coarse.end(), per_block[b].begin(), per_block[b].end());
}

} // namespace detail
} // namespace forestmod
} // namespace cv
