// The configuration loader: any text as a service's configuration file (first byte picks the
// service), and the same text as one --set override. Property: it either loads or says why;
// a loaded configuration can be described (logged) and loaded again from its own text.
#include <google/protobuf/text_format.h>

#include <memory>

#include "capture.pb.h"
#include "config/config_loader.hpp"
#include "detector.pb.h"
#include "fusion.pb.h"
#include "fuzz_util.hpp"
#include "geoseg.pb.h"
#include "slam.pb.h"

using namespace df;

namespace {

std::unique_ptr<google::protobuf::Message> service_config(uint8_t which) {
    switch (which % 5) {
        case 0:
            return std::make_unique<config::SlamServiceConfig>();
        case 1:
            return std::make_unique<config::CaptureConfig>();
        case 2:
            return std::make_unique<config::GeosegServiceConfig>();
        case 3:
            return std::make_unique<config::DetectorServiceConfig>();
        default:
            return std::make_unique<config::FusionServiceConfig>();
    }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    if (size < 1) return 0;
    auto message = service_config(data[0]);
    const std::string path = fuzz::as_file("config", data + 1, size - 1, ".pbtxt");
    if (config::load(path, {}, message.get()).is_ok()) {
        (void)config::describe(*message);
        std::string text;
        DF_FUZZ_CHECK(google::protobuf::TextFormat::PrintToString(*message, &text));
        auto again = service_config(data[0]);
        DF_FUZZ_CHECK(google::protobuf::TextFormat::ParseFromString(text, again.get()));
    }
    auto with_override = service_config(data[0]);
    const std::string line(reinterpret_cast<const char*>(data + 1), size - 1);
    (void)config::load("", {line}, with_override.get());
    return 0;
}
