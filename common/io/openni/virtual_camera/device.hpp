#pragma once
/// The virtual OpenNI2 device: plays a recorded sequence through a colour and a depth stream.
///
/// Timed mode (default): frames leave at the pace of the sequence's depth stamps, once every
/// created stream has been started; a reader that falls behind loses frames, as with a camera.
/// Lockstep mode (DF_VIRTUAL_CAMERA_LOCKSTEP=1): OpenNI pokes the device (tryManualTrigger) when a
/// reader waits and no frame is ready; each poke sends the next frame pair, so nothing is lost.
/// After the last frame the device reports itself disconnected (or starts over with
/// DF_VIRTUAL_CAMERA_LOOP=1, stamps continuing to increase).
#include <Driver/OniDriverAPI.h>

#include <chrono>
#include <condition_variable>
#include <functional>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "sequence.hpp"
#include "stream.hpp"

namespace df::virtual_camera {

/// How the device reaches the driver: a warning line, and "the sequence is over".
struct DeviceHooks {
    std::function<void(const std::string&)> warn;
    std::function<void()> ended;
};

class VirtualDevice final : public oni::driver::DeviceBase {
  public:
    VirtualDevice(Sequence sequence, Settings settings, DeviceHooks hooks);
    ~VirtualDevice() override;
    VirtualDevice(const VirtualDevice&) = delete;
    VirtualDevice& operator=(const VirtualDevice&) = delete;

    OniStatus getSensorInfoList(OniSensorInfo** sensors, int* count) override;
    oni::driver::StreamBase* createStream(OniSensorType sensor) override;
    void destroyStream(oni::driver::StreamBase* stream) override;

    OniStatus setProperty(int property, const void* data, int size) override;
    OniStatus getProperty(int property, void* data, int* size) override;
    OniBool isPropertySupported(int property) override;
    OniBool isImageRegistrationModeSupported(OniImageRegistrationMode mode) override;
    OniStatus tryManualTrigger() override;

  private:
    using Clock = std::chrono::steady_clock;

    StreamShape shape_of(OniSensorType sensor) const;
    bool all_streams_started() const;  // needs streams_mutex_
    void on_start_stop();
    void play_loop();
    /// Decodes the next entry and sends it to the started streams. False when the sequence is
    /// over (and not looping). Called by one producer at a time (player thread or trigger).
    bool send_next();

    const Sequence sequence_;
    const Settings settings_;
    const DeviceHooks hooks_;
    std::vector<OniVideoMode> color_modes_, depth_modes_;
    std::vector<OniSensorInfo> sensor_infos_;

    // Never held while calling into OpenNI (OpenNI holds its own locks when it calls us).
    mutable std::mutex streams_mutex_;  // streams_, registration_, quit_
    std::condition_variable player_wake_;
    std::vector<std::shared_ptr<VirtualStream>> streams_;  // shared: a send may outlive removal
    OniImageRegistrationMode registration_ = ONI_IMAGE_REGISTRATION_OFF;
    bool quit_ = false;
    std::thread player_;

    // Position in the sequence; touched by the one producer only (player or trigger_mutex_).
    std::mutex trigger_mutex_;
    size_t next_entry_ = 0;
    uint64_t stamp_offset_us_ = 0;  // added to the stamps when looping, so they keep increasing
    int frame_index_ = 0;
    bool ended_ = false;
    FramePair pair_;
};

}  // namespace df::virtual_camera
