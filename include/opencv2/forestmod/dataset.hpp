// This file is part of OpenCV project.
// It is subject to the license terms in the LICENSE file found in the top-level directory
// of this distribution and at http://opencv.org/license.html

#ifndef OPENCV_FORESTMOD_DATASET_HPP
#define OPENCV_FORESTMOD_DATASET_HPP

#include "opencv2/core.hpp"

#include <vector>

namespace cv {
namespace forestmod {

//! @addtogroup forestmod_dataset
//! @{

/** @brief Ground truth of one object instance in a frame (BOP scene_gt.json + scene_gt_info.json).

Pose model -> camera, R = cam_R_m2c (row-major in the file), t = cam_t_m2c in mm. The boxes and
visib_fract come from scene_gt_info.json when the scene has it; otherwise the boxes are empty and
visib_fract is -1.
*/
struct CV_EXPORTS GroundTruth
{
    GroundTruth();
    int obj_id;
    Matx33d R;
    Vec3d t;
    Rect bbox_obj;      //!< box of the whole projected object (x, y, w, h)
    Rect bbox_visib;    //!< box of its visible part
    double visib_fract; //!< visible share of the object's pixels (0..1), -1 when unknown
};

/** @brief One object model (BOP models_info.json). */
struct CV_EXPORTS ModelInfo
{
    ModelInfo();
    int obj_id;
    double diameter;  //!< mm
    Point3d min;      //!< corner of the model's bounding box (min_x, min_y, min_z), mm
    Point3d size;     //!< size of the bounding box (size_x, size_y, size_z), mm
    /** Symmetric (use ADI instead of ADD): the file has non-empty symmetries_discrete or
    symmetries_continuous, or the id is in the list given to BopDataset::open() (LINEMOD's eggbox
    and glue by default), or BopDataset::setSymmetric() said so. */
    bool symmetric;
    /** The discrete symmetries of models_info.json (symmetries_discrete), each a 4x4 rigid
    transform of model coordinates (row-major, translation in mm) that leaves the object's look
    unchanged; empty when the file gives none. */
    std::vector<Matx44d> symmetries_discrete;
    /** True when models_info.json lists continuous symmetries (symmetries_continuous). */
    bool continuous_symmetry;
    String mesh_path; //!< models/obj_XXXXXX.ply (may not exist)
};

/** @brief One image of a BOP scene with its ground truth. */
struct CV_EXPORTS Frame
{
    Frame();
    int scene_id;
    int im_id;
    Matx33d K;          //!< cam_K of scene_camera.json
    double depth_scale; //!< depth in mm = stored value * depth_scale
    String rgb_path;    //!< rgb/XXXXXX.png (or .jpg; gray/ for grey-level datasets)
    String depth_path;  //!< depth/XXXXXX.png, empty when the dataset has no depth
    std::vector<GroundTruth> gt;

    /** @brief The colour image (CV_8UC3 BGR); throws when it cannot be read. */
    Mat rgb() const;
    /** @brief The depth image, CV_16UC1 in millimetres (depth_scale applied, rounded, saturated);
    empty when the frame has no depth; throws when the file exists but cannot be read. */
    Mat depth() const;
};

/** @brief Reader of a dataset in the BOP format (github.com/thodan/bop_toolkit,
docs/bop_datasets_format.md), e.g. LM-O.

Files read (JSON, through cv::FileStorage): `camera.json`, `models/models_info.json`, and for each
scene folder `<split>/<scene_id:06d>/`: `scene_camera.json`, `scene_gt.json` (both required),
`scene_gt_info.json` (optional), images in `rgb/` (or `gray/`), optional `depth/`.
A file that is missing, is not valid JSON, or lacks a field raises cv::Exception with a message
naming the file and the key.
*/
class CV_EXPORTS BopDataset
{
public:
    BopDataset();

    /** @brief Object ids that LINEMOD (LM, LM-O) treats as symmetric: 10 (eggbox) and 11 (glue).
    Hinterstoisser et al. ACCV 2012 evaluate them with ADI. */
    static std::vector<int> linemodSymmetricIds();

    /** @brief Opens a dataset.
    @param root  folder with camera.json, models/ and the split folders.
    @param split split folder under root ("test", "train", "val", ...).
    @param symmetric_ids objects that are symmetric whatever models_info.json says. The default,
           {10, 11}, is LINEMOD's (eggbox, glue) and is right for LM and LM-O, whose older
           models_info files carry no symmetry flags; pass an empty vector for other datasets.
    */
    static BopDataset open(const String& root, const String& split = "test",
                           const std::vector<int>& symmetric_ids = linemodSymmetricIds());

    String root() const { return root_; }
    String split() const { return split_; }

    /** @brief Scene ids found in the split folder (numeric folder names with a scene_gt.json or
    scene_camera.json), ascending. */
    std::vector<int> sceneIds() const;
    /** @brief The frames of one scene (image ids of scene_camera.json, ascending) with their
    ground truth. Reads the scene's JSON files at each call. */
    std::vector<Frame> frames(int scene_id) const;

    /** @brief All models of models_info.json, by ascending id. */
    std::vector<ModelInfo> models() const;
    /** @brief One model; throws when obj_id is not in models_info.json. */
    ModelInfo model(int obj_id) const;
    /** @brief Overrides the symmetry flag of one object. */
    void setSymmetric(int obj_id, bool symmetric);
    /** @brief Path of the mesh of an object (models/obj_XXXXXX.ply). */
    String modelPath(int obj_id) const;

    /** @brief Intrinsics of camera.json (fx, fy, cx, cy). */
    Matx33d cameraK() const { return K_; }
    /** @brief Image size of camera.json (width, height). */
    Size imageSize() const { return size_; }
    /** @brief depth_scale of camera.json (1 when absent). */
    double depthScale() const { return depth_scale_; }

private:
    String root_, split_;
    Matx33d K_;
    Size size_;
    double depth_scale_;
    std::vector<ModelInfo> models_;
};

/** @brief Writes pose estimates as a BOP results CSV file
(`scene_id,im_id,obj_id,score,R,t,time`: R row-major, 9 numbers, and t in mm, 3 numbers, each
space-separated; time in seconds per image, -1 when unknown).

Refuses to overwrite an existing file unless asked. Lines are flushed as they are written; the
file is closed by close() or the destructor.
*/
class CV_EXPORTS BopResultWriter
{
public:
    /** @param path output file (.csv).
    @param overwrite replace an existing file; otherwise an existing file raises an error. */
    explicit BopResultWriter(const String& path, bool overwrite = false);
    ~BopResultWriter();

    /** @brief Appends one estimate. */
    void write(int scene_id, int im_id, int obj_id, double score, const Matx33d& R,
               const Vec3d& t, double time_s = -1.0);
    /** @brief Closes the file (further write() calls raise). */
    void close();
    String path() const { return path_; }

private:
    BopResultWriter(const BopResultWriter&);            // not copyable
    BopResultWriter& operator=(const BopResultWriter&); // not copyable
    struct Impl;
    Ptr<Impl> impl_;
    String path_;
};

//! @}

} // namespace forestmod
} // namespace cv

#endif // OPENCV_FORESTMOD_DATASET_HPP
