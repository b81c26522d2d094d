// This file is part of OpenCV project.
// It is subject to the license terms in the LICENSE file found in the top-level directory
// of this distribution and at http://opencv.org/license.html

#include "perf_precomp.hpp"

namespace opencv_test { namespace {

CV_ENUM(ModalityKind, 0, 1)
typedef tuple<ModalityKind, Size> QuantizeParams;
typedef TestBaseWithParam<QuantizeParams> Forestmod_Quantize;

// ColorHue (0) against LINEMOD's ColorGradient (1): process + quantize of one frame.
PERF_TEST_P(Forestmod_Quantize, hue_vs_gradient,
            Combine(ModalityKind::all(), Values(szVGA, sz720p)))
{
    const int kind = get<0>(GetParam());
    const Size size = get<1>(GetParam());
    Mat src(size, CV_8UC3);
    declare.in(src, WARMUP_RNG);
    Ptr<linemod::Modality> modality = kind == 0
        ? Ptr<linemod::Modality>(ColorHue::create())
        : linemod::Modality::create("ColorGradient");
    Mat quantized;
    TEST_CYCLE()
    {
        modality->process(src)->quantize(quantized);
    }
    ASSERT_EQ(size, quantized.size());
    ASSERT_EQ(CV_8U, quantized.type());
    SANITY_CHECK_NOTHING();
}

}} // namespace
