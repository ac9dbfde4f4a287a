/// libDfVirtualCamera: an OpenNI2 driver that serves recorded RGB-D folders as cameras.
/// URI: df-virtual://<absolute folder path>. At initialize() it announces the folder named by
/// DF_VIRTUAL_CAMERA_FOLDER (if set); any other df-virtual:// URI is announced on demand when an
/// application opens it (tryDevice). Settings: see sequence.hpp (DF_VIRTUAL_CAMERA_*).
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <new>
#include <string>

// OniDriverAPI.h's export macro allocates with these (they live in OpenNI's private XnOS.h).
#define XN_NEW(type, arg) new (std::nothrow) type(arg)
#define XN_DELETE(p) delete (p)
#include <Driver/OniDriverAPI.h>

#include "device.hpp"
#include "sequence.hpp"

namespace df::virtual_camera {
namespace {

constexpr const char* kUriPrefix = "df-virtual://";
constexpr const char* kLogMask = "DfVirtualCamera";
constexpr int kSeverityWarning = 2;  // OpenNI log severities: 0 verbose .. 3 error

bool has_prefix(const char* uri) {
    return uri != nullptr && std::strncmp(uri, kUriPrefix, std::strlen(kUriPrefix)) == 0;
}

std::string base_name(std::string path) {
    while (path.size() > 1 && path.back() == '/') path.pop_back();
    const size_t slash = path.find_last_of('/');
    return slash == std::string::npos ? path : path.substr(slash + 1);
}

}  // namespace

class VirtualCameraDriver final : public oni::driver::DriverBase {
  public:
    explicit VirtualCameraDriver(OniDriverServices* services) : DriverBase(services) {}

    OniStatus initialize(oni::driver::DeviceConnectedCallback connected,
                         oni::driver::DeviceDisconnectedCallback disconnected,
                         oni::driver::DeviceStateChangedCallback state_changed,
                         void* cookie) override {
        const OniStatus rc = DriverBase::initialize(connected, disconnected, state_changed, cookie);
        if (rc != ONI_STATUS_OK) return rc;
        const char* folder = std::getenv("DF_VIRTUAL_CAMERA_FOLDER");
        if (folder != nullptr && *folder != '\0') {
            // A bad folder must not hide the driver: warn and keep on-demand URIs working.
            const std::string uri = std::string(kUriPrefix) + folder;
            if (announce(uri) != ONI_STATUS_OK) {
                warn("DF_VIRTUAL_CAMERA_FOLDER: " + last_error_);
            }
        }
        return ONI_STATUS_OK;
    }

    OniStatus tryDevice(const char* uri) override {
        if (!has_prefix(uri)) return ONI_STATUS_ERROR;
        const OniStatus rc = announce(uri);
        if (rc != ONI_STATUS_OK) getServices().errorLoggerAppend("%s", last_error_.c_str());
        return rc;
    }

    oni::driver::DeviceBase* deviceOpen(const char* uri, const char* /*mode*/) override {
        if (!has_prefix(uri)) return nullptr;
        const std::string folder = uri + std::strlen(kUriPrefix);
        Settings settings;
        Sequence sequence;
        std::string error;
        if (!Settings::from_env(&settings, &error) || !Sequence::load(folder, &sequence, &error)) {
            getServices().errorLoggerAppend("df-virtual: %s", error.c_str());
            return nullptr;
        }
        OniDeviceInfo info = make_info(uri);
        DeviceHooks hooks;
        hooks.warn = [this](const std::string& message) { warn(message); };
        // The end of a recording is the camera going away: readers see a disconnection.
        hooks.ended = [this, info] { deviceDisconnected(&info); };
        return new (std::nothrow) VirtualDevice(std::move(sequence), settings, std::move(hooks));
    }

    void deviceClose(oni::driver::DeviceBase* device) override { delete device; }

    void shutdown() override {}

    void* enableFrameSync(oni::driver::StreamBase** streams, int count) override {
        // OpenNI pairs synced frames by frameIndex; ours match by construction, so the group
        // needs no state. OpenNI only wants a non-null handle back.
        if (streams == nullptr || count < 1) return nullptr;
        return new (std::nothrow) int(count);
    }

    void disableFrameSync(void* group) override { delete static_cast<int*>(group); }

  private:
    static OniDeviceInfo make_info(const std::string& uri) {
        OniDeviceInfo info{};
        std::snprintf(info.uri, sizeof(info.uri), "%s", uri.c_str());
        std::snprintf(info.vendor, sizeof(info.vendor), "%s", "DetectFusion");
        const std::string name =
            "Virtual RGB-D camera (" + base_name(uri.substr(std::strlen(kUriPrefix))) + ")";
        std::snprintf(info.name, sizeof(info.name), "%s", name.c_str());
        return info;
    }

    // Checks the folder and tells OpenNI the device exists.
    OniStatus announce(const std::string& uri) {
        if (uri.size() >= ONI_MAX_STR) {
            last_error_ = "df-virtual: URI longer than " + std::to_string(ONI_MAX_STR - 1) +
                          " characters: " + uri;
            return ONI_STATUS_BAD_PARAMETER;
        }
        Sequence sequence;
        std::string error;
        if (!Sequence::load(uri.substr(std::strlen(kUriPrefix)), &sequence, &error)) {
            last_error_ = "df-virtual: " + error;
            return ONI_STATUS_ERROR;
        }
        const OniDeviceInfo info = make_info(uri);
        deviceConnected(&info);
        return ONI_STATUS_OK;
    }

    void warn(const std::string& message) {
        // OpenNI's own log is off by default; stderr keeps problems visible.
        std::fprintf(stderr, "DfVirtualCamera: warning: %s\n", message.c_str());
        getServices().log(kSeverityWarning, __FILE__, __LINE__, kLogMask, message.c_str());
    }

    std::string last_error_;
};

}  // namespace df::virtual_camera

ONI_EXPORT_DRIVER(df::virtual_camera::VirtualCameraDriver)
