#pragma once
/// Tiny YOLO-shaped models that the tests write themselves (no download), each with one known
/// box: centre (16, 16), class 2 ("car"), in a 32x32 network input.
#include <string>

namespace df::test {

/// 32x32 Darknet net: one 1x1 stride-32 convolution (255 filters, no batch norm) and a YOLO layer
/// (anchors 10,13 16,30 33,23, 80 classes). Zero weights; biases give anchor 0 objectness logit 6
/// and "car" logit 3, so the box is 10x13 pixels with score sigmoid(6) sigmoid(3) = 0.950.
/// `drop_floats` > 0 truncates the weights file by that many floats.
void write_tiny_darknet(const std::string& cfg_path, const std::string& weights_path,
                        int drop_floats = 0);

/// 32x32 ONNX net, YOLOv8 layout: Conv 1x1 (3 -> 84 channels, zero weights) + Reshape to
/// [1, 84, 1024]. Biases: box (16, 16, 10, 12) pixels, "car" score 0.9, other classes 0.
void write_tiny_onnx(const std::string& path);

}  // namespace df::test
