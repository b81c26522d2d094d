// This file is part of OpenCV project.
// It is subject to the license terms in the LICENSE file found in the top-level directory
// of this distribution and at http://opencv.org/license.html

// The verification stage: the best hypotheses of each class are rendered at their pose and scored
// on evidence the LINEMOD similarity does not use (colour on the visible mask, the whole rendered
// contour against the scene's edges, occlusion, depth), then re-ranked by a weighted sum
// (doc/verification.md).

#include "precomp.hpp"
#include "params_io.hpp"
#include "verification.hpp"
#include "edge_gradient.hpp"
#include "pose_refine.hpp"
#include "opencv2/core/hal/intrin.hpp"

#include <map>

namespace cv {
namespace forestmod {

VerificationParams::VerificationParams()
    : enabled(true), top_k(10), second_round_below(0.75), min_saturation(0.25), min_value(0.15),
      hue_tolerance(20),
      edge_distance(3), depth_tolerance(0.05), min_visible(0.5), sample_step(2),
      w_similarity(0.1), w_color(0.3), w_edges(0.3), w_depth(0.4), w_region(0.3), region_width(6),
      background_weight(1.5), background_quantile(0.99)
{
}

void VerificationParams::read(const FileNode& fn)
{
    detail::readField(fn, "enabled", enabled);
    detail::readField(fn, "top_k", top_k);
    detail::readField(fn, "second_round_below", second_round_below);
    detail::readField(fn, "min_saturation", min_saturation);
    detail::readField(fn, "min_value", min_value);
    detail::readField(fn, "hue_tolerance", hue_tolerance);
    detail::readField(fn, "edge_distance", edge_distance);
    if (!fn["edge_params"].empty())
        edge_params.read(fn["edge_params"]);
    detail::readField(fn, "depth_tolerance", depth_tolerance);
    detail::readField(fn, "min_visible", min_visible);
    detail::readField(fn, "sample_step", sample_step);
    detail::readField(fn, "w_similarity", w_similarity);
    detail::readField(fn, "w_color", w_color);
    detail::readField(fn, "w_edges", w_edges);
    detail::readField(fn, "w_depth", w_depth);
    detail::readField(fn, "w_region", w_region);
    detail::readField(fn, "region_width", region_width);
    detail::readField(fn, "background_weight", background_weight);
    detail::readField(fn, "background_quantile", background_quantile);
}

void VerificationParams::write(FileStorage& fs) const
{
    fs << "enabled" << (int)enabled << "top_k" << top_k << "second_round_below"
       << second_round_below << "min_saturation" << min_saturation
       << "min_value" << min_value << "hue_tolerance" << hue_tolerance << "edge_distance"
       << edge_distance;
    fs << "edge_params" << "{";
    edge_params.write(fs);
    fs << "}";
    fs << "depth_tolerance" << depth_tolerance << "min_visible" << min_visible << "sample_step"
       << sample_step << "w_similarity" << w_similarity << "w_color" << w_color << "w_edges"
       << w_edges << "w_depth" << w_depth << "w_region" << w_region << "region_width"
       << region_width << "background_weight" << background_weight << "background_quantile"
       << background_quantile;
}

namespace detail {

static void checkWeight(double w, const char* name)
{
    if (!(w >= 0 && w < 1e6))
        CV_Error_(Error::StsOutOfRange, ("VerificationParams: %s must be a finite weight >= 0, "
                                         "got %g", name, w));
}

void checkBackgroundQuantile(double q)
{
    if (!(q > 0 && q <= 1))
        CV_Error_(Error::StsOutOfRange, ("background quantile must be in (0, 1], got %g", q));
}

void checkVerificationParams(const VerificationParams& p)
{
    if (p.top_k < 1)
        CV_Error_(Error::StsOutOfRange, ("VerificationParams: top_k must be >= 1, got %d",
                                         p.top_k));
    if (!(p.second_round_below >= 0 && p.second_round_below < 1e6))
        CV_Error_(Error::StsOutOfRange, ("VerificationParams: second_round_below must be finite "
                                         "and >= 0, got %g", p.second_round_below));
    if (!(p.min_saturation >= 0 && p.min_saturation <= 1) || !(p.min_value >= 0
                                                                && p.min_value <= 1))
        CV_Error(Error::StsOutOfRange, "VerificationParams: min_saturation and min_value must be "
                                       "in [0, 1]");
    if (!(p.hue_tolerance > 0 && p.hue_tolerance <= 180))
        CV_Error_(Error::StsOutOfRange, ("VerificationParams: hue_tolerance must be in (0, 180] "
                                         "degrees, got %g", p.hue_tolerance));
    if (!(p.edge_distance > 0 && p.edge_distance < p.edge_params.max_distance))
        CV_Error_(Error::StsOutOfRange, ("VerificationParams: edge_distance must be in (0, "
                                         "edge_params.max_distance = %g) px, got %g",
                                         p.edge_params.max_distance, p.edge_distance));
    if (p.edge_params.orientations < 2 || p.edge_params.orientations > 32
        || !(p.edge_params.canny_low >= 0 && p.edge_params.canny_high >= p.edge_params.canny_low))
        CV_Error(Error::StsOutOfRange, "VerificationParams: edge_params needs orientations in "
                                       "[2, 32] and 0 <= canny_low <= canny_high");
    if (!(p.depth_tolerance > 0 && p.depth_tolerance < 10))
        CV_Error_(Error::StsOutOfRange, ("VerificationParams: depth_tolerance must be a share of "
                                         "the diameter in (0, 10), got %g", p.depth_tolerance));
    if (!(p.min_visible > 0 && p.min_visible <= 1))
        CV_Error_(Error::StsOutOfRange, ("VerificationParams: min_visible must be in (0, 1], got "
                                         "%g", p.min_visible));
    if (p.sample_step < 1 || p.sample_step > 64)
        CV_Error_(Error::StsOutOfRange, ("VerificationParams: sample_step must be in [1, 64], got "
                                         "%d", p.sample_step));
    checkWeight(p.w_similarity, "w_similarity");
    checkWeight(p.w_color, "w_color");
    checkWeight(p.w_edges, "w_edges");
    checkWeight(p.w_depth, "w_depth");
    checkWeight(p.w_region, "w_region");
    if (p.region_width < 1 || p.region_width > 64)
        CV_Error_(Error::StsOutOfRange, ("VerificationParams: region_width must be in [1, 64] px, "
                                         "got %d", p.region_width));
    checkWeight(p.background_weight, "background_weight");
    checkBackgroundQuantile(p.background_quantile);
    if (!(p.w_similarity + p.w_color + p.w_edges + p.w_region > 0))
        CV_Error(Error::StsOutOfRange, "VerificationParams: w_similarity + w_color + w_edges + "
                                       "w_region must be > 0");
}

namespace {

// One hypothesis rendered: the crop (scene image coordinates) around it and the crop-sized images
// (face: the face seen at each pixel, whose colour face_hsv holds).
struct Rendered
{
    Rect rect;  // crop in the scene image (what is scored; the images below are of its size)
    Rect drawn; // the drawing's crop, which holds rect (Canny runs on it when there are no maps)
    Mat face, depth, mask;
    const Mat* face_hsv;
    double diameter;
};

// The scene's edges around a crop: read from the frame's edge maps when the pose stage made them
// (distance to an edge of a bin or its neighbours), else Canny on the crop with the refinement's
// thresholds, each pixel's orientation bin (that of the strongest channel's gradient, as
// computeEdgeMaps) computed the first time a contour point looks at it.
class SceneEdges
{
public:
    SceneEdges(const Mat& color, const Rect& crop, const EdgeMaps* maps,
               const EdgeRefineParams& ep)
        : crop_(crop), maps_(maps), sobel_(color(crop)),
          orientations_(ep.orientations)
    {
        if (maps)
            return;
        Canny(color(crop), bins_, ep.canny_low, ep.canny_high, 3, true);
        bins_.setTo(kUnknown, bins_);
        bins_.setTo(kNone, bins_ == 0);
    }
    // a scene edge of orientation bin b (or a neighbouring one) within radius r of crop pixel
    // (x, y)
    bool edgeWithin(int x, int y, int b, double r)
    {
        if (maps_)
            return maps_->distance[b].at<float>(y + crop_.y, x + crop_.x) <= r;
        const int R = cvCeil(r), B = orientations_;
        const double r2 = r * r;
        for (int v = std::max(0, y - R); v <= std::min(bins_.rows - 1, y + R); ++v)
        {
            for (int u = std::max(0, x - R); u <= std::min(bins_.cols - 1, x + R); ++u)
            {
                if ((u - x) * (u - x) + (v - y) * (v - y) > r2)
                    continue;
                const int e = bin(u, v);
                if (e == kNone)
                    continue;
                const int d = std::abs(e - b);
                if (std::min(d, B - d) <= 1)
                    return true;
            }
        }
        return false;
    }

private:
    // the orientation bin of the crop's edge at (x, y), kNone without one
    int bin(int x, int y)
    {
        uchar& b = bins_.at<uchar>(y, x);
        if (b == kUnknown)
        {
            int gx = 0, gy = 0;
            sobel_.strongest(x, y, gx, gy);
            b = (uchar)orientationBin((float)gx, (float)gy, orientations_);
        }
        return b;
    }
    static const uchar kNone = 255, kUnknown = 254;
    const Rect crop_;
    const EdgeMaps* maps_;
    const PointSobel sobel_;
    const int orientations_;
    Mat bins_;
};

// colour class of an HSV pixel: -1 achromatic, else the hue (0..179)
static inline int hueClass(const uchar* hsv, int min_s, int min_v)
{
    return hsv[1] < min_s || hsv[2] < min_v ? -1 : (int)hsv[0];
}

static inline bool colourAgrees(int hm, int hs, int tol)
{
    if (hm < 0 || hs < 0)
        return hm < 0 && hs < 0;
    int d = std::abs(hm - hs);
    d = std::min(d, 180 - d);
    return d <= tol;
}

// f(x) for each x < n with row[x] != 0, in order; whole vectors of zeros skipped (the drawn
// masks, their interiors and contours leave most of a crop's bytes 0).
template <typename F>
static inline void forEachNonZero(const uchar* row, int n, F f)
{
    int x = 0;
#if CV_SIMD
    const v_uint8 zero = vx_setzero_u8();
    for (; x + v_uint8::nlanes <= n; x += v_uint8::nlanes)
    {
        if (!v_check_any(vx_load(row + x) != zero))
            continue;
        for (int k = x; k < x + v_uint8::nlanes; ++k)
            if (row[k])
                f(k);
    }
#endif
    for (; x < n; ++x)
        if (row[x])
            f(x);
}

// Colour and depth agreement on the interior of the drawn mask; `state` receives per interior
// pixel 0 no sample, 1 agrees, 2 disagrees, 3 occluded (depth nearer). Returns the share of
// visible samples whose colour agrees. `inner`: the mask eroded once (3 x 3).
static double scoreInterior(const Rendered& r, const Mat& inner, const Mat& hsv_s,
                            const Mat& scene_depth, const VerificationParams& p, Mat& state,
                            PoseMatch& m)
{
    const Size sz = r.rect.size();
    const int min_s = cvRound(255 * p.min_saturation), min_v = cvRound(255 * p.min_value);
    const int hue_tol = std::max(0, cvRound(p.hue_tolerance / 2)); // OpenCV hue: 2 degrees
    const double tol_mm = p.depth_tolerance * r.diameter;
    const bool with_depth = !scene_depth.empty();
    const Mat depth = with_depth ? scene_depth(r.rect) : Mat();
    const Vec3b* face_hsv = r.face_hsv->ptr<Vec3b>();
    Mat interior;
    erode(inner, interior, Mat()); // eroded twice: colours at the silhouette are mixed
    if (countNonZero(interior) == 0)
        interior = r.mask;
    state = Mat::zeros(sz, CV_8UC1);
    int n_all = 0, n_occ = 0, n_col = 0, n_dvalid = 0, n_dvalid_vis = 0, n_dok = 0;
    for (int y = 0; y < sz.height; ++y)
    {
        const uchar* in = interior.ptr<uchar>(y);
        const int* face = r.face.ptr<int>(y);
        const uchar* hs = hsv_s.ptr<uchar>(y);
        const ushort* rd = r.depth.ptr<ushort>(y);
        const ushort* sd = with_depth ? depth.ptr<ushort>(y) : 0;
        uchar* st = state.ptr<uchar>(y);
        const bool row_sampled = y % p.sample_step == 0;
        forEachNonZero(in, sz.width, [&](int x) {
            bool occluded = false, dvalid = false;
            if (with_depth && sd[x] > 0)
            {
                dvalid = true;
                occluded = (double)sd[x] < (double)rd[x] - tol_mm;
            }
            const bool agree = !occluded
                && colourAgrees(hueClass(face_hsv[face[x]].val, min_s, min_v),
                                hueClass(hs + 3 * x, min_s, min_v), hue_tol);
            st[x] = occluded ? 3 : agree ? 1 : 2;
            if (!row_sampled || x % p.sample_step != 0)
                return;
            ++n_all;
            n_occ += occluded;
            n_col += agree;
            if (dvalid)
            {
                ++n_dvalid;
                if (!occluded)
                {
                    ++n_dvalid_vis;
                    n_dok += std::abs((double)sd[x] - (double)rd[x]) <= tol_mm;
                }
            }
        });
    }
    const int n_vis = n_all - n_occ;
    m.color_score = n_all > 0 ? n_col / std::max((double)n_vis, p.min_visible * n_all) : 0.0;
    m.depth_score = !with_depth ? -1.0
        : n_dvalid > 0 ? n_dok / std::max((double)n_dvalid_vis, p.min_visible * n_dvalid) : 0.0;
    const double raw_colour = n_vis > 0 ? double(n_col) / n_vis : 0.0;
    // the occlusion share with depth (scoreContour sets it without)
    m.occlusion = n_all > 0 ? double(n_occ) / n_all : 0.0;
    return raw_colour;
}

// The nonzero pixels of a crop-sized CV_8UC1 image (the drawn contour: a thin line), row by row.
static void nonZeroPixels(const Mat& img, std::vector<Point>& out)
{
    out.clear();
    for (int y = 0; y < img.rows; ++y)
        forEachNonZero(img.ptr<uchar>(y), img.cols, [&](int x) { out.push_back(Point(x, y)); });
}

// The whole drawn contour against the scene's edges of its orientation; a contour point without
// an edge is excused when the pixels around it say it is covered (`state` of scoreInterior).
// In three passes over the contour's points: their orientations, the edge test of each (the
// frame's distance maps read point after point, so that their cache misses overlap), then the
// neighbourhood of the points without an edge.
static void scoreContour(const Rendered& r, const Mat& inner, const Mat& scene_color,
                         const EdgeMaps* maps, bool with_depth, double raw_colour,
                         const Mat& state, const VerificationParams& p, PoseMatch& m)
{
    const Size sz = r.rect.size();
    SceneEdges edges(scene_color, r.drawn, maps, p.edge_params);
    const Point in_drawn = r.rect.tl() - r.drawn.tl();
    const int B = p.edge_params.orientations;
    Mat contour, blurred;
    subtract(r.mask, inner, contour);
    GaussianBlur(r.mask, blurred, Size(5, 5), 0);
    const PointSobel sobel(blurred);
    std::vector<Point> points;
    nonZeroPixels(contour, points);
    const int n_contour = (int)points.size();
    std::vector<uchar> bins(points.size()), matched(points.size());
    for (int i = 0; i < n_contour; ++i)
    {
        int gx, gy;
        sobel.at(points[i].x, points[i].y, 0, gx, gy); // the smoothed mask's gradient
        bins[i] = (uchar)orientationBin((float)gx, (float)gy, B);
    }
    for (int i = 0; i < n_contour; ++i)
        matched[i] = edges.edgeWithin(points[i].x + in_drawn.x, points[i].y + in_drawn.y,
                                      bins[i], p.edge_distance);
    const int W = 3; // half window of the local evidence of a contour point
    int n_matched = 0, n_covered = 0;
    for (int i = 0; i < n_contour; ++i)
    {
        if (matched[i])
        {
            ++n_matched;
            continue;
        }
        // no edge here: is the fragment covered by something nearer?
        const int x = points[i].x, y = points[i].y;
        int occ = 0, dis = 0, agr = 0;
        for (int v = std::max(0, y - W); v <= std::min(sz.height - 1, y + W); ++v)
        {
            const uchar* st = state.ptr<uchar>(v);
            for (int u = std::max(0, x - W); u <= std::min(sz.width - 1, x + W); ++u)
            {
                occ += st[u] == 3;
                agr += st[u] == 1;
                dis += st[u] == 2;
            }
        }
        bool covered;
        if (with_depth)
            covered = occ > 0 && occ >= agr + dis;
        else // the object is there (its colour mostly agrees) but not here
            covered = raw_colour >= 0.5 && dis > agr;
        n_covered += covered;
    }
    m.edge_score = n_contour > 0
        ? n_matched / std::max((double)(n_contour - n_covered), p.min_visible * n_contour)
        : 0.0;
    if (!with_depth)
        m.occlusion = n_contour > 0 ? double(n_covered) / n_contour : 0.0;
}

// The ring of scoreRegion starts this far (chessboard distance, px) outside the silhouette.
static const int kRingGap = 2;

// Colour bin of an HSV pixel for the region histograms: 12 hues x 2 saturations, or one of 4
// grey levels when achromatic (hueClass' rule).
static inline int regionBin(const uchar* hsv, int min_s, int min_v)
{
    const int hue = hueClass(hsv, min_s, min_v);
    if (hue < 0)
        return 24 + (hsv[2] >> 6);
    return (hue / 15) * 2 + (hsv[1] >= 153);
}

// The scene's colours inside the silhouette (the interior pixels not occluded) against those of
// a ring around it: total variation distance of the two histograms.
static void scoreRegion(const Rendered& r, const Mat& hsv_s, const Mat& state,
                        const VerificationParams& p, PoseMatch& m)
{
    const int min_s = cvRound(255 * p.min_saturation), min_v = cvRound(255 * p.min_value);
    const int gap = kRingGap, reach = gap + p.region_width; // the ring: gap < distance <= reach
    Mat outer, inner;
    // (a rectangle's dilation of a rectangle's: the same as the mask's by the sum of both)
    dilate(r.mask, inner, getStructuringElement(MORPH_RECT, Size(2 * gap + 1, 2 * gap + 1)));
    dilate(inner, outer, getStructuringElement(MORPH_RECT, Size(2 * (reach - gap) + 1,
                                                                 2 * (reach - gap) + 1)));
    const int kBins = 28;
    int h_in[kBins] = { 0 }, h_out[kBins] = { 0 };
    int n_in = 0, n_out = 0;
    const int step = p.sample_step;
    for (int y = 0; y < hsv_s.rows; y += step)
    {
        const uchar* hs = hsv_s.ptr<uchar>(y);
        const uchar* st = state.ptr<uchar>(y);
        const uchar* o = outer.ptr<uchar>(y);
        const uchar* in = inner.ptr<uchar>(y);
        for (int x = 0; x < hsv_s.cols; x += step)
        {
            if (st[x] == 1 || st[x] == 2)
            {
                ++h_in[regionBin(hs + 3 * x, min_s, min_v)];
                ++n_in;
            }
            else if (o[x] && !in[x])
            {
                ++h_out[regionBin(hs + 3 * x, min_s, min_v)];
                ++n_out;
            }
        }
    }
    if (n_in == 0 || n_out == 0)
    {
        m.region_score = 0;
        return;
    }
    double tv = 0;
    for (int b = 0; b < kBins; ++b)
        tv += std::abs(h_in[b] / (double)n_in - h_out[b] / (double)n_out);
    m.region_score = 0.5 * tv;
}

// The part of a drawing that its scores read: the mask's bounding box and `pad` pixels around it
// (the ring of scoreRegion, the neighbourhoods of the contour and the blur), within the drawing's
// crop, its corner on the sampling grid of `step` (the samples stay where they were). Every
// filter and scan of the scores then gives there what it gives on the whole crop, where the mask
// is 0 beyond the pad: the same scores on about half the pixels.
static Rendered maskedPart(const Rendered& r, int pad, int step)
{
    Rect box = boundingRect(r.mask);
    box.x -= pad;
    box.y -= pad;
    box.width += 2 * pad;
    box.height += 2 * pad;
    box &= Rect(Point(), r.mask.size());
    const int x0 = box.x - box.x % step, y0 = box.y - box.y % step;
    box = Rect(Point(x0, y0), box.br());
    Rendered part = r;
    part.rect = box + r.rect.tl();
    part.face = r.face(box);
    part.depth = r.depth(box);
    part.mask = r.mask(box);
    return part;
}

static void scoreHypothesis(const Rendered& r, const Mat& scene_color, const Mat& scene_depth,
                            const EdgeMaps* maps, const VerificationParams& p, PoseMatch& m)
{
    const bool with_depth = !scene_depth.empty();
    Mat state, hsv_s, inner;
    cvtColor(scene_color(r.rect), hsv_s, COLOR_BGR2HSV);
    erode(r.mask, inner, Mat());
    const double raw_colour = scoreInterior(r, inner, hsv_s, scene_depth, p, state, m);
    scoreContour(r, inner, scene_color, maps, with_depth, raw_colour, state, p, m);
    scoreRegion(r, hsv_s, state, p, m);
    double wsum = p.w_similarity + p.w_color + p.w_edges + p.w_region;
    double v = p.w_similarity * m.similarity / 100.0 + p.w_color * m.color_score
        + p.w_edges * m.edge_score + p.w_region * m.region_score;
    if (with_depth)
    {
        wsum += p.w_depth;
        v += p.w_depth * m.depth_score;
    }
    m.verification = v / wsum;
}

// no evidence at all (the object is not in the image at this pose): the similarity's share only
static void noEvidence(const VerificationParams& p, bool with_depth, PoseMatch& m)
{
    m.color_score = m.edge_score = m.occlusion = m.region_score = 0;
    m.depth_score = with_depth ? 0 : -1;
    m.verification = p.w_similarity * m.similarity / 100.0
        / (p.w_similarity + p.w_color + p.w_edges + p.w_region + (with_depth ? p.w_depth : 0));
}

} // namespace

void verifyHypotheses(PoseEstimator& poses, const Mat& color, const Mat& depth, const Matx33d& K,
                      std::vector<PoseMatch>& matches, const VerificationParams& p,
                      const EdgeMaps* maps, DetectionStats* stats)
{
    checkVerificationParams(p);
    if (color.empty() || color.type() != CV_8UC3)
        CV_Error(Error::StsUnsupportedFormat, "forestmod::Detector::verify: color must be a "
                                              "non-empty CV_8UC3 BGR image");
    if (!depth.empty() && depth.type() != CV_16UC1)
        CV_Error_(Error::StsUnsupportedFormat, ("forestmod::Detector::verify: depth must be "
                                                "CV_16UC1 in mm, got %s",
                                                typeToString(depth.type()).c_str()));
    if (!depth.empty() && depth.size() != color.size())
        CV_Error_(Error::StsUnmatchedSizes, ("forestmod::Detector::verify: depth is %dx%d, color "
                                             "%dx%d", depth.cols, depth.rows, color.cols,
                                             color.rows));
    detail::checkIntrinsics(K, "forestmod::Detector::verify", "K");
    if (maps)
    {
        checkEdgeMaps(*maps, p.edge_params.orientations, color.size(),
                      "forestmod::Detector::verify");
        if (!(maps->max_distance >= p.edge_distance))
            CV_Error_(Error::StsBadArg, ("forestmod::Detector::verify: the edge maps are "
                                         "truncated at %g px, below params.edge_distance %g",
                                         maps->max_distance, p.edge_distance));
    }
    TickMeter tm;
    tm.start();
    for (size_t i = 0; i < matches.size(); ++i)
        matches[i].verification = matches[i].color_score = matches[i].edge_score
            = matches[i].depth_score = matches[i].occlusion = matches[i].region_score = -1;
    // 1. the first top_k hypotheses with a pose of each class whose mesh is known
    std::vector<size_t> todo;
    std::vector<const DrawnMesh*> meshes;
    std::map<String, int> per_class;
    for (size_t i = 0; i < matches.size(); ++i)
    {
        const PoseMatch& m = matches[i];
        if (!m.has_pose || per_class[m.class_id] >= p.top_k)
            continue;
        const DrawnMesh* mesh = poses.drawnMesh(m.class_id);
        if (!mesh)
            continue;
        checkPose(m.R, m.t, "forestmod::Detector::verify",
                  format("the pose of match %d (has_pose set)", (int)i).c_str());
        ++per_class[m.class_id];
        todo.push_back(i);
        meshes.push_back(mesh);
    }
    // 2. each drawn in its crop and scored against the scene there
    // (the pose stage's last drawing of a hypothesis when it is this one: same mesh (the one set
    // now), pose, camera and crop margin)
    const int margin = std::max(kDrawMargin, cvCeil(p.edge_distance) + 4);
    parallel_for_(Range(0, (int)todo.size()), [&](const Range& range) {
        for (int j = range.start; j < range.end; ++j)
        {
            PoseMatch& m = matches[todo[j]];
            const DrawnMesh& mesh = *meshes[j];
            Drawing own;
            const Drawing* d = m.drawing.get();
            if (!d || !d->isOf(mesh.id, K, m.R, m.t, color.size(), margin))
            {
                drawMesh(mesh.mesh, mesh.winding, K, m.R, m.t, color.size(), margin, own,
                         &mesh.clusters);
                d = &own;
            }
            Rendered r;
            r.rect = r.drawn = d->rect;
            r.face = d->face;
            r.depth = d->depth;
            r.mask = d->mask;
            r.face_hsv = &mesh.face_hsv;
            r.diameter = mesh.diameter;
            if (r.rect.area() == 0 || countNonZero(r.mask) == 0)
                noEvidence(p, !depth.empty(), m);
            else
            {
                // the ring's reach, and at least the 3 px of the contour's 7 x 7 neighbourhoods
                // and of the blur (5 x 5) under its Sobel
                const int pad = std::max(kRingGap + p.region_width, 3);
                scoreHypothesis(maskedPart(r, pad, p.sample_step), color, depth, maps, p, m);
            }
        }
    });
    // 3. verified hypotheses first, best first; the others after them in their order; the
    // drawings released
    std::vector<PoseMatch> verified, rest;
    for (size_t i = 0; i < matches.size(); ++i)
    {
        matches[i].drawing.release();
        (matches[i].verification >= 0 ? verified : rest).push_back(matches[i]);
    }
    std::stable_sort(verified.begin(), verified.end(),
                     [](const PoseMatch& a, const PoseMatch& b) {
                         return a.verification > b.verification;
                     });
    const int n_verified = (int)todo.size();
    verified.insert(verified.end(), rest.begin(), rest.end());
    matches.swap(verified);
    tm.stop();
    if (stats)
    {
        stats->t_verify_ms += tm.getTimeMilli();
        stats->verified += n_verified;
    }
}

} // namespace detail
} // namespace forestmod
} // namespace cv
