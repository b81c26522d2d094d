// This file is part of OpenCV project.
// It is subject to the license terms in the LICENSE file found in the top-level directory
// of this distribution and at http://opencv.org/license.html

#include "precomp.hpp"
#include "nms.hpp"

#include "opencv2/core/hal/intrin.hpp"

#include <climits>

namespace cv {
namespace forestmod {
namespace detail {

// A cell's kept boxes for suppressOverlaps, in blocks of 8 boxes stored field by field: 8
// indices, then 8 doubled centres x, 8 y, 8 bounds x, 8 bounds y.
enum
{
    KEPT_INDEX = 0,
    KEPT_CX,
    KEPT_CY,
    KEPT_BX,
    KEPT_BY,
    KEPT_FIELDS,
    KEPT_BLOCK = 8 * KEPT_FIELDS
};

// An unused slot: index INT_MAX (after every box), a centre no box's bound reaches (centres and
// bounds are image coordinates, far below 2^28), bounds 0.
static const int kFar = 1 << 28;
static const int kUnusedSlots[KEPT_BLOCK] = {
    INT_MAX, INT_MAX, INT_MAX, INT_MAX, INT_MAX, INT_MAX, INT_MAX, INT_MAX,
    kFar, kFar, kFar, kFar, kFar, kFar, kFar, kFar,
    kFar, kFar, kFar, kFar, kFar, kFar, kFar, kFar,
    0, 0, 0, 0, 0, 0, 0, 0,
    0, 0, 0, 0, 0, 0, 0, 0
};

// Bit k set when kept box k of block `b` lies within the centres' bound of box `me` (its fields
// as a block's): |dcx| <= max(bounds x) and |dcy| <= max(bounds y).
static inline unsigned nearKept(const int* b, const int* me)
{
#if CV_SIMD128
    const v_int32x4 cx = v_setall_s32(me[KEPT_CX]), cy = v_setall_s32(me[KEPT_CY]);
    const v_int32x4 bx = v_setall_s32(me[KEPT_BX]), by = v_setall_s32(me[KEPT_BY]);
    unsigned pass = 0;
    for (int h = 0; h < 8; h += 4)
    {
        const v_int32x4 dx = v_reinterpret_as_s32(v_abs(cx - v_load(b + KEPT_CX * 8 + h)));
        const v_int32x4 dy = v_reinterpret_as_s32(v_abs(cy - v_load(b + KEPT_CY * 8 + h)));
        const v_int32x4 ok = (dx <= v_max(bx, v_load(b + KEPT_BX * 8 + h)))
            & (dy <= v_max(by, v_load(b + KEPT_BY * 8 + h)));
        pass |= (unsigned)v_signmask(ok) << h;
    }
    return pass;
#else
    unsigned pass = 0;
    for (int k = 0; k < 8; ++k)
        pass |= (unsigned)((std::abs(me[KEPT_CX] - b[KEPT_CX * 8 + k])
                            <= std::max(me[KEPT_BX], b[KEPT_BX * 8 + k]))
                           & (std::abs(me[KEPT_CY] - b[KEPT_CY * 8 + k])
                              <= std::max(me[KEPT_BY], b[KEPT_BY * 8 + k])))
            << k;
    return pass;
#endif
}

void suppressOverlaps(const std::vector<Rect>& boxes, float iou, std::vector<int>& leader)
{
    CV_Assert(iou > 0.f && iou < 1.f);
    const int n = static_cast<int>(boxes.size());
    leader.assign(n, -1);
    if (n == 0)
        return;
    // IoU(a, b) > iou needs an overlap wider than iou x max(a.width, b.width) (the union is at
    // least max(w) x min(h), the intersection at most overlap x min(h)), so the centres lie less
    // than (1 - iou) x max(w) apart in x (likewise in y). The kept boxes go into a grid of cells
    // of that size by their centre (doubled: integers), and a box is compared only with the kept
    // boxes of the 3 x 3 cells around its centre's, each once. A cell's boxes ascend: the first
    // one that overlaps enough is the lowest index, the same leader as comparing with every kept
    // box in order.
    int x0 = INT_MAX, y0 = INT_MAX, x1 = INT_MIN, y1 = INT_MIN, max_w = 1, max_h = 1;
    for (int i = 0; i < n; ++i)
    {
        const Rect& a = boxes[i];
        x0 = std::min(x0, 2 * a.x + a.width);
        x1 = std::max(x1, 2 * a.x + a.width);
        y0 = std::min(y0, 2 * a.y + a.height);
        y1 = std::max(y1, 2 * a.y + a.height);
        max_w = std::max(max_w, a.width);
        max_h = std::max(max_h, a.height);
    }
    int cw = 2 * std::max(1, cvCeil((1.0 - iou) * max_w));
    int ch = 2 * std::max(1, cvCeil((1.0 - iou) * max_h));
    // larger cells hold more boxes but keep the bound: at most about 4 cells per box (small boxes
    // spread over a large range, or a high iou, would ask for millions)
    while ((int64)((x1 - x0) / cw + 1) * ((y1 - y0) / ch + 1) > std::max(64, 4 * n))
    {
        cw *= 2;
        ch *= 2;
    }
    const int gx = (x1 - x0) / cw + 1, gy = (y1 - y0) / ch + 1;
    // the kept boxes of a cell in blocks of 8, field by field (KEPT_*): index, doubled centre,
    // and the centres' bounds for its width and height, floor(reach x side + 1) (the bound for
    // two boxes is the larger of their two); a block's unused slots fail every bound; count: the
    // boxes kept in each cell (the slot of the next one in its last block)
    std::vector<std::vector<int> > grid((size_t)gx * gy);
    std::vector<int> count((size_t)gx * gy, 0);
    const double reach = 2.0 * (1.0 - iou);
    for (int i = 0; i < n; ++i)
    {
        const Rect& a = boxes[i];
        const int me[KEPT_FIELDS] = { i, 2 * a.x + a.width, 2 * a.y + a.height,
                                      (int)std::floor(reach * a.width + 1),
                                      (int)std::floor(reach * a.height + 1) };
        const int cx = (me[KEPT_CX] - x0) / cw, cy = (me[KEPT_CY] - y0) / ch;
        // its own cell first (a leader found there cuts the others short), then the 8 around
        int cells[9], n_cells = 0;
        cells[n_cells++] = cy * gx + cx;
        for (int y = std::max(cy - 1, 0); y <= std::min(cy + 1, gy - 1); ++y)
            for (int x = std::max(cx - 1, 0); x <= std::min(cx + 1, gx - 1); ++x)
                if (x != cx || y != cy)
                    cells[n_cells++] = y * gx + x;
        for (int c = 0; c < n_cells; ++c)
        {
            const std::vector<int>& kept = grid[(size_t)cells[c]];
            const int blocks = static_cast<int>(kept.size()) / KEPT_BLOCK;
            // the centres' bound of a block's 8 kept boxes at once (most kept boxes nearby fail
            // it), then the overlaps of those that pass, in order
            bool found = false;
            for (int k = 0; k < blocks && !found; ++k)
            {
                const int* b = &kept[(size_t)k * KEPT_BLOCK];
                if (leader[i] >= 0 && b[KEPT_INDEX * 8] > leader[i])
                    break;
                const unsigned pass = nearKept(b, me);
                for (int bit = 0; (pass >> bit) && !found; ++bit)
                {
                    if (!((pass >> bit) & 1u))
                        continue;
                    const int j = b[KEPT_INDEX * 8 + bit];
                    if (leader[i] >= 0 && j > leader[i])
                        break;
                    const Rect& o = boxes[j];
                    const double inter = (a & o).area();
                    const double uni = a.area() + o.area() - inter;
                    if (uni > 0 && inter / uni > iou)
                    {
                        leader[i] = j;
                        found = true;
                    }
                }
            }
        }
        if (leader[i] < 0)
        {
            const size_t cell = (size_t)cy * gx + cx;
            std::vector<int>& kept = grid[cell];
            const int slot = count[cell]++ % 8;
            if (slot == 0)
                kept.insert(kept.end(), kUnusedSlots, kUnusedSlots + KEPT_BLOCK);
            int* b = &kept[kept.size() - KEPT_BLOCK];
            for (int f = 0; f < KEPT_FIELDS; ++f)
                b[f * 8 + slot] = me[f];
        }
    }
}

void nonMaximumSuppression(const std::vector<cv::linemod::Match>& matches,
                           const TemplateStore& store, float iou, std::vector<int>& leader)
{
    // the sizes of the classes met so far (a model has few), looked up once each: a map look-up
    // and a read of each template's own heap block per match had taken 0.9 % of the 8-object
    // model's match() samples, against 3.3 % for suppressOverlaps (doc/detector.md)
    std::vector<std::pair<const String*, const std::vector<Size>*> > seen;
    std::vector<Rect> boxes(matches.size());
    for (size_t i = 0; i < matches.size(); ++i)
    {
        const cv::linemod::Match& m = matches[i];
        const std::vector<Size>* sizes = 0;
        for (size_t c = 0; c < seen.size() && !sizes; ++c)
            if (*seen[c].first == m.class_id)
                sizes = seen[c].second;
        if (!sizes)
        {
            sizes = store.classSizes(m.class_id);
            if (!sizes)
                CV_Error_(Error::StsBadArg, ("forestmod::Detector: a match of class '%s', which "
                                             "the detector does not hold", m.class_id.c_str()));
            seen.push_back(std::make_pair(&m.class_id, sizes));
        }
        if (m.template_id < 0 || m.template_id >= (int)sizes->size())
            CV_Error_(Error::StsBadArg, ("forestmod::Detector: no template %d of class '%s'",
                                         m.template_id, m.class_id.c_str()));
        const Size& s = (*sizes)[m.template_id];
        boxes[i] = Rect(m.x, m.y, std::max(1, s.width), std::max(1, s.height));
    }
    suppressOverlaps(boxes, iou, leader);
}

void keepLeaders(std::vector<cv::linemod::Match>& matches, const std::vector<int>& leader)
{
    size_t n = 0;
    for (size_t i = 0; i < matches.size(); ++i)
        if (leader[i] < 0)
            matches[n++] = matches[i];
    matches.resize(n);
}

} // namespace detail
} // namespace forestmod
} // namespace cv
