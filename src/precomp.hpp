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

namespace cv {
namespace forestmod {
namespace detail {

/** Asks the cache for the line holding p: a hint, it never faults wherever p points. */
static inline void prefetchLine(const void* p)
{
#if defined(__GNUC__)
    __builtin_prefetch(p);
#else
    CV_UNUSED(p);
#endif
}

} // namespace detail
} // namespace forestmod
} // namespace cv

#endif // OPENCV_FORESTMOD_PRECOMP_HPP
