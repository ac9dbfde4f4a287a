#include "device.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>

namespace df::virtual_camera {
namespace {

int nominal_fps(double period_s) {
    const double fps = 1.0 / period_s;
    return (std::isfinite(fps) && fps >= 1.0 && fps <= 120.0) ? static_cast<int>(std::lround(fps))
                                                              : 30;
}

uint64_t to_us(double seconds) { return static_cast<uint64_t>(std::llround(seconds * 1e6)); }

}  // namespace

VirtualDevice::VirtualDevice(Sequence sequence, Settings settings, DeviceHooks hooks)
    : sequence_(std::move(sequence)), settings_(settings), hooks_(std::move(hooks)) {
    const int fps = nominal_fps(sequence_.period_s);
    color_modes_ = {{ONI_PIXEL_FORMAT_RGB888, sequence_.width, sequence_.height, fps}};
    depth_modes_ = {{ONI_PIXEL_FORMAT_DEPTH_1_MM, sequence_.width, sequence_.height, fps}};
    sensor_infos_ = {{ONI_SENSOR_COLOR, 1, color_modes_.data()},
                     {ONI_SENSOR_DEPTH, 1, depth_modes_.data()}};
    if (!settings_.lockstep) player_ = std::thread([this] { play_loop(); });
}

VirtualDevice::~VirtualDevice() {
    {
        std::lock_guard<std::mutex> lock(streams_mutex_);
        quit_ = true;
    }
    player_wake_.notify_all();
    if (player_.joinable()) player_.join();
}

OniStatus VirtualDevice::getSensorInfoList(OniSensorInfo** sensors, int* count) {
    *sensors = sensor_infos_.data();
    *count = static_cast<int>(sensor_infos_.size());
    return ONI_STATUS_OK;
}

StreamShape VirtualDevice::shape_of(OniSensorType sensor) const {
    StreamShape shape;
    shape.sensor = sensor;
    shape.mode = sensor == ONI_SENSOR_DEPTH ? depth_modes_.front() : color_modes_.front();
    shape.horizontal_fov_rad =
        static_cast<float>(2.0 * std::atan(sequence_.width / (2.0 * settings_.fx)));
    shape.vertical_fov_rad =
        static_cast<float>(2.0 * std::atan(sequence_.height / (2.0 * settings_.fy)));
    if (sensor == ONI_SENSOR_DEPTH) {
        shape.max_value = static_cast<int>(
            std::min(65535.0, std::floor(65535.0 * 1000.0 / settings_.depth_units_per_m)));
    }
    return shape;
}

oni::driver::StreamBase* VirtualDevice::createStream(OniSensorType sensor) {
    if (sensor != ONI_SENSOR_COLOR && sensor != ONI_SENSOR_DEPTH) return nullptr;
    auto stream = std::make_shared<VirtualStream>(shape_of(sensor), [this] { on_start_stop(); });
    std::lock_guard<std::mutex> lock(streams_mutex_);
    streams_.push_back(std::move(stream));
    return streams_.back().get();
}

void VirtualDevice::destroyStream(oni::driver::StreamBase* stream) {
    std::shared_ptr<VirtualStream> doomed;
    {
        std::lock_guard<std::mutex> lock(streams_mutex_);
        auto it = std::find_if(streams_.begin(), streams_.end(),
                               [stream](const auto& s) { return s.get() == stream; });
        if (it == streams_.end()) return;
        doomed = std::move(*it);
        streams_.erase(it);
    }
    // OpenNI stopped the stream before destroying it (and may hold its locks now, so waiting
    // for a send here could deadlock); a send still holding `doomed` will find it stopped.
    player_wake_.notify_all();
}

OniBool VirtualDevice::isPropertySupported(int property) {
    return property == ONI_DEVICE_PROPERTY_IMAGE_REGISTRATION ? TRUE : FALSE;
}

OniBool VirtualDevice::isImageRegistrationModeSupported(OniImageRegistrationMode mode) {
    // The recording is registered already; both answers describe the same images.
    return (mode == ONI_IMAGE_REGISTRATION_OFF || mode == ONI_IMAGE_REGISTRATION_DEPTH_TO_COLOR)
               ? TRUE
               : FALSE;
}

OniStatus VirtualDevice::setProperty(int property, const void* data, int size) {
    if (property != ONI_DEVICE_PROPERTY_IMAGE_REGISTRATION) return ONI_STATUS_NOT_SUPPORTED;
    OniImageRegistrationMode mode{};
    if (data == nullptr || size != static_cast<int>(sizeof(mode))) return ONI_STATUS_BAD_PARAMETER;
    std::memcpy(&mode, data, sizeof(mode));
    if (!isImageRegistrationModeSupported(mode)) return ONI_STATUS_NOT_SUPPORTED;
    std::lock_guard<std::mutex> lock(streams_mutex_);
    registration_ = mode;
    return ONI_STATUS_OK;
}

OniStatus VirtualDevice::getProperty(int property, void* data, int* size) {
    if (property != ONI_DEVICE_PROPERTY_IMAGE_REGISTRATION) return ONI_STATUS_NOT_SUPPORTED;
    if (data == nullptr || size == nullptr || *size < static_cast<int>(sizeof(registration_))) {
        return ONI_STATUS_BAD_PARAMETER;
    }
    std::lock_guard<std::mutex> lock(streams_mutex_);
    std::memcpy(data, &registration_, sizeof(registration_));
    *size = sizeof(registration_);
    return ONI_STATUS_OK;
}

bool VirtualDevice::all_streams_started() const {
    return !streams_.empty() && std::all_of(streams_.begin(), streams_.end(),
                                            [](const auto& s) { return s->started(); });
}

void VirtualDevice::on_start_stop() { player_wake_.notify_all(); }

bool VirtualDevice::send_next() {
    const size_t count = sequence_.entries.size();
    if (ended_) return false;
    if (next_entry_ >= count) {
        if (!settings_.loop) {
            ended_ = true;
            return false;
        }
        const double span_s = sequence_.entries.back().depth_stamp_s -
                              sequence_.entries.front().depth_stamp_s + sequence_.period_s;
        stamp_offset_us_ += to_us(std::max(span_s, sequence_.period_s));
        next_entry_ = 0;
    }
    const size_t entry = next_entry_++;
    ++frame_index_;  // counts skipped entries too, so a reader sees the gap
    std::string error;
    if (!read_frame(sequence_, entry, settings_.depth_units_per_m, &pair_, &error)) {
        hooks_.warn("skipping frame " + std::to_string(frame_index_) + ": " + error);
        return true;
    }
    pair_.rgb_stamp_us += stamp_offset_us_;
    pair_.depth_stamp_us += stamp_offset_us_;
    std::vector<std::shared_ptr<VirtualStream>> streams;
    {
        std::lock_guard<std::mutex> lock(streams_mutex_);
        streams = streams_;
    }
    for (const auto& stream : streams) {
        if (!stream->push(pair_, frame_index_)) {
            hooks_.warn("OpenNI gave no buffer for frame " + std::to_string(frame_index_));
        }
    }
    return true;
}

OniStatus VirtualDevice::tryManualTrigger() {
    if (!settings_.lockstep) return ONI_STATUS_OK;
    bool just_ended = false;
    {
        std::lock_guard<std::mutex> trigger_lock(trigger_mutex_);
        if (ended_) return ONI_STATUS_OK;
        {
            std::lock_guard<std::mutex> lock(streams_mutex_);
            const bool any_started = std::any_of(streams_.begin(), streams_.end(),
                                                 [](const auto& s) { return s->started(); });
            if (!any_started) return ONI_STATUS_OK;
        }
        just_ended = !send_next();
    }
    // Outside our locks: OpenNI takes its own while it handles the disconnection.
    if (just_ended) hooks_.ended();
    return ONI_STATUS_OK;
}

void VirtualDevice::play_loop() {
    const auto& entries = sequence_.entries;
    std::unique_lock<std::mutex> lock(streams_mutex_);
    bool playing = false;
    Clock::time_point due;
    while (!quit_) {
        if (!all_streams_started()) {
            playing = false;
            player_wake_.wait(lock);
            continue;
        }
        if (!playing) {
            // Like a camera, the first frame comes one period after the start, which leaves a
            // reader time to finish its set-up (frame sync) instead of losing frame 0.
            playing = true;
            due = Clock::now() + std::chrono::microseconds(to_us(sequence_.period_s));
        }
        const bool interrupted =
            player_wake_.wait_until(lock, due, [this] { return quit_ || !all_streams_started(); });
        if (interrupted) continue;
        const size_t sent = next_entry_ < entries.size() ? next_entry_ : 0;
        lock.unlock();
        const bool more = send_next();
        lock.lock();
        if (!more) break;
        const double step_s = next_entry_ < entries.size()
                                  ? entries[next_entry_].depth_stamp_s - entries[sent].depth_stamp_s
                                  : sequence_.period_s;
        due += std::chrono::microseconds(to_us(std::max(0.0, step_s)));
    }
    // Reported without our locks. OpenNI takes its context lock here; an application that shuts
    // OpenNI down without closing the device first holds that lock while it waits for us in
    // ~VirtualDevice, hence the quit_ check (OpenNiSource closes the device first).
    const bool tell = !quit_ && ended_;
    lock.unlock();
    if (tell) hooks_.ended();
}

}  // namespace df::virtual_camera
