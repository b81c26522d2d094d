// This file is part of OpenCV project.
// It is subject to the license terms in the LICENSE file found in the top-level directory
// of this distribution and at http://opencv.org/license.html

// Writes a colour-coded PNG of the quantized hue (cv::forestmod::ColorHue) of an image:
// every pixel with a reliable hue is painted with the centre colour of its bin, the others black.

#include <opencv2/core.hpp>
#include <opencv2/core/utils/filesystem.hpp>
#include <opencv2/forestmod.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "sample_utils.hpp"
#include <iostream>

static const char* keys = "{help h usage ? |      | print this message }"
                          "{@image         |      | input colour image (BGR, 8-bit) }"
                          "{@output        |      | output PNG }"
                          "{saturation     | 50   | minimum saturation for a hue (0..255) }"
                          "{value          | 40   | minimum value for a hue (0..255) }"
                          "{force          |      | overwrite the output if it exists }";

int main(int argc, char** argv)
{
    cv::CommandLineParser parser(argc, argv, keys);
    parser.about("forestmod_hue: colour-coded quantized hue (8 bins, black = no reliable hue)");
    if (parser.has("help"))
    {
        parser.printMessage();
        return 0;
    }
    const std::string input = parser.get<std::string>("@image");
    const std::string output = parser.get<std::string>("@output");
    const int saturation = parser.get<int>("saturation"), value = parser.get<int>("value");
    if (!parser.check())
    {
        parser.printErrors();
        return 1;
    }
    if (input.empty() || output.empty())
    {
        std::cerr << "forestmod_hue: an input image and an output path are required (see --help)\n";
        return 1;
    }
    if (cv::forestmod::samples::refuseOutput("forestmod_hue", output, parser.has("force")))
        return 1;
    cv::Mat image = cv::imread(input, cv::IMREAD_COLOR);
    if (image.empty())
    {
        std::cerr << "forestmod_hue: cannot read an image from " << input << "\n";
        return 1;
    }
    try
    {
        cv::Mat labels;
        cv::forestmod::quantizeHue(image, labels, saturation, value);
        // bin i -> the fully saturated colour of hue 22.5 * i
        cv::Mat palette_hsv(1, 256, CV_8UC3, cv::Scalar::all(0)), palette;
        for (int bin = 0; bin < 8; ++bin)
            palette_hsv.at<cv::Vec3b>(0, 1 << bin) = cv::Vec3b(cv::saturate_cast<uchar>(22.5 * bin), 255, 255);
        cv::cvtColor(palette_hsv, palette, cv::COLOR_HSV2BGR);
        for (int i = 0; i < 256; ++i)
            if ((i & (i - 1)) != 0 || i == 0)
                palette.at<cv::Vec3b>(0, i) = cv::Vec3b(0, 0, 0);
        cv::Mat labels3, coded;
        cv::cvtColor(labels, labels3, cv::COLOR_GRAY2BGR);
        cv::LUT(labels3, palette, coded);
        if (!cv::imwrite(output, coded))
        {
            std::cerr << "forestmod_hue: cannot write " << output << "\n";
            return 1;
        }
        const double share = cv::countNonZero(labels) / double(labels.total());
        std::cout << "quantized hue of " << input << " (" << image.cols << "x" << image.rows
                  << "): " << cvRound(100 * share) << "% of pixels have a reliable hue -> "
                  << output << std::endl;
    }
    catch (const cv::Exception& e)
    {
        std::cerr << "forestmod_hue: " << e.what() << std::endl;
        return 1;
    }
    return 0;
}
