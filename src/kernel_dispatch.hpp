// This file is part of OpenCV project.
// It is subject to the license terms in the LICENSE file found in the top-level directory
// of this distribution and at http://opencv.org/license.html

// Internal: the choice between the baseline and the AVX2 build of the vectorised kernels
// (score_kernels.cpp, quantize_kernels.cpp), made at every call as OpenCV's own dispatched
// functions: the AVX2 code runs when cv::checkHardwareSupport(CV_CPU_AVX2) (false after
// cv::setUseOptimized(false)).

#ifndef OPENCV_FORESTMOD_KERNEL_DISPATCH_HPP
#define OPENCV_FORESTMOD_KERNEL_DISPATCH_HPP

#include "opencv2/core/utility.hpp"

namespace cv {
namespace forestmod {
namespace detail {

/** The instruction set the vectorised kernels (score_kernels, quantize_kernels) run with on this
machine now: "AVX2" or "baseline" (exported for the tests). */
CV_EXPORTS const char* kernelsPath();

static inline bool useAVX2()
{
#ifdef FORESTMOD_HAVE_AVX2
    return checkHardwareSupport(CV_CPU_AVX2);
#else
    return false;
#endif
}

} // namespace detail
} // namespace forestmod
} // namespace cv

#ifdef FORESTMOD_HAVE_AVX2
#define FORESTMOD_DISPATCH(call)                                                                  \
    if (useAVX2())                                                                                \
        opt_AVX2::call;                                                                           \
    else                                                                                          \
        cpu_baseline::call
#else
#define FORESTMOD_DISPATCH(call) cpu_baseline::call
#endif

#endif
