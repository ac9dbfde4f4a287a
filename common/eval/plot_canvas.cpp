#include "eval/plot_canvas.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

namespace df::eval {

namespace {

constexpr int kFont = cv::FONT_HERSHEY_SIMPLEX;
constexpr double kTextScale = 0.5;
constexpr int kLeft = 90, kRight = 20, kTop = 40, kBottom = 60;

struct Range {
    double lo = std::numeric_limits<double>::infinity();
    double hi = -std::numeric_limits<double>::infinity();
    void add(double v) {
        if (!std::isfinite(v)) return;
        lo = std::min(lo, v);
        hi = std::max(hi, v);
    }
    bool valid() const { return lo <= hi; }
    double span() const { return hi - lo; }
};

/// 1, 2 or 5 times a power of ten, about range / 5.
double nice_step(double range) {
    const double raw = range / 5;
    const double power = std::pow(10.0, std::floor(std::log10(raw)));
    for (double m : {1.0, 2.0, 5.0, 10.0}) {
        if (raw <= m * power) return m * power;
    }
    return 10 * power;
}

std::string tick_text(double v, double step) {
    const int decimals = std::max(0, static_cast<int>(-std::floor(std::log10(step) + 1e-9)));
    char text[64];
    std::snprintf(text, sizeof text, "%.*f", decimals, std::abs(v) < step * 1e-6 ? 0.0 : v);
    return text;
}

void put_text(cv::Mat& img, const std::string& text, cv::Point at, double scale = kTextScale,
              int thickness = 1) {
    cv::putText(img, text, at, kFont, scale, cv::Scalar(0, 0, 0), thickness, cv::LINE_AA);
}

cv::Size text_size(const std::string& text, double scale = kTextScale, int thickness = 1) {
    int baseline = 0;
    return cv::getTextSize(text, kFont, scale, thickness, &baseline);
}

/// Text rotated by 90 degrees (reading upwards), centred at `centre`.
void put_vertical_text(cv::Mat& img, const std::string& text, cv::Point centre) {
    const cv::Size ts = text_size(text);
    cv::Mat strip(ts.height + 8, ts.width + 4, CV_8UC3, cv::Scalar(255, 255, 255));
    put_text(strip, text, cv::Point(2, ts.height + 2));
    cv::Mat rotated;
    cv::rotate(strip, rotated, cv::ROTATE_90_COUNTERCLOCKWISE);
    const cv::Rect roi(centre.x - rotated.cols / 2, centre.y - rotated.rows / 2, rotated.cols,
                       rotated.rows);
    const cv::Rect clipped = roi & cv::Rect(0, 0, img.cols, img.rows);
    if (clipped.area() == 0) return;
    rotated(cv::Rect(clipped.x - roi.x, clipped.y - roi.y, clipped.width, clipped.height))
        .copyTo(img(clipped));
}

void pad(Range* r, double fraction) {
    if (!r->valid()) {
        r->lo = 0;
        r->hi = 1;
    }
    if (r->span() <= 0) {
        const double half = std::max(1e-3, std::abs(r->lo) * 0.05);
        r->lo -= half;
        r->hi += half;
    }
    const double margin = r->span() * fraction;
    r->lo -= margin;
    r->hi += margin;
}

/// Draws the legend in the corner of `area` that covers the fewest drawn pixels.
void draw_legend(cv::Mat& img, const PlotPanel& panel, const cv::Rect& area) {
    std::vector<std::pair<std::string, cv::Scalar>> entries;
    for (const auto& s : panel.segments) {
        if (!s.label.empty()) entries.emplace_back(s.label, s.color);
    }
    for (const auto& s : panel.series) {
        if (!s.label.empty()) entries.emplace_back(s.label, s.color);
    }
    if (entries.empty()) return;
    int width = 0;
    for (const auto& e : entries) width = std::max(width, text_size(e.first).width);
    const int row = 20;
    const cv::Size size(width + 42, row * static_cast<int>(entries.size()) + 8);
    const int left = area.x + 8, right = area.x + area.width - size.width - 8;
    const int top = area.y + 8, bottom = area.y + area.height - size.height - 8;
    cv::Rect box;
    int fewest = -1;
    for (const cv::Point corner : {cv::Point(right, top), cv::Point(left, top),
                                   cv::Point(right, bottom), cv::Point(left, bottom)}) {
        const cv::Rect candidate = cv::Rect(corner, size) & cv::Rect(0, 0, img.cols, img.rows);
        cv::Mat gray;
        cv::cvtColor(img(candidate), gray, cv::COLOR_BGR2GRAY);
        const int used = cv::countNonZero(gray < 200);  // drawn pixels, not grid or background
        if (fewest < 0 || used < fewest) {
            fewest = used;
            box = candidate;
        }
    }
    cv::rectangle(img, box, cv::Scalar(255, 255, 255), cv::FILLED);
    cv::rectangle(img, box, cv::Scalar(160, 160, 160), 1);
    for (size_t i = 0; i < entries.size(); ++i) {
        const int y = box.y + 4 + row * static_cast<int>(i) + row / 2;
        cv::line(img, {box.x + 6, y}, {box.x + 30, y}, entries[i].second, 2, cv::LINE_AA);
        put_text(img, entries[i].first, {box.x + 36, y + 5});
    }
}

}  // namespace

cv::Mat render_panel(const PlotPanel& panel, cv::Size size) {
    cv::Mat img(size, CV_8UC3, cv::Scalar(255, 255, 255));
    const cv::Rect area(kLeft, kTop, size.width - kLeft - kRight, size.height - kTop - kBottom);
    Range xr, yr;
    for (const auto& s : panel.series) {
        for (const auto& p : s.points) {
            if (!std::isfinite(p.x) || !std::isfinite(p.y)) continue;  // a break, not a point
            xr.add(p.x);
            yr.add(p.y);
        }
    }
    for (const auto& s : panel.segments) {
        for (const auto& [a, b] : s.lines) {
            xr.add(a.x), xr.add(b.x), yr.add(a.y), yr.add(b.y);
        }
    }
    if (panel.y_from_zero) yr.add(0);
    pad(&xr, 0.04);
    pad(&yr, 0.06);
    if (panel.y_from_zero && yr.lo < 0 && yr.valid()) yr.lo = 0;
    if (panel.equal_aspect) {  // widen the tighter axis so one metre is as long on both
        const double sx = xr.span() / area.width, sy = yr.span() / area.height;
        if (sx > sy) {
            const double grow = (sx * area.height - yr.span()) / 2;
            yr.lo -= grow, yr.hi += grow;
        } else {
            const double grow = (sy * area.width - xr.span()) / 2;
            xr.lo -= grow, xr.hi += grow;
        }
    }
    auto to_px = [&](const cv::Point2d& p) {
        return cv::Point(
            static_cast<int>(std::lround(area.x + (p.x - xr.lo) / xr.span() * area.width)),
            static_cast<int>(
                std::lround(area.y + area.height - (p.y - yr.lo) / yr.span() * area.height)));
    };
    // Grid and tick labels.
    const double xs = nice_step(xr.span()), ys = nice_step(yr.span());
    for (double v = std::ceil(xr.lo / xs) * xs; v <= xr.hi; v += xs) {
        const int x = to_px({v, yr.lo}).x;
        cv::line(img, {x, area.y}, {x, area.y + area.height}, cv::Scalar(225, 225, 225), 1);
        const std::string t = tick_text(v, xs);
        put_text(img, t, {x - text_size(t).width / 2, area.y + area.height + 18});
    }
    for (double v = std::ceil(yr.lo / ys) * ys; v <= yr.hi; v += ys) {
        const int y = to_px({xr.lo, v}).y;
        cv::line(img, {area.x, y}, {area.x + area.width, y}, cv::Scalar(225, 225, 225), 1);
        const std::string t = tick_text(v, ys);
        put_text(img, t, {area.x - text_size(t).width - 6, y + 5});
    }
    cv::Mat plot = img(area);
    const cv::Point offset(-area.x, -area.y);
    for (const auto& s : panel.segments) {
        for (const auto& [a, b] : s.lines) {
            cv::line(plot, to_px(a) + offset, to_px(b) + offset, s.color, s.thickness, cv::LINE_AA);
        }
    }
    for (const auto& s : panel.series) {
        std::vector<cv::Point> run;
        auto flush = [&] {
            if (run.size() == 1) cv::circle(plot, run[0], s.thickness, s.color, cv::FILLED);
            if (run.size() > 1) cv::polylines(plot, run, false, s.color, s.thickness, cv::LINE_AA);
            run.clear();
        };
        for (const auto& p : s.points) {
            if (!std::isfinite(p.x) || !std::isfinite(p.y)) {
                flush();
            } else {
                run.push_back(to_px(p) + offset);
            }
        }
        flush();
    }
    cv::rectangle(img, area, cv::Scalar(0, 0, 0), 1);
    draw_legend(img, panel, area);
    const cv::Size title = text_size(panel.title, 0.6, 1);
    put_text(img, panel.title, {(size.width - title.width) / 2, 26}, 0.6, 1);
    const cv::Size xl = text_size(panel.x_label);
    put_text(img, panel.x_label, {area.x + (area.width - xl.width) / 2, size.height - 14});
    put_vertical_text(img, panel.y_label, {18, area.y + area.height / 2});
    return img;
}

Status write_png(const std::string& file, const cv::Mat& image) {
    try {
        if (cv::imwrite(file, image)) return Status::ok();
    } catch (const cv::Exception& e) {
        return error(StatusCode::kIoError, "cannot write " + file + ": " + e.what());
    }
    return error(StatusCode::kIoError, "cannot write " + file);
}

}  // namespace df::eval
