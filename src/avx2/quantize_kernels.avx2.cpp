// This file is part of OpenCV project.
// It is subject to the license terms in the LICENSE file found in the top-level directory
// of this distribution and at http://opencv.org/license.html

// AVX2 build of the fast quantization's row kernels (../quantize_kernels.simd.hpp). Compiled with
// -mavx2 and CV_CPU_DISPATCH_MODE=AVX2 by CMakeLists.txt on x86-64 only; called by
// ../quantize_kernels.cpp when the CPU has AVX2.

#include <immintrin.h>

#define FORESTMOD_KERNELS_NAMESPACE opt_AVX2
#include "../quantize_kernels.simd.hpp"

#if !CV_SIMD256
#error "the AVX2 build of the kernels must get 256-bit universal intrinsics"
#endif
