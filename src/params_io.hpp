// This file is part of OpenCV project.
// It is subject to the license terms in the LICENSE file found in the top-level directory
// of this distribution and at http://opencv.org/license.html

// Internal: reading the fields of a parameter struct from a FileNode, keeping the current value
// when the key is absent (files written by older versions lack newer keys).

#ifndef OPENCV_FORESTMOD_PARAMS_IO_HPP
#define OPENCV_FORESTMOD_PARAMS_IO_HPP

#include "opencv2/core.hpp"

namespace cv {
namespace forestmod {
namespace detail {

template <typename T> static inline void readField(const FileNode& fn, const char* key, T& value)
{
    const FileNode node = fn[key];
    if (!node.empty())
        node >> value;
}

static inline void readField(const FileNode& fn, const char* key, bool& value)
{
    const FileNode node = fn[key];
    if (!node.empty())
        value = (int)node != 0;
}

} // namespace detail
} // namespace forestmod
} // namespace cv

#endif
