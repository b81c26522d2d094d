// This file is part of OpenCV project.
// It is subject to the license terms in the LICENSE file found in the top-level directory
// of this distribution and at http://opencv.org/license.html

// Internal: the state behind forestmod::Detector (shared by detector.cpp and detector_pose.cpp).

#ifndef OPENCV_FORESTMOD_DETECTOR_IMPL_HPP
#define OPENCV_FORESTMOD_DETECTOR_IMPL_HPP

#include "opencv2/forestmod/detector.hpp"

#include <map>

namespace cv {
namespace forestmod {

/** Dense quantized patch of a template at the coarsest level, kept to build its descriptor. */
struct DensePatch
{
    std::vector<Mat> quantized; //!< [modality] CV_8U, the template's box at the coarsest level
    Mat mask;                   //!< CV_8U, nonzero on the object
};

struct TemplateRef
{
    String class_id;
    int template_id;
};

/** One search group: classes of similar size sharing a descriptor window and a forest. */
struct SearchGroup
{
    std::vector<String> classes;          //!< smallest first
    std::vector<int> rows;                //!< forest row (template id of the forest) -> Impl::rows
    std::vector<Point> grid;              //!< descriptor grid offsets from the anchor (coarsest level)
    std::vector<int> plane_of;            //!< per descriptor dimension
    std::vector<Point> dim_offset;        //!< per descriptor dimension
    int min_labels;                       //!< fewest labelled values of a training descriptor
    std::vector<uchar> flat_mask;         //!< per dimension: the bits the flat-window test counts
    Ptr<TemplateForest> forest;
    bool grey;                            //!< colourless classes: hue read with the grey label

    SearchGroup() : min_labels(0), grey(false) {}
};

struct Detector::Impl
{
    DetectorParams params;
    std::map<String, std::vector<TemplatePose> > poses;
    std::map<String, std::vector<DensePatch> > patches;
    //! depth samples (x, y relative to the template's top-left at level 0, z mm)
    std::map<String, std::vector<std::vector<Point3i> > > depth;

    // pose refinement
    std::map<String, Mesh> meshes;
    std::map<String, double> diameters;
    Ptr<Renderer> renderer;               //!< of the last scene size, guarded by render_mutex
    std::map<String, int> mesh_handles;   //!< handles in `renderer`
    Mutex render_mutex;

    // trained state
    bool trained;
    std::vector<TemplateRef> rows;        //!< all templates, class by class
    std::vector<SearchGroup> groups;      //!< windows and forests (DetectorParams::group_size_ratio)
    int z_min, z_max;                     //!< depth range (mm) of the templates' depth samples
    std::vector<Point> depth_probe;       //!< offsets (coarsest level) of the depth-range probes
    Mutex mutex;

    Impl() : trained(false), z_min(0), z_max(0) {}
};

} // namespace forestmod
} // namespace cv

#endif
