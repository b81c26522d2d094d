// This file is part of OpenCV project.
// It is subject to the license terms in the LICENSE file found in the top-level directory
// of this distribution and at http://opencv.org/license.html

// Helpers of the pose tests: synthetic scenes (depth of a mesh + sensor-like noise), random poses.

#ifndef OPENCV_FORESTMOD_TEST_POSE_COMMON_HPP
#define OPENCV_FORESTMOD_TEST_POSE_COMMON_HPP

#include "opencv2/calib3d.hpp"

#include <fstream>
#include <sstream>

namespace opencv_test {
namespace pose_test {

/** A triangle mesh: vertices (mm) and faces. */
struct TriMesh
{
    std::vector<Point3f> vertices;
    std::vector<Vec3i> faces;
};

/** Minimal reader of ASCII PLY meshes (BOP models): x, y, z of the vertices, triangles. */
inline TriMesh readAsciiPly(const std::string& path)
{
    std::ifstream in(path.c_str());
    CV_Assert(in.good());
    std::string line, word;
    int nv = -1, nf = -1, nprops = 0, ix = -1, iy = -1, iz = -1;
    bool in_vertex = false;
    while (std::getline(in, line))
    {
        std::istringstream ls(line);
        ls >> word;
        if (word == "format")
        {
            ls >> word;
            CV_Assert(word == "ascii");
        }
        else if (word == "element")
        {
            std::string what;
            int count;
            ls >> what >> count;
            in_vertex = what == "vertex";
            if (in_vertex)
                nv = count;
            else if (what == "face")
                nf = count;
        }
        else if (word == "property" && in_vertex)
        {
            std::string type, name;
            ls >> type >> name;
            if (name == "x") ix = nprops;
            if (name == "y") iy = nprops;
            if (name == "z") iz = nprops;
            ++nprops;
        }
        else if (word == "end_header")
            break;
    }
    CV_Assert(nv > 0 && nf > 0 && ix >= 0 && iy >= 0 && iz >= 0);
    TriMesh m;
    std::vector<double> v(nprops);
    for (int i = 0; i < nv; ++i)
    {
        for (int k = 0; k < nprops; ++k)
            in >> v[k];
        m.vertices.push_back(Point3f((float)v[ix], (float)v[iy], (float)v[iz]));
    }
    for (int i = 0; i < nf; ++i)
    {
        int n, a, b, c;
        in >> n >> a >> b >> c;
        CV_Assert(n == 3);
        m.faces.push_back(Vec3i(a, b, c));
    }
    CV_Assert(!in.fail());
    return m;
}

/** Z-buffer rasteriser: depth (float mm, 0 = empty) of the mesh at pose (R, t) seen with K,
pixel centres at integer coordinates; draws into `depth` (CV_32FC1) keeping the closest surface. */
inline void rasterizeDepth(const TriMesh& m, const Matx33d& R, const Vec3d& t, const Matx33d& K,
                           Mat& depth)
{
    CV_Assert(depth.type() == CV_32FC1);
    std::vector<Vec3d> pc(m.vertices.size());
    for (size_t i = 0; i < m.vertices.size(); ++i)
    {
        const Point3f& p = m.vertices[i];
        const Vec3d c = R * Vec3d(p.x, p.y, p.z) + t;
        pc[i] = Vec3d(K(0, 0) * c[0] / c[2] + K(0, 2), K(1, 1) * c[1] / c[2] + K(1, 2), c[2]);
    }
    for (size_t f = 0; f < m.faces.size(); ++f)
    {
        const Vec3d& a = pc[m.faces[f][0]];
        const Vec3d& b = pc[m.faces[f][1]];
        const Vec3d& c = pc[m.faces[f][2]];
        if (a[2] <= 0 || b[2] <= 0 || c[2] <= 0)
            continue;
        const double area = (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]);
        if (std::abs(area) < 1e-12)
            continue;
        const int x0 = std::max(0, (int)std::ceil(std::min(a[0], std::min(b[0], c[0]))));
        const int x1 = std::min(depth.cols - 1, (int)std::floor(std::max(a[0], std::max(b[0], c[0]))));
        const int y0 = std::max(0, (int)std::ceil(std::min(a[1], std::min(b[1], c[1]))));
        const int y1 = std::min(depth.rows - 1, (int)std::floor(std::max(a[1], std::max(b[1], c[1]))));
        for (int y = y0; y <= y1; ++y)
            for (int x = x0; x <= x1; ++x)
            {
                const double w0 = ((b[0] - x) * (c[1] - y) - (b[1] - y) * (c[0] - x)) / area;
                const double w1 = ((c[0] - x) * (a[1] - y) - (c[1] - y) * (a[0] - x)) / area;
                const double w2 = 1 - w0 - w1;
                if (w0 < 0 || w1 < 0 || w2 < 0)
                    continue;
                // perspective-correct: 1/z is affine in the image
                const double z = 1.0 / (w0 / a[2] + w1 / b[2] + w2 / c[2]);
                float& d = depth.at<float>(y, x);
                if (d == 0 || z < d)
                    d = (float)z;
            }
    }
}

/** Ideal CV_16UC1 depth (mm, rounded) of the mesh at (R, t). */
inline Mat renderDepth16(const TriMesh& m, const Matx33d& R, const Vec3d& t, const Matx33d& K,
                         Size size)
{
    Mat d(size, CV_32FC1, Scalar(0));
    rasterizeDepth(m, R, t, K, d);
    Mat d16;
    d.convertTo(d16, CV_16U);
    return d16;
}

/** Adds Kinect-like noise to a float depth (mm): axial Gaussian noise sigma(z) = 1.2 mm +
1.9 mm (z/1000 - 0.4)^2 (Nguyen et al. 2012), 2 % random dropouts, no depth at pixels next to a
depth jump > 20 mm (shadows at silhouettes), rounding to mm. */
inline Mat sensorNoise(const Mat& depth32, RNG& rng)
{
    Mat out(depth32.size(), CV_16UC1, Scalar(0));
    for (int y = 0; y < depth32.rows; ++y)
        for (int x = 0; x < depth32.cols; ++x)
        {
            const float z = depth32.at<float>(y, x);
            if (z <= 0)
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
            if (edge || rng.uniform(0.0, 1.0) < 0.02)
                continue;
            const double zm = z / 1000.0 - 0.4;
            const double sigma = 1.2 + 1.9 * zm * zm;
            out.at<ushort>(y, x) = saturate_cast<ushort>(z + rng.gaussian(sigma));
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

/** The LM-O camera (BOP lmo camera.json). */
inline Matx33d lmoK()
{
    return Matx33d(572.4114, 0, 325.2611, 0, 573.57043, 242.04899, 0, 0, 1);
}

} // namespace pose_test
} // namespace opencv_test

#endif
