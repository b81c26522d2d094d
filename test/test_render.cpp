// This file is part of OpenCV project.
// It is subject to the license terms in the LICENSE file found in the top-level directory
// of this distribution and at http://opencv.org/license.html

#include "test_precomp.hpp"

#include "opencv2/calib3d.hpp"

#include <fstream>
#include <map>

namespace opencv_test { namespace {

// ---- helpers ------------------------------------------------------------------------------------

static Matx33d cameraK(double fx, double fy, double cx, double cy)
{
    return Matx33d(fx, 0, cx, 0, fy, cy, 0, 0, 1);
}

static Matx33d lmoIntrinsics()
{
    return cameraK(572.4114, 573.57043, 325.2611, 242.04899);
}

static Matx33d rodrigues(const Vec3d& rvec)
{
    Matx33d R;
    Rodrigues(rvec, R);
    return R;
}

// a square plate of side `side` mm in the model's z = 0 plane, centred at the origin
static Mesh plateMesh(float side, Vec3b color = Vec3b(40, 160, 220))
{
    Mesh m;
    const float h = side / 2;
    m.vertices.push_back(Point3f(-h, -h, 0));
    m.vertices.push_back(Point3f(h, -h, 0));
    m.vertices.push_back(Point3f(h, h, 0));
    m.vertices.push_back(Point3f(-h, h, 0));
    m.faces.push_back(Vec3i(0, 1, 2));
    m.faces.push_back(Vec3i(0, 2, 3));
    m.colors.assign(4, color);
    return m;
}

// an axis-aligned cube of side `side` mm centred at the origin (8 vertices, 12 triangles)
static Mesh cubeMesh(float side)
{
    Mesh m;
    const float h = side / 2;
    for (int i = 0; i < 8; ++i)
        m.vertices.push_back(Point3f((i & 1) ? h : -h, (i & 2) ? h : -h, (i & 4) ? h : -h));
    const int quads[6][4] = { { 0, 2, 3, 1 }, { 4, 5, 7, 6 }, { 0, 1, 5, 4 },
                              { 2, 6, 7, 3 }, { 0, 4, 6, 2 }, { 1, 3, 7, 5 } };
    for (int q = 0; q < 6; ++q)
    {
        m.faces.push_back(Vec3i(quads[q][0], quads[q][1], quads[q][2]));
        m.faces.push_back(Vec3i(quads[q][0], quads[q][2], quads[q][3]));
    }
    return m;
}

// distance along the ray (camera frame, direction d with d.z = 1) to an axis-aligned cube of
// half side h in the model frame; returns the camera z of the first hit, or -1 if it misses
static double rayCube(const Matx33d& R, const Vec3d& t, const Vec3d& d, double h)
{
    const Vec3d o = -(R.t() * t), dm = R.t() * d;
    double tn = -DBL_MAX, tf = DBL_MAX;
    for (int k = 0; k < 3; ++k)
    {
        if (std::fabs(dm[k]) < 1e-15)
        {
            if (o[k] < -h || o[k] > h)
                return -1;
            continue;
        }
        double a = (-h - o[k]) / dm[k], b = (h - o[k]) / dm[k];
        if (a > b)
            std::swap(a, b);
        tn = std::max(tn, a);
        tf = std::min(tf, b);
    }
    if (tn > tf || tf < 0)
        return -1;
    return tn * d[2];
}

static double iou(const Rect2d& a, const Rect2d& b)
{
    const double inter = (a & b).area();
    const double uni = a.area() + b.area() - inter;
    return uni > 0 ? inter / uni : 0.0;
}

// BOP's bbox of a mask: (xmin, ymin, xmax - xmin, ymax - ymin) (bop_toolkit misc.calc_2d_bbox)
static Rect2d bopBox(const Mat& mask, Point offset = Point())
{
    std::vector<Point> pts;
    findNonZero(mask, pts);
    if (pts.empty())
        return Rect2d();
    int x0 = INT_MAX, y0 = INT_MAX, x1 = INT_MIN, y1 = INT_MIN;
    for (size_t i = 0; i < pts.size(); ++i)
    {
        x0 = std::min(x0, pts[i].x);
        y0 = std::min(y0, pts[i].y);
        x1 = std::max(x1, pts[i].x);
        y1 = std::max(y1, pts[i].y);
    }
    return Rect2d(x0 - offset.x, y0 - offset.y, x1 - x0, y1 - y0);
}

static std::string writeTextFile(const std::string& ext, const std::string& content)
{
    const std::string path = cv::tempfile(ext.c_str());
    std::ofstream f(path.c_str(), std::ios::binary);
    f << content;
    return path;
}

static Mat readMatx(const FileNode& n, int rows, int cols)
{
    std::vector<double> v;
    n >> v;
    CV_Assert((int)v.size() == rows * cols);
    return Mat(v, true).reshape(1, rows);
}

static std::string apePath()
{
    return cvtest::findDataFile("lmo_mini/models/obj_000001.ply");
}

// ---- depth is metric --------------------------------------------------------------------------

TEST(Forestmod_Renderer, plate_depth_is_metric_and_mask_matches)
{
    const Size size(320, 240);
    const Matx33d K = cameraK(300, 300, 160.3, 119.7);
    Ptr<Renderer> renderer = Renderer::create(size);
    const int h = renderer->addMesh(plateMesh(200));
    Mat color, depth, mask;
    renderer->render(h, Matx33d::eye(), Vec3d(0, 0, 800), K, color, depth, mask);
    ASSERT_EQ(CV_8UC3, color.type());
    ASSERT_EQ(CV_16UC1, depth.type());
    ASSERT_EQ(CV_8UC1, mask.type());
    ASSERT_EQ(size, depth.size());
    // projected square: u in cx +- 300 * 100 / 800 = cx +- 37.5
    int inside = 0;
    for (int v = 0; v < size.height; ++v)
        for (int u = 0; u < size.width; ++u)
        {
            const double du = std::fabs(u - K(0, 2)), dv = std::fabs(v - K(1, 2));
            const ushort d = depth.at<ushort>(v, u);
            ASSERT_EQ(d > 0 ? 255 : 0, mask.at<uchar>(v, u)) << u << "," << v;
            if (du < 37.5 - 0.01 && dv < 37.5 - 0.01)
            {
                ASSERT_EQ(800, d) << "inside the plate at " << u << "," << v;
                ++inside;
            }
            else if (du > 37.5 + 0.01 || dv > 37.5 + 0.01)
            {
                ASSERT_EQ(0, d) << "outside the plate at " << u << "," << v;
            }
        }
    EXPECT_GT(inside, 70 * 70);
    // facing the light: full diffuse, colour = vertex colour
    const Vec3b c = color.at<Vec3b>(cvRound(K(1, 2)), cvRound(K(0, 2)));
    EXPECT_LE(cv::norm(Vec3i(c) - Vec3i(40, 160, 220), NORM_INF), 1) << c;
    EXPECT_EQ(Vec3b(0, 0, 0), color.at<Vec3b>(0, 0));
}

TEST(Forestmod_Renderer, cube_depth_equals_ray_cast)
{
    const Size size(320, 240);
    const Matx33d K = cameraK(400, 410, 150.5, 125.25);
    Ptr<Renderer> renderer = Renderer::create(size);
    const double side = 120;
    const int h = renderer->addMesh(cubeMesh((float)side));
    const Vec3d rvecs[3] = { Vec3d(0.3, -0.5, 0.2), Vec3d(1.2, 0.4, -0.7), Vec3d(-0.4, 2.5, 0.1) };
    const Vec3d ts[3] = { Vec3d(20, -10, 700), Vec3d(-30, 15, 450), Vec3d(0, 0, 1200) };
    const Matx33d Kinv = K.inv();
    for (int p = 0; p < 3; ++p)
    {
        const Matx33d R = rodrigues(rvecs[p]);
        Mat depth, mask;
        renderer->render(h, R, ts[p], K, noArray(), depth, mask);
        int object_pixels = 0;
        double max_err = 0;
        for (int v = 0; v < size.height; ++v)
            for (int u = 0; u < size.width; ++u)
            {
                const Vec3d d = Kinv * Vec3d(u, v, 1);
                const ushort z = depth.at<ushort>(v, u);
                ASSERT_EQ(z > 0 ? 255 : 0, mask.at<uchar>(v, u));
                if (z > 0)
                {
                    // hits a slightly larger cube, and the depth is that of the exact cube
                    ASSERT_GT(rayCube(R, ts[p], d, side / 2 + 0.05), 0) << "pose " << p << " at "
                                                                        << u << "," << v;
                    double zc = rayCube(R, ts[p], d, side / 2);
                    if (zc < 0) // grazing the edge: the slightly larger cube
                        zc = rayCube(R, ts[p], d, side / 2 + 0.05);
                    max_err = std::max(max_err, std::fabs(z - zc));
                    ASSERT_LE(std::fabs(z - zc), 1.0) << "pose " << p << " at " << u << "," << v;
                    ++object_pixels;
                }
                else
                    ASSERT_LT(rayCube(R, ts[p], d, side / 2 - 0.05), 0)
                        << "missed object pixel, pose " << p << " at " << u << "," << v;
            }
        EXPECT_GT(object_pixels, 1000) << p;
        EXPECT_LE(max_err, 0.51) << p; // rounding to the mm only
    }
}

// ---- projection -------------------------------------------------------------------------------

TEST(Forestmod_Renderer, model_origin_projects_to_K_t)
{
    const Size size(640, 480);
    Ptr<Renderer> renderer = Renderer::create(size);
    const double side = 150;
    const int h = renderer->addMesh(plateMesh((float)side));
    const Matx33d Ks[2] = { lmoIntrinsics(), cameraK(500, 520, 300.7, 260.2) };
    const Vec3d ts[3] = { Vec3d(0, 0, 800), Vec3d(37.3, -21.7, 650), Vec3d(-120.4, 80.9, 1000) };
    for (int k = 0; k < 2; ++k)
        for (int i = 0; i < 3; ++i)
        {
            const Matx33d& K = Ks[k];
            const Vec3d& t = ts[i];
            Mat mask;
            renderer->render(h, Matx33d::eye(), t, K, noArray(), noArray(), mask);
            // the fronto-parallel plate covers exactly the pixels whose centre lies inside its
            // projection u in cx + fx (tx +- side/2) / tz (same for v): checked to 0.01 px, so a
            // half-pixel convention error cannot pass
            const double u0 = K(0, 2) + K(0, 0) * (t[0] - side / 2) / t[2];
            const double u1 = K(0, 2) + K(0, 0) * (t[0] + side / 2) / t[2];
            const double v0 = K(1, 2) + K(1, 1) * (t[1] - side / 2) / t[2];
            const double v1 = K(1, 2) + K(1, 1) * (t[1] + side / 2) / t[2];
            for (int v = 0; v < size.height; ++v)
                for (int u = 0; u < size.width; ++u)
                {
                    const double inside = std::min(std::min(u - u0, u1 - u), std::min(v - v0, v1 - v));
                    if (inside > 0.01)
                    {
                        ASSERT_EQ(255, mask.at<uchar>(v, u))
                            << "K " << k << " t " << t << " at " << u << "," << v;
                    }
                    else if (inside < -0.01)
                    {
                        ASSERT_EQ(0, mask.at<uchar>(v, u))
                            << "K " << k << " t " << t << " at " << u << "," << v;
                    }
                }
            // and the mask centroid (image of the plate's centre, the model origin) is K t, up to
            // the half pixel of discretising the square's edges
            const Moments m = moments(mask, true);
            ASSERT_GT(m.m00, 100);
            const Vec3d p = K * t;
            const Point2d expected(p[0] / p[2], p[1] / p[2]);
            const Point2d centroid(m.m10 / m.m00, m.m01 / m.m00);
            EXPECT_LE(std::fabs(centroid.x - expected.x), 0.5) << "K " << k << " t " << t;
            EXPECT_LE(std::fabs(centroid.y - expected.y), 0.5) << "K " << k << " t " << t;
        }
}

TEST(Forestmod_Renderer, projected_vertices_fall_on_the_mask)
{
    const Mesh ape = Mesh::load(apePath());
    const Size size(640, 480);
    const Matx33d K = lmoIntrinsics();
    Ptr<Renderer> renderer = Renderer::create(size);
    const int h = renderer->addMesh(ape);
    const Vec3d rvecs[2] = { Vec3d(2.0, 0.3, -0.4), Vec3d(-1.0, 1.7, 0.6) };
    const Vec3d ts[2] = { Vec3d(40, -30, 700), Vec3d(-80, 60, 950) };
    for (int p = 0; p < 2; ++p)
    {
        Mat depth, mask, dilated;
        const Matx33d R = rodrigues(rvecs[p]);
        renderer->render(h, R, ts[p], K, noArray(), depth, mask);
        dilate(mask, dilated, Mat());
        std::vector<Point2f> img;
        projectPoints(ape.vertices, rvecs[p], ts[p], K, noArray(), img);
        int on = 0, near = 0;
        for (size_t i = 0; i < img.size(); ++i)
        {
            const Point q(cvRound(img[i].x), cvRound(img[i].y));
            ASSERT_TRUE(Rect(0, 0, size.width, size.height).contains(q));
            near += dilated.at<uchar>(q) ? 1 : 0;
            if (!mask.at<uchar>(q))
                continue;
            ++on;
            // the rendered surface is the nearest one along that pixel's ray: not behind the
            // vertex. Checked where the surface faces the camera (cos > 0.5), as the vertex is up
            // to 0.7 px (~1 mm) off the pixel centre: 1 mm x tan(60 deg) + rounding < 3 mm
            const Vec3d x = R * Vec3d(ape.vertices[i].x, ape.vertices[i].y, ape.vertices[i].z) + ts[p];
            const Vec3d n = R * Vec3d(ape.normals[i][0], ape.normals[i][1], ape.normals[i][2]);
            if (-n.dot(x) / cv::norm(x) > 0.5)
            {
                ASSERT_LE(depth.at<ushort>(q), x[2] + 3.0) << "vertex " << i;
            }
        }
        // vertices on the silhouette round to either side of it: most land on the mask, all
        // within one pixel of it
        EXPECT_GE(on, (int)(0.9 * img.size())) << p;
        EXPECT_EQ((int)img.size(), near) << p;
    }
}

// ---- several meshes, several renderers ----------------------------------------------------------

TEST(Forestmod_Renderer, scene_is_z_buffered_with_labels)
{
    const Size size(200, 160);
    const Matx33d K = cameraK(250, 250, 100, 80);
    Ptr<Renderer> renderer = Renderer::create(size);
    const int a = renderer->addMesh(plateMesh(100, Vec3b(255, 0, 0)));
    const int b = renderer->addMesh(plateMesh(100, Vec3b(0, 0, 255)));
    std::vector<int> handles;
    handles.push_back(a);
    handles.push_back(b);
    std::vector<Matx33d> Rs(2, Matx33d::eye());
    std::vector<Vec3d> ts;
    ts.push_back(Vec3d(-30, 0, 900)); // far, left
    ts.push_back(Vec3d(30, 0, 600));  // near, right: wins where they overlap
    Mat color, depth, labels;
    renderer->renderScene(handles, Rs, ts, K, color, depth, labels);
    ASSERT_EQ(CV_8UC1, labels.type());
    EXPECT_EQ(1, labels.at<uchar>(80, 85)); // row 80, column 85: only the far plate
    EXPECT_EQ(900, depth.at<ushort>(80, 85));
    EXPECT_EQ(Vec3b(255, 0, 0), color.at<Vec3b>(80, 85));
    EXPECT_EQ(2, labels.at<uchar>(80, 100)); // overlap
    EXPECT_EQ(600, depth.at<ushort>(80, 100));
    EXPECT_EQ(Vec3b(0, 0, 255), color.at<Vec3b>(80, 100));
    EXPECT_EQ(0, labels.at<uchar>(5, 5));
    for (int v = 0; v < size.height; ++v)
        for (int u = 0; u < size.width; ++u)
            ASSERT_EQ(depth.at<ushort>(v, u) > 0, labels.at<uchar>(v, u) > 0);

    // an entry drawn alone in the scene equals render()
    Mat d1, m1, d2, l2;
    renderer->render(b, Rs[1], ts[1], K, noArray(), d1, m1);
    renderer->renderScene(std::vector<int>(1, b), std::vector<Matx33d>(1, Rs[1]),
                          std::vector<Vec3d>(1, ts[1]), K, noArray(), d2, l2);
    EXPECT_EQ(0, cvtest::norm(d1, d2, NORM_INF));
    EXPECT_EQ(0, cvtest::norm(m1 > 0, l2 > 0, NORM_INF));
}

TEST(Forestmod_Renderer, two_renderers_in_one_process)
{
    const Mesh cube = cubeMesh(100);
    const Matx33d R = rodrigues(Vec3d(0.4, 0.5, 0.1));
    const Vec3d t(0, 0, 700);
    const Matx33d K = cameraK(300, 300, 160, 120);
    Ptr<Renderer> r1 = Renderer::create(Size(320, 240));
    Mat ref_c, ref_d;
    const int h1 = r1->addMesh(cube);
    r1->render(h1, R, t, K, ref_c, ref_d);
    Ptr<Renderer> r2 = Renderer::create(Size(160, 120));
    const int h2 = r2->addMesh(plateMesh(50));
    for (int i = 0; i < 3; ++i) // interleaved
    {
        Mat c1, d1, c2, d2;
        r2->render(h2, Matx33d::eye(), Vec3d(0, 0, 500), cameraK(150, 150, 80, 60), c2, d2);
        r1->render(h1, R, t, K, c1, d1);
        EXPECT_EQ(Size(160, 120), c2.size());
        EXPECT_EQ(500, d2.at<ushort>(60, 80));
        EXPECT_EQ(0, cvtest::norm(c1, ref_c, NORM_INF));
        EXPECT_EQ(0, cvtest::norm(d1, ref_d, NORM_INF));
    }
    r1.release(); // destroying one must not disturb the other
    Mat d3;
    r2->render(h2, Matx33d::eye(), Vec3d(0, 0, 500), cameraK(150, 150, 80, 60), noArray(), d3);
    EXPECT_EQ(500, d3.at<ushort>(60, 80));
}

TEST(Forestmod_Renderer, bad_input_raises)
{
    EXPECT_THROW(Renderer::create(Size(0, 10)), cv::Exception);
    Ptr<Renderer> renderer = Renderer::create(Size(64, 48));
    EXPECT_THROW(renderer->addMesh(Mesh()), cv::Exception);
    Mesh broken = plateMesh(10);
    broken.faces.push_back(Vec3i(0, 1, 7));
    EXPECT_THROW(renderer->addMesh(broken), cv::Exception);
    const int h = renderer->addMesh(plateMesh(10));
    Mat c;
    const Matx33d K = cameraK(50, 50, 32, 24);
    EXPECT_THROW(renderer->render(h + 1, Matx33d::eye(), Vec3d(0, 0, 100), K, c), cv::Exception);
    EXPECT_THROW(renderer->render(h, Matx33d::eye() * 2, Vec3d(0, 0, 100), K, c), cv::Exception);
    EXPECT_THROW(renderer->render(h, Matx33d::eye(), Vec3d(0, 0, 100), Matx33d::zeros(), c),
                 cv::Exception);
    EXPECT_THROW(renderer->renderScene(std::vector<int>(2, h), std::vector<Matx33d>(1),
                                       std::vector<Vec3d>(2), K, c),
                 cv::Exception);
    // behind the camera, or far off-screen: empty images, no error
    const Vec3d nowhere[3] = { Vec3d(0, 0, -100), Vec3d(1e12, 0, 1000), Vec3d(0, -1e13, 50) };
    for (int i = 0; i < 3; ++i)
    {
        Mat d, m;
        renderer->render(h, Matx33d::eye(), nowhere[i], K, c, d, m);
        EXPECT_EQ(0, countNonZero(m)) << nowhere[i];
        EXPECT_EQ(0, countNonZero(d)) << nowhere[i];
        EXPECT_EQ(Size(64, 48), c.size());
    }
}

// ---- real data ----------------------------------------------------------------------------------

struct GtEntry
{
    int obj_id;
    Matx33d R;
    Vec3d t;
    Rect2d bbox_obj;
    double visib_fract;
};

// scene_gt.json + scene_gt_info.json + scene_camera.json of a BOP scene folder
static void readBopScene(const std::string& scene, std::vector<int>& ids,
                         std::vector<std::vector<GtEntry> >& gts, std::vector<Matx33d>& Ks)
{
    FileStorage gt(scene + "/scene_gt.json", FileStorage::READ);
    FileStorage info(scene + "/scene_gt_info.json", FileStorage::READ);
    FileStorage cam(scene + "/scene_camera.json", FileStorage::READ);
    ASSERT_TRUE(gt.isOpened() && info.isOpened() && cam.isOpened()) << scene;
    const FileNode root = gt.root();
    for (FileNodeIterator it = root.begin(); it != root.end(); ++it)
    {
        const std::string key = (*it).name();
        ids.push_back(atoi(key.c_str()));
        const FileNode g = *it, gi = info.root()[key];
        ASSERT_EQ(g.size(), gi.size()) << key;
        std::vector<GtEntry> entries;
        for (size_t k = 0; k < g.size(); ++k)
        {
            GtEntry e;
            e.obj_id = (int)g[(int)k]["obj_id"];
            Mat R = readMatx(g[(int)k]["cam_R_m2c"], 3, 3), t = readMatx(g[(int)k]["cam_t_m2c"], 3, 1);
            e.R = Matx33d((const double*)R.data);
            e.t = Vec3d((const double*)t.data);
            std::vector<int> b;
            gi[(int)k]["bbox_obj"] >> b;
            ASSERT_EQ(4u, b.size());
            e.bbox_obj = Rect2d(b[0], b[1], b[2], b[3]);
            e.visib_fract = (double)gi[(int)k]["visib_fract"];
            entries.push_back(e);
        }
        gts.push_back(entries);
        Mat K = readMatx(cam.root()[key]["cam_K"], 3, 3);
        Ks.push_back(Matx33d((const double*)K.data));
    }
}

// Renders every GT pose of the scene (objects with a mesh in `models`) on a canvas three times
// the image size (as bop_toolkit's calc_gt_info does) and compares the box with bbox_obj.
static void checkGtBoxes(const std::string& scene, const std::string& models, Size im_size,
                         const std::vector<int>& obj_ids, int expected_frames)
{
    std::vector<int> ids;
    std::vector<std::vector<GtEntry> > gts;
    std::vector<Matx33d> Ks;
    readBopScene(scene, ids, gts, Ks);
    ASSERT_EQ(expected_frames, (int)ids.size());
    Ptr<Renderer> renderer = Renderer::create(Size(3 * im_size.width, 3 * im_size.height));
    std::map<int, int> handle;
    for (size_t i = 0; i < obj_ids.size(); ++i)
    {
        const std::string path = cv::format("%s/obj_%06d.ply", models.c_str(), obj_ids[i]);
        handle[obj_ids[i]] = renderer->addMesh(Mesh::load(path));
    }
    int checked = 0;
    double worst = 1.0;
    for (size_t f = 0; f < ids.size(); ++f)
        for (size_t k = 0; k < gts[f].size(); ++k)
        {
            const GtEntry& e = gts[f][k];
            if (!handle.count(e.obj_id) || e.bbox_obj.x == -1)
                continue;
            Matx33d K = Ks[f];
            K(0, 2) += im_size.width;
            K(1, 2) += im_size.height;
            Mat mask;
            renderer->render(handle[e.obj_id], e.R, e.t, K, noArray(), noArray(), mask);
            const Rect2d box = bopBox(mask, Point(im_size.width, im_size.height));
            const double v = iou(box, e.bbox_obj);
            worst = std::min(worst, v);
            EXPECT_GE(v, 0.9) << "frame " << ids[f] << " obj " << e.obj_id << ": rendered " << box
                              << " vs bbox_obj " << e.bbox_obj;
            ++checked;
        }
    EXPECT_GT(checked, 0);
    std::cout << "checked " << checked << " ground-truth boxes, worst IoU " << worst << std::endl;
}

TEST(Forestmod_Renderer, lmo_mini_ape_boxes_match_ground_truth)
{
    const std::string scene = cvtest::findDataFile("lmo_mini/test/000002/scene_gt.json");
    const std::string dir = scene.substr(0, scene.rfind('/'));
    checkGtBoxes(dir, dir + "/../../models", Size(640, 480), std::vector<int>(1, 1), 3);
}

TEST(Forestmod_Renderer, lmo_all_ground_truth_boxes_match)
{
    const std::string root = sharedDataPath();
    if (root.empty())
        throw SkipTestException("FORESTMOD_SHARED_DATA (../shared/data with lmo/) is not available");
    const int objs[] = { 1, 5, 6, 8, 9, 10, 11, 12 };
    checkGtBoxes(root + "/lmo/test/000002", root + "/lmo/models", Size(640, 480),
                 std::vector<int>(objs, objs + 8), 50);
}

// The rendered ape (vertex colours) against the real frames of a BOP scene: the mean colour
// difference under the (eroded) rendered mask must be lower than with the frame read at an
// offset of half the object size in each of four directions. Frames where the ape is at least
// 90 % visible; returns how many were compared.
static int checkApeColour(const std::string& dir)
{
    std::vector<int> ids;
    std::vector<std::vector<GtEntry> > gts;
    std::vector<Matx33d> Ks;
    readBopScene(dir, ids, gts, Ks);
    Ptr<Renderer> renderer = Renderer::create(Size(640, 480));
    const int h = renderer->addMesh(Mesh::load(apePath()));
    int frames = 0;
    if (ids.empty())
        return 0;
    for (size_t f = 0; f < ids.size(); ++f)
        for (size_t k = 0; k < gts[f].size(); ++k)
        {
            const GtEntry& e = gts[f][k];
            if (e.obj_id != 1 || e.visib_fract < 0.9)
                continue;
            const Mat real = imread(cv::format("%s/rgb/%06d.png", dir.c_str(), ids[f]));
            if (real.empty())
            {
                ADD_FAILURE() << "cannot read frame " << ids[f] << " in " << dir;
                return frames;
            }
            Mat color, mask;
            renderer->render(h, e.R, e.t, Ks[f], color, noArray(), mask);
            erode(mask, mask, Mat(), Point(-1, -1), 2); // keep away from the silhouette
            EXPECT_GT(countNonZero(mask), 500) << "frame " << ids[f];
            // mean absolute colour difference between the rendering and the frame, the frame
            // being read at an offset (0, 0 = aligned)
            Mat realf, colorf;
            real.convertTo(realf, CV_32F);
            color.convertTo(colorf, CV_32F);
            const Rect box = boundingRect(mask);
            struct Local
            {
                static double diff(const Mat& c, const Mat& r, const Mat& m, const Rect& b, Point s)
                {
                    double sum = 0;
                    int n = 0;
                    for (int y = b.y; y < b.y + b.height; ++y)
                        for (int x = b.x; x < b.x + b.width; ++x)
                        {
                            if (!m.at<uchar>(y, x))
                                continue;
                            const Point q(x + s.x, y + s.y);
                            if (q.x < 0 || q.y < 0 || q.x >= r.cols || q.y >= r.rows)
                                continue;
                            const Vec3f a = c.at<Vec3f>(y, x), bb = r.at<Vec3f>(q);
                            sum += std::fabs(a[0] - bb[0]) + std::fabs(a[1] - bb[1])
                                   + std::fabs(a[2] - bb[2]);
                            ++n;
                        }
                    return n ? sum / (3 * n) : DBL_MAX;
                }
            };
            const double aligned = Local::diff(colorf, realf, mask, box, Point(0, 0));
            const int s = std::max(box.width, box.height) / 2;
            const Point shifts[4] = { Point(s, 0), Point(-s, 0), Point(0, s), Point(0, -s) };
            for (int i = 0; i < 4; ++i)
            {
                const double shifted = Local::diff(colorf, realf, mask, box, shifts[i]);
                EXPECT_LT(aligned, shifted) << "frame " << ids[f] << " shift " << shifts[i];
            }
            std::cout << "frame " << ids[f] << ": mean |rendered - real| " << aligned << std::endl;
            ++frames;
        }
    return frames;
}

TEST(Forestmod_Renderer, rendered_ape_colour_matches_the_real_frame)
{
    const std::string scene_file = cvtest::findDataFile("lmo_mini/test/000002/scene_gt.json");
    EXPECT_EQ(3, checkApeColour(scene_file.substr(0, scene_file.rfind('/'))));
}

TEST(Forestmod_Renderer, lmo_rendered_ape_colour_matches_the_real_frames)
{
    const std::string root = sharedDataPath();
    if (root.empty())
        throw SkipTestException("FORESTMOD_SHARED_DATA (../shared/data with lmo/) is not available");
    EXPECT_GE(checkApeColour(root + "/lmo/test/000002"), 10);
}

// ---- ViewSampler --------------------------------------------------------------------------------

TEST(Forestmod_ViewSampler, count_per_level)
{
    for (int level = 0; level <= 4; ++level)
    {
        const int full = 10 * (1 << (2 * level)) + 2;
        EXPECT_EQ(full, (int)ViewSampler::icosphere(level).size()) << level;
        ViewSampler::Params p;
        p.level = level;
        p.min_elevation = -90;
        EXPECT_EQ(full, (int)ViewSampler(p).viewpoints().size()) << level;
        // upper + lower - equator = all
        p.min_elevation = 0;
        const int upper = (int)ViewSampler(p).viewpoints().size();
        p.min_elevation = -90;
        p.max_elevation = 0;
        const int lower = (int)ViewSampler(p).viewpoints().size();
        p.min_elevation = p.max_elevation = 0;
        const int equator = (int)ViewSampler(p).viewpoints().size();
        EXPECT_EQ(full, upper + lower - equator) << level;
        EXPECT_EQ(upper, lower) << level; // the icosphere is symmetric under z -> -z
    }
    // defaults: 3 subdivisions of the icosphere's hemisphere x 6 radii x 7 in-plane angles
    ViewSampler def;
    EXPECT_EQ(91, (int)def.viewpoints().size());
    EXPECT_EQ(7, (int)def.inplaneAngles().size());
    EXPECT_EQ(91 * 6 * 7, def.size());
    EXPECT_EQ(6, ViewSampler(ViewSampler::Params::coarse()).size());
}

TEST(Forestmod_ViewSampler, level_two_spacing_is_about_15_degrees)
{
    const std::vector<Vec3d> v = ViewSampler::icosphere(2);
    double worst = 0, best = 180;
    for (size_t i = 0; i < v.size(); ++i)
    {
        double nearest = 180;
        for (size_t j = 0; j < v.size(); ++j)
            if (i != j)
                nearest = std::min(nearest, std::acos(std::min(1.0, v[i].dot(v[j]))) * 180 / CV_PI);
        worst = std::max(worst, nearest);
        best = std::min(best, nearest);
    }
    EXPECT_GT(best, 10.0);
    EXPECT_LT(worst, 20.0);
}

TEST(Forestmod_ViewSampler, poses_look_at_the_centre_from_the_upper_hemisphere)
{
    ViewSampler::Params p;
    p.level = 1;
    p.radii.clear();
    p.radii.push_back(500);
    p.radii.push_back(900);
    p.inplane_min = -30;
    p.inplane_max = 30;
    p.inplane_step = 30;
    const ViewSampler sampler(p);
    const Point3d center(12.5, -40, 33);
    const std::vector<ViewPose> poses = sampler.poses(center);
    ASSERT_EQ(sampler.size(), (int)poses.size());
    ASSERT_EQ(2 * (int)sampler.viewpoints().size() * 3, (int)poses.size());
    for (size_t i = 0; i < poses.size(); ++i)
    {
        const ViewPose& q = poses[i];
        EXPECT_LE(cv::norm(q.R * q.R.t(), Matx33d::eye(), NORM_INF), 1e-12);
        EXPECT_NEAR(1.0, determinant(q.R), 1e-12);
        const Vec3d c = q.R * Vec3d(center.x, center.y, center.z) + q.t;
        EXPECT_LE(cv::norm(c - Vec3d(0, 0, q.radius)), 1e-9) << i; // centre on the optical axis
        const Vec3d cam = -(q.R.t() * q.t);                          // camera centre, model frame
        const Vec3d rel = cam - Vec3d(center.x, center.y, center.z);
        EXPECT_NEAR(p.radii[q.radius_index], cv::norm(rel), 1e-9);
        EXPECT_GE(rel[2], -1e-9) << "below the hemisphere: " << i;
        EXPECT_NEAR(q.elevation, std::asin(rel[2] / cv::norm(rel)) * 180 / CV_PI, 1e-9);
        if (q.inplane == 0 && q.elevation < 89)
        {
            // the model's +z points up in the image
            const Vec3d up = q.R * Vec3d(center.x, center.y, center.z + 10) + q.t;
            EXPECT_LT(up[1] / up[2], 0.0) << i;
            EXPECT_NEAR(0.0, up[0] / up[2], 1e-9) << i;
        }
    }
}

TEST(Forestmod_ViewSampler, deterministic_and_readable_params)
{
    ViewSampler::Params p;
    p.level = 1;
    p.min_elevation = 10;
    p.max_elevation = 80;
    p.radii.assign(1, 700);
    const std::vector<ViewPose> a = ViewSampler(p).poses(Point3d(1, 2, 3));
    const std::vector<ViewPose> b = ViewSampler(p).poses(Point3d(1, 2, 3));
    ASSERT_EQ(a.size(), b.size());
    for (size_t i = 0; i < a.size(); ++i)
    {
        EXPECT_EQ(0, std::memcmp(a[i].R.val, b[i].R.val, sizeof(a[i].R.val)));
        EXPECT_EQ(0, std::memcmp(a[i].t.val, b[i].t.val, sizeof(a[i].t.val)));
        EXPECT_GE(a[i].elevation, 10 - 1e-9);
        EXPECT_LE(a[i].elevation, 80 + 1e-9);
    }
    FileStorage fs(".yml", FileStorage::WRITE | FileStorage::MEMORY);
    fs << "sampler" << "{";
    p.write(fs);
    fs << "}";
    const std::string text = fs.releaseAndGetString();
    FileStorage in(text, FileStorage::READ | FileStorage::MEMORY);
    ViewSampler::Params q;
    q.read(in["sampler"]);
    EXPECT_EQ(p.level, q.level);
    EXPECT_EQ(p.min_elevation, q.min_elevation);
    EXPECT_EQ(p.max_elevation, q.max_elevation);
    EXPECT_EQ(p.radii, q.radii);
    EXPECT_EQ(p.inplane_step, q.inplane_step);

    ViewSampler::Params bad;
    bad.radii.clear();
    EXPECT_THROW(ViewSampler s(bad), cv::Exception);
    bad = ViewSampler::Params();
    bad.min_elevation = 50;
    bad.max_elevation = 40;
    EXPECT_THROW(ViewSampler s(bad), cv::Exception);
    bad = ViewSampler::Params();
    bad.inplane_step = 0;
    EXPECT_THROW(ViewSampler s(bad), cv::Exception);
}

TEST(Forestmod_ViewSampler, inplane_rotation_rotates_the_image_about_the_principal_point)
{
    const Mesh ape = Mesh::load(apePath());
    const Size size(320, 240);
    const Matx33d K = cameraK(500, 500, 150.5, 130.5); // fx = fy: a pure image rotation
    ViewSampler::Params p = ViewSampler::Params::coarse();
    p.radii.assign(1, 500);
    p.inplane_min = 0;
    p.inplane_max = 40;
    p.inplane_step = 40;
    std::vector<TemplateView> views;
    renderTemplates(ape, ViewSampler(p), K, size, views);
    ASSERT_EQ(12u, views.size());
    for (size_t i = 0; i + 1 < views.size(); i += 2)
    {
        ASSERT_EQ(0, views[i].inplane_index);
        ASSERT_EQ(1, views[i + 1].inplane_index);
        // forward map of the documented convention: (du, dv) -> (c du - s dv, s du + c dv)
        const double a = 40 * CV_PI / 180, c = std::cos(a), s = std::sin(a);
        const double cx = K(0, 2), cy = K(1, 2);
        Mat M = (Mat_<double>(2, 3) << c, -s, cx - c * cx + s * cy, s, c, cy - s * cx - c * cy);
        Mat warped, wrong;
        warpAffine(views[i].mask, warped, M, size, INTER_NEAREST);
        Mat Minv;
        invertAffineTransform(M, Minv);
        warpAffine(views[i].mask, wrong, Minv, size, INTER_NEAREST);
        const Mat& target = views[i + 1].mask;
        const double good = countNonZero(warped & target) / (double)countNonZero(warped | target);
        const double bad = countNonZero(wrong & target) / (double)countNonZero(wrong | target);
        EXPECT_GT(good, 0.95) << i;
        EXPECT_LT(bad, good) << i;
    }
}

// ---- renderTemplates ----------------------------------------------------------------------------

TEST(Forestmod_RenderTemplates, labelled_deterministic_and_cancellable)
{
    const Mesh ape = Mesh::load(apePath());
    const Size size(320, 240);
    const Matx33d K = cameraK(286, 287, 160.5, 121.0);
    ViewSampler::Params p = ViewSampler::Params::coarse();
    p.inplane_min = -15;
    p.inplane_max = 15;
    p.inplane_step = 15;
    const ViewSampler sampler(p);
    std::vector<TemplateView> a, b;
    std::vector<int> seen;
    renderTemplates(ape, sampler, K, size, a, [&](int done, int total) {
        seen.push_back(done);
        EXPECT_EQ(sampler.size(), total);
        return true;
    });
    ASSERT_EQ(sampler.size(), (int)a.size());
    ASSERT_EQ(a.size(), seen.size());
    const Point3f c = ape.center();
    for (size_t i = 0; i < a.size(); ++i)
    {
        EXPECT_EQ((int)i + 1, seen[i]);
        EXPECT_EQ((int)i, a[i].view_id);
        ASSERT_EQ(CV_8UC3, a[i].color.type());
        ASSERT_EQ(size, a[i].mask.size());
        EXPECT_GT(countNonZero(a[i].mask), 200);
        EXPECT_EQ(0, cvtest::norm(a[i].mask, a[i].depth > 0, NORM_INF));
        EXPECT_EQ(boundingRect(a[i].mask), a[i].bbox);
        EXPECT_EQ(K, a[i].K);
        // the object's centre projects onto the principal point
        const Vec3d pc = a[i].R * Vec3d(c.x, c.y, c.z) + a[i].t;
        EXPECT_NEAR(K(0, 2), K(0, 0) * pc[0] / pc[2] + K(0, 2), 1e-6);
        EXPECT_NEAR(K(1, 2), K(1, 1) * pc[1] / pc[2] + K(1, 2), 1e-6);
        // the centre's depth is inside the rendered depth range
        double dmin, dmax;
        minMaxLoc(a[i].depth, &dmin, &dmax, 0, 0, a[i].mask);
        EXPECT_LE(dmin, pc[2]);
        EXPECT_GE(dmax + 1, pc[2]);
    }
    renderTemplates(ape, sampler, K, size, b);
    ASSERT_EQ(a.size(), b.size());
    for (size_t i = 0; i < a.size(); ++i)
    {
        EXPECT_EQ(0, cvtest::norm(a[i].color, b[i].color, NORM_INF)) << i;
        EXPECT_EQ(0, cvtest::norm(a[i].depth, b[i].depth, NORM_INF)) << i;
        EXPECT_EQ(a[i].R, b[i].R);
        EXPECT_EQ(a[i].t, b[i].t);
    }
    // stop after 4
    std::vector<TemplateView> c4;
    renderTemplates(ape, sampler, K, size, c4, [](int done, int) { return done < 4; });
    EXPECT_EQ(4u, c4.size());
    // streaming overload: same content, nothing kept
    int streamed = 0;
    renderTemplates(ape, sampler, K, size, [&](const TemplateView& v, int done, int) {
        EXPECT_EQ(0, cvtest::norm(v.depth, a[done - 1].depth, NORM_INF));
        ++streamed;
        return true;
    });
    EXPECT_EQ((int)a.size(), streamed);
}

// ---- Mesh / assimp ------------------------------------------------------------------------------

static const char* kTetraPlyHeader = "ply\nformat %s 1.0\nelement vertex 4\n"
                                     "property float x\nproperty float y\nproperty float z\n"
                                     "property uchar red\nproperty uchar green\nproperty uchar blue\n"
                                     "element face 4\nproperty list uchar int vertex_indices\n"
                                     "end_header\n";
static const float kTetra[4][3] = { { 0, 0, 0 }, { 100, 0, 0 }, { 0, 50, 0 }, { 0, 0, 25 } };
static const uchar kTetraRGB[4][3] = { { 255, 0, 0 }, { 0, 255, 0 }, { 0, 0, 255 }, { 10, 20, 30 } };
static const int kTetraFaces[4][3] = { { 0, 2, 1 }, { 0, 1, 3 }, { 0, 3, 2 }, { 1, 2, 3 } };

static void checkTetra(const Mesh& m, double scale)
{
    ASSERT_EQ(4u, m.vertices.size());
    ASSERT_EQ(4u, m.faces.size());
    ASSERT_EQ(4u, m.colors.size());
    ASSERT_EQ(4u, m.normals.size());
    for (int i = 0; i < 4; ++i)
    {
        // find vertex i (assimp may reorder)
        int found = -1;
        for (int j = 0; j < 4; ++j)
            if (cv::norm(Vec3f(m.vertices[j]) - Vec3f(kTetra[i][0], kTetra[i][1], kTetra[i][2]) * (float)scale) < 1e-4)
                found = j;
        ASSERT_GE(found, 0) << "vertex " << i;
        EXPECT_EQ(Vec3b(kTetraRGB[i][2], kTetraRGB[i][1], kTetraRGB[i][0]), m.colors[found]) << i;
        EXPECT_NEAR(1.0, cv::norm(m.normals[found]), 1e-5);
    }
    EXPECT_NEAR(std::sqrt(100.0 * 100 + 50 * 50) * scale, m.diameter(), 1e-3 * scale);
    EXPECT_EQ(Point3f(0, 0, 0), m.bboxMin());
    EXPECT_EQ(Point3f(100, 50, 25) * (float)scale, m.bboxMax());
    EXPECT_EQ(Point3f(50, 25, 12.5f) * (float)scale, m.center());
}

TEST(Forestmod_Mesh, ply_ascii_with_colours)
{
    std::string text = cv::format(kTetraPlyHeader, "ascii");
    for (int i = 0; i < 4; ++i)
        text += cv::format("%g %g %g %d %d %d\n", kTetra[i][0], kTetra[i][1], kTetra[i][2],
                           kTetraRGB[i][0], kTetraRGB[i][1], kTetraRGB[i][2]);
    for (int f = 0; f < 4; ++f)
        text += cv::format("3 %d %d %d\n", kTetraFaces[f][0], kTetraFaces[f][1], kTetraFaces[f][2]);
    const std::string path = writeTextFile(".ply", text);
    checkTetra(Mesh::load(path), 1.0);
    checkTetra(Mesh::load(path, 1000.0), 1000.0); // metres -> mm
    EXPECT_THROW(Mesh::load(path, 0.0), cv::Exception);
    remove(path.c_str());
}

TEST(Forestmod_Mesh, ply_binary_with_colours)
{
    std::string data = cv::format(kTetraPlyHeader, "binary_little_endian");
    for (int i = 0; i < 4; ++i)
    {
        data.append(reinterpret_cast<const char*>(kTetra[i]), 3 * sizeof(float));
        data.append(reinterpret_cast<const char*>(kTetraRGB[i]), 3);
    }
    for (int f = 0; f < 4; ++f)
    {
        data.push_back((char)3);
        data.append(reinterpret_cast<const char*>(kTetraFaces[f]), 3 * sizeof(int));
    }
    const std::string path = writeTextFile(".ply", data);
    checkTetra(Mesh::load(path), 1.0);
    remove(path.c_str());
}

TEST(Forestmod_Mesh, obj_without_colours_or_normals)
{
    // a unit cube (quads: assimp triangulates)
    const std::string text = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0 0 1\nv 1 0 1\nv 1 1 1\nv 0 1 1\n"
                             "f 1 4 3 2\nf 5 6 7 8\nf 1 2 6 5\nf 3 4 8 7\nf 1 5 8 4\nf 2 3 7 6\n";
    const std::string path = writeTextFile(".obj", text);
    const Mesh m = Mesh::load(path, 10.0);
    ASSERT_EQ(8u, m.vertices.size());
    EXPECT_EQ(12u, m.faces.size());
    ASSERT_EQ(8u, m.colors.size());
    for (size_t i = 0; i < m.colors.size(); ++i)
        EXPECT_EQ(Vec3b(128, 128, 128), m.colors[i]);
    ASSERT_EQ(8u, m.normals.size());
    const Point3f c = m.center();
    EXPECT_EQ(Point3f(5, 5, 5), c);
    for (size_t i = 0; i < m.normals.size(); ++i)
    {
        EXPECT_NEAR(1.0, cv::norm(m.normals[i]), 1e-5);
        // computed normals of a convex, consistently wound solid point outwards
        const Point3f d = m.vertices[i] - c;
        EXPECT_GT(d.dot(Point3f(m.normals[i][0], m.normals[i][1], m.normals[i][2])), 0) << i;
    }
    EXPECT_NEAR(10 * std::sqrt(3.0), m.diameter(), 1e-4);
    remove(path.c_str());
}

TEST(Forestmod_Mesh, ape_matches_models_info)
{
    const Mesh ape = Mesh::load(apePath());
    EXPECT_EQ(5841u, ape.vertices.size());
    FileStorage info(cvtest::findDataFile("lmo_mini/models/models_info.json"), FileStorage::READ);
    ASSERT_TRUE(info.isOpened());
    const FileNode e = info.root()["1"];
    EXPECT_NEAR((double)e["diameter"], ape.diameter(), 0.01);
    const Point3f lo = ape.bboxMin(), hi = ape.bboxMax();
    EXPECT_NEAR((double)e["min_x"], lo.x, 1e-3);
    EXPECT_NEAR((double)e["min_y"], lo.y, 1e-3);
    EXPECT_NEAR((double)e["min_z"], lo.z, 1e-3);
    EXPECT_NEAR((double)e["size_x"], hi.x - lo.x, 1e-3);
    // colours from the file: the ape is brown, not the grey default
    int grey = 0;
    for (size_t i = 0; i < ape.colors.size(); ++i)
        grey += ape.colors[i] == Vec3b(128, 128, 128) ? 1 : 0;
    EXPECT_LT(grey, (int)ape.colors.size() / 10);
}

TEST(Forestmod_Mesh, missing_empty_and_corrupt_files_raise_with_the_path)
{
    const std::string missing = cv::tempfile(".ply");
    try
    {
        Mesh::load(missing);
        FAIL() << "no exception for a missing file";
    }
    catch (const cv::Exception& e)
    {
        EXPECT_NE(std::string::npos, e.err.find(missing)) << e.err;
    }
    const std::string empty = writeTextFile(".ply", "");
    const std::string corrupt = writeTextFile(
        ".ply", "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nend_header\n1 2\nfoo");
    const std::string garbage = writeTextFile(".obj", std::string("\x01\x02\x03 not a mesh", 15));
    const std::string points = writeTextFile(
        ".ply", "ply\nformat ascii 1.0\nelement vertex 2\nproperty float x\nproperty float y\n"
                "property float z\nend_header\n0 0 0\n1 1 1\n");
    const std::string files[] = { empty, corrupt, garbage, points };
    for (int i = 0; i < 4; ++i)
    {
        try
        {
            Mesh m = Mesh::load(files[i]);
            ADD_FAILURE() << "no exception for " << files[i] << " (" << m.vertices.size()
                          << " vertices, " << m.faces.size() << " faces)";
        }
        catch (const cv::Exception& e)
        {
            EXPECT_NE(std::string::npos, e.err.find(files[i])) << e.err;
        }
        remove(files[i].c_str());
    }
}

static std::string readBytes(const std::string& path)
{
    std::ifstream f(path.c_str(), std::ios::binary);
    return std::string((std::istreambuf_iterator<char>(f)), std::istreambuf_iterator<char>());
}

static void expectLoadThrowsNamingFile(const std::string& path, const std::string& what)
{
    try
    {
        Mesh m = Mesh::load(path);
        ADD_FAILURE() << what << ": no exception (" << m.vertices.size() << " vertices, "
                      << m.faces.size() << " faces)";
    }
    catch (const cv::Exception& e)
    {
        EXPECT_NE(std::string::npos, e.err.find(path)) << what << ": " << e.err;
    }
}

TEST(Forestmod_Mesh, truncated_ply_raises_instead_of_loading_garbage)
{
    // assimp's PLY reader pads a truncated file (zeros, repeated faces, faces without indices on
    // which its own post-processing aborts); Mesh::load must report it. ASCII: the shipped ape,
    // cut in the vertex list, early and late in the face list; binary: the ape written as binary.
    const std::string ascii = readBytes(apePath());
    ASSERT_GT(ascii.size(), 500000u);
    const size_t cuts[] = { 1000, 100000, 300000, 450000, ascii.size() - 700 };
    for (size_t i = 0; i < sizeof(cuts) / sizeof(cuts[0]); ++i)
    {
        const std::string path = writeTextFile(".ply", ascii.substr(0, cuts[i]));
        expectLoadThrowsNamingFile(path, cv::format("ascii ape cut at %d bytes", (int)cuts[i]));
        remove(path.c_str());
    }
    const Mesh ape = Mesh::load(apePath());
    std::string bin = cv::format("ply\nformat binary_little_endian 1.0\nelement vertex %d\n"
                                 "property float x\nproperty float y\nproperty float z\n"
                                 "element face %d\nproperty list uchar int vertex_indices\n"
                                 "end_header\n",
                                 (int)ape.vertices.size(), (int)ape.faces.size());
    for (size_t i = 0; i < ape.vertices.size(); ++i)
        bin.append(reinterpret_cast<const char*>(&ape.vertices[i]), 3 * sizeof(float));
    for (size_t f = 0; f < ape.faces.size(); ++f)
    {
        bin.push_back((char)3);
        bin.append(reinterpret_cast<const char*>(&ape.faces[f]), 3 * sizeof(int));
    }
    {
        const std::string path = writeTextFile(".ply", bin);
        EXPECT_EQ(ape.faces.size(), Mesh::load(path).faces.size()); // the full file is fine
        remove(path.c_str());
    }
    const size_t bcuts[] = { 2000, bin.size() / 2, bin.size() - 13 * 50 };
    for (size_t i = 0; i < sizeof(bcuts) / sizeof(bcuts[0]); ++i)
    {
        const std::string path = writeTextFile(".ply", bin.substr(0, bcuts[i]));
        expectLoadThrowsNamingFile(path, cv::format("binary ape cut at %d bytes", (int)bcuts[i]));
        remove(path.c_str());
    }
}

TEST(Forestmod_Mesh, diameter_is_the_largest_vertex_distance)
{
    RNG rng(7);
    for (int trial = 0; trial < 5; ++trial)
    {
        Mesh m;
        const int n = 300;
        for (int i = 0; i < n; ++i)
            m.vertices.push_back(Point3f(rng.uniform(-50.f, 80.f), rng.uniform(-20.f, 30.f),
                                         rng.uniform(-60.f, 10.f)));
        double brute = 0;
        for (int i = 0; i < n; ++i)
            for (int j = i + 1; j < n; ++j)
                brute = std::max(brute, (double)cv::norm(m.vertices[i] - m.vertices[j]));
        EXPECT_NEAR(brute, m.diameter(), 1e-4);
    }
}

}} // namespace
