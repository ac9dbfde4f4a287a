#include "stream.hpp"

#include <cstring>

namespace df::virtual_camera {
namespace {

// Writes a plain value into an OpenNI property buffer after checking its size.
template <typename T>
OniStatus put(const T& value, void* data, int* size) {
    if (data == nullptr || size == nullptr || *size < static_cast<int>(sizeof(T))) {
        return ONI_STATUS_BAD_PARAMETER;
    }
    std::memcpy(data, &value, sizeof(T));
    *size = sizeof(T);
    return ONI_STATUS_OK;
}

template <typename T>
bool take(const void* data, int size, T* value) {
    if (data == nullptr || size != static_cast<int>(sizeof(T))) return false;
    std::memcpy(value, data, sizeof(T));
    return true;
}

bool same_mode(const OniVideoMode& a, const OniVideoMode& b) {
    return a.pixelFormat == b.pixelFormat && a.resolutionX == b.resolutionX &&
           a.resolutionY == b.resolutionY && a.fps == b.fps;
}

}  // namespace

VirtualStream::VirtualStream(const StreamShape& shape, std::function<void()> on_start_stop)
    : shape_(shape), on_start_stop_(std::move(on_start_stop)) {}

OniStatus VirtualStream::start() {
    // No lock: OpenNI may hold its own locks here, and a push racing a start is harmless.
    started_ = true;
    on_start_stop_();
    return ONI_STATUS_OK;
}

void VirtualStream::stop() {
    {
        std::lock_guard<std::mutex> lock(push_mutex_);
        started_ = false;
    }
    on_start_stop_();
}

int VirtualStream::bytes_per_pixel() const { return shape_.sensor == ONI_SENSOR_DEPTH ? 2 : 3; }

int VirtualStream::bytes_per_frame() const {
    return shape_.mode.resolutionX * shape_.mode.resolutionY * bytes_per_pixel();
}

OniBool VirtualStream::isPropertySupported(int property) {
    switch (property) {
        case ONI_STREAM_PROPERTY_VIDEO_MODE:
        case ONI_STREAM_PROPERTY_HORIZONTAL_FOV:
        case ONI_STREAM_PROPERTY_VERTICAL_FOV:
        case ONI_STREAM_PROPERTY_MIRRORING:
        case ONI_STREAM_PROPERTY_CROPPING:
        case ONI_STREAM_PROPERTY_STRIDE:
            return TRUE;
        case ONI_STREAM_PROPERTY_MAX_VALUE:
        case ONI_STREAM_PROPERTY_MIN_VALUE:
            return shape_.sensor == ONI_SENSOR_DEPTH ? TRUE : FALSE;
        default:
            return FALSE;
    }
}

OniStatus VirtualStream::getProperty(int property, void* data, int* size) {
    switch (property) {
        case ONI_STREAM_PROPERTY_VIDEO_MODE:
            return put(shape_.mode, data, size);
        case ONI_STREAM_PROPERTY_HORIZONTAL_FOV:
            return put(shape_.horizontal_fov_rad, data, size);
        case ONI_STREAM_PROPERTY_VERTICAL_FOV:
            return put(shape_.vertical_fov_rad, data, size);
        case ONI_STREAM_PROPERTY_MIRRORING:
            return put(OniBool{FALSE}, data, size);
        case ONI_STREAM_PROPERTY_CROPPING:
            return put(OniCropping{FALSE, 0, 0, shape_.mode.resolutionX, shape_.mode.resolutionY},
                       data, size);
        case ONI_STREAM_PROPERTY_STRIDE:
            return put(shape_.mode.resolutionX * bytes_per_pixel(), data, size);
        case ONI_STREAM_PROPERTY_MAX_VALUE:
            if (shape_.sensor != ONI_SENSOR_DEPTH) return ONI_STATUS_NOT_SUPPORTED;
            return put(shape_.max_value, data, size);
        case ONI_STREAM_PROPERTY_MIN_VALUE:
            if (shape_.sensor != ONI_SENSOR_DEPTH) return ONI_STATUS_NOT_SUPPORTED;
            return put(0, data, size);
        default:
            return ONI_STATUS_NOT_SUPPORTED;
    }
}

OniStatus VirtualStream::setProperty(int property, const void* data, int size) {
    // The recording fixes every setting: accept a request only when it asks for what we serve.
    switch (property) {
        case ONI_STREAM_PROPERTY_VIDEO_MODE: {
            OniVideoMode mode{};
            if (!take(data, size, &mode)) return ONI_STATUS_BAD_PARAMETER;
            return same_mode(mode, shape_.mode) ? ONI_STATUS_OK : ONI_STATUS_NOT_SUPPORTED;
        }
        case ONI_STREAM_PROPERTY_MIRRORING: {
            OniBool mirror = FALSE;
            if (!take(data, size, &mirror)) return ONI_STATUS_BAD_PARAMETER;
            return mirror ? ONI_STATUS_NOT_SUPPORTED : ONI_STATUS_OK;
        }
        case ONI_STREAM_PROPERTY_CROPPING: {
            OniCropping cropping{};
            if (!take(data, size, &cropping)) return ONI_STATUS_BAD_PARAMETER;
            return cropping.enabled ? ONI_STATUS_NOT_SUPPORTED : ONI_STATUS_OK;
        }
        default:
            return ONI_STATUS_NOT_SUPPORTED;
    }
}

bool VirtualStream::push(const FramePair& pair, int frame_index) {
    std::lock_guard<std::mutex> lock(push_mutex_);
    if (!started_) return true;
    OniFrame* frame = getServices().acquireFrame();
    if (frame == nullptr) return false;
    const int bytes = bytes_per_frame();
    if (frame->data == nullptr || (frame->dataSize > 0 && frame->dataSize < bytes)) {
        getServices().releaseFrame(frame);
        return false;
    }
    const bool depth = shape_.sensor == ONI_SENSOR_DEPTH;
    std::memcpy(frame->data,
                depth ? static_cast<const void*>(pair.depth_mm.data()) : pair.rgb.data(),
                static_cast<size_t>(bytes));
    frame->dataSize = bytes;
    frame->sensorType = shape_.sensor;
    frame->timestamp = depth ? pair.depth_stamp_us : pair.rgb_stamp_us;
    frame->frameIndex = frame_index;
    frame->width = shape_.mode.resolutionX;
    frame->height = shape_.mode.resolutionY;
    frame->videoMode = shape_.mode;
    frame->croppingEnabled = FALSE;
    frame->cropOriginX = 0;
    frame->cropOriginY = 0;
    frame->stride = shape_.mode.resolutionX * bytes_per_pixel();
    raiseNewFrame(frame);
    getServices().releaseFrame(frame);
    return true;
}

}  // namespace df::virtual_camera
