// This file is part of OpenCV project.
// It is subject to the license terms in the LICENSE file found in the top-level directory
// of this distribution and at http://opencv.org/license.html

// libFuzzer target: forestmod::Detector::load on arbitrary bytes (YAML, JSON or XML, as
// cv::FileStorage detects), then, when the file loads, match() on a small fixed frame: a model
// that loads must be usable. Every outcome but a cv::Exception or a result is a finding.

#include "fuzz_common.hpp"

#include <opencv2/core.hpp>
#include <opencv2/core/utils/logger.hpp>
#include <opencv2/forestmod.hpp>
#include <opencv2/imgproc.hpp>

#include <vector>

static cv::Mat fixedColor()
{
    cv::Mat img(96, 128, CV_8UC3, cv::Scalar(40, 90, 160));
    cv::rectangle(img, cv::Rect(30, 20, 50, 40), cv::Scalar(200, 40, 20), cv::FILLED);
    cv::circle(img, cv::Point(80, 60), 18, cv::Scalar(20, 220, 90), cv::FILLED);
    return img;
}

static cv::Mat fixedDepth()
{
    cv::Mat d(96, 128, CV_16UC1, cv::Scalar(800));
    cv::rectangle(d, cv::Rect(30, 20, 50, 40), cv::Scalar(760), cv::FILLED);
    return d;
}

extern "C" int LLVMFuzzerInitialize(int*, char***)
{
    cv::utils::logging::setLogLevel(cv::utils::logging::LOG_LEVEL_SILENT);
    cv::setNumThreads(1);
    return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size)
{
    static const std::string path = forestmod_fuzz::inputPath(".yml");
    static const cv::Mat color = fixedColor(), depth = fixedDepth();
    if (!forestmod_fuzz::writeInput(path, data, size))
        return 0;
    cv::forestmod::Detector det;
    try
    {
        det.load(path);
    }
    catch (const cv::Exception&)
    {
        return 0; // refused: fine
    }
    std::vector<cv::Mat> sources;
    const std::vector<cv::Ptr<cv::linemod::Modality> > mods = det.getModalities();
    for (size_t i = 0; i < mods.size(); ++i)
        sources.push_back(mods[i]->name() == "DepthNormal" ? depth : color);
    try
    {
        std::vector<cv::linemod::Match> matches;
        det.match(sources, 50.f, matches);
    }
    catch (const cv::Exception&)
    {
    }
    return 0;
}
