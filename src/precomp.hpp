// This file is part of OpenCV project.
// It is subject to the license terms in the LICENSE file found in the top-level directory
// of this distribution and at http://opencv.org/license.html

#ifndef OPENCV_FORESTMOD_PRECOMP_HPP
#define OPENCV_FORESTMOD_PRECOMP_HPP

#include "opencv2/forestmod.hpp"

#include "opencv2/core.hpp"
#include "opencv2/core/utility.hpp"
#include "opencv2/imgproc.hpp"

#include <algorithm>
#include <cmath>
#include <vector>

#endif // OPENCV_FORESTMOD_PRECOMP_HPP
