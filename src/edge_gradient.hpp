// This file is part of OpenCV project.
// It is subject to the license terms in the LICENSE file found in the top-level directory
// of this distribution and at http://opencv.org/license.html

// Internal: the gradient of the edge alignment (pose_edges.cpp) and of the verification's
// contour check (verification.cpp): LINEMOD's colour gradient and its orientation bin.

#ifndef OPENCV_FORESTMOD_EDGE_GRADIENT_HPP
#define OPENCV_FORESTMOD_EDGE_GRADIENT_HPP

#include "opencv2/core.hpp"

#include <cmath>

namespace cv {
namespace forestmod {
namespace detail {

/** Orientation bin (gradient direction modulo 180 degrees, `bins` bins) of a gradient. */
static inline int orientationBin(float dx, float dy, int bins)
{
    float a = std::atan2(dy, dx); // (-pi, pi]
    if (a < 0)
        a += (float)CV_PI;
    int b = (int)(a * bins / (float)CV_PI);
    return b >= bins ? b - bins : b;
}

/** Per pixel the 3x3 Sobel gradient (CV_32F) of the channel with the largest magnitude. */
void strongestGradient(const Mat& img, Mat& dx, Mat& dy);

} // namespace detail
} // namespace forestmod
} // namespace cv

#endif
