// This file is part of OpenCV project.
// It is subject to the license terms in the LICENSE file found in the top-level directory
// of this distribution and at http://opencv.org/license.html

// Internal: reading the fields of a parameter struct from a FileNode, keeping the current value
// when the key is absent (files written by older versions lack newer keys). A present key must
// hold a number that fits the field: cv::FileNode reads a string as INT_MAX, which would pass
// as a valid count.

#ifndef OPENCV_FORESTMOD_PARAMS_IO_HPP
#define OPENCV_FORESTMOD_PARAMS_IO_HPP

#include "opencv2/core.hpp"

#include <cmath>
#include <limits>
#include <type_traits>

namespace cv {
namespace forestmod {
namespace detail {

// the node of a present numeric key: an int, or a real within T's range (integral T: finite)
template <typename T> static inline bool numericField(const FileNode& fn, const char* key,
                                                     FileNode& node)
{
    static_assert(std::is_arithmetic<T>::value, "readField reads numbers");
    node = fn[key];
    if (node.empty())
        return false;
    if (!node.isInt() && !node.isReal())
        CV_Error(Error::StsParseError,
                 cv::format("parameter '%s' must be a number", key));
    if (std::is_integral<T>::value && node.isReal())
    {
        const double v = (double)node;
        if (!(std::isfinite(v) && v >= (double)std::numeric_limits<T>::min() &&
              v <= (double)std::numeric_limits<T>::max()))
            CV_Error(Error::StsOutOfRange,
                     cv::format("parameter '%s' is out of the range of an integer", key));
    }
    return true;
}

template <typename T> static inline void readField(const FileNode& fn, const char* key, T& value)
{
    FileNode node;
    if (numericField<T>(fn, key, node))
        node >> value;
}

static inline void readField(const FileNode& fn, const char* key, bool& value)
{
    FileNode node;
    if (numericField<int>(fn, key, node))
        value = (int)node != 0;
}

} // namespace detail
} // namespace forestmod
} // namespace cv

#endif
