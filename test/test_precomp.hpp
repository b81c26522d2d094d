// This file is part of OpenCV project.
// It is subject to the license terms in the LICENSE file found in the top-level directory
// of this distribution and at http://opencv.org/license.html

#ifndef OPENCV_FORESTMOD_TEST_PRECOMP_HPP
#define OPENCV_FORESTMOD_TEST_PRECOMP_HPP

#include "opencv2/ts.hpp"
#include "opencv2/forestmod.hpp"
#include "opencv2/imgproc.hpp"
#include "opencv2/imgcodecs.hpp"
#include "opencv2/calib3d.hpp"
#include "opencv2/core/utils/filesystem.hpp"
#include "../samples/sample_utils.hpp"

#include <fstream>
#include <sstream>
#include <unistd.h>
#include <set>
#include <thread>

namespace opencv_test {
using namespace cv::forestmod;
using namespace cv::forestmod::samples;

/** Root of the optional real data (../shared/data: lmo/, real_rgbd/), or "" when absent. */
std::string sharedDataPath();
/** Folder of the test binary (the samples are built next to it). */
std::string testBinaryDir();

/** Expects two lists of matches of the same length to be the same matches in the same order
(position, template, similarity); `what` names the case in the failure messages. */
inline void expectSameMatches(const std::vector<cv::linemod::Match>& a,
                              const std::vector<cv::linemod::Match>& b,
                              const std::string& what = std::string())
{
    ASSERT_EQ(a.size(), b.size()) << what;
    for (size_t k = 0; k < a.size(); ++k)
    {
        EXPECT_EQ(a[k].x, b[k].x) << what << " match " << k;
        EXPECT_EQ(a[k].y, b[k].y) << what << " match " << k;
        EXPECT_EQ(a[k].template_id, b[k].template_id) << what << " match " << k;
        EXPECT_EQ(a[k].similarity, b[k].similarity) << what << " match " << k;
    }
}

/** A temporary folder (cv::tempfile, `suffix` in its name), removed with what it holds at the
end of the test. */
struct TempDir
{
    explicit TempDir(const std::string& suffix = "dir") : path(cv::tempfile(suffix.c_str()))
    {
        cv::utils::fs::createDirectories(path);
    }
    ~TempDir() { cv::utils::fs::remove_all(path); }
    std::string path;

private:
    TempDir(const TempDir&);
    TempDir& operator=(const TempDir&);
};
} // namespace opencv_test

#endif
