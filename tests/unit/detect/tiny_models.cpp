/// Writers of the tiny Darknet and ONNX models of tiny_models.hpp.
#include "tiny_models.hpp"

#include <cstdint>
#include <fstream>
#include <vector>

#include "onnx_subset.pb.h"

namespace df::test {

void write_tiny_darknet(const std::string& cfg_path, const std::string& weights_path,
                        int drop_floats) {
    std::ofstream(cfg_path)
        << "[net]\nwidth=32\nheight=32\nchannels=3\n\n"
           "[convolutional]\nfilters=255\nsize=1\nstride=32\npad=0\nactivation=linear\n\n"
           "[yolo]\nmask=0,1,2\nanchors=10,13, 16,30, 33,23\nclasses=80\nnum=3\n";
    // Darknet weights: int32 major, minor, revision, uint64 images seen, then per convolution
    // its biases [filters] and weights [filters * channels * size * size].
    std::vector<float> biases(255, -10.f);
    biases[4] = 6.f;                                      // anchor 0 objectness
    biases[5 + 2] = 3.f;                                  // anchor 0, class 2 (car)
    biases[0] = biases[1] = biases[2] = biases[3] = 0.f;  // centre of the cell, anchor size
    std::vector<float> weights(255 * 3, 0.f);
    std::vector<float> all(biases);
    all.insert(all.end(), weights.begin(), weights.end());
    all.resize(all.size() - drop_floats);
    std::ofstream out(weights_path, std::ios::binary);
    const int32_t header[3] = {0, 2, 0};
    const uint64_t seen = 0;
    out.write(reinterpret_cast<const char*>(header), sizeof(header));
    out.write(reinterpret_cast<const char*>(&seen), sizeof(seen));
    out.write(reinterpret_cast<const char*>(all.data()),
              static_cast<std::streamsize>(all.size() * sizeof(float)));
}

namespace {

void add_value_info(onnxpb::ValueInfoProto* info, const std::string& name,
                    std::vector<int64_t> dims) {
    info->set_name(name);
    auto* tensor = info->mutable_type()->mutable_tensor_type();
    tensor->set_elem_type(1);
    for (int64_t d : dims) tensor->mutable_shape()->add_dim()->set_dim_value(d);
}

}  // namespace

void write_tiny_onnx(const std::string& path) {
    constexpr int kChannels = 84;  // 4 box + 80 classes
    onnxpb::ModelProto model;
    model.set_ir_version(7);
    model.set_producer_name("df_detect_unit_test");
    auto* opset = model.add_opset_import();
    opset->set_domain("");
    opset->set_version(13);
    auto* graph = model.mutable_graph();
    graph->set_name("tiny_yolov8");
    add_value_info(graph->add_input(), "images", {1, 3, 32, 32});
    add_value_info(graph->add_output(), "output0", {1, kChannels, 32 * 32});

    auto* w = graph->add_initializer();
    w->set_name("conv.weight");
    w->set_data_type(1);
    for (int64_t d : {kChannels, 3, 1, 1}) w->add_dims(d);
    for (int i = 0; i < kChannels * 3; ++i) w->add_float_data(0.f);
    auto* b = graph->add_initializer();
    b->set_name("conv.bias");
    b->set_data_type(1);
    b->add_dims(kChannels);
    for (int i = 0; i < kChannels; ++i) b->add_float_data(0.f);
    b->set_float_data(0, 16.f);      // cx, pixels
    b->set_float_data(1, 16.f);      // cy
    b->set_float_data(2, 10.f);      // w
    b->set_float_data(3, 12.f);      // h
    b->set_float_data(4 + 2, 0.9f);  // car
    auto* shape = graph->add_initializer();
    shape->set_name("reshape.shape");
    shape->set_data_type(7);
    shape->add_dims(3);
    for (int64_t d : {1, kChannels, -1}) shape->add_int64_data(d);

    auto* conv = graph->add_node();
    conv->set_name("conv");
    conv->set_op_type("Conv");
    for (const char* in : {"images", "conv.weight", "conv.bias"}) conv->add_input(in);
    conv->add_output("features");
    auto* kernel = conv->add_attribute();
    kernel->set_name("kernel_shape");
    kernel->set_type(7);
    kernel->add_ints(1);
    kernel->add_ints(1);
    auto* reshape = graph->add_node();
    reshape->set_name("reshape");
    reshape->set_op_type("Reshape");
    reshape->add_input("features");
    reshape->add_input("reshape.shape");
    reshape->add_output("output0");

    std::ofstream out(path, std::ios::binary);
    model.SerializeToOstream(&out);
}

}  // namespace df::test
