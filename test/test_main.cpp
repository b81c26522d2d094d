// This file is part of OpenCV project.
// It is subject to the license terms in the LICENSE file found in the top-level directory
// of this distribution and at http://opencv.org/license.html

#include "test_precomp.hpp"

namespace opencv_test {
std::string sharedDataPath()
{
    const char* p = getenv("FORESTMOD_SHARED_DATA");
    if (!p || !*p)
        return std::string();
    std::string path(p);
    return cv::utils::fs::exists(path + "/lmo/camera.json") ? path : std::string();
}

std::string testBinaryDir()
{
    char buf[4096];
    const ssize_t n = readlink("/proc/self/exe", buf, sizeof(buf) - 1);
    if (n <= 0)
        return std::string();
    buf[n] = 0;
    const std::string p(buf);
    return p.substr(0, p.find_last_of('/'));
}
} // namespace opencv_test

CV_TEST_MAIN("forestmod")
