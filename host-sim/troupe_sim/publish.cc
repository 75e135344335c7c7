// The data messages of the simulated devices.
#include <algorithm>
#include <cmath>
#include <cstring>
#include <string>

#include "wire/image.h"
#include "wire/log.h"
#include "wire/png.h"

#include "host-sim/sim_control/kicker_state.h"
#include "host-sim/troupe_sim/sim_server.h"

namespace troupe::sim {

void SimServer::publish() {
  woken_.clear();
  for (Device& d : devices_) publish_if_read(d);
}

void SimServer::publish_woken() {
  for (uint32_t i : woken_) publish_if_read(devices_[i]);
  woken_.clear();
}

void SimServer::publish_if_read(Device& d) {
  if (!node_->has_readers(d.id)) return;
  if (d.kind == Kind::Camera) {
    publish_camera(d);
  } else {
    publish_one(d);
  }
}

void SimServer::on_read_start(DeviceId id) {
  const Device* d = find(id);
  if (d == nullptr || d->kind == Kind::Map) return;
  // publish() skips a device nobody reads: what the node holds for this one
  // is from when it was last read (the robot may have driven on since). The
  // new reader gets the current sample, or, for a sensor not computed at
  // this step, nothing until a step computes it.
  node_->forget_data(id);
  uint64_t computed_at = world_.steps();
  switch (d->kind) {
    case Kind::Ranger:
      computed_at = world_.ranger(d->index).step;
      break;
    case Kind::Blobfinder:
      computed_at = world_.blobfinder(d->index).step;
      break;
    case Kind::Fiducial:
      computed_at = world_.fiducial(d->index).step;
      break;
    case Kind::Bumper:
      computed_at = world_.bumper(d->index).step;
      break;
    case Kind::Camera:
      computed_at = world_.camera(d->index).step;
      break;
    default:
      break;
  }
  // A camera's image goes out from on_packing_start(), which follows, packed
  // as the reader asked.
  if (computed_at != world_.steps() || d->kind == Kind::Camera) return;
  publish_one(*d);
}

void SimServer::on_packing_start(DeviceId id, wire::ImageCompression compression) {
  const Device* d = find(id);
  if (d == nullptr || d->kind != Kind::Camera || world_.camera(d->index).step != world_.steps()) return;
  publish_camera(devices_[id - first_], compression);  // now, whatever the rate
}

void SimServer::publish_one(const Device& d) {
  switch (d.kind) {
    case Kind::Position:
      publish_position(d);
      break;
    case Kind::Ranger:
      publish_ranger(d);
      break;
    case Kind::Blobfinder:
      publish_blobs(d);
      break;
    case Kind::Fiducial:
      publish_fiducials(d);
      break;
    case Kind::Bumper:
      publish_bumper(d);
      break;
    case Kind::Power:
      publish_power(d);
      break;
    case Kind::Gripper:
      publish_gripper(d);
      break;
    case Kind::Kicker:
      publish_kicker_state(*node_, d.id, kickers_.ready(d.index));
      break;
    case Kind::Camera:  // publish_camera(): it keeps state per device
      break;
    case Kind::Simulation:
      publish_clock(d);
      publish_poses(d);
      break;
    case Kind::Map:
      break;
  }
}

void SimServer::publish_position(const Device& d) {
  const RobotState& s = world_.state(d.robot);
  auto& b = node_->begin();
  wire::Pose2d pose(float(s.odometry.x), float(s.odometry.y), float(s.odometry.a));
  wire::Pose2d vel(float(s.velocity.x), float(s.velocity.y), float(s.velocity.a));
  auto body = wire::CreatePosition2dState(b, &pose, &vel, s.stalled);
  node_->publish(d.id, uint8_t(wire::Position2dDataSub::State), wire::Body::Position2dState, body.Union());
}

void SimServer::publish_ranger(const Device& d) {
  const RangerView v = world_.ranger(d.index);
  if (v.step == UINT64_MAX) return;  // not computed yet
  const RangerDesc& rd = world_.ranger_desc(d.index);
  double max_range = 0;
  for (const TransducerDesc& t : rd.transducers) max_range = std::max(max_range, t.range_max);
  // Millimetres unless the sensor reaches beyond what 16 bits of them hold.
  const double scale = max_range <= 65.535 ? 0.001 : max_range / 65535.0;
  scratch_ranges_.resize(v.ranges.size());
  for (size_t i = 0; i < v.ranges.size(); ++i) {
    scratch_ranges_[i] = uint16_t(std::clamp(std::lround(v.ranges[i] / scale), 0L, 65535L));
  }
  float min_angle = 0, res = 0;
  if (rd.transducers.size() == 1 && rd.transducers[0].samples > 1) {
    const TransducerDesc& t = rd.transducers[0];
    min_angle = float(wrap_angle(t.pose.a - rd.pose.a) - t.fov / 2);
    res = float(t.fov / (t.samples - 1));
  }
  auto& b = node_->begin();
  auto ranges = b.CreateVector(scratch_ranges_);
  auto body = wire::CreateRangerScan(b, ranges, float(scale), min_angle, res, float(max_range));
  node_->publish(d.id, uint8_t(wire::RangerDataSub::Scan), wire::Body::RangerScan, body.Union());
}

void SimServer::publish_blobs(const Device& d) {
  const BlobView v = world_.blobfinder(d.index);
  if (v.step == UINT64_MAX) return;
  std::vector<wire::Blob> blobs;
  blobs.reserve(v.blobs.size());
  for (const Blob& bl : v.blobs) {
    const uint16_t range_mm = uint16_t(std::clamp(std::lround(bl.range * 1000), 0L, 65535L));
    blobs.emplace_back(bl.color, bl.area, uint16_t(std::lround(bl.x)), uint16_t(std::lround(bl.y)),
                       uint16_t(bl.left), uint16_t(bl.right), uint16_t(bl.top), uint16_t(bl.bottom), range_mm,
                       uint16_t(bl.channel));
  }
  auto& b = node_->begin();
  auto body = wire::CreateBlobList(b, b.CreateVectorOfStructs(blobs), uint16_t(v.width), uint16_t(v.height));
  node_->publish(d.id, uint8_t(wire::BlobfinderDataSub::Blobs), wire::Body::BlobList, body.Union());
}

void SimServer::publish_fiducials(const Device& d) {
  const FiducialView v = world_.fiducial(d.index);
  if (v.step == UINT64_MAX) return;
  std::vector<wire::Fiducial> out;
  out.reserve(v.readings.size());
  for (const FiducialReading& f : v.readings) {
    out.emplace_back(f.id, float(f.pose.x), float(f.pose.y), float(f.pose.a));
  }
  auto& b = node_->begin();
  auto body = wire::CreateFiducialList(b, b.CreateVectorOfStructs(out));
  node_->publish(d.id, uint8_t(wire::FiducialDataSub::Detections), wire::Body::FiducialList, body.Union());
}

void SimServer::publish_gripper(const Device& d) {
  const GripperView g = world_.gripper(d.index);
  auto& b = node_->begin();
  auto body = wire::CreateActuatorState(b, g.closed ? wire::ActuatorMode::Closed : wire::ActuatorMode::Open,
                                        0.0f, 0, uint8_t(g.holding ? 1 : 0));
  node_->publish(d.id, uint8_t(wire::ActuatorDataSub::State), wire::Body::ActuatorState, body.Union());
}

void SimServer::publish_bumper(const Device& d) {
  const BumperView v = world_.bumper(d.index);
  if (v.step == UINT64_MAX) return;
  auto& b = node_->begin();
  auto body = wire::CreateBumperState(b, v.pressed, uint8_t(std::min<uint32_t>(v.count, 255)));
  node_->publish(d.id, uint8_t(wire::BumperDataSub::State), wire::Body::BumperState, body.Union());
}

void SimServer::publish_camera(Device& d, std::optional<wire::ImageCompression> only) {
  const CameraView v = world_.camera(d.index);
  if (v.step == UINT64_MAX || v.width == 0) return;
  if (!only && d.rate > 0 && d.last_image >= 0 && world_.time() - d.last_image < 1.0 / d.rate - 1e-9) return;
  std::string why;
  if (!wire::image_fits(uint32_t(v.width), uint32_t(v.height), d.format, node_->options().limits.max_frame_bytes,
                        why)) {
    // Refused, never truncated; said once per configuration, not every step.
    if (!d.refused_logged) log_error("troupe-sim: camera of robot %s: %s", world_.robot(d.robot).name.c_str(), why.c_str());
    d.refused_logged = true;
    return;
  }
  const size_t n = size_t(v.width) * size_t(v.height);
  const size_t bpp = wire::bytes_per_pixel(d.format);
  scratch_pixels_.resize(n * bpp);
  uint8_t* out = scratch_pixels_.data();
  switch (d.format) {
    case wire::PixelFormat::Rgb8:
      std::copy(v.rgb.begin(), v.rgb.end(), out);
      break;
    case wire::PixelFormat::Mono8:
      // Rec. 601 luma in integers, so every host gives the same bytes.
      for (size_t i = 0; i < n; ++i) {
        const uint8_t* p = v.rgb.data() + 3 * i;
        out[i] = uint8_t((299u * p[0] + 587u * p[1] + 114u * p[2] + 500u) / 1000u);
      }
      break;
    case wire::PixelFormat::DepthF32:
      for (size_t i = 0; i < n; ++i) {
        uint32_t bits;
        std::memcpy(&bits, &v.depth[i], 4);
        for (int k = 0; k < 4; ++k) out[4 * i + size_t(k)] = uint8_t(bits >> (8 * k));  // little-endian
      }
      break;
    case wire::PixelFormat::DepthU16:
      for (size_t i = 0; i < n; ++i) {
        const float m = v.depth[i];
        const long mm = std::isfinite(m) ? std::lround(double(m) * 1000) : 0;
        const uint16_t q = mm > 65535 ? 0 : uint16_t(mm);  // beyond 16 bits: "nothing", as the schema says
        out[2 * i] = uint8_t(q);
        out[2 * i + 1] = uint8_t(q >> 8);
      }
      break;
  }
  const uint32_t stride = uint32_t(size_t(v.width) * bpp);
  // Each packing readers asked for is published once, to them only: PNG
  // readers share one encoding of the image. An image with no PNG form
  // (DepthF32), or whose PNG would not fit a frame, reaches them raw.
  for (auto packing : {wire::ImageCompression::None, wire::ImageCompression::Png}) {
    if (only ? *only != packing : !node_->has_readers(d.id, packing)) continue;
    std::string png_why;
    const bool png =
        packing == wire::ImageCompression::Png &&
        wire::encode_png({uint32_t(v.width), uint32_t(v.height), d.format, stride, scratch_pixels_},
                         scratch_png_, png_why) &&
        scratch_png_.size() + wire::kImageEnvelopeBytes <= node_->options().limits.max_frame_bytes;
    auto& b = node_->begin();
    auto data = b.CreateVector(png ? scratch_png_ : scratch_pixels_);
    auto body = wire::CreateCameraImage(b, uint16_t(v.width), uint16_t(v.height), d.format, png ? 0 : stride,
                                        png ? packing : wire::ImageCompression::None, data);
    // No stamp_us: the image is of this step, whose time the header carries.
    node_->publish_packed(d.id, packing, uint8_t(wire::CameraDataSub::Image), wire::Body::CameraImage,
                          body.Union());
  }
  if (!only) d.last_image = world_.time();
}

void SimServer::publish_power(const Device& d) {
  const PowerView p = world_.power(d.robot);
  auto& b = node_->begin();
  const float percent = p.capacity > 0 ? float(100.0 * p.joules / p.capacity) : 0.0f;
  auto body =
      wire::CreatePowerState(b, flatbuffers::nullopt, percent, float(p.joules), float(p.watts), false);
  node_->publish(d.id, uint8_t(wire::PowerDataSub::State), wire::Body::PowerState, body.Union());
}

void SimServer::publish_clock(const Device& d) {
  auto& b = node_->begin();
  auto body = wire::CreateSimClock(b, uint64_t(std::llround(world_.time() * 1e6)), world_.steps(),
                                   control_.paused, float(control_.speed), float(control_.real_time_factor));
  node_->publish(d.id, uint8_t(wire::SimulationDataSub::Clock), wire::Body::SimClock, body.Union());
}

}  // namespace troupe::sim
