// This file is part of OpenCV project.
// It is subject to the license terms in the LICENSE file found in the top-level directory
// of this distribution and at http://opencv.org/license.html

// The samples' check of an output path: nothing on disk is overwritten without --force, and a
// dangling symbolic link is never written through (it would create a file elsewhere).

#ifndef FORESTMOD_SAMPLES_OUTPUT_PATH_HPP
#define FORESTMOD_SAMPLES_OUTPUT_PATH_HPP

#include "opencv2/core/utils/filesystem.hpp"

#include <iostream>
#include <string>
#ifndef _WIN32
#include <sys/stat.h>
#endif

namespace forestmod_samples {

inline bool isDanglingSymlink(const std::string& path)
{
#ifndef _WIN32
    struct stat st;
    return ::lstat(path.c_str(), &st) == 0 && S_ISLNK(st.st_mode)
           && ::stat(path.c_str(), &st) != 0;
#else
    (void)path;
    return false;
#endif
}

/** true (after a message on stderr naming `tool`) when `path` must not be written: it exists
and force is false, or it is a dangling symbolic link. */
inline bool refuseOutput(const char* tool, const std::string& path, bool force)
{
    if (isDanglingSymlink(path))
    {
        std::cerr << tool << ": " << path << " is a dangling symbolic link; it is not written "
                  << "through (remove it or choose another path)\n";
        return true;
    }
    if (!force && cv::utils::fs::exists(path))
    {
        std::cerr << tool << ": " << path << " exists; pass --force to overwrite it\n";
        return true;
    }
    return false;
}

} // namespace forestmod_samples

#endif
