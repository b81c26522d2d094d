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

#include <map>

namespace cv {
namespace forestmod {
namespace detail {

namespace {
// Share of background values taken to be 0 ("no feature") when a rejector accepts 0: only the
// choice of the rejector's prefix reads it (labels count 1 / 9 each, as a uniform value would).
const double kZeroBackground = 0.5;

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

// Value histogram of every dimension over the node's templates, on the object mask only: labels
// 1..8, and with `absence` also 0 ("no feature": evidence of absence, doc/forest.md, "Evidence of
// absence"); the dimensions covered by at least `coverage` of them, lowest entropy first.
static std::vector<DimScore> rankDimensions(const Mat& codes, const Mat& fg,
                                            const std::vector<int>& ids, float coverage,
                                            bool absence, std::vector<int>& hist,
                                            std::vector<int>& cover)
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
            if (f[j] && (c[j] || absence))
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
        for (int v = 0; v < 9; ++v)
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
static std::vector<int> labelAllowance(int maxK, float noise)
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

// Noise allowance: a template with a1 accepted labels and a0 accepted zeros keeps passing with
// probability >= 1 - eps when each label is corrupted with probability q1 and each zero with
// probability q0 (a real view shows texture, shading or noise where the rendering has none):
// allow[a1 * (maxK + 2) + a0] failures, a1 + a0 <= maxK + 1.
static std::vector<int> noiseAllowance(int maxK, float noise, float zero_noise)
{
    const int W = maxK + 2;
    std::vector<int> allow((size_t)W * W, 0);
    const double eps = 1e-3;
    // binomial pmfs of the failures of a dims corrupted with probability q, a = 0..maxK + 1
    std::vector<std::vector<double> > pmf[2];
    const double qs[2] = {std::min(0.99, std::max(0.0, (double)noise)),
                          std::min(0.99, std::max(0.0, (double)zero_noise))};
    for (int k = 0; k < 2; ++k)
    {
        pmf[k].resize(W);
        for (int a = 0; a < W; ++a)
        {
            std::vector<double>& P = pmf[k][a];
            P.assign(a + 1, 0.0);
            P[0] = 1.0;
            for (int s = 0; s < a; ++s) // add one dim
                for (int f = s + 1; f >= 0; --f)
                    P[f] = (f <= s ? P[f] * (1 - qs[k]) : 0.0) + (f ? P[f - 1] * qs[k] : 0.0);
        }
    }
    for (int a1 = 0; a1 < W; ++a1)
        for (int a0 = 1; a1 + a0 < W; ++a0)
        {
            // smallest f with P(F1 + F0 > f) <= eps
            std::vector<double> conv(a1 + a0 + 1, 0.0);
            for (int f1 = 0; f1 <= a1; ++f1)
                for (int f0 = 0; f0 <= a0; ++f0)
                    conv[f1 + f0] += pmf[0][a1][f1] * pmf[1][a0][f0];
            double cdf = 0;
            int f = 0;
            for (; f <= a1 + a0; ++f)
            {
                cdf += conv[f];
                if (1 - cdf <= eps)
                    break;
            }
            allow[(size_t)a1 * W + a0] = std::min(f, a1 + a0);
        }
    const std::vector<int> labels_only = labelAllowance(maxK, noise); // the same, without zeros
    for (int a1 = 0; a1 < W; ++a1)
        allow[(size_t)a1 * W] = labels_only[a1];
    return allow;
}

// The allowance table of a configuration, computed once (it costs O(maxK^4) with zeros) and shared
// by the nodes of every tree (trees train in parallel).
static std::vector<int> cachedAllowance(int maxK, float noise, float zero_noise)
{
    static Mutex mutex;
    static std::map<std::pair<int, std::pair<float, float> >, std::vector<int> > cache;
    AutoLock lock(mutex);
    const std::pair<int, std::pair<float, float> > key(maxK, std::make_pair(noise, zero_noise));
    std::map<std::pair<int, std::pair<float, float> >, std::vector<int> >::iterator it
        = cache.find(key);
    if (it == cache.end())
    {
        if (cache.size() > 64) // parameter sweeps: keep the cache bounded
            cache.clear();
        it = cache.insert(std::make_pair(key, noiseAllowance(maxK, noise, zero_noise))).first;
    }
    return it->second;
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
    const bool absence = cfg.zero_noise > 0.f;
    const std::vector<DimScore> scores = rankDimensions(codes, fg, ids, cfg.coverage, absence,
                                                        hist, cover);
    const int maxK = std::min(cfg.dims, (int)scores.size());
    const int W = maxK + 2;
    const std::vector<int> allow = cachedAllowance(maxK, cfg.noise, cfg.zero_noise);

    // Lowest entropy first, every prefix of the ranking is a candidate rejector; keep the prefix
    // that separates background best, measured as the z-score of its threshold against the
    // number of dims a random background value accepts (p_j = |labels of LUT_j| / 9, plus
    // kZeroBackground when the LUT accepts 0). The threshold of a prefix is the largest that
    // keeps every template of the node accepted with its noise allowance (and at most
    // ceil(tau_r * K)).
    std::vector<int> acc(n, 0), acc0(n, 0);
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
        if (h[0] > 0 && (double)h[0] > cfg.rho * cover[j]) // only counted with `absence`
            lut |= codeBit(0);
        dims_out.push_back(j);
        lut_out.push_back(lut);
        int need = k + 1;
        for (int i = 0; i < n; ++i)
        {
            const uchar c = codes.ptr<uchar>(ids[i])[j];
            const bool ok = (lut & codeBit(c)) != 0;
            acc[i] += ok && c != 0;
            acc0[i] += ok && c == 0;
            if (core[i])
                need = std::min(need, acc[i] + acc0[i] - allow[(size_t)acc[i] * W + acc0[i]]);
        }
        need = std::min(need, (int)std::ceil(cfg.tau * (k + 1) - 1e-6));
        const double p = labels / 9.0 + ((lut & codeBit(0)) ? kZeroBackground : 0.0);
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
