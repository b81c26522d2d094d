// This file is part of OpenCV project.
// It is subject to the license terms in the LICENSE file found in the top-level directory
// of this distribution and at http://opencv.org/license.html

// Rejection probe: one object's model (an untrained model file, e.g. forestmod_eval's template
// cache) on the frames of a BOP scene, RGB only, without the pose stage. Per frame: the share of
// locations rejected before validation, whether the best match's box covers the object (2D IoU
// of the template box with the ground-truth box >= 0.5), and whether any location within one step
// of the object's centre reached validation. --exhaustive gives the same for the linear LINEMOD
// search of the same templates (DetectorParams::use_forest false). --absence prints how often the
// forest's label planes hold 0 ("no feature") on the object and on the background
// (doc/experiments.md, "Evidence of absence"). --occupancy prints how much of the exhaustive
// search's work the locations that pass hold (doc/experiments.md, "The forests' rejection and
// the exhaustive search's vectors"). --hue_windows prints how much a test of the hue labels'
// share in a window, without templates, would reject (doc/experiments.md, "Hue content of a
// window").

#include <opencv2/core.hpp>
#include <opencv2/core/utility.hpp>
#include <opencv2/imgproc.hpp>
#include <opencv2/forestmod.hpp>

#include <cstdio>
#include <iostream>

namespace fm = cv::forestmod;

static const char* keys
    = "{help h usage ?  |          | print this message }"
      "{dataset         |          | BOP dataset root (e.g. ../shared/data/lmo) }"
      "{scene           | 2        | scene id }"
      "{model           |          | model file with the object's templates (one class) }"
      "{object          |          | the object's id in the dataset }"
      "{first           | 0        | first frame (index in the scene) }"
      "{frames          | 0        | frames from the first (0: all) }"
      "{exhaustive      |          | linear LINEMOD search instead of the forest }"
      "{trees           | 1        | trees of the forest }"
      "{exhaustive_ratio |         | DetectorParams::exhaustive_ratio (negative: the forest path "
      "for every search group; default: the library's) }"
      "{max_survivors   |          | DetectorParams::max_survivors (default: the library's) }"
      "{breadth_first   |          | DetectorParams::breadth_first, 0 or 1 (default: the "
      "library's) }"
      "{fuzzy_margin    |          | ForestParams::fuzzy_margin, 0: crisp splits (default: the "
      "library's) }"
      "{rejector_noise  |          | ForestParams::rejector_noise (default: the library's) }"
      "{group_size_ratio |         | DetectorParams::group_size_ratio (default: the library's) }"
      "{threshold       | 80       | similarity threshold (percent) }"
      "{absence         |          | print P(0) of the label planes on the object / background }"
      "{weak_threshold  | -1       | --absence: ColorGradient's weak threshold (gradient "
      "magnitude) of the statistics (-1: the model's, 10 in LINEMOD) }"
      "{occupancy       |          | the share of locations that pass the tests before the "
      "forest (flat window, root rejectors) and the whole forest, and of the exhaustive search's "
      "T grid cells and 32-cell vectors that hold one (needs the forest path: "
      "--exhaustive_ratio=-1) }"
      "{hue_windows     |          | print the share of windows (the object's box, on the T grid) "
      "that a test of the object's hue labels' share in the window would reject }"
      "{verbose v       |          | one line per frame }";

static double boxIoU(const cv::Rect& a, const cv::Rect& b)
{
    const double inter = (a & b).area();
    const double uni = (double)a.area() + b.area() - inter;
    return uni > 0 ? inter / uni : 0.;
}

// P(a label plane holds 0 at the coarsest level, 3 x 3 dominant labels) in the central quarter of
// the object's visible box (objects at least half visible) and outside every object's box.
static void absenceStats(const fm::Detector& det, const std::vector<fm::Frame>& frames,
                         int first, int last, int obj_id, float weak_threshold)
{
    std::vector<cv::Ptr<cv::linemod::Modality> > mods = det.getModalities();
    for (size_t m = 0; m < mods.size(); ++m)
        if (weak_threshold >= 0.f && mods[m]->name() == "ColorGradient")
            mods[m] = cv::makePtr<cv::linemod::ColorGradient>(
                weak_threshold, 63, std::max(55.f, weak_threshold));
    std::vector<double> zin(mods.size(), 0.), zout(mods.size(), 0.);
    double nin = 0, nout = 0;
    for (int i = first; i < last; ++i)
    {
        const fm::Frame& f = frames[i];
        const fm::GroundTruth* gt = 0;
        for (size_t k = 0; k < f.gt.size(); ++k)
            if (f.gt[k].obj_id == obj_id)
                gt = &f.gt[k];
        if (!gt || gt->visib_fract < 0.5)
            continue;
        const cv::Mat rgb = f.rgb();
        const int L = det.pyramidLevels() - 1;
        const cv::Size size(rgb.cols >> L, rgb.rows >> L);
        const cv::Rect frame(cv::Point(), size);
        cv::Mat bg(size, CV_8U, cv::Scalar(1)), in = cv::Mat::zeros(size, CV_8U);
        for (size_t k = 0; k < f.gt.size(); ++k)
        {
            const cv::Rect b = f.gt[k].bbox_obj;
            bg(cv::Rect(b.x >> L, b.y >> L, b.width >> L, b.height >> L) & frame).setTo(0);
        }
        const cv::Rect v = gt->bbox_visib;
        in(cv::Rect((v.x + v.width / 4) >> L, (v.y + v.height / 4) >> L, (v.width / 2) >> L,
                    (v.height / 2) >> L) & frame).setTo(1);
        nin += cv::countNonZero(in);
        nout += cv::countNonZero(bg);
        for (size_t m = 0; m < mods.size(); ++m)
        {
            cv::Ptr<cv::linemod::QuantizedPyramid> qp = mods[m]->process(rgb, cv::Mat());
            for (int l = 0; l < L; ++l)
                qp->pyrDown();
            cv::Mat q, cnt;
            qp->quantize(q);
            const cv::Mat labelled = (q != 0) / 255;
            cv::boxFilter(labelled, cnt, CV_32S, cv::Size(3, 3), cv::Point(-1, -1), false);
            const cv::Mat zero = cnt == 0;
            zin[m] += cv::countNonZero(zero & (in != 0));
            zout[m] += cv::countNonZero(zero & (bg != 0));
        }
    }
    for (size_t m = 0; m < mods.size(); ++m)
        printf("P(0) %s: object centre %.3f, background %.3f\n", mods[m]->name().c_str(),
               nin > 0 ? zin[m] / nin : 0., nout > 0 ? zout[m] / nout : 0.);
}

// The work of the exhaustive search that the locations passing a rejection hold, summed over
// frames: the location grid's locations, the T grid's cells (one of their R x R locations
// passes after a 3 x 3 dilation: a template's location lies between the grid's points) and the
// vectors of 32 cells (AVX2's 32 bytes) of the cells in rows of cells_x + 1, the search's layout.
struct Occupancy
{
    double locations, passing, cells, cells_kept, vectors, vectors_kept;
    int object_kept;  //!< frames where a location within one step of the object's centre passes
    Occupancy()
        : locations(0), passing(0), cells(0), cells_kept(0), vectors(0), vectors_kept(0),
          object_kept(0)
    {
    }

    void add(const cv::Mat& pass, int R, cv::Size grid)
    {
        locations += pass.total();
        passing += cv::countNonZero(pass);
        cv::Mat kept;
        cv::dilate(pass, kept, cv::Mat::ones(3, 3, CV_8U));
        const int stride = grid.width + 1, n = grid.height * stride;
        std::vector<uchar> cell(n, 0);
        for (int cy = 0; cy < grid.height; ++cy)
            for (int cx = 0; cx < grid.width; ++cx)
            {
                const cv::Rect r(cx * R, cy * R, R, R);
                const cv::Rect in = r & cv::Rect(0, 0, kept.cols, kept.rows);
                cell[cy * stride + cx] = in.area() > 0 && cv::countNonZero(kept(in)) > 0;
                cells_kept += cell[cy * stride + cx];
            }
        cells += grid.area();
        for (int v = 0; v < n; v += 32)
        {
            ++vectors;
            bool any = false;
            for (int k = v; k < std::min(n, v + 32); ++k)
                any |= cell[k] != 0;
            vectors_kept += any;
        }
    }
    void print(const char* what, int object_frames) const
    {
        printf("%s: locations passing %.1f %% (the object's in %d / %d frames), T grid cells "
               "holding one %.1f %%, 32-cell vectors holding one %.1f %%\n", what,
               100. * passing / std::max(1., locations), object_kept, object_frames,
               100. * cells_kept / std::max(1., cells),
               100. * vectors_kept / std::max(1., vectors));
    }
};

// The hue labels (bits of the quantized image, 0 for "no hue") that the class's templates'
// ColorHue features carry on at least 3 % of them (with `neighbours`, each one's neighbours on the
// hue circle too); "no hue" alone for a class without hue features.
static int objectHueLabels(const fm::Detector& det, const cv::String& cls, int modality,
                           bool neighbours)
{
    std::vector<double> count(8, 0.);
    double total = 0;
    for (int id = 0; id < det.numTemplates(cls); ++id)
    {
        const std::vector<cv::linemod::Feature>& f = det.getTemplates(cls, id)[modality].features;
        for (size_t k = 0; k < f.size(); ++k)
            count[f[k].label & 7] += 1;
        total += (double)f.size();
    }
    int labels = 0;
    for (int b = 0; b < 8 && total > 0; ++b)
        if (count[b] >= 0.03 * total)
            labels |= neighbours ? (1 << b) | (1 << ((b + 1) & 7)) | (1 << ((b + 7) & 7))
                                 : 1 << b;
    return labels;
}

// What --hue_windows counts for one set of labels, per share threshold.
struct HueTally
{
    enum { N = 5 };
    int labels;
    double rejected[N], vectors_out[N], kept[N];
    explicit HueTally(int labels_) : labels(labels_)
    {
        for (int t = 0; t < N; ++t)
            rejected[t] = vectors_out[t] = kept[t] = 0;
    }
};

// --hue_windows: windows of the object's ground-truth box size at every position of the coarsest
// level's T grid (`cell` level-0 pixels), each with the share of its pixels whose quantized hue
// (level 0) is one of the object's labels (objectHueLabels: the labels alone, then with their
// neighbours). Per share threshold: the windows below it (rejected), the vectors of 32
// consecutive positions in row-major order (as the exhaustive search's, without its wrapped row
// ends) that lie below it whole, and the frames where one of the 4 windows at the object's box
// corner passes it.
static void hueWindowStats(const fm::Detector& det, const std::vector<fm::Frame>& frames,
                           int first, int last, int obj_id, int cell)
{
    const std::vector<cv::Ptr<cv::linemod::Modality> > mods = det.getModalities();
    int m = -1;
    for (size_t k = 0; k < mods.size(); ++k)
        if (mods[k]->name() == "ColorHue")
            m = (int)k;
    if (m < 0)
    {
        std::cerr << "forestmod_reject_probe: --hue_windows needs a ColorHue modality\n";
        return;
    }
    const double thr[HueTally::N] = { 0.05, 0.1, 0.15, 0.2, 0.3 };
    HueTally tally[2] = { HueTally(objectHueLabels(det, det.classIds()[0], m, false)),
                          HueTally(objectHueLabels(det, det.classIds()[0], m, true)) };
    double windows = 0, vectors = 0;
    int object_frames = 0;
    for (int i = first; i < last; ++i)
    {
        const fm::GroundTruth* gt = 0;
        for (size_t k = 0; k < frames[i].gt.size(); ++k)
            if (frames[i].gt[k].obj_id == obj_id)
                gt = &frames[i].gt[k];
        if (!gt || gt->bbox_obj.area() <= 0)
            continue;
        cv::Mat q;
        mods[m]->process(frames[i].rgb())->quantize(q);
        const cv::Rect box = gt->bbox_obj & cv::Rect(0, 0, q.cols, q.rows);
        const int cx = (q.cols - box.width) / cell + 1, cy = (q.rows - box.height) / cell + 1;
        if (box.area() <= 0 || cx <= 0 || cy <= 0)
            continue;
        ++object_frames;
        windows += (double)cx * cy;
        vectors += (double)((cx * cy + 31) / 32);
        for (HueTally& h : tally)
        {
            cv::Mat ok, sum;
            if (h.labels == 0)
                ok = q == 0;
            else
                cv::bitwise_and(q, cv::Scalar(h.labels), ok);
            cv::integral(ok != 0, sum, CV_32S); // 255 per pixel with one of the labels
            std::vector<double> share((size_t)cx * cy);
            for (int y = 0; y < cy; ++y)
                for (int x = 0; x < cx; ++x)
                {
                    const int x0 = x * cell, y0 = y * cell;
                    const int x1 = x0 + box.width, y1 = y0 + box.height;
                    share[(size_t)y * cx + x] = (sum.at<int>(y1, x1) - sum.at<int>(y0, x1)
                                                 - sum.at<int>(y1, x0) + sum.at<int>(y0, x0))
                                                / (255. * box.area());
                }
            for (int t = 0; t < HueTally::N; ++t)
            {
                for (size_t v = 0; v < share.size(); v += 32)
                {
                    int below = 0;
                    const size_t e = std::min(share.size(), v + 32);
                    for (size_t k = v; k < e; ++k)
                        below += share[k] < thr[t];
                    h.rejected[t] += below;
                    h.vectors_out[t] += below == (int)(e - v);
                }
                bool near = false;
                for (int dy = 0; dy <= 1; ++dy)
                    for (int dx = 0; dx <= 1; ++dx)
                        near = near || share[(size_t)std::min(cy - 1, box.y / cell + dy) * cx
                                             + std::min(cx - 1, box.x / cell + dx)] >= thr[t];
                h.kept[t] += near;
            }
        }
    }
    for (int v = 0; v < 2; ++v)
    {
        printf("the object's hue labels%s (0x%02x):\n", v ? " and their neighbours" : "",
               tally[v].labels);
        for (int t = 0; t < HueTally::N; ++t)
            printf("  hue share >= %.2f: windows rejected %.1f %%, 32-position vectors rejected "
                   "whole %.1f %%, object kept in %.0f / %d frames\n", thr[t],
                   100. * tally[v].rejected[t] / std::max(1., windows),
                   100. * tally[v].vectors_out[t] / std::max(1., vectors), tally[v].kept[t],
                   object_frames);
    }
}

// The model (RGB, one class); empty with a message when it does not fit the probe.
static cv::Ptr<fm::Detector> loadModel(const std::string& model)
{
    std::vector<cv::Ptr<cv::linemod::Modality> > mods;
    mods.push_back(cv::linemod::Modality::create("ColorGradient"));
    mods.push_back(fm::ColorHue::create());
    std::vector<int> T;
    T.push_back(5);
    T.push_back(8);
    cv::Ptr<fm::Detector> det = cv::makePtr<fm::Detector>(mods, T);
    det->load(model);
    for (size_t m = 0; m < det->getModalities().size(); ++m)
        if (det->getModalities()[m]->name() == "DepthNormal")
        {
            std::cerr << "forestmod_reject_probe: the model has a DepthNormal modality; this "
                         "probe is RGB only\n";
            return cv::Ptr<fm::Detector>();
        }
    if (det->classIds().size() != 1)
    {
        std::cerr << "forestmod_reject_probe: the model must hold one class\n";
        return cv::Ptr<fm::Detector>();
    }
    return det;
}

// The model holds templates; the parameters are the library's defaults and the flags'.
static fm::DetectorParams probeParams(const cv::CommandLineParser& parser, bool exhaustive,
                                      int trees)
{
    fm::DetectorParams p;
    p.nms_iou = 0;
    p.use_forest = !exhaustive;
    p.forest.num_trees = trees;
    if (parser.has("exhaustive_ratio"))
        p.exhaustive_ratio = parser.get<float>("exhaustive_ratio");
    if (parser.has("max_survivors"))
        p.max_survivors = parser.get<int>("max_survivors");
    if (parser.has("breadth_first"))
        p.breadth_first = parser.get<int>("breadth_first") != 0;
    if (parser.has("rejector_noise"))
        p.forest.rejector_noise = parser.get<float>("rejector_noise");
    if (parser.has("group_size_ratio"))
        p.group_size_ratio = parser.get<float>("group_size_ratio");
    if (parser.has("fuzzy_margin"))
        p.forest.fuzzy_margin = parser.get<float>("fuzzy_margin");
    return p;
}

// Whether a location within one step of the object's centre (level 0) passed the whole forest
// (`forest`) and the tests before it (`before`), from the rejection map's codes; `stride`: the
// location grid's in level-0 pixels (the anchor is the window's centre).
static void objectLocation(const cv::Mat& code, cv::Point centre, int stride, int& forest,
                           int& before)
{
    forest = before = 0;
    for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx)
        {
            const int x = centre.x / stride + dx, y = centre.y / stride + dy;
            if (x < 0 || y < 0 || x >= code.cols || y >= code.rows)
                continue;
            const short v = code.at<short>(y, x);
            forest |= v == -1;
            before |= v == -1 || v > 0;
        }
}

// --occupancy reads the forest's rejections of every location: a group searched exhaustively is
// not traversed, and its locations would count as passing. False with a message without the
// forest path on every group.
static bool occupancyAllowed(const cv::CommandLineParser& parser, bool exhaustive)
{
    if (!parser.has("occupancy")
        || (!exhaustive && parser.has("exhaustive_ratio")
            && parser.get<float>("exhaustive_ratio") < 0.f))
        return true;
    std::cerr << "forestmod_reject_probe: --occupancy needs the forest path on every group "
                 "(--exhaustive_ratio=-1, not --exhaustive)\n";
    return false;
}

static int probe(int argc, char** argv)
{
    cv::CommandLineParser parser(argc, argv, keys);
    parser.about("forestmod_reject_probe: rejected share and 2D box recall of one object's model "
                 "on a BOP scene (RGB, no pose stage)");
    if (parser.has("help"))
    {
        parser.printMessage();
        return 0;
    }
    const std::string root = parser.get<std::string>("dataset");
    const std::string model = parser.get<std::string>("model");
    const int obj_id = parser.get<int>("object"), scene = parser.get<int>("scene");
    const int first = parser.get<int>("first"), count = parser.get<int>("frames");
    const int trees = parser.get<int>("trees");
    const float threshold = parser.get<float>("threshold");
    const bool exhaustive = parser.has("exhaustive"), verbose = parser.has("verbose");
    if (!parser.check() || root.empty() || model.empty() || obj_id <= 0 || first < 0
        || count < 0 || trees < 1)
    {
        parser.printErrors();
        std::cerr << "forestmod_reject_probe: --dataset, --model and --object (> 0) are required; "
                     "--first, --frames >= 0, --trees >= 1\n";
        return 1;
    }
    if (!occupancyAllowed(parser, exhaustive))
        return 1;
    const cv::Ptr<fm::Detector> loaded = loadModel(model);
    if (!loaded)
        return 1;
    fm::Detector& det = *loaded;
    const cv::String cls = det.classIds()[0];
    const fm::DetectorParams p = probeParams(parser, exhaustive, trees);
    det.setParams(p);
    cv::TickMeter train;
    train.start();
    if (!exhaustive)
        det.train();
    train.stop();
    cv::setNumThreads(1);

    const fm::BopDataset ds = fm::BopDataset::open(root);
    const std::vector<fm::Frame> frames = ds.frames(scene);
    const int last = count > 0 ? std::min((int)frames.size(), first + count) : (int)frames.size();
    if (parser.has("absence"))
        absenceStats(det, frames, first, last, obj_id, parser.get<float>("weak_threshold"));
    if (parser.has("hue_windows"))
        hueWindowStats(det, frames, first, last, obj_id,
                       det.getT(det.pyramidLevels() - 1) << (det.pyramidLevels() - 1));
    const int L = det.pyramidLevels() - 1;
    int n = 0, with_gt = 0, hits = 0, kept = 0;
    Occupancy before_forest, forest;
    const bool occupancy = parser.has("occupancy");
    const int T_L = det.getT(L), S = p.location_step > 0 ? p.location_step : std::max(1, T_L / 2);
    double rejected = 0, ms = 0;
    for (int i = first; i < last; ++i)
    {
        const fm::Frame& f = frames[i];
        const fm::GroundTruth* gt = 0;
        for (size_t k = 0; k < f.gt.size(); ++k)
            if (f.gt[k].obj_id == obj_id)
                gt = &f.gt[k];
        const cv::Mat rgb = f.rgb();
        std::vector<cv::Mat> sources(det.getModalities().size(), rgb);
        std::vector<cv::linemod::Match> matches;
        fm::DetectionStats st;
        det.match(sources, threshold, matches, std::vector<cv::String>(), cv::noArray(),
                  std::vector<cv::Mat>(), &st);
        ++n;
        if (occupancy && !st.rejection_map.empty())
        {
            // codes (DetectionStats::rejection_map): -1 passed, -2 flat, >= 0 the deepest
            // rejecting forest depth of the location's groups
            const cv::Mat& code = st.rejection_map;
            const cv::Size cells((rgb.cols >> L) / T_L, (rgb.rows >> L) / T_L);
            before_forest.add((code == -1) | (code > 0), T_L / S, cells);
            forest.add(code == -1, T_L / S, cells);
        }
        rejected += st.rejectedFraction();
        ms += st.t_total_ms;
        int hit = 0, near = -1;
        if (gt)
        {
            ++with_gt;
            for (size_t k = 0; k < matches.size(); ++k)
                if (matches[k].class_id == cls)
                {
                    const cv::linemod::Template& t0 = det.getTemplates(cls,
                                                                       matches[k].template_id)[0];
                    hit = boxIoU(cv::Rect(matches[k].x, matches[k].y, t0.width, t0.height),
                                 gt->bbox_obj) >= 0.5;
                    break;
                }
            hits += hit;
            if (!st.rejection_map.empty())
            {
                int near_before = 0;
                objectLocation(st.rejection_map, (gt->bbox_obj.tl() + gt->bbox_obj.br()) / 2,
                               S << L, near, near_before);
                kept += near;
                before_forest.object_kept += near_before;
            }
        }
        if (verbose)
            printf("frame %d: rejected %.3f, hit %d, centre kept %d, candidates per location "
                   "%.1f, %.0f ms\n", i, st.rejectedFraction(), hit, near,
                   st.validated ? (double)st.candidates / st.validated : 0., st.t_total_ms);
    }
    if (occupancy)
    {
        forest.object_kept = kept;
        before_forest.print("tests before the forest", with_gt);
        forest.print("whole forest", with_gt);
    }
    printf("object %d (%s), %s, frames %d..%d: rejected %.1f %%, 2D hits %d / %d, centre "
           "locations kept %d / %d, %.0f ms per frame, training %.1f s\n", obj_id, cls.c_str(),
           exhaustive ? "exhaustive" : cv::format("%d tree(s)", trees).c_str(), first, last - 1,
           n ? 100. * rejected / n : 0., hits, with_gt, exhaustive ? 0 : kept,
           exhaustive ? 0 : with_gt, n ? ms / n : 0., train.getTimeSec());
    return 0;
}

int main(int argc, char** argv)
{
    try
    {
        return probe(argc, argv);
    }
    catch (const cv::Exception& e) // a missing or corrupt file, a parameter out of range
    {
        std::cerr << "forestmod_reject_probe: " << e.what() << std::endl;
        return 1;
    }
}
