// This file is part of OpenCV project.
// It is subject to the license terms in the LICENSE file found in the top-level directory
// of this distribution and at http://opencv.org/license.html

// The scene pyramid: the frame's maps, computed once per frame (the finer levels' quantized and
// spread images on demand, in tiles).

#include "precomp.hpp"
#include "scene_pyramid.hpp"
#include "search_index.hpp"
#include "quantize_fast.hpp"

namespace cv {
namespace forestmod {
namespace detail {

void quantizeScene(const std::vector<Ptr<cv::linemod::Modality> >& modalities,
                   const ModalityRoles& roles, const std::vector<int>& T_at_level,
                   const std::vector<Mat>& sources, const std::vector<Mat>& masks,
                   ScenePyramid& scene, OutputArrayOfArrays quantized_images)
{
    const int M = static_cast<int>(modalities.size());
    const int levels_n = static_cast<int>(T_at_level.size());
    const int L = levels_n - 1;
    std::vector<ModalityInfo> infos(M);
    for (int i = 0; i < M; ++i)
        infos[i] = roles.currentInfo(modalities, i);
    std::vector<std::vector<Mat> > quantized; // [level][modality]
    // the finer levels of the colour modalities are quantized in tiles (prepareRefinementLevels)
    // unless the caller wants the whole images
    quantizeAllLevels(modalities, infos, sources, masks, levels_n, quantized,
                      quantized_images.needed() ? 0 : &scene.deferred);
    if (quantized_images.needed())
        scene.deferred.assign(levels_n, std::vector<LevelSource>(M));
    scene.levels.assign(levels_n, LevelMaps());
    scene.tiles.assign(L, Mat());
    if (quantized_images.needed())
        quantized_images.create(1, levels_n * M, CV_8U);
    for (int l = 0; l < levels_n; ++l)
    {
        LevelMaps& lm = scene.levels[l];
        lm.T = T_at_level[l];
        lm.pad = 0;
        lm.quantized = quantized[l];
        lm.size = lm.quantized[0].size();
        lm.spread.resize(M);
        for (int i = 0; i < M; ++i)
        {
            if (l == L)
                spreadLabelsFast(lm.quantized[i], lm.spread[i], lm.T, lm.pad);
            else
                lm.spread[i].create(lm.size, CV_8U); // in tiles by prepareRefinementLevels
            if (quantized_images.needed())
                lm.quantized[i].copyTo(quantized_images.getMatRef(l * M + i));
        }
        if (l < L)
            scene.tiles[l] = Mat::zeros((lm.size.height + ScenePyramid::TILE_H - 1)
                                            / ScenePyramid::TILE_H,
                                        (lm.size.width + ScenePyramid::TILE_W - 1)
                                            / ScenePyramid::TILE_W,
                                        CV_8U);
    }
}

// Marks `bit` in the tiles of `grid` within `reach` tiles right of and below (tx, ty) (itself
// included) and appends the ones not marked before to `todo` as (tx, ty, l).
static void markTiles(Mat& grid, int tx, int ty, Point reach, uchar bit, int l,
                      std::vector<Point3i>& todo)
{
    for (int y = ty; y <= std::min(ty + reach.y, grid.rows - 1); ++y)
    {
        uchar* g = grid.ptr<uchar>(y);
        for (int x = tx; x <= std::min(tx + reach.x, grid.cols - 1); ++x)
            if (!(g[x] & bit))
            {
                g[x] |= bit;
                todo.push_back(Point3i(x, y, l));
            }
    }
}

// Share of a level's tiles from which prepareRefinementLevels quantizes the whole level at once: a
// tile costs about 1.7 times a whole level's stripes per pixel (OpenCV's filters set up per call,
// the margins). Perf test Forestmod_ScenePyramid_tiles, VGA RGB, 1 thread (commit 33f5134): one
// 240 x 240 region (a third of the tiles) 1.05 ms in tiles; the whole level 1.87 ms.
static const double kWholeLevelShare = 0.5;

// Spreads whole the levels below the coarsest whose tiles in `todo` (tile column, row, level)
// cover at least kWholeLevelShare of them and whose quantized images are whole; their tiles
// leave `todo`. Row stripes cost less than tiles of 64 pixels, whose rows are as many calls.
static void spreadWholeLevels(ScenePyramid& scene, std::vector<Point3i>& todo)
{
    const int L = scene.coarsestIndex();
    std::vector<int> tiles_of(L, 0);
    for (size_t k = 0; k < todo.size(); ++k)
        tiles_of[todo[k].z]++;
    std::vector<uchar> whole(L, 0);
    for (int l = 0; l < L; ++l)
    {
        if (tiles_of[l] < kWholeLevelShare * (double)scene.tiles[l].total())
            continue;
        LevelMaps& lm = scene.levels[l];
        bool quantized_whole = true;
        for (size_t i = 0; i < lm.quantized.size(); ++i)
            quantized_whole = quantized_whole && scene.deferred[l][i].image.empty();
        if (!quantized_whole)
            continue;
        for (size_t i = 0; i < lm.quantized.size(); ++i)
        {
            const uchar* data = lm.spread[i].data;
            spreadLabelsFast(lm.quantized[i], lm.spread[i], lm.T, 0);
            CV_Assert(lm.spread[i].data == data); // written in place
        }
        scene.tiles[l] |= ScenePyramid::TILE_MAPS;
        whole[l] = 1;
    }
    size_t kept = 0;
    for (size_t k = 0; k < todo.size(); ++k)
        if (!whole[todo[k].z])
            todo[kept++] = todo[k];
    todo.resize(kept);
}

void prepareRefinementLevels(ScenePyramid& scene, const std::vector<std::vector<Rect> >& regions)
{
    const int TW = ScenePyramid::TILE_W, TH = ScenePyramid::TILE_H;
    const int L = std::min(scene.coarsestIndex(), static_cast<int>(regions.size()));
    // the tiles to compute (level, tile column, tile row), marked first: no lock below. A tile's
    // maps read the quantized images T - 1 pixels further right and down: those tiles are
    // quantized first
    std::vector<Point3i> maps_todo, quant_todo;
    for (int l = 0; l < L; ++l)
    {
        Mat& grid = scene.tiles[l];
        const int T = scene.levels[l].T;
        const Point reach((T - 1 + TW - 1) / TW, (T - 1 + TH - 1) / TH);
        const Rect bounds(Point(0, 0), scene.levels[l].size);
        for (size_t k = 0; k < regions[l].size(); ++k)
        {
            const Rect r = regions[l][k] & bounds;
            if (r.empty())
                continue;
            for (int ty = r.y / TH; ty <= (r.y + r.height - 1) / TH; ++ty)
                for (int tx = r.x / TW; tx <= (r.x + r.width - 1) / TW; ++tx)
                    if (!(grid.at<uchar>(ty, tx) & ScenePyramid::TILE_MAPS))
                    {
                        markTiles(grid, tx, ty, Point(0, 0), ScenePyramid::TILE_MAPS, l,
                                  maps_todo);
                        markTiles(grid, tx, ty, reach, ScenePyramid::TILE_QUANTIZED, l,
                                  quant_todo);
                    }
        }
    }
    // a level whose tiles to quantize cover much of it: quantized whole (stripes cost less than
    // tiles, which blur and differentiate a margin around each)
    std::vector<int> tiles_of(L, 0);
    for (size_t k = 0; k < quant_todo.size(); ++k)
        tiles_of[quant_todo[k].z]++;
    for (int l = 0; l < L; ++l)
    {
        if (tiles_of[l] < kWholeLevelShare * (double)scene.tiles[l].total())
            continue;
        LevelMaps& lm = scene.levels[l];
        for (size_t i = 0; i < lm.quantized.size(); ++i)
        {
            LevelSource& src = scene.deferred[l][i];
            if (src.image.empty())
                continue;
            std::vector<Mat> q(1, lm.quantized[i]);
            fastQuantize(src.info, src.image, src.mask, 1, q);
            CV_Assert(q[0].data == lm.quantized[i].data); // written in place
            src.image.release(); // the level is whole now
        }
        scene.tiles[l] |= ScenePyramid::TILE_QUANTIZED;
    }
    parallel_for_(Range(0, static_cast<int>(quant_todo.size())), [&](const Range& range) {
        for (int k = range.start; k < range.end; ++k)
        {
            const int l = quant_todo[k].z;
            LevelMaps& lm = scene.levels[l];
            const Rect tile(quant_todo[k].x * TW, quant_todo[k].y * TH, TW, TH);
            for (size_t i = 0; i < lm.quantized.size(); ++i)
            {
                const LevelSource& src = scene.deferred[l][i];
                if (!src.image.empty())
                    quantizeLevelRect(src.info, src.image, src.mask, tile, lm.quantized[i]);
            }
        }
    });
    // likewise the spread images of a level whose tiles cover much of it, when the level is
    // quantized whole (the spreading reads T - 1 pixels beyond a tile)
    spreadWholeLevels(scene, maps_todo);
    parallel_for_(Range(0, static_cast<int>(maps_todo.size())), [&](const Range& range) {
        for (int k = range.start; k < range.end; ++k)
        {
            LevelMaps& lm = scene.levels[maps_todo[k].z];
            const Rect tile(maps_todo[k].x * TW, maps_todo[k].y * TH, TW, TH);
            for (size_t i = 0; i < lm.quantized.size(); ++i)
                spreadTile(lm.quantized[i], lm.T, tile, lm.spread[i]);
        }
    });
}

void forestPlanes(int dominant_window, int border, ScenePyramid& scene)
{
    const LevelMaps& top = scene.coarsest();
    const size_t M = top.quantized.size();
    scene.planes.assign(M, Mat());
    scene.plane_ptr.assign(M, (const uchar*)0);
    scene.border = border;
    for (size_t m = 0; m < M; ++m)
    {
        // the forest reads the plain quantized images (one label per point, as the templates it
        // was trained on; spreading would add labels and mislead the splits: doc/forest.md)
        const Size size = top.quantized[m].size();
        scene.planes[m] = Mat::zeros(size.height + 2 * border, size.width + 2 * border, CV_8U);
        Mat inner = scene.planes[m](Rect(border, border, size.width, size.height));
        dominantLabelsFast(top.quantized[m], dominant_window, inner);
        scene.plane_ptr[m] = scene.planes[m].ptr();
    }
    scene.plane_step = M ? scene.planes[0].step : 0;
}

void depthContexts(const Mat& depth, const std::vector<int>& T_at_level, int tolerance,
                   ScenePyramid& scene)
{
    const int L = static_cast<int>(T_at_level.size()) - 1;
    scene.depth_ctx.assign(L + 1, DepthContext());
    for (int l = 0; l < L; ++l)
    {
        scene.depth_ctx[l].set(depth, (T_at_level[l] / 2) << l);
        scene.depth_ctx[l].tolerance = tolerance;
        scene.depth_ctx[l].scale_shift = l;
    }
}

} // namespace detail
} // namespace forestmod
} // namespace cv
