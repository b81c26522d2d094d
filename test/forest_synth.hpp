// This file is part of OpenCV project.
// It is subject to the license terms in the LICENSE file found in the top-level directory
// of this distribution and at http://opencv.org/license.html

// Synthetic template descriptors for the TemplateForest tests and perf tests (header only, used
// by test/test_forest.cpp and perf/perf_forest.cpp).
//
// "Objects" are star-shaped planar shapes with a smooth intensity and colour texture. A template is a
// view of one object: rotated by alpha, scaled by s, squashed by e (a crude elevation change),
// sampled on a G x G grid of points in a window centred on the object, for two modalities:
//   modality 0, "gradient": near the silhouette the quantized orientation (mod pi, 8 bins) of the
//             silhouette normal; inside, the quantized orientation of the gradient of a smooth
//             intensity field (three plane waves), 0 where that gradient is weak;
//   modality 1, "hue": a smooth hue field quantized to 8 bins, 0 (grey) where a smooth saturation
//             field is low.
// Off the object the values are 0 and the foreground mask is 0 (the forest replaces them with noise).
// Neighbouring views give similar descriptors, as rendered views do.

#ifndef OPENCV_FORESTMOD_TEST_FOREST_SYNTH_HPP
#define OPENCV_FORESTMOD_TEST_FOREST_SYNTH_HPP

#include "opencv2/core.hpp"
#include <cmath>

namespace opencv_test {
namespace forest_synth {

struct Wave
{
    double kx, ky, ph, amp;
};

/** Parameters of one rendered view (to render it again, e.g. misaligned). */
struct View
{
    int object;
    double alpha, scale, squash;
};

struct Shape
{
    double r0, a, phi;
    int k;
    Wave intensity[3];   // intensity field: its gradient orientation is the "gradient" modality
    Wave hue[2];         // hue field: quantized to 8 bins; grey where `sat` is low
    Wave sat;
};

static inline Wave makeWave(cv::RNG& rng, double fmin, double fmax)
{
    const double f = rng.uniform(fmin, fmax), th = rng.uniform(0., CV_2PI);
    Wave w;
    w.kx = f * std::cos(th);
    w.ky = f * std::sin(th);
    w.ph = rng.uniform(0., CV_2PI);
    w.amp = rng.uniform(0.5, 1.0);
    return w;
}

static inline Shape makeShape(int object)
{
    cv::RNG rng(0x5eed + 7919 * (uint64)object);
    Shape s;
    s.r0 = rng.uniform(0.7, 0.85);
    s.a = rng.uniform(0.1, 0.3);
    s.k = rng.uniform(2, 6);
    s.phi = rng.uniform(0., CV_2PI);
    for (int i = 0; i < 3; ++i)
        s.intensity[i] = makeWave(rng, 1., 2.5);
    for (int i = 0; i < 2; ++i)
        s.hue[i] = makeWave(rng, 0.5, 1.5);
    s.sat = makeWave(rng, 1., 3.);
    return s;
}

static inline int orientationLabel(double angle)
{
    double a = std::fmod(angle, CV_PI);
    if (a < 0)
        a += CV_PI;
    return std::min(7, (int)(a / (CV_PI / 8)));
}

/** One view: G*G*2 values (modality-major) and the foreground mask. */
static inline void renderView(const Shape& s, double alpha, double scale, double squash, int G,
                              uchar* desc, uchar* fg, double weak_gradient, double grey,
                              double tx = 0, double ty = 0)
{
    const int GG = G * G;
    const double ca = std::cos(alpha), sa = std::sin(alpha);
    for (int y = 0; y < G; ++y)
        for (int x = 0; x < G; ++x)
        {
            const int j = y * G + x;
            // window coordinates in [-1, 1]; (tx, ty) moves the object (a misaligned window)
            const double px = (x + 0.5) / G * 2 - 1 - tx, py = (y + 0.5) / G * 2 - 1 - ty;
            // image -> object frame
            double qx = (ca * px + sa * py) / scale, qy = (-sa * px + ca * py) / (scale * squash);
            const double th = std::atan2(qy, qx), r = std::sqrt(qx * qx + qy * qy);
            const double R = s.r0 * (1 + s.a * std::cos(s.k * th + s.phi));
            if (r >= R)
            {
                desc[j] = desc[GG + j] = 0;
                fg[j] = fg[GG + j] = 0;
                continue;
            }
            fg[j] = fg[GG + j] = 1;
            // gradient modality
            double gx, gy;
            if (r > 0.75 * R)
            {
                // silhouette: normal = radial direction corrected by dR/dtheta
                const double dR = -s.r0 * s.a * s.k * std::sin(s.k * th + s.phi);
                gx = std::cos(th) * R + std::sin(th) * dR;
                gy = std::sin(th) * R - std::cos(th) * dR;
            }
            else
            {
                gx = gy = 0;
                for (int i = 0; i < 3; ++i)
                {
                    const Wave& w = s.intensity[i];
                    const double c = w.amp * std::cos(w.kx * qx + w.ky * qy + w.ph);
                    gx += w.kx * c;
                    gy += w.ky * c;
                }
                const double mag = std::sqrt(gx * gx + gy * gy);
                if (mag < weak_gradient)
                    gx = gy = 0;   // weak gradient: no feature
            }
            int g = -1;
            if (gx != 0 || gy != 0)
            {
                // object frame -> image frame (rotation by alpha)
                const double ix = ca * gx - sa * gy, iy = sa * gx + ca * gy;
                g = orientationLabel(std::atan2(iy, ix));
            }
            desc[j] = g < 0 ? 0 : (uchar)(1 << g);
            // hue modality
            int h = -1;
            const double sat = std::sin(s.sat.kx * qx + s.sat.ky * qy + s.sat.ph);
            if (sat > -grey)
            {
                double v = 0;
                for (int i = 0; i < 2; ++i)
                    v += s.hue[i].amp * std::sin(s.hue[i].kx * qx + s.hue[i].ky * qy + s.hue[i].ph);
                h = ((int)std::floor((v + 2.0) * 2.0) % 8 + 8) % 8;
            }
            desc[GG + j] = h < 0 ? 0 : (uchar)(1 << h);
        }
}

/** n templates of `objects` objects on a G x G grid (D = 2 G^2). As a rendered template set, the
views of one object sample a regular grid: 3 scales (0.9, 1.0, 1.1) x 2 squash factors (1, 0.85;
a crude elevation change) x in-plane rotations in equal steps over 360 degrees; `seed` adds a small
jitter (+-10 % of a step) so that template sets of different seeds differ. The window is sized to
the object, as a detector's is, so most grid points lie on it. `weak_gradient` (gradient magnitude
below which a point has no gradient label) and `grey` (share of the saturation field's range that
is coloured) set how dense the labels are: the defaults give about 5 % unlabelled points. */
static inline void makeTemplates(int n, int objects, int G, uint64 seed, cv::Mat& desc,
                                 cv::Mat& fg, std::vector<int>* object_of = 0,
                                 double weak_gradient = 0.5, double grey = 0.95,
                                 std::vector<View>* views = 0)
{
    desc.create(n, 2 * G * G, CV_8U);
    fg.create(n, 2 * G * G, CV_8U);
    cv::RNG rng(seed);
    std::vector<Shape> shapes;
    for (int o = 0; o < objects; ++o)
        shapes.push_back(makeShape(o));
    if (object_of)
        object_of->resize(n);
    const int per_object = (n + objects - 1) / objects;
    const int nrot = std::max(1, (per_object + 5) / 6);
    const double step = CV_2PI / nrot;
    for (int i = 0; i < n; ++i)
    {
        const int o = i % objects, v = i / objects;
        const int rot = v % nrot, rest = v / nrot;
        const double alpha = (rot + rng.uniform(-0.1, 0.1)) * step;
        const double scale = 0.9 + 0.1 * (rest % 3) + rng.uniform(-0.01, 0.01);
        const double squash = (rest / 3) % 2 == 0 ? 1.0 : 0.85;
        renderView(shapes[o], alpha, scale, squash, G, desc.ptr<uchar>(i), fg.ptr<uchar>(i),
                   weak_gradient, grey);
        if (object_of)
            (*object_of)[i] = o;
        if (views)
        {
            View view;
            view.object = o;
            view.alpha = alpha;
            view.scale = scale;
            view.squash = squash;
            views->push_back(view);
        }
    }
}

/** A uniformly random value: 0 or one of the 8 label bits, each with probability 1/9. */
static inline uchar randomValue(cv::RNG& rng)
{
    const int u = rng.uniform(0, 9);
    return u == 8 ? 0 : (uchar)(1 << u);
}

/** Copies `src` and replaces a share `frac` of its dims (distinct, random) by random values. */
static inline void perturb(const uchar* src, int D, double frac, cv::RNG& rng, uchar* dst)
{
    std::copy(src, src + D, dst);
    const int k = cvRound(frac * D);
    std::vector<int> perm(D);
    for (int j = 0; j < D; ++j)
        perm[j] = j;
    for (int i = 0; i < k; ++i)
    {
        const int s = i + rng.uniform(0, D - i);
        std::swap(perm[i], perm[s]);
        dst[perm[i]] = randomValue(rng);
    }
}

} // namespace forest_synth
} // namespace opencv_test

#endif
