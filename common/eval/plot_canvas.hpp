#pragma once
/// A small line-plot renderer on OpenCV images: axes with ticks, labels, grid, legend. Enough for
/// the evaluation figures; no python or GUI needed.
#include <opencv2/core.hpp>
#include <string>
#include <utility>
#include <vector>

#include "core/status.hpp"

namespace df::eval {

/// A polyline in data units; a NaN point breaks the line (gaps in a trajectory).
struct PlotSeries {
    std::vector<cv::Point2d> points;
    cv::Scalar color;   ///< BGR
    std::string label;  ///< legend entry; empty: not in the legend
    int thickness = 2;
};

/// Separate segments in data units (e.g. the residual of each associated pair).
struct PlotSegments {
    std::vector<std::pair<cv::Point2d, cv::Point2d>> lines;
    cv::Scalar color;
    std::string label;
    int thickness = 1;
};

struct PlotPanel {
    std::string title;
    std::string x_label;  ///< with unit, e.g. "time [s]"
    std::string y_label;
    std::vector<PlotSegments> segments;  ///< drawn under the series
    std::vector<PlotSeries> series;
    bool equal_aspect = false;  ///< same metres per pixel on both axes (top views)
    bool y_from_zero = false;   ///< include y = 0 (error plots)
};

/// Renders one panel on a white image of `size` (CV_8UC3).
cv::Mat render_panel(const PlotPanel& panel, cv::Size size);

/// Writes a PNG; kIoError naming the file if OpenCV cannot.
Status write_png(const std::string& file, const cv::Mat& image);

/// Colours used by the figures (BGR).
namespace colors {
inline const cv::Scalar kGroundTruth(0, 0, 0);
inline const cv::Scalar kEstimate(200, 90, 20);
inline const cv::Scalar kDifference(40, 40, 230);
inline const cv::Scalar kSecond(30, 140, 30);
}  // namespace colors

}  // namespace df::eval
