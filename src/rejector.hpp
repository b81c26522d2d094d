// This file is part of OpenCV project.
// It is subject to the license terms in the LICENSE file found in the top-level directory
// of this distribution and at http://opencv.org/license.html

// Preemptive background rejector (paper: "Preemptive Background Rejector"), internal.

#ifndef OPENCV_FORESTMOD_REJECTOR_HPP
#define OPENCV_FORESTMOD_REJECTOR_HPP

#include "opencv2/forestmod/forest.hpp"

#include <vector>

namespace cv {
namespace forestmod {
namespace detail {

/** A rejector as stored in a node: `count` dimensions, for each a look-up table of accepted
values (bits 0..7: labels, bit 8: the value 0), and the minimum number of accepted dimensions. */
struct RejectorRef
{
    const int* dims;
    const ushort* lut;
    int count;
    int min_accept;
};

/** Query side: true when the location passes (is not rejected). Stops as soon as the outcome is
known. */
static inline bool rejectorPasses(const RejectorRef& r, const LocationView& view)
{
    if (r.min_accept <= 0)
        return true;
    int accepted = 0;
    for (int k = 0; k < r.count; ++k)
    {
        const uchar s = view.value(r.dims[k]);
        const ushort m = r.lut[k];
        accepted += s ? ((m & s) != 0) : ((m >> 8) & 1);
        if (accepted >= r.min_accept)
            return true;
        if (accepted + (r.count - 1 - k) < r.min_accept)
            return false;
    }
    return accepted >= r.min_accept;
}

/** Training side of the rejector. */
class BackgroundRejectorTrainer
{
public:
    struct Config
    {
        int dims;        //!< maximum number of dimensions (K)
        float rho;       //!< LUT: value frequency among the foreground templates > rho
        float tau;       //!< reject when accepted share < tau
        float coverage;  //!< min share of templates with a label on the mask at a dimension
        float noise;     //!< share of corrupted values a template must survive
    };

    /** Learns the rejector of a node from its templates.
    @param codes N x D CV_8U training codes (0 = no feature, 1..8 = label + 1; off-mask values
                 already replaced by noise).
    @param fg    N x D CV_8U, nonzero on the object mask.
    @param ids   the node's templates (rows of codes), n of them.
    @param core  per template of ids: nonzero when the template's own crisp path passes the node
                 (it keeps a noise allowance); the others (fuzzy duplicates) only pass clean.
    Appends the chosen dims and LUTs to @p dims_out / @p lut_out; returns the count chosen (0: no
    rejector at this node) and sets @p min_accept (low enough that no core template is rejected,
    even with a share cfg.noise of its values corrupted, with probability 0.999) and @p lowered
    (whether it is below ceil(tau * count)). */
    static int train(const Mat& codes, const Mat& fg, const std::vector<int>& ids,
                     const std::vector<uchar>& core, const Config& cfg, std::vector<int>& dims_out, std::vector<ushort>& lut_out,
                     int& min_accept, bool& lowered);
};

/** The LUT bit of a training code (0..8). */
static inline ushort codeBit(int code)
{
    return (ushort)(code == 0 ? 256 : (1 << (code - 1)));
}

} // namespace detail
} // namespace forestmod
} // namespace cv

#endif // OPENCV_FORESTMOD_REJECTOR_HPP
