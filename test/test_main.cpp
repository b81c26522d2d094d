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
} // namespace opencv_test

CV_TEST_MAIN("forestmod")
