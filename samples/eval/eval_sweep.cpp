// This file is part of OpenCV project.
// It is subject to the license terms in the LICENSE file found in the top-level directory
// of this distribution and at http://opencv.org/license.html

// forestmod_eval: how match() time grows with the templates of one object and with the classes
// of one model, for forestmod (1 and 5 trees) and cv::linemod on the same templates and frames.

#include "eval_common.hpp"

#include <opencv2/core/utils/filesystem.hpp>
#include <opencv2/imgcodecs.hpp>

#include <cstdio>
#include <iostream>

namespace fmeval {

namespace {

struct SweepPoint
{
    SweepPoint() : x(0), templates(0), train1(0), train5(0) {}
    int x;          //!< asked: templates (templates sweep) or classes (objects sweep)
    int templates;  //!< in the model
    std::vector<std::string> classes;
    Result r1, r5, rl;
    double train1, train5;
};

struct Sweep
{
    std::string name, note, object;
    fm::ViewSampler::Params sampler;
    int per_class;
    std::vector<SweepPoint> points;
};

/** The three detectors on one model (its forest trained twice), times only. */
void measure(const EvalOptions& opt, fm::Detector& det, const RunContext& ctx,
             const std::string& label, SweepPoint& pt)
{
    fm::DetectorParams p = det.getParams();
    p.nms_iou = 0; // as in the tables: the matches as cv::linemod returns them
    const std::vector<ObjectInfo*> none;
    for (int trees = 1; trees <= 5; trees += 4)
    {
        p.forest.num_trees = trees;
        det.setParams(p);
        ctx.progress->show(cv::format("%s: training %d tree(s)", label.c_str(), trees));
        (trees == 1 ? pt.train1 : pt.train5) = trainDetector(det, opt);
        std::vector<Result> rr(1);
        runForestmod(det, none, -1, ctx, cv::format("%s: forestmod %d tree(s)", label.c_str(),
                                                    trees), rr);
        (trees == 1 ? pt.r1 : pt.r5) = rr[0];
    }
    cv::Ptr<cv::linemod::Detector> lm = linemodCopy(det);
    std::vector<Result> rr(1);
    runLinemod(*lm, 0, none, -1, ctx, label + ": cv::linemod", rr);
    pt.rl = rr[0];
}

/** The sampler's poses made denser until there are at least n: one more icosahedron level than
the regime's, then distances halfway between the ones there are (up to 5 distances), then more
icosahedron levels. */
fm::ViewSampler::Params denserSampler(fm::ViewSampler::Params p, int n)
{
    const int level0 = p.level;
    while (fm::ViewSampler(p).size() < n)
    {
        if (p.level < level0 + 1 || p.radii.size() >= 5)
            ++p.level;
        else
        {
            std::vector<double> r;
            for (size_t i = 0; i < p.radii.size(); ++i)
            {
                if (i > 0)
                    r.push_back(0.5 * (p.radii[i - 1] + p.radii[i]));
                r.push_back(p.radii[i]);
            }
            if (r.size() == p.radii.size()) // one distance: add one 25 % further
                r.push_back(p.radii[0] * 1.25);
            p.radii = r;
        }
    }
    return p;
}

void printSweep(const Sweep& s, const char* xname)
{
    printf("| %s | templates | forestmod 1 tree (ms) | 5 trees (ms) | cv::linemod (ms) | "
           "linemod / 1 tree | linemod / 5 trees | rejected 1 tree | rejected 5 trees | "
           "T_quant forestmod / linemod (ms) | T_tree 1 / 5 trees (ms) | T_valid 1 / 5 trees "
           "(ms) |\n", xname);
    printf("|---|---|---|---|---|---|---|---|---|---|---|---|\n");
    for (size_t i = 0; i < s.points.size(); ++i)
    {
        const SweepPoint& p = s.points[i];
        printf("| %d | %d | %s | %s | %s | %s | %s | %s | %s | %s / %s | %s / %s | %s / %s |\n",
               p.x, p.templates, num(tTotal(p.r1), "%.1f").c_str(),
               num(tTotal(p.r5), "%.1f").c_str(), num(tTotal(p.rl), "%.1f").c_str(),
               num(tTotal(p.rl) / tTotal(p.r1)).c_str(), num(tTotal(p.rl) / tTotal(p.r5)).c_str(),
               pct(rejectedFraction(p.r1)).c_str(), pct(rejectedFraction(p.r5)).c_str(),
               num(tQuant(p.r1), "%.1f").c_str(), num(tQuant(p.rl), "%.1f").c_str(),
               num(tTree(p.r1), "%.1f").c_str(), num(tTree(p.r5), "%.1f").c_str(),
               num(tValid(p.r1), "%.1f").c_str(), num(tValid(p.r5), "%.1f").c_str());
    }
    printf("\n");
    fflush(stdout);
}

void writeSweep(cv::FileStorage& fs, const Sweep& s, const char* xkey)
{
    fs << s.name << "{";
    fs << "note" << s.note; // no apostrophe: cv::FileStorage would escape it (invalid JSON)
    fs << "sampler" << "{";
    s.sampler.write(fs);
    fs << "}";
    fs << "sampling" << samplingText(s.sampler);
    fs << "templates_per_class" << s.per_class;
    fs << "points" << "[";
    for (size_t i = 0; i < s.points.size(); ++i)
    {
        const SweepPoint& p = s.points[i];
        fs << "{";
        fs << xkey << p.x << "templates" << p.templates;
        if (!p.classes.empty())
        {
            fs << "class_ids" << "[:";
            for (size_t k = 0; k < p.classes.size(); ++k)
                fs << p.classes[k];
            fs << "]";
        }
        writeResult(fs, "forestmod", p.r1, false);
        writeResult(fs, "forestmod_5", p.r5, false);
        writeResult(fs, "linemod", p.rl, false);
        writeNumber(fs, "speedup_1tree", tTotal(p.rl) / tTotal(p.r1));
        writeNumber(fs, "speedup_5trees", tTotal(p.rl) / tTotal(p.r5));
        fs << "train_s" << "{" << "forestmod" << p.train1 << "forestmod_5" << p.train5 << "}";
        fs << "}";
    }
    fs << "]";
    fs << "}";
}

cv::Mat plotSweep(const Sweep& s, const std::string& title, const std::string& xlabel,
                  bool x_is_classes)
{
    Series f1, f5, lm, j1, j5;
    f1.label = j1.label = "forestmod, 1 tree";
    f5.label = j5.label = "forestmod, 5 trees";
    lm.label = "cv::linemod";
    f1.color = j1.color = cv::Scalar(200, 110, 0);
    f5.color = j5.color = cv::Scalar(40, 160, 40);
    lm.color = cv::Scalar(30, 30, 220);
    for (size_t i = 0; i < s.points.size(); ++i)
    {
        const SweepPoint& p = s.points[i];
        const double x = x_is_classes ? p.x : p.templates;
        f1.x.push_back(x);
        f5.x.push_back(x);
        lm.x.push_back(x);
        j1.x.push_back(x);
        j5.x.push_back(x);
        f1.y.push_back(tTotal(p.r1));
        f5.y.push_back(tTotal(p.r5));
        lm.y.push_back(tTotal(p.rl));
        j1.y.push_back(rejectedFraction(p.r1));
        j5.y.push_back(rejectedFraction(p.r5));
    }
    std::vector<Series> times, rej;
    times.push_back(f1);
    times.push_back(f5);
    times.push_back(lm);
    rej.push_back(j1);
    rej.push_back(j5);
    return plotCurves(title, xlabel, times, rej, x_is_classes ? f1.x : std::vector<double>());
}

void writePng(const std::string& file, const cv::Mat& img)
{
    if (!cv::imwrite(file, img))
        CV_Error_(cv::Error::StsError, ("cannot write %s", file.c_str()));
    std::cerr << "wrote " << file << "\n";
}

} // namespace

std::vector<std::string> sweepOutputs(const EvalOptions& opt)
{
    std::vector<std::string> out;
    if (!opt.sweep_templates && !opt.sweep_objects)
        return out;
    out.push_back(opt.plots_dir + "/scaling.json");
    if (opt.sweep_templates)
        out.push_back(opt.plots_dir + "/scaling_templates.png");
    if (opt.sweep_objects)
        out.push_back(opt.plots_dir + "/scaling_objects.png");
    return out;
}

int runSweeps(const EvalOptions& opt, const std::vector<ObjectInfo>& objects,
              const std::vector<EvalFrame>& all_frames, const TemplateSetup& setup,
              bool use_depth, cv::FileStorage& fs)
{
    if (!opt.sweep_templates && !opt.sweep_objects)
        return 0;
    std::vector<EvalFrame> frames = all_frames;
    if (opt.sweep_frames > 0 && (int)frames.size() > opt.sweep_frames)
        frames.resize(opt.sweep_frames);
    for (size_t i = 0; i < frames.size(); ++i)
        frames[i].owner = -1; // timing only: every model on every frame
    Progress progress;
    const RunContext ctx = runContext(opt, frames, use_depth, progress);
    const int F = (int)frames.size();

    Sweep ts, os;
    // ---- (a) one object, more and more templates
    if (opt.sweep_templates)
    {
        const ObjectInfo* obj = &objects[0];
        for (size_t o = 0; o < objects.size(); ++o)
            if (objects[o].obj_id == opt.sweep_object)
                obj = &objects[o];
        if (opt.sweep_object > 0 && obj->obj_id != opt.sweep_object)
        {
            std::cerr << "forestmod_eval: --sweep_object=" << opt.sweep_object
                      << " is not among the objects\n";
            return 1;
        }
        TemplateSetup s = setup;
        s.sampler = fm::ViewSampler(denserSampler(setup.sampler.params, opt.sweep_counts.back()));
        ts.name = "templates";
        ts.sampler = s.sampler.params;
        ts.per_class = 0;
        ts.object = obj->name;
        ts.note = cv::format("one object (%s); each point: that many poses of the sampler, "
                             "spread evenly over its order (radius, direction, in-plane)",
                             obj->name.c_str());
        printf("## Scaling with templates: %s, %d frames, best of %d match() calls per frame\n\n"
               "- sampler: %s; each point takes that many poses, spread evenly (views without "
               "features give no template)\n\n",
               obj->name.c_str(), F, opt.repeat, samplingText(ts.sampler).c_str());
        fflush(stdout);
        progress.total = (int64)opt.sweep_counts.size() * F * 3;
        for (size_t i = 0; i < opt.sweep_counts.size(); ++i)
        {
            s.subset = opt.sweep_counts[i];
            ObjectInfo o = *obj;
            double render_s = 0;
            cv::Ptr<fm::Detector> det = objectTemplates(opt, o, s, progress, render_s);
            if (!det)
            {
                progress.done += 3 * F;
                continue;
            }
            SweepPoint pt;
            pt.x = opt.sweep_counts[i];
            pt.templates = det->numTemplates();
            pt.classes.push_back(o.class_id);
            measure(opt, *det, ctx, cv::format("%d templates", pt.templates), pt);
            ts.points.push_back(pt);
        }
        progress.finish();
        printSweep(ts, "poses asked");
    }

    // ---- (b) more and more classes in one model
    if (opt.sweep_objects)
    {
        TemplateSetup s = setup;
        s.subset = opt.sweep_per_class;
        os.name = "objects";
        os.sampler = s.sampler.params;
        os.per_class = opt.sweep_per_class > 0 ? std::min(opt.sweep_per_class, s.sampler.size())
                                               : s.sampler.size();
        const int n = (int)objects.size();
        os.note = cv::format("classes 1..%d: the objects of the dataset; beyond: copies of their "
                             "meshes recoloured (hue turned) and rescaled, for timing", n);
        printf("## Scaling with objects: classes in one model, %d poses per class, %d frames, "
               "best of %d match() calls per frame\n\n- sampler: %s, %d poses of it per class "
               "spread evenly\n- classes 1..%d are the dataset's objects, further classes copies "
               "of their meshes recoloured (hue turned by 90 deg steps) and rescaled "
               "(0.7-1.5x): distinct classes for timing, not for accuracy\n\n",
               os.per_class, F, opt.repeat, samplingText(os.sampler).c_str(), os.per_class, n);
        fflush(stdout);
        const int max_classes = opt.sweep_classes.back();
        progress.total = (int64)opt.sweep_classes.size() * F * 3 + max_classes;
        progress.done = 0;
        std::vector<ObjectInfo> classes;
        for (int k = 0; (int)classes.size() < max_classes && k < 64 * n; ++k)
        {
            ObjectInfo v = objectVariant(objects[k % n], k / n);
            double render_s = 0;
            cv::Ptr<fm::Detector> det = objectTemplates(opt, v, s, progress, render_s);
            progress.step(v.name + ": templates");
            if (det)
                classes.push_back(v);
        }
        for (size_t i = 0; i < opt.sweep_classes.size(); ++i)
        {
            const int K = std::min(opt.sweep_classes[i], (int)classes.size());
            if (!os.points.empty() && os.points.back().x == K)
                continue;
            std::vector<ObjectInfo*> use;
            for (int k = 0; k < K; ++k)
                use.push_back(&classes[k]);
            cv::Ptr<fm::Detector> det = multiObjectDetector(opt, s.modalities, use);
            SweepPoint pt;
            pt.x = K;
            pt.templates = det->numTemplates();
            for (int k = 0; k < K; ++k)
                pt.classes.push_back(classes[k].class_id);
            measure(opt, *det, ctx, cv::format("%d classes", K), pt);
            os.points.push_back(pt);
        }
        progress.finish();
        printSweep(os, "classes");
    }

    // ---- JSON and plots
    cv::utils::fs::createDirectories(opt.plots_dir);
    const std::string json = opt.plots_dir + "/scaling.json";
    cv::FileStorage sf(json, cv::FileStorage::WRITE | cv::FileStorage::FORMAT_JSON);
    if (!sf.isOpened())
        CV_Error_(cv::Error::StsError, ("cannot write %s", json.c_str()));
    cv::FileStorage* out[2] = { &sf, &fs };
    for (int k = 0; k < 2; ++k)
    {
        cv::FileStorage& f = *out[k];
        if (!f.isOpened())
            continue;
        f << "sweeps" << "{";
        f << "frames" << F << "repetitions" << opt.repeat << "threads" << opt.threads;
        f << "threshold" << opt.threshold;
        if (opt.sweep_templates)
            writeSweep(f, ts, "poses");
        if (opt.sweep_objects)
            writeSweep(f, os, "classes");
        f << "}";
    }
    sf.release();
    std::cerr << "wrote " << json << "\n";
    if (opt.sweep_templates)
        writePng(opt.plots_dir + "/scaling_templates.png",
                 plotSweep(ts, cv::format("match() time vs templates of one object (%s), "
                                          "%d frames, 1 thread", ts.object.c_str(), F),
                           "templates", false));
    if (opt.sweep_objects)
        writePng(opt.plots_dir + "/scaling_objects.png",
                 plotSweep(os, cv::format("match() time vs classes in one model, %d templates "
                                          "per class, %d frames, 1 thread", os.per_class, F),
                           cv::format("classes (beyond %d: recoloured/rescaled copies)",
                                      (int)objects.size()), true));
    return 0;
}

} // namespace fmeval
