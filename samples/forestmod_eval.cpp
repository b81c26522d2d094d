// This file is part of OpenCV project.
// It is subject to the license terms in the LICENSE file found in the top-level directory
// of this distribution and at http://opencv.org/license.html

// Evaluation of forestmod::Detector against cv::linemod::Detector on a BOP dataset (e.g. LM-O)
// or on rendered RGB-D scenes: the paper's Table 1 (one object per model: T_tree, T_valid,
// T_total, accuracy, locations rejected, for 1 and 5 trees and for cv::linemod), Table 2 (all
// objects in one model) and the scaling of match() time with the templates of one object and
// with the classes of one model (JSON + PNG plots). Both detectors get the same templates,
// modalities, pyramid and frames. See doc/tutorial_train_detect_eval.md and doc/evaluation.md.
//
// The parts: samples/eval/eval_options.cpp (command line, regimes), eval_templates.cpp
// (template cache), eval_run.cpp (runners, scoring), eval_tables.cpp (Tables 1 and 2),
// eval_sweep.cpp (scaling sweeps), eval_report.cpp (rows, JSON, heat maps, plots).

#include "eval/eval_common.hpp"

#include <opencv2/core/utils/filesystem.hpp>

#include <algorithm>
#include <cstdio>
#include <iostream>

using namespace fmeval;

/** The dataset's objects (--objects, or every model with a mesh). */
static bool loadObjects(const EvalOptions& opt, const fm::BopDataset& ds,
                        std::vector<ObjectInfo>& objects)
{
    std::vector<int> ids = opt.object_ids;
    if (ids.empty())
    {
        const std::vector<fm::ModelInfo> models = ds.models();
        for (size_t i = 0; i < models.size(); ++i)
            if (cv::utils::fs::exists(models[i].mesh_path))
                ids.push_back(models[i].obj_id);
    }
    if (ids.empty())
    {
        std::cerr << "forestmod_eval: no object with a mesh in " << opt.root << "/models\n";
        return false;
    }
    for (size_t i = 0; i < ids.size(); ++i)
    {
        const fm::ModelInfo mi = ds.model(ids[i]);
        if (!cv::utils::fs::exists(mi.mesh_path))
        {
            std::cerr << "forestmod_eval: object " << ids[i] << " has no mesh (" << mi.mesh_path
                      << ")\n";
            return false;
        }
        ObjectInfo o;
        o.obj_id = mi.obj_id;
        o.name = lmoName(mi.obj_id);
        o.class_id = o.name;
        o.mesh_path = mi.mesh_path;
        o.mesh = fm::Mesh::load(mi.mesh_path);
        o.diameter = mi.diameter > 0 ? mi.diameter : o.mesh.diameter();
        o.symmetric = mi.symmetric;
        o.symmetries = mi.symmetries_discrete;
        const size_t step = std::max<size_t>(1, o.mesh.vertices.size() / 2000);
        for (size_t k = 0; k < o.mesh.vertices.size(); k += step)
            o.pts.push_back(o.mesh.vertices[k]);
        objects.push_back(o);
    }
    return true;
}

/** --synthetic: N rendered RGB-D scenes per object: the object at a random template pose
(perturbed, moved in the image), the other meshes as clutter, the dataset's frames as colour
background. */
static void syntheticFrames(const EvalOptions& opt, const fm::BopDataset& ds,
                            std::vector<ObjectInfo>& objects, const TemplateSetup& setup,
                            const std::vector<fm::Frame>& dframes, size_t nuse,
                            std::vector<EvalFrame>& frames)
{
    Progress progress;
    cv::Ptr<fm::Renderer> renderer = fm::Renderer::create(setup.size);
    fm::SceneSynthesizer synth(renderer, setup.K);
    for (size_t o = 0; o < objects.size(); ++o)
        synth.addObject(objects[o].mesh);
    // the dataset's other meshes are clutter too
    const std::vector<fm::ModelInfo> models = ds.models();
    for (size_t i = 0; i < models.size(); ++i)
    {
        bool used = false;
        for (size_t o = 0; o < objects.size(); ++o)
            used = used || objects[o].obj_id == models[i].obj_id;
        if (!used && cv::utils::fs::exists(models[i].mesh_path))
            synth.addObject(fm::Mesh::load(models[i].mesh_path));
    }
    std::vector<cv::Mat> backgrounds;
    for (size_t i = 0; i < nuse; ++i)
        backgrounds.push_back(dframes[i].rgb());
    synth.setBackgrounds(backgrounds);
    cv::RNG rng((uint64)opt.seed);
    for (size_t o = 0; o < objects.size(); ++o)
    {
        double render_s = 0;
        cv::Ptr<fm::Detector> det = objectTemplates(opt, objects[o], setup, progress, render_s);
        if (!det)
            continue; // no template: left out
        // the poses of the object's templates (not every sampler pose gives one)
        std::vector<fm::TemplatePose> poses;
        for (int i = 0; i < det->numTemplates(objects[o].class_id); ++i)
            poses.push_back(det->getTemplatePose(objects[o].class_id, i));
        for (int n = 0; n < opt.synthetic; ++n)
        {
            progress.show(cv::format("%s: rendering scene %d/%d", objects[o].name.c_str(), n + 1,
                                     opt.synthetic));
            const fm::TemplatePose& vp = poses[rng.uniform(0, (int)poses.size())];
            const fm::SyntheticScene s = synth.render((int)o, vp.R, vp.t, rng);
            EvalFrame f;
            f.scene_id = 0;
            f.im_id = (int)(o * opt.synthetic + n);
            f.rgb = s.color;
            f.depth = s.depth;
            f.K = setup.K;
            fm::GroundTruth g;
            g.obj_id = objects[o].obj_id;
            g.R = s.R;
            g.t = s.t;
            g.bbox_obj = cv::Rect(); // projected at scoring time
            g.visib_fract = s.visible;
            f.gt.push_back(g);
            f.owner = (int)o;
            frames.push_back(f);
        }
    }
    progress.finish();
}

static std::string samplingLine(const EvalOptions& opt)
{
    std::string overrides;
    for (size_t i = 0; i < opt.sampler_overrides.size(); ++i)
        overrides += (i ? ", " : "; overridden: ") + opt.sampler_overrides[i];
    return cv::format("- templates (the same for every detector): regime %s%s: %s\n",
                      opt.regime.c_str(), overrides.c_str(), samplingText(opt.sampler).c_str());
}

static int run(const EvalOptions& opt)
{
    // outputs that must not be overwritten
    std::vector<std::string> outputs = sweepOutputs(opt);
    if (!opt.json_path.empty())
        outputs.push_back(opt.json_path);
    for (size_t i = 0; i < outputs.size(); ++i)
        if (cv::forestmod::samples::refuseOutput("forestmod_eval", outputs[i], opt.force))
            return 1;
    cv::setNumThreads(opt.threads);

    fm::BopDataset ds = fm::BopDataset::open(opt.root, opt.split);
    TemplateSetup setup;
    setup.sampler = fm::ViewSampler(opt.sampler);
    setup.subset = 0;
    setup.K = ds.cameraK();
    setup.size = ds.imageSize();
    std::vector<ObjectInfo> objects;
    if (!loadObjects(opt, ds, objects))
        return 1;

    std::vector<fm::Frame> dframes = ds.frames(opt.scene);
    // --first_frame: frames held out of a run (e.g. to set a parameter on frames not reported)
    dframes.erase(dframes.begin(),
                  dframes.begin() + std::min<size_t>((size_t)opt.first_frame, dframes.size()));
    if (dframes.empty())
    {
        std::cerr << "forestmod_eval: scene " << opt.scene << " of " << opt.root << "/"
                  << opt.split << " has no frames (after --first_frame=" << opt.first_frame
                  << ")\n";
        return 1;
    }
    const size_t nuse = opt.max_frames > 0 ? std::min<size_t>(opt.max_frames, dframes.size())
                                           : dframes.size();
    bool all_depth = true;
    for (size_t i = 0; i < nuse; ++i)
        all_depth = all_depth && !dframes[i].depth_path.empty();
    const bool use_depth = (opt.synthetic > 0 || all_depth) && !opt.rgb_only;
    if (opt.modalities_arg.empty())
    {
        setup.modalities.push_back("ColorGradient");
        if (use_depth)
            setup.modalities.push_back("DepthNormal");
        setup.modalities.push_back("ColorHue");
    }
    for (size_t i = 0; i < opt.modalities_arg.size(); ++i)
    {
        const std::string& m = opt.modalities_arg[i];
        if (m != "ColorGradient" && m != "DepthNormal" && m != "ColorHue")
        {
            std::cerr << "forestmod_eval: unknown modality '" << m << "' (ColorGradient, "
                         "DepthNormal, ColorHue)\n";
            return 1;
        }
        if (m == "DepthNormal" && !use_depth)
        {
            std::cerr << "forestmod_eval: DepthNormal needs depth (the frames have none, or "
                         "--rgb_only)\n";
            return 1;
        }
        setup.modalities.push_back(m);
    }
    cv::utils::fs::createDirectories(opt.cache_dir);
    if (!cv::utils::fs::isDirectory(opt.cache_dir))
    {
        std::cerr << "forestmod_eval: cannot create the cache folder " << opt.cache_dir << "\n";
        return 1;
    }

    std::vector<EvalFrame> frames;
    if (opt.synthetic == 0)
        for (size_t i = 0; i < nuse; ++i)
        {
            EvalFrame f;
            f.scene_id = dframes[i].scene_id;
            f.im_id = dframes[i].im_id;
            f.rgb = dframes[i].rgb();
            if (use_depth)
                f.depth = dframes[i].depth();
            f.K = dframes[i].K;
            f.gt = dframes[i].gt;
            f.owner = -1;
            frames.push_back(f);
        }
    else
        syntheticFrames(opt, ds, objects, setup, dframes, nuse, frames);

    const std::string mode = use_depth ? "RGB-D" : "RGB only";
    std::string modnames;
    for (size_t i = 0; i < setup.modalities.size(); ++i)
        modnames += (i ? " + " : "") + setup.modalities[i];
    printf("# forestmod_eval\n\n");
    if (opt.synthetic > 0)
        printf("- data: %d rendered RGB-D scenes per object (SceneSynthesizer: clutter from "
               "the other meshes, backgrounds from %d frames of %s scene %d)\n",
               opt.synthetic, (int)nuse, opt.root.c_str(), opt.scene);
    else
        printf("- data: %s, split %s, scene %d, %d frames (the first %d skipped)\n",
               opt.root.c_str(), opt.split.c_str(), opt.scene, (int)frames.size(),
               opt.first_frame);
    printf("- mode: %s; modalities %s; pyramid T = {5, 8}; threshold %.0f; %d OpenCV "
           "thread(s) while matching (cv::setNumThreads; %d while training the forests)\n",
           mode.c_str(), modnames.c_str(), opt.threshold, opt.threads, opt.train_threads);
    printf("%s", samplingLine(opt).c_str());
    printf("- times: median over frames of the best of %d match() calls per frame, ms "
           "(T_total includes the modalities' quantization, T_quant); T_tree, T_valid and "
           "rejected are forestmod's DetectionStats\n", opt.repeat);
    printf("- accuracy of the best match per object: 2D = box of the projected model at the "
           "match's pose (%s), IoU >= 0.5 with bbox_obj; proj = 2D projection error < 5 px; "
           "ADD = ADD (ADI for symmetric objects) < 0.1 d after ICP (RGB-D only)\n\n",
           use_depth ? "after ICP" : opt.rgb_refine ? "refined by edge alignment"
                                                    : "the template's pose");
    fflush(stdout);

    cv::FileStorage fs;
    if (!opt.json_path.empty())
    {
        fs.open(opt.json_path, cv::FileStorage::WRITE | cv::FileStorage::FORMAT_JSON);
        if (!fs.isOpened())
            CV_Error_(cv::Error::StsError, ("cannot write %s", opt.json_path.c_str()));
        fs << "regime" << opt.regime;
        fs << "sampling" << samplingText(opt.sampler);
        fs << "sampler" << "{";
        opt.sampler.write(fs);
        fs << "}";
        fs << "poses_per_object" << fm::ViewSampler(opt.sampler).size();
        fs << "modalities" << modnames << "mode" << mode;
        fs << "threshold" << opt.threshold << "threads" << opt.threads;
        fs << "repetitions" << opt.repeat;
    }
    int rc = 0;
    if (opt.tables)
        rc = runTables(opt, objects, frames, setup, use_depth, fs);
    if (rc == 0)
        rc = runSweeps(opt, objects, frames, setup, use_depth, fs);
    if (fs.isOpened())
    {
        fs.release();
        std::cerr << "wrote " << opt.json_path << "\n";
    }
    return rc;
}

int main(int argc, char** argv)
{
    try
    {
        EvalOptions opt;
        const int rc = parseOptions(argc, argv, opt);
        if (rc != 0)
            return rc < 0 ? 0 : rc;
        if (opt.dry_run)
        {
            printf("# forestmod_eval (dry run)\n\n%s", samplingLine(opt).c_str());
            return 0;
        }
        return run(opt);
    }
    catch (const cv::Exception& e)
    {
        std::cerr << "\nforestmod_eval: " << e.what() << std::endl;
        return 1;
    }
}
