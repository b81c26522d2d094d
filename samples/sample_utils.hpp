// This file is part of OpenCV project.
// It is subject to the license terms in the LICENSE file found in the top-level directory
// of this distribution and at http://opencv.org/license.html

// Small helpers shared by the samples, the tests and the perf tests (header only): lists,
// LM-O intrinsics, rotations, the samples' check of an output path (nothing on disk is
// overwritten without --force, a dangling symbolic link is never written through), and a
// cv::linemod::Detector with a forestmod::Detector's templates.

#ifndef OPENCV_FORESTMOD_SAMPLE_UTILS_HPP
#define OPENCV_FORESTMOD_SAMPLE_UTILS_HPP

#include "opencv2/core.hpp"
#include "opencv2/calib3d.hpp"
#include "opencv2/core/utils/filesystem.hpp"
#include "opencv2/forestmod/detector.hpp"

#include <iostream>
#include <sstream>
#include <string>
#include <vector>
#ifndef _WIN32
#include <sys/stat.h>
#endif

namespace cv {
namespace forestmod {
namespace samples {

/** The non-empty items of a list separated by `sep`. */
inline std::vector<std::string> splitList(const std::string& s, char sep = ',')
{
    std::vector<std::string> out;
    std::stringstream ss(s);
    std::string item;
    while (std::getline(ss, item, sep))
        if (!item.empty())
            out.push_back(item);
    return out;
}

/** Intrinsics of the LineMOD / LM-O Primesense camera (BOP camera.json). */
inline Matx33d lmoIntrinsics()
{
    return Matx33d(572.4114, 0, 325.2611, 0, 573.57043, 242.04899, 0, 0, 1);
}

/** The rotation that takes the optical axis onto the ray through pixel p. */
inline Matx33d rayRotation(const Matx33d& K, Point2d p)
{
    Vec3d d = K.inv() * Vec3d(p.x, p.y, 1);
    d *= 1.0 / cv::norm(d);
    Vec3d axis = Vec3d(0, 0, 1).cross(d);
    const double s = cv::norm(axis);
    if (s < 1e-12)
        return Matx33d::eye();
    axis *= std::atan2(s, d[2]) / s;
    Matx33d R;
    Rodrigues(axis, R);
    return R;
}

/** Angle (degrees) of the rotation between A and B. */
inline double rotationAngleDeg(const Matx33d& A, const Matx33d& B)
{
    const Matx33d D = A.t() * B;
    const double c = std::max(-1.0, std::min(1.0, (trace(D) - 1) / 2));
    return std::acos(c) * 180 / CV_PI;
}

/** True when `path` is a symbolic link to nothing: writing through it would create a file
elsewhere. */
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

/** A detector's sources for an image and its depth, one per modality: the depth for DepthNormal,
the image otherwise. */
inline std::vector<Mat> sourcesOf(const std::vector<Ptr<cv::linemod::Modality> >& mods,
                                  const Mat& color, const Mat& depth)
{
    std::vector<Mat> src;
    for (size_t i = 0; i < mods.size(); ++i)
        src.push_back(mods[i]->name() == "DepthNormal" ? depth : color);
    return src;
}

/** cv::linemod::Detector with exactly the templates (and modality objects) of a forestmod one,
for comparisons on the same templates. */
inline Ptr<cv::linemod::Detector> linemodCopy(const Detector& det)
{
    std::vector<int> T;
    for (int l = 0; l < det.pyramidLevels(); ++l)
        T.push_back(det.getT(l));
    Ptr<cv::linemod::Detector> lm = makePtr<cv::linemod::Detector>(det.getModalities(), T);
    const std::vector<String> ids = det.classIds();
    for (size_t c = 0; c < ids.size(); ++c)
        for (int i = 0; i < det.numTemplates(ids[c]); ++i)
        {
            const int id = lm->addSyntheticTemplate(det.getTemplates(ids[c], i), ids[c]);
            CV_Assert(id == i);
        }
    return lm;
}

} // namespace samples
} // namespace forestmod
} // namespace cv

#endif
