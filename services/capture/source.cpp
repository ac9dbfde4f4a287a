#include "source.hpp"

#include "core/log.hpp"
#include "io/openni/openni_source.hpp"
#include "io/tum/tum_folder.hpp"

namespace df::capture {
namespace {

Result<std::unique_ptr<io::FrameSource>> open_tum(const config::CaptureConfig& c) {
    io::TumFolderConfig tc;
    tc.folder = c.folder();
    auto preset = io::intrinsics_preset(c.intrinsics_preset());
    if (!preset) return preset.status();
    tc.intrinsics = *preset;
    if (c.has_fx()) tc.intrinsics.fx = c.fx();
    if (c.has_fy()) tc.intrinsics.fy = c.fy();
    if (c.has_cx()) tc.intrinsics.cx = c.cx();
    if (c.has_cy()) tc.intrinsics.cy = c.cy();
    tc.depth_units_per_m = c.depth_units_per_m();
    tc.depth_invalid_value = static_cast<int>(c.depth_invalid_value());
    tc.max_difference_s = c.max_difference_s();
    tc.use_associations_file = c.use_associations_file();
    tc.width = static_cast<int>(c.width());
    tc.height = static_cast<int>(c.height());
    auto source = io::TumFolderSource::open(tc);
    if (!source) return source.status();
    for (const auto& e : (*source)->list_errors()) log::error("bad list line skipped: ", e);
    return std::unique_ptr<io::FrameSource>(std::move(*source));
}

}  // namespace

Result<std::unique_ptr<io::FrameSource>> open_source(const config::CaptureConfig& c) {
    if (c.source() == config::CaptureConfig::OPENNI) {
        io::OpenNiConfig oc;
        oc.uri = c.openni_uri();
        auto source = io::OpenNiSource::open(oc);
        if (!source) return source.status();
        return std::unique_ptr<io::FrameSource>(std::move(*source));
    }
    if (c.folder().empty()) {
        return Status(StatusCode::kInvalidArgument,
                      "no input: set 'folder' (a TUM RGB-D folder) or 'source: OPENNI'");
    }
    return open_tum(c);
}

}  // namespace df::capture
