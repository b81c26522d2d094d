// This file is part of OpenCV project.
// It is subject to the license terms in the LICENSE file found in the top-level directory
// of this distribution and at http://opencv.org/license.html

// Internal: drawing a mesh on the CPU, into the crop around its projection (verification, edge
// refinement).

#ifndef OPENCV_FORESTMOD_DRAW_MESH_HPP
#define OPENCV_FORESTMOD_DRAW_MESH_HPP

#include "opencv2/forestmod/render.hpp"
#include "silhouette.hpp"

namespace cv {
namespace forestmod {
namespace detail {

/** The mesh simplified by vertex clustering: vertices in the same cell of a grid of `cell` mm
are merged into their mean (position and colour), faces that lose a corner are dropped. The
verification and the pose refinements draw it with cells of drawingCell() (LM-O's meshes have
12-46 k faces, 9-24 k are left: the can 45.7 k -> 24.1 k, the driller 25.3 k -> 21.7 k, the ape
11.7 k -> 11.2 k).
cell <= 0: the mesh as it is. */
CV_EXPORTS Mesh coarseMesh(const Mesh& mesh, double cell);

/** Cell (mm) of the coarseMesh() that the pose stage and the verification draw for an object of
this diameter (mm): 1/64 of the diameter, at most 2.5 mm (about 1.4 px at 1 m with LM-O's
camera). The bound is for large objects: with cells of 1/64 alone the driller's are 4 mm, its
drawn silhouette loses detail and its correct hypotheses on real frames fit the edges less well
than the clutter's (doc/pose.md, "Drawing at detection time"). */
CV_EXPORTS double drawingCell(double diameter);

/** The side of the faces that never shows: +1 when the mesh is closed (at least 99 % of its
directed edges occur once, and their reverse once) and its faces turn counter-clockwise seen from
outside (positive signed volume), -1 when closed and turning the other way, 0 otherwise. On a
closed mesh the nearest surface along any ray is seen from outside, so drawMesh() skips the faces
seen from inside. */
CV_EXPORTS int closedWinding(const Mesh& mesh);

/** A mesh's faces in clusters that face about the same way and lie close together, so that a
drawing skips a cluster seen from behind without projecting its faces (on a closed mesh about half
the faces face away; the clusters hold three quarters of those at LM-O's poses). Cluster k is
faces begin[k] .. begin[k + 1] - 1 of the mesh as clusterFaces() ordered it. */
struct CV_EXPORTS FaceClusters
{
    /** A cluster's faces seen as one: the cone of their outward normals and a ball holding them. */
    struct Bound
    {
        Vec3d axis; //!< unit mean direction of the outward normals
        /** Of the largest angle of a normal to the axis (cos_half -1: never skipped). */
        double cos_half, sin_half;
        Vec3d centre; //!< of the ball, mm
        double radius;
    };
    std::vector<int> begin; //!< first face of each cluster, then the number of faces
    std::vector<Bound> bound;
    Point3f box_min, box_max; //!< the mesh's bounding box (a drawing's crop)
    /** True when every face of cluster k faces away from a camera at `centre` (model frame):
    each face's outward normal points away from the camera with some margin, whatever point of
    the ball the face lies at (its angle to the axis, the axis' to the ball and the ball's own
    angle sum to less than 90 degrees). */
    bool facesAway(int k, const Vec3d& centre) const;
};

/** Orders the faces of a closed mesh (winding: closedWinding(), not 0) by the direction of their
outward normals (an octahedral grid of 16 x 16 directions), then along a Z-order curve of their
centres, renumbers the vertices in the order the faces first use them (colours and normals
follow), and returns clusters of at most 16 consecutive faces of one direction. drawMesh() draws
the same mask and depth with the faces in any order; only the face it records at a pixel that
two faces cover at exactly the same depth may change. winding 0: the mesh is left as it is, no
clusters. */
CV_EXPORTS FaceClusters clusterFaces(Mesh& mesh, int winding);

/** The box of the projections of the eight corners of the box (lo, hi) (model frame, mm) at
(R, t) seen with K; false when a corner lies less than 1 mm in front of the camera. */
bool projectedBox(const Point3f& lo, const Point3f& hi, const Matx33d& K, const Matx33d& R,
                  const Vec3d& t, Rect2d& box);

/** The crop's margin around the projected bounding box with which the pose stage and the
verification draw (the refinement's 3 px around the silhouette and its blur's reach, the
verification's edge distance and region ring): one margin, so that the verification can score
the pose stage's last drawing of a hypothesis. */
const int kDrawMargin = 8;

/** Each face's colour: the mean of its vertices' colours (CV_8UC3, one row per face; grey
without colours). */
CV_EXPORTS Mat faceColours(const Mesh& mesh);

/** An object drawn at a pose, as the pose stage hands it to the verification: the crop and its
images, how it was drawn, and (drawn by drawMesh()) the face seen at each pixel. */
struct CV_EXPORTS Drawing
{
    Drawing() : source(0), margin(0) {}
    Rect rect; //!< the crop in the image (empty when nothing is drawn)
    Mat depth; //!< CV_16U, mm, 0 off the object
    Mat mask; //!< CV_8U
    /** What was drawn: the id a MeshDrawer was given (the pose stage's DrawnMesh::id, never
    reused, so a mesh set again is not taken for the old one), 0 when unknown. */
    uint64 source;
    Matx33d K, R;
    Vec3d t;
    Size image;
    int margin;
    Mat face; //!< CV_32S, the nearest face of each pixel, -1 for none (drawMesh() only)

    /** True when this is `source` (not 0) drawn by drawMesh() at exactly (R, t) with K into an
    image of size `image` with `margin`. */
    bool isOf(uint64 source, const Matx33d& K, const Matx33d& R, const Vec3d& t, Size image,
              int margin) const;
};

/** drawMesh() below without colours, with the face seen at each pixel (Drawing::face). */
CV_EXPORTS void drawMesh(const Mesh& mesh, int winding, const Matx33d& K, const Matx33d& R,
                         const Vec3d& t, Size image, int margin, Drawing& drawing,
                         const FaceClusters* clusters = 0);

/** A hypothesis drawn for the verification or the pose refinements: the mesh at (R, t) seen
with K, drawn into the crop `rect` around its projection (the projected bounding box widened by
margin, clipped to the image of size `image`): z-buffered triangles, a pixel is the object's when
its centre is covered (the Renderer's rule), vertex colours interpolated without shading (hue and
saturation are what the scores read; grey without colours; not computed for noArray()), depth in
mm (CV_16U), mask CV_8U. rect is empty when a corner of the bounding box is behind the camera or
nothing projects into the image. winding: closedWinding() of the mesh (0 draws every face).
clusters: clusterFaces() of the mesh, whose clusters seen from behind are skipped whole (the
same image as without them), or 0. No lock (unlike the OSMesa Renderer): the hypotheses are
drawn in parallel. */
CV_EXPORTS void drawMesh(const Mesh& mesh, int winding, const Matx33d& K, const Matx33d& R,
                         const Vec3d& t, Size image, int margin, Rect& rect, OutputArray color,
                         Mat& depth, Mat& mask, const FaceClusters* clusters = 0);

/** How the pose refinements and the depth check see the object at a pose: its depth (CV_16U,
mm, 0 off the object) and mask (CV_8U) in the crop `rect` of the scene image (empty when nothing
is drawn). */
class CV_EXPORTS ObjectDrawer
{
public:
    virtual ~ObjectDrawer() {}
    /** Size of the scene image (the edge maps' size). */
    virtual Size imageSize() const = 0;
    virtual void draw(const Matx33d& K, const Matx33d& R, const Vec3d& t, Rect& rect, Mat& depth,
                      Mat& mask) const = 0;
    /** draw() into a Drawing that can be kept (rect, depth, mask; what colours it when the
    drawer can). */
    virtual Ptr<Drawing> drawing(const Matx33d& K, const Matx33d& R, const Vec3d& t) const;
    /** The object's outer silhouette without drawing it (meshSilhouette()), when the drawer
    can: false when it cannot, and the silhouette is then the drawn mask's boundary. */
    virtual bool silhouette(const Matx33d& K, const Matx33d& R, const Vec3d& t, int max_points,
                            std::vector<SilhouettePoint>& pts) const
    {
        CV_UNUSED(K), CV_UNUSED(R), CV_UNUSED(t), CV_UNUSED(max_points), CV_UNUSED(pts);
        return false;
    }
};

/** drawMesh() of a mesh (e.g. coarseMesh()) with its closedWinding(): no lock, so the
hypotheses of a frame refine in parallel. The mesh (and its clusters, clusterFaces(), and
silhouette edges, silhouetteEdges(), or 0) must outlive the drawer. `source` names the mesh in
the drawings (Drawing::source). */
class CV_EXPORTS MeshDrawer : public ObjectDrawer
{
public:
    MeshDrawer(const Mesh& mesh, int winding, Size image, uint64 source = 0,
               const FaceClusters* clusters = 0, const SilhouetteEdges* silhouette = 0)
        : mesh_(mesh), winding_(winding), image_(image), source_(source), clusters_(clusters),
          silhouette_(silhouette)
    {
    }
    Size imageSize() const CV_OVERRIDE { return image_; }
    void draw(const Matx33d& K, const Matx33d& R, const Vec3d& t, Rect& rect, Mat& depth,
              Mat& mask) const CV_OVERRIDE;
    Ptr<Drawing> drawing(const Matx33d& K, const Matx33d& R, const Vec3d& t) const CV_OVERRIDE;
    /** meshSilhouette() when the drawer has the mesh's silhouette edges (not empty) and the
    object's projection is not too large for it. */
    bool silhouette(const Matx33d& K, const Matx33d& R, const Vec3d& t, int max_points,
                    std::vector<SilhouettePoint>& pts) const CV_OVERRIDE;

private:
    const Mesh& mesh_;
    const int winding_;
    const Size image_;
    const uint64 source_;
    const FaceClusters* clusters_;
    const SilhouetteEdges* silhouette_;
};

/** The OSMesa Renderer's drawing of mesh `handle`: the whole image (the public refinePose(),
refinePoseEdges() and depthCheck() take a Renderer). */
class CV_EXPORTS RendererDrawer : public ObjectDrawer
{
public:
    RendererDrawer(Renderer& renderer, int handle) : renderer_(renderer), handle_(handle) {}
    Size imageSize() const CV_OVERRIDE { return renderer_.size(); }
    void draw(const Matx33d& K, const Matx33d& R, const Vec3d& t, Rect& rect, Mat& depth,
              Mat& mask) const CV_OVERRIDE;

private:
    Renderer& renderer_;
    const int handle_;
};

} // namespace detail
} // namespace forestmod
} // namespace cv

#endif
