// This file is part of OpenCV project.
// It is subject to the license terms in the LICENSE file found in the top-level directory
// of this distribution and at http://opencv.org/license.html

// The quantized hue modality (paper: "Hue" of the LINEMOD descriptor; LINEMOD ACCV 2012).

#include "precomp.hpp"
#include "params_io.hpp"

namespace cv {
namespace forestmod {

using linemod::Feature;
using linemod::QuantizedPyramid;
using linemod::Template;

int hueBin(int h)
{
    CV_CheckGE(h, 0, "hueBin: OpenCV 8-bit hue is in [0, 180)");
    CV_CheckLT(h, 180, "hueBin: OpenCV 8-bit hue is in [0, 180)");
    // bins centred on 22.5 * i: shift by half a bin, in units of 1/4 to stay in integers
    // (22.5 = 90/4, 11.25 = 45/4)
    return ((4 * h + 45) / 90) & 7;
}

void quantizeHue(InputArray _bgr, OutputArray _dst, int saturation_threshold, int value_threshold)
{
    Mat bgr = _bgr.getMat();
    if (bgr.empty())
        CV_Error(Error::StsBadArg, "quantizeHue: the image is empty");
    if (bgr.type() != CV_8UC3)
        CV_Error_(Error::StsUnsupportedFormat,
                  ("quantizeHue: expected a BGR image of type CV_8UC3, got %s",
                   typeToString(bgr.type()).c_str()));
    if (saturation_threshold < 0 || saturation_threshold > 255 || value_threshold < 0
        || value_threshold > 255)
        CV_Error_(Error::StsOutOfRange, ("quantizeHue: saturation_threshold %d and "
                                         "value_threshold %d must be in [0, 255] (8-bit HSV)",
                                         saturation_threshold, value_threshold));

    uchar lut[256];
    for (int h = 0; h < 256; ++h)
        lut[h] = h < 180 ? static_cast<uchar>(1 << hueBin(h)) : 0;

    Mat hsv;
    cvtColor(bgr, hsv, COLOR_BGR2HSV);
    _dst.create(bgr.size(), CV_8UC1);
    Mat dst = _dst.getMat();
    const int smin = saturation_threshold, vmin = value_threshold;
    parallel_for_(Range(0, hsv.rows), [&](const Range& rows) {
        for (int r = rows.start; r < rows.end; ++r)
        {
            const uchar* p = hsv.ptr<uchar>(r);
            uchar* q = dst.ptr<uchar>(r);
            for (int c = 0; c < hsv.cols; ++c, p += 3)
                q[c] = (p[1] >= smin && p[2] >= vmin) ? lut[p[0]] : 0;
        }
    });
}

ColorHue::Params::Params()
    : saturation_threshold(50), feature_saturation_threshold(70), min_feature_area(0.1f),
      value_threshold(40), num_features(63), blur_size(3), mask_erosion(2)
{
}

void ColorHue::Params::read(const FileNode& fn)
{
    detail::readField(fn, "saturation_threshold", saturation_threshold);
    detail::readField(fn, "feature_saturation_threshold", feature_saturation_threshold);
    detail::readField(fn, "min_feature_area", min_feature_area);
    detail::readField(fn, "value_threshold", value_threshold);
    detail::readField(fn, "num_features", num_features);
    detail::readField(fn, "blur_size", blur_size);
    detail::readField(fn, "mask_erosion", mask_erosion);
}

void ColorHue::Params::write(FileStorage& fs) const
{
    fs << "saturation_threshold" << saturation_threshold;
    fs << "feature_saturation_threshold" << feature_saturation_threshold;
    fs << "min_feature_area" << min_feature_area;
    fs << "value_threshold" << value_threshold;
    fs << "num_features" << num_features;
    fs << "blur_size" << blur_size;
    fs << "mask_erosion" << mask_erosion;
}

static void checkParams(const ColorHue::Params& p)
{
    CV_CheckGE(p.saturation_threshold, 0, "ColorHue: saturation_threshold must be in [0, 255]");
    CV_CheckLE(p.saturation_threshold, 255, "ColorHue: saturation_threshold must be in [0, 255]");
    CV_CheckGE(p.feature_saturation_threshold, 0,
               "ColorHue: feature_saturation_threshold must be in [0, 255]");
    CV_CheckLE(p.feature_saturation_threshold, 255,
               "ColorHue: feature_saturation_threshold must be in [0, 255]");
    CV_Check(p.min_feature_area, p.min_feature_area >= 0.f && p.min_feature_area <= 1.f,
             "ColorHue: min_feature_area must be in [0, 1]");
    CV_CheckGE(p.value_threshold, 0, "ColorHue: value_threshold must be in [0, 255]");
    CV_CheckLE(p.value_threshold, 255, "ColorHue: value_threshold must be in [0, 255]");
    CV_CheckGT(p.num_features, 0, "ColorHue: num_features must be positive");
    CV_CheckGE(p.blur_size, 0, "ColorHue: blur_size must be 0 (none) or an odd size");
    CV_Check(p.blur_size, p.blur_size <= 1 || (p.blur_size & 1) == 1,
             "ColorHue: blur_size must be 0 (none) or an odd size");
    CV_CheckGE(p.mask_erosion, 0, "ColorHue: mask_erosion must not be negative");
}

namespace {

/** Quantized hue of one image and its pyramid; the QuantizedPyramid of ColorHue. */
class HuePyramid CV_FINAL : public QuantizedPyramid
{
public:
    HuePyramid(const Mat& src, const Mat& mask, const ColorHue::Params& params)
        : src_(src), mask_(mask), params_(params), pyramid_level_(0)
    {
        update();
    }

    void quantize(Mat& dst) const CV_OVERRIDE
    {
        dst = Mat::zeros(quantized_.size(), CV_8U);
        quantized_.copyTo(dst, mask_);
    }

    bool extractTemplate(Template& templ) const CV_OVERRIDE;

    void pyrDown() CV_OVERRIDE
    {
        Size size(src_.cols / 2, src_.rows / 2);
        Mat down;
        cv::pyrDown(src_, down, size);
        src_ = down;
        if (!mask_.empty())
        {
            Mat m;
            resize(mask_, m, size, 0.0, 0.0, INTER_NEAREST);
            mask_ = m;
        }
        ++pyramid_level_;
        update();
    }

private:
    void update()
    {
        // a new buffer: `smoothed = src_` would share the caller's pixels and blur them in place
        Mat smoothed;
        if (params_.blur_size > 1)
            GaussianBlur(src_, smoothed, Size(params_.blur_size, params_.blur_size), 0, 0,
                         BORDER_REPLICATE);
        else
            smoothed = src_;
        quantizeHue(smoothed, quantized_, params_.saturation_threshold, params_.value_threshold);
        Mat hsv;
        cvtColor(smoothed, hsv, COLOR_BGR2HSV);
        extractChannel(hsv, saturation_, 1);
    }

    Mat src_, mask_;
    ColorHue::Params params_;
    int pyramid_level_;
    Mat quantized_;  // 1 << bin, or 0
    Mat saturation_; // feature score: a more saturated pixel has a more reliable hue
};

static int bitToBin(uchar bit)
{
    int bin = 0;
    while (bit > 1)
    {
        bit >>= 1;
        ++bin;
    }
    return bin;
}

bool HuePyramid::extractTemplate(Template& templ) const
{
    // Hue is a region property: take features inside the object, away from its silhouette where
    // object and background colours mix.
    Mat local_mask;
    if (!mask_.empty())
    {
        if (params_.mask_erosion > 0)
            erode(mask_, local_mask, Mat(), Point(-1, -1), params_.mask_erosion,
                  BORDER_CONSTANT, Scalar(0));
        else
            local_mask = mask_;
    }

    // a labelled pixel has saturation >= saturation_threshold; a feature needs the stronger one
    const int s_min = params_.feature_saturation_threshold;
    std::vector<Candidate> candidates;
    size_t area = 0;
    for (int r = 0; r < quantized_.rows; ++r)
    {
        const uchar* q = quantized_.ptr<uchar>(r);
        const uchar* s = saturation_.ptr<uchar>(r);
        const uchar* m = local_mask.empty() ? 0 : local_mask.ptr<uchar>(r);
        for (int c = 0; c < quantized_.cols; ++c)
        {
            if (m && !m[c])
                continue;
            ++area;
            if (q[c] && s[c] >= s_min)
                candidates.push_back(Candidate(c, r, bitToBin(q[c]), static_cast<float>(s[c])));
        }
    }
    templ.features.clear();
    templ.width = -1; // size is set by the detector, shared by all modalities
    templ.height = -1;
    templ.pyramid_level = pyramid_level_;
    // Like ColorGradient, refuse a template without usable features (addTemplate returns -1); a
    // few coloured spots on a colourless object are not its colour either.
    if (candidates.empty() || candidates.size() < params_.min_feature_area * area)
        return false;

    std::stable_sort(candidates.begin(), candidates.end());
    const size_t n = std::min(static_cast<size_t>(params_.num_features), candidates.size());
    // Candidates fill an area (not a contour as for gradients): start from the spacing of n points
    // spread evenly over it; selectScatteredFeatures relaxes it until n are chosen.
    float distance = std::sqrt(static_cast<float>(candidates.size()) / n) + 1.f;
    selectScatteredFeatures(candidates, templ.features, n, distance);
    return true;
}

} // namespace

ColorHue::ColorHue() {}

ColorHue::ColorHue(const Params& params) : params_(params)
{
    checkParams(params_);
}

Ptr<ColorHue> ColorHue::create(const Params& params)
{
    return makePtr<ColorHue>(params);
}

String ColorHue::name() const
{
    return "ColorHue";
}

void ColorHue::setParams(const Params& params)
{
    checkParams(params);
    params_ = params;
}

void ColorHue::read(const FileNode& fn)
{
    if (fn.empty() || !fn.isMap())
        CV_Error(Error::StsParseError, "ColorHue::read: expected a map node");
    String type = fn["type"];
    if (type != name())
        CV_Error_(Error::StsParseError,
                  ("ColorHue::read: node is of modality '%s', not 'ColorHue'", type.c_str()));
    Params p = params_;
    p.read(fn);
    setParams(p);
}

void ColorHue::write(FileStorage& fs) const
{
    fs << "type" << name();
    params_.write(fs);
}

Ptr<QuantizedPyramid> ColorHue::processImpl(const Mat& src, const Mat& mask) const
{
    if (src.empty())
        CV_Error(Error::StsBadArg, "ColorHue: the source image is empty");
    if (src.type() != CV_8UC3)
        CV_Error_(Error::StsUnsupportedFormat,
                  ("ColorHue: expected a BGR image of type CV_8UC3, got %s",
                   typeToString(src.type()).c_str()));
    if (!mask.empty())
    {
        if (mask.type() != CV_8UC1)
            CV_Error_(Error::StsUnsupportedFormat,
                      ("ColorHue: the mask must be CV_8UC1, got %s",
                       typeToString(mask.type()).c_str()));
        if (mask.size() != src.size())
            CV_Error_(Error::StsUnmatchedSizes,
                      ("ColorHue: mask is %dx%d, image is %dx%d", mask.cols, mask.rows, src.cols,
                       src.rows));
    }
    return makePtr<HuePyramid>(src, mask, params_);
}

} // namespace forestmod
} // namespace cv
