// This file is part of OpenCV project.
// It is subject to the license terms in the LICENSE file found in the top-level directory
// of this distribution and at http://opencv.org/license.html

// Writes the seed models of testdata/forestmod/fuzz/model/ (small detectors of a drawn shape:
// untrained, trained, with poses and depth; YAML and JSON). Usage: fuzz_make_seeds <folder>

#include <opencv2/core.hpp>
#include <opencv2/forestmod.hpp>
#include <opencv2/imgproc.hpp>

#include <iostream>

static void view(int i, cv::Mat& color, cv::Mat& depth, cv::Mat& mask)
{
    color = cv::Mat(64, 64, CV_8UC3, cv::Scalar(0, 0, 0));
    depth = cv::Mat(64, 64, CV_16UC1, cv::Scalar(0));
    mask = cv::Mat::zeros(64, 64, CV_8UC1);
    const cv::RotatedRect r(cv::Point2f(32, 32), cv::Size2f(34.f - 4 * i, 22.f + 3 * i), 20.f * i);
    cv::Point2f p[4];
    r.points(p);
    std::vector<cv::Point> poly(p, p + 4);
    cv::fillConvexPoly(color, poly, cv::Scalar(30, 60, 200));
    cv::fillConvexPoly(depth, poly, cv::Scalar(700 + 10 * i));
    cv::fillConvexPoly(mask, poly, cv::Scalar(255));
    cv::circle(color, cv::Point(30, 34), 6, cv::Scalar(200, 140, 20), cv::FILLED);
}

static void build(cv::forestmod::Detector& det, int n, bool pose)
{
    for (int i = 0; i < n; ++i)
    {
        cv::Mat color, depth, mask;
        view(i, color, depth, mask);
        std::vector<cv::Mat> sources;
        for (size_t m = 0; m < det.getModalities().size(); ++m)
            sources.push_back(det.getModalities()[m]->name() == "DepthNormal" ? depth : color);
        if (pose)
            det.addTemplate(sources, "shape", mask, cv::Matx33d::eye(), cv::Vec3d(0, 0, 700),
                            cv::Matx33d(500, 0, 32, 0, 500, 32, 0, 0, 1));
        else
            det.addTemplate(sources, "shape", mask);
    }
}

int main(int argc, char** argv)
{
    if (argc != 2)
    {
        std::cerr << "usage: fuzz_make_seeds <folder>\n";
        return 1;
    }
    const std::string dir = argv[1];
    std::vector<cv::Ptr<cv::linemod::Modality> > grad(
        1, cv::linemod::Modality::create("ColorGradient"));
    std::vector<int> T(1, 4);
    T.push_back(8);
    cv::forestmod::DetectorParams p;
    p.forest.num_trees = 1;
    {
        cv::forestmod::Detector det(grad, T, p);
        build(det, 2, false);
        det.save(dir + "/gradient_untrained.yml", true);
        det.save(dir + "/gradient_untrained.json", true);
    }
    {
        cv::Ptr<cv::forestmod::Detector> det = cv::forestmod::getDefaultForestLINE();
        det->setParams(p);
        build(*det, 3, true);
        det->train();
        det->save(dir + "/line_trained_pose.yml", true);
    }
    {
        cv::Ptr<cv::forestmod::Detector> det = cv::forestmod::getDefaultForestLINEMOD();
        det->setParams(p);
        build(*det, 2, true);
        det->save(dir + "/linemod_depth_untrained.yml", true);
    }
    return 0;
}
