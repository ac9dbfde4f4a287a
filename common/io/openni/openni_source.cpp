#include "io/openni/openni_source.hpp"

#include <OpenNI.h>
#include <dlfcn.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cctype>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <sstream>

#include "core/log.hpp"

namespace df::io {
namespace {

using openni::OpenNI;
using openni::VideoFrameRef;
using openni::VideoStream;

constexpr int kWaitSliceMs = 50;  // how often next() looks at the disconnection flag

// Where OpenNI was loaded from decides where it looks for drivers; say so in errors.
std::string openni_library_path() {
    Dl_info info{};
    if (dladdr(reinterpret_cast<void*>(&oniInitialize), &info) == 0 || info.dli_fname == nullptr) {
        return "(unknown)";
    }
    return info.dli_fname;
}

std::string driver_hint() {
    const std::string lib = openni_library_path();
    const size_t slash = lib.find_last_of('/');
    const std::string drivers =
        (slash == std::string::npos ? std::string(".") : lib.substr(0, slash)) + "/OpenNI2/Drivers";
    std::string hint = "OpenNI2 library " + lib + " loads drivers from " + drivers;
    if (access((drivers + "/libDfVirtualCamera.so.0").c_str(), F_OK) != 0) {
        hint +=
            " (no DfVirtualCamera driver there: for df-virtual:// URIs run with "
            "LD_LIBRARY_PATH=<build>/openni2)";
    }
    return hint;
}

// OpenNI's extended error, on one line with single spaces.
std::string oni_error() {
    std::string text;
    for (const char* c = OpenNI::getExtendedError(); c != nullptr && *c != '\0'; ++c) {
        const bool space = std::isspace(static_cast<unsigned char>(*c)) != 0;
        if (space && (text.empty() || text.back() == ' ')) continue;
        text += space ? ' ' : *c;
    }
    while (!text.empty() && text.back() == ' ') text.pop_back();
    return text.empty() ? "no details from OpenNI" : text;
}

const char* format_name(openni::PixelFormat format) {
    switch (format) {
        case openni::PIXEL_FORMAT_DEPTH_1_MM:
            return "DEPTH_1_MM";
        case openni::PIXEL_FORMAT_DEPTH_100_UM:
            return "DEPTH_100_UM";
        case openni::PIXEL_FORMAT_SHIFT_9_2:
            return "SHIFT_9_2";
        case openni::PIXEL_FORMAT_SHIFT_9_3:
            return "SHIFT_9_3";
        case openni::PIXEL_FORMAT_RGB888:
            return "RGB888";
        case openni::PIXEL_FORMAT_YUV422:
            return "YUV422";
        case openni::PIXEL_FORMAT_GRAY8:
            return "GRAY8";
        case openni::PIXEL_FORMAT_GRAY16:
            return "GRAY16";
        case openni::PIXEL_FORMAT_JPEG:
            return "JPEG";
        case openni::PIXEL_FORMAT_YUYV:
            return "YUYV";
    }
    return "format?";
}

std::string mode_text(const openni::VideoMode& mode) {
    std::ostringstream s;
    s << mode.getResolutionX() << "x" << mode.getResolutionY() << "@" << mode.getFps() << " "
      << format_name(mode.getPixelFormat());
    return s.str();
}

std::string device_list_text(const std::vector<OpenNiDeviceInfo>& devices) {
    if (devices.empty()) return "none";
    std::string text;
    for (const auto& d : devices) {
        if (!text.empty()) text += ", ";
        text += "'" + d.uri + "' (" + d.vendor + " " + d.name + ")";
    }
    return text;
}

std::vector<OpenNiDeviceInfo> enumerate() {
    openni::Array<openni::DeviceInfo> found;
    OpenNI::enumerateDevices(&found);
    std::vector<OpenNiDeviceInfo> devices;
    for (int i = 0; i < found.getSize(); ++i) {
        devices.push_back({found[i].getUri(), found[i].getName(), found[i].getVendor()});
    }
    return devices;
}

// One OpenNI::initialize() matched by one OpenNI::shutdown() (OpenNI counts them).
class OpenNiRuntime {
  public:
    OpenNiRuntime() = default;
    ~OpenNiRuntime() {
        if (active_) OpenNI::shutdown();
    }
    OpenNiRuntime(const OpenNiRuntime&) = delete;
    OpenNiRuntime& operator=(const OpenNiRuntime&) = delete;

    Status start() {
        if (OpenNI::initialize() != openni::STATUS_OK) {
            return error(StatusCode::kUnavailable,
                         "OpenNI2 initialise failed: " + oni_error() + "; " + driver_hint());
        }
        active_ = true;
        return Status::ok();
    }

  private:
    bool active_ = false;
};

// Notices when our device goes away (unplugged, or the end of a virtual recording).
class DisconnectWatch final : public OpenNI::DeviceDisconnectedListener {
  public:
    void watch(std::string uri) { uri_ = std::move(uri); }
    void onDeviceDisconnected(const openni::DeviceInfo* info) override {
        if (info != nullptr && uri_ == info->getUri()) lost_ = true;
    }
    bool lost() const { return lost_; }

  private:
    std::string uri_;
    std::atomic<bool> lost_{false};
};

// Picks `format` at width x height @ fps, or explains which modes the sensor offers.
Status set_mode(VideoStream& stream, const char* sensor_name, openni::PixelFormat format,
                const OpenNiConfig& config) {
    const auto& modes = stream.getSensorInfo().getSupportedVideoModes();
    std::string offered;
    for (int i = 0; i < modes.getSize(); ++i) {
        const openni::VideoMode& mode = modes[i];
        if (mode.getPixelFormat() == format && mode.getResolutionX() == config.width &&
            mode.getResolutionY() == config.height && mode.getFps() == config.fps) {
            if (stream.setVideoMode(mode) != openni::STATUS_OK) {
                return error(StatusCode::kUnavailable, std::string("setting the ") + sensor_name +
                                                           " mode " + mode_text(mode) +
                                                           " failed: " + oni_error());
            }
            return Status::ok();
        }
        offered += (offered.empty() ? "" : ", ") + mode_text(mode);
    }
    openni::VideoMode wanted;
    wanted.setResolution(config.width, config.height);
    wanted.setFps(config.fps);
    wanted.setPixelFormat(format);
    return error(StatusCode::kInvalidArgument, std::string("the ") + sensor_name +
                                                   " sensor does not offer " + mode_text(wanted) +
                                                   "; it offers: " + offered);
}

double focal_px(int size_px, float fov_rad) {
    return size_px / (2.0 * std::tan(static_cast<double>(fov_rad) / 2.0));
}

}  // namespace

struct OpenNiSource::Impl {
    OpenNiConfig config;
    OpenNiRuntime runtime;  // declared first: shut down last
    openni::Device device;
    VideoStream color, depth;
    DisconnectWatch watch;
    bool watching = false;
    bool synced = false;
    bool registered = false;
    Intrinsics intrinsics;
    std::string description;
    int first_frame_index = -1;
    uint64_t frames_returned = 0;
    bool end_logged = false;

    ~Impl() {
        for (VideoStream* s : {&color, &depth}) {
            if (s->isValid()) {
                s->stop();
                s->destroy();
            }
        }
        if (watching) OpenNI::removeDeviceDisconnectedListener(&watch);
        if (device.isValid()) device.close();
    }

    Status open_device();
    Status open_streams();
    void set_registration();
    void set_intrinsics();

    enum class Step { kGotFrame, kNothingYet, kLost, kFailed };
    /// Waits up to `slice_ms` for a frame of whichever stream is still missing and reads it.
    Step wait_one(VideoFrameRef* color_frame, VideoFrameRef* depth_frame, int slice_ms);
    /// Same frameIndex when frame sync is on, else stamps within half a frame period.
    bool same_instant(const VideoFrameRef& color_frame, const VideoFrameRef& depth_frame) const;
    FrameRead fill(const VideoFrameRef& color_frame, const VideoFrameRef& depth_frame);
    FrameRead bad_frame(const std::string& what) const;
    FrameRead timed_out(const VideoFrameRef& color_frame, const VideoFrameRef& depth_frame) const;
    FrameRead ended();
};

Status OpenNiSource::Impl::open_device() {
    const char* uri = config.uri.empty() ? openni::ANY_DEVICE : config.uri.c_str();
    if (device.open(uri) != openni::STATUS_OK) {
        const std::string why = oni_error();
        return error(StatusCode::kNotFound,
                     "cannot open OpenNI2 device '" +
                         (config.uri.empty() ? std::string("(first device)") : config.uri) +
                         "': " + why + ". Devices found: " + device_list_text(enumerate()) + ". " +
                         driver_hint());
    }
    watch.watch(device.getDeviceInfo().getUri());
    watching = OpenNI::addDeviceDisconnectedListener(&watch) == openni::STATUS_OK;
    if (!watching) log::warn("OpenNI2: cannot watch for disconnection: ", oni_error());
    return Status::ok();
}

Status OpenNiSource::Impl::open_streams() {
    const std::string uri = device.getDeviceInfo().getUri();
    if (color.create(device, openni::SENSOR_COLOR) != openni::STATUS_OK) {
        return error(StatusCode::kUnavailable,
                     "OpenNI2 device '" + uri + "' has no usable colour sensor: " + oni_error());
    }
    if (depth.create(device, openni::SENSOR_DEPTH) != openni::STATUS_OK) {
        return error(StatusCode::kUnavailable,
                     "OpenNI2 device '" + uri + "' has no usable depth sensor: " + oni_error());
    }
    DF_RETURN_IF_ERROR(set_mode(color, "colour", openni::PIXEL_FORMAT_RGB888, config));
    DF_RETURN_IF_ERROR(set_mode(depth, "depth", openni::PIXEL_FORMAT_DEPTH_1_MM, config));
    for (VideoStream* s : {&color, &depth}) {
        if (s->isPropertySupported(openni::STREAM_PROPERTY_MIRRORING)) {
            if (s->setMirroringEnabled(config.mirror) != openni::STATUS_OK) {
                log::warn("OpenNI2: cannot set mirroring to ", config.mirror, ": ", oni_error());
            }
        } else if (config.mirror) {
            log::warn("OpenNI2: the device cannot mirror; images stay unmirrored");
        }
    }
    set_registration();
    if (depth.start() != openni::STATUS_OK || color.start() != openni::STATUS_OK) {
        return error(StatusCode::kUnavailable,
                     "cannot start the streams of OpenNI2 device '" + uri + "': " + oni_error());
    }
    // After start: OpenNI only groups streams that are running.
    synced = device.setDepthColorSyncEnabled(true) == openni::STATUS_OK;
    if (!synced) {
        log::warn("OpenNI2: depth-colour frame sync not supported (", oni_error(),
                  "); pairing frames by time stamp");
    }
    set_intrinsics();
    return Status::ok();
}

void OpenNiSource::Impl::set_registration() {
    if (!config.register_depth_to_color) return;
    if (!device.isImageRegistrationModeSupported(openni::IMAGE_REGISTRATION_DEPTH_TO_COLOR)) {
        log::warn(
            "OpenNI2: the device cannot register depth to colour; depth stays in the depth "
            "camera's frame");
        return;
    }
    registered = device.setImageRegistrationMode(openni::IMAGE_REGISTRATION_DEPTH_TO_COLOR) ==
                 openni::STATUS_OK;
    if (!registered)
        log::warn("OpenNI2: enabling depth-to-colour registration failed: ", oni_error());
}

void OpenNiSource::Impl::set_intrinsics() {
    const openni::VideoMode mode = depth.getVideoMode();
    const int w = mode.getResolutionX(), h = mode.getResolutionY();
    const float hfov = depth.getHorizontalFieldOfView(), vfov = depth.getVerticalFieldOfView();
    if (std::isfinite(hfov) && std::isfinite(vfov) && hfov > 0.0f && vfov > 0.0f) {
        intrinsics.fx = focal_px(w, hfov);
        intrinsics.fy = focal_px(h, vfov);
        intrinsics.cx = w / 2.0;
        intrinsics.cy = h / 2.0;
    } else {
        log::warn(
            "OpenNI2: the depth stream reports no field of view; using default intrinsics fx=",
            intrinsics.fx, " fy=", intrinsics.fy);
    }
}

FrameRead OpenNiSource::Impl::fill(const VideoFrameRef& color_frame,
                                   const VideoFrameRef& depth_frame) {
    FrameRead read;
    const int w = depth_frame.getWidth(), h = depth_frame.getHeight();
    if (color_frame.getWidth() != w || color_frame.getHeight() != h ||
        color_frame.getVideoMode().getPixelFormat() != openni::PIXEL_FORMAT_RGB888 ||
        depth_frame.getVideoMode().getPixelFormat() != openni::PIXEL_FORMAT_DEPTH_1_MM) {
        return bad_frame("OpenNI2 frames do not match: colour " +
                         mode_text(color_frame.getVideoMode()) + ", depth " +
                         mode_text(depth_frame.getVideoMode()));
    }
    // Sizes checked before any view: the mode asked for (and the intrinsics made for it), and
    // buffers that hold what their size and stride say.
    if (w != config.width || h != config.height) {
        return bad_frame("OpenNI2 frame is " + std::to_string(w) + "x" + std::to_string(h) +
                         ", expected " + std::to_string(config.width) + "x" +
                         std::to_string(config.height) + " (the mode opened, its intrinsics)");
    }
    const auto holds = [&](const VideoFrameRef& f, int bytes_per_pixel) {
        const int64_t stride = f.getStrideInBytes();
        return stride >= int64_t{w} * bytes_per_pixel &&
               static_cast<int64_t>(f.getDataSize()) >= stride * h && f.getData() != nullptr;
    };
    if (!holds(color_frame, 3) || !holds(depth_frame, 2)) {
        return bad_frame("OpenNI2 frame buffers are smaller than " + std::to_string(w) + "x" +
                         std::to_string(h) + " with their stride (colour " +
                         std::to_string(color_frame.getDataSize()) + " bytes, depth " +
                         std::to_string(depth_frame.getDataSize()) + " bytes)");
    }
    if (first_frame_index < 0) first_frame_index = depth_frame.getFrameIndex();
    RgbdImage& image = read.image;
    // OpenNI owns the buffers only while the frame refs live: copy.
    image.rgb = cv::Mat(h, w, CV_8UC3, const_cast<void*>(color_frame.getData()),
                        static_cast<size_t>(color_frame.getStrideInBytes()))
                    .clone();
    image.depth = cv::Mat(h, w, CV_16UC1, const_cast<void*>(depth_frame.getData()),
                          static_cast<size_t>(depth_frame.getStrideInBytes()))
                      .clone();
    image.depth_units_per_m = 1000.0;
    image.intrinsics = intrinsics;
    image.sensor_ns = static_cast<int64_t>(depth_frame.getTimestamp()) * 1000;
    image.index = static_cast<uint64_t>(depth_frame.getFrameIndex() - first_frame_index);
    read.kind = FrameRead::Kind::kFrame;
    ++frames_returned;
    return read;
}

OpenNiSource::Impl::Step OpenNiSource::Impl::wait_one(VideoFrameRef* color_frame,
                                                      VideoFrameRef* depth_frame, int slice_ms) {
    VideoStream* waiting[2];
    VideoFrameRef* into[2];
    int count = 0;
    if (!depth_frame->isValid()) {
        waiting[count] = &depth;
        into[count++] = depth_frame;
    }
    if (!color_frame->isValid()) {
        waiting[count] = &color;
        into[count++] = color_frame;
    }
    int ready = -1;
    const openni::Status rc = OpenNI::waitForAnyStream(waiting, count, &ready, slice_ms);
    if (rc == openni::STATUS_TIME_OUT) return watch.lost() ? Step::kLost : Step::kNothingYet;
    if (rc != openni::STATUS_OK || ready < 0 || ready >= count) return Step::kFailed;
    VideoFrameRef frame;
    if (waiting[ready]->readFrame(&frame) != openni::STATUS_OK || !frame.isValid()) {
        return Step::kNothingYet;
    }
    *into[ready] = frame;
    return Step::kGotFrame;
}

bool OpenNiSource::Impl::same_instant(const VideoFrameRef& color_frame,
                                      const VideoFrameRef& depth_frame) const {
    if (synced) return color_frame.getFrameIndex() == depth_frame.getFrameIndex();
    const uint64_t a = color_frame.getTimestamp(), b = depth_frame.getTimestamp();
    const uint64_t half_period_us = 500000 / static_cast<uint64_t>(config.fps);
    return (a > b ? a - b : b - a) <= half_period_us;
}

FrameRead OpenNiSource::Impl::bad_frame(const std::string& what) const {
    FrameRead read;
    read.kind = FrameRead::Kind::kBadFrame;
    read.error = "seq=" + std::to_string(frames_returned) + " " + what;
    return read;
}

FrameRead OpenNiSource::Impl::timed_out(const VideoFrameRef& color_frame,
                                        const VideoFrameRef& depth_frame) const {
    const char* missing = !color_frame.isValid() && !depth_frame.isValid() ? "frames"
                          : depth_frame.isValid()                          ? "colour frame"
                                                                           : "depth frame";
    return bad_frame(std::string("no ") + missing + " from OpenNI2 device '" +
                     device.getDeviceInfo().getUri() + "' within " +
                     std::to_string(config.timeout_ms) + " ms");
}

FrameRead OpenNiSource::Impl::ended() {
    if (!end_logged) {
        log::info("seq=", frames_returned, " OpenNI2 device '", device.getDeviceInfo().getUri(),
                  "' disconnected: end of stream");
        end_logged = true;
    }
    return FrameRead{};  // kEnd
}

OpenNiSource::OpenNiSource(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}
OpenNiSource::~OpenNiSource() = default;

Result<std::unique_ptr<OpenNiSource>> OpenNiSource::open(const OpenNiConfig& config) {
    if (config.width <= 0 || config.height <= 0 || config.width > kMaxWidth ||
        config.height > kMaxHeight || config.fps <= 0 || config.timeout_ms <= 0) {
        return error(StatusCode::kInvalidArgument,
                     "OpenNiConfig: width, height, fps and timeout_ms must be positive and the "
                     "size at most " +
                         std::to_string(kMaxWidth) + "x" + std::to_string(kMaxHeight) + "; found " +
                         std::to_string(config.width) + "x" + std::to_string(config.height) + "@" +
                         std::to_string(config.fps) + ", timeout " +
                         std::to_string(config.timeout_ms) + " ms");
    }
    auto impl = std::make_unique<Impl>();
    impl->config = config;
    DF_RETURN_IF_ERROR(impl->runtime.start());
    DF_RETURN_IF_ERROR(impl->open_device());
    DF_RETURN_IF_ERROR(impl->open_streams());

    const openni::DeviceInfo& info = impl->device.getDeviceInfo();
    const Intrinsics& k = impl->intrinsics;
    std::ostringstream d;
    d << "OpenNI2 " << info.getVendor() << " " << info.getName() << " (" << info.getUri() << ") "
      << config.width << "x" << config.height << "@" << config.fps
      << ", depth registered to colour: " << (impl->registered ? "yes" : "no")
      << ", frame sync: " << (impl->synced ? "yes" : "no") << ", fx=" << k.fx << " fy=" << k.fy
      << " cx=" << k.cx << " cy=" << k.cy;
    impl->description = d.str();
    log::info("opened ", impl->description, " [", openni_library_path(), "]");
    return std::unique_ptr<OpenNiSource>(new OpenNiSource(std::move(impl)));
}

Result<std::vector<OpenNiDeviceInfo>> OpenNiSource::list_devices() {
    OpenNiRuntime runtime;
    DF_RETURN_IF_ERROR(runtime.start());
    return enumerate();
}

std::string OpenNiSource::describe() const { return impl_->description; }

const Intrinsics& OpenNiSource::intrinsics() const { return impl_->intrinsics; }

FrameRead OpenNiSource::next() {
    using Clock = std::chrono::steady_clock;
    Impl& s = *impl_;
    const auto deadline = Clock::now() + std::chrono::milliseconds(s.config.timeout_ms);
    VideoFrameRef color_frame, depth_frame;
    while (!color_frame.isValid() || !depth_frame.isValid()) {
        const auto left =
            std::chrono::duration_cast<std::chrono::milliseconds>(deadline - Clock::now());
        if (left.count() <= 0) return s.timed_out(color_frame, depth_frame);
        const int slice_ms = static_cast<int>(std::min<int64_t>(left.count(), kWaitSliceMs));
        switch (s.wait_one(&color_frame, &depth_frame, slice_ms)) {
            case Impl::Step::kLost:
                return s.ended();
            case Impl::Step::kFailed:
                return s.bad_frame("waiting for OpenNI2 frames failed: " + oni_error());
            case Impl::Step::kGotFrame:
            case Impl::Step::kNothingYet:
                break;
        }
        if (color_frame.isValid() && depth_frame.isValid() &&
            !s.same_instant(color_frame, depth_frame)) {
            // Drop the older frame and wait for its successor.
            const bool color_older = s.synced
                                         ? color_frame.getFrameIndex() < depth_frame.getFrameIndex()
                                         : color_frame.getTimestamp() < depth_frame.getTimestamp();
            (color_older ? color_frame : depth_frame).release();
        }
    }
    return s.fill(color_frame, depth_frame);
}

}  // namespace df::io
