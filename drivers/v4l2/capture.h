// A V4L2 capture device, memory-mapped streaming, through the kernel's
// ioctls only (<linux/videodev2.h>, no libv4l). Opened non-blocking: the
// driver watches fd() in the node's loop and dequeues when it is readable.
//
//   open:  open(O_NONBLOCK) -> QUERYCAP (capture + streaming) -> ENUM_FMT
//          (pick the format) -> S_FMT (size) -> S_PARM (rate) -> REQBUFS
//          (mmap) -> QUERYBUF + mmap + QBUF each -> STREAMON
//   run:   DQBUF (EAGAIN: nothing yet) -> read the buffer -> QBUF it back
//   close: STREAMOFF, munmap, close
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>

#include "drivers/v4l2/pixel_convert.h"

namespace troupe::drivers::v4l2 {

/// What the driver asks a camera for.
struct CaptureRequest {
  std::string device;              // e.g. "/dev/video0"
  uint32_t width = 0, height = 0;  // px
  float rate = 0;                  // images per second
  /// Formats acceptable, in order of preference (the first the camera lists).
  const Fourcc* formats = nullptr;
  size_t format_count = 0;
  uint32_t buffers = 4;
};

/// One captured image, valid until Capture::release().
struct Frame {
  const uint8_t* data = nullptr;
  size_t bytes = 0;
  uint32_t index = 0;
  /// When the camera took it, CLOCK_MONOTONIC, us (0: the camera did not say).
  uint64_t monotonic_us = 0;
};

enum class Dequeued : uint8_t { Frame, Nothing, Lost };

class Capture {
 public:
  static constexpr uint32_t kMaxBuffers = 16;

  Capture() = default;
  ~Capture() { close(); }
  Capture(const Capture&) = delete;
  Capture& operator=(const Capture&) = delete;

  /// Opens, negotiates and starts streaming. False with `error` naming the
  /// device, the step that failed and the kernel's reason.
  bool open(const CaptureRequest& want, std::string& error);
  /// Stops streaming, unmaps, closes. Safe to call when closed.
  void close();
  bool is_open() const { return fd_ >= 0; }
  int fd() const { return fd_; }

  /// Takes the next filled buffer, if any. Lost: the device failed or
  /// vanished (`error` says how); close() it.
  Dequeued dequeue(Frame& frame, std::string& error);
  /// Gives the buffer back to the camera. False (with `error`) when the
  /// device failed.
  bool release(const Frame& frame, std::string& error);

  /// What was negotiated.
  Fourcc format() const { return format_; }
  uint32_t width() const { return width_; }    // px
  uint32_t height() const { return height_; }  // px
  size_t stride() const { return stride_; }    // bytes per row
  bool full_range() const { return full_range_; }
  /// Images per second in force (0: the camera does not say).
  float rate() const { return rate_; }

 private:
  bool fail(const std::string& step, std::string& error);

  int fd_ = -1;
  std::string device_;
  bool streaming_ = false;
  Fourcc format_ = Fourcc::Rgb24;
  uint32_t width_ = 0, height_ = 0;
  size_t stride_ = 0;
  bool full_range_ = false;
  float rate_ = 0;
  struct Mapping {
    void* start = nullptr;
    size_t length = 0;
  };
  Mapping buffers_[kMaxBuffers];
  uint32_t buffer_count_ = 0;
};

}  // namespace troupe::drivers::v4l2
