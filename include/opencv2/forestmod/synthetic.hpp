// This file is part of OpenCV project.
// It is subject to the license terms in the LICENSE file found in the top-level directory
// of this distribution and at http://opencv.org/license.html

#ifndef OPENCV_FORESTMOD_SYNTHETIC_HPP
#define OPENCV_FORESTMOD_SYNTHETIC_HPP

#include "opencv2/core.hpp"
#include "opencv2/forestmod/render.hpp"

namespace cv {
namespace forestmod {

//! @addtogroup forestmod_render
//! @{

/** @brief Parameters of synthetic RGB-D test scenes. FileStorage keys are the field names. */
struct CV_EXPORTS_W_SIMPLE SyntheticSceneParams
{
    CV_WRAP SyntheticSceneParams();

    /** Other meshes drawn as clutter around the object. Default 3. */
    CV_PROP_RW int clutter_objects;
    /** Largest random rotation (degrees) applied to the given view: the object's pose then lies
    between templates, as in real data. Default 5. */
    CV_PROP_RW double max_perturbation_deg;
    /** Relative change of the viewing distance, uniform in [-x, x]. Default 0.03. */
    CV_PROP_RW double distance_jitter;
    /** The object centre is placed uniformly inside the image shrunk by this share per side.
    Default 0.2. */
    CV_PROP_RW double margin;
    /** Depth noise: sigma = depth_noise * (z / 1 m)^2 mm, the axial noise model of
    Kinect-class sensors (Khoshelham and Elberink 2012: ~1.5 mm at 1 m). Default 1.5. */
    CV_PROP_RW double depth_noise;
    /** Share of pixels without depth (0), as sensor holes. Default 0.02. */
    CV_PROP_RW double depth_dropout;
    /** The supporting plane lies this far (mm) behind the object centre. Default 100. */
    CV_PROP_RW double plane_offset;
    /** Gaussian colour noise (grey levels). Default 2. */
    CV_PROP_RW double color_noise;

    void read(const FileNode& fn);
    void write(FileStorage& fs) const;
};

/** @brief A synthetic RGB-D scene with its ground truth. */
struct CV_EXPORTS_W_SIMPLE SyntheticScene
{
    CV_PROP Mat color;        //!< CV_8UC3 BGR: rendered objects over a background image
    CV_PROP Mat depth;        //!< CV_16UC1 mm: objects + supporting plane, with sensor noise
    CV_PROP Mat labels;       //!< CV_8UC1: 1 on the object, 2.. on clutter, 0 background
    CV_PROP Matx33d R;        //!< the object's pose, model -> camera
    CV_PROP Vec3d t;          //!< mm
    CV_PROP Point2d center;   //!< projection of the object's centre (Mesh::center())
    CV_PROP Rect bbox;        //!< box of the visible object
    CV_PROP double visible;   //!< visible share of the object's silhouette
};

/** @brief Renders test scenes: one object at a pose near a given view, other meshes as clutter,
a real colour image as background, a supporting plane, Kinect-like depth noise.

Deterministic for a given RNG state. Uses the renderer it is given (one thread at a time). */
class CV_EXPORTS SceneSynthesizer
{
public:
    SceneSynthesizer(const Ptr<Renderer>& renderer, const Matx33d& K,
                     const SyntheticSceneParams& params = SyntheticSceneParams());
    /** Adds a mesh (uploaded once); returns its index. Every mesh may serve as clutter. */
    int addObject(const Mesh& mesh);
    /** Background colour images (any size: resized to the renderer's size). Without any, a
    random smooth texture is drawn. */
    void setBackgrounds(const std::vector<Mat>& images);
    /** A scene of object `index` seen from a view (R, t) that looks at the object's centre (as
    ViewSampler makes them): the view is perturbed, moved to a random image location and drawn
    with clutter. */
    SyntheticScene render(int index, const Matx33d& R, const Vec3d& t, RNG& rng) const;

private:
    Ptr<Renderer> renderer_;
    Matx33d K_;
    SyntheticSceneParams params_;
    std::vector<int> handles_;
    std::vector<Point3d> centers_;
    std::vector<double> diameters_;
    std::vector<Mat> backgrounds_;
};

//! @}

} // namespace forestmod
} // namespace cv

#endif // OPENCV_FORESTMOD_SYNTHETIC_HPP
