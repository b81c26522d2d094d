// This file is part of OpenCV project.
// It is subject to the license terms in the LICENSE file found in the top-level directory
// of this distribution and at http://opencv.org/license.html

// Preemptive background rejector (paper: "Preemptive Background Rejector").
//
// The rejector of a node needs no negative samples: it keeps dimensions where the node's
// templates agree most (lowest entropy of their on-mask labels), and for each a look-up table of
// the labels whose frequency is above rho. A location with too few accepted values cannot be one
// of the node's templates and leaves the forest. Off-mask (noise) values never define a table and
// 0 ("no feature") is never accepted. The threshold is the largest that keeps every template whose
// own crisp path passes the node accepted even with a share `noise` of its values corrupted
// (probability 0.999), at most ceil(tau_r * K); of the prefixes of the entropy ranking the one that
// separates uniform background best is kept. Decisions and numbers: doc/forest.md.

#include "precomp.hpp"
#include "rejector.hpp"

namespace cv {
namespace forestmod {
namespace detail {

namespace {
struct DimScore
{
    float entropy;
    int coverage;
    int dim;
    bool operator<(const DimScore& o) const
    {
        if (entropy != o.entropy)
            return entropy < o.entropy;
        if (coverage != o.coverage)
            return coverage > o.coverage;
        return dim < o.dim;
    }
};
} // namespace

// Label histogram (1..8; "no feature" is not a label: never in a table, doc/forest.md) of every
// dimension over the node's templates, on the object mask only; the dimensions covered by at
// least `coverage` of them, lowest entropy first.
static std::vector<DimScore> rankDimensions(const Mat& codes, const Mat& fg,
                                            const std::vector<int>& ids, float coverage,
                                            std::vector<int>& hist, std::vector<int>& cover)
{
    const int n = (int)ids.size();
    const int D = codes.cols;
    hist.assign((size_t)D * 9, 0);
    cover.assign(D, 0);
    for (int i = 0; i < n; ++i)
    {
        const uchar* c = codes.ptr<uchar>(ids[i]);
        const uchar* f = fg.ptr<uchar>(ids[i]);
        for (int j = 0; j < D; ++j)
            if (f[j] && c[j])
            {
                hist[(size_t)j * 9 + c[j]]++;
                cover[j]++;
            }
    }
    const int min_cover = std::max(1, (int)std::ceil(coverage * n - 1e-6));
    std::vector<DimScore> scores;
    scores.reserve(D);
    for (int j = 0; j < D; ++j)
    {
        if (cover[j] < min_cover)
            continue;
        const int* h = &hist[(size_t)j * 9];
        double e = 0;
        for (int v = 1; v < 9; ++v)
            if (h[v])
            {
                const double p = (double)h[v] / cover[j];
                e -= p * std::log(p);
            }
        DimScore s;
        s.entropy = (float)e;
        s.coverage = cover[j];
        s.dim = j;
        scores.push_back(s);
    }
    std::sort(scores.begin(), scores.end());
    return scores;
}

// Noise allowance: a template with a accepted dims keeps passing with probability >= 1 - eps when
// each of its values is corrupted with probability q: allow[a] failures, a = 1..maxK + 1.
static std::vector<int> noiseAllowance(int maxK, float noise)
{
    std::vector<int> allow(maxK + 2, 0);
    const double q = std::min(0.99, std::max(0.0, (double)noise)), eps = 1e-3;
    for (int a = 1; a <= maxK + 1; ++a)
    {
        // smallest f with P(Binomial(a, q) > f) <= eps
        double pk = std::pow(1 - q, a), cdf = pk;
        int f = 0;
        while (1 - cdf > eps && f < a)
        {
            pk *= (double)(a - f) / (f + 1) * (q / std::max(1e-12, 1 - q));
            ++f;
            cdf += pk;
        }
        allow[a] = f;
    }
    return allow;
}

int BackgroundRejectorTrainer::train(const Mat& codes, const Mat& fg, const std::vector<int>& ids,
                                     const std::vector<uchar>& core, const Config& cfg,
                                     std::vector<int>& dims_out, std::vector<ushort>& lut_out,
                                     int& min_accept, bool& lowered)
{
    min_accept = 0;
    lowered = false;
    const int n = (int)ids.size();
    if (cfg.dims <= 0 || n == 0)
        return 0;
    std::vector<int> hist, cover;
    const std::vector<DimScore> scores = rankDimensions(codes, fg, ids, cfg.coverage, hist, cover);
    const int maxK = std::min(cfg.dims, (int)scores.size());
    const std::vector<int> allow = noiseAllowance(maxK, cfg.noise);

    // Lowest entropy first, every prefix of the ranking is a candidate rejector; keep the prefix
    // that separates background best, measured as the z-score of its threshold against the
    // number of dims a uniformly random value accepts (p_j = |LUT_j| / 9). The threshold of a
    // prefix is the largest that keeps every template of the node accepted with its noise
    // allowance (and at most ceil(tau_r * K)).
    std::vector<int> acc(n, 0);
    const size_t base = dims_out.size();
    int best_k = 0, best_need = 0;
    double mean_bg = 0, var_bg = 0, best_z = 0;
    for (int k = 0; k < maxK; ++k)
    {
        const int j = scores[k].dim;
        const int* h = &hist[(size_t)j * 9];
        ushort lut = 0;
        int labels = 0;
        for (int v = 1; v < 9; ++v)
            if (h[v] > 0 && (double)h[v] > cfg.rho * cover[j])
            {
                lut |= codeBit(v);
                ++labels;
            }
        dims_out.push_back(j);
        lut_out.push_back(lut);
        int need = k + 1;
        for (int i = 0; i < n; ++i)
        {
            const uchar c = codes.ptr<uchar>(ids[i])[j];
            const int a = (acc[i] += (lut & codeBit(c)) != 0);
            if (core[i])
                need = std::min(need, a - allow[a]);
        }
        need = std::min(need, (int)std::ceil(cfg.tau * (k + 1) - 1e-6));
        const double p = labels / 9.0;
        mean_bg += p;
        var_bg += p * (1 - p);
        const double z = (need - 0.5 - mean_bg) / std::sqrt(std::max(var_bg, 1e-6));
        if (need > 0 && z > best_z)
        {
            best_z = z;
            best_k = k + 1;
            best_need = need;
        }
    }
    dims_out.resize(base + best_k);
    lut_out.resize(base + best_k);
    if (best_k == 0)
        return 0;
    lowered = best_need < (int)std::ceil(cfg.tau * best_k - 1e-6);
    min_accept = best_need;
    return best_k;
}

} // namespace detail
} // namespace forestmod
} // namespace cv
