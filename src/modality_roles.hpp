// This file is part of OpenCV project.
// It is subject to the license terms in the LICENSE file found in the top-level directory
// of this distribution and at http://opencv.org/license.html

// Internal: what each modality of a detector is (decided once, when the modalities are set), and
// the checks of the images a frame or a template brings for them.

#ifndef OPENCV_FORESTMOD_MODALITY_ROLES_HPP
#define OPENCV_FORESTMOD_MODALITY_ROLES_HPP

#include "opencv2/core.hpp"
#include "opencv2/rgbd/linemod.hpp"
#include "quantize_fast.hpp"

#include <vector>

namespace cv {
namespace forestmod {
namespace detail {

enum ModalityRole
{
    ROLE_GRADIENT, //!< cv::linemod ColorGradient: source CV_8UC3
    ROLE_NORMAL,   //!< cv::linemod DepthNormal: source CV_16UC1 mm
    ROLE_HUE,      //!< forestmod ColorHue: source CV_8UC3
    ROLE_OTHER     //!< a user's modality: any source
};

struct ModalityRoles
{
    std::vector<ModalityRole> role; //!< per modality
    /** Per modality, whether the scene pyramid computes it with a fast path (quantize_fast.hpp:
    exactly cv::linemod's ColorGradient or DepthNormal, or forestmod's ColorHue, recognised by
    dynamic type) and with which parameters when the modalities were set; see
    currentInfo(). */
    std::vector<ModalityInfo> info;
    int depth;                      //!< index of the DepthNormal modality, -1 without one

    ModalityRoles() : depth(-1) {}
    /** The roles of a detector's modalities. */
    CV_EXPORTS static ModalityRoles of(const std::vector<Ptr<cv::linemod::Modality> >& modalities);
    /** info[i] with the parameters modality i has now (they are public: ColorGradient's
    members, ColorHue::setParams); a modality without a fast path is not looked at again. */
    ModalityInfo currentInfo(const std::vector<Ptr<cv::linemod::Modality> >& modalities,
                             int i) const;
};

/** Checks the sources (and optional masks) of a frame or template against the modalities:
count, emptiness, type per role, equal sizes. `where` names the calling method in messages. */
void checkSources(const std::vector<Ptr<cv::linemod::Modality> >& modalities,
                  const ModalityRoles& roles, const std::vector<Mat>& sources,
                  const std::vector<Mat>& masks, const char* where);

/** The sources of a rendered view for each modality: the colour image for the colour roles,
the depth for DepthNormal; a user's modality raises StsNotImplemented. */
std::vector<Mat> sourcesFor(const std::vector<Ptr<cv::linemod::Modality> >& modalities,
                            const ModalityRoles& roles, const Mat& color, const Mat& depth);

} // namespace detail
} // namespace forestmod
} // namespace cv

#endif
