// This file is part of OpenCV project.
// It is subject to the license terms in the LICENSE file found in the top-level directory
// of this distribution and at http://opencv.org/license.html

// A forestmod model + a colour image (and optional depth) -> matches with 6-DoF poses on stdout,
// and an overlay PNG (box, projected model outline, axes, class and score). With a BOP dataset
// frame, the ground truth is read too and the pose errors are printed. With --linemod,
// cv::linemod::Detector matches the frame with the same templates: both match() times and its
// best match per class.

#include <opencv2/core.hpp>
#include <opencv2/core/utils/filesystem.hpp>
#include <opencv2/calib3d.hpp>
#include <opencv2/forestmod.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "sample_utils.hpp"
#include <cstdio>
#include <iostream>
#include <map>
#include <sstream>

using cv::forestmod::samples::splitList;
using cv::forestmod::samples::lmoIntrinsics;
using cv::forestmod::samples::linemodCopy;

static const char* keys
    = "{help h usage ?  |      | print this message }"
      "{model           |      | model file written by forestmod_train }"
      "{color           |      | colour image (BGR) }"
      "{depth           |      | optional 16-bit depth image (mm) }"
      "{K               |      | fx,fy,cx,cy of the images (default: LM-O's Kinect, or the "
      "dataset's) }"
      "{meshes          |      | class=mesh,... for poses refined with depth and for drawing }"
      "{dataset         |      | BOP dataset root: read the frame, K, meshes and ground truth "
      "from it }"
      "{scene           | 2    | dataset scene id }"
      "{frame           | -1   | dataset image id }"
      "{threshold       | 80   | LINEMOD similarity threshold (percent) }"
      "{top             | 1    | detections printed and drawn per class, best first (the "
      "verification's order; their scores on the overlay) }"
      "{verify          | true | verify and re-rank the detections (PoseParams::verification) }"
      "{verify_k        | 10   | hypotheses verified per class (VerificationParams::top_k) }"
      "{second_round    | -1   | without depth: the next verify_k are verified for a class whose "
      "best scores below this (VerificationParams::second_round_below; 0: one round; -1: the "
      "library's default) }"
      "{rgb_hypotheses  | 24   | without depth: matches a detection's pose is chosen among "
      "(PoseParams::rgb_hypotheses) }"
      "{rgb_keep        | 4    | without depth: of those, refined past the first pass "
      "(PoseParams::rgb_keep) }"
      "{search_per_class | false | a model of several classes: each class keeps lists of its "
      "own, its matches those of its templates alone (DetectorParams::search_per_class; slower) }"
      "{exhaustive_ratio |      | DetectorParams::exhaustive_ratio (empty: the model's; 0: every "
      "search group searched exhaustively, negative: every group on the forest path) }"
      "{descent_cost    |      | DetectorParams::descent_cost (empty: the model's; 0: the "
      "scan's sample counts the pairs only, not the trees' descents) }"
      "{linemod         |      | also match the frame with cv::linemod::Detector and the same "
      "templates: both match() times (1 thread, best of --repeat calls) and its best match per "
      "class }"
      "{repeat          | 3    | --linemod: match() calls per detector }"
      "{out             |      | overlay PNG }"
      "{force           |      | overwrite the overlay }";

// "obj_000001" or "1" -> 1; anything else -> -1
static int objectId(const std::string& class_id)
{
    const size_t p = class_id.find_first_of("0123456789");
    if (p == std::string::npos)
        return -1;
    if (class_id.compare(0, 4, "obj_") != 0 && p != 0)
        return -1;
    return atoi(class_id.c_str() + p);
}

// --linemod: match() of the frame by both detectors with the same templates and 1 thread (the
// best of `repeat` calls each), and cv::linemod's best match per class against forestmod's first
// detection of that class (`detections`, the verification's order).
static void compareWithLinemod(const cv::forestmod::Detector& detector,
                               const std::vector<cv::Mat>& sources, float threshold, int repeat,
                               const std::vector<cv::forestmod::PoseMatch>& detections)
{
    cv::Ptr<cv::linemod::Detector> lm = linemodCopy(detector);
    std::vector<cv::linemod::Match> fm_matches, lm_matches;
    double t_fm = 1e30, t_lm = 1e30;
    const int threads = cv::getNumThreads();
    cv::setNumThreads(1);
    for (int r = 0; r < repeat; ++r)
    {
        cv::forestmod::DetectionStats stats;
        detector.match(sources, threshold, fm_matches, std::vector<cv::String>(), cv::noArray(),
                       std::vector<cv::Mat>(), &stats);
        t_fm = std::min(t_fm, stats.t_total_ms);
        cv::TickMeter tm;
        tm.start();
        lm->match(sources, threshold, lm_matches);
        tm.stop();
        t_lm = std::min(t_lm, tm.getTimeMilli());
    }
    cv::setNumThreads(threads);
    printf("match(), 1 thread, best of %d calls, %d templates: forestmod %.1f ms (%d matches), "
           "cv::linemod %.1f ms (%d matches): %.1fx\n", repeat, lm->numTemplates(), t_fm,
           (int)fm_matches.size(), t_lm, (int)lm_matches.size(), t_lm / t_fm);
    const std::vector<cv::String> classes = detector.classIds();
    for (size_t c = 0; c < classes.size(); ++c)
    {
        bool found = false;
        for (size_t i = 0; i < lm_matches.size() && !found; ++i) // best first
        {
            const cv::linemod::Match& m = lm_matches[i];
            if (m.class_id != classes[c])
                continue;
            const std::vector<cv::linemod::Template>& t = lm->getTemplates(m.class_id,
                                                                           m.template_id);
            const cv::Rect box(m.x, m.y, t[0].width, t[0].height);
            printf("cv::linemod's best match: %s score %.1f box (%d,%d %dx%d) template %d",
                   m.class_id.c_str(), m.similarity, box.x, box.y, box.width, box.height,
                   m.template_id);
            for (size_t d = 0; d < detections.size(); ++d)
                if (detections[d].class_id == m.class_id)
                {
                    printf("; box IoU %.2f with forestmod's first detection",
                           cv::forestmod::boxIoU(cv::Rect2d(box),
                                                 cv::Rect2d(detections[d].box)));
                    break;
                }
            printf("\n");
            found = true;
        }
        if (!found)
            printf("cv::linemod's best match: %s none\n", classes[c].c_str());
    }
}

static void drawPose(cv::Mat& img, const cv::forestmod::PoseMatch& m, const cv::Matx33d& K,
                     const cv::forestmod::Mesh* mesh, cv::forestmod::Renderer* renderer,
                     int handle, const cv::Scalar& colour, int rank)
{
    cv::rectangle(img, m.box, colour, 2);
    if (m.has_pose)
    {
        if (renderer && handle >= 0)
        {
            cv::Mat mask;
            renderer->render(handle, m.R, m.t, K, cv::noArray(), cv::noArray(), mask);
            std::vector<std::vector<cv::Point> > contours;
            cv::findContours(mask, contours, cv::RETR_EXTERNAL, cv::CHAIN_APPROX_SIMPLE);
            cv::drawContours(img, contours, -1, colour, 2);
        }
        const double len = mesh ? 0.5 * mesh->diameter() : 50.0;
        const cv::Point3f c = mesh ? mesh->center() : cv::Point3f();
        std::vector<cv::Point3f> axes;
        axes.push_back(c);
        axes.push_back(c + cv::Point3f((float)len, 0, 0));
        axes.push_back(c + cv::Point3f(0, (float)len, 0));
        axes.push_back(c + cv::Point3f(0, 0, (float)len));
        cv::Mat rvec;
        cv::Rodrigues(cv::Mat(m.R), rvec);
        std::vector<cv::Point2f> p;
        cv::projectPoints(axes, rvec, cv::Mat(m.t), cv::Mat(K), cv::noArray(), p);
        cv::line(img, p[0], p[1], cv::Scalar(0, 0, 255), 2);
        cv::line(img, p[0], p[2], cv::Scalar(0, 255, 0), 2);
        cv::line(img, p[0], p[3], cv::Scalar(255, 0, 0), 2);
    }
    // "#rank class similarity", and the verification score with its parts when verified
    std::string label = cv::format("#%d %s %.1f", rank, m.class_id.c_str(), m.similarity);
    if (m.verification >= 0)
        label += cv::format(" v %.2f (c %.2f e %.2f r %.2f%s)", m.verification, m.color_score,
                            m.edge_score, m.region_score,
                            m.depth_score >= 0 ? cv::format(" d %.2f", m.depth_score).c_str()
                                               : "");
    cv::putText(img, label, m.box.tl() + cv::Point(0, -6), cv::FONT_HERSHEY_SIMPLEX, 0.5, colour,
                rank == 1 ? 2 : 1);
}

int main(int argc, char** argv)
{
    cv::CommandLineParser parser(argc, argv, keys);
    parser.about("forestmod_detect: matches with 6-DoF poses, and an overlay");
    if (parser.has("help"))
    {
        parser.printMessage();
        return 0;
    }
    const std::string model = parser.get<std::string>("model");
    std::string color_path = parser.get<std::string>("color");
    std::string depth_path = parser.get<std::string>("depth");
    const std::string dataset = parser.get<std::string>("dataset");
    const int scene_id = parser.get<int>("scene"), frame_id = parser.get<int>("frame");
    const float threshold = parser.get<float>("threshold");
    const int top = parser.get<int>("top");
    const bool verify = parser.get<bool>("verify");
    const int verify_k = parser.get<int>("verify_k");
    const double second_round = parser.get<double>("second_round");
    const bool with_linemod = parser.has("linemod");
    const int repeat = parser.get<int>("repeat");
    cv::forestmod::PoseParams pose_params;
    pose_params.rgb_hypotheses = parser.get<int>("rgb_hypotheses");
    pose_params.rgb_keep = parser.get<int>("rgb_keep");
    const bool search_per_class = parser.get<bool>("search_per_class");
    const bool set_ratio = parser.has("exhaustive_ratio");
    const float exhaustive_ratio = set_ratio ? parser.get<float>("exhaustive_ratio") : 0.f;
    const bool set_descent = parser.has("descent_cost");
    const float descent_cost = set_descent ? parser.get<float>("descent_cost") : 0.f;
    const std::string out = parser.get<std::string>("out");
    const std::string Kstr = parser.get<std::string>("K");
    const std::string meshes_arg = parser.get<std::string>("meshes");
    if (!parser.check())
    {
        parser.printErrors();
        return 1;
    }
    if (model.empty() || (color_path.empty() && dataset.empty()))
    {
        std::cerr << "forestmod_detect: --model and --color (or --dataset with --frame) are "
                     "required (see --help)\n";
        return 1;
    }
    if (repeat < 1)
    {
        std::cerr << "forestmod_detect: --repeat must be at least 1\n";
        return 1;
    }
    if (!(second_round >= 0 || second_round == -1) || !(second_round < 1e6))
    {
        std::cerr << "forestmod_detect: --second_round must be finite and >= 0 (-1: the "
                     "library's default)\n";
        return 1;
    }
    if (!cv::utils::fs::exists(model))
    {
        std::cerr << "forestmod_detect: model not found: " << model << "\n";
        return 1;
    }
    if (!out.empty()
        && cv::forestmod::samples::refuseOutput("forestmod_detect", out, parser.has("force")))
        return 1;
    try
    {
        cv::Matx33d K = lmoIntrinsics();
        std::vector<cv::forestmod::GroundTruth> gt;
        std::map<std::string, std::string> mesh_paths;
        cv::Mat color, depth;
        cv::Ptr<cv::forestmod::BopDataset> ds;
        if (!dataset.empty())
        {
            if (!cv::utils::fs::exists(dataset))
            {
                std::cerr << "forestmod_detect: dataset not found: " << dataset << "\n";
                return 1;
            }
            ds = cv::makePtr<cv::forestmod::BopDataset>(cv::forestmod::BopDataset::open(dataset));
            const std::vector<cv::forestmod::Frame> frames = ds->frames(scene_id);
            const cv::forestmod::Frame* f = 0;
            for (size_t i = 0; i < frames.size(); ++i)
                if (frames[i].im_id == frame_id)
                    f = &frames[i];
            if (!f)
            {
                std::cerr << "forestmod_detect: scene " << scene_id << " has no frame " << frame_id
                          << "\n";
                return 1;
            }
            color = f->rgb();
            depth = f->depth();
            K = f->K;
            gt = f->gt;
        }
        else
        {
            const cv::Mat raw = cv::imread(color_path, cv::IMREAD_UNCHANGED);
            if (raw.empty())
            {
                std::cerr << "forestmod_detect: cannot read an image from " << color_path << "\n";
                return 1;
            }
            if (raw.depth() != CV_8U)
            {
                // IMREAD_COLOR would turn a 16-bit depth image into 8-bit grey silently
                std::cerr << "forestmod_detect: " << color_path << " is "
                          << cv::typeToString(raw.type())
                          << "; --color takes an 8-bit colour image (a depth image goes to "
                             "--depth)\n";
                return 1;
            }
            color = cv::imread(color_path, cv::IMREAD_COLOR);
            if (!depth_path.empty())
            {
                depth = cv::imread(depth_path, cv::IMREAD_ANYDEPTH);
                if (depth.empty() || depth.type() != CV_16UC1)
                {
                    std::cerr << "forestmod_detect: " << depth_path
                              << " is not a 16-bit depth image\n";
                    return 1;
                }
            }
        }
        if (!Kstr.empty())
        {
            std::vector<std::string> k = splitList(Kstr, ',');
            if (k.size() != 4)
            {
                std::cerr << "forestmod_detect: --K is fx,fy,cx,cy\n";
                return 1;
            }
            K = cv::Matx33d(atof(k[0].c_str()), 0, atof(k[2].c_str()), 0, atof(k[1].c_str()),
                            atof(k[3].c_str()), 0, 0, 1);
            if (!(K(0, 0) > 0) || !(K(1, 1) > 0) || !cv::checkRange(cv::Mat(K)))
            {
                std::cerr << "forestmod_detect: --K needs finite numbers, fx and fy > 0\n";
                return 1;
            }
        }
        std::vector<std::string> pairs = splitList(meshes_arg, ',');
        for (size_t i = 0; i < pairs.size(); ++i)
        {
            const size_t eq = pairs[i].find('=');
            if (eq == std::string::npos)
            {
                std::cerr << "forestmod_detect: --meshes takes class=path pairs\n";
                return 1;
            }
            mesh_paths[pairs[i].substr(0, eq)] = pairs[i].substr(eq + 1);
        }

        cv::forestmod::Detector detector;
        detector.load(model);
        if (search_per_class || set_ratio || set_descent)
        {
            cv::forestmod::DetectorParams dp = detector.getParams();
            dp.search_per_class = dp.search_per_class || search_per_class;
            if (set_ratio)
                dp.exhaustive_ratio = exhaustive_ratio;
            if (set_descent)
                dp.descent_cost = descent_cost;
            detector.setParams(dp);
        }
        const std::vector<cv::String> classes = detector.classIds();
        std::map<std::string, cv::forestmod::Mesh> meshes;
        for (size_t i = 0; i < classes.size(); ++i)
        {
            std::string path = mesh_paths.count(classes[i]) ? mesh_paths[classes[i]] : "";
            if (path.empty() && ds && objectId(classes[i]) > 0)
                path = ds->modelPath(objectId(classes[i]));
            if (!path.empty() && cv::utils::fs::exists(path))
            {
                meshes[classes[i]] = cv::forestmod::Mesh::load(path);
                detector.setMesh(classes[i], meshes[classes[i]]);
            }
        }
        // sources in the detector's modality order
        std::vector<cv::Mat> sources;
        const std::vector<cv::Ptr<cv::linemod::Modality> >& mods = detector.getModalities();
        for (size_t i = 0; i < mods.size(); ++i)
        {
            if (mods[i]->name() == "DepthNormal")
            {
                if (depth.empty())
                {
                    std::cerr << "forestmod_detect: the model uses depth (DepthNormal): pass "
                                 "--depth\n";
                    return 1;
                }
                sources.push_back(depth);
            }
            else
                sources.push_back(color);
        }
        if (!detector.isTrained()) // else the first match() would train, inside its time
        {
            cv::TickMeter tm;
            tm.start();
            detector.train();
            tm.stop();
            printf("forests trained in %.1f s (the model file has none)\n", tm.getTimeSec());
        }
        cv::forestmod::DetectionStats stats;
        std::vector<cv::forestmod::PoseMatch> matches;
        pose_params.verification.enabled = verify;
        pose_params.verification.top_k = verify_k;
        if (second_round >= 0)
            pose_params.verification.second_round_below = second_round;
        detector.detect(sources, K, threshold, matches, std::vector<cv::String>(), pose_params,
                        &stats);
        printf("%d matches in %.1f ms (quantize %.1f, forest %.1f, validation %.1f); %.1f %% of "
               "%lld locations rejected before validation\n",
               (int)matches.size(), stats.t_total_ms, stats.t_quantize_ms, stats.t_tree_ms,
               stats.t_valid_ms, 100 * stats.rejectedFraction(), (long long)stats.locations);
        if (verify)
            printf("background of the matches: %.1f ms; verification: %lld hypotheses in %.1f "
                   "ms\n", stats.t_background_ms, (long long)stats.verified, stats.t_verify_ms);
        if (with_linemod)
            compareWithLinemod(detector, sources, threshold, repeat, matches);

        cv::Mat overlay = color.clone();
        cv::Ptr<cv::forestmod::Renderer> renderer;
        std::map<std::string, int> handles;
        if (!out.empty() && !meshes.empty())
        {
            renderer = cv::forestmod::Renderer::create(color.size());
            for (std::map<std::string, cv::forestmod::Mesh>::const_iterator it = meshes.begin();
                 it != meshes.end(); ++it)
                handles[it->first] = renderer->addMesh(it->second);
        }
        std::map<std::string, int> shown;
        for (size_t i = 0; i < matches.size(); ++i)
        {
            const cv::forestmod::PoseMatch& m = matches[i];
            const int rank = ++shown[m.class_id];
            if (rank > top)
                continue;
            printf("%s score %.1f box (%d,%d %dx%d) template %d", m.class_id.c_str(), m.similarity,
                   m.box.x, m.box.y, m.box.width, m.box.height, m.template_id);
            if (m.background >= 0) // its template's similarity over the rest of the frame
                printf(" background %.1f", m.background);
            if (m.has_pose)
            {
                cv::Vec3d rvec;
                cv::Rodrigues(m.R, rvec);
                printf(" pose: rvec (%.3f %.3f %.3f) t (%.1f %.1f %.1f) mm%s", rvec[0], rvec[1],
                       rvec[2], m.t[0], m.t[1], m.t[2],
                       !m.refined ? ""
                       : depth.empty() ? " [refined: edge alignment]" : " [refined by ICP]");
                if (m.depth_agreement >= 0)
                    printf(" depth check %.2f", m.depth_agreement);
            }
            if (m.verification >= 0)
            {
                printf(" verification %.3f (colour %.2f, edges %.2f, region %.2f", m.verification,
                       m.color_score, m.edge_score, m.region_score);
                if (m.depth_score >= 0)
                    printf(", depth %.2f", m.depth_score);
                printf(", occluded %.2f)", m.occlusion);
            }
            printf("\n");
            const int obj = objectId(m.class_id);
            for (size_t g = 0; g < gt.size(); ++g)
            {
                if (gt[g].obj_id != obj || !m.has_pose || !meshes.count(m.class_id))
                    continue;
                const cv::forestmod::Mesh& mesh = meshes[m.class_id];
                std::vector<cv::Point3f> pts(mesh.vertices.begin(), mesh.vertices.end());
                const double diameter = mesh.diameter();
                const bool sym = ds && ds->model(obj).symmetric;
                const double add = sym ? cv::forestmod::adiError(pts, m.R, m.t, gt[g].R, gt[g].t)
                                       : cv::forestmod::addError(pts, m.R, m.t, gt[g].R, gt[g].t);
                const double proj
                    = cv::forestmod::projectionError2D(pts, K, m.R, m.t, gt[g].R, gt[g].t);
                const double iou = cv::forestmod::boxIoU(cv::Rect2d(m.box),
                                                         cv::Rect2d(gt[g].bbox_obj));
                printf("  vs ground truth: %s %.1f mm (%.2f d: %s), 2D projection error %.1f px "
                       "(%s), box IoU %.2f (%s)\n",
                       sym ? "ADI" : "ADD", add, add / diameter,
                       cv::forestmod::isCorrect(add, diameter) ? "correct" : "wrong", proj,
                       proj < 5 ? "< 5 px" : ">= 5 px", iou, iou >= 0.5 ? ">= 0.5" : "< 0.5");
            }
            if (!out.empty())
            {
                const bool has_mesh = meshes.count(m.class_id) > 0;
                // the first detection of a class in yellow, the next ones darker
                const double fade = 1.0 / rank;
                drawPose(overlay, m, K, has_mesh ? &meshes[m.class_id] : 0, renderer.get(),
                         has_mesh && renderer ? handles[m.class_id] : -1,
                         cv::Scalar(0, 255 * fade, 255 * (0.4 + 0.6 * fade)), rank);
            }
        }
        if (!out.empty())
        {
            for (size_t g = 0; g < gt.size(); ++g)
                for (size_t c = 0; c < classes.size(); ++c)
                    if (objectId(classes[c]) == gt[g].obj_id)
                        cv::rectangle(overlay, gt[g].bbox_obj, cv::Scalar(0, 255, 0), 1);
            if (!cv::imwrite(out, overlay))
            {
                std::cerr << "forestmod_detect: cannot write " << out << "\n";
                return 1;
            }
            printf("overlay: %s (yellow: detection, green: ground-truth box)\n", out.c_str());
        }
    }
    catch (const cv::Exception& e)
    {
        std::cerr << "forestmod_detect: " << e.what() << std::endl;
        return 1;
    }
    return 0;
}
