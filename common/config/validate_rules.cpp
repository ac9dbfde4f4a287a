// The cross-field rules of the service configs: what one field's declaration cannot say.
#include <cstdio>
#include <set>
#include <string>

#include "capture.pb.h"
#include "config/validate.hpp"
#include "detector.pb.h"
#include "fusion.pb.h"
#include "geoseg.pb.h"
#include "slam.pb.h"

namespace df::config {
namespace {

Status invalid(const std::string& message) { return error(StatusCode::kInvalidArgument, message); }

Status class_rules(const ClassParams& c, const std::string& where) {
    const std::set<std::string> rigid(c.rigid().begin(), c.rigid().end());
    for (const std::string& name : c.non_rigid()) {
        if (rigid.count(name)) {
            return invalid("class '" + name + "' is listed in both " + where + ".rigid and " +
                           where +
                           ".non_rigid; an instance is one or the other: remove it from "
                           "one list");
        }
    }
    return Status::ok();
}

Status detector_rules(const DetectorServiceConfig& c) {
    for (const auto& [name, threshold] : c.class_score_thresholds()) {
        if (!(threshold >= 0.f && threshold <= 1.f)) {
            char value[32];
            std::snprintf(value, sizeof value, "%g", threshold);
            return invalid("class_score_thresholds[" + name + "] is " + value +
                           ", allowed: >= 0 and <= 1");
        }
    }
    if (c.input_width() % 32 != 0 || c.input_height() % 32 != 0) {
        return invalid("input_width x input_height is " + std::to_string(c.input_width()) + "x" +
                       std::to_string(c.input_height()) + ", allowed: multiples of 32");
    }
    if (c.model() == "simulated" && c.sim_sequence().empty()) {
        return invalid("model 'simulated' needs sim_sequence (a df_make_sequence folder)");
    }
    if (c.model() == "darknet" && (!c.has_model_path() || !c.has_weights_path())) {
        return invalid("model 'darknet' needs model_path (.cfg) and weights_path (.weights)");
    }
    return Status::ok();
}

Status capture_rules(const CaptureConfig& c) {
    if ((c.width() == 0) != (c.height() == 0)) {
        return invalid("width and height go together: found " + std::to_string(c.width()) + "x" +
                       std::to_string(c.height()) + " (0x0 = the first frame's size)");
    }
    return Status::ok();
}

Status geoseg_rules(const GeosegServiceConfig& c) {
    if (c.params().has_neighbours() && c.params().neighbours() != 4 &&
        c.params().neighbours() != 8) {
        return invalid("params.neighbours is " + std::to_string(c.params().neighbours()) +
                       ", allowed: 4 or 8");
    }
    return Status::ok();
}

}  // namespace

Status check_rules(const google::protobuf::Message& message) {
    const std::string& type = message.GetDescriptor()->full_name();
    // The generated types are known here; a dynamic message of the same type is left alone.
    if (type == FusionServiceConfig::descriptor()->full_name()) {
        if (auto* c = dynamic_cast<const FusionServiceConfig*>(&message))
            return class_rules(c->classes(), "classes");
    } else if (type == SlamServiceConfig::descriptor()->full_name()) {
        if (auto* c = dynamic_cast<const SlamServiceConfig*>(&message))
            return class_rules(c->classes(), "classes");
    } else if (type == DetectorServiceConfig::descriptor()->full_name()) {
        if (auto* c = dynamic_cast<const DetectorServiceConfig*>(&message))
            return detector_rules(*c);
    } else if (type == CaptureConfig::descriptor()->full_name()) {
        if (auto* c = dynamic_cast<const CaptureConfig*>(&message)) return capture_rules(*c);
    } else if (type == GeosegServiceConfig::descriptor()->full_name()) {
        if (auto* c = dynamic_cast<const GeosegServiceConfig*>(&message)) return geoseg_rules(*c);
    }
    return Status::ok();
}

}  // namespace df::config
