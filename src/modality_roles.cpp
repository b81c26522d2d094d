// This file is part of OpenCV project.
// It is subject to the license terms in the LICENSE file found in the top-level directory
// of this distribution and at http://opencv.org/license.html

#include "precomp.hpp"
#include "modality_roles.hpp"

namespace cv {
namespace forestmod {
namespace detail {

ModalityRoles ModalityRoles::of(const std::vector<Ptr<cv::linemod::Modality> >& modalities)
{
    ModalityRoles r;
    for (size_t i = 0; i < modalities.size(); ++i)
    {
        const String name = modalities[i]->name();
        const ModalityRole role = name == "ColorGradient" ? ROLE_GRADIENT
            : name == "DepthNormal"                       ? ROLE_NORMAL
            : name == "ColorHue"                          ? ROLE_HUE
                                                          : ROLE_OTHER;
        r.role.push_back(role);
        r.info.push_back(classifyModality(modalities[i]));
        if (role == ROLE_NORMAL && r.depth < 0)
            r.depth = static_cast<int>(i);
    }
    return r;
}

ModalityInfo ModalityRoles::currentInfo(
    const std::vector<Ptr<cv::linemod::Modality> >& modalities, int i) const
{
    CV_DbgAssert(i >= 0 && i < (int)info.size() && info.size() == modalities.size());
    return info[i].kind == MODALITY_OTHER ? info[i] : classifyModality(modalities[i]);
}

static void checkMasks(const std::vector<Mat>& sources, const std::vector<Mat>& masks,
                       const char* where)
{
    if (masks.empty())
        return;
    if (masks.size() != sources.size())
        CV_Error_(Error::StsBadArg, ("forestmod::Detector::%s: %d masks for %d sources", where,
                                     (int)masks.size(), (int)sources.size()));
    for (size_t i = 0; i < masks.size(); ++i)
        if (!masks[i].empty() && (masks[i].size() != sources[i].size()
                                  || masks[i].type() != CV_8UC1))
            CV_Error_(Error::StsUnmatchedSizes, ("forestmod::Detector::%s: mask %d must be "
                                                 "CV_8UC1 of the source's size", where, (int)i));
}

void checkSources(const std::vector<Ptr<cv::linemod::Modality> >& modalities,
                  const ModalityRoles& roles, const std::vector<Mat>& sources,
                  const std::vector<Mat>& masks, const char* where)
{
    if (modalities.empty())
        CV_Error_(Error::StsError, ("forestmod::Detector::%s: the detector has no modalities "
                                    "(default-constructed? use a factory or read a model)",
                                    where));
    CV_Assert(roles.role.size() == modalities.size());
    if (sources.size() != modalities.size())
        CV_Error_(Error::StsBadArg, ("forestmod::Detector::%s: %d sources for %d modalities",
                                     where, (int)sources.size(), (int)modalities.size()));
    for (size_t i = 0; i < sources.size(); ++i)
    {
        if (sources[i].empty())
            CV_Error_(Error::StsBadArg, ("forestmod::Detector::%s: source %d (%s) is empty",
                                         where, (int)i, modalities[i]->name().c_str()));
        if (roles.role[i] == ROLE_NORMAL && sources[i].type() != CV_16UC1)
            CV_Error_(Error::StsUnsupportedFormat,
                      ("forestmod::Detector::%s: source %d (DepthNormal) must be CV_16UC1 depth "
                       "in mm, got %s", where, (int)i, typeToString(sources[i].type()).c_str()));
        if ((roles.role[i] == ROLE_GRADIENT || roles.role[i] == ROLE_HUE)
            && sources[i].type() != CV_8UC3)
            CV_Error_(Error::StsUnsupportedFormat,
                      ("forestmod::Detector::%s: source %d (%s) must be a CV_8UC3 BGR image, "
                       "got %s", where, (int)i, modalities[i]->name().c_str(),
                       typeToString(sources[i].type()).c_str()));
        if (sources[i].size() != sources[0].size())
            CV_Error_(Error::StsUnmatchedSizes,
                      ("forestmod::Detector::%s: source %d is %dx%d, source 0 is %dx%d", where,
                       (int)i, sources[i].cols, sources[i].rows, sources[0].cols,
                       sources[0].rows));
    }
    checkMasks(sources, masks, where);
}

std::vector<Mat> sourcesFor(const std::vector<Ptr<cv::linemod::Modality> >& modalities,
                            const ModalityRoles& roles, const Mat& color, const Mat& depth)
{
    std::vector<Mat> sources;
    for (size_t i = 0; i < roles.role.size(); ++i)
    {
        if (roles.role[i] == ROLE_OTHER)
            CV_Error_(Error::StsNotImplemented,
                      ("forestmod::Detector::addTemplates: no rendered source for modality '%s'",
                       modalities[i]->name().c_str()));
        sources.push_back(roles.role[i] == ROLE_NORMAL ? depth : color);
    }
    return sources;
}

} // namespace detail
} // namespace forestmod
} // namespace cv
