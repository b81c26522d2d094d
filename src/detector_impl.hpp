// This file is part of OpenCV project.
// It is subject to the license terms in the LICENSE file found in the top-level directory
// of this distribution and at http://opencv.org/license.html

// Internal: the state behind forestmod::Detector, one member per stage that keeps state.

#ifndef OPENCV_FORESTMOD_DETECTOR_IMPL_HPP
#define OPENCV_FORESTMOD_DETECTOR_IMPL_HPP

#include "opencv2/forestmod/detector.hpp"
#include "modality_roles.hpp"
#include "template_store.hpp"
#include "search_index.hpp"
#include "pose_estimator.hpp"

namespace cv {
namespace forestmod {
namespace detail {

struct DetectorImpl
{
    DetectorImpl() {}
    /** Detector's copy: everything but the mutex (the caller holds other.mutex); the trained
    forests are shared, read-only once trained (train() makes new ones). */
    DetectorImpl(const DetectorImpl& other)
        : params(other.params), roles(other.roles), store(other.store), index(other.index),
          poses(other.poses)
    {
    }
    DetectorImpl& operator=(const DetectorImpl&) = delete;

    DetectorParams params;
    ModalityRoles roles;     //!< of the base class's modalities, set with them
    TemplateStore store;     //!< records beside the base class's template pyramids
    SearchIndex index;       //!< groups, windows, forests (trained state)
    PoseEstimator poses;     //!< meshes and renderer
    /** Guards the templates, parameters and training: match() trains under it when the index is
    out of date (automatic training), so several threads may call match() at once. */
    Mutex mutex;
};

/** DetectorParams in their documented ranges (setParams, the constructor, read). */
void checkParams(const DetectorParams& p);

} // namespace detail
} // namespace forestmod
} // namespace cv

#endif
