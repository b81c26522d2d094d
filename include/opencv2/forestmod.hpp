// This file is part of OpenCV project.
// It is subject to the license terms in the LICENSE file found in the top-level directory
// of this distribution and at http://opencv.org/license.html

#ifndef OPENCV_FORESTMOD_HPP
#define OPENCV_FORESTMOD_HPP

#include "opencv2/forestmod/hue.hpp"
#include "opencv2/forestmod/render.hpp"
#include "opencv2/forestmod/synthetic.hpp"
#include "opencv2/forestmod/forest.hpp"
#include "opencv2/forestmod/detector.hpp"
#include "opencv2/forestmod/pose.hpp"
#include "opencv2/forestmod/dataset.hpp"

/** @defgroup forestmod Fuzzy template forest for real-time 6-DoF pose estimation

Real-time, background-aware pose estimation of texture-less objects in RGB-D images after
Shao, Tang and Kim @cite shao2016forest : LINEMOD templates @cite hinterstoisser2012gradient
rendered from CAD meshes are indexed by a fuzzy random forest whose nodes carry a preemptive
background rejector; candidates of a leaf are validated breadth-first.

  @{
    @defgroup forestmod_hue Quantized hue modality (LINEMOD's colour cue)
    @defgroup forestmod_forest Fuzzy template forest with preemptive background rejectors
    @defgroup forestmod_render Meshes, off-screen rendering and template view sampling
    @defgroup forestmod_detector Detector: drop-in cv::linemod::Detector with forest search
    @defgroup forestmod_pose Pose of a match: initial pose, ICP refinement, depth check, ADD/ADI
    @defgroup forestmod_dataset BOP dataset reader and results writer
  @}
*/

#endif // OPENCV_FORESTMOD_HPP
