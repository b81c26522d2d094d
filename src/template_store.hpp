// This file is part of OpenCV project.
// It is subject to the license terms in the LICENSE file found in the top-level directory
// of this distribution and at http://opencv.org/license.html

// Internal: the templates of a detector. cv::linemod::Detector keeps every template's LINEMOD
// pyramid (its `class_templates`, read by its own methods); the store keeps, for the same
// template, everything forestmod adds (pose label, dense patch for the forest's descriptor, depth
// samples) in one record, added and removed with the pyramid in one place.

#ifndef OPENCV_FORESTMOD_TEMPLATE_STORE_HPP
#define OPENCV_FORESTMOD_TEMPLATE_STORE_HPP

#include "opencv2/forestmod/detector.hpp"
#include "similarity.hpp"
#include "depth_modality.hpp"
#include "modality_roles.hpp"

#include <map>

namespace cv {
namespace forestmod {
namespace detail {

typedef std::map<String, std::vector<TemplatePyramid> > ClassPyramids;

/** Dense quantized patch of a template at the coarsest level, kept to build its descriptor. */
struct DensePatch
{
    std::vector<Mat> quantized; //!< [modality] CV_8U, the template's box at the coarsest level
    Mat mask;                   //!< CV_8U, nonzero on the object; empty: descriptor from features
};

/** What forestmod keeps of a template besides its LINEMOD pyramid. */
struct TemplateRecord
{
    TemplatePose pose;            //!< pose label (valid false without one); box: level-0 box
    DensePatch patch;
    std::vector<Point3i> depth;   //!< depth samples: x, y relative to the box's top-left, z mm
    /** Per pyramid level l, the smallest and largest feature coordinates of every modality
    ([2 l], [2 l + 1]; (0, 0) twice for a level without features): set by TemplateStore from
    the pyramid (what refinementRegions() reads for every coarse match). */
    std::vector<Point> feature_extent;
};

class CV_EXPORTS TemplateStore // exported for the tests
{
public:
    /** Appends a template: its pyramid to `pyramids` (the base class's map) and its record here.
    Returns its id in the class. */
    int add(ClassPyramids& pyramids, const String& class_id, const TemplatePyramid& tp,
            const TemplateRecord& record);
    /** Replaces a whole class (readClass). Both vectors must have the same size. */
    void setClass(ClassPyramids& pyramids, const String& class_id,
                  const std::vector<TemplatePyramid>& tps,
                  const std::vector<TemplateRecord>& records);
    /** The records of a class, in template order, or null. */
    const std::vector<TemplateRecord>* classRecords(const String& class_id) const;
    /** The level-0 size of each template of a class (its pyramid's first template), in template
    order, or null: one flat array per class, what non-maximum suppression reads per match. */
    const std::vector<Size>* classSizes(const String& class_id) const;
    /** The record of a template, or null. */
    const TemplateRecord* find(const String& class_id, int template_id) const;
    /** The record of a template; StsBadArg naming it when there is none. */
    const TemplateRecord& get(const String& class_id, int template_id) const;
    void clear(ClassPyramids& pyramids);

private:
    std::map<String, std::vector<TemplateRecord> > records_;
    std::map<String, std::vector<Size> > sizes_;
};

/** LINEMOD's template extraction (every modality, every pyramid level, cropped to the features'
box) plus the record: the dense coarsest-level patch and up to `depth_samples` depth samples
(with a DepthNormal modality). False when some level has no feature (the view is refused, as
cv::linemod refuses it); a colourless view just has no hue features. `box` receives the template's
box in level-0 pixels. */
bool makeTemplate(const std::vector<Ptr<cv::linemod::Modality> >& modalities,
                  const ModalityRoles& roles, int pyramid_levels, const std::vector<Mat>& sources,
                  const Mat& object_mask, int depth_samples, TemplatePyramid& tp,
                  TemplateRecord& record, Rect& box);

/** A template's depth samples with its pose geometry (null samples without samples, focal
lengths 0 without a usable pose). */
DepthTemplate depthTemplate(const TemplateRecord& record);

} // namespace detail
} // namespace forestmod
} // namespace cv

#endif
