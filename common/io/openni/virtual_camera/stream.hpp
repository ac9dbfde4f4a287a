#pragma once
/// One sensor stream (colour RGB888 or depth DEPTH_1_MM) of the virtual OpenNI2 camera.
#include <Driver/OniDriverAPI.h>

#include <atomic>
#include <functional>
#include <mutex>

#include "sequence.hpp"

namespace df::virtual_camera {

/// What a stream serves: its single video mode and its field of view.
struct StreamShape {
    OniSensorType sensor = ONI_SENSOR_DEPTH;
    OniVideoMode mode{};
    float horizontal_fov_rad = 0.0f, vertical_fov_rad = 0.0f;
    int max_value = 0;  ///< largest depth value (mm) the stream can carry; 0 for colour
};

class VirtualStream final : public oni::driver::StreamBase {
  public:
    /// `on_start_stop` is called (on the caller's thread) after start() and stop().
    VirtualStream(const StreamShape& shape, std::function<void()> on_start_stop);

    OniStatus start() override;
    /// After stop() returns no push() is running or will send a frame: OpenNI may then free
    /// what our frame callback points to. OpenNI stops a stream before destroying it.
    void stop() override;
    bool started() const { return started_; }
    OniSensorType sensor() const { return shape_.sensor; }

    OniStatus setProperty(int property, const void* data, int size) override;
    OniStatus getProperty(int property, void* data, int* size) override;
    OniBool isPropertySupported(int property) override;
    int getRequiredFrameSize() override { return bytes_per_frame(); }

    /// Copies the stream's half of `pair` into an OpenNI frame and hands it to OpenNI, if the
    /// stream is started. False when OpenNI gave no frame buffer (then nothing was sent).
    bool push(const FramePair& pair, int frame_index);

  private:
    int bytes_per_pixel() const;
    int bytes_per_frame() const;

    StreamShape shape_;
    std::function<void()> on_start_stop_;
    std::mutex push_mutex_;  // held while a frame is handed to OpenNI; start/stop wait for it
    std::atomic<bool> started_{false};
};

}  // namespace df::virtual_camera
