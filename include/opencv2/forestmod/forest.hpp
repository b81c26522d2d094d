// This file is part of OpenCV project.
// It is subject to the license terms in the LICENSE file found in the top-level directory
// of this distribution and at http://opencv.org/license.html

#ifndef OPENCV_FORESTMOD_FOREST_HPP
#define OPENCV_FORESTMOD_FOREST_HPP

#include "opencv2/core.hpp"

#include <vector>

namespace cv {
namespace forestmod {

//! @addtogroup forestmod_forest
//! @{

/** @brief True when a template (exemplar) value @p e and a query value @p s agree.

Descriptor values are one uchar per dimension: 0 = no significant feature, otherwise a bit set of
quantized labels (`1 << label`, label 0..7, as in cv::linemod quantized images). Template values
carry at most one bit (the paper's value x in 1..8 is label + 1); query values may come from
spread quantized images and carry several bits. Two template values agree iff they are equal.
*/
static inline bool valuesAgree(uchar e, uchar s)
{
    return e == 0 ? s == 0 : (e & s) != 0;
}

/** @brief Reads the D descriptor values of one query location in place, without copying.

`value(j) = planes[plane_of[j]][offset + delta[j]]`. For a plain descriptor row: one plane = the
row pointer, `delta[j] = j`, `plane_of[j] = 0`, `offset = 0`. The Detector builds it from the
scene's spread quantized images and the window geometry (a grid of points x modalities).
*/
struct CV_EXPORTS LocationView
{
    const uchar* const* planes;
    const int* plane_of;
    const int* delta;
    ptrdiff_t offset;
    uchar value(int j) const { return planes[plane_of[j]][offset + delta[j]]; }
};

/** @brief Parameters of TemplateForest. FileStorage keys are the field names.

The numbers that decided the defaults are in doc/forest.md (synthetic template sets, command
given there).
*/
struct CV_EXPORTS_W_SIMPLE ForestParams
{
    CV_WRAP ForestParams();

    /** Number of trees. Default 3: on the synthetic benchmark of doc/forest.md one tree finds a
    template with 10 % corrupted values in 82 % of the queries, three trees (leaves concatenated
    and de-duplicated, as in the paper) in 98 %, for about twice the candidates. The paper reports
    1 and 5 trees. Trees differ by their random draws (seed + tree index). */
    CV_PROP_RW int num_trees;
    /** Maximum depth of a leaf (root = 0). Default 8, the paper's value for one object; the paper
    uses 9 for several objects (the Detector sets it). */
    CV_PROP_RW int max_depth;
    /** A node with fewer templates than this becomes a leaf. Default 8: the paper's leaves hold
    "tens, at most a hundred" templates; smaller sets are validated faster than traversed. */
    CV_PROP_RW int min_node_size;
    /** d': dimensions per exemplar split test (paper: d' > 2 for heavily quantized, noisy
    features). Default 32 (of D = 128 in the benchmark), measured (doc/forest.md); at most 4096. */
    CV_PROP_RW int split_dims;
    /** |Theta|: number of random split candidates (exemplar, dims, tau) per node, the paper's
    small random pool. Default 32, measured (doc/forest.md); at most 65536. */
    CV_PROP_RW int pool_size;
    /** xi: fuzzy margin in units of the distance (number of disagreeing dims). tau is
    half-integral, so a template goes to both children when |distance - tau| < xi: xi = 1
    duplicates the templates at distance tau +- 0.5, xi = 2 those at tau +- 0.5 and tau +- 1.5.
    Default 1, measured (doc/forest.md). 0 = crisp split. */
    CV_PROP_RW float fuzzy_margin;
    /** Split dims are drawn among the dims that at least this share of the node's templates
    have on their object mask (all dims when fewer than d' qualify): off-mask values are noise.
    Default 0.5, measured (doc/forest.md). */
    CV_PROP_RW float split_coverage;
    /** Maximum number of dimensions tested by the background rejector of a node (the rejector
    keeps the prefix of its lowest-entropy dims that separates background best). Default 32.
    0 disables the rejectors; at most 4096. */
    CV_PROP_RW int rejector_dims;
    /** rho: a label is in a rejector dimension's look-up table when its frequency among the
    node's foreground templates is above rho. Default 0 (every label a foreground template has
    there): measured (doc/forest.md), 0.05 rejects about as much and loses more templates. */
    CV_PROP_RW float rejector_rho;
    /** tau_r: a location is rejected at a node when the share of its values accepted by the
    look-up tables is below tau_r. Default 0.8. A node lowers its own threshold so that each
    template whose own (crisp) path passes the node is still accepted with rejector_noise of its
    values corrupted (with probability 0.999): self-recall is guaranteed. */
    CV_PROP_RW float rejector_tau;
    /** A dimension may be a rejector dimension of a node only when at least this share of the
    node's templates has a label (not 0) there on the object mask; off-mask values are noise and
    never define a look-up table. Default 0.8, measured (doc/forest.md). */
    CV_PROP_RW float rejector_coverage;
    /** Share of a template's values that may be corrupted (occlusion, clutter, noise) while
    its own rejectors still accept it with probability 0.999 per node. Default 0.05, measured
    (doc/forest.md): 0.1 keeps more templates and rejects less background. */
    CV_PROP_RW float rejector_noise;
    /** With several trees: true = a location is rejected when any tree rejects it (the paper:
    "enters validation only if it passes all the rejectors"); false = only when every tree
    rejects it (candidates come from the trees that accept it). Default false, measured
    (doc/forest.md): with 3 trees, "any" loses a third of the recall that the extra trees bring. */
    CV_PROP_RW bool reject_any_tree;
    /** Seed of all random draws (background noise of off-mask values, split candidates). Same
    seed and data give a bit-identical forest whatever the number of threads. Default 0. */
    CV_PROP_RW int seed;

    void read(const FileNode& fn);
    void write(FileStorage& fs) const;
};

/** @brief Counters of TemplateForest::query, accumulated over queries (+=). */
struct CV_EXPORTS_W_SIMPLE ForestQueryStats
{
    CV_WRAP ForestQueryStats() { reset(); }

    CV_PROP_RW int64 locations;        //!< queries
    CV_PROP_RW int64 rejected;         //!< queries rejected by a background rejector
    std::vector<int64> rejected_at_depth;  //!< rejected queries by depth (root = 0)
    CV_PROP_RW int64 nodes_visited;    //!< nodes visited, summed over trees
    CV_PROP_RW int64 candidates;       //!< candidates returned (after de-duplication)

    void reset()
    {
        locations = rejected = nodes_visited = candidates = 0;
        rejected_at_depth.clear();
    }
    /** Share of rejected queries (0 when there was none). */
    double rejectionRate() const { return locations ? double(rejected) / double(locations) : 0.; }
    /** Accumulates another set of counters (e.g. of another thread). */
    void add(const ForestQueryStats& other);
};

/** @brief Random forest over template descriptors with fuzzy exemplar splits and a preemptive
background rejector in every node (Shao, Tang, Kim @cite shao2016forest, sections "Template
Matching in Random Forest Framework", "Split Function for Insufficient, High-dimensional Noisy
Data", "Preemptive Background Rejector").

Each split node compares d' dimensions of a query with those of an exemplar template; the
distance is the number of disagreeing dimensions (see valuesAgree()). A query goes left (near)
when distance < tau, right otherwise. In training a template goes left when distance - tau < xi
and right when distance - tau > -xi, so templates near the boundary reach both children (fuzzy
split). The split is the best of a small random pool by completeness-weighted unsupervised
entropy gain. Each node also holds a rejector: a few dimensions where the node's templates agree,
and for each a look-up table of frequent values; a query whose share of accepted values is under
tau_r leaves the forest at that node. See doc/forest.md for every decision and its numbers.
*/
class CV_EXPORTS_W TemplateForest : public Algorithm
{
public:
    /** @brief Size and shape of a trained forest. */
    struct CV_EXPORTS Statistics
    {
        int trees;                        //!< number of trees
        int nodes;                        //!< nodes of all trees (split nodes + leaves)
        int leaves;                       //!< leaves of all trees
        int max_depth;                    //!< deepest leaf (root = 0)
        double mean_leaf_size;            //!< templates per leaf, mean over leaves
        double mean_leaves_per_template;  //!< leaves a template lands in, per tree, mean
        double lowered_rejectors;         //!< share of nodes whose threshold is below tau_r
                                          //!< (kept low for their templates' guarantee)
        size_t bytes;                     //!< memory of the node arrays
    };

    CV_WRAP static Ptr<TemplateForest> create(const ForestParams& params = ForestParams());

    /** @brief Trains the forest (replaces a previous one).

    @param descriptors N x D CV_8U, one template per row; values 0 or `1 << label` (at most one
    bit). Templates are identified by their row index 0..N-1.
    @param foreground N x D CV_8U, nonzero where the grid point lies on the template's object
    mask. Off-mask values are replaced by uniform random labels (the paper's background model,
    see applyBackgroundModel()); completeness (lambda) discounts them.
    */
    virtual void train(InputArray descriptors, InputArray foreground) = 0;

    /** @brief Trains with several descriptors (samples) per template.

    Row i of @p descriptors / @p foreground is a sample of template `template_ids[i]` (CV_32S,
    one per row, >= 0; numTemplates() = max id + 1). Leaves hold template ids, de-duplicated.
    Use it to add jittered samples of each template (e.g. its descriptor read at grid positions
    shifted by a pixel or two): the forest then routes misaligned windows to the template too
    (doc/forest.md, "Misaligned windows"). An empty @p template_ids means row i = template i.
    */
    virtual void train(InputArray descriptors, InputArray foreground,
                       InputArray template_ids) = 0;

    /** @brief Traverses all trees for one location.

    @return true with the sorted, de-duplicated candidate templates of the leaves reached; false
    when a background rejector sends the location out (then *rejected_depth, if given, is the depth
    of the rejecting node, root = 0; with reject_any_tree = false, the deepest one over the trees).
    Thread-safe (const); @p stats may be null.
    */
    virtual bool query(const LocationView& view, std::vector<int>& candidates,
                       int* rejected_depth = 0, ForestQueryStats* stats = 0) const = 0;
    /** @brief Traverses one tree only (diagnostics, tests): the leaf's templates in
    @p candidates (in leaf order), or false when a rejector of this tree sends the location out. */
    virtual bool queryTree(int tree, const LocationView& view, std::vector<int>& candidates,
                           int* rejected_depth = 0) const = 0;
    /** @brief Traverses one tree without copying (the scan's fast path, node tests vectorised):
    @p values are the location's dims() descriptor values in one row (gathered once per location,
    shared by the trees); @p ids and @p count receive the reached leaf's templates (ascending,
    valid while the forest is unchanged), or false when a rejector of this tree sends the location
    out. @p root_passed: the caller has tested rootRejector() on this location already (it
    passed). @p nodes, if given, receives the nodes visited (1 + the depth of the leaf reached or
    of the rejecting node: the descent's cost, which the scan's sample counts). No check of
    @p tree: 0 <= tree < getParams().num_trees is the caller's. */
    virtual bool leaf(int tree, const uchar* values, const int*& ids, int& count,
                      int* rejected_depth = 0, bool root_passed = false,
                      int* nodes = 0) const = 0;
    /** @brief The background rejector of tree @p tree's root, which every location meets first
    (the scan tests it on a whole row of locations at once, vectorised): its dimensions, for each
    the accepted values (bits 0..7: labels, bit 8: the value 0) and the minimum number of accepted
    dimensions. Returns false (and leaves the outputs empty) when the root has no rejector. */
    virtual bool rootRejector(int tree, std::vector<int>& dims, std::vector<ushort>& accepted,
                              int& min_accept) const = 0;
    /** @overload Convenience for one descriptor row of dims() values. */
    bool query(const uchar* descriptor, std::vector<int>& candidates, int* rejected_depth = 0,
               ForestQueryStats* stats = 0) const;

    /** @brief True when untrained. */
    CV_WRAP virtual bool empty() const CV_OVERRIDE = 0;
    /** @brief D, the descriptor length (0 when untrained). */
    CV_WRAP virtual int dims() const = 0;
    /** @brief N, the number of training templates (0 when untrained). */
    CV_WRAP virtual int numTemplates() const = 0;
    CV_WRAP virtual ForestParams getParams() const = 0;
    virtual Statistics statistics() const = 0;
    /** @brief The number of leaves of tree @p tree that hold each template (size N). */
    virtual void leavesPerTemplate(int tree, std::vector<int>& counts) const = 0;

    /** @brief The descriptors as train() sees them: off-mask values replaced by uniform random
    labels `1 << u`, u in 0..7, drawn from @p seed (deterministic). Querying a training
    template with its row of this matrix reaches a leaf that holds it in every tree. */
    static void applyBackgroundModel(InputArray descriptors, InputArray foreground, int seed,
                                     OutputArray dst);

    /** @brief Reads a forest written by save() / write(). Throws cv::Exception naming the file
    when it cannot be opened or parsed (truncated, corrupt) or has another format_version. */
    CV_WRAP static Ptr<TemplateForest> load(const String& filename);

    /** @brief "forestmod.TemplateForest". */
    virtual String getDefaultName() const CV_OVERRIDE;

    /** @brief Writes the forest to a file (YAML/XML/JSON, optionally .gz) under the top-level key
    storageKey(). (Algorithm::save would use getDefaultName(), whose '.' FileStorage refuses in a
    key.) Read it back with load() or Algorithm::load<TemplateForest>(). */
    CV_WRAP virtual void save(const String& filename) const CV_OVERRIDE;

    /** @brief "forestmod_TemplateForest": the top-level FileStorage key used by save(). */
    static String storageKey();
};

//! @}

} // namespace forestmod
} // namespace cv

#endif // OPENCV_FORESTMOD_FOREST_HPP
