#include "dds/msg_types.hpp"

namespace df::dds {

const std::vector<TypeInfo>& all_types() {
    static const std::vector<TypeInfo> types = {
        {"df::msg::RgbdFrame", &df_msg_RgbdFrame_desc, QosProfile::kFrames},
        {"df::msg::CompressedImage", &df_msg_CompressedImage_desc, QosProfile::kResults},
        {"df::msg::Detections", &df_msg_Detections_desc, QosProfile::kResults},
        {"df::msg::GeometricSegments", &df_msg_GeometricSegments_desc, QosProfile::kResults},
        {"df::msg::ObjectSegments", &df_msg_ObjectSegments_desc, QosProfile::kResults},
        {"df::msg::CameraPose", &df_msg_CameraPose_desc, QosProfile::kResults},
        {"df::msg::ObjectPoses", &df_msg_ObjectPoses_desc, QosProfile::kResults},
        {"df::msg::MapCloud", &df_msg_MapCloud_desc, QosProfile::kFrames},
        {"df::msg::StageStatus", &df_msg_StageStatus_desc, QosProfile::kStatus},
    };
    return types;
}

const TypeInfo* find_type(const std::string& type_name) {
    for (const auto& t : all_types()) {
        if (type_name == t.name) return &t;
    }
    return nullptr;
}

std::string topic_name(const std::string& ns, const std::string& name) {
    if (ns.empty()) return name;
    return ns + "/" + name;
}

}  // namespace df::dds
