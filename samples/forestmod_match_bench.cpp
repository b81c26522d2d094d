// This file is part of OpenCV project.
// It is subject to the license terms in the LICENSE file found in the top-level directory
// of this distribution and at http://opencv.org/license.html

// match() benchmark of one trained model on a BOP scene's RGB frames, for profiling: the model is
// built once from untrained model files (e.g. forestmod_eval's template cache, one or more classes
// each, every file's classes in one detector), trained and written to --trained; later runs read
// that file (an existing file is never overwritten). Per frame the best of 3 calls of the whole
// match() (the library's defaults but --trees, RGB: every modality gets the colour image), then
// the mean and the mean stage times (DetectionStats). `perf record -g -D <ms>` with the loading
// time left out profiles the calls alone (doc/detector.md, "One model of several objects").

#include <opencv2/core.hpp>
#include <opencv2/core/utility.hpp>
#include <opencv2/core/utils/filesystem.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/forestmod.hpp>

#include <algorithm>
#include <cstdio>
#include <iostream>
#include <sstream>
#include "sample_utils.hpp"

namespace fm = cv::forestmod;

static const char* keys
    = "{help h usage ? |      | print this message }"
      "{dataset        |      | BOP dataset root (e.g. ../shared/data/lmo) }"
      "{scene          | 2    | scene id }"
      "{models         |      | untrained model files, comma-separated (their classes in one "
      "detector; needed when --trained does not exist) }"
      "{trained        |      | trained model file: read when it exists, else built from --models, "
      "trained and written there }"
      "{trees          | 1    | forest.num_trees of a model built from --models }"
      "{first          | 0    | first frame (index in the scene's sorted rgb/ files) }"
      "{frames         | 15   | frames from the first }"
      "{repeat         | 1    | passes over the frames }"
      "{threads        | 1    | cv::setNumThreads }"
      "{threshold      | 80   | similarity threshold (percent) }";

static cv::Ptr<fm::Detector> buildModel(const std::vector<std::string>& files, int trees)
{
    cv::Ptr<fm::Detector> det = cv::makePtr<fm::Detector>();
    det->load(files[0]);
    for (size_t i = 1; i < files.size(); ++i)
    {
        cv::FileStorage fs(files[i], cv::FileStorage::READ);
        if (!fs.isOpened())
            CV_Error_(cv::Error::StsError, ("cannot read %s", files[i].c_str()));
        cv::FileNode classes = fs["classes"];
        for (cv::FileNodeIterator it = classes.begin(); it != classes.end(); ++it)
            det->readClass(*it);
    }
    fm::DetectorParams p; // the library's defaults, as forestmod_eval's runs
    p.forest.num_trees = trees;
    det->setParams(p);
    det->train();
    return det;
}

int main(int argc, char** argv)
{
    cv::CommandLineParser parser(argc, argv, keys);
    parser.about("forestmod_match_bench: match() of one trained model on a BOP scene's frames");
    if (parser.has("help"))
    {
        parser.printMessage();
        return 0;
    }
    const std::string dataset = parser.get<std::string>("dataset");
    const std::string trained = parser.get<std::string>("trained");
    const std::vector<std::string> models
        = fm::samples::splitList(parser.get<std::string>("models"));
    const int first = parser.get<int>("first"), frames = parser.get<int>("frames");
    const int repeat = parser.get<int>("repeat"), trees = parser.get<int>("trees");
    const float threshold = parser.get<float>("threshold");
    if (!parser.check() || dataset.empty() || trained.empty() || first < 0 || frames < 1
        || repeat < 1 || trees < 1
        || (!cv::utils::fs::exists(trained) && models.empty()))
    {
        parser.printErrors();
        std::cerr << "forestmod_match_bench: --dataset and --trained are needed (--models when "
                     "--trained does not exist yet); --frames, --repeat, --trees >= 1\n";
        return 1;
    }
    cv::setNumThreads(parser.get<int>("threads"));
    try
    {
        // the frames first: a model is not built (and written) for a scene that lacks them
        std::vector<cv::String> files;
        cv::glob(cv::format("%s/test/%06d/rgb/*.png", dataset.c_str(),
                            parser.get<int>("scene")), files);
        std::sort(files.begin(), files.end());
        if ((int)files.size() < first + frames)
            CV_Error_(cv::Error::StsBadArg, ("the scene has %d frames, not %d from %d",
                                             (int)files.size(), frames, first));
        cv::TickMeter tm;
        tm.start();
        cv::Ptr<fm::Detector> det;
        const bool built = !cv::utils::fs::exists(trained);
        if (!built)
        {
            det = cv::makePtr<fm::Detector>();
            det->load(trained);
        }
        else
        {
            det = buildModel(models, trees);
            det->save(trained);
        }
        tm.stop();
        printf("model: %d classes, %d templates, %.1f s to %s it\n", (int)det->classIds().size(),
               det->numTemplates(), tm.getTimeSec(), built ? "build, train and write" : "read");
        const size_t n_mod = det->getModalities().size();
        fm::DetectionStats stats;
        double total = 0;
        size_t matches = 0;
        for (int r = 0; r < repeat; ++r)
            for (int f = first; f < first + frames; ++f)
            {
                const cv::Mat img = cv::imread(files[f], cv::IMREAD_COLOR);
                if (img.empty())
                    CV_Error_(cv::Error::StsError, ("cannot read %s", files[f].c_str()));
                const std::vector<cv::Mat> src(n_mod, img);
                std::vector<cv::linemod::Match> m;
                double best = 1e30;
                for (int k = 0; k < 3; ++k)
                {
                    fm::DetectionStats s;
                    cv::TickMeter t;
                    t.start();
                    det->match(src, threshold, m, std::vector<cv::String>(), cv::noArray(),
                               std::vector<cv::Mat>(), &s);
                    t.stop();
                    best = std::min(best, t.getTimeMilli());
                    if (k == 2) // the stage times: the third call's
                    {
                        stats.t_quantize_ms += s.t_quantize_ms;
                        stats.t_tree_ms += s.t_tree_ms;
                        stats.t_valid_ms += s.t_valid_ms;
                        stats.t_total_ms += s.t_total_ms;
                    }
                }
                total += best;
                matches += m.size();
                if (r == 0)
                    printf("frame %d: %.2f ms, %d matches\n", f, best, (int)m.size());
            }
        const double calls = (double)repeat * frames;
        printf("mean of %d frames x %d: %.2f ms per frame (best of 3 calls), %.1f matches; "
               "third call's stages: T_quant %.2f, T_tree %.2f, T_valid %.2f, T_total %.2f ms\n",
               frames, repeat, total / calls, matches / calls, stats.t_quantize_ms / calls,
               stats.t_tree_ms / calls, stats.t_valid_ms / calls, stats.t_total_ms / calls);
    }
    catch (const cv::Exception& e)
    {
        std::cerr << "forestmod_match_bench: " << e.what() << "\n";
        return 1;
    }
    return 0;
}
