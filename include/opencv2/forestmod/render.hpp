// This file is part of OpenCV project.
// It is subject to the license terms in the LICENSE file found in the top-level directory
// of this distribution and at http://opencv.org/license.html

#ifndef OPENCV_FORESTMOD_RENDER_HPP
#define OPENCV_FORESTMOD_RENDER_HPP

#include "opencv2/core.hpp"

#include <functional>
#include <vector>

namespace cv {
namespace forestmod {

//! @addtogroup forestmod_render
//! @{

/** @brief A triangle mesh with per-vertex normals and colours, in millimetres.

A plain value type (copyable; the fields are public). Meshes built in code may leave `normals`
and `colors` empty: Renderer::addMesh() then computes area-weighted vertex normals and uses grey.
*/
class CV_EXPORTS_W Mesh
{
public:
    std::vector<Point3f> vertices; //!< vertex positions, mm, in the model frame of the file
    std::vector<Vec3f> normals;    //!< unit vertex normals (computed when the file has none)
    std::vector<Vec3b> colors;     //!< vertex colours, BGR (grey 128 when the file has none)
    std::vector<Vec3i> faces;      //!< triangles: indices into `vertices`

    /** Limits of load(): a file declaring more is refused before anything is allocated. */
    enum Limits
    {
        MAX_VERTICES = 1 << 24,     //!< vertices (and any element count but faces) of a file
        MAX_FACES = 1 << 25,        //!< faces of a file
        MAX_FACE_INDICES = 256,     //!< vertex indices of one PLY face
        MAX_COORDINATE_MM = 1000000 //!< |x|, |y|, |z| of a vertex (mm, after load's scale)
    };

    /** @brief Loads a mesh with assimp (PLY ascii/binary, OBJ, STL and every other format
    assimp reads).

    Every mesh of the file is merged into one (node transforms applied); polygons are
    triangulated, points and lines dropped, identical vertices joined. Vertex colours are read
    from the first colour set; without one the vertices are grey (128). Normals are taken from
    the file when it has them, otherwise computed (computeNormals()). Coordinates are kept as
    they are in the file (no centring): poses of datasets like BOP refer to them.

    A PLY file is first checked against its header, without allocating: header lines of
    exactly their fields (identifier names, no control characters), element counts within
    MAX_VERTICES / MAX_FACES, faces of at most MAX_FACE_INDICES indices, every value a number of
    its type (reals finite; ASCII reals within +-1e12 as the file holds them), and the data
    exactly as long as the header declares (a truncated file, or more data than declared, is
    refused). The mesh is then validated (validate()).

    @param path  the file.
    @param scale file units -> mm (1 for files in mm, 1000 for files in metres).
    @throws cv::Exception when the file is missing, unreadable, corrupt, beyond the limits or
    degenerate (see validate()), with the path and the problem (or what assimp said).
    */
    static Mesh load(const String& path, double scale = 1.0);

    /** @brief Area-weighted vertex normals from the faces (overwrites `normals`). Vertices of
    no non-degenerate face get (0, 0, 1). */
    void computeNormals();

    /** @brief Throws a cv::Exception naming the problem when the mesh is inconsistent: no
    vertices or faces, a face index out of range, normals/colours of another length than the
    vertices, non-finite coordinates or beyond +-MAX_COORDINATE_MM, a degenerate mesh (all
    vertices equal, every triangle of zero area). */
    void validate() const;

    Point3f bboxMin() const; //!< axis-aligned bounding box, minimum corner (mm)
    Point3f bboxMax() const; //!< axis-aligned bounding box, maximum corner (mm)
    Point3f center() const;  //!< centre of the bounding box (mm), not the centroid
    /** @brief Largest distance between two vertices (mm), as BOP's `models_info.json` defines
    the diameter. Exact; computed on each call (O(n log n) plus a pruned pair search). */
    double diameter() const;
    bool empty() const; //!< no vertices or no faces
};

/** @brief Off-screen OpenGL renderer (OSMesa, Mesa's llvmpipe: no display, no GPU).

Camera model: pinhole with the intrinsics K (fx, fy, cx, cy; skew ignored), OpenCV axes (x right,
y down, z forward), pixel (u, v) has its centre at integer coordinates, as cv::projectPoints.
A pose (R, t) maps model to camera coordinates, X_c = R X_m + t, t in mm: BOP's `cam_R_m2c`,
`cam_t_m2c`. Outputs:
- colour `CV_8UC3` BGR: vertex colour x (ambient + (1 - ambient) |n . l|), light at the camera
  centre (l = direction from the surface point to the camera), black background;
- depth `CV_16UC1`: the true camera z of the surface in mm (perspective-correct, rounded to the
  nearest mm, at least 1 on the object), 0 for the background;
- mask `CV_8UC1`: 255 on the object, 0 elsewhere; always equal to depth > 0.

No anti-aliasing: a pixel belongs to the object when its centre is covered (OpenGL's rule).
Meshes are uploaded once by addMesh() and referred to by their handle afterwards.

Thread safety: a Renderer owns its own OpenGL context and must be used by one thread at a
time (calls are serialized by an internal mutex; the context is made current in the calling
thread at each call). Several Renderers may exist in one process.
*/
class CV_EXPORTS_W Renderer
{
public:
    virtual ~Renderer();

    /** @brief Creates an OSMesa context (GL 3.3 core) rendering images of `size`.
    @throws cv::Exception if OSMesa is unavailable (module built without it) or fails. */
    static Ptr<Renderer> create(Size size);

    virtual Size size() const = 0;

    /** @brief Uploads a mesh to the GPU buffers of this renderer; returns its handle (0, 1, ...).
    Missing normals are computed and missing colours are grey. The mesh is validated. */
    virtual int addMesh(const Mesh& mesh) = 0;

    /** @brief Number of meshes added. */
    virtual int numMeshes() const = 0;

    /** @brief Ambient share of the shading in [0, 1] (default 0.3); the rest is diffuse. */
    virtual void setAmbient(double ambient) = 0;
    virtual double getAmbient() const = 0;

    /** @brief Renders one mesh.
    @param handle  from addMesh().
    @param R, t    model -> camera (BOP `cam_R_m2c`, `cam_t_m2c`, mm).
    @param K       camera matrix [fx 0 cx; 0 fy cy; 0 0 1] (no skew; others raise).
    @param color   CV_8UC3 BGR (skipped when noArray()).
    @param depth   CV_16UC1 mm, 0 = background (skipped when noArray()).
    @param mask    CV_8UC1, 255 on the object (skipped when noArray()).
    */
    virtual void render(int handle, const Matx33d& R, const Vec3d& t, const Matx33d& K,
                        OutputArray color, OutputArray depth = noArray(),
                        OutputArray mask = noArray()) = 0;

    /** @brief Renders several meshes into one image, z-buffered.
    @param handles meshes (a handle may repeat); at most 255.
    @param R, t    one pose per entry of handles.
    @param labels  CV_8UC1: 0 background, i + 1 where entry i of handles is visible.
    */
    virtual void renderScene(const std::vector<int>& handles, const std::vector<Matx33d>& R,
                             const std::vector<Vec3d>& t, const Matx33d& K, OutputArray color,
                             OutputArray depth = noArray(), OutputArray labels = noArray()) = 0;
};

/** @brief One viewpoint of a ViewSampler: a pose and where it comes from. */
struct CV_EXPORTS_W_SIMPLE ViewPose
{
    CV_WRAP ViewPose();
    CV_PROP_RW Matx33d R;       //!< model -> camera rotation
    CV_PROP_RW Vec3d t;         //!< model -> camera translation (mm)
    CV_PROP_RW int view_index;  //!< index into ViewSampler::viewpoints()
    CV_PROP_RW int radius_index;  //!< index into Params::radii
    CV_PROP_RW int inplane_index; //!< index into ViewSampler::inplaneAngles()
    CV_PROP_RW double radius;     //!< camera distance to the object centre (mm)
    CV_PROP_RW double elevation;  //!< degrees above the model's xy plane (90 = from +z)
    CV_PROP_RW double azimuth;    //!< degrees, atan2(y, x) of the viewing direction
    CV_PROP_RW double inplane;    //!< rotation about the camera z axis (degrees)
};

/** @brief Viewpoints on the upper hemisphere from a recursively subdivided icosahedron.

The unit icosahedron (a vertex pair on the z axis) is subdivided `level` times (each triangle into
four, new vertices pushed onto the sphere): 12, 42, 162, 642, 2562 vertices for levels 0..4, with
neighbouring directions about 63, 32, 16, 8 and 4 degrees apart. The directions d whose elevation
asin(d.z) lies in [min_elevation, max_elevation] are kept ("upper" = +z of the model frame).
For each radius r, direction d and in-plane angle a, the camera sits at `center + r d`, looks at
`center` and is rolled by a about its optical axis:
  R = Rz(a) R0(d),  t = -R center + (0, 0, r),
so the object's centre projects onto the principal point. R0's image "up" (-y) is the model's +z
projected (at the pole: the direction of increasing elevation at that azimuth). Positive a turns
image content clockwise on screen (image y down): a pixel offset (du, dv) from the principal point
becomes (cos a du - sin a dv, sin a du + cos a dv) for fx = fy.

Order (deterministic): radius (as given), then direction (generation order of the icosphere,
filtered), then in-plane angle (ascending).
*/
struct CV_EXPORTS_W_SIMPLE ViewSampler
{
    /** @brief Sampling parameters. FileStorage keys are the field names.

    Defaults follow LINEMOD's training set (Hinterstoisser et al., ACCV 2012): upper hemisphere,
    about 15 degrees between neighbouring views, distances 650-1150 mm in 100 mm steps, in-plane
    rotations -45..45 degrees in 15 degree steps: 91 x 6 x 7 = 3822 poses (ACCV 2012 reports about
    3115; their exact icosahedron orientation and step are not published). */
    struct CV_EXPORTS_W_SIMPLE Params
    {
        CV_WRAP Params();
        /** Icosahedron subdivisions, >= 0. Default 2 (162 directions on the sphere, 91 on the
        upper hemisphere, neighbours ~16 degrees apart ~ ACCV 2012's 15). */
        CV_PROP_RW int level;
        /** Lowest elevation kept (degrees). Default 0: the upper hemisphere incl. the equator. */
        CV_PROP_RW double min_elevation;
        /** Highest elevation kept (degrees). Default 90. */
        CV_PROP_RW double max_elevation;
        /** Camera distances to the object centre (mm). Default 650, 750, ..., 1150 (ACCV 2012). */
        CV_PROP_RW std::vector<double> radii;
        /** In-plane rotation range and step (degrees). Defaults -45, 45, 15 (ACCV 2012). The
        angles are min, min + step, ... <= max (+1e-9). */
        CV_PROP_RW double inplane_min;
        CV_PROP_RW double inplane_max;
        CV_PROP_RW double inplane_step;

        /** A coarse set for tests and quick runs: level 0, radii {800}, in-plane {0}
        (6 directions on the upper hemisphere -> 6 poses). */
        CV_WRAP static Params coarse();

        void read(const FileNode& fn);
        void write(FileStorage& fs) const;
    };

    CV_WRAP ViewSampler();
    CV_WRAP explicit ViewSampler(const Params& params);

    /** Checks the parameters; throws cv::Exception naming the bad one. */
    void validate() const;

    /** Unit directions from the object centre to the camera (model frame), filtered. */
    CV_WRAP std::vector<Vec3d> viewpoints() const;
    /** The in-plane angles (degrees), ascending. */
    CV_WRAP std::vector<double> inplaneAngles() const;
    /** Number of poses = radii x viewpoints x in-plane angles (StsOutOfRange beyond INT_MAX). */
    CV_WRAP int size() const;
    /** All poses looking at `center` (model frame, mm; use Mesh::center()). */
    CV_WRAP std::vector<ViewPose> poses(const Point3d& center = Point3d()) const;

    /** @brief The pose of a camera at `center + radius * direction` looking at `center`, rolled
    by `inplane_deg` about its optical axis (see the class description). */
    static void lookAt(const Point3d& center, const Vec3d& direction, double radius,
                       double inplane_deg, Matx33d& R, Vec3d& t);

    /** The directions of the full icosphere of a level, in generation order (10 4^level + 2). */
    static std::vector<Vec3d> icosphere(int level);

    CV_PROP_RW Params params;
};

/** @brief A rendered, labelled template: images of one view and its pose. */
struct CV_EXPORTS_W_SIMPLE TemplateView
{
    CV_WRAP TemplateView(); //!< identity pose, empty images, indices -1
    CV_PROP_RW Mat color;   //!< CV_8UC3 BGR, full image size
    CV_PROP_RW Mat depth;   //!< CV_16UC1 mm, 0 = background
    CV_PROP_RW Mat mask;    //!< CV_8UC1 255 on the object
    CV_PROP_RW Matx33d R;   //!< model -> camera rotation
    CV_PROP_RW Vec3d t;     //!< model -> camera translation (mm)
    CV_PROP_RW Matx33d K;   //!< camera matrix of the images
    CV_PROP_RW int view_id; //!< index of this template in the sampler's order (0, 1, ...)
    CV_PROP_RW int view_index;    //!< direction index (ViewSampler::viewpoints())
    CV_PROP_RW int radius_index;  //!< index into ViewSampler::Params::radii
    CV_PROP_RW int inplane_index; //!< index into ViewSampler::inplaneAngles()
    CV_PROP_RW double radius;     //!< mm
    CV_PROP_RW double elevation;  //!< degrees
    CV_PROP_RW double azimuth;    //!< degrees
    CV_PROP_RW double inplane;    //!< degrees
    CV_PROP_RW Rect bbox;         //!< bounding rectangle of the mask (empty if not visible)
};

/** @brief Renders a mesh from every pose of a sampler (camera looking at mesh.center()).

The mesh is uploaded once. The output order is the sampler's order; `view_id` is the position.
Deterministic: the same inputs give the same images and poses.
Memory: every template holds full-size images (640x480: 1.8 MB); for thousands of templates
prefer the streaming overload.
@param progress called after each template with (done, total); return false to stop early
(`out` then holds the templates rendered so far).
*/
CV_EXPORTS void renderTemplates(const Mesh& mesh, const ViewSampler& sampler, const Matx33d& K,
                                Size size, std::vector<TemplateView>& out,
                                const std::function<bool(int done, int total)>& progress
                                = std::function<bool(int, int)>());

/** @brief Streaming variant: `sink` receives each template as soon as it is rendered (images
are not kept); return false from it to stop. Same order and content as the other overload. */
CV_EXPORTS void renderTemplates(const Mesh& mesh, const ViewSampler& sampler, const Matx33d& K,
                                Size size,
                                const std::function<bool(const TemplateView& view, int done,
                                                         int total)>& sink);

/** @brief Streaming variant on an existing renderer and an already uploaded mesh (no re-upload
across calls). `center` is the point the cameras look at (Mesh::center() of that mesh). */
CV_EXPORTS void renderTemplates(Renderer& renderer, int handle, const Point3d& center,
                                const ViewSampler& sampler, const Matx33d& K,
                                const std::function<bool(const TemplateView& view, int done,
                                                         int total)>& sink);

//! @}

} // namespace forestmod
} // namespace cv

#endif // OPENCV_FORESTMOD_RENDER_HPP
