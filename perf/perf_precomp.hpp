// This file is part of OpenCV project.
// It is subject to the license terms in the LICENSE file found in the top-level directory
// of this distribution and at http://opencv.org/license.html

#ifndef OPENCV_FORESTMOD_PERF_PRECOMP_HPP
#define OPENCV_FORESTMOD_PERF_PRECOMP_HPP

#include "opencv2/ts.hpp"
#include "opencv2/forestmod.hpp"
#include "opencv2/imgproc.hpp"
#include "opencv2/imgcodecs.hpp"
#include "../samples/sample_utils.hpp"

#include <map>

namespace opencv_test {
using namespace perf;
using namespace cv::forestmod;
using namespace cv::forestmod::samples;
} // namespace opencv_test

#endif
