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
// (doc/experiments.md, "Evidence of absence").

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
      "{threshold       | 80       | similarity threshold (percent) }"
      "{absence         |          | print P(0) of the label planes on the object / background }"
      "{weak_threshold  | -1       | --absence: ColorGradient's weak threshold (gradient magnitude) "
      "of the statistics (-1: the model's, 10 in LINEMOD) }"
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
    std::vector<cv::Ptr<cv::linemod::Modality> > mods;
    mods.push_back(cv::linemod::Modality::create("ColorGradient"));
    mods.push_back(fm::ColorHue::create());
    std::vector<int> T;
    T.push_back(5);
    T.push_back(8);
    fm::Detector det(mods, T);
    det.load(model);
    for (size_t m = 0; m < det.getModalities().size(); ++m)
        if (det.getModalities()[m]->name() == "DepthNormal")
        {
            std::cerr << "forestmod_reject_probe: the model has a DepthNormal modality; this "
                         "probe is RGB only\n";
            return 1;
        }
    if (det.classIds().size() != 1)
    {
        std::cerr << "forestmod_reject_probe: the model must hold one class\n";
        return 1;
    }
    const cv::String cls = det.classIds()[0];
    // the model holds templates; the parameters are the library's defaults and the flags'
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
    if (parser.has("fuzzy_margin"))
        p.forest.fuzzy_margin = parser.get<float>("fuzzy_margin");
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
    const int L = det.pyramidLevels() - 1;
    int n = 0, with_gt = 0, hits = 0, kept = 0;
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
                // the location grid's stride in level-0 pixels; the anchor is the window's centre
                const int stride = (p.location_step > 0 ? p.location_step
                                                        : std::max(1, det.getT(L) / 2)) << L;
                const cv::Point c = (gt->bbox_obj.tl() + gt->bbox_obj.br()) / 2;
                near = 0;
                for (int dy = -1; dy <= 1; ++dy)
                    for (int dx = -1; dx <= 1; ++dx)
                    {
                        const int x = c.x / stride + dx, y = c.y / stride + dy;
                        if (x >= 0 && y >= 0 && x < st.rejection_map.cols
                            && y < st.rejection_map.rows)
                            near |= st.rejection_map.at<short>(y, x) == -1;
                    }
                kept += near;
            }
        }
        if (verbose)
            printf("frame %d: rejected %.3f, hit %d, centre kept %d, candidates per location "
                   "%.1f, %.0f ms\n", i, st.rejectedFraction(), hit, near,
                   st.validated ? (double)st.candidates / st.validated : 0., st.t_total_ms);
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
