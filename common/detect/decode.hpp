#pragma once
/// Letterboxing and the decoding of YOLO network outputs into candidate boxes. Internal to
/// df_detect.
#include <opencv2/core.hpp>
#include <vector>

#include "core/status.hpp"
#include "detect/detection.hpp"

namespace df::detect {

/// How an image was fitted into the network input: net = image * scale + pad.
struct Letterbox {
    float scale = 1.f;
    float pad_x = 0.f;
    float pad_y = 0.f;
};

/// Resizes `image` (aspect kept) into a width x height canvas of grey 114, centred.
Letterbox letterbox(const cv::Mat& image, int width, int height, cv::Mat* out);

/// YOLOv5 head: three NCHW blobs [1, 3*(5+C), H/s, W/s] for strides 8, 16, 32 (raw logits; xy =
/// (2 sigmoid - 0.5 + grid) * stride, wh = (2 sigmoid)^2 * anchor). Appends candidates whose
/// score >= min_score, boxes in network input pixels, class_name unset.
Status decode_yolov5_grids(const std::vector<cv::Mat>& outs, float min_score,
                           std::vector<Detection>* out);

/// Darknet YOLO layers through OpenCV: 2D [N, 5+C] rows (cx, cy, w, h normalised to the input,
/// objectness, objectness x class probability).
Status decode_darknet_rows(const std::vector<cv::Mat>& outs, int net_width, int net_height,
                           float min_score, std::vector<Detection>* out);

/// ONNX exports: one output [1, N, 5+C] (YOLOv5: cx, cy, w, h pixels, objectness, class
/// probabilities) or [1, 4+C, N] (YOLOv8: cx, cy, w, h pixels, class scores), C = num_classes.
Status decode_onnx_output(const cv::Mat& output, int num_classes, float min_score,
                          std::vector<Detection>* out);

}  // namespace df::detect
