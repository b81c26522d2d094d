// This file is part of OpenCV project.
// It is subject to the license terms in the LICENSE file found in the top-level directory
// of this distribution and at http://opencv.org/license.html

// The background similarity of matches: each template scored at every position of the coarsest
// level, the similarity it reaches at a quantile of the positions.

#include "precomp.hpp"
#include "background.hpp"
#include "exhaustive_search.hpp"
#include "linear_memories.hpp"
#include "similarity.hpp"

#include <algorithm>
#include <map>

namespace cv {
namespace forestmod {
namespace detail {

// The raw score at `quantile` of the positions (c <= span_x, r <= span_y) of a scoreEverywhere
// map of row stride `stride`, by a histogram of the raw scores (at most 4 per feature).
static int quantileScore(const std::vector<ushort>& scores, int stride, int span_x, int span_y,
                         int max_raw, double quantile, std::vector<int>& hist)
{
    hist.assign(max_raw + 1, 0);
    for (int r = 0; r <= span_y; ++r)
    {
        const ushort* row = &scores[(size_t)r * stride];
        for (int c = 0; c <= span_x; ++c)
            ++hist[std::min<int>(row[c], max_raw)];
    }
    const int64 n = (int64)(span_x + 1) * (span_y + 1);
    // the smallest score that at least quantile x n positions do not exceed
    const int64 rank = std::max<int64>(1, (int64)std::ceil(quantile * (double)n));
    int64 seen = 0;
    for (int s = 0; s <= max_raw; ++s)
    {
        seen += hist[s];
        if (seen >= rank)
            return s;
    }
    return max_raw;
}

void backgroundSimilarity(const ScenePyramid& scene, const ClassPyramids& pyramids,
                          const std::vector<cv::linemod::Match>& matches, double quantile,
                          std::vector<float>& background)
{
    CV_Assert(quantile > 0 && quantile <= 1);
    background.assign(matches.size(), 0.f);
    if (matches.empty())
        return;
    // the distinct templates of the matches
    std::map<std::pair<String, int>, int> index;
    std::vector<const TemplatePyramid*> templates;
    std::vector<int> slot(matches.size());
    for (size_t i = 0; i < matches.size(); ++i)
    {
        const cv::linemod::Match& m = matches[i];
        const std::pair<String, int> key(m.class_id, m.template_id);
        std::map<std::pair<String, int>, int>::iterator it = index.find(key);
        if (it == index.end())
        {
            ClassPyramids::const_iterator c = pyramids.find(m.class_id);
            if (c == pyramids.end() || m.template_id < 0
                || m.template_id >= (int)c->second.size())
                CV_Error_(Error::StsBadArg, ("backgroundSimilarity: no template %d of class "
                                             "'%s'", m.template_id, m.class_id.c_str()));
            it = index.insert(std::make_pair(key, (int)templates.size())).first;
            templates.push_back(&c->second[m.template_id]);
        }
        slot[i] = it->second;
    }
    const LevelMaps& top = scene.coarsest();
    const int L = scene.coarsestIndex();
    const int M = top.modalities();
    LinearMemories lm;
    lm.build(top);
    std::vector<float> per(templates.size(), 0.f);
    parallel_for_(Range(0, (int)templates.size()), [&](const Range& range) {
        std::vector<ushort> scores;
        std::vector<int> hist;
        for (int t = range.start; t < range.end; ++t)
        {
            const TemplatePyramid& tp = *templates[t];
            const int nf = numFeatures(tp, L, M);
            int span_x = 0, span_y = 0;
            if (nf == 0 || !scoreEverywhere(lm, tp, L, M, span_x, span_y, scores))
                continue;
            const int raw = quantileScore(scores, lm.stride, span_x, span_y, 4 * nf, quantile,
                                          hist);
            per[t] = (raw * 100.f) / (4 * nf) + 0.5f; // as LINEMOD rounds Match::similarity
        }
    });
    for (size_t i = 0; i < matches.size(); ++i)
        background[i] = per[slot[i]];
}

// The matches sorted (stably) by similarity - weight x background[i], best first.
template <typename M, typename Background>
static void sortByDistinctiveness(std::vector<M>& matches, Background background, double weight)
{
    std::vector<std::pair<float, int> > key(matches.size());
    for (size_t i = 0; i < matches.size(); ++i)
        key[i] = std::make_pair(-(float)(matches[i].similarity - weight * background(i)), (int)i);
    std::stable_sort(key.begin(), key.end());
    std::vector<M> sorted;
    sorted.reserve(matches.size());
    for (size_t i = 0; i < key.size(); ++i)
        sorted.push_back(matches[key[i].second]);
    matches.swap(sorted);
}

void orderByDistinctiveness(std::vector<cv::linemod::Match>& matches,
                            const std::vector<float>& background, double weight)
{
    CV_Assert(background.size() == matches.size());
    sortByDistinctiveness(matches, [&](size_t i) { return (double)background[i]; }, weight);
}

} // namespace detail

void orderByBackground(std::vector<PoseMatch>& matches, double weight)
{
    if (!(weight >= 0 && weight < 1e6))
        CV_Error_(Error::StsOutOfRange, ("orderByBackground: weight must be finite and >= 0, got "
                                         "%g", weight));
    for (size_t i = 0; i < matches.size(); ++i)
        if (matches[i].background < 0)
            CV_Error_(Error::StsBadArg, ("orderByBackground: match %d has no background "
                                         "(Detector::backgroundSimilarity)", (int)i));
    detail::sortByDistinctiveness(matches, [&](size_t i) { return matches[i].background; },
                                  weight);
}

} // namespace forestmod
} // namespace cv
