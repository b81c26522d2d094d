// This file is part of OpenCV project.
// It is subject to the license terms in the LICENSE file found in the top-level directory
// of this distribution and at http://opencv.org/license.html

// Synthetic RGB-D test scenes (the "dataset" stage for depth-based evaluation: LM-O frames have
// no depth, so depth accuracy is measured on scenes the project renders itself).

#include "precomp.hpp"
#include "params_io.hpp"

#include "opencv2/calib3d.hpp"
#include "opencv2/forestmod/synthetic.hpp"

namespace cv {
namespace forestmod {

SyntheticSceneParams::SyntheticSceneParams()
    : clutter_objects(3), max_perturbation_deg(5), distance_jitter(0.03), margin(0.2),
      depth_noise(1.5), depth_dropout(0.02), plane_offset(100), color_noise(2)
{
}

void SyntheticSceneParams::read(const FileNode& fn)
{
    detail::readField(fn, "clutter_objects", clutter_objects);
    detail::readField(fn, "max_perturbation_deg", max_perturbation_deg);
    detail::readField(fn, "distance_jitter", distance_jitter);
    detail::readField(fn, "margin", margin);
    detail::readField(fn, "depth_noise", depth_noise);
    detail::readField(fn, "depth_dropout", depth_dropout);
    detail::readField(fn, "plane_offset", plane_offset);
    detail::readField(fn, "color_noise", color_noise);
}

void SyntheticSceneParams::write(FileStorage& fs) const
{
    fs << "clutter_objects" << clutter_objects << "max_perturbation_deg" << max_perturbation_deg
       << "distance_jitter" << distance_jitter << "margin" << margin << "depth_noise"
       << depth_noise << "depth_dropout" << depth_dropout << "plane_offset" << plane_offset
       << "color_noise" << color_noise;
}

SceneSynthesizer::SceneSynthesizer(const Ptr<Renderer>& renderer, const Matx33d& K,
                                   const SyntheticSceneParams& params)
    : renderer_(renderer), K_(K), params_(params)
{
    CV_Assert(!renderer.empty() && "SceneSynthesizer: null renderer");
    CV_CheckGE(params.clutter_objects, 0, "SceneSynthesizer: clutter_objects must be >= 0");
    CV_CheckGE(params.margin, 0.0, "SceneSynthesizer: margin must be in [0, 0.5)");
    CV_CheckLT(params.margin, 0.5, "SceneSynthesizer: margin must be in [0, 0.5)");
    // each in [lo, hi) (hi included for max_perturbation_deg); NaN fails every comparison
    struct Range
    {
        const char* name;
        double value, lo, hi;
        bool hi_included;
    };
    const Range ranges[] = {
        { "max_perturbation_deg", params.max_perturbation_deg, 0, 180, true },
        { "distance_jitter", params.distance_jitter, 0, 1, false },
        { "depth_noise", params.depth_noise, 0, 1e3, false },
        { "depth_dropout", params.depth_dropout, 0, 1, false },
        { "plane_offset", params.plane_offset, 0, 1e6, false },
        { "color_noise", params.color_noise, 0, 1e3, false },
    };
    for (size_t i = 0; i < sizeof(ranges) / sizeof(ranges[0]); ++i)
    {
        const Range& r = ranges[i];
        if (!(r.value >= r.lo && (r.value < r.hi || (r.hi_included && r.value == r.hi))))
            CV_Error_(Error::StsOutOfRange, ("SceneSynthesizer: %s is %g, it must be in [%g, %g%s",
                                             r.name, r.value, r.lo, r.hi,
                                             r.hi_included ? "]" : ")"));
    }
}

int SceneSynthesizer::addObject(const Mesh& mesh)
{
    handles_.push_back(renderer_->addMesh(mesh));
    const Point3f c = mesh.center();
    centers_.push_back(Point3d(c.x, c.y, c.z));
    diameters_.push_back(mesh.diameter());
    return static_cast<int>(handles_.size()) - 1;
}

void SceneSynthesizer::setBackgrounds(const std::vector<Mat>& images)
{
    backgrounds_.clear();
    for (size_t i = 0; i < images.size(); ++i)
    {
        if (images[i].empty() || images[i].type() != CV_8UC3)
            CV_Error_(Error::StsBadArg, ("SceneSynthesizer::setBackgrounds: image %d must be a "
                                         "non-empty CV_8UC3 BGR image", (int)i));
        backgrounds_.push_back(images[i]);
    }
}

// rotation that takes the optical axis (0, 0, 1) onto the unit direction d
static Matx33d rotationToRay(const Vec3d& d)
{
    const Vec3d z(0, 0, 1);
    Vec3d axis = z.cross(d);
    const double s = norm(axis), c = z.dot(d);
    if (s < 1e-12)
        return Matx33d::eye();
    axis *= std::atan2(s, c) / s;
    Matx33d R;
    Rodrigues(axis, R);
    return R;
}

static Matx33d randomRotation(RNG& rng, double max_deg)
{
    Vec3d axis(rng.gaussian(1), rng.gaussian(1), rng.gaussian(1));
    const double n = norm(axis);
    if (n < 1e-12 || max_deg <= 0)
        return Matx33d::eye();
    axis *= rng.uniform(0.0, max_deg) * CV_PI / 180 / n;
    Matx33d R;
    Rodrigues(axis, R);
    return R;
}

SyntheticScene SceneSynthesizer::render(int index, const Matx33d& Rv, const Vec3d& tv,
                                        RNG& rng) const
{
    CV_CheckGE(index, 0, "SceneSynthesizer::render: bad object index");
    CV_CheckLT(index, (int)handles_.size(), "SceneSynthesizer::render: bad object index");
    const Size size = renderer_->size();
    const Matx33d Kinv = K_.inv();
    const Point3d c = centers_[index];
    const Vec3d cv(c.x, c.y, c.z);
    const double r = norm(Rv * cv + tv) * (1 + rng.uniform(-params_.distance_jitter,
                                                             params_.distance_jitter));

    // the object: the view, perturbed, turned onto the ray through a random pixel
    const double mx = params_.margin * size.width, my = params_.margin * size.height;
    const Point2d px(rng.uniform(mx, size.width - mx), rng.uniform(my, size.height - my));
    Vec3d ray = Kinv * Vec3d(px.x, px.y, 1);
    ray *= 1.0 / norm(ray);
    const Matx33d Rray = rotationToRay(ray);
    SyntheticScene scene;
    scene.R = Rray * randomRotation(rng, params_.max_perturbation_deg) * Rv;
    scene.t = ray * r - scene.R * cv;
    const Vec3d pc = K_ * (scene.R * cv + scene.t);
    scene.center = Point2d(pc[0] / pc[2], pc[1] / pc[2]);

    std::vector<int> handles(1, handles_[index]);
    std::vector<Matx33d> Rs(1, scene.R);
    std::vector<Vec3d> ts(1, scene.t);
    // clutter: other meshes at random orientations, away from the object in the image
    const double f = K_(0, 0);
    const double obj_px = 0.5 * diameters_[index] * f / r;
    for (int k = 0, tries = 0; k < params_.clutter_objects && tries < 100 && handles_.size() > 1;
         ++tries)
    {
        int j = rng.uniform(0, (int)handles_.size());
        if (j == index)
            continue;
        const double rj = r * (1 + rng.uniform(-0.1, 0.1));
        const double clutter_px = 0.5 * diameters_[j] * f / rj;
        const Point2d q(rng.uniform(0.0, (double)size.width), rng.uniform(0.0, (double)size.height));
        if (norm(q - scene.center) < 1.1 * (obj_px + clutter_px))
            continue;
        Vec3d qray = Kinv * Vec3d(q.x, q.y, 1);
        qray *= 1.0 / norm(qray);
        const Matx33d Rj = rotationToRay(qray) * randomRotation(rng, 180.0);
        const Vec3d cj(centers_[j].x, centers_[j].y, centers_[j].z);
        handles.push_back(handles_[j]);
        Rs.push_back(Rj);
        ts.push_back(qray * rj - Rj * cj);
        ++k;
    }
    Mat color, depth, labels;
    renderer_->renderScene(handles, Rs, ts, K_, color, depth, labels);
    scene.labels = labels;

    // full silhouette of the object alone, for the visible share
    Mat alone;
    renderer_->render(handles_[index], scene.R, scene.t, K_, noArray(), noArray(), alone);
    const Mat visible = labels == 1;
    const int full = countNonZero(alone);
    scene.visible = full ? double(countNonZero(visible)) / full : 0.0;
    scene.bbox = boundingRect(visible);

    // background colour: a real image (random crop and flip) or a smooth random texture
    Mat bg;
    if (!backgrounds_.empty())
    {
        const Mat& src = backgrounds_[rng.uniform(0, (int)backgrounds_.size())];
        Mat resized;
        const double s = std::max(double(size.width) / src.cols, double(size.height) / src.rows)
            * rng.uniform(1.0, 1.3);
        resize(src, resized, Size(), s, s, INTER_LINEAR);
        const int x0 = rng.uniform(0, resized.cols - size.width + 1);
        const int y0 = rng.uniform(0, resized.rows - size.height + 1);
        bg = resized(Rect(x0, y0, size.width, size.height)).clone();
        if (rng.uniform(0, 2))
            flip(bg, bg, 1);
    }
    else
    {
        Mat coarse(size.height / 16 + 1, size.width / 16 + 1, CV_8UC3);
        rng.fill(coarse, RNG::UNIFORM, Scalar::all(30), Scalar::all(220));
        resize(coarse, bg, size, 0, 0, INTER_CUBIC);
    }
    bg.copyTo(color, labels == 0);
    if (params_.color_noise > 0)
    {
        Mat noise(size, CV_16SC3);
        rng.fill(noise, RNG::NORMAL, Scalar::all(0), Scalar::all(params_.color_noise));
        Mat c16;
        color.convertTo(c16, CV_16SC3);
        c16 += noise;
        c16.convertTo(color, CV_8UC3);
    }
    scene.color = color;

    // supporting plane behind the object, slightly tilted, then sensor noise and holes
    const double z0 = r + params_.plane_offset;
    const double ax = rng.uniform(-0.2, 0.2), ay = rng.uniform(-0.4, 0.0);
    Mat z(size, CV_64F);
    for (int v = 0; v < size.height; ++v)
        for (int u = 0; u < size.width; ++u)
        {
            const ushort d = depth.at<ushort>(v, u);
            double zz = d ? d : z0 + ax * (u - K_(0, 2)) + ay * (v - K_(1, 2));
            const double sigma = params_.depth_noise * (zz / 1000.0) * (zz / 1000.0);
            zz += rng.gaussian(sigma);
            if (rng.uniform(0.0, 1.0) < params_.depth_dropout)
                zz = 0;
            z.at<double>(v, u) = zz;
        }
    z.convertTo(scene.depth, CV_16U);
    return scene;
}

} // namespace forestmod
} // namespace cv
