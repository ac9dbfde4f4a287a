/// Letterboxing, YOLO output decoding and NMS.
#include "detect/decode.hpp"

#include <algorithm>
#include <cmath>
#include <opencv2/imgproc.hpp>
#include <string>

#include "detect/detector.hpp"

namespace df::detect {
namespace {

float sigmoid(float x) { return 1.f / (1.f + std::exp(-x)); }

std::string shape_of(const cv::Mat& m) {
    std::string s = "[";
    for (int i = 0; i < m.dims; ++i) s += (i ? "," : "") + std::to_string(m.size[i]);
    return s + "]";
}

Detection make(float cx, float cy, float w, float h, int class_id, float score) {
    Detection d;
    d.box = cv::Rect2f(cx - 0.5f * w, cy - 0.5f * h, w, h);
    d.class_id = class_id;
    d.score = score;
    return d;
}

}  // namespace

Letterbox letterbox(const cv::Mat& image, int width, int height, cv::Mat* out) {
    Letterbox lb;
    lb.scale =
        std::min(static_cast<float>(width) / image.cols, static_cast<float>(height) / image.rows);
    const int w = std::max(1, static_cast<int>(std::lround(image.cols * lb.scale)));
    const int h = std::max(1, static_cast<int>(std::lround(image.rows * lb.scale)));
    lb.pad_x = 0.5f * (width - w);
    lb.pad_y = 0.5f * (height - h);
    out->create(height, width, image.type());
    out->setTo(cv::Scalar::all(114));
    const cv::Rect roi(static_cast<int>(lb.pad_x), static_cast<int>(lb.pad_y), w, h);
    cv::resize(image, (*out)(roi), roi.size(), 0, 0, cv::INTER_LINEAR);
    lb.pad_x = static_cast<float>(roi.x);
    lb.pad_y = static_cast<float>(roi.y);
    return lb;
}

Status decode_yolov5_grids(const std::vector<cv::Mat>& outs, float min_score,
                           std::vector<Detection>* out) {
    static const float kAnchors[3][6] = {
        {10, 13, 16, 30, 33, 23}, {30, 61, 62, 45, 59, 119}, {116, 90, 156, 198, 373, 326}};
    static const float kStrides[3] = {8.f, 16.f, 32.f};
    if (outs.size() != 3) return error(StatusCode::kInternal, "YOLOv5: expected 3 outputs");
    for (int level = 0; level < 3; ++level) {
        const cv::Mat& blob = outs[level];
        if (blob.dims != 4 || blob.size[1] % 3 != 0 || blob.size[1] / 3 <= 5 ||
            blob.type() != CV_32F) {
            return error(StatusCode::kInternal, "YOLOv5: output " + std::to_string(level) +
                                                    " has shape " + shape_of(blob) +
                                                    ", expected [1,3*(5+C),H,W]");
        }
        const int per_anchor = blob.size[1] / 3, gh = blob.size[2], gw = blob.size[3];
        const size_t plane = static_cast<size_t>(gh) * gw;
        const float* data = blob.ptr<float>();
        // score = obj * cls <= obj, so cells whose objectness is below min_score are skipped.
        const float min_logit = std::log(min_score / (1.f - std::min(min_score, 0.999999f)));
        for (int a = 0; a < 3; ++a) {
            const float* base = data + static_cast<size_t>(a) * per_anchor * plane;
            for (int y = 0; y < gh; ++y) {
                for (int x = 0; x < gw; ++x) {
                    const size_t cell = static_cast<size_t>(y) * gw + x;
                    if (base[4 * plane + cell] < min_logit) continue;
                    const float obj = sigmoid(base[4 * plane + cell]);
                    int best = 0;
                    float best_logit = -1e30f;
                    for (int c = 0; c < per_anchor - 5; ++c) {
                        const float v = base[(5 + c) * plane + cell];
                        if (v > best_logit) {
                            best_logit = v;
                            best = c;
                        }
                    }
                    const float score = obj * sigmoid(best_logit);
                    if (score < min_score) continue;
                    const float s = kStrides[level];
                    const float cx = (2.f * sigmoid(base[cell]) - 0.5f + x) * s;
                    const float cy = (2.f * sigmoid(base[plane + cell]) - 0.5f + y) * s;
                    const float bw = std::pow(2.f * sigmoid(base[2 * plane + cell]), 2.f) *
                                     kAnchors[level][2 * a];
                    const float bh = std::pow(2.f * sigmoid(base[3 * plane + cell]), 2.f) *
                                     kAnchors[level][2 * a + 1];
                    out->push_back(make(cx, cy, bw, bh, best, score));
                }
            }
        }
    }
    return Status::ok();
}

Status decode_darknet_rows(const std::vector<cv::Mat>& outs, int net_width, int net_height,
                           float min_score, std::vector<Detection>* out) {
    for (const cv::Mat& m : outs) {
        if (m.dims != 2 || m.cols <= 5 || m.type() != CV_32F) {
            return error(StatusCode::kInternal,
                         "Darknet: output of shape " + shape_of(m) + ", expected [N,5+C]");
        }
        for (int r = 0; r < m.rows; ++r) {
            const float* row = m.ptr<float>(r);
            const float* best = std::max_element(row + 5, row + m.cols);
            if (*best < min_score) continue;
            out->push_back(make(row[0] * net_width, row[1] * net_height, row[2] * net_width,
                                row[3] * net_height, static_cast<int>(best - (row + 5)), *best));
        }
    }
    return Status::ok();
}

Status decode_onnx_output(const cv::Mat& output, int num_classes, float min_score,
                          std::vector<Detection>* out) {
    if (output.dims == 3 && output.size[2] == 5 + num_classes) {  // YOLOv5 export [1, N, 5+C]
        const cv::Mat rows(output.size[1], output.size[2], CV_32F,
                           const_cast<float*>(output.ptr<float>()));
        for (int r = 0; r < rows.rows; ++r) {
            const float* row = rows.ptr<float>(r);
            const float* best = std::max_element(row + 5, row + rows.cols);
            const float score = row[4] * *best;
            if (score < min_score) continue;
            out->push_back(
                make(row[0], row[1], row[2], row[3], static_cast<int>(best - (row + 5)), score));
        }
        return Status::ok();
    }
    if (output.dims == 3 && output.size[1] == 4 + num_classes) {  // YOLOv8 export [1, 4+C, N]
        const int n = output.size[2];
        const float* data = output.ptr<float>();
        for (int i = 0; i < n; ++i) {
            int best = 0;
            for (int c = 1; c < num_classes; ++c)
                if (data[(4 + c) * n + i] > data[(4 + best) * n + i]) best = c;
            const float score = data[(4 + best) * n + i];
            if (score < min_score) continue;
            out->push_back(
                make(data[i], data[n + i], data[2 * n + i], data[3 * n + i], best, score));
        }
        return Status::ok();
    }
    return error(StatusCode::kInvalidArgument,
                 "ONNX: output of shape " + shape_of(output) + " is neither [1,N," +
                     std::to_string(5 + num_classes) + "] (YOLOv5) nor [1," +
                     std::to_string(4 + num_classes) + ",N] (YOLOv8)");
}

float iou(const cv::Rect2f& a, const cv::Rect2f& b) {
    const float inter = (a & b).area();
    const float uni = a.area() + b.area() - inter;
    return uni > 0.f ? inter / uni : 0.f;
}

std::vector<Detection> nms_per_class(std::vector<Detection> detections, float iou_threshold) {
    std::stable_sort(detections.begin(), detections.end(),
                     [](const Detection& a, const Detection& b) { return a.score > b.score; });
    std::vector<Detection> kept;
    for (auto& d : detections) {
        bool suppressed = false;
        for (const auto& k : kept) {
            if (k.class_id == d.class_id && iou(k.box, d.box) > iou_threshold) {
                suppressed = true;
                break;
            }
        }
        if (!suppressed) kept.push_back(std::move(d));
    }
    return kept;
}

}  // namespace df::detect
