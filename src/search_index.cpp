// This file is part of OpenCV project.
// It is subject to the license terms in the LICENSE file found in the top-level directory
// of this distribution and at http://opencv.org/license.html

// The search index (paper: "Training"): search groups, their descriptor windows, the templates'
// descriptors (with shifted samples) and the template forests.

#include "precomp.hpp"
#include "search_index.hpp"

#include <climits>

namespace cv {
namespace forestmod {
namespace detail {

using linemod::Template;

void dominantLabels(const Mat& quantized, const Mat& mask, int k, Mat& dst)
{
    if (k <= 1)
    {
        dst = quantized.clone();
        return;
    }
    Mat best_count = Mat::zeros(quantized.size(), CV_32S);
    dst = Mat::zeros(quantized.size(), CV_8U);
    Mat ind, cnt;
    for (int b = 0; b < 8; ++b)
    {
        const uchar bit = (uchar)(1 << b);
        ind = Mat::zeros(quantized.size(), CV_8U);
        ind.setTo(1, (quantized & bit) != 0);
        if (!mask.empty())
            ind.setTo(0, mask == 0);
        boxFilter(ind, cnt, CV_32S, Size(k, k), Point(-1, -1), false, BORDER_CONSTANT);
        for (int y = 0; y < cnt.rows; ++y)
        {
            const int* c = cnt.ptr<int>(y);
            int* bc = best_count.ptr<int>(y);
            uchar* d = dst.ptr<uchar>(y);
            for (int x = 0; x < cnt.cols; ++x)
                if (c[x] > bc[x])
                {
                    bc[x] = c[x];
                    d[x] = bit;
                }
        }
    }
}

// Descriptor of a template made of features only (addSyntheticTemplate): a grid point takes the
// label of a feature within half a grid step, and is foreground when it does.
static void featureDescriptor(const TemplatePyramid& tp, int M, int L,
                              const std::vector<Point>& grid, int grid_step, Point anchor,
                              uchar* desc, uchar* fg)
{
    const int G = static_cast<int>(grid.size());
    const int r2 = std::max(1, (grid_step * grid_step) / 4);
    for (int m = 0; m < M; ++m)
    {
        const Template& t = tp[L * M + m];
        for (int g = 0; g < G; ++g)
        {
            const Point p = anchor + grid[g];
            const int j = m * G + g;
            desc[j] = 0;
            fg[j] = 0;
            int best = INT_MAX;
            for (size_t k = 0; k < t.features.size(); ++k)
            {
                const int dx = t.features[k].x - p.x, dy = t.features[k].y - p.y;
                const int d2 = dx * dx + dy * dy;
                if (d2 <= r2 && d2 < best)
                {
                    best = d2;
                    desc[j] = static_cast<uchar>(1 << t.features[k].label);
                    fg[j] = 1;
                }
            }
        }
    }
}

// Descriptor of one template under the window geometry (paper: v_T = {Psi(O, r)}): its quantized
// value (dominant labels of its dense patch) at every grid point and modality; foreground where
// the grid point is on its mask.
static void templateDescriptor(const TemplatePyramid& tp, const DensePatch& patch, int M, int L,
                               const std::vector<Point>& grid, int grid_step, Point shift,
                               uchar* desc, uchar* fg)
{
    const Template& top = tp[L * M];
    const Point anchor = Point(top.width / 2, top.height / 2) + shift;
    if (patch.mask.empty())
    {
        featureDescriptor(tp, M, L, grid, grid_step, anchor, desc, fg);
        return;
    }
    const int G = static_cast<int>(grid.size());
    for (int m = 0; m < M; ++m)
        for (int g = 0; g < G; ++g)
        {
            const Point p = anchor + grid[g];
            const int j = m * G + g;
            desc[j] = 0;
            fg[j] = 0;
            if (p.x >= 0 && p.y >= 0 && p.x < patch.mask.cols && p.y < patch.mask.rows
                && patch.mask.at<uchar>(p))
            {
                desc[j] = patch.quantized[m].at<uchar>(p);
                fg[j] = 1;
            }
        }
}

namespace {
// What the search groups are made of: whole classes, or (group_templates) every template on its
// own, so that the views of one class at different distances get windows of their own.
struct Unit
{
    int extent;     //!< largest side at the coarsest level + 1
    String class_id;
    int row;        //!< first index row of the unit
    int n;          //!< rows of the unit
    bool operator<(const Unit& b) const
    {
        if (extent != b.extent)
            return extent < b.extent;
        if (class_id != b.class_id)
            return class_id < b.class_id;
        return row < b.row;
    }
};
} // namespace

// The index rows (every template, class by class) and the units to group, smallest first.
static std::vector<Unit> groupUnits(SearchIndex& index, const ClassPyramids& pyramids, int M,
                                    int L, bool group_templates)
{
    index.rows.clear();
    index.max_extent = 0;
    std::vector<Unit> units;
    for (ClassPyramids::const_iterator it = pyramids.begin(); it != pyramids.end(); ++it)
    {
        if (it->second.empty())
            continue;
        const int first = (int)index.rows.size();
        int extent = 1;
        for (size_t i = 0; i < it->second.size(); ++i)
        {
            const Template& top = it->second[i][L * M];
            const Template& t0 = it->second[i][0];
            const int e = std::max(top.width, top.height) + 1;
            extent = std::max(extent, e);
            index.max_extent = std::max(index.max_extent, std::max(t0.width, t0.height));
            TemplateRef ref = { it->first, static_cast<int>(i) };
            index.rows.push_back(ref);
            if (group_templates)
            {
                Unit u = { e, it->first, first + (int)i, 1 };
                units.push_back(u);
            }
        }
        if (!group_templates)
        {
            Unit u = { extent, it->first, first, (int)it->second.size() };
            units.push_back(u);
        }
    }
    std::sort(units.begin(), units.end());
    return units;
}

// The search groups (DetectorParams::group_size_ratio): units sorted by size, grouped greedily; a
// group takes the next unit while its size is at most the ratio times the group's smallest.
static void buildGroups(SearchIndex& index, const ClassPyramids& pyramids, int M, int L,
                        const DetectorParams& params)
{
    const std::vector<Unit> units = groupUnits(index, pyramids, M, L, params.group_templates);
    const float ratio = params.group_size_ratio;
    index.groups.clear();
    int group_extent = 0;
    for (size_t k = 0; k < units.size(); ++k)
    {
        const Unit& u = units[k];
        const bool fits = !index.groups.empty()
            && (ratio <= 0.f || u.extent <= ratio * group_extent);
        if (!fits)
        {
            index.groups.push_back(SearchGroup());
            group_extent = u.extent;
        }
        SearchGroup& g = index.groups.back();
        if (std::find(g.classes.begin(), g.classes.end(), u.class_id) == g.classes.end())
            g.classes.push_back(u.class_id);
        for (int i = 0; i < u.n; ++i)
            g.rows.push_back(u.row + i);
    }
}

static const TemplatePyramid& pyramidOf(const ClassPyramids& pyramids, const TemplateRef& ref)
{
    return pyramids.find(ref.class_id)->second[ref.template_id];
}

// The descriptor geometry of a group (paper: the sample locations r of the templates): a
// grid_size x grid_size grid over the group's largest template at the coarsest level, for every
// modality. Returns the grid step (pixels).
static double buildGeometry(const SearchIndex& index, SearchGroup& group,
                            const ClassPyramids& pyramids, int M, int L, int grid_size)
{
    int half = 1;
    for (size_t r = 0; r < group.rows.size(); ++r)
    {
        const Template& top = pyramidOf(pyramids, index.rows[group.rows[r]])[L * M];
        half = std::max(half, (std::max(top.width, top.height) + 1) / 2);
    }
    const int G = grid_size;
    const double step = 2.0 * half / G;
    group.grid.clear();
    for (int gy = 0; gy < G; ++gy)
        for (int gx = 0; gx < G; ++gx)
            group.grid.push_back(Point(cvFloor(-half + (gx + 0.5) * step),
                                       cvFloor(-half + (gy + 0.5) * step)));
    const int P = static_cast<int>(group.grid.size());
    group.plane_of.resize(M * P);
    group.dim_offset.resize(M * P);
    for (int m = 0; m < M; ++m)
        for (int g = 0; g < P; ++g)
        {
            group.plane_of[m * P + g] = m;
            group.dim_offset[m * P + g] = group.grid[g];
        }
    return step;
}

// Each template also as seen from locations up to half the location step off its anchor (the
// scene is queried every location_step pixels): doc/forest.md, "Misaligned windows"; in strides
// of dominant_window - 1: the dominant labels absorb the pixel in between (doc/detector.md: 9
// instead of 25 samples per template, fewer candidates, more rejection).
static std::vector<Point> trainingShifts(const DetectorParams& params, int T)
{
    const int a = locationStep(params, T) / 2;
    const int sstride = std::max(1, params.dominant_window - 1);
    std::vector<Point> shifts;
    for (int dy = -a; dy <= a; dy += sstride)
        for (int dx = -a; dx <= a; dx += sstride)
            shifts.push_back(Point(dx, dy));
    return shifts;
}

// A group's training descriptors (one row per template and shift), and its flat-window limit: the
// fewest labelled values any of them has.
static void groupDescriptors(const SearchIndex& index, SearchGroup& group,
                             const ClassPyramids& pyramids, const TemplateStore& store,
                             const DetectorParams& params, int M, int L, int T, Mat& desc,
                             Mat& fg, Mat& ids)
{
    const double step = buildGeometry(index, group, pyramids, M, L, params.grid_size);
    const std::vector<Point> shifts = trainingShifts(params, T);
    const int R = static_cast<int>(shifts.size());
    const int D = M * static_cast<int>(group.grid.size());
    const int N = (int)group.rows.size();
    desc.create(N * R, D, CV_8U);
    fg.create(N * R, D, CV_8U);
    ids.create(N * R, 1, CV_32S);
    for (int r = 0; r < N; ++r)
    {
        const TemplateRef& ref = index.rows[group.rows[r]];
        const DensePatch& raw = store.get(ref.class_id, ref.template_id).patch;
        DensePatch patch; // the descriptor reads the dominant labels, as the scene's windows do
        if (!raw.mask.empty())
        {
            patch.mask = raw.mask;
            patch.quantized.resize(raw.quantized.size());
            for (size_t m = 0; m < raw.quantized.size(); ++m)
                dominantLabels(raw.quantized[m], raw.mask, params.dominant_window,
                               patch.quantized[m]);
        }
        for (int k = 0; k < R; ++k)
        {
            templateDescriptor(pyramidOf(pyramids, ref), patch, M, L, group.grid,
                               std::max(1, cvRound(step)), shifts[k], desc.ptr(r * R + k),
                               fg.ptr(r * R + k));
            ids.at<int>(r * R + k) = r;
        }
    }
    group.min_labels = D;
    for (int i = 0; i < desc.rows; ++i)
        group.min_labels = std::min(group.min_labels, countNonZero(desc.row(i)));
}

// Out-of-depth-range rejection (depth_range.hpp): each template's depth samples' range, each
// group's the union of its templates'.
static void depthSpans(SearchIndex& index, const TemplateStore& store)
{
    index.depth.assign(index.rows.size(), DepthSpan());
    for (size_t r = 0; r < index.rows.size(); ++r)
    {
        const TemplateRef& ref = index.rows[r];
        const std::vector<Point3i>& dz = store.get(ref.class_id, ref.template_id).depth;
        for (size_t k = 0; k < dz.size(); ++k)
            index.depth[r].add(DepthSpan(dz[k].z, dz[k].z));
    }
    for (size_t g = 0; g < index.groups.size(); ++g)
    {
        SearchGroup& grp = index.groups[g];
        grp.depth = DepthSpan();
        for (size_t k = 0; k < grp.rows.size(); ++k)
            grp.depth.add(index.depth[grp.rows[k]]);
    }
}

Size coarseFeatures(const TemplatePyramid& tp, int level_index, int num_modalities, int T,
                    std::vector<CoarseFeature>& features)
{
    CV_Assert(T > 0 && (int)tp.size() >= (level_index + 1) * num_modalities);
    const Template& t0 = tp[level_index * num_modalities];
    for (int m = 0; m < num_modalities; ++m)
    {
        const Template& t = tp[level_index * num_modalities + m];
        for (size_t i = 0; i < t.features.size(); ++i)
        {
            const linemod::Feature& f = t.features[i];
            // features lie in [0, width] x [0, height] (model_check.cpp): one cell beyond the
            // positions' cells at most
            if (f.x < 0 || f.y < 0 || f.x > t0.width || f.y > t0.height)
                continue;
            const int cx = f.x / T, cy = f.y / T;
            CoarseFeature c;
            c.memory = linearMemory(m, f.label, f.x - cx * T, f.y - cy * T, T);
            c.cx = static_cast<short>(cx);
            c.cy = static_cast<short>(cy);
            features.push_back(c);
        }
    }
    return Size((t0.width - 1) / T + 1, (t0.height - 1) / T + 1);
}

std::shared_ptr<const CoarseRuns::Offsets> CoarseRuns::offsetsFor(int stride, int rows) const
{
    AutoLock lock(offsets_mutex_);
    if (!offsets_ || offsets_->stride != stride || offsets_->rows != rows)
    {
        std::shared_ptr<Offsets> o = std::make_shared<Offsets>();
        o->stride = stride;
        o->rows = rows;
        o->offsets.resize(features.size());
        for (size_t k = 0; k < features.size(); ++k)
        {
            const int64 off = runOffset(features[k], stride, rows);
            CV_Assert(off <= INT_MAX); // the memories' offsets are ints, as LINEMOD's
            o->offsets[k] = static_cast<int>(off);
        }
        offsets_ = o;
    }
    return offsets_;
}

CoarseRuns& CoarseRuns::operator=(const CoarseRuns& other)
{
    if (&other == this)
        return *this;
    features = other.features;
    begin = other.begin;
    cells = other.cells;
    centre = other.centre;
    total = other.total;
    std::shared_ptr<const Offsets> kept;
    {
        AutoLock lock(other.offsets_mutex_);
        kept = other.offsets_;
    }
    AutoLock lock(offsets_mutex_);
    offsets_ = kept;
    return *this;
}

void CoarseRuns::clearOffsets()
{
    AutoLock lock(offsets_mutex_);
    offsets_.reset();
}

static void buildCoarseRuns(SearchIndex& index, const ClassPyramids& pyramids, int M, int L,
                            int T)
{
    CoarseRuns& c = index.coarse;
    c.clearOffsets();
    c.features.clear();
    c.begin.assign(1, 0);
    c.cells.clear();
    c.centre.clear();
    c.total.clear();
    for (size_t r = 0; r < index.rows.size(); ++r)
    {
        const TemplatePyramid& tp = pyramidOf(pyramids, index.rows[r]);
        c.cells.push_back(coarseFeatures(tp, L, M, T, c.features));
        // the cell of its centre, from the cell of the position its matches are reported at
        const Template& top = tp[L * M];
        const int offset = matchOffset(T);
        c.centre.push_back(Point((offset + top.width / 2) / T, (offset + top.height / 2) / T));
        c.begin.push_back(static_cast<int>(c.features.size()));
        c.total.push_back(numFeatures(tp, L, M));
    }
}

// Everything training derives from the templates besides the forests: groups, windows,
// descriptors per group, rejection limits. Deterministic: load() runs it too.
static void prepare(SearchIndex& index, const ClassPyramids& pyramids, const TemplateStore& store,
                    const DetectorParams& params, int M, int L, int T, std::vector<Mat>& descs,
                    std::vector<Mat>& fgs, std::vector<Mat>& idss)
{
    buildGroups(index, pyramids, M, L, params);
    const size_t NG = index.groups.size();
    descs.assign(NG, Mat());
    fgs.assign(NG, Mat());
    idss.assign(NG, Mat());
    for (size_t gi = 0; gi < NG; ++gi)
        groupDescriptors(index, index.groups[gi], pyramids, store, params, M, L, T, descs[gi],
                         fgs[gi], idss[gi]);
    depthSpans(index, store);
    buildCoarseRuns(index, pyramids, M, L, T);
}

// Automatic forest depth (DetectorParams::auto_depth_leaf_samples).
static int forestDepth(const DetectorParams& params, int samples_n, int classes)
{
    // paper: 8 for one object, 9 for several. Here: 8, deeper when the group has more samples
    // (templates x shifts) than that gives leaves for, plus one level per doubling of the
    // detector's classes (the paper's +1 for several objects, generalised; doc/detector.md)
    int depth = classes > 1 ? 9 : 8;
    if (params.auto_depth_leaf_samples > 0.f)
    {
        const double samples = std::max(1, samples_n);
        const int by_samples = (int)std::ceil(std::log2(std::max(
            1.0, samples / (double)params.auto_depth_leaf_samples)));
        depth = std::max(8, by_samples) + (int)std::ceil(std::log2((double)classes));
        // never deeper than log2(samples) + 1: the splits have nothing left to separate and
        // only overfit (LM-O can alone, 432 samples: depth 11 lost 3 of 10 rendered scenes
        // that depth 8 finds)
        depth = std::min(depth, (int)std::ceil(std::log2(samples)) + 1);
        depth = std::max(depth, 8); // the paper's depth for one object is the floor
    }
    return std::min(depth, 20);
}

void SearchIndex::train(const ClassPyramids& pyramids, const TemplateStore& store,
                        const DetectorParams& params, int M, int L, int T)
{
    trained = false;
    std::vector<Mat> descs, fgs, idss;
    prepare(*this, pyramids, store, params, M, L, T, descs, fgs, idss);
    for (size_t gi = 0; gi < groups.size(); ++gi)
    {
        ForestParams fp = params.forest;
        if (fp.max_depth <= 0)
            fp.max_depth = forestDepth(params, descs[gi].rows, (int)pyramids.size());
        Ptr<TemplateForest> forest = TemplateForest::create(fp);
        forest->train(descs[gi], fgs[gi], idss[gi]);
        groups[gi].forest = forest;
    }
    trained = true;
}

void SearchIndex::attach(const ClassPyramids& pyramids, const TemplateStore& store,
                         const DetectorParams& params, int M, int L, int T,
                         const std::vector<Ptr<TemplateForest> >& forests, const String& filename)
{
    trained = false;
    std::vector<Mat> descs, fgs, idss;
    prepare(*this, pyramids, store, params, M, L, T, descs, fgs, idss);
    if (forests.size() != groups.size())
        CV_Error_(Error::StsParseError, ("forestmod::Detector::load: '%s' holds %d forests, its "
                                         "templates and parameters make %d search groups "
                                         "(corrupt file?)", filename.c_str(),
                                         (int)forests.size(), (int)groups.size()));
    for (size_t g = 0; g < forests.size(); ++g)
    {
        const Ptr<TemplateForest>& f = forests[g];
        if (f.empty() || f->empty() || f->numTemplates() != (int)groups[g].rows.size()
            || f->dims() != (int)groups[g].plane_of.size())
            CV_Error_(Error::StsParseError, ("forestmod::Detector::load: forest %d in '%s' does "
                                             "not fit its templates (corrupt file?)", (int)g,
                                             filename.c_str()));
        groups[g].forest = f;
    }
    trained = true;
}

void SearchIndex::clear()
{
    rows.clear();
    groups.clear();
    depth.clear();
    max_extent = 0;
    coarse.features.clear();
    coarse.begin.clear();
    coarse.cells.clear();
    coarse.centre.clear();
    coarse.total.clear();
    coarse.clearOffsets();
    trained = false;
}

} // namespace detail
} // namespace forestmod
} // namespace cv
