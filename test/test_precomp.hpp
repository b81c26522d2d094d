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

/** The parameters written with DetectorParams::write into an in-memory YAML map and read back
(the round trip of a model file's "params"). */
inline cv::forestmod::DetectorParams writtenAndRead(const cv::forestmod::DetectorParams& p)
{
    cv::FileStorage out(".yml", cv::FileStorage::WRITE | cv::FileStorage::MEMORY);
    out << "params" << "{";
    p.write(out);
    out << "}";
    cv::FileStorage in(out.releaseAndGetString(), cv::FileStorage::READ | cv::FileStorage::MEMORY);
    cv::forestmod::DetectorParams back;
    back.read(in["params"]);
    return back;
}

/** A closed cube of side 2 h centred at the origin, its faces turning counter-clockwise seen from
outside (two triangles per side), grey, with normals. */
inline Mesh closedCube(float h)
{
    Mesh m;
    for (int c = 0; c < 8; ++c)
        m.vertices.push_back(cv::Point3f(c & 1 ? h : -h, c & 2 ? h : -h, c & 4 ? h : -h));
    const int quads[6][4] = { { 0, 2, 3, 1 }, { 4, 5, 7, 6 }, { 0, 1, 5, 4 },
                              { 2, 6, 7, 3 }, { 0, 4, 6, 2 }, { 1, 3, 7, 5 } };
    for (int q = 0; q < 6; ++q)
    {
        m.faces.push_back(cv::Vec3i(quads[q][0], quads[q][1], quads[q][2]));
        m.faces.push_back(cv::Vec3i(quads[q][0], quads[q][2], quads[q][3]));
    }
    m.colors.assign(8, cv::Vec3b(128, 128, 128));
    m.computeNormals();
    return m;
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
