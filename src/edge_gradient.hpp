// This file is part of OpenCV project.
// It is subject to the license terms in the LICENSE file found in the top-level directory
// of this distribution and at http://opencv.org/license.html

// Internal: the gradient of the edge alignment (pose_edges.cpp) and of the verification's
// contour check (verification.cpp): LINEMOD's colour gradient and its orientation bin.

#ifndef OPENCV_FORESTMOD_EDGE_GRADIENT_HPP
#define OPENCV_FORESTMOD_EDGE_GRADIENT_HPP

#include "opencv2/core.hpp"

#include <cmath>

namespace cv {
namespace forestmod {
namespace detail {

/** Orientation bin (gradient direction modulo 180 degrees, `bins` bins) of a gradient. */
static inline int orientationBin(float dx, float dy, int bins)
{
    float a = std::atan2(dy, dx); // (-pi, pi]
    if (a < 0)
        a += (float)CV_PI;
    int b = (int)(a * bins / (float)CV_PI);
    return b >= bins ? b - bins : b;
}

/** Per pixel the 3x3 Sobel gradient (CV_32F) of the channel with the largest magnitude (the
first such channel). */
CV_EXPORTS void strongestGradient(const Mat& img, Mat& dx, Mat& dy);

/** The 3x3 Sobel derivatives of an 8-bit image at single pixels, integer-exact: what cv::Sobel
computes there on the image or on a ROI of it (the pixels around the ROI are read, the whole
image's own edge reflected as BORDER_REFLECT_101), for when a few pixels need them. */
class PointSobel
{
public:
    explicit PointSobel(const Mat& image) : img_(image), cn_(image.channels())
    {
        CV_Assert(image.depth() == CV_8U);
        img_.locateROI(whole_, ofs_);
    }
    /** derivatives of channel c at (x, y) */
    void at(int x, int y, int c, int& gx, int& gy) const
    {
        int v[3][3];
        const bool inside = x + ofs_.x >= 1 && y + ofs_.y >= 1 && x + ofs_.x + 1 < whole_.width
            && y + ofs_.y + 1 < whole_.height;
        for (int dy = -1; dy <= 1; ++dy)
            for (int dx = -1; dx <= 1; ++dx)
            {
                int xx = x + dx, yy = y + dy;
                if (!inside)
                {
                    xx = borderInterpolate(xx + ofs_.x, whole_.width, BORDER_REFLECT_101) - ofs_.x;
                    yy = borderInterpolate(yy + ofs_.y, whole_.height, BORDER_REFLECT_101)
                        - ofs_.y;
                }
                // a ROI's neighbours are its parent's pixels
                v[dy + 1][dx + 1]
                    = img_.data[(ptrdiff_t)yy * (ptrdiff_t)img_.step[0] + xx * cn_ + c];
            }
        gx = (v[0][2] - v[0][0]) + 2 * (v[1][2] - v[1][0]) + (v[2][2] - v[2][0]);
        gy = (v[2][0] - v[0][0]) + 2 * (v[2][1] - v[0][1]) + (v[2][2] - v[0][2]);
    }
    /** strongestGradient() at (x, y) */
    void strongest(int x, int y, int& gx, int& gy) const
    {
        int m = -1;
        for (int c = 0; c < cn_; ++c)
        {
            int cx, cy;
            at(x, y, c, cx, cy);
            if (cx * cx + cy * cy > m)
            {
                m = cx * cx + cy * cy;
                gx = cx;
                gy = cy;
            }
        }
    }

private:
    const Mat img_; // a header: the data is shared
    const int cn_;
    Size whole_;
    Point ofs_;
};

} // namespace detail
} // namespace forestmod
} // namespace cv

#endif
