// Proxies of sensors: ranger, power, bumper, blobfinder, camera, fiducial, imu.
#include <cmath>
#include <cstring>

#include "wire/client/proxies.h"

namespace troupe::client {

using wire::Interface;

RangerProxy::RangerProxy(Client& client, uint16_t index, uint16_t robot)
    : RangerProxy(client, address_of(Interface::Ranger, index, robot)) {}

RangerProxy::RangerProxy(Client& client, const wire::Address& addr) : Proxy(client, addr) { attach(); }

void RangerProxy::update(const wire::Message& msg) {
  const wire::RangerScan* s = msg.body_as_RangerScan();
  if (s == nullptr) return;
  ranges_.clear();
  if (s->ranges()) {
    ranges_.reserve(s->ranges()->size());
    for (uint16_t r : *s->ranges()) ranges_.push_back(float(r) * s->scale());
  }
  intensities_.clear();
  if (s->intensities()) intensities_.assign(s->intensities()->begin(), s->intensities()->end());
  min_angle_ = s->min_angle();
  angular_res_ = s->angular_res();
  max_range_ = s->max_range();
}

bool RangerProxy::geometry(wire::Pose3d& pose, std::vector<wire::Pose3d>& elements) {
  Reply r = request(uint8_t(wire::RangerReqSub::Geometry));
  const wire::RangerGeometry* g = r.ok() ? r.message()->body_as_RangerGeometry() : nullptr;
  if (g == nullptr) return false;
  if (g->pose()) pose = *g->pose();
  copy_structs(g->elements(), elements);
  return true;
}

bool RangerProxy::set_power(bool on) {
  auto& b = client().begin();
  auto body = wire::CreateSwitch(b, on);
  return request(uint8_t(wire::RangerReqSub::Power), wire::Body::Switch, body.Union()).ok();
}

PowerProxy::PowerProxy(Client& client, uint16_t index, uint16_t robot)
    : Proxy(client, address_of(Interface::Power, index, robot)) {
  attach();
}

void PowerProxy::update(const wire::Message& msg) {
  const wire::PowerState* s = msg.body_as_PowerState();
  if (s == nullptr) return;
  auto get = [](const flatbuffers::Optional<float>& v) { return v ? std::optional<float>(*v) : std::nullopt; };
  volts_ = get(s->volts());
  percent_ = get(s->percent());
  watts_ = get(s->watts());
  charging_ = s->charging() ? std::optional<bool>(*s->charging()) : std::nullopt;
}

BumperProxy::BumperProxy(Client& client, uint16_t index, uint16_t robot)
    : Proxy(client, address_of(Interface::Bumper, index, robot)) {
  attach();
}

void BumperProxy::update(const wire::Message& msg) {
  if (const wire::BumperState* s = msg.body_as_BumperState()) {
    bits_ = s->pressed();
    count_ = s->count();
  }
}

BlobfinderProxy::BlobfinderProxy(Client& client, uint16_t index, uint16_t robot)
    : Proxy(client, address_of(Interface::Blobfinder, index, robot)) {
  attach();
}

void BlobfinderProxy::update(const wire::Message& msg) {
  const wire::BlobList* s = msg.body_as_BlobList();
  if (s == nullptr) return;
  copy_structs(s->blobs(), blobs_);
  width_ = s->width();
  height_ = s->height();
}

CameraProxy::CameraProxy(Client& client, uint16_t index, uint16_t robot, wire::ImageCompression compression)
    : Proxy(client, address_of(Interface::Camera, index, robot)) {
  attach(wire::Access::All, wire::Delivery::Push, compression);
}

void CameraProxy::update(const wire::Message& msg) {
  const wire::CameraImage* s = msg.body_as_CameraImage();
  if (s == nullptr) return;
  image_.width = s->width();
  image_.height = s->height();
  image_.format = s->format();
  image_.stride = s->stride();
  image_.compression = s->compression();
  image_.stamp_us = s->stamp_us() != 0 ? s->stamp_us() : wire::time_us(*msg.header());
  if (s->data()) {
    image_.data.assign(s->data()->begin(), s->data()->end());
  } else {
    image_.data.clear();
  }
}

float CameraProxy::depth(unsigned u, unsigned v) const {
  const Image& im = image_;
  if (im.compression != wire::ImageCompression::None || u >= im.width || v >= im.height) return NAN;
  const size_t at = size_t(v) * im.stride;
  if (im.format == wire::PixelFormat::DepthF32) {
    if (at + (u + 1) * 4 > im.data.size()) return NAN;
    // The wire is little-endian, as every host this library builds for.
    float d;
    std::memcpy(&d, im.data.data() + at + u * 4, 4);
    return d;
  }
  if (im.format == wire::PixelFormat::DepthU16) {
    if (at + (u + 1) * 2 > im.data.size()) return NAN;
    const uint16_t mm = uint16_t(im.data[at + u * 2] | im.data[at + u * 2 + 1] << 8);
    return mm == 0 ? INFINITY : float(mm) * 0.001f;
  }
  return NAN;
}

bool CameraProxy::geometry(CameraModel& out) {
  Reply r = request(uint8_t(wire::CameraReqSub::Geometry));
  const wire::CameraGeometry* g = r.ok() ? r.message()->body_as_CameraGeometry() : nullptr;
  if (g == nullptr) return false;
  if (g->pose()) out.pose = *g->pose();
  out.hfov = g->hfov();
  out.vfov = g->vfov();
  out.fx = g->fx();
  out.fy = g->fy();
  out.cx = g->cx();
  out.cy = g->cy();
  out.near = g->near();
  out.far = g->far();
  out.projection = g->projection();
  out.ground_radius = g->ground_radius();
  out.rim_radius = g->rim_radius();
  out.mirror_range = g->mirror_range();
  out.rim_elevation = g->rim_elevation();
  return true;
}

bool CameraProxy::configure(CameraSettings& want) {
  auto& b = client().begin();
  auto body = wire::CreateCameraConfig(b, uint16_t(want.width), uint16_t(want.height), want.rate, want.format);
  Reply r = request(uint8_t(wire::CameraReqSub::SetConfig), wire::Body::CameraConfig, body.Union());
  const wire::CameraConfig* c = r.ok() ? r.message()->body_as_CameraConfig() : nullptr;
  if (c == nullptr) return false;
  want.width = c->width();
  want.height = c->height();
  want.rate = c->rate();
  want.format = c->format();
  return true;
}

FiducialProxy::FiducialProxy(Client& client, uint16_t index, uint16_t robot)
    : Proxy(client, address_of(Interface::Fiducial, index, robot)) {
  attach();
}

void FiducialProxy::update(const wire::Message& msg) {
  const wire::FiducialList* s = msg.body_as_FiducialList();
  if (s == nullptr) return;
  copy_structs(s->fiducials(), fiducials_);
  kinds_.assign(fiducials_.size(), wire::FiducialKind::Generic);
  if (const auto* kinds = s->kinds()) {
    for (size_t i = 0; i < kinds_.size() && i < kinds->size(); ++i) {
      kinds_[i] = wire::FiducialKind(kinds->Get(flatbuffers::uoffset_t(i)));
    }
  }
}

ImuProxy::ImuProxy(Client& client, uint16_t index, uint16_t robot)
    : Proxy(client, address_of(Interface::Imu, index, robot)) {
  attach();
}

void ImuProxy::update(const wire::Message& msg) {
  const wire::ImuState* s = msg.body_as_ImuState();
  if (s == nullptr) return;
  auto get = [](const wire::Vec3* v) { return v ? std::optional<wire::Vec3>(*v) : std::nullopt; };
  gyro_ = get(s->gyro());
  accel_ = get(s->accel());
  orientation_ = get(s->orientation());
}

}  // namespace troupe::client
