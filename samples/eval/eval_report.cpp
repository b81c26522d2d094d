// This file is part of OpenCV project.
// It is subject to the license terms in the LICENSE file found in the top-level directory
// of this distribution and at http://opencv.org/license.html

// forestmod_eval: markdown rows, JSON (cv::FileStorage), heat maps and plots (plain cv:: drawing:
// log-log axes, several curves and a legend, which cv::plot::Plot2d does not draw).

#include "eval_common.hpp"

#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cmath>
#include <limits>

namespace fmeval {

std::string num(double v, const char* fmt)
{
    return cvIsNaN(v) || cvIsInf(v) ? std::string("-") : cv::format(fmt, v);
}

std::string pct(double v)
{
    return cvIsNaN(v) ? std::string("-") : cv::format("%.1f %%", 100 * v);
}

std::string mdRow(const std::string& name, const std::string& det, int templates,
                  const Result& r)
{
    return cv::format("| %s | %s | %d | %s | %s | %s | %s | %s | %s | %s | %s | %s | %s |\n",
                      name.c_str(), det.c_str(), templates, num(tTree(r)).c_str(),
                      num(tValid(r)).c_str(), num(tQuant(r)).c_str(), num(tTotal(r)).c_str(),
                      pct(ratio(r.ok2d, r.n2d)).c_str(), pct(ratio(r.okproj, r.n2d)).c_str(),
                      pct(ratio(r.ok2d_at10, r.n2d)).c_str(),
                      pct(ratio(r.okproj_at10, r.n2d)).c_str(), pct(addRate(r)).c_str(),
                      pct(rejectedFraction(r)).c_str());
}

std::string meanRow(const std::string& det, const std::vector<Result>& rs)
{
    double tree = 0, valid = 0, quant = 0, total = 0;
    int64 locations = 0, rejected = 0;
    for (size_t o = 0; o < rs.size(); ++o)
    {
        tree += tTree(rs[o]);
        valid += tValid(rs[o]);
        quant += tQuant(rs[o]);
        total += tTotal(rs[o]);
        locations += rs[o].locations;
        rejected += rs[o].rejected;
    }
    const double n = (double)rs.size();
    const Result p = pooled(rs);
    const double rej = p.has_forest && locations > 0 ? double(rejected) / locations
                                                     : std::numeric_limits<double>::quiet_NaN();
    return cv::format("| **mean** | %s | - | %s | %s | %s | %s | %s | %s | %s | %s | %s | %s |\n",
                      det.c_str(), num(tree / n).c_str(), num(valid / n).c_str(),
                      num(quant / n).c_str(), num(total / n).c_str(),
                      pct(ratio(p.ok2d, p.n2d)).c_str(), pct(ratio(p.okproj, p.n2d)).c_str(),
                      pct(ratio(p.ok2d_at10, p.n2d)).c_str(),
                      pct(ratio(p.okproj_at10, p.n2d)).c_str(), pct(addRate(p)).c_str(),
                      pct(rej).c_str());
}

void writeNumber(cv::FileStorage& fs, const std::string& key, double v)
{
    if (cvIsNaN(v) || cvIsInf(v))
        fs << key << "n/a";
    else
        fs << key << v;
}

void writeResult(cv::FileStorage& fs, const std::string& key, const Result& r, bool per_frame)
{
    fs << key << "{";
    writeNumber(fs, "t_total_ms", tTotal(r));
    writeNumber(fs, "t_tree_ms", tTree(r));
    writeNumber(fs, "t_valid_ms", tValid(r));
    writeNumber(fs, "recall_2d", ratio(r.ok2d, r.n2d));
    writeNumber(fs, "proj2d_5px", ratio(r.okproj, r.n2d));
    // recall@k: any of the first k hypotheses (k = --verify_k, default 10)
    writeNumber(fs, "recall_2d_at10", ratio(r.ok2d_at10, r.n2d));
    writeNumber(fs, "proj2d_5px_at10", ratio(r.okproj_at10, r.n2d));
    if (!r.verify.empty()) // verified rows: the verification stage alone, median ms per frame
        writeNumber(fs, "t_verify_ms", median(r.verify));
    if (!r.verify_per10.empty()) // the same per 10 hypotheses (a second round verifies up to 20)
        writeNumber(fs, "t_verify_per10_ms", median(r.verify_per10));
    if (!r.background.empty()) // verified rows: the background similarity, median ms per frame
        writeNumber(fs, "t_background_ms", median(r.background));
    if (!r.pose.empty()) // plain rows: the hypotheses' poses, median ms per frame
        writeNumber(fs, "t_pose_ms", median(r.pose));
    writeNumber(fs, "add_01d", addRate(r));
    writeNumber(fs, "rejected_fraction", rejectedFraction(r));
    // forestmod: DetectionStats::t_quantize_ms (modalities, spreading, response maps);
    // cv::linemod: its modalities' process + pyrDown + quantize, timed apart on the same frame
    writeNumber(fs, "t_quant_ms", tQuant(r));
    // the rest of the call: NMS, bookkeeping (forestmod), spreading, response maps, similarity
    // and refinement (cv::linemod); T_refine is part of T_valid in forestmod's DetectionStats
    std::vector<double> other;
    for (size_t i = 0; i < r.total.size(); ++i)
        other.push_back(r.total[i] - (i < r.quant.size() ? r.quant[i] : 0)
                        - (r.has_forest && i < r.tree.size() ? r.tree[i] + r.valid[i] : 0));
    writeNumber(fs, "t_other_ms", median(other));
    fs << "t_total_spread" << "{";
    writeNumber(fs, "min", quantile(r.total, 0));
    writeNumber(fs, "q25", quantile(r.total, 0.25));
    writeNumber(fs, "median", quantile(r.total, 0.5));
    writeNumber(fs, "q75", quantile(r.total, 0.75));
    writeNumber(fs, "max", quantile(r.total, 1));
    fs << "}";
    fs << "frames" << (int)r.total.size();
    if (per_frame)
    {
        // the frames one by one: time, the scored hypothesis, its box IoU, projection error and
        // ADD/ADI (in diameters), "n/a" where not measured; "top": the class's best matches as
        // the detector returned them, [template_id, x, y, similarity]
        fs << "per_frame" << "[";
        for (size_t i = 0; i < r.per_frame.size(); ++i)
        {
            const FrameRecord& f = r.per_frame[i];
            fs << "{";
            fs << "scene_id" << f.scene_id << "im_id" << f.im_id;
            writeNumber(fs, "t_ms", f.t_ms);
            fs << "template_id" << f.template_id;
            fs << "similarity" << (double)f.similarity;
            fs << "x" << f.pos.x << "y" << f.pos.y;
            writeNumber(fs, "iou", f.iou);
            writeNumber(fs, "proj2d_px", f.proj);
            writeNumber(fs, "add_d", f.add);
            writeNumber(fs, "verification", f.verification);
            writeNumber(fs, "correct_similarity", f.correct_similarity);
            writeNumber(fs, "off_similarity", f.off_similarity);
            writeNumber(fs, "gt_similarity", f.gt_similarity);
            fs << "top" << "[";
            for (size_t k = 0; k < f.top.size(); ++k)
                fs << "[:" << f.top[k].template_id << f.top[k].x << f.top[k].y
                   << (double)f.top[k].similarity << "]";
            fs << "]";
            if (!f.hyps.empty())
            {
                // verified rows: [similarity, color, edges, depth, occlusion, iou, proj_px,
                // region, background] of every hypothesis, in the verification's order
                fs << "hypotheses" << "[";
                for (size_t k = 0; k < f.hyps.size(); ++k)
                {
                    fs << "[:";
                    for (int j = 0; j < 9; ++j)
                    {
                        const double v = f.hyps[k][j];
                        if (cvIsNaN(v) || cvIsInf(v))
                            fs << "n/a";
                        else
                            fs << v;
                    }
                    fs << "]";
                }
                fs << "]";
            }
            fs << "}";
        }
        fs << "]";
    }
    fs << "}";
}

// ---------------------------------------------------------------------------------------------
// heat map of the rejection depth (the paper's last figure)

cv::Mat heatmapImage(const cv::Mat& frame, const cv::Mat& map, int max_depth)
{
    cv::Mat dim;
    frame.convertTo(dim, -1, 0.5);
    cv::Mat over = dim.clone();
    const double cell = double(frame.cols) / map.cols;
    const int w = std::max(1, cvRound(cell));
    const int D = std::max(1, max_depth);
    cv::Mat lut(1, 256, CV_8UC1);
    for (int i = 0; i < 256; ++i)
        lut.at<uchar>(i) = (uchar)i;
    cv::Mat colors;
    cv::applyColorMap(lut, colors, cv::COLORMAP_JET);
    for (int r = 0; r < map.rows; ++r)
        for (int c = 0; c < map.cols; ++c)
        {
            const short d = map.at<short>(r, c);
            const cv::Point p(cvRound(c * cell), cvRound(r * cell));
            const cv::Rect box(p.x - w / 2, p.y - w / 2, w, w);
            if (d < 0) // reached validation: a white dot, the image stays visible
                cv::circle(over, p, std::max(1, w / 4), cv::Scalar(255, 255, 255), cv::FILLED);
            else
            {
                const cv::Vec3b col = colors.at<cv::Vec3b>(std::min(255, 255 * d / D));
                cv::rectangle(over, box, cv::Scalar(col[0], col[1], col[2]), cv::FILLED);
            }
        }
    cv::Mat blend;
    cv::addWeighted(dim, 0.3, over, 0.7, 0, blend);
    // legend: colour bar of the depth, white = reached validation
    cv::Mat legend(40, frame.cols * 2, CV_8UC3, cv::Scalar::all(0));
    const int bar = std::min(legend.cols - 260, 400);
    for (int x = 0; x < bar; ++x)
    {
        const cv::Vec3b col = colors.at<cv::Vec3b>(255 * x / std::max(1, bar - 1));
        cv::line(legend, cv::Point(80 + x, 8), cv::Point(80 + x, 22),
                 cv::Scalar(col[0], col[1], col[2]));
    }
    cv::putText(legend, "depth 0", cv::Point(4, 20), cv::FONT_HERSHEY_SIMPLEX, 0.4,
                cv::Scalar::all(255));
    cv::putText(legend, cv::format("%d", D), cv::Point(86 + bar, 20), cv::FONT_HERSHEY_SIMPLEX,
                0.4, cv::Scalar::all(255));
    cv::putText(legend, "rejected at tree depth; white: reached validation",
                cv::Point(120 + bar, 20), cv::FONT_HERSHEY_SIMPLEX, 0.4, cv::Scalar::all(255));
    cv::Mat top, out;
    cv::hconcat(frame, blend, top);
    cv::vconcat(top, legend, out);
    return out;
}

std::string heatFile(const std::string& dir, const char* model, const EvalFrame& f)
{
    return cv::format("%s/heatmap_%s_%06d_%06d.png", dir.c_str(), model, f.scene_id, f.im_id);
}

// ---------------------------------------------------------------------------------------------
// plots

namespace {

/** A log10 axis over [lo, hi] (positive) onto pixels [p0, p1]. */
struct LogAxis
{
    double lo, hi;
    int p0, p1;
    int at(double v) const
    {
        const double f = (std::log10(v) - std::log10(lo)) / (std::log10(hi) - std::log10(lo));
        return cvRound(p0 + f * (p1 - p0));
    }
};

/** Ticks 1, 2, 5 x 10^k inside [lo, hi] (1, 2, 3, 5 over less than two decades). */
std::vector<double> logTicks(double lo, double hi)
{
    std::vector<double> t;
    const bool fine = hi < 100 * lo;
    const double m[4] = { 1, 2, 3, 5 };
    for (int e = (int)std::floor(std::log10(lo)) - 1; e <= (int)std::ceil(std::log10(hi)); ++e)
    {
        for (int k = 0; k < 4; ++k)
        {
            if (m[k] == 3 && !fine)
                continue;
            const double v = m[k] * std::pow(10.0, e);
            if (v >= lo * (1 - 1e-9) && v <= hi * (1 + 1e-9))
                t.push_back(v);
        }
    }
    return t;
}

std::string tickText(double v)
{
    if (v >= 10000)
        return cv::format("%gk", v / 1000);
    return cv::format("%g", v);
}

void text(cv::Mat& img, const std::string& s, cv::Point p, double scale = 0.45,
          cv::Scalar color = cv::Scalar::all(0), int align = 0) // align: 0 left, 1 centre, 2 right
{
    int base = 0;
    const cv::Size sz = cv::getTextSize(s, cv::FONT_HERSHEY_SIMPLEX, scale, 1, &base);
    p.x -= align * sz.width / 2;
    cv::putText(img, s, p, cv::FONT_HERSHEY_SIMPLEX, scale, color, 1, cv::LINE_AA);
}

void range(const std::vector<Series>& s, bool xs, double& lo, double& hi)
{
    lo = std::numeric_limits<double>::infinity();
    hi = 0;
    for (size_t i = 0; i < s.size(); ++i)
    {
        const std::vector<double>& v = xs ? s[i].x : s[i].y;
        for (size_t k = 0; k < v.size(); ++k)
            if (v[k] > 0 && !cvIsInf(v[k]))
            {
                lo = std::min(lo, v[k]);
                hi = std::max(hi, v[k]);
            }
    }
    if (!(hi > 0))
    {
        lo = 1;
        hi = 10;
    }
    if (hi <= lo * 1.5)
    {
        lo /= 1.5;
        hi *= 1.5;
    }
}

} // namespace

cv::Mat plotCurves(const std::string& title, const std::string& xlabel,
                   const std::vector<Series>& times, const std::vector<Series>& rejection,
                   const std::vector<double>& x_ticks)
{
    const int W = 900, H_top = 560, H_bottom = rejection.empty() ? 0 : 240;
    const int left = 90, right = 30, top = 50;
    cv::Mat img(H_top + H_bottom + 50, W, CV_8UC3, cv::Scalar::all(255));
    double xlo, xhi, ylo, yhi;
    range(times, true, xlo, xhi);
    range(times, false, ylo, yhi);
    xlo /= 1.25;
    xhi *= 1.25;
    ylo /= 1.6;
    yhi *= 1.6;
    const LogAxis ax = { xlo, xhi, left, W - right };
    const LogAxis ay = { ylo, yhi, H_top - 40, top };
    const cv::Scalar grid(225, 225, 225), axis(0, 0, 0);
    text(img, title, cv::Point(W / 2, 28), 0.6, axis, 1);

    // time panel: log-log
    const std::vector<double> xt = x_ticks.empty() ? logTicks(xlo, xhi) : x_ticks;
    const std::vector<double> yt = logTicks(ylo, yhi);
    for (size_t i = 0; i < xt.size(); ++i)
    {
        const int x = ax.at(xt[i]);
        cv::line(img, cv::Point(x, ay.p1), cv::Point(x, ay.p0), grid);
        text(img, tickText(xt[i]), cv::Point(x, ay.p0 + 18), 0.42, axis, 1);
    }
    for (size_t i = 0; i < yt.size(); ++i)
    {
        const int y = ay.at(yt[i]);
        cv::line(img, cv::Point(ax.p0, y), cv::Point(ax.p1, y), grid);
        text(img, tickText(yt[i]), cv::Point(ax.p0 - 6, y + 5), 0.42, axis, 2);
    }
    cv::rectangle(img, cv::Point(ax.p0, ay.p1), cv::Point(ax.p1, ay.p0), axis);
    text(img, xlabel + " (log)", cv::Point((ax.p0 + ax.p1) / 2, ay.p0 + 36), 0.5, axis, 1);
    {
        cv::Mat label(30, H_top - top - 40, CV_8UC3, cv::Scalar::all(255));
        text(label, "median ms per frame, match() (log)", cv::Point(label.cols / 2, 20), 0.5,
             axis, 1);
        cv::Mat rotated;
        cv::rotate(label, rotated, cv::ROTATE_90_COUNTERCLOCKWISE);
        rotated.copyTo(img(cv::Rect(4, top, rotated.cols, rotated.rows)));
    }
    for (size_t s = 0; s < times.size(); ++s)
    {
        std::vector<cv::Point> pts;
        for (size_t k = 0; k < times[s].x.size() && k < times[s].y.size(); ++k)
            if (times[s].x[k] > 0 && times[s].y[k] > 0)
                pts.push_back(cv::Point(ax.at(times[s].x[k]), ay.at(times[s].y[k])));
        if (pts.size() > 1)
            cv::polylines(img, pts, false, times[s].color, 2, cv::LINE_AA);
        for (size_t k = 0; k < pts.size(); ++k)
            cv::circle(img, pts[k], 4, times[s].color, cv::FILLED, cv::LINE_AA);
    }
    // legend
    for (size_t s = 0; s < times.size(); ++s)
    {
        const cv::Point p(ax.p0 + 14, ay.p1 + 20 + 22 * (int)s);
        cv::line(img, p, p + cv::Point(26, 0), times[s].color, 2, cv::LINE_AA);
        cv::circle(img, p + cv::Point(13, 0), 4, times[s].color, cv::FILLED, cv::LINE_AA);
        text(img, times[s].label, p + cv::Point(34, 5), 0.45, axis);
    }

    if (rejection.empty())
        return img;
    // rejection panel: same x axis, share of locations rejected before validation (linear)
    const int y0 = H_top + H_bottom - 10, y1 = H_top + 40;
    for (int v = 0; v <= 100; v += 25)
    {
        const int y = y0 + (y1 - y0) * v / 100;
        cv::line(img, cv::Point(ax.p0, y), cv::Point(ax.p1, y), grid);
        text(img, cv::format("%d %%", v), cv::Point(ax.p0 - 6, y + 5), 0.42, axis, 2);
    }
    for (size_t i = 0; i < xt.size(); ++i)
    {
        const int x = ax.at(xt[i]);
        cv::line(img, cv::Point(x, y1), cv::Point(x, y0), grid);
        text(img, tickText(xt[i]), cv::Point(x, y0 + 18), 0.42, axis, 1);
    }
    cv::rectangle(img, cv::Point(ax.p0, y1), cv::Point(ax.p1, y0), axis);
    text(img, "rejected before validation (forestmod)", cv::Point(ax.p0, y1 - 8),
         0.45, axis);
    text(img, xlabel + " (log)", cv::Point((ax.p0 + ax.p1) / 2, y0 + 36), 0.5, axis, 1);
    for (size_t s = 0; s < rejection.size(); ++s)
    {
        std::vector<cv::Point> pts;
        for (size_t k = 0; k < rejection[s].x.size() && k < rejection[s].y.size(); ++k)
            if (rejection[s].x[k] > 0 && !cvIsNaN(rejection[s].y[k]))
                pts.push_back(cv::Point(ax.at(rejection[s].x[k]),
                                        y0 + cvRound((y1 - y0) * rejection[s].y[k])));
        if (pts.size() > 1)
            cv::polylines(img, pts, false, rejection[s].color, 2, cv::LINE_AA);
        for (size_t k = 0; k < pts.size(); ++k)
            cv::rectangle(img, pts[k] - cv::Point(4, 4), pts[k] + cv::Point(4, 4),
                          rejection[s].color, cv::FILLED);
        const cv::Point p(ax.p1 - 380 + 190 * (int)s, y1 - 12);
        cv::line(img, p, p + cv::Point(26, 0), rejection[s].color, 2, cv::LINE_AA);
        text(img, rejection[s].label, p + cv::Point(34, 5), 0.45, axis);
    }
    return img;
}

} // namespace fmeval
