// This file is part of OpenCV project.
// It is subject to the license terms in the LICENSE file found in the top-level directory
// of this distribution and at http://opencv.org/license.html

// Internal: the search index (paper: "Training"): the templates in search groups of similar size,
// each with its descriptor window (a grid over its largest template at the coarsest level), the
// templates' descriptors under that window, and a trained template forest with a background
// rejector in every node. Built by train(), or from a model file's forests by load().

#ifndef OPENCV_FORESTMOD_SEARCH_INDEX_HPP
#define OPENCV_FORESTMOD_SEARCH_INDEX_HPP

#include "template_store.hpp"
#include "depth_range.hpp"
#include "opencv2/forestmod/forest.hpp"

#include <memory>

namespace cv {
namespace forestmod {
namespace detail {

struct TemplateRef
{
    String class_id;
    int template_id;
};

/** A template's feature at the coarsest level, as LINEMOD's linearized memories on that level's
T grid read it: `memory` is (modality x 8 + label) x T^2 + dy x T + dx for the feature's phase
(dx, dy) in its T x T cell, (cx, cy) that cell from the template's top-left cell. In a frame
whose memories are `stride` x `rows` cells, the feature's responses at every position of the
T grid are the run starting at memory x stride x rows + cy x stride + cx
(LinearMemories::index). */
struct CoarseFeature
{
    int memory;
    short cx, cy;
};

/** The start of a feature's run in linearized memories of `stride` x `rows` cells: its
responses at the positions of the T grid from a template's top-left cell (0, 0). */
static inline int64 runOffset(const CoarseFeature& f, int stride, int rows)
{
    return (int64)f.memory * stride * rows + (int64)f.cy * stride + f.cx;
}

/** The number of the linearized memory of a modality, label and phase (dx, dy) in a T x T cell:
memories are stored in this order (LinearMemories::index). */
static inline int linearMemory(int modality, int label, int dx, int dy, int T)
{
    return (modality * 8 + label) * T * T + dy * T + dx;
}

/** Every template's coarsest-level features for the exhaustive search, made once per model
(not per frame, and read without touching the templates): row r's are features[begin[r]] ..
features[begin[r + 1]], its box covers cells[r] cells of the T grid, and its score's
denominator is total[r] features (numFeatures: every modality's, those left out included). */
struct CoarseRuns
{
    std::vector<CoarseFeature> features;
    std::vector<int> begin;
    std::vector<Size> cells;
    std::vector<Point> centre; //!< the cell of its centre, from its position's cell
    std::vector<int> total;

    /** The features as runs of memories of `stride` x `rows` cells: offsets[k] = features[k]'s
    memory x stride x rows + cy x stride + cx (the runs of a template's first row of positions,
    indexed as `features`). */
    struct Offsets
    {
        int stride, rows;
        std::vector<int> offsets;
    };
    /** The offsets for a frame's memories: made at the first frame of a size and kept for the
    next frames of that size (a frame of another size replaces them; a caller keeps its own). */
    std::shared_ptr<const Offsets> offsetsFor(int stride, int rows) const;
    /** Drops the kept offsets (the features changed). */
    void clearOffsets();

    CoarseRuns() {}
    /** A copy of the features; the kept offsets are shared (they never change once made). */
    CoarseRuns(const CoarseRuns& other) { *this = other; }
    CoarseRuns& operator=(const CoarseRuns& other);

private:
    mutable std::shared_ptr<const Offsets> offsets_;
    mutable Mutex offsets_mutex_;
};

/** Appends the features of `tp` at level `level_index` (modality by modality, in the template's
order) that lie in its box (a feature beyond it, which only a hostile model file holds, is left
out) and returns its size in cells of T. */
CV_EXPORTS Size coarseFeatures(const TemplatePyramid& tp, int level_index, int num_modalities,
                               int T, std::vector<CoarseFeature>& features);

/** One search group: templates of similar size sharing a descriptor window and a forest. */
struct SearchGroup
{
    std::vector<String> classes;          //!< the classes of its templates, smallest first
    std::vector<int> rows;                //!< forest row (template id of the forest) -> index row
    std::vector<Point> grid;              //!< descriptor grid offsets from the anchor (coarsest level)
    std::vector<int> plane_of;            //!< per descriptor dimension: its modality
    std::vector<Point> dim_offset;        //!< per descriptor dimension: its grid offset
    int min_labels;                       //!< fewest labelled values of a training descriptor
    DepthSpan depth;                      //!< its templates' depth samples' range (mm)
    Ptr<TemplateForest> forest;

    SearchGroup() : min_labels(0) {}
};

struct SearchIndex
{
    std::vector<TemplateRef> rows;        //!< all templates, class by class
    std::vector<SearchGroup> groups;      //!< windows and forests (DetectorParams::group_size_ratio)
    std::vector<DepthSpan> depth;         //!< [row]: its depth samples' range (mm)
    int max_extent;                       //!< largest template side (level 0 pixels)
    CoarseRuns coarse;                    //!< [row]: its features for the exhaustive search
    bool trained;

    SearchIndex() : max_extent(0), trained(false) {}

    /** Groups, windows, descriptors and forests of the templates (train()). */
    void train(const ClassPyramids& pyramids, const TemplateStore& store,
               const DetectorParams& params, int M, int L, int T);
    /** Groups and windows of the templates with forests read from a model file (load()); raises
    StsParseError naming `filename` when they do not fit the templates. */
    void attach(const ClassPyramids& pyramids, const TemplateStore& store,
                const DetectorParams& params, int M, int L, int T,
                const std::vector<Ptr<TemplateForest> >& forests, const String& filename);
    void clear();
};

/** Stride (coarsest level pixels) of the forest's locations: location_step, or T / 2 when 0. */
static inline int locationStep(const DetectorParams& p, int T)
{
    return p.location_step > 0 ? p.location_step : std::max(1, T / 2);
}

/** Dominant label of each k x k neighbourhood (only where mask, if given, is set): a single-label
image that tolerates a misalignment of about k / 2 pixels, for the forest's descriptors of the
templates and the scene alike (doc/detector.md, "Search"). k <= 1: a copy. */
void dominantLabels(const Mat& quantized, const Mat& mask, int k, Mat& dst);

} // namespace detail
} // namespace forestmod
} // namespace cv

#endif
