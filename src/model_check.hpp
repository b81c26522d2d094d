// This file is part of OpenCV project.
// It is subject to the license terms in the LICENSE file found in the top-level directory
// of this distribution and at http://opencv.org/license.html

// Internal: range checks of everything a model file holds (and of DetectorParams, shared with
// Detector::setParams), so that a loaded detector is as valid as one trained in memory. Every
// check raises a cv::Exception whose message names the field, its value and the allowed range.

#ifndef OPENCV_FORESTMOD_MODEL_CHECK_HPP
#define OPENCV_FORESTMOD_MODEL_CHECK_HPP

#include "opencv2/forestmod/detector.hpp"
#include "detector_impl.hpp"
#include "similarity.hpp"
#include "template_store.hpp"

namespace cv {
namespace forestmod {
namespace detail {

//! Limits of a model (README, "Model files"): beyond them a file is refused, not allocated.
enum ModelLimits
{
    MAX_PYRAMID_LEVELS = 8,        //!< pyramid_levels
    MAX_T = 64,                    //!< every T of T_at_level
    MAX_TEMPLATE_SIZE = 4096,      //!< template width / height at level 0 (pixels)
    MAX_TEMPLATE_FEATURES = 8192,  //!< features of one template (one level, one modality)
    MAX_MODALITIES = 8,            //!< modalities of a detector
    MAX_LOCATION_STEP = 16,        //!< DetectorParams::location_step
    MAX_SURVIVORS = 64,            //!< DetectorParams::max_survivors
    MAX_DEPTH_SAMPLE_MM = 65535    //!< depth of a depth sample (16-bit depth images)
};

/** DetectorParams in their documented ranges (DetectorParams in detector.hpp); used by the
constructor, setParams and the model loader alike. */
void checkDetectorParams(const DetectorParams& p);

/** ForestParams in their documented ranges (forest.hpp); used where a forest is made and by
checkDetectorParams, so that a model file's forest parameters are refused on load, not when the
first match() trains (defined in forest.cpp). */
void checkForestParams(const ForestParams& p);

/** The most text load() reads from a model file (1 GiB, decompressed), and save() writes. A 2.9 GB
text makes cv::FileStorage (OpenCV 4.6) itself fail an assertion while parsing. */
const size_t MAX_MODEL_TEXT_BYTES = size_t(1) << 30;

/** cv::FileStorage's format flag of a model file name: FORMAT_JSON for .json, FORMAT_XML for .xml,
else FORMAT_YAML; a trailing ".gz" (compression) is left out. */
int modelFileFormat(const String& filename);

/** Writes a model's text (cv::FileStorage::MEMORY) to `filename`, gzip-compressed when the name
ends with ".gz". Raises, writing nothing, when the text is longer than max_bytes (the default:
what load() reads; smaller in tests). */
CV_EXPORTS void writeModelText(const String& filename, const String& text,
                               size_t max_bytes = MAX_MODEL_TEXT_BYTES);

/** The text of a model file (a .gz file decompressed), for cv::FileStorage::MEMORY: at most
MAX_MODEL_TEXT_BYTES, and every base64 block (YAML "!!binary |", JSON "$base64$", XML
type_id="binary") starting with a data type header: OpenCV 4.6's base64 reader loops forever on
a block whose header is empty; in YAML and JSON text every bracket closed by its own and none
left open (its YAML parser loops forever on a stray ']' followed by an unclosed '[', found by
fuzzing). Its errors name `func`. */
String readModelText(const String& filename, const char* func = "forestmod::Detector::load");

/** Opens `fs` on readModelText(filename) (cv::FileStorage::MEMORY): every guard of load() for
any model-like file (readClasses, TemplateForest::load); OpenCV's parse errors and the standard
exceptions its parsers let through become StsParseError naming `func` and the file. */
void openModelText(FileStorage& fs, const String& filename, const char* func);

/** cv::read of a matrix node, after checking that it is a 2-D matrix ("opencv-matrix") of at
most max_elements values (rows x cols x channels) whose data holds exactly that many values:
OpenCV's reader allocates rows x cols first, whatever the data holds. An absent node gives an
empty matrix. */
void readMat(const FileNode& fn, Mat& m, int64 max_elements, const String& where);

/** pyramid_levels in [1, MAX_PYRAMID_LEVELS], one T per level, each in [1, MAX_T]. `who` and
`code`: the error's prefix and code (a model file's by default; the constructor passes its own). */
void checkPyramidGeometry(const std::vector<int>& T_at_level, int pyramid_levels,
                          const char* who = "forestmod model", int code = Error::StsParseError);

/** The parameters of a modality read from a file or given to the constructor (ColorGradient,
DepthNormal; ColorHue checks its own): finite thresholds, num_features in
[1, MAX_TEMPLATE_FEATURES]. `who`, `code`: as for checkPyramidGeometry(). */
void checkModality(const Ptr<linemod::Modality>& modality, int index,
                   const char* who = "forestmod model", int code = Error::StsParseError);

/** The structure of one template's node before linemod::Template::read reads it: integer
width, height and pyramid_level, and features a sequence of [x, y, label] integer triples (a
string, a real or a NaN where an integer is expected is refused, not read as 0 or INT_MIN). */
void checkTemplateNode(const FileNode& fn, const String& where);

/** One template pyramid (num_modalities x pyramid_levels templates, level-major as LINEMOD
stores them): levels in order, level-0 width and height in [1, MAX_TEMPLATE_SIZE] and level l's
equal to level 0's >> l (LINEMOD's cropTemplates), at least one feature per level, at most
MAX_TEMPLATE_FEATURES per template, every label in 0..7 and every feature inside its template
(0 <= x <= width, 0 <= y <= height). Errors with `code`, their messages starting with `where`
(model files: StsParseError; addSyntheticTemplate: StsBadArg). */
void checkTemplatePyramid(const TemplatePyramid& tp, int num_modalities, int pyramid_levels,
                          const String& where, int code = Error::StsParseError);

/** A template pose (when valid): finite R and t with t's z > 0, K with entries within 1e6,
focal lengths of at least 1 pixel and the last row (0, 0, 1), the object centre projecting
within 1e6 pixels, and a box of exactly the template's level-0 size at a position in
[0, 65535] (the box of the template's features in its own image). Errors as
checkTemplatePyramid's. */
void checkTemplatePose(const TemplatePose& pose, const linemod::Template& level0,
                       const String& where, int code = Error::StsParseError);

/** A dense patch (when present): CV_8UC1 mask of the coarsest template's (height + 1) x
(width + 1), one CV_8UC1 quantized plane per modality of the same size. */
void checkDensePatch(const DensePatch& patch, const linemod::Template& coarsest,
                     int num_modalities, const String& where);

/** Depth samples: at most 256, x and y in [-MAX_TEMPLATE_SIZE, MAX_TEMPLATE_SIZE], z in
[1, MAX_DEPTH_SAMPLE_MM]. */
void checkDepthSamples(const std::vector<Point3i>& samples, const String& where);

/** A rendered view that addTemplates would turn into a template: raises when its mask has no
object pixel or covers the whole frame (a degenerate mesh, or radii that do not fit the mesh's
size), naming the view, its radius and the class. */
void checkTemplateView(const Mat& mask, int view_id, double radius, const String& class_id);

/** addTemplates after rendering `views` views: raises when none of them gave a template. */
void checkViewsGaveTemplates(int added, int views, const String& class_id);

/** A file about to be written: raises when it exists and overwrite is false, and always when
it is a dangling symbolic link (it is not written through: the link would create a file
elsewhere). `who` starts the message. */
void checkOutputFile(const String& filename, bool overwrite, const char* who);

} // namespace detail
} // namespace forestmod
} // namespace cv

#endif
