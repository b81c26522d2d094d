// This file is part of OpenCV project.
// It is subject to the license terms in the LICENSE file found in the top-level directory
// of this distribution and at http://opencv.org/license.html

// Template forest (paper: "Template Matching in Random Forest Framework", "Split Function for
// Insufficient, High-dimensional Noisy Data"); every node carries a background rejector
// (rejector.cpp). Decisions and their numbers: doc/forest.md.

#include "precomp.hpp"
#include "params_io.hpp"
#include "rejector.hpp"
#include "model_check.hpp"
#include "opencv2/core/hal/intrin.hpp"

#include <cstring>

namespace cv {
namespace forestmod {

using detail::RejectorRef;
using detail::BackgroundRejectorTrainer;

static const int kFormatVersion = 1;
// template ids index per-template tables (leaf counts, candidates): 2^24 templates at most
static const int kMaxTemplateId = 1 << 24;

// ------------------------------------------------------------------------------------------------
// Params and stats

ForestParams::ForestParams()
    : num_trees(3), max_depth(8), min_node_size(8), split_dims(32), pool_size(32),
      fuzzy_margin(1.f), split_coverage(0.5f), rejector_dims(32), rejector_rho(0.f),
      rejector_tau(0.8f), rejector_coverage(0.8f), rejector_noise(0.05f),
      reject_any_tree(false), seed(0)
{
}

void ForestParams::read(const FileNode& fn)
{
    detail::readField(fn, "num_trees", num_trees);
    detail::readField(fn, "max_depth", max_depth);
    detail::readField(fn, "min_node_size", min_node_size);
    detail::readField(fn, "split_dims", split_dims);
    detail::readField(fn, "pool_size", pool_size);
    detail::readField(fn, "fuzzy_margin", fuzzy_margin);
    detail::readField(fn, "split_coverage", split_coverage);
    detail::readField(fn, "rejector_dims", rejector_dims);
    detail::readField(fn, "rejector_rho", rejector_rho);
    detail::readField(fn, "rejector_tau", rejector_tau);
    detail::readField(fn, "rejector_coverage", rejector_coverage);
    detail::readField(fn, "rejector_noise", rejector_noise);
    detail::readField(fn, "reject_any_tree", reject_any_tree);
    detail::readField(fn, "seed", seed);
}

void ForestParams::write(FileStorage& fs) const
{
    fs << "num_trees" << num_trees;
    fs << "max_depth" << max_depth;
    fs << "min_node_size" << min_node_size;
    fs << "split_dims" << split_dims;
    fs << "pool_size" << pool_size;
    fs << "fuzzy_margin" << fuzzy_margin;
    fs << "split_coverage" << split_coverage;
    fs << "rejector_dims" << rejector_dims;
    fs << "rejector_rho" << rejector_rho;
    fs << "rejector_tau" << rejector_tau;
    fs << "rejector_coverage" << rejector_coverage;
    fs << "rejector_noise" << rejector_noise;
    fs << "reject_any_tree" << (int)reject_any_tree;
    fs << "seed" << seed;
}

namespace detail {

void checkForestParams(const ForestParams& p)
{
    CV_CheckGE(p.num_trees, 1, "ForestParams::num_trees must be >= 1");
    CV_CheckGE(p.max_depth, 0, "ForestParams::max_depth must be >= 0");
    CV_CheckLE(p.max_depth, 30, "ForestParams::max_depth must be <= 30");
    CV_CheckGE(p.min_node_size, 1, "ForestParams::min_node_size must be >= 1");
    CV_Check(p.split_dims, p.split_dims >= 1 && p.split_dims <= 4096,
             "ForestParams::split_dims (d') must be in [1, 4096]");
    CV_Check(p.pool_size, p.pool_size >= 1 && p.pool_size <= 65536,
             "ForestParams::pool_size must be in [1, 65536]");
    CV_CheckGE(p.fuzzy_margin, 0.f, "ForestParams::fuzzy_margin (xi) must be >= 0");
    CV_Check(p.rejector_dims, p.rejector_dims >= 0 && p.rejector_dims <= 4096,
             "ForestParams::rejector_dims must be in [0, 4096]");
    CV_Check(p.rejector_rho, p.rejector_rho >= 0.f && p.rejector_rho < 1.f,
             "ForestParams::rejector_rho must be in [0, 1)");
    CV_Check(p.rejector_tau, p.rejector_tau >= 0.f && p.rejector_tau <= 1.f,
             "ForestParams::rejector_tau must be in [0, 1]");
    CV_Check(p.rejector_coverage, p.rejector_coverage >= 0.f && p.rejector_coverage <= 1.f,
             "ForestParams::rejector_coverage must be in [0, 1]");
    CV_Check(p.split_coverage, p.split_coverage >= 0.f && p.split_coverage <= 1.f,
             "ForestParams::split_coverage must be in [0, 1]");
    CV_Check(p.rejector_noise, p.rejector_noise >= 0.f && p.rejector_noise < 1.f,
             "ForestParams::rejector_noise must be in [0, 1)");
}

} // namespace detail

void ForestQueryStats::add(const ForestQueryStats& o)
{
    locations += o.locations;
    rejected += o.rejected;
    nodes_visited += o.nodes_visited;
    candidates += o.candidates;
    if (rejected_at_depth.size() < o.rejected_at_depth.size())
        rejected_at_depth.resize(o.rejected_at_depth.size(), 0);
    for (size_t i = 0; i < o.rejected_at_depth.size(); ++i)
        rejected_at_depth[i] += o.rejected_at_depth[i];
}

// ------------------------------------------------------------------------------------------------
// Input checks and the background model

static void checkDescriptors(const Mat& desc, const Mat& fg, const char* who)
{
    if (desc.empty())
        CV_Error_(Error::StsBadArg, ("%s: the descriptor matrix is empty", who));
    if (desc.type() != CV_8UC1)
        CV_Error_(Error::StsUnsupportedFormat,
                  ("%s: descriptors must be CV_8UC1 (N x D), got %s", who,
                   typeToString(desc.type()).c_str()));
    if (fg.type() != CV_8UC1 || fg.size() != desc.size())
        CV_Error_(Error::StsBadSize,
                  ("%s: foreground must be CV_8UC1 of the descriptors' size %d x %d, got %s %d x %d",
                   who, desc.rows, desc.cols, typeToString(fg.type()).c_str(), fg.rows, fg.cols));
    for (int i = 0; i < desc.rows; ++i)
    {
        const uchar* d = desc.ptr<uchar>(i);
        for (int j = 0; j < desc.cols; ++j)
            if (d[j] & (d[j] - 1))
                CV_Error_(Error::StsBadArg,
                          ("%s: template %d, dimension %d has value 0x%02x: template values must "
                           "be 0 or one label bit (1 << label)", who, i, j, (int)d[j]));
    }
}

static inline uchar codeOf(uchar v)
{
    // 0 -> 0, 1 << l -> l + 1
    static const uchar table[129] = {0, 1, 2, 0, 3, 0, 0, 0, 4, 0, 0, 0, 0, 0, 0, 0, 5, 0, 0, 0,
        0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 6, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0,
        0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 7, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0,
        0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0,
        0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 8};
    return table[v];
}

static inline uint64 mixSeed(uint64 a, uint64 b)
{
    uint64 z = a * 0x9E3779B97F4A7C15ULL + b + 0x632BE59BD9B4E019ULL;
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ULL;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBULL;
    z ^= z >> 31;
    return z ? z : 1;
}

void TemplateForest::applyBackgroundModel(InputArray _desc, InputArray _fg, int seed,
                                          OutputArray _dst)
{
    Mat desc = _desc.getMat(), fg = _fg.getMat();
    checkDescriptors(desc, fg, "TemplateForest::applyBackgroundModel");
    Mat dst = desc.clone();
    for (int i = 0; i < dst.rows; ++i)
    {
        RNG rng(mixSeed((uint64)(int64)seed, (uint64)i + 1));   // one stream per template
        uchar* d = dst.ptr<uchar>(i);
        const uchar* f = fg.ptr<uchar>(i);
        for (int j = 0; j < dst.cols; ++j)
            if (!f[j])
                d[j] = (uchar)(1 << rng.uniform(0, 8));
    }
    dst.copyTo(_dst);
}

bool TemplateForest::query(const uchar* descriptor, std::vector<int>& candidates,
                           int* rejected_depth, ForestQueryStats* stats) const
{
    CV_Assert(descriptor != 0);
    const int D = dims();
    if (D <= 0)
        CV_Error(Error::StsError, "TemplateForest::query: the forest is not trained");
    std::vector<int> delta(D), plane_of(D, 0);
    for (int j = 0; j < D; ++j)
        delta[j] = j;
    const uchar* planes[1] = {descriptor};
    LocationView view;
    view.planes = planes;
    view.plane_of = &plane_of[0];
    view.delta = &delta[0];
    view.offset = 0;
    return query(view, candidates, rejected_depth, stats);
}

Ptr<TemplateForest> TemplateForest::load(const String& filename)
{
    FileStorage fs;
    detail::openModelText(fs, filename, "TemplateForest::load"); // the guards of Detector::load
    FileNode fn = fs.getFirstTopLevelNode();
    Ptr<TemplateForest> forest = create();
    try
    {
        forest->read(fn);
    }
    catch (const cv::Exception& e)
    {
        CV_Error_(Error::StsParseError,
                  ("TemplateForest::load: '%s': %s", filename.c_str(), e.err.c_str()));
    }
    catch (const std::exception& e)
    {
        CV_Error_(Error::StsParseError,
                  ("TemplateForest::load: '%s': %s", filename.c_str(), e.what()));
    }
    return forest;
}

String TemplateForest::getDefaultName() const
{
    return "forestmod.TemplateForest";
}

String TemplateForest::storageKey()
{
    return "forestmod_TemplateForest";
}

void TemplateForest::save(const String& filename) const
{
    FileStorage fs(filename, FileStorage::WRITE);
    if (!fs.isOpened())
        CV_Error_(Error::StsError, ("TemplateForest::save: cannot open '%s' for writing",
                                    filename.c_str()));
    fs << storageKey() << "{";
    write(fs);
    fs << "}";
}

// ------------------------------------------------------------------------------------------------
// Implementation

namespace {

/** One node of a tree, in a flat array (preorder: children after their parent). */
struct Node
{
    int left, right;     // child indices, -1 for a leaf
    int split_begin;     // offset into Tree::split_dims / split_vals (d' entries)
    float tau;           // half-integral threshold on the distance
    int rej_begin;       // offset into Tree::rej_dims / rej_lut
    int rej_count;
    int rej_min;         // min accepted dims (0: rejector off)
    int leaf_begin;      // offset into Tree::leaf_ids
    int leaf_count;
    int depth;
};
const int kNodeFields = 10;

struct Tree
{
    std::vector<Node> nodes;
    std::vector<int> split_dims;
    std::vector<uchar> split_vals;   // exemplar values as bits (0 or 1 << label)
    std::vector<int> rej_dims;
    std::vector<ushort> rej_lut;
    // rej_lut split for the vectorised test: accepted labels, and 255 where the value 0 is accepted
    std::vector<uchar> rej_labels, rej_zero;
    std::vector<int> leaf_ids;
    int lowered;                      // nodes whose rejector threshold was lowered
};

// The look-ups of the vectorised rejector test, from rej_lut (after training and reading).
static void splitLookups(Tree& t)
{
    t.rej_labels.resize(t.rej_lut.size());
    t.rej_zero.resize(t.rej_lut.size());
    for (size_t k = 0; k < t.rej_lut.size(); ++k)
    {
        t.rej_labels[k] = (uchar)(t.rej_lut[k] & 255);
        t.rej_zero[k] = (t.rej_lut[k] >> 8) & 1 ? (uchar)255 : (uchar)0;
    }
}

// The node tests on a gathered descriptor row (the scan's path), vectorised 16 dims at a time:
// the same counts as valuesAgree / rejectorPasses dimension by dimension.
#if CV_SIMD128
// lanes of a comparison mask (0 or 255) that are set
static inline int setLanes(const v_uint8x16& mask)
{
    return (int)v_reduce_sum(mask & v_setall_u8(1));
}
#endif

// Dimensions of `dims` where the row disagrees with the exemplar's values `ev`.
static inline int disagreements(const uchar* values, const int* dims, const uchar* ev, int n)
{
    int agree = 0, k = 0;
#if CV_SIMD128
    const v_uint8x16 z = v_setzero_u8();
    for (; k <= n - 16; k += 16)
    {
        const v_uint8x16 v = v_lut(values, dims + k), e = v_load(ev + k);
        // valuesAgree: e == 0 ? v == 0 : (e & v) != 0; (e & v) is 0 where e is
        agree += setLanes(((e == z) & (v == z)) | ((e & v) != z));
    }
#endif
    for (; k < n; ++k)
        agree += valuesAgree(ev[k], values[dims[k]]);
    return n - agree;
}

// rejectorPasses on a row: 16 dimensions at a time, leaving as soon as the outcome is known.
static inline bool rowPasses(const Tree& t, const Node& nd, const uchar* values)
{
    const int* dims = &t.rej_dims[nd.rej_begin];
    const uchar* labels = &t.rej_labels[nd.rej_begin];
    const uchar* zero = &t.rej_zero[nd.rej_begin];
    const int n = nd.rej_count, need = nd.rej_min;
    int accepted = 0, k = 0;
#if CV_SIMD128
    const v_uint8x16 z = v_setzero_u8();
    for (; k <= n - 16; k += 16)
    {
        const v_uint8x16 v = v_lut(values, dims + k);
        accepted += setLanes(((v & v_load(labels + k)) != z) | ((v == z) & v_load(zero + k)));
        if (accepted >= need)
            return true;
        if (accepted + (n - k - 16) < need)
            return false;
    }
#endif
    for (; k < n; ++k)
    {
        const uchar v = values[dims[k]];
        accepted += v ? (v & labels[k]) != 0 : zero[k] != 0;
    }
    return accepted >= need;
}

struct Candidate
{
    int exemplar;
    std::vector<int> dims;
    uint64 tau_state;
    // results
    double energy;
    float tau;
    bool valid;
};

/** Training context of one tree. */
class TreeBuilder
{
public:
    TreeBuilder(const Mat& codes, const Mat& fg, const std::vector<int>& template_of,
                const ForestParams& p, int dsplit, uint64 seed)
        : codes_(codes), fg_(fg), template_of_(template_of), p_(p), dsplit_(dsplit), rng_(seed)
    {
        rcfg_.dims = p.rejector_dims;
        rcfg_.rho = p.rejector_rho;
        rcfg_.tau = p.rejector_tau;
        rcfg_.coverage = p.rejector_coverage;
        rcfg_.noise = p.rejector_noise;
    }

    void build(Tree& tree)
    {
        tree_ = &tree;
        tree.lowered = 0;
        std::vector<int> all(codes_.rows);
        for (int i = 0; i < codes_.rows; ++i)
            all[i] = i;
        std::vector<uchar> core(all.size(), 1);
        grow(all, core, 0);
    }

private:
    int grow(const std::vector<int>& ids, const std::vector<uchar>& core, int depth)
    {
        Tree& t = *tree_;
        const int index = (int)t.nodes.size();
        Node node;
        node.left = node.right = -1;
        node.split_begin = 0;
        node.tau = 0.f;
        node.leaf_begin = node.leaf_count = 0;
        node.depth = depth;
        node.rej_begin = (int)t.rej_dims.size();
        bool lowered = false;
        node.rej_count = BackgroundRejectorTrainer::train(codes_, fg_, ids, core, rcfg_, t.rej_dims,
                                                          t.rej_lut, node.rej_min, lowered);
        t.lowered += lowered ? 1 : 0;
        t.nodes.push_back(node);

        std::vector<int> left, right;
        std::vector<uchar> lcore, rcore;
        Candidate best;
        if (depth < p_.max_depth && (int)ids.size() >= p_.min_node_size && ids.size() > 1 &&
            findSplit(ids, best))
        {
            partition(ids, core, best, left, right, lcore, rcore);
            t.nodes[index].split_begin = (int)t.split_dims.size();
            t.nodes[index].tau = best.tau;
            const uchar* e = codes_.ptr<uchar>(best.exemplar);
            for (int k = 0; k < dsplit_; ++k)
            {
                t.split_dims.push_back(best.dims[k]);
                const int c = e[best.dims[k]];
                t.split_vals.push_back((uchar)(c ? 1 << (c - 1) : 0));
            }
            const int l = grow(left, lcore, depth + 1);
            t.nodes[index].left = l;
            const int r = grow(right, rcore, depth + 1);
            t.nodes[index].right = r;
        }
        else
        {
            t.nodes[index].leaf_begin = (int)t.leaf_ids.size();
            // the leaf holds templates (sorted, unique), the samples were their descriptors
            std::vector<int> tmpl(ids.size());
            for (size_t i = 0; i < ids.size(); ++i)
                tmpl[i] = template_of_[ids[i]];
            std::sort(tmpl.begin(), tmpl.end());
            tmpl.erase(std::unique(tmpl.begin(), tmpl.end()), tmpl.end());
            t.nodes[index].leaf_count = (int)tmpl.size();
            t.leaf_ids.insert(t.leaf_ids.end(), tmpl.begin(), tmpl.end());
        }
        return index;
    }

    void distances(const std::vector<int>& ids, const Candidate& c, std::vector<int>& dist,
                   int& fg_count) const
    {
        const int n = (int)ids.size();
        dist.resize(n);
        const uchar* e = codes_.ptr<uchar>(c.exemplar);
        uchar ev[64];
        const int* dims = &c.dims[0];
        CV_DbgAssert(dsplit_ <= 64);
        for (int k = 0; k < dsplit_; ++k)
            ev[k] = e[dims[k]];
        fg_count = 0;
        for (int i = 0; i < n; ++i)
        {
            const uchar* v = codes_.ptr<uchar>(ids[i]);
            const uchar* f = fg_.ptr<uchar>(ids[i]);
            int d = 0;
            for (int k = 0; k < dsplit_; ++k)
            {
                d += v[dims[k]] != ev[k];
                fg_count += f[dims[k]] != 0;
            }
            dist[i] = d;
        }
    }

    static double entropy(const int* h, int total)
    {
        if (total <= 0)
            return 0.;
        double e = 0;
        for (int v = 0; v < 9; ++v)
            if (h[v])
            {
                const double p = (double)h[v] / total;
                e -= p * std::log(p);
            }
        return e;
    }

    // Completeness-weighted unsupervised entropy gain of one candidate (paper, energy E).
    void evaluate(const std::vector<int>& ids, Candidate& c) const
    {
        c.valid = false;
        c.energy = 0;
        const int n = (int)ids.size();
        std::vector<int> dist;
        int fg_count = 0;
        distances(ids, c, dist, fg_count);
        int dmin = dsplit_, dmax = 0;
        for (int i = 0; i < n; ++i)
        {
            dmin = std::min(dmin, dist[i]);
            dmax = std::max(dmax, dist[i]);
        }
        if (dmax <= dmin)
            return;
        // tau = k + 0.5 with k the node's median distance to the exemplar or one less (drawn):
        // balanced splits (doc/forest.md: a uniform tau in [dmin, dmax) peels off small groups)
        RNG r(c.tau_state);
        {
            std::vector<int> tmp(dist);
            std::nth_element(tmp.begin(), tmp.begin() + n / 2, tmp.end());
            int k = tmp[n / 2] - r.uniform(0, 2);
            k = std::max(dmin, std::min(k, dmax - 1));
            c.tau = (float)k + 0.5f;
        }
        // per-dimension value histograms (0..8, "no feature" counts as a value) of the parent and
        // of both children, with the fuzzy duplication
        const float xi = p_.fuzzy_margin;
        std::vector<int> hist((size_t)dsplit_ * 27, 0);
        int nl = 0, nr = 0;
        for (int i = 0; i < n; ++i)
        {
            const float h = (float)dist[i] - c.tau;
            const bool goL = h < xi, goR = h > -xi;
            nl += goL;
            nr += goR;
            const uchar* v = codes_.ptr<uchar>(ids[i]);
            for (int k = 0; k < dsplit_; ++k)
            {
                const int x = v[c.dims[k]];
                int* hh = &hist[(size_t)k * 27];
                hh[x]++;
                if (goL) hh[9 + x]++;
                if (goR) hh[18 + x]++;
            }
        }
        if (nl == 0 || nr == 0 || nl >= n || nr >= n)
            return;
        // unsupervised entropy: sum over the d' dims of the entropy of the dim's values
        double H = 0, HL = 0, HR = 0;
        for (int k = 0; k < dsplit_; ++k)
        {
            const int* hh = &hist[(size_t)k * 27];
            H += entropy(hh, n);
            HL += entropy(hh + 9, nl);
            HR += entropy(hh + 18, nr);
        }
        // children weighted by their share of the duplicated set (nl + nr >= n)
        const double gain = H - (nl * HL + nr * HR) / (double)(nl + nr);
        const double lambda = (double)fg_count / ((double)n * dsplit_);   // mean completeness
        c.energy = lambda * gain;
        c.valid = gain > 0;
    }

    bool findSplit(const std::vector<int>& ids, Candidate& best)
    {
        const int n = (int)ids.size();
        const int D = codes_.cols;
        const int P = p_.pool_size;
        // all random draws in sequence (deterministic whatever the thread count)
        std::vector<Candidate> pool(P);
        // split dims are drawn among the dims that at least split_coverage of the node's
        // templates have on their object mask (all dims when there are fewer than d')
        std::vector<int> pool_dims;
        {
            std::vector<int> cover(D, 0);
            for (int i = 0; i < n; ++i)
            {
                const uchar* f = fg_.ptr<uchar>(ids[i]);
                for (int j = 0; j < D; ++j)
                    cover[j] += f[j] != 0;
            }
            for (int j = 0; j < D; ++j)
                if (cover[j] >= p_.split_coverage * n)
                    pool_dims.push_back(j);
            if ((int)pool_dims.size() < dsplit_)
                pool_dims.clear();
        }
        if (pool_dims.empty())
            for (int j = 0; j < D; ++j)
                pool_dims.push_back(j);
        const int PD = (int)pool_dims.size();
        std::vector<int> perm(PD);
        for (int c = 0; c < P; ++c)
        {
            Candidate& cand = pool[c];
            cand.exemplar = ids[rng_.uniform(0, n)];
            for (int j = 0; j < PD; ++j)
                perm[j] = pool_dims[j];
            cand.dims.resize(dsplit_);
            for (int k = 0; k < dsplit_; ++k)   // partial Fisher-Yates: d' distinct dims
            {
                const int s = k + rng_.uniform(0, PD - k);
                std::swap(perm[k], perm[s]);
                cand.dims[k] = perm[k];
            }
            cand.tau_state = mixSeed((uint64)rng_.next(), (uint64)c);
            cand.valid = false;
        }
        const double work = (double)n * P * dsplit_;
        if (work > 2e5)
            parallel_for_(Range(0, P), [&](const Range& r) {
                for (int c = r.start; c < r.end; ++c)
                    evaluate(ids, pool[c]);
            });
        else
            for (int c = 0; c < P; ++c)
                evaluate(ids, pool[c]);
        int bi = -1;
        for (int c = 0; c < P; ++c)
            if (pool[c].valid && (bi < 0 || pool[c].energy > pool[bi].energy))
                bi = c;
        if (bi < 0)
            return false;
        best = pool[bi];
        return true;
    }

    // Fuzzy partition (paper): left if dist - tau < xi, right if dist - tau > -xi. A template is
    // "core" in a child when its own crisp path (dist < tau: left) goes there.
    void partition(const std::vector<int>& ids, const std::vector<uchar>& core, const Candidate& c,
                   std::vector<int>& left, std::vector<int>& right, std::vector<uchar>& lcore,
                   std::vector<uchar>& rcore) const
    {
        std::vector<int> dist;
        int fg_count = 0;
        distances(ids, c, dist, fg_count);
        const float xi = p_.fuzzy_margin;
        for (size_t i = 0; i < ids.size(); ++i)
        {
            const float h = (float)dist[i] - c.tau;
            if (h < xi)
            {
                left.push_back(ids[i]);
                lcore.push_back((uchar)(core[i] && h < 0));
            }
            if (h > -xi)
            {
                right.push_back(ids[i]);
                rcore.push_back((uchar)(core[i] && h > 0));
            }
        }
    }

    const Mat& codes_;
    const Mat& fg_;
    const std::vector<int>& template_of_;
    const ForestParams& p_;
    int dsplit_;
    RNG rng_;
    BackgroundRejectorTrainer::Config rcfg_;
    Tree* tree_;
};

class TemplateForestImpl CV_FINAL : public TemplateForest
{
public:
    explicit TemplateForestImpl(const ForestParams& p) : params_(p), D_(0), N_(0), dsplit_(0)
    {
        detail::checkForestParams(p);
    }

    void train(InputArray _desc, InputArray _fg) CV_OVERRIDE
    {
        train(_desc, _fg, noArray());
    }

    void train(InputArray _desc, InputArray _fg, InputArray _ids) CV_OVERRIDE
    {
        Mat desc = _desc.getMat(), fg = _fg.getMat();
        checkDescriptors(desc, fg, "TemplateForest::train");
        std::vector<int> template_of(desc.rows);
        int N = desc.rows;
        if (_ids.empty())
        {
            for (int i = 0; i < desc.rows; ++i)
                template_of[i] = i;
        }
        else
        {
            Mat ids = _ids.getMat();
            if (ids.type() != CV_32SC1 || ids.total() != (size_t)desc.rows)
                CV_Error_(Error::StsBadArg,
                          ("TemplateForest::train: template_ids must hold one CV_32S id per "
                           "descriptor row (%d), got %s with %d elements", desc.rows,
                           typeToString(ids.type()).c_str(), (int)ids.total()));
            Mat idc = ids.reshape(1, 1).clone();
            N = 0;
            for (int i = 0; i < desc.rows; ++i)
            {
                template_of[i] = idc.at<int>(i);
                if (template_of[i] < 0 || template_of[i] >= kMaxTemplateId)
                    CV_Error_(Error::StsBadArg,
                              ("TemplateForest::train: template_ids[%d] = %d is outside "
                               "[0, %d) (ids index per-template tables)", i, template_of[i],
                               kMaxTemplateId));
                N = std::max(N, template_of[i] + 1);
            }
        }
        Mat noisy;
        applyBackgroundModel(desc, fg, params_.seed, noisy);
        Mat codes(noisy.size(), CV_8U);
        for (int i = 0; i < noisy.rows; ++i)
        {
            const uchar* s = noisy.ptr<uchar>(i);
            uchar* d = codes.ptr<uchar>(i);
            for (int j = 0; j < noisy.cols; ++j)
                d[j] = codeOf(s[j]);
        }
        Mat fgc = fg.isContinuous() ? fg : fg.clone();

        const int dsplit = std::min(std::min(params_.split_dims, desc.cols), 64);
        std::vector<Tree> trees(params_.num_trees);
        // trees in parallel (each has its own random stream: the result does not depend on the
        // schedule); inside a tree, the candidates of big nodes are evaluated in parallel too
        const ForestParams& params = params_;
        parallel_for_(Range(0, params.num_trees), [&](const Range& r) {
            for (int t = r.start; t < r.end; ++t)
            {
                TreeBuilder builder(codes, fgc, template_of, params, dsplit,
                                    mixSeed((uint64)(int64)params.seed, 1000003ULL * (t + 1)));
                builder.build(trees[t]);
            }
        });
        for (size_t t = 0; t < trees.size(); ++t)
            splitLookups(trees[t]);
        trees_.swap(trees);
        D_ = desc.cols;
        N_ = N;
        dsplit_ = dsplit;
    }

    bool query(const LocationView& view, std::vector<int>& candidates, int* rejected_depth,
               ForestQueryStats* stats) const CV_OVERRIDE
    {
        if (trees_.empty())
            CV_Error(Error::StsError, "TemplateForest::query: the forest is not trained");
        candidates.clear();
        int visited = 0, rdepth = -1, accepted_trees = 0;
        const bool any = params_.reject_any_tree;
        const int ntrees = (int)trees_.size();
        for (int ti = 0; ti < ntrees; ++ti)
        {
            int depth = -1;
            const bool rejected = !traverse(trees_[ti], view, candidates, depth, visited);
            if (rejected)
                rdepth = std::max(rdepth, depth);
            if (rejected && any)
            {
                candidates.clear();
                accepted_trees = 0;
                break;
            }
            accepted_trees += rejected ? 0 : 1;
        }
        const bool ok = accepted_trees > 0;
        if (ok && ntrees > 1)
        {
            std::sort(candidates.begin(), candidates.end());
            candidates.erase(std::unique(candidates.begin(), candidates.end()), candidates.end());
        }
        if (rejected_depth)
            *rejected_depth = ok ? -1 : rdepth;
        if (stats)
        {
            stats->locations++;
            stats->nodes_visited += visited;
            if (ok)
                stats->candidates += (int64)candidates.size();
            else
            {
                stats->rejected++;
                if ((int)stats->rejected_at_depth.size() <= rdepth)
                    stats->rejected_at_depth.resize(rdepth + 1, 0);
                stats->rejected_at_depth[rdepth]++;
            }
        }
        return ok;
    }

    bool queryTree(int tree, const LocationView& view, std::vector<int>& candidates,
                   int* rejected_depth) const CV_OVERRIDE
    {
        CV_Check(tree, tree >= 0 && tree < (int)trees_.size(),
                 "TemplateForest::queryTree: tree index out of range");
        candidates.clear();
        int depth = -1, visited = 0;
        const bool ok = traverse(trees_[tree], view, candidates, depth, visited);
        if (rejected_depth)
            *rejected_depth = ok ? -1 : depth;
        return ok;
    }

    bool leaf(int tree, const uchar* values, const int*& ids, int& count, int* rejected_depth,
              bool root_passed, int* nodes) const CV_OVERRIDE
    {
        const Tree& t = trees_[tree];
        int depth = -1, visited = 0;
        const int ni = descend(t, RowTests(values), depth, visited, root_passed);
        if (rejected_depth)
            *rejected_depth = ni < 0 ? depth : -1;
        if (nodes)
            *nodes = visited;
        if (ni < 0)
            return false;
        ids = &t.leaf_ids[t.nodes[ni].leaf_begin];
        count = t.nodes[ni].leaf_count;
        return true;
    }

    bool rootRejector(int tree, std::vector<int>& dims, std::vector<ushort>& accepted,
                      int& min_accept) const CV_OVERRIDE
    {
        CV_Assert(tree >= 0 && tree < (int)trees_.size()
                  && "TemplateForest::rootRejector: tree index out of range");
        dims.clear();
        accepted.clear();
        min_accept = 0;
        const Tree& t = trees_[tree];
        const Node& root = t.nodes[0];
        if (root.rej_min <= 0)
            return false;
        dims.assign(t.rej_dims.begin() + root.rej_begin,
                    t.rej_dims.begin() + root.rej_begin + root.rej_count);
        accepted.assign(t.rej_lut.begin() + root.rej_begin,
                        t.rej_lut.begin() + root.rej_begin + root.rej_count);
        min_accept = root.rej_min;
        return true;
    }

    bool empty() const CV_OVERRIDE { return trees_.empty(); }
    int dims() const CV_OVERRIDE { return D_; }
    int numTemplates() const CV_OVERRIDE { return N_; }
    ForestParams getParams() const CV_OVERRIDE { return params_; }

    void leavesPerTemplate(int tree, std::vector<int>& counts) const CV_OVERRIDE
    {
        CV_Check(tree, tree >= 0 && tree < (int)trees_.size(),
                 "TemplateForest::leavesPerTemplate: tree index out of range");
        counts.assign(N_, 0);
        const std::vector<int>& ids = trees_[tree].leaf_ids;
        for (size_t i = 0; i < ids.size(); ++i)
            counts[ids[i]]++;
    }

    Statistics statistics() const CV_OVERRIDE
    {
        Statistics s;
        s.trees = (int)trees_.size();
        s.nodes = s.leaves = s.max_depth = 0;
        s.mean_leaf_size = s.mean_leaves_per_template = s.lowered_rejectors = 0;
        s.bytes = 0;
        size_t leaf_entries = 0;
        int lowered = 0;
        for (size_t t = 0; t < trees_.size(); ++t)
        {
            const Tree& tr = trees_[t];
            s.nodes += (int)tr.nodes.size();
            for (size_t i = 0; i < tr.nodes.size(); ++i)
                if (tr.nodes[i].left < 0)
                {
                    s.leaves++;
                    s.max_depth = std::max(s.max_depth, tr.nodes[i].depth);
                }
            leaf_entries += tr.leaf_ids.size();
            lowered += tr.lowered;
            s.bytes += tr.nodes.size() * sizeof(Node) + tr.split_dims.size() * sizeof(int) +
                       tr.split_vals.size() + tr.rej_dims.size() * sizeof(int) +
                       tr.rej_lut.size() * sizeof(ushort) + tr.leaf_ids.size() * sizeof(int);
        }
        if (s.leaves)
            s.mean_leaf_size = (double)leaf_entries / s.leaves;
        if (N_ && s.trees)
            s.mean_leaves_per_template = (double)leaf_entries / ((double)N_ * s.trees);
        if (s.nodes)
            s.lowered_rejectors = (double)lowered / s.nodes;
        return s;
    }

    void write(FileStorage& fs) const CV_OVERRIDE
    {
        if (trees_.empty())
            CV_Error(Error::StsError, "TemplateForest::write: the forest is not trained");
        writeFormat(fs);
        fs << "format_version" << kFormatVersion;
        fs << "params" << "{";
        params_.write(fs);
        fs << "}";
        fs << "dims" << D_ << "num_templates" << N_ << "split_dims_used" << dsplit_;
        fs << "trees" << "[";
        for (size_t t = 0; t < trees_.size(); ++t)
        {
            const Tree& tr = trees_[t];
            Mat nodes((int)tr.nodes.size(), kNodeFields, CV_32S);
            for (int i = 0; i < nodes.rows; ++i)
            {
                const Node& n = tr.nodes[i];
                int* r = nodes.ptr<int>(i);
                float tau = n.tau;
                int tau_bits;
                std::memcpy(&tau_bits, &tau, sizeof(int));
                r[0] = n.left; r[1] = n.right; r[2] = n.split_begin; r[3] = tau_bits;
                r[4] = n.rej_begin; r[5] = n.rej_count; r[6] = n.rej_min; r[7] = n.leaf_begin;
                r[8] = n.leaf_count; r[9] = n.depth;
            }
            std::vector<int> lut(tr.rej_lut.begin(), tr.rej_lut.end());
            fs << "{";
            fs << "nodes" << nodes;
            fs << "split_dims" << tr.split_dims;
            fs << "split_vals" << Mat(tr.split_vals, false).reshape(1, 1);
            fs << "rej_dims" << tr.rej_dims;
            fs << "rej_lut" << lut;
            fs << "leaf_ids" << tr.leaf_ids;
            fs << "lowered" << tr.lowered;
            fs << "}";
        }
        fs << "]";
    }

    void read(const FileNode& fn) CV_OVERRIDE
    {
        if (fn.empty() || !fn.isMap())
            CV_Error(Error::StsParseError, "TemplateForest::read: the node is empty or not a map");
        if (fn["format_version"].empty())
            CV_Error(Error::StsParseError,
                     "TemplateForest::read: no 'format_version': not a TemplateForest file");
        const int version = (int)fn["format_version"];
        if (version != kFormatVersion)
            CV_Error_(Error::StsParseError,
                      ("TemplateForest::read: format_version %d is not supported (this build "
                       "reads version %d)", version, kFormatVersion));
        ForestParams p;
        if (fn["params"].empty())
            CV_Error(Error::StsParseError, "TemplateForest::read: 'params' missing");
        p.read(fn["params"]);
        detail::checkForestParams(p);
        const FileNode fd = fn["dims"], fnn = fn["num_templates"], fds = fn["split_dims_used"],
                       ft = fn["trees"];
        if (fd.empty() || fnn.empty() || fds.empty() || ft.empty() || !ft.isSeq())
            CV_Error(Error::StsParseError, "TemplateForest::read: 'dims', 'num_templates', "
                                           "'split_dims_used' or 'trees' missing (truncated?)");
        const int D = (int)fd, N = (int)fnn, ds = (int)fds;
        if (D <= 0 || N <= 0 || ds <= 0 || ds > std::min(D, 64))
            CV_Error_(Error::StsParseError,
                      ("TemplateForest::read: inconsistent sizes dims=%d num_templates=%d "
                       "split_dims_used=%d", D, N, ds));
        if ((int)ft.size() != p.num_trees)
            CV_Error_(Error::StsParseError,
                      ("TemplateForest::read: %d trees stored, params say %d (truncated?)",
                       (int)ft.size(), p.num_trees));
        std::vector<Tree> trees(p.num_trees);
        for (int t = 0; t < p.num_trees; ++t)
        {
            readTree(ft[t], t, D, N, ds, trees[t]);
            splitLookups(trees[t]);
        }
        params_ = p;
        trees_.swap(trees);
        D_ = D;
        N_ = N;
        dsplit_ = ds;
    }

private:
    /** One tree: appends the leaf's templates and returns true, or returns false with the depth
    of the rejecting node. No allocation. */
    bool traverse(const Tree& t, const LocationView& view, std::vector<int>& candidates,
                  int& rejected_depth, int& visited) const
    {
        const int ni = descend(t, ViewTests(view), rejected_depth, visited);
        if (ni < 0)
            return false;
        const int* ids = &t.leaf_ids[t.nodes[ni].leaf_begin];
        candidates.insert(candidates.end(), ids, ids + t.nodes[ni].leaf_count);
        return true;
    }

    /** The node tests on a LocationView, dimension by dimension. */
    struct ViewTests
    {
        const LocationView& view;
        explicit ViewTests(const LocationView& v) : view(v) {}
        bool passes(const Tree& t, const Node& nd) const
        {
            RejectorRef r;
            r.dims = &t.rej_dims[nd.rej_begin];
            r.lut = &t.rej_lut[nd.rej_begin];
            r.count = nd.rej_count;
            r.min_accept = nd.rej_min;
            return detail::rejectorPasses(r, view);
        }
        int distance(const Tree& t, const Node& nd, int n) const
        {
            const int* dims = &t.split_dims[nd.split_begin];
            const uchar* ev = &t.split_vals[nd.split_begin];
            int d = 0;
            for (int k = 0; k < n; ++k)
                d += !valuesAgree(ev[k], view.value(dims[k]));
            return d;
        }
    };
    /** The node tests on a gathered row, 16 dimensions at a time (the scan's path). */
    struct RowTests
    {
        const uchar* values;
        explicit RowTests(const uchar* v) : values(v) {}
        bool passes(const Tree& t, const Node& nd) const { return rowPasses(t, nd, values); }
        int distance(const Tree& t, const Node& nd, int n) const
        {
            return disagreements(values, &t.split_dims[nd.split_begin],
                                 &t.split_vals[nd.split_begin], n);
        }
    };

    /** One tree down to its leaf: the leaf's node index, or -1 with the depth of the rejecting
    node. `root_passed`: the root's rejector is known to pass. */
    template <class Tests>
    int descend(const Tree& t, const Tests& tests, int& rejected_depth, int& visited,
                bool root_passed = false) const
    {
        const Node* nodes = &t.nodes[0];
        int ni = 0;
        for (;;)
        {
            const Node& nd = nodes[ni];
            ++visited;
            if (nd.rej_min > 0 && !(ni == 0 && root_passed) && !tests.passes(t, nd))
            {
                rejected_depth = nd.depth;
                return -1;
            }
            if (nd.left < 0)
                return ni;
            ni = (float)tests.distance(t, nd, dsplit_) < nd.tau ? nd.left : nd.right;
        }
    }

    static void corrupt(int t, const char* what)
    {
        CV_Error_(Error::StsParseError, ("TemplateForest::read: tree %d: %s (corrupt file)", t,
                                         what));
    }

    static void readTree(const FileNode& fn, int t, int D, int N, int ds, Tree& tr)
    {
        if (fn.empty() || !fn.isMap())
            corrupt(t, "not a map");
        Mat nodes;
        // issue 18 (model_check): the data must hold what rows x cols announce
        detail::readMat(fn["nodes"], nodes, INT_MAX, "forest tree nodes");
        std::vector<int> lut;
        Mat vals;
        fn["split_dims"] >> tr.split_dims;
        detail::readMat(fn["split_vals"], vals, INT_MAX, "forest tree split_vals");
        fn["rej_dims"] >> tr.rej_dims;
        fn["rej_lut"] >> lut;
        fn["leaf_ids"] >> tr.leaf_ids;
        tr.lowered = fn["lowered"].empty() ? 0 : (int)fn["lowered"];
        if (nodes.empty() || nodes.type() != CV_32S || nodes.cols != kNodeFields)
            corrupt(t, "'nodes' missing or of the wrong shape");
        if (!vals.empty() && vals.type() != CV_8U)
            corrupt(t, "'split_vals' is not 8-bit");
        tr.split_vals.assign(vals.datastart, vals.dataend);
        if (tr.split_vals.size() != tr.split_dims.size() || tr.rej_dims.size() != lut.size())
            corrupt(t, "array sizes disagree");
        tr.rej_lut.resize(lut.size());
        for (size_t i = 0; i < lut.size(); ++i)
        {
            if (lut[i] < 0 || lut[i] > 511)
                corrupt(t, "rejector look-up value out of range");
            tr.rej_lut[i] = (ushort)lut[i];
        }
        for (size_t i = 0; i < tr.split_dims.size(); ++i)
            if (tr.split_dims[i] < 0 || tr.split_dims[i] >= D)
                corrupt(t, "split dimension out of range");
        for (size_t i = 0; i < tr.split_vals.size(); ++i)
            if (tr.split_vals[i] & (tr.split_vals[i] - 1))
                corrupt(t, "exemplar value with more than one label bit");
        for (size_t i = 0; i < tr.rej_dims.size(); ++i)
            if (tr.rej_dims[i] < 0 || tr.rej_dims[i] >= D)
                corrupt(t, "rejector dimension out of range");
        for (size_t i = 0; i < tr.leaf_ids.size(); ++i)
            if (tr.leaf_ids[i] < 0 || tr.leaf_ids[i] >= N)
                corrupt(t, "leaf template id out of range");
        const int n = nodes.rows;
        tr.nodes.resize(n);
        for (int i = 0; i < n; ++i)
        {
            const int* r = nodes.ptr<int>(i);
            Node& nd = tr.nodes[i];
            nd.left = r[0]; nd.right = r[1]; nd.split_begin = r[2];
            std::memcpy(&nd.tau, &r[3], sizeof(float));
            nd.rej_begin = r[4]; nd.rej_count = r[5]; nd.rej_min = r[6]; nd.leaf_begin = r[7];
            nd.leaf_count = r[8]; nd.depth = r[9];
            if (nd.depth < 0 || nd.depth > 30)
                corrupt(t, "node depth out of range");
            if (nd.rej_count < 0 || nd.rej_begin < 0 ||
                (size_t)nd.rej_begin + nd.rej_count > tr.rej_dims.size() || nd.rej_min < 0 ||
                nd.rej_min > nd.rej_count)
                corrupt(t, "rejector range out of bounds");
            if (nd.left < 0)
            {
                if (nd.right >= 0 || nd.leaf_count <= 0 || nd.leaf_begin < 0 ||
                    (size_t)nd.leaf_begin + nd.leaf_count > tr.leaf_ids.size())
                    corrupt(t, "leaf range out of bounds");
            }
            else
            {
                // preorder: children come after their parent, so there are no cycles
                if (nd.left <= i || nd.right <= i || nd.left >= n || nd.right >= n)
                    corrupt(t, "child index out of range");
                if (nd.split_begin < 0 || (size_t)nd.split_begin + ds > tr.split_dims.size())
                    corrupt(t, "split range out of bounds");
                if (!(nd.tau > 0.f && nd.tau < (float)ds))
                    corrupt(t, "split threshold out of range");
            }
        }
        for (int i = 0; i < n; ++i)
            if (tr.nodes[i].left >= 0 && (tr.nodes[tr.nodes[i].left].depth != tr.nodes[i].depth + 1 ||
                                          tr.nodes[tr.nodes[i].right].depth != tr.nodes[i].depth + 1))
                corrupt(t, "child depth inconsistent");
        if (tr.nodes[0].depth != 0)
            corrupt(t, "root depth is not 0");
    }

    ForestParams params_;
    std::vector<Tree> trees_;
    int D_, N_, dsplit_;
};

} // namespace

Ptr<TemplateForest> TemplateForest::create(const ForestParams& params)
{
    return makePtr<TemplateForestImpl>(params);
}

} // namespace forestmod
} // namespace cv
