// This file is part of OpenCV project.
// It is subject to the license terms in the LICENSE file found in the top-level directory
// of this distribution and at http://opencv.org/license.html

// Internal: everything computed from a frame, once (paper: the scene's quantized images; LINEMOD
// 2.3): per pyramid level and modality the quantized and spread images (the response maps are
// computed from the spread images by their readers, in their own layouts); the forest's
// label planes of the coarsest level; the depth contexts of the refinement levels. Every later
// stage reads it in place. The coarsest level covers the whole frame; the finer levels' quantized
// images (of the modalities with a rectangle path: ColorGradient, ColorHue) and spread images
// are computed on demand, in tiles, where refinement will read them
// (prepareRefinementLevels). The
// functions marked CV_EXPORTS are exported for the tests only; the header is not installed.

#ifndef OPENCV_FORESTMOD_SCENE_PYRAMID_HPP
#define OPENCV_FORESTMOD_SCENE_PYRAMID_HPP

#include "similarity.hpp"
#include "depth_modality.hpp"
#include "depth_range.hpp"
#include "modality_roles.hpp"

#include <vector>

namespace cv {
namespace forestmod {
namespace detail {

struct ScenePyramid
{
    /** Level 0 (finest) .. coarsest. Below the coarsest level, the spread images (and the
    quantized images of the deferred modalities) are allocated at full size but valid only in
    the tiles marked in `tiles`. */
    std::vector<LevelMaps> levels;
    /** Per level below the coarsest: CV_8U grid of TILE_W x TILE_H pixel tiles, bit 1 where the
    spread images are computed, bit 2 where the quantized images are. */
    std::vector<Mat> tiles;
    enum { TILE_MAPS = 1, TILE_QUANTIZED = 2 };
    /** [level][modality]: what the quantized images of the levels below the coarsest are
    computed from, tile by tile (quantizeLevelRect()); an empty image where the whole level was
    quantized up front (modalities without a rectangle path, or quantized images asked for). */
    std::vector<std::vector<LevelSource> > deferred;
    enum { TILE_W = 64, TILE_H = 32 };
    /** The forest's view of the coarsest level: per modality the dominant labels of the plain
    quantized image (DetectorParams::dominant_window), with a zero border of `border` pixels on
    every side so that a window read never leaves the buffer. Empty without a forest. */
    std::vector<Mat> planes;
    std::vector<const uchar*> plane_ptr; //!< planes[m].ptr()
    size_t plane_step;
    int border;
    /** Scene depth (CV_16UC1 mm) when the detector has a DepthNormal modality, else empty. */
    Mat depth;
    /** The scene depth per cell of the coarsest level's T grid (out-of-depth-range rejection)
    when the scene has depth and DetectorParams::depth_range_tolerance >= 0, else empty. */
    DepthCells depth_cells;
    /** Depth contexts of the refinement levels (all but the coarsest) when depth is scored. */
    std::vector<DepthContext> depth_ctx;

    ScenePyramid() : plane_step(0), border(0) {}
    const LevelMaps& coarsest() const { return levels.back(); }
    int coarsestIndex() const { return static_cast<int>(levels.size()) - 1; }
};

/** The modalities' quantized images, equal to their process, pyrDown, quantize (the fast paths of
quantize_fast.hpp for the modalities `roles` recognised, the virtual calls for the others): the
coarsest level's, spread over T; of the finer levels those of the modalities without a
rectangle path, the others deferred to the tiles; the finer levels' spread images
allocated, no tile computed. `quantized_images`, when needed, receives the quantized images of
every level, whole, as cv::linemod::Detector::match returns them (nothing deferred then). */
CV_EXPORTS void quantizeScene(const std::vector<Ptr<cv::linemod::Modality> >& modalities,
                              const ModalityRoles& roles, const std::vector<int>& T_at_level,
                              const std::vector<Mat>& sources, const std::vector<Mat>& masks,
                              ScenePyramid& scene, OutputArrayOfArrays quantized_images);

/** Spread images of the levels below the coarsest in every tile that meets one of
`regions[l]` (rectangles of level-l pixels, clipped to the level), computed in parallel over the
tiles not computed yet, after the deferred quantized images of the tiles they read; a level
whose tiles cover much of it is quantized and spread whole, in row stripes. Equal there to the
full-frame computation. */
CV_EXPORTS void prepareRefinementLevels(ScenePyramid& scene,
                                        const std::vector<std::vector<Rect> >& regions);

/** The forest's label planes of the coarsest level, bordered by `border` zero pixels. */
CV_EXPORTS void forestPlanes(int dominant_window, int border, ScenePyramid& scene);

/** Depth contexts of the refinement levels: at level l a match's position is known to +-T_l / 2
pixels, so the scene's depth range is taken over squares of that radius (level-0 pixels). */
CV_EXPORTS void depthContexts(const Mat& depth, const std::vector<int>& T_at_level,
                              int tolerance, ScenePyramid& scene);

} // namespace detail
} // namespace forestmod
} // namespace cv

#endif
