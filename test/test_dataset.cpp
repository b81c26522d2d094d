// This file is part of OpenCV project.
// It is subject to the license terms in the LICENSE file found in the top-level directory
// of this distribution and at http://opencv.org/license.html

#include "test_precomp.hpp"

#include <fstream>
#include <functional>

namespace opencv_test {
namespace {

namespace fs = cv::utils::fs;

static std::string errorOf(const std::function<void()>& f)
{
    try
    {
        f();
    }
    catch (const cv::Exception& e)
    {
        return e.what();
    }
    return std::string();
}

static bool contains(const std::string& s, const std::string& what)
{
    return s.find(what) != std::string::npos;
}

static void writeText(const std::string& path, const std::string& text)
{
    std::ofstream out(path.c_str());
    ASSERT_TRUE(out.good()) << path;
    out << text;
}

/** Deviation from a rotation: |R R^T - I| + |det R - 1|. LM-O's ground-truth rotations are not
quite orthonormal (up to 0.03 in this measure), so the bound below only catches garbled values. */
static double rotationDeviation(const Matx33d& R)
{
    return cv::norm(Mat(R * R.t()), Mat(Matx33d::eye())) + std::abs(determinant(R) - 1);
}

TEST(Forestmod_Dataset, reads_shipped_lmo_mini)
{
    const std::string root = fs::getParent(cvtest::findDataFile("lmo_mini/camera.json"));
    BopDataset ds = BopDataset::open(root);
    EXPECT_EQ(ds.imageSize(), Size(640, 480));
    const Matx33d K = lmoIntrinsics();
    EXPECT_LT(cv::norm(Mat(ds.cameraK()), Mat(K)), 1e-9);

    std::vector<ModelInfo> models = ds.models();
    ASSERT_EQ(models.size(), 1u);
    EXPECT_EQ(models[0].obj_id, 1);
    EXPECT_DOUBLE_EQ(models[0].diameter, 102.099);
    EXPECT_DOUBLE_EQ(models[0].min.x, -37.9343);
    EXPECT_DOUBLE_EQ(models[0].size.z, 91.769);
    EXPECT_FALSE(models[0].symmetric);
    EXPECT_TRUE(fs::exists(models[0].mesh_path));
    EXPECT_EQ(ds.modelPath(1), models[0].mesh_path);
    EXPECT_THROW(ds.model(2), cv::Exception);

    std::vector<int> scenes = ds.sceneIds();
    ASSERT_EQ(scenes.size(), 1u);
    EXPECT_EQ(scenes[0], 2);
    std::vector<Frame> frames = ds.frames(2);
    ASSERT_EQ(frames.size(), 3u);
    EXPECT_EQ(frames[0].im_id, 224);
    EXPECT_EQ(frames[1].im_id, 902);
    EXPECT_EQ(frames[2].im_id, 1038);

    // the first instance of image 224 as stored in scene_gt.json / scene_gt_info.json
    const Frame& f = frames[0];
    EXPECT_EQ(f.scene_id, 2);
    EXPECT_LT(cv::norm(Mat(f.K), Mat(K)), 1e-9);
    EXPECT_EQ(f.depth_scale, 1.0);
    ASSERT_FALSE(f.gt.empty());
    EXPECT_EQ(f.gt[0].obj_id, 1);
    EXPECT_DOUBLE_EQ(f.gt[0].R(0, 0), -0.24290547);
    EXPECT_DOUBLE_EQ(f.gt[0].R(0, 1), 0.7897998); // row-major
    EXPECT_DOUBLE_EQ(f.gt[0].R(1, 0), 0.2914954);
    EXPECT_DOUBLE_EQ(f.gt[0].t[2], 701.08018322);
    EXPECT_EQ(f.gt[0].bbox_obj, Rect(367, 270, 68, 65));
    EXPECT_EQ(f.gt[0].visib_fract, 1.0);

    Mesh ape = Mesh::load(ds.modelPath(1));
    Ptr<Renderer> renderer = Renderer::create(ds.imageSize());
    const int h = renderer->addMesh(ape);
    for (size_t i = 0; i < frames.size(); ++i)
    {
        Mat rgb = frames[i].rgb();
        EXPECT_EQ(rgb.size(), Size(640, 480));
        EXPECT_EQ(rgb.type(), CV_8UC3);
        EXPECT_TRUE(frames[i].depth_path.empty());
        EXPECT_TRUE(frames[i].depth().empty());
        for (size_t k = 0; k < frames[i].gt.size(); ++k)
        {
            const GroundTruth& g = frames[i].gt[k];
            EXPECT_LT(rotationDeviation(g.R), 0.05) << "frame " << frames[i].im_id << " instance " << k;
            EXPECT_GT(g.t[2], 0);
            EXPECT_GE(g.visib_fract, 0);
            EXPECT_LE(g.visib_fract, 1);
            if (g.obj_id != 1)
                continue;
            // the pose convention: the ape rendered at its ground truth fills bbox_obj
            Mat mask;
            renderer->render(h, g.R, g.t, frames[i].K, noArray(), noArray(), mask);
            const Rect box = boundingRect(mask);
            const double iou = boxIoU(Rect2d(box), Rect2d(g.bbox_obj));
            EXPECT_GT(iou, 0.9) << "frame " << frames[i].im_id << ": rendered " << box
                                << ", bbox_obj " << g.bbox_obj;
        }
    }
}

TEST(Forestmod_Dataset, reads_shared_lmo)
{
    const std::string shared = sharedDataPath();
    if (shared.empty())
        throw SkipTestException("FORESTMOD_SHARED_DATA (../shared/data with lmo/) is not available");
    BopDataset ds = BopDataset::open(shared + "/lmo");
    std::vector<ModelInfo> models = ds.models();
    ASSERT_EQ(models.size(), 8u);
    std::set<int> ids, symmetric;
    for (size_t i = 0; i < models.size(); ++i)
    {
        ids.insert(models[i].obj_id);
        if (models[i].symmetric)
            symmetric.insert(models[i].obj_id);
        EXPECT_GT(models[i].diameter, 50);
        EXPECT_TRUE(fs::exists(models[i].mesh_path)) << models[i].mesh_path;
    }
    EXPECT_EQ(symmetric, std::set<int>({ 10, 11 }));
    EXPECT_FALSE(ds.model(10).symmetries_discrete.empty());
    // flags from the file do not need the LINEMOD default
    BopDataset plain = BopDataset::open(shared + "/lmo", "test", std::vector<int>());
    EXPECT_TRUE(plain.model(10).symmetric);
    EXPECT_TRUE(plain.model(11).symmetric);
    EXPECT_FALSE(plain.model(1).symmetric);
    plain.setSymmetric(10, false);
    EXPECT_FALSE(plain.model(10).symmetric);
    EXPECT_THROW(plain.setSymmetric(99, true), cv::Exception);

    std::vector<int> scenes = ds.sceneIds();
    ASSERT_EQ(scenes, std::vector<int>(1, 2));
    std::vector<Frame> frames = ds.frames(2);
    EXPECT_EQ(frames.size(), 50u);
    size_t instances = 0;
    for (size_t i = 0; i < frames.size(); ++i)
    {
        EXPECT_TRUE(fs::exists(frames[i].rgb_path)) << frames[i].im_id;
        if (i > 0)
        {
            EXPECT_LT(frames[i - 1].im_id, frames[i].im_id);
        }
        for (size_t k = 0; k < frames[i].gt.size(); ++k)
        {
            EXPECT_EQ(ids.count(frames[i].gt[k].obj_id), 1u);
            EXPECT_LT(rotationDeviation(frames[i].gt[k].R), 0.05);
            EXPECT_GE(frames[i].gt[k].visib_fract, 0.0);
        }
        instances += frames[i].gt.size();
    }
    EXPECT_GT(instances, frames.size()); // several objects per frame
    EXPECT_EQ(frames[0].rgb().size(), ds.imageSize());
}

static const char* kCamera =
    "{\"cx\": 320.5, \"cy\": 240.25, \"depth_scale\": 0.1, \"fx\": 600.0, \"fy\": 601.0, "
    "\"height\": 48, \"width\": 64}";
static const char* kModels =
    "{\"3\": {\"diameter\": 80.5, \"min_x\": -10, \"min_y\": -20, \"min_z\": -30, \"size_x\": 20,"
    " \"size_y\": 40, \"size_z\": 60, \"symmetries_continuous\": [{\"axis\": [0, 0, 1], "
    "\"offset\": [0, 0, 0]}]},\n"
    " \"7\": {\"diameter\": 100, \"min_x\": 0, \"min_y\": 0, \"min_z\": 0, \"size_x\": 1, "
    "\"size_y\": 1, \"size_z\": 1},\n"
    " \"10\": {\"diameter\": 164.6, \"min_x\": 0, \"min_y\": 0, \"min_z\": 0, \"size_x\": 1, "
    "\"size_y\": 1, \"size_z\": 1}}";
static const char* kSceneCamera =
    "{\"0\": {\"cam_K\": [600.0, 0.0, 320.5, 0.0, 601.0, 240.25, 0.0, 0.0, 1.0], "
    "\"depth_scale\": 0.1},\n"
    " \"1\": {\"cam_K\": [610.0, 0.0, 300.0, 0.0, 611.0, 200.0, 0.0, 0.0, 1.0], "
    "\"depth_scale\": 0.5}}";
static const char* kSceneGt =
    "{\"0\": [{\"cam_R_m2c\": [0, -1, 0, 1, 0, 0, 0, 0, 1], \"cam_t_m2c\": [1.5, -2.5, 700], "
    "\"obj_id\": 3}, {\"cam_R_m2c\": [1, 0, 0, 0, 1, 0, 0, 0, 1], \"cam_t_m2c\": [0, 0, 900], "
    "\"obj_id\": 7}],\n"
    " \"1\": [{\"cam_R_m2c\": [1, 0, 0, 0, 1, 0, 0, 0, 1], \"cam_t_m2c\": [10, 20, 800], "
    "\"obj_id\": 10}]}";
static const char* kSceneGtInfo =
    "{\"0\": [{\"bbox_obj\": [1, 2, 30, 40], \"bbox_visib\": [1, 2, 20, 40], \"visib_fract\": 0.5},"
    " {\"bbox_obj\": [5, 6, 7, 8], \"bbox_visib\": [-1, -1, 0, 0], \"visib_fract\": 0.0}],\n"
    " \"1\": [{\"bbox_obj\": [3, 3, 3, 3], \"bbox_visib\": [3, 3, 3, 3], \"visib_fract\": 1}]}";

/** Writes a small BOP dataset: root/camera.json, models/, test/000005/ with two images. */
static void writeDataset(const std::string& root)
{
    fs::createDirectories(root + "/models");
    fs::createDirectories(root + "/test/000005/rgb");
    fs::createDirectories(root + "/test/000005/depth");
    fs::createDirectories(root + "/test/notascene");
    writeText(root + "/camera.json", kCamera);
    writeText(root + "/models/models_info.json", kModels);
    writeText(root + "/test/000005/scene_camera.json", kSceneCamera);
    writeText(root + "/test/000005/scene_gt.json", kSceneGt);
    writeText(root + "/test/000005/scene_gt_info.json", kSceneGtInfo);
    Mat rgb(48, 64, CV_8UC3, Scalar(10, 20, 30));
    ASSERT_TRUE(imwrite(root + "/test/000005/rgb/000000.png", rgb));
    ASSERT_TRUE(imwrite(root + "/test/000005/rgb/000001.png", rgb));
    Mat depth(48, 64, CV_16UC1, Scalar(7000)); // 700 mm at depth_scale 0.1
    depth.at<ushort>(0, 0) = 0;
    ASSERT_TRUE(imwrite(root + "/test/000005/depth/000000.png", depth));
}

TEST(Forestmod_Dataset, reads_a_dataset_written_by_the_test)
{
    TempDir tmp;
    const std::string root = tmp.path + "/mini";
    writeDataset(root);

    BopDataset ds = BopDataset::open(root);
    EXPECT_EQ(ds.imageSize(), Size(64, 48));
    EXPECT_EQ(ds.depthScale(), 0.1);
    EXPECT_EQ(ds.cameraK()(0, 2), 320.5);
    EXPECT_EQ(ds.sceneIds(), std::vector<int>(1, 5));

    std::vector<ModelInfo> m = ds.models();
    ASSERT_EQ(m.size(), 3u);
    EXPECT_EQ(m[0].obj_id, 3); // ascending ids
    EXPECT_EQ(m[1].obj_id, 7);
    EXPECT_EQ(m[2].obj_id, 10);
    EXPECT_TRUE(m[0].symmetric); // symmetries_continuous
    EXPECT_TRUE(m[0].continuous_symmetry);
    EXPECT_FALSE(m[1].symmetric);
    EXPECT_TRUE(m[2].symmetric); // LINEMOD's eggbox by default
    EXPECT_TRUE(m[2].symmetries_discrete.empty());
    EXPECT_EQ(m[0].size, Point3d(20, 40, 60));
    EXPECT_FALSE(BopDataset::open(root, "test", std::vector<int>()).model(10).symmetric);

    std::vector<Frame> frames = ds.frames(5);
    ASSERT_EQ(frames.size(), 2u);
    const Frame& f0 = frames[0];
    EXPECT_EQ(f0.im_id, 0);
    EXPECT_EQ(f0.depth_scale, 0.1);
    EXPECT_EQ(f0.K(1, 1), 601.0);
    ASSERT_EQ(f0.gt.size(), 2u);
    EXPECT_EQ(f0.gt[0].obj_id, 3);
    EXPECT_EQ(f0.gt[0].R(0, 1), -1.0); // row-major
    EXPECT_EQ(f0.gt[0].R(1, 0), 1.0);
    EXPECT_EQ(f0.gt[0].t, Vec3d(1.5, -2.5, 700));
    EXPECT_EQ(f0.gt[0].bbox_obj, Rect(1, 2, 30, 40));
    EXPECT_EQ(f0.gt[0].bbox_visib, Rect(1, 2, 20, 40));
    EXPECT_EQ(f0.gt[0].visib_fract, 0.5);
    EXPECT_EQ(f0.gt[1].obj_id, 7);
    Mat d = f0.depth();
    ASSERT_EQ(d.type(), CV_16UC1);
    EXPECT_EQ(d.at<ushort>(0, 0), 0);
    EXPECT_EQ(d.at<ushort>(10, 10), 700); // scaled to mm
    EXPECT_EQ(f0.rgb().at<Vec3b>(5, 5), Vec3b(10, 20, 30));

    const Frame& f1 = frames[1];
    EXPECT_EQ(f1.im_id, 1);
    EXPECT_EQ(f1.depth_scale, 0.5);
    EXPECT_EQ(f1.K(0, 2), 300.0);
    EXPECT_TRUE(f1.depth_path.empty());
    EXPECT_TRUE(f1.depth().empty());
    ASSERT_EQ(f1.gt.size(), 1u);
    EXPECT_EQ(f1.gt[0].obj_id, 10);

    // without scene_gt_info.json: no boxes, visib_fract -1
    fs::remove_all(root + "/test/000005/scene_gt_info.json");
    frames = ds.frames(5);
    EXPECT_TRUE(frames[0].gt[0].bbox_obj.empty());
    EXPECT_EQ(frames[0].gt[0].visib_fract, -1.0);

    EXPECT_THROW(ds.frames(6), cv::Exception);
    EXPECT_THROW(BopDataset::open(root, "val").sceneIds(), cv::Exception);
}

TEST(Forestmod_Dataset, bad_files_raise_with_file_and_key)
{
    TempDir tmp;
    const std::string root = tmp.path + "/bad";
    writeDataset(root);
    const std::string gt = root + "/test/000005/scene_gt.json";

    // malformed JSON
    writeText(gt, std::string(kSceneGt).substr(0, 60));
    std::string msg = errorOf([&]() { BopDataset::open(root).frames(5); });
    EXPECT_TRUE(contains(msg, "scene_gt.json")) << msg;

    // a missing field
    std::string text(kSceneGt);
    text.replace(text.find("\"cam_t_m2c\""), 11, "\"cam_t_m2x\"");
    writeText(gt, text);
    msg = errorOf([&]() { BopDataset::open(root).frames(5); });
    EXPECT_TRUE(contains(msg, "scene_gt.json")) << msg;
    EXPECT_TRUE(contains(msg, "cam_t_m2c")) << msg;
    EXPECT_TRUE(contains(msg, "image '0'")) << msg;

    // a field of the wrong size
    text = kSceneGt;
    text.replace(text.find("[1.5, -2.5, 700]"), 16, "[1.5, -2.5]");
    writeText(gt, text);
    msg = errorOf([&]() { BopDataset::open(root).frames(5); });
    EXPECT_TRUE(contains(msg, "cam_t_m2c")) << msg;
    writeText(gt, kSceneGt);

    // camera.json without fx
    std::string cam(kCamera);
    cam.replace(cam.find("\"fx\": 600.0, "), 13, "");
    writeText(root + "/camera.json", cam);
    msg = errorOf([&]() { BopDataset::open(root); });
    EXPECT_TRUE(contains(msg, "camera.json")) << msg;
    EXPECT_TRUE(contains(msg, "'fx'")) << msg;
    writeText(root + "/camera.json", kCamera);

    // models_info.json: a diameter that is not a number
    std::string models(kModels);
    models.replace(models.find("80.5"), 4, "\"x\"");
    writeText(root + "/models/models_info.json", models);
    msg = errorOf([&]() { BopDataset::open(root); });
    EXPECT_TRUE(contains(msg, "models_info.json")) << msg;
    EXPECT_TRUE(contains(msg, "diameter")) << msg;
    writeText(root + "/models/models_info.json", kModels);

    // values out of range: a zero focal length, a width beyond an int, a negative depth scale
    // and diameter, a camera matrix that is not a pinhole (the detector's and the pose stage's)
    const char* cam_bad[][2] = { { "\"fx\": 600.0", "\"fx\": 0" },
                                 { "\"width\": 64", "\"width\": 1e12" },
                                 { "\"width\": 64", "\"width\": 0.4" },
                                 { "\"width\": 64", "\"width\": 64.7" },
                                 { "\"cx\": 320.5", "\"cx\": 1e999" },
                                 { "\"depth_scale\": 0.1", "\"depth_scale\": -0.1" } };
    for (const auto& b : cam_bad)
    {
        cam = kCamera;
        cam.replace(cam.find(b[0]), strlen(b[0]), b[1]);
        writeText(root + "/camera.json", cam);
        msg = errorOf([&]() { BopDataset::open(root); });
        EXPECT_TRUE(contains(msg, "camera.json")) << b[1] << ": " << msg;
        EXPECT_TRUE(contains(msg, std::string(b[0]).substr(1, std::string(b[0]).find('"', 1) - 1)))
            << b[1] << ": " << msg;
    }
    writeText(root + "/camera.json", kCamera);
    models = kModels;
    models.replace(models.find("80.5"), 4, "-80.5");
    writeText(root + "/models/models_info.json", models);
    msg = errorOf([&]() { BopDataset::open(root); });
    EXPECT_TRUE(contains(msg, "diameter")) << msg;
    writeText(root + "/models/models_info.json", kModels);
    std::string sc(kSceneCamera);
    sc.replace(sc.find("[600.0, 0.0, 320.5, 0.0, 601.0"), 30, "[600.0, 0.0, 320.5, 0.0, -601.");
    writeText(root + "/test/000005/scene_camera.json", sc);
    msg = errorOf([&]() { BopDataset::open(root).frames(5); });
    EXPECT_TRUE(contains(msg, "scene_camera.json")) << msg;
    EXPECT_TRUE(contains(msg, "image '0'")) << msg;
    EXPECT_TRUE(contains(msg, "cam_K is not a pinhole")) << msg;
    sc = kSceneCamera;
    sc.replace(sc.find("\"depth_scale\": 0.5"), 18, "\"depth_scale\": 0");
    writeText(root + "/test/000005/scene_camera.json", sc);
    msg = errorOf([&]() { BopDataset::open(root).frames(5); });
    EXPECT_TRUE(contains(msg, "depth_scale")) << msg;

    // scene_camera.json: cam_K missing
    sc = kSceneCamera;
    sc.replace(sc.find("\"cam_K\""), 7, "\"cam_k\"");
    writeText(root + "/test/000005/scene_camera.json", sc);
    msg = errorOf([&]() { BopDataset::open(root).frames(5); });
    EXPECT_TRUE(contains(msg, "scene_camera.json")) << msg;
    EXPECT_TRUE(contains(msg, "cam_K")) << msg;

    // missing files and folders
    fs::remove_all(root + "/test/000005/scene_camera.json");
    msg = errorOf([&]() { BopDataset::open(root).frames(5); });
    EXPECT_TRUE(contains(msg, "scene_camera.json")) << msg;
    fs::remove_all(root + "/camera.json");
    msg = errorOf([&]() { BopDataset::open(root); });
    EXPECT_TRUE(contains(msg, "camera.json")) << msg;
    EXPECT_THROW(BopDataset::open(tmp.path + "/nothing"), cv::Exception);

    // an unreadable image
    writeDataset(root);
    writeText(root + "/test/000005/depth/000000.png", "not a png");
    std::vector<Frame> frames = BopDataset::open(root).frames(5);
    EXPECT_THROW(frames[0].depth(), cv::Exception);
}

TEST(Forestmod_Dataset, result_writer_writes_bop_csv)
{
    TempDir tmp;
    const std::string path = tmp.path + "/res_lmo-test.csv";
    {
        BopResultWriter w(path);
        const Matx33d R(0, -1, 0, 1, 0, 0, 0, 0, 1);
        w.write(2, 224, 1, 0.875, R, Vec3d(98.5, 70.25, 701.125), 0.031);
        w.write(2, 902, 5, 0.5, Matx33d::eye(), Vec3d(-1, 2, 3));
        w.close();
        EXPECT_THROW(w.write(2, 1, 1, 1, R, Vec3d(0, 0, 1)), cv::Exception);
    }
    std::ifstream in(path.c_str());
    std::string l0, l1, l2, l3;
    std::getline(in, l0);
    std::getline(in, l1);
    std::getline(in, l2);
    EXPECT_FALSE(std::getline(in, l3));
    EXPECT_EQ(l0, "scene_id,im_id,obj_id,score,R,t,time");
    EXPECT_EQ(l1, "2,224,1,0.875,0 -1 0 1 0 0 0 0 1,98.5 70.25 701.125,0.031");
    EXPECT_EQ(l2, "2,902,5,0.5,1 0 0 0 1 0 0 0 1,-1 2 3,-1");

    // an existing file is not replaced unless asked
    std::string msg = errorOf([&]() { BopResultWriter w(path); });
    EXPECT_TRUE(contains(msg, "exists")) << msg;
    {
        BopResultWriter w(path, true);
    }
    std::ifstream in2(path.c_str());
    std::string only;
    std::getline(in2, only);
    EXPECT_EQ(only, "scene_id,im_id,obj_id,score,R,t,time");
    EXPECT_FALSE(std::getline(in2, only));
    EXPECT_THROW(BopResultWriter(tmp.path + "/no/such/dir/x.csv"), cv::Exception);
}

} // namespace
} // namespace opencv_test
