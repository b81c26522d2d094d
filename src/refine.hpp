// This file is part of OpenCV project.
// It is subject to the license terms in the LICENSE file found in the top-level directory
// of this distribution and at http://opencv.org/license.html

// Internal: LINEMOD's pyramid refinement of coarse matches (with the depth samples scored at every
// refinement level), and the exhaustive LINEMOD search (every template at every position: the
// detector without its forest, for comparison and tests).

#ifndef OPENCV_FORESTMOD_REFINE_HPP
#define OPENCV_FORESTMOD_REFINE_HPP

#include "scene_pyramid.hpp"
#include "template_store.hpp"

namespace cv {
namespace forestmod {
namespace detail {

/** Refines coarse matches up the pyramid (LINEMOD's arithmetic); a match that falls under the
threshold at some level is dropped. The finer levels' maps must be ready where the matches'
refinementRegions() lie (prepareRefinementLevels()). With the scene's depth contexts
(ScenePyramid::depth_ctx non-empty), each template's depth samples join its score at every
level. Keeps the order. */
CV_EXPORTS void refineMatches(const ScenePyramid& scene, const ClassPyramids& pyramids,
                              const TemplateStore& store, float threshold,
                              std::vector<cv::linemod::Match>& matches);

/** Where refineMatches() reads the levels below the coarsest for these coarse matches: per
level, one rectangle (level pixels) per match that holds every pixel its refinement may read,
whatever positions the coarser levels give it (what prepareRefinementLevels() computes). The
features' extents come from the store's records (TemplateRecord::feature_extent). */
CV_EXPORTS void refinementRegions(const ScenePyramid& scene, const ClassPyramids& pyramids,
                                  const TemplateStore& store,
                                  const std::vector<cv::linemod::Match>& matches,
                                  std::vector<std::vector<Rect> >& regions);

} // namespace detail
} // namespace forestmod
} // namespace cv

#endif
