// This file is part of OpenCV project.
// It is subject to the license terms in the LICENSE file found in the top-level directory
// of this distribution and at http://opencv.org/license.html

#ifndef OPENCV_FORESTMOD_HUE_HPP
#define OPENCV_FORESTMOD_HUE_HPP

#include "opencv2/core.hpp"
#include "opencv2/rgbd/linemod.hpp"

namespace cv {
namespace forestmod {

//! @addtogroup forestmod_hue
//! @{

/** @brief Quantized hue: the third modality of the paper (LINEMOD's colour cue, ACCV 2012).

Hue (OpenCV HSV, 0..180 for 8-bit images) is quantized into 8 bins of 22.5 (45 degrees of the
colour circle). The bins are centred on the hues 0, 22.5, 45, ... so that red, which straddles
0/180, falls into one bin (bin 0). A pixel whose saturation or value is below its threshold has no
reliable hue and gets no label (quantized value 0).

As the other LINEMOD modalities, the quantized image holds one bit per pixel, `1 << bin`, and
cv::linemod::Feature::label is the bin (0..7). The hue circle is circular like LINEMOD's
orientation circle, so the similarity of cv::linemod (4 for the same bin, 3 for a neighbour, ...,
0 for the opposite colour) applies as it is: ColorHue works inside a plain cv::linemod::Detector.
A template of an object without reliable hue (white, grey, black) has no hue features:
extractTemplate() returns false, so cv::linemod::Detector refuses it (as ColorGradient refuses a
template with too few gradients); forestmod::Detector learns it from its other modalities.
Note that cv::linemod::Modality::create(const FileNode&) only knows LINEMOD's own modalities, so
cv::linemod::Detector::read() cannot restore a ColorHue; cv::forestmod's own I/O can.
*/
class CV_EXPORTS_W ColorHue : public cv::linemod::Modality
{
public:
    /** @brief Parameters of the hue modality. FileStorage keys are the field names. */
    struct CV_EXPORTS_W_SIMPLE Params
    {
        CV_WRAP Params();

        /** Minimum saturation (0..255) for a pixel to have a hue. Default 50 (about 20 %):
        the hue of a pixel with saturation S is uncertain by roughly (noise / S), so with the
        usual 2-4 grey levels of colour noise, hue below S = 50 wanders by more than half a bin.
        Greys, white and black have no hue at all. */
        CV_PROP_RW int saturation_threshold;
        /** Minimum saturation of a template pixel to become a hue feature (the scene keeps
        saturation_threshold), as ColorGradient's strong and weak thresholds. Default 70: drawn
        at LM-O's ground-truth poses, the driller's mesh colours of saturation 50-69 fall into
        the real frame's hue bin at 21 % of its pixels (the next bin at 65 %), those from 70 on
        at 72-99 % for every object (doc/detector.md, "Hue features of pale colours"). 0 or
        saturation_threshold: every labelled pixel. */
        CV_PROP_RW int feature_saturation_threshold;
        /** Smallest share of the eroded object mask that those pixels must cover for a template
        to have hue features at all. Default 0.1: drawn at LM-O's ground-truth poses, those of
        the driller cover 1.2 % of it and the glue's 2.9 % (coloured spots on colourless
        objects), those of the ape, cat, duck and holepuncher 99-100 %. 0: any. */
        CV_PROP_RW float min_feature_area;
        /** Minimum value V = max(R,G,B) (0..255). Default 40: in dark pixels the channel
        differences that define hue are within sensor noise. */
        CV_PROP_RW int value_threshold;
        /** Number of features extracted per template, as cv::linemod::ColorGradient (63 keeps
        a cv::linemod::Detector's 8-bit accumulation exact). */
        CV_PROP_RW int num_features;
        /** Side of the Gaussian kernel applied to the image before quantization; 0 or 1 = none.
        Default 3: removes pixel noise of colour cameras while keeping region borders (the
        gradient modality uses 7 because it differentiates). */
        CV_PROP_RW int blur_size;
        /** Erosion (pixels) of the object mask before features are chosen: pixels on the
        silhouette mix object and background colours. Default 2. */
        CV_PROP_RW int mask_erosion;

        void read(const FileNode& fn);
        void write(FileStorage& fs) const;
    };

    ColorHue();
    explicit ColorHue(const Params& params);

    CV_WRAP static Ptr<ColorHue> create(const Params& params = Params());

    /** @brief "ColorHue". */
    CV_WRAP virtual String name() const CV_OVERRIDE;
    CV_WRAP virtual void read(const FileNode& fn) CV_OVERRIDE;
    virtual void write(FileStorage& fs) const CV_OVERRIDE;

    CV_WRAP const Params& getParams() const { return params_; }
    CV_WRAP void setParams(const Params& params);

protected:
    virtual Ptr<cv::linemod::QuantizedPyramid> processImpl(const Mat& src,
                                                           const Mat& mask) const CV_OVERRIDE;

private:
    Params params_;
};

/** @brief The hue bin (0..7) of an OpenCV 8-bit hue value h in [0, 180).

Bin i covers [22.5 i - 11.25, 22.5 i + 11.25) modulo 180.
*/
CV_EXPORTS_W int hueBin(int h);

/** @brief Quantizes the hue of a BGR 8-bit image.

@param bgr    CV_8UC3 BGR image.
@param dst    CV_8UC1, `1 << hueBin(h)` where saturation >= saturation_threshold and
              value >= value_threshold, else 0.
@param saturation_threshold see ColorHue::Params.
@param value_threshold      see ColorHue::Params.
*/
CV_EXPORTS_W void quantizeHue(InputArray bgr, OutputArray dst,
                              int saturation_threshold = 50, int value_threshold = 40);

//! @}

} // namespace forestmod
} // namespace cv

#endif // OPENCV_FORESTMOD_HUE_HPP
