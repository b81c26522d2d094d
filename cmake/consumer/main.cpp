// Uses the installed forestmod: quantizes a red patch and checks the result.
#include <opencv2/forestmod.hpp>

#include <iostream>

int main()
{
    cv::Mat img(8, 8, CV_8UC3, cv::Scalar(0, 0, 255)), q;
    cv::forestmod::quantizeHue(img, q);
    cv::Ptr<cv::forestmod::ColorHue> hue = cv::forestmod::ColorHue::create();
    if (q.at<uchar>(3, 3) != 1 || hue->name() != "ColorHue")
    {
        std::cerr << "unexpected result from the installed forestmod\n";
        return 1;
    }
    std::cout << "forestmod consumer: ok\n";
    return 0;
}
