// This file is part of OpenCV project.
// It is subject to the license terms in the LICENSE file found in the top-level directory
// of this distribution and at http://opencv.org/license.html

// forestmod_eval: the paper's Table 1 (one object per model: forestmod 1 and 5 trees,
// cv::linemod) and Table 2 (all objects in one model), printed and written to the JSON.

#include "eval_common.hpp"

#include <opencv2/core/utils/filesystem.hpp>
#include <opencv2/imgcodecs.hpp>

#include <cstdio>
#include <iostream>
#include <limits>

namespace fmeval {

// The values of the frames' records that are measured (not NaN).
static std::vector<double> measured(const std::vector<FrameRecord>& records,
                                    double FrameRecord::*field)
{
    std::vector<double> v;
    for (size_t i = 0; i < records.size(); ++i)
        if (records[i].*field == records[i].*field)
            v.push_back(records[i].*field);
    return v;
}

// --gt_similarity: per object, the medians over the frames of the best similarity off the object
// and on it, and of a template made at the ground-truth pose; and the frames where that template
// scores below cv::linemod's best match off the object (one of the templates on the clutter).
static void printSimilarityOnTheObject(const std::vector<ObjectInfo>& objects,
                                       const std::vector<Result>& fm1,
                                       const std::vector<Result>& lm)
{
    printf("\n## Similarity on the object\n\n");
    printf("| object | frames | best off the object: forestmod / cv::linemod | best on the object: "
           "forestmod / cv::linemod (frames with one) | template at the ground truth (frames) | "
           "frames where it scores below cv::linemod's best off the object |\n"
           "|---|---|---|---|---|---|\n");
    for (size_t o = 0; o < objects.size(); ++o)
    {
        int below = 0, compared = 0;
        for (size_t i = 0; i < lm[o].per_frame.size(); ++i)
        {
            const FrameRecord& r = lm[o].per_frame[i];
            if (r.gt_similarity == r.gt_similarity && r.off_similarity == r.off_similarity)
            {
                ++compared;
                below += r.gt_similarity < r.off_similarity;
            }
        }
        const std::vector<double> off_fm = measured(fm1[o].per_frame,
                                                    &FrameRecord::off_similarity),
                                  off_lm = measured(lm[o].per_frame, &FrameRecord::off_similarity),
                                  on_fm = measured(fm1[o].per_frame,
                                                   &FrameRecord::correct_similarity),
                                  on_lm = measured(lm[o].per_frame,
                                                   &FrameRecord::correct_similarity),
                                  gt = measured(lm[o].per_frame, &FrameRecord::gt_similarity);
        printf("| %s | %d | %s / %s | %s / %s (%d / %d) | %s (%d) | %d of %d |\n",
               objects[o].name.c_str(), (int)lm[o].per_frame.size(),
               num(median(off_fm), "%.1f").c_str(), num(median(off_lm), "%.1f").c_str(),
               num(median(on_fm), "%.1f").c_str(), num(median(on_lm), "%.1f").c_str(),
               (int)on_fm.size(), (int)on_lm.size(), num(median(gt), "%.1f").c_str(),
               (int)gt.size(), below, compared);
    }
    printf("\nMedians over the frames with ground truth. On the object: a match whose template "
           "box has IoU >= 0.5 with the ground truth's box (off: < 0.5, the clutter and the other "
           "objects). Template at the ground truth: the "
           "object rendered at its ground-truth pose, a template made of it with the same "
           "modalities and its best match on the object (threshold 50).\n");
}

// Per object, how far its ground-truth poses lie from the nearest template (templateCoverage).
static void printTemplateCoverage(const std::vector<ObjectInfo>& objects,
                                  const std::vector<std::vector<double> >& coverage)
{
    printf("\n## Template coverage\n\n| object | ground truths | nearest template (deg): median / "
           "90 %% / max |\n|---|---|---|\n");
    for (size_t o = 0; o < objects.size(); ++o)
        printf("| %s | %d | %s / %s / %s |\n", objects[o].name.c_str(), (int)coverage[o].size(),
               num(median(coverage[o]), "%.1f").c_str(),
               num(quantile(coverage[o], 0.9), "%.1f").c_str(),
               num(quantile(coverage[o], 1), "%.1f").c_str());
    printf("\nThe rotation from each ground-truth pose, seen along its line of sight and taken at "
           "the nearest of its symmetries, to the nearest template's: no matcher of these "
           "templates finds a closer view.\n");
}

int runTables(const EvalOptions& opt, std::vector<ObjectInfo>& objects,
              const std::vector<EvalFrame>& frames, const TemplateSetup& setup, bool use_depth,
              cv::FileStorage& fs)
{
    const bool multi = opt.multi;
    const std::string& heat_dir = opt.heat_dir;
    const int heat_frames = opt.heat_frames;
    Progress progress;

    // heat maps must not overwrite files: the first object's model (1 tree) on its first
    // frames, and the model of all objects (5 trees); the files are named after the frame
    if (!heat_dir.empty())
    {
        std::vector<std::string> heat_files;
        for (size_t i = 0; i < frames.size(); ++i)
        {
            int rank = 0; // position among the frames of the object the scene was made for
            for (size_t j = 0; j < i; ++j)
                rank += frames[j].owner == frames[i].owner;
            if (rank < heat_frames && frames[i].owner <= 0) // the first object's (all when real)
                heat_files.push_back(heatFile(heat_dir, "single", frames[i]));
            if (i < (size_t)heat_frames && multi)
                heat_files.push_back(heatFile(heat_dir, "all", frames[i]));
        }
        for (size_t i = 0; i < heat_files.size(); ++i)
            if (cv::forestmod::samples::refuseOutput("forestmod_eval", heat_files[i], opt.force))
                return 1;
        cv::utils::fs::createDirectories(heat_dir);
    }

    // templates of every object: from the cache, or rendered (and cached)
    std::vector<cv::Ptr<fm::Detector> > dets(objects.size());
    std::vector<double> render(objects.size());
    for (size_t o = 0; o < objects.size(); ++o)
        dets[o] = objectTemplates(opt, objects[o], setup, progress, render[o]);

    const int frames_per_object = opt.synthetic > 0 ? opt.synthetic : (int)frames.size();
    const int rows = opt.five_trees ? 3 : 2; // matcher runs per object and frame
    progress.total = (int64)objects.size() * frames_per_object * rows
        + (multi ? (int64)frames.size() * 2 : 0);
    progress.done = 0;

    const RunContext ctx = runContext(opt, frames, use_depth, progress);

    // ---- Table 1: one object per model
    std::vector<Result> r1(objects.size()), r5(objects.size()), rl(objects.size());
    // the same hypotheses re-ranked by the verification stage (Detector::verify)
    std::vector<Result> r1v(objects.size()), rlv(objects.size());
    std::vector<double> train1(objects.size()), train5(objects.size());
    std::vector<std::vector<double> > coverage(objects.size());
    std::vector<std::pair<int, cv::Mat> > heat_single, heat_all;
    std::vector<std::string> skipped;
    for (size_t o = 0; o < objects.size(); ++o)
    {
        ObjectInfo& obj = objects[o];
        cv::Ptr<fm::Detector> det = dets[o];
        dets[o].release();
        if (!det)
        {
            skipped.push_back(obj.name);
            progress.done += rows * frames_per_object;
            continue;
        }
        std::vector<ObjectInfo*> one(1, &obj);
        const int oi = opt.synthetic > 0 ? (int)o : -1;
        coverage[o] = templateCoverage(*det, obj, frames);
        fm::DetectorParams p = det->getParams();
        p.nms_iou = 0; // matches as cv::linemod returns them: the pose choice sees them all
        for (int trees = 1; trees <= (opt.five_trees ? 5 : 1); trees += 4)
        {
            p.forest.num_trees = trees;
            det->setParams(p);
            progress.show(cv::format("%s: training %d tree(s)", obj.name.c_str(), trees));
            (trees == 1 ? train1 : train5)[o] = trainDetector(*det, opt);
            std::vector<Result> rr(1), rv(1);
            const bool want_heat = !heat_dir.empty() && o == 0 && trees == 1;
            runForestmod(*det, one, oi, ctx,
                         cv::format("%s: forestmod %d tree(s)", obj.name.c_str(), trees), rr,
                         want_heat ? &heat_single : 0, heat_frames, trees == 1 ? &rv : 0);
            (trees == 1 ? r1 : r5)[o] = rr[0];
            if (trees == 1)
                r1v[o] = rv[0];
        }
        cv::Ptr<cv::linemod::Detector> lm = linemodCopy(*det);
        std::vector<Result> rr(1), rv(1);
        runLinemod(*lm, det, one, oi, ctx, obj.name + ": cv::linemod", rr, &rv);
        rl[o] = rr[0];
        rlv[o] = rv[0];
    }

    // objects without templates are left out from here on
    {
        size_t k = 0;
        for (size_t o = 0; o < objects.size(); ++o)
            if (objects[o].templates > 0)
            {
                objects[k] = objects[o];
                r1[k] = r1[o];
                r5[k] = r5[o];
                rl[k] = rl[o];
                r1v[k] = r1v[o];
                rlv[k] = rlv[o];
                train1[k] = train1[o];
                train5[k] = train5[o];
                coverage[k] = coverage[o];
                render[k] = render[o];
                ++k;
            }
        objects.resize(k);
        if (objects.empty())
        {
            progress.finish();
            std::cerr << "forestmod_eval: no object has a template with these modalities\n";
            return 1;
        }
    }

    // ---- Table 2: every object in one model (forestmod 5 trees vs cv::linemod)
    Result m5, ml;
    int multi_templates = 0;
    double multi_train = 0;
    std::vector<Result> m5o(objects.size()), mlo(objects.size());
    if (multi)
    {
        progress.show("all objects: loading templates");
        std::vector<ObjectInfo*> all;
        for (size_t o = 0; o < objects.size(); ++o)
            all.push_back(&objects[o]);
        cv::Ptr<fm::Detector> det = multiObjectDetector(opt, setup.modalities, all);
        multi_templates = det->numTemplates();
        fm::DetectorParams p = det->getParams();
        p.nms_iou = 0; // as for one object
        p.forest.num_trees = 5;
        det->setParams(p);
        progress.show("all objects: training 5 trees");
        multi_train = trainDetector(*det, opt);
        runForestmod(*det, all, -1, ctx, "all objects: forestmod 5 trees", m5o,
                     heat_dir.empty() ? 0 : &heat_all, heat_frames);
        cv::Ptr<cv::linemod::Detector> lm = linemodCopy(*det);
        runLinemod(*lm, det, all, -1, ctx, "all objects: cv::linemod", mlo);
        m5 = pooled(m5o);
        ml = pooled(mlo);
    }
    progress.finish();

    // heat maps
    for (int kind = 0; kind < 2; ++kind)
    {
        const std::vector<std::pair<int, cv::Mat> >& heat = kind ? heat_all : heat_single;
        for (size_t i = 0; i < heat.size(); ++i)
        {
            const EvalFrame& f = frames[heat[i].first];
            double mx = 0;
            cv::minMaxLoc(heat[i].second, 0, &mx);
            const std::string file = heatFile(heat_dir, kind ? "all" : "single", f);
            if (!cv::imwrite(file, heatmapImage(f.rgb, heat[i].second, std::max(1, (int)mx))))
                CV_Error_(cv::Error::StsError, ("cannot write %s", file.c_str()));
        }
    }

    // ---- tables
    printf("## Table 1: one object per model\n\n");
    for (size_t i = 0; i < skipped.size(); ++i)
        printf("- %s: left out, no view gave a template (every modality needs features: "
               "ColorHue finds none on an unsaturated object)\n%s", skipped[i].c_str(),
               i + 1 == skipped.size() ? "\n" : "");
    printf("| object | detector | templates | T_tree | T_valid | T_quant | T_total | 2D IoU "
           ">= 0.5 | proj < 5 px | 2D @%d | proj @%d | ADD/ADI < 0.1 d | rejected |\n",
           opt.verify_k, opt.verify_k);
    printf("|---|---|---|---|---|---|---|---|---|---|---|---|---|\n");
    double s1 = 0, s5 = 0, sl = 0; // sums of the per-object median T_total
    for (size_t o = 0; o < objects.size(); ++o)
    {
        const ObjectInfo& obj = objects[o];
        printf("%s", mdRow(obj.name, "forestmod, 1 tree", obj.templates, r1[o]).c_str());
        if (opt.five_trees)
            printf("%s", mdRow(obj.name, "forestmod, 5 trees", obj.templates, r5[o]).c_str());
        printf("%s", mdRow(obj.name, "cv::linemod", obj.templates, rl[o]).c_str());
        printf("%s", mdRow(obj.name, "forestmod, 1 tree, verified", obj.templates,
                           r1v[o]).c_str());
        printf("%s", mdRow(obj.name, "cv::linemod, verified", obj.templates, rlv[o]).c_str());
        s1 += tTotal(r1[o]);
        s5 += tTotal(r5[o]);
        sl += tTotal(rl[o]);
    }
    const double n = (double)objects.size();
    printf("%s", meanRow("forestmod, 1 tree", r1).c_str());
    if (opt.five_trees)
        printf("%s", meanRow("forestmod, 5 trees", r5).c_str());
    printf("%s", meanRow("cv::linemod", rl).c_str());
    printf("%s", meanRow("forestmod, 1 tree, verified", r1v).c_str());
    printf("%s", meanRow("cv::linemod, verified", rlv).c_str());
    {
        std::vector<double> tv, tv10, tp, tpv, tb;
        for (size_t o = 0; o < objects.size(); ++o)
        {
            tv.insert(tv.end(), r1v[o].verify.begin(), r1v[o].verify.end());
            tv.insert(tv.end(), rlv[o].verify.begin(), rlv[o].verify.end());
            tv10.insert(tv10.end(), r1v[o].verify_per10.begin(), r1v[o].verify_per10.end());
            tv10.insert(tv10.end(), rlv[o].verify_per10.begin(), rlv[o].verify_per10.end());
            tp.insert(tp.end(), r1[o].pose.begin(), r1[o].pose.end());
            tpv.insert(tpv.end(), r1v[o].pose.begin(), r1v[o].pose.end());
            tb.insert(tb.end(), r1v[o].background.begin(), r1v[o].background.end());
        }
        printf("\nRecall@1 (2D IoU >= 0.5, proj < 5 px) scores each detector's first hypothesis, "
               "@%d any of its first %d (locations of the object's matches, grouped at box IoU > "
               "0.5). *verified*: the hypotheses of the matches ordered by similarity - %s x "
               "background (Detector::backgroundSimilarity, as Detector::detect() orders them; "
               "T_background for forestmod's: median %s ms, max %s ms), re-ranked by "
               "Detector::verify(), without depth with a second round of the next %d where the "
               "best of the first scores below %s (VerificationParams::second_round_below); "
               "T_verify (verification alone, up to %d hypotheses per object and frame, twice "
               "as many with a second round): median %s ms, max %s ms; per 10 verified "
               "hypotheses median %s ms, max %s ms. T_pose (forestmod's "
               "hypotheses' poses, Detector::choosePoses: with depth "
               "the first of each location's matches whose ICP pose passes the depth check; "
               "without it the first %d refined by edge alignment, %d of them past the first "
               "pass): median %s ms, max %s ms; of the verified hypotheses (both rounds): "
               "median %s ms, max %s ms.\n", opt.verify_k, opt.verify_k,
               num(ctx.verify.background_weight).c_str(),
               num(median(tb)).c_str(), num(quantile(tb, 1)).c_str(), opt.verify_k,
               num(ctx.verify.second_round_below).c_str(), opt.verify_k,
               num(median(tv)).c_str(), num(quantile(tv, 1)).c_str(),
               num(median(tv10)).c_str(), num(quantile(tv10, 1)).c_str(), opt.rgb_hypotheses,
               opt.rgb_keep, num(median(tp)).c_str(), num(quantile(tp, 1)).c_str(),
               num(median(tpv)).c_str(), num(quantile(tpv, 1)).c_str());
    }
    if (opt.gt_similarity)
        printSimilarityOnTheObject(objects, r1, rl);
    printTemplateCoverage(objects, coverage);
    printf("\nT_quant: forestmod's DetectionStats::t_quantize_ms (modalities, spreading, response "
           "maps); cv::linemod's modalities' process + pyrDown + quantize of every level, timed "
           "apart on the same frame (its spreading and response maps are in T_total only).\n");
    printf("\nTemplate rendering (cold cache, s) / forest training 1 tree / 5 trees (s):");
    for (size_t o = 0; o < objects.size(); ++o)
        printf(" %s %.1f/%.1f/%.1f%s", objects[o].name.c_str(), render[o], train1[o],
               train5[o], o + 1 < objects.size() ? "," : "\n");
    const double speedup_single = sl / s5;
    double growth_fm = std::numeric_limits<double>::quiet_NaN(), growth_lm = growth_fm,
           speedup_multi = growth_fm;
    if (multi)
    {
        printf("\n## Table 2: all %d objects in one model (%d templates, forest training "
               "%.1f s)\n\n", (int)objects.size(), multi_templates, multi_train);
        printf("| object | detector | templates | T_tree | T_valid | T_quant | T_total | "
               "2D IoU >= 0.5 | proj < 5 px | 2D @%d | proj @%d | ADD/ADI < 0.1 d | rejected "
               "|\n", opt.verify_k, opt.verify_k);
        printf("|---|---|---|---|---|---|---|---|---|---|---|---|---|\n");
        printf("%s", mdRow("**all**", "forestmod, 5 trees", multi_templates, m5).c_str());
        printf("%s", mdRow("**all**", "cv::linemod", multi_templates, ml).c_str());
        for (size_t o = 0; o < objects.size(); ++o)
        {
            printf("%s", mdRow(objects[o].name, "forestmod, 5 trees", multi_templates,
                               m5o[o]).c_str());
            printf("%s", mdRow(objects[o].name, "cv::linemod", multi_templates, mlo[o]).c_str());
        }
        speedup_multi = tTotal(ml) / tTotal(m5);
        growth_fm = tTotal(m5) / (s5 / n);
        growth_lm = tTotal(ml) / (sl / n);
    }
    printf("\n## Summary\n\n");
    printf("- speed-up, one object per model: cv::linemod / forestmod (5 trees) = %s "
           "(1 tree: %s), mean of the per-object median T_total\n",
           num(speedup_single).c_str(), num(sl / s1).c_str());
    if (multi)
    {
        printf("- speed-up, all objects in one model: cv::linemod / forestmod (5 trees) = %s\n",
               num(speedup_multi).c_str());
        printf("- time growth, all objects in one model / mean single-object model: forestmod "
               "(5 trees) %s, cv::linemod %s (%d objects)\n",
               num(growth_fm).c_str(), num(growth_lm).c_str(), (int)objects.size());
    }
    printf("\n");
    fflush(stdout);

    // ---- JSON
    if (fs.isOpened())
    {
        fs << "frames" << frames_per_object;
        fs << "objects" << "[";
        for (size_t o = 0; o < objects.size(); ++o)
        {
            fs << "{";
            fs << "obj_id" << objects[o].obj_id << "name" << objects[o].name;
            fs << "templates" << objects[o].templates;
            fs << "template_coverage_deg" << "{";
            writeNumber(fs, "median", median(coverage[o]));
            writeNumber(fs, "max", quantile(coverage[o], 1));
            fs << "}";
            writeResult(fs, "forestmod", r1[o], true);
            writeResult(fs, "forestmod_5", r5[o], true);
            writeResult(fs, "linemod", rl[o], true);
            writeResult(fs, "forestmod_verified", r1v[o], true);
            writeResult(fs, "linemod_verified", rlv[o], true);
            fs << "train_s" << "{" << "forestmod" << train1[o] << "forestmod_5" << train5[o]
               << "}";
            fs << "}";
        }
        fs << "]";
        if (multi)
        {
            fs << "multi" << "{";
            fs << "objects" << (int)objects.size() << "templates" << multi_templates;
            writeResult(fs, "forestmod", m5, false);
            writeResult(fs, "linemod", ml, false);
            fs << "train_s" << multi_train;
            fs << "}";
        }
        else
            fs << "multi" << "n/a";
        fs << "summary" << "{";
        writeNumber(fs, "speedup_single", speedup_single);
        writeNumber(fs, "speedup_single_1tree", sl / s1);
        writeNumber(fs, "speedup_multi", speedup_multi);
        writeNumber(fs, "growth_multi_over_single", growth_fm);
        writeNumber(fs, "growth_multi_over_single_linemod", growth_lm);
        fs << "}";
    }
    return 0;
}

} // namespace fmeval
