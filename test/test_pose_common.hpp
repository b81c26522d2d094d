// This file is part of OpenCV project.
// It is subject to the license terms in the LICENSE file found in the top-level directory
// of this distribution and at http://opencv.org/license.html

// Helpers of the pose tests: synthetic scenes (depth of a mesh + sensor-like noise), random poses.

#ifndef OPENCV_FORESTMOD_TEST_POSE_COMMON_HPP
#define OPENCV_FORESTMOD_TEST_POSE_COMMON_HPP

#include "opencv2/calib3d.hpp"
#include "../src/draw_mesh.hpp"


namespace opencv_test {
namespace pose_test {

/** The shipped LM-O ape (lmo_mini), loaded once. */
inline const Mesh& apeMesh()
{
    static Mesh m = Mesh::load(cvtest::findDataFile("lmo_mini/models/obj_000001.ply"));
    return m;
}

/** A renderer of `size` with one mesh uploaded. */
struct MeshRenderer
{
    MeshRenderer(const Mesh& m, Size size) : mesh(m)
    {
        renderer = Renderer::create(size);
        handle = renderer->addMesh(mesh);
    }
    /** CV_16UC1 depth (mm) of the mesh at (R, t). */
    Mat depth16(const Matx33d& R, const Vec3d& t, const Matx33d& K)
    {
        Mat d;
        renderer->render(handle, R, t, K, noArray(), d);
        return d;
    }
    /** The same as CV_32FC1. */
    Mat depth32(const Matx33d& R, const Vec3d& t, const Matx33d& K)
    {
        Mat d;
        depth16(R, t, K).convertTo(d, CV_32F);
        return d;
    }
    Mesh mesh;
    Ptr<Renderer> renderer;
    int handle;
};

/** The mesh of `mr` rendered at `distance` mm, seen from the direction (0.5, 0.5, 0.7071) of its
centre and turned 30 degrees in-plane (its pose in R, t), pasted on real LM-O frame 902 (the
renderer's image size: 640 x 480). */
inline Mat pastedOnRealFrame(MeshRenderer& mr, const Matx33d& K, double distance, Matx33d& R,
                             Vec3d& t)
{
    ViewSampler::lookAt(mr.mesh.center(), Vec3d(0.5, 0.5, 0.7071), distance, 30, R, t);
    Mat img = imread(cvtest::findDataFile("lmo_mini/test/000002/rgb/000902.png")), color, mask;
    CV_Assert(!img.empty());
    mr.renderer->render(mr.handle, R, t, K, color, noArray(), mask);
    color.copyTo(img, mask);
    return img;
}

/** The ape drawn both ways for 640 x 480 images: the renderer of its full mesh, and the CPU
drawing of the coarse copy that the detector's poses draw (coarseMesh with cells of
drawingCell()). */
struct CoarseApe
{
    CoarseApe()
        : mr(apeMesh(), Size(640, 480)),
          coarse(cv::forestmod::detail::coarseMesh(
              mr.mesh, cv::forestmod::detail::drawingCell(mr.mesh.diameter()))),
          silhouette(cv::forestmod::detail::silhouetteEdges(
              coarse, cv::forestmod::detail::closedWinding(coarse))),
          drawer(coarse, cv::forestmod::detail::closedWinding(coarse), Size(640, 480)),
          outline_drawer(coarse, cv::forestmod::detail::closedWinding(coarse), Size(640, 480), 0,
                         0, &silhouette)
    {
    }
    MeshRenderer mr;
    const Mesh coarse;
    const cv::forestmod::detail::SilhouetteEdges silhouette;
    /** Draws the coarse mesh; the edge alignment's points: the drawn mask's boundary. */
    const cv::forestmod::detail::MeshDrawer drawer;
    /** The same, the edge alignment's points from the silhouette edges (as the detector's). */
    const cv::forestmod::detail::MeshDrawer outline_drawer;
};

/** Kinect-like depth (CV_16UC1 mm) from an ideal float depth (mm):
- axial Gaussian noise sigma(z) = 1.2 mm + 1.9 mm (z/1000 - 0.4)^2 (Nguyen, Izadi, Lovell 2012);
- the projector's shadow: a pixel that the projector (75 mm to the right of the camera) cannot
  see behind a closer surface gets no depth (the invalid band left of foreground objects);
- pixels next to a depth jump > 20 mm (silhouettes) are lost with probability 1/2;
- 2 % random dropouts; rounding to mm. */
inline Mat sensorNoise(const Mat& depth32, RNG& rng)
{
    const double baseline_px_mm = 75.0 * 572.0; // baseline (mm) x focal length (px)
    Mat out(depth32.size(), CV_16UC1, Scalar(0));
    const int reach = 40; // pixels: 75 mm * 572 px * (1/400 - 1/1500) mm^-1 ~ 80, halved
    Mat shadow(depth32.size(), CV_8UC1, Scalar(0));
    for (int y = 0; y < depth32.rows; ++y)
    {
        const float* row = depth32.ptr<float>(y);
        uchar* sh = shadow.ptr<uchar>(y);
        // a closer surface starting at x1 hides from the projector the farther pixels x < x1
        // whose disparity offset it covers
        for (int x1 = 1; x1 < depth32.cols; ++x1)
        {
            const float z1 = row[x1];
            if (!(z1 > 0 && (row[x1 - 1] <= 0 || row[x1 - 1] > z1 + 20.f)))
                continue;
            for (int x = x1 - 1; x >= std::max(0, x1 - reach); --x)
                if (row[x] > z1 + 20.f
                    && baseline_px_mm * (1.0 / z1 - 1.0 / row[x]) >= (double)(x1 - x))
                    sh[x] = 1;
        }
    }
    for (int y = 0; y < depth32.rows; ++y)
    {
        const float* row = depth32.ptr<float>(y);
        for (int x = 0; x < depth32.cols; ++x)
        {
            const float z = row[x];
            if (z <= 0 || shadow.at<uchar>(y, x))
                continue;
            bool edge = false;
            for (int dy = -1; dy <= 1 && !edge; ++dy)
                for (int dx = -1; dx <= 1 && !edge; ++dx)
                {
                    const int xx = std::min(std::max(x + dx, 0), depth32.cols - 1);
                    const int yy = std::min(std::max(y + dy, 0), depth32.rows - 1);
                    const float zz = depth32.at<float>(yy, xx);
                    edge = zz <= 0 || std::abs(zz - z) > 20.f;
                }
            const double drop = edge ? 0.5 : 0.02;
            if (rng.uniform(0.0, 1.0) < drop)
                continue;
            const double zm = z / 1000.0 - 0.4;
            const double sigma = 1.2 + 1.9 * zm * zm;
            out.at<ushort>(y, x) = saturate_cast<ushort>(z + rng.gaussian(sigma));
        }
    }
    return out;
}

/** Rotation by `angle` (radians) about a random axis. */
inline Matx33d randomRotation(RNG& rng, double angle)
{
    Vec3d axis(rng.gaussian(1), rng.gaussian(1), rng.gaussian(1));
    axis /= cv::norm(axis);
    Matx33d R;
    Rodrigues(axis * angle, R);
    return R;
}

/** Uniformly random rotation (random axis, angle from the Haar measure by rejection). */
inline Matx33d uniformRotation(RNG& rng)
{
    // unit quaternion from 4 Gaussians
    double q[4];
    double n = 0;
    for (int i = 0; i < 4; ++i)
    {
        q[i] = rng.gaussian(1);
        n += q[i] * q[i];
    }
    n = std::sqrt(n);
    const double w = q[0] / n, x = q[1] / n, y = q[2] / n, z = q[3] / n;
    return Matx33d(1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w),
                   2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w),
                   2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y));
}

/** Angle (degrees) of R_a^T R_b. */
inline double rotationErrorDeg(const Matx33d& Ra, const Matx33d& Rb)
{
    const Matx33d D = Ra.t() * Rb;
    const double c = std::max(-1.0, std::min(1.0, (D(0, 0) + D(1, 1) + D(2, 2) - 1) / 2));
    return std::acos(c) * 180.0 / CV_PI;
}

/** Views of `mesh` from a level-1 hemisphere at these distances (mm), looking at its centre (the
default sampler's elevations and in-plane rotations). */
inline std::vector<ViewPose> hemisphereViews(const Mesh& mesh, const std::vector<double>& radii)
{
    ViewSampler::Params sp;
    sp.level = 1;
    sp.radii = radii;
    const Point3f c = mesh.center();
    return ViewSampler(sp).poses(Point3d(c.x, c.y, c.z));
}

/** A match whose template pose is (R, t) with intrinsics K, placed where that pose projects the
mesh: its initial pose in a frame of the same K is (R, t) itself. */
inline PoseMatch matchAtPose(const Mesh& mesh, const Matx33d& K, const Matx33d& R, const Vec3d& t,
                             const String& class_id = "ape")
{
    std::vector<Point2f> px;
    for (size_t i = 0; i < mesh.vertices.size(); ++i)
    {
        const Vec3d q = K * (R * Vec3d(mesh.vertices[i].x, mesh.vertices[i].y,
                                       mesh.vertices[i].z) + t);
        px.push_back(Point2f((float)(q[0] / q[2]), (float)(q[1] / q[2])));
    }
    PoseMatch m;
    m.class_id = class_id;
    m.pose.R = R;
    m.pose.t = t;
    m.pose.K = K;
    m.pose.box = boundingRect(px);
    m.pose.valid = true;
    m.box = m.pose.box;
    m.x = m.box.x;
    m.y = m.box.y;
    m.similarity = 90.f;
    return m;
}

} // namespace pose_test
} // namespace opencv_test

#endif
