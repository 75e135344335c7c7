#include "drivers/v4l2/v4l2_camera.h"

#include <sys/epoll.h>
#include <time.h>

#include <algorithm>
#include <cmath>

#include "runtime/log.h"
#include "runtime/node.h"
#include "runtime/node_config.h"
#include "wire/check.h"
#include "wire/image.h"

namespace troupe::drivers::v4l2 {
namespace {

constexpr float kPi = 3.14159265f;

uint64_t monotonic_us() {
  timespec ts{};
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return uint64_t(ts.tv_sec) * 1000000u + uint64_t(ts.tv_nsec) / 1000u;
}

const char* fourcc_name(Fourcc f) {
  switch (f) {
    case Fourcc::Rgb24:
      return "RGB24";
    case Fourcc::Yuyv:
      return "YUYV";
    case Fourcc::Grey:
      return "GREY";
  }
  return "?";
}

bool image_size_ok(uint32_t width, uint32_t height, wire::PixelFormat format, size_t max_frame_bytes,
                   std::string& error) {
  if (width < 1 || height < 1 || width > wire::kMaxImageSide || height > wire::kMaxImageSide) {
    error = "camera images are 1 to " + std::to_string(wire::kMaxImageSide) + " pixels each way, not " +
            std::to_string(width) + "x" + std::to_string(height);
    return false;
  }
  return wire::image_fits(width, height, format, max_frame_bytes, error);
}

}  // namespace

bool read_options(const Options& o, size_t max_frame_bytes, CameraOptions& out, std::string& error) {
  if (o.device() == nullptr || o.device()->size() == 0) {
    error = "option \"device\" is missing: the camera's video device, e.g. \"/dev/video0\"";
    return false;
  }
  out.device = o.device()->str();
  out.width = o.width();
  out.height = o.height();
  out.format = o.format() == ImageFormat::Mono8 ? wire::PixelFormat::Mono8 : wire::PixelFormat::Rgb8;
  if (!image_size_ok(out.width, out.height, out.format, max_frame_bytes, error)) {
    error = "options \"width\" and \"height\": " + error;
    return false;
  }
  if (!(o.rate() > 0 && o.rate() <= wire::kMaxImageRate)) {
    error =
        "option \"rate\": images per second, more than 0 and at most 1000, not " + std::to_string(o.rate());
    return false;
  }
  out.rate = o.rate();
  switch (o.capture_format()) {
    case CaptureFormat::Rgb24:
      out.capture_formats[0] = Fourcc::Rgb24;
      out.capture_format_count = 1;
      break;
    case CaptureFormat::Yuyv:
      out.capture_formats[0] = Fourcc::Yuyv;
      out.capture_format_count = 1;
      break;
    case CaptureFormat::Grey:
      out.capture_formats[0] = Fourcc::Grey;
      out.capture_format_count = 1;
      break;
    default:  // Auto: RGB24 needs no conversion, YUYV is what webcams give, then GREY
      out.capture_format_count = 3;
      break;
  }
  if (o.buffers() < 2 || o.buffers() > Capture::kMaxBuffers) {
    error = "option \"buffers\": 2 to " + std::to_string(Capture::kMaxBuffers) + " capture buffers, not " +
            std::to_string(o.buffers());
    return false;
  }
  out.buffers = o.buffers();
  const float pose[] = {o.pose_x(), o.pose_y(), o.pose_z(), o.pose_pitch(), o.pose_yaw()};
  if (!std::all_of(std::begin(pose), std::end(pose), [](float v) { return std::isfinite(v); })) {
    error = "options \"pose_*\" must be finite (m, rad)";
    return false;
  }
  out.pose_x = o.pose_x();
  out.pose_y = o.pose_y();
  out.pose_z = o.pose_z();
  out.pose_pitch = o.pose_pitch();
  out.pose_yaw = o.pose_yaw();
  if (!(o.hfov() > 0 && o.hfov() < kPi) || !(o.vfov() >= 0 && o.vfov() < kPi)) {
    error = "options \"hfov\" (more than 0) and \"vfov\" (0: from hfov) are fields of view below pi rad";
    return false;
  }
  out.hfov = o.hfov();
  out.vfov = o.vfov();
  if (!(o.near() >= 0) || !(o.far() >= 0) || (o.far() > 0 && o.far() < o.near())) {
    error = "options \"near\" and \"far\": distances, m, 0 <= near <= far (0: not stated)";
    return false;
  }
  out.near = o.near();
  out.far = o.far();
  if (o.frame_timeout_ms() < 200) {
    error = "option \"frame_timeout_ms\" must be at least 200, not " + std::to_string(o.frame_timeout_ms());
    return false;
  }
  if (o.reopen_min_ms() == 0 || o.reopen_max_ms() < o.reopen_min_ms()) {
    error = "options \"reopen_min_ms\" > 0 and \"reopen_max_ms\" >= it";
    return false;
  }
  out.frame_timeout_us = o.frame_timeout_ms() * 1000ull;
  out.reopen_min_us = o.reopen_min_ms() * 1000ull;
  out.reopen_max_us = o.reopen_max_ms() * 1000ull;
  return true;
}

bool V4l2Camera::setup(Node& node, const DriverSetup& setup, std::string& error) {
  name_ = setup.name;
  if (setup.provides.size() != 1 ||
      node.address(setup.provides[0]).iface() != uint16_t(wire::Interface::Camera)) {
    error = "v4l2 provides exactly one camera device";
    return false;
  }
  camera_ = setup.provides[0];
  OptionsView<Options> opt(setup);
  if (!read_options(*opt.operator->(), node.options().limits.max_frame_bytes, want_, error)) return false;
  tick_ = node.loop().start_timer(kTickUs, kTickUs, this);
  if (tick_ == 0) {
    error = "no timer left for the camera";
    return false;
  }
  // A camera not plugged in yet is no reason to refuse to start: the node
  // serves its other devices and the tick keeps trying.
  std::string why;
  if (!start(why)) lose(why);
  return true;
}

bool V4l2Camera::start(std::string& error) {
  CaptureRequest req;
  req.device = want_.device;
  req.width = want_.width;
  req.height = want_.height;
  req.rate = want_.rate;
  req.formats = want_.capture_formats;
  req.format_count = want_.capture_format_count;
  req.buffers = want_.buffers;
  if (!capture_.open(req, error)) return false;
  // The camera may give a larger image than asked for; one that cannot be
  // sent is refused here, never truncated.
  if (!image_size_ok(capture_.width(), capture_.height(), want_.format,
                     node_->options().limits.max_frame_bytes, error)) {
    error = want_.device + " gives " + std::to_string(capture_.width()) + "x" +
            std::to_string(capture_.height()) + ": " + error;
    capture_.close();
    return false;
  }
  if (!node_->loop().watch(capture_.fd(), EPOLLIN, this)) {
    error = "cannot watch " + want_.device + " in the loop";
    capture_.close();
    return false;
  }
  state_ = State::Streaming;
  failures_ = 0;
  backoff_us_ = 0;
  last_frame_us_ = node_->loop().now_us();
  last_publish_us_ = 0;
  log_info("%s: %s streams %ux%u %s at %.1f images/s", name_.c_str(), want_.device.c_str(), capture_.width(),
           capture_.height(), fourcc_name(capture_.format()), double(capture_.rate()));
  return true;
}

void V4l2Camera::stop() {
  if (capture_.is_open()) node_->loop().unwatch(capture_.fd());
  capture_.close();
  state_ = State::Closed;
}

void V4l2Camera::lose(const std::string& why) {
  stop();
  node_->forget_data(camera_);
  down_why_ = why;
  // Said once per outage; the retries that fail the same way are debug.
  if (failures_++ == 0) {
    log_warn("%s: %s; trying again", name_.c_str(), why.c_str());
  } else {
    log_debug("%s: %s", name_.c_str(), why.c_str());
  }
  backoff_us_ = backoff_us_ == 0 ? want_.reopen_min_us : std::min(2 * backoff_us_, want_.reopen_max_us);
  reopen_at_us_ = node_->loop().now_us() + backoff_us_;
}

void V4l2Camera::on_timer(TimerId) {
  const uint64_t now = node_->loop().now_us();
  if (state_ == State::Closed) {
    if (now < reopen_at_us_) return;
    std::string why;
    if (!start(why)) lose(why);
    return;
  }
  if (now - last_frame_us_ > want_.frame_timeout_us) {
    lose(want_.device + ": no image for " + std::to_string((now - last_frame_us_) / 1000) + " ms");
  }
}

void V4l2Camera::on_fd(int, uint32_t events) {
  if (state_ != State::Streaming) return;
  if (events & (EPOLLERR | EPOLLHUP)) {
    // A device unplugged (or its driver unbound), or whose queue failed,
    // reports an error on poll.
    return lose(want_.device + ": the device reports an error (a streaming error, or unplugged)");
  }
  std::string why;
  for (;;) {
    Frame frame;
    switch (capture_.dequeue(frame, why)) {
      case Dequeued::Nothing:
        return;
      case Dequeued::Lost:
        return lose(why);
      case Dequeued::Frame:
        handle(frame);
        if (!capture_.release(frame, why)) return lose(why);
        break;
    }
  }
}

void V4l2Camera::handle(const Frame& frame) {
  const uint64_t now = node_->loop().now_us();
  last_frame_us_ = now;
  if (frame.bytes == 0 || !node_->has_readers(camera_)) return;
  // The rate option also caps what is sent, for cameras that ignore it;
  // three quarters of the period lets a camera at exactly that rate, with
  // its jitter, through.
  const uint64_t period_us = uint64_t(1e6f / want_.rate);
  if (last_publish_us_ != 0 && now - last_publish_us_ < period_us - period_us / 4) return;
  last_publish_us_ = now;

  const uint32_t w = capture_.width(), h = capture_.height();
  const bool rgb = want_.format == wire::PixelFormat::Rgb8;
  const size_t row = size_t(w) * (rgb ? 3 : 1);
  auto& b = node_->begin();
  uint8_t* pixels = nullptr;
  auto data = b.CreateUninitializedVector(row * h, &pixels);
  convert_image(capture_.format(), frame.data, capture_.stride(), w, h, capture_.full_range(), rgb, pixels);
  // The camera's exposure time in the node's clock: its age now, taken
  // from the node's time (the header carries the time of sending).
  uint64_t stamp = 0;
  if (frame.monotonic_us != 0) {
    const uint64_t mono = monotonic_us();
    const uint64_t age = mono > frame.monotonic_us ? mono - frame.monotonic_us : 0;
    const uint64_t node_now = node_->now_us();
    stamp = node_now > age ? node_now - age : 0;
  }
  auto body = wire::CreateCameraImage(b, uint16_t(w), uint16_t(h), want_.format, uint32_t(row),
                                      wire::ImageCompression::None, data, stamp);
  node_->publish(camera_, uint8_t(wire::CameraDataSub::Image), wire::Body::CameraImage, body.Union());
}

void V4l2Camera::on_read_start(DeviceId) {
  // The stored image may be old (nobody read the camera); the next one
  // comes within a frame time.
  node_->forget_data(camera_);
}

void V4l2Camera::on_request(DeviceId device, const wire::Message& req, RequestToken token) {
  using Sub = wire::CameraReqSub;
  switch (Sub(req.header()->subtype())) {
    case Sub::Geometry: {
      // The pinhole model of the configured fields of view over the image
      // in force (the asked-for size while the camera is away).
      const bool open = state_ == State::Streaming;
      const float w = float(open ? capture_.width() : want_.width);
      const float h = float(open ? capture_.height() : want_.height);
      const float fx = 0.5f * w / std::tan(0.5f * want_.hfov);
      const float vfov = want_.vfov > 0 ? want_.vfov : 2.0f * std::atan(0.5f * h / fx);
      const float fy = 0.5f * h / std::tan(0.5f * vfov);
      auto& b = node_->begin();
      wire::Pose3d pose(want_.pose_x, want_.pose_y, want_.pose_z, 0, want_.pose_pitch, want_.pose_yaw);
      auto body = wire::CreateCameraGeometry(b, &pose, want_.hfov, vfov, fx, fy, 0.5f * w, 0.5f * h,
                                             want_.near, want_.far);
      return node_->ack(token, wire::Body::CameraGeometry, body.Union());
    }
    case Sub::GetConfig:
      return reply_config(token);
    case Sub::SetConfig:
      return set_config(req, token);
    default:
      break;
  }
  Driver::on_request(device, req, token);
}

void V4l2Camera::reply_config(RequestToken token) {
  if (state_ != State::Streaming) {
    return node_->nack(token, wire::ErrorCode::DeviceFailed, "camera unavailable: " + down_why_);
  }
  // The rate in force: the camera's, capped by the one asked for.
  const float rate = capture_.rate() > 0 ? std::min(capture_.rate(), want_.rate) : want_.rate;
  auto& b = node_->begin();
  auto body = wire::CreateCameraConfig(b, uint16_t(capture_.width()), uint16_t(capture_.height()), rate,
                                       want_.format);
  node_->ack(token, wire::Body::CameraConfig, body.Union());
}

void V4l2Camera::set_config(const wire::Message& req, RequestToken token) {
  const wire::CameraConfig* c = req.body_as_CameraConfig();  // check_message() made sure it is there
  if (c->format() != wire::PixelFormat::Rgb8 && c->format() != wire::PixelFormat::Mono8) {
    return node_->nack(token, wire::ErrorCode::BadArgument, "a V4L2 camera gives Rgb8 or Mono8 images");
  }
  CameraOptions next = want_;
  next.width = c->width() ? c->width() : want_.width;
  next.height = c->height() ? c->height() : want_.height;
  next.rate = c->rate() > 0 ? c->rate() : want_.rate;
  next.format = c->format();
  std::string why;
  // An image that could never be sent is refused here, with the reason,
  // rather than configured and then never delivered.
  if (!image_size_ok(next.width, next.height, next.format, node_->options().limits.max_frame_bytes, why)) {
    return node_->nack(token, wire::ErrorCode::BadArgument, why);
  }
  if (state_ != State::Streaming) {
    return node_->nack(token, wire::ErrorCode::DeviceFailed, "camera unavailable: " + down_why_);
  }
  // Size and rate are negotiated only while the camera is not streaming.
  const CameraOptions before = want_;
  want_ = next;
  stop();
  if (start(why)) return reply_config(token);
  // The camera refused the new settings: back to the ones that worked. If
  // it refuses those too, it failed rather than the request.
  want_ = before;
  std::string again;
  if (start(again)) return node_->nack(token, wire::ErrorCode::BadArgument, why);
  lose(again);
  node_->nack(token, wire::ErrorCode::DeviceFailed, "camera unavailable: " + again);
}

void V4l2Camera::shutdown() {
  stop();
  if (tick_ != 0) node_->loop().cancel_timer(tick_);
  tick_ = 0;
}

extern const DriverEntry kEntry;
const DriverEntry kEntry{"v4l2", []() -> Driver* { return new V4l2Camera; }};

}  // namespace troupe::drivers::v4l2
