// This file is part of OpenCV project.
// It is subject to the license terms in the LICENSE file found in the top-level directory
// of this distribution and at http://opencv.org/license.html

// Internal: the outer silhouette of a closed mesh at a pose, from the edges where its faces turn
// from facing the camera to facing away, without drawing its faces (the edge alignment's points).

#ifndef OPENCV_FORESTMOD_SILHOUETTE_HPP
#define OPENCV_FORESTMOD_SILHOUETTE_HPP

#include "opencv2/forestmod/render.hpp"

namespace cv {
namespace forestmod {
namespace detail {

/** What a closed mesh's silhouette is made of, built once per mesh: the plane of each face and the
edges between faces. On a closed mesh drawn without the faces seen from inside (drawMesh()), the
boundary of the drawn mask lies on the projections of the edges whose two faces look different
ways (one towards the camera, one away), or of the edges of a face that faces the camera and
shares them with no other face or with more than one: a manifold edge between two faces that
look the same way has one face on each side of its projection. */
struct CV_EXPORTS SilhouetteEdges
{
    /** The faces' outward normals (not unit) and offsets, n faces each: x of every face, then y,
    z and offset. Face f looks towards a camera at c (model frame) when n . c > offset. */
    std::vector<float> plane;
    /** Per edge its faces; the second -1 for an edge of the first that no other face, or several,
    share. Ordered by the first face. */
    std::vector<Vec2i> faces;
    std::vector<Vec2i> ends; //!< per edge its vertices
    Point3f box_min, box_max; //!< the mesh's bounding box
    /** The edges in blocks of kBlockEdges, each with the chunks of kChunkFaces faces that its
    edges' faces belong to (chunk `nf / kChunkFaces` rounded up stands for the missing face of an
    edge that the second face leaves -1, as facing away; one more, never uniform, for a block of
    more than kBlockChunks chunks): block b's are block_chunks[block_start[b] ..
    block_start[b + 1]). A block whose chunks all face the camera, or all face away, holds no
    silhouette edge. The faces ordered by clusterFaces() make most chunks uniform. */
    std::vector<int> block_start, block_chunks;
    enum { kBlockEdges = 32, kChunkFaces = 16, kBlockChunks = 24 };
};

/** The silhouette edges of a mesh whose faces turn `winding` seen from outside (closedWinding(),
+1 or -1); empty for winding 0 (an open mesh: its silhouette is the drawn mask's). */
CV_EXPORTS SilhouetteEdges silhouetteEdges(const Mesh& mesh, int winding);

/** A point of the outer silhouette: model frame, mm (by an edge of SilhouetteEdges, half a pixel
inside the outline), and the outline's normal in the image (not unit, either sign). */
struct SilhouettePoint
{
    Point3f model;
    Vec2f normal;
};

/** The outer silhouette of `mesh` at (R, t) seen with K, in an image of size `image`: the
pixels of the silhouette edges' projections (8-connected lines between the rounded projections of
their ends) that border the region outside all of them, traced along the outline
(cv::findContours, RETR_EXTERNAL) over the whole projection, the object's parts off the image
included; of those inside the image but its outermost pixels, up to max_points evenly spaced
along the outline. Each gives the point of the edge nearest in depth at that pixel whose
projection is nearest the pixel (pixel centres at integer coordinates, as drawMesh() samples
them), moved half a pixel into the outline at its depth across the line of sight (where the
boundary pixels of drawMesh()'s mask lie on average), and the outline's normal there (between the
pixels two before and two after it): the boundary of drawMesh()'s mask to within a pixel, without
drawing the faces. Returns true with `pts` empty when a corner of the bounding box lies behind
the camera or the object does not project into the image; returns false, without points, when the
projected bounding box is more than twice the image's width or height (its buffers would be larger
than a drawing's crop: draw the object instead). The edges must be this mesh's (their planes one
per face). */
CV_EXPORTS bool meshSilhouette(const Mesh& mesh, const SilhouetteEdges& edges, const Matx33d& K,
                               const Matx33d& R, const Vec3d& t, Size image, int max_points,
                               std::vector<SilhouettePoint>& pts);

} // namespace detail
} // namespace forestmod
} // namespace cv

#endif
