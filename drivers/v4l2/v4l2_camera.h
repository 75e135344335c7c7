// v4l2: a Linux V4L2 camera (USB webcam, the Raspberry Pi camera through its
// V4L2 driver) served as a camera device.
//
// Provides: camera (exactly one): Rgb8 or Mono8 images, converted from the
// camera's RGB24, YUYV or GREY. Requests: Geometry (the pose and fov
// options, the image size), GetConfig, SetConfig (size, rate, format).
//
// Single-threaded and never blocking: the device is opened non-blocking,
// its fd watched in the node's loop (a filled buffer makes it readable) and
// one 100 ms tick reopens or watches it:
//
//   Closed --open + negotiate + STREAMON--> Streaming --DQBUF/QBUF--> publish
//     ^  (fails: again after a backoff,       |
//     |   doubled up to reopen_max_ms)        | ENODEV/EIO, poll error, or no
//     +---------------------------------------+ image for frame_timeout_ms
//
// While Closed the device's stored image is dropped and GetConfig and
// SetConfig are refused with DeviceFailed and the reason, so a client sees
// the camera is gone rather than waiting; every other device of the node
// is served meanwhile.
#pragma once

#include <cstdint>
#include <string>

#include "drivers/v4l2/capture.h"
#include "runtime/driver.h"

namespace troupe::drivers::v4l2 {

struct Options;  // v4l2.fbs, generated into the node config schema

/// The options, checked and in SI units.
struct CameraOptions {
  std::string device;
  uint32_t width = 0, height = 0;  // px
  float rate = 0;                  // images per second
  wire::PixelFormat format = wire::PixelFormat::Rgb8;
  Fourcc capture_formats[3] = {Fourcc::Rgb24, Fourcc::Yuyv, Fourcc::Grey};
  size_t capture_format_count = 3;
  uint32_t buffers = 4;
  float pose_x = 0, pose_y = 0, pose_z = 0, pose_pitch = 0, pose_yaw = 0;  // m, rad
  float hfov = 1, vfov = 0;  // rad (vfov 0: from hfov and the image's shape)
  float near = 0, far = 0;   // m
  uint64_t frame_timeout_us = 0, reopen_min_us = 0, reopen_max_us = 0;
};

/// Checks `o` (the node config's options) into `out`. False with `error`
/// naming the option and what it may be. `max_frame_bytes`: the node's
/// frame limit, which the configured image must fit.
bool read_options(const Options& o, size_t max_frame_bytes, CameraOptions& out, std::string& error);

class V4l2Camera final : public Driver {
 public:
  enum class State : uint8_t { Closed, Streaming };

  bool setup(Node& node, const DriverSetup& setup, std::string& error) override;
  void on_request(DeviceId device, const wire::Message& request, RequestToken token) override;
  void on_read_start(DeviceId device) override;
  void on_fd(int fd, uint32_t events) override;
  void on_timer(TimerId id) override;
  void shutdown() override;

 private:
  // Opens the camera with want_; on failure stays Closed, `error` says why.
  bool start(std::string& error);
  void stop();
  // The camera failed or vanished: close, drop the stale image, reopen later.
  void lose(const std::string& why);
  void handle(const Frame& frame);
  void reply_config(RequestToken token);
  void set_config(const wire::Message& request, RequestToken token);

  static constexpr uint64_t kTickUs = 100'000;

  std::string name_ = "v4l2";
  DeviceId camera_ = kNoDevice;
  CameraOptions want_;
  Capture capture_;
  State state_ = State::Closed;
  TimerId tick_ = 0;
  // Why the camera is closed, for the Nacks while it is.
  std::string down_why_ = "not opened yet";
  uint64_t reopen_at_us_ = 0, backoff_us_ = 0;
  uint32_t failures_ = 0;
  uint64_t last_frame_us_ = 0, last_publish_us_ = 0;
};

}  // namespace troupe::drivers::v4l2
