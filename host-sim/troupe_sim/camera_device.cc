// camera:k requests: geometry (pose, fields of view, intrinsics, range) and
// configuration (image size, rate, pixel format).
#include <algorithm>
#include <cmath>
#include <string>

#include "host-sim/troupe_sim/sim_server.h"
#include "wire/image.h"

namespace troupe::sim {

using wire::ErrorCode;

void SimServer::camera_request(Device& d, const wire::Message& req, RequestToken token) {
  using Sub = wire::CameraReqSub;
  const uint8_t sub = req.header()->subtype();
  if (sub == uint8_t(Sub::SetConfig)) {
    const wire::CameraConfig* c = req.body_as_CameraConfig();  // check_message() made sure it is there
    const CameraDesc& now = world_.camera_desc(d.index);
    const int w = c->width() ? int(c->width()) : now.width;
    const int h = c->height() ? int(c->height()) : now.height;
    std::string why;
    // An image that could never be sent is refused here, with the reason,
    // rather than configured and then never delivered.
    if (!wire::image_fits(uint32_t(w), uint32_t(h), c->format(), node_->options().limits.max_frame_bytes, why)) {
      return node_->nack(token, ErrorCode::BadArgument, why.c_str());
    }
    if (!world_.set_camera_size(d.index, w, h)) {
      return node_->nack(token, ErrorCode::BadArgument, "camera images are 1 to 4096 pixels each way");
    }
    d.format = c->format();
    if (c->rate() > 0) d.rate = c->rate();
    d.refused_logged = false;
    d.last_image = -1;
    // Images of the old configuration go: a new reader must not get one, and
    // a change to DepthF32 (no PNG form) leaves no PNG image behind.
    node_->forget_data(d.id);
  } else if (sub != uint8_t(Sub::GetConfig) && sub != uint8_t(Sub::Geometry)) {
    return Driver::on_request(d.id, req, token);
  }
  const CameraDesc& cd = world_.camera_desc(d.index);
  auto& b = node_->begin();
  if (sub == uint8_t(Sub::Geometry)) {
    // The same projections the renderer uses (host-sim/sim/camera.cc).
    wire::Pose3d pose(float(cd.pose.x), float(cd.pose.y), float(cd.z), 0, float(-cd.tilt), float(cd.pose.a));
    wire::Vec3 size(float(cd.size.x), float(cd.size.y), float(cd.size_z));
    wire::CameraGeometryBuilder g(b);
    g.add_pose(&pose);
    g.add_size(&size);
    g.add_near(float(cd.near));
    g.add_far(float(cd.far));
    g.add_cx(float(0.5 * cd.width));
    if (cd.projection == CameraProjection::Omni) {
      const double rim = 0.5 * std::min(cd.width, cd.height);
      g.add_projection(wire::CameraProjection::OmniIsometric);
      g.add_hfov(float(2 * kPi));
      g.add_vfov(float(cd.mirror_top + kPi / 2));  // from straight down to the rim's elevation
      g.add_cy(float(0.5 * cd.height));
      g.add_ground_radius(float(cd.mirror_ground * rim));
      g.add_rim_radius(float(rim));
      g.add_mirror_range(float(cd.mirror_range));
      g.add_rim_elevation(float(cd.mirror_top));
    } else {
      const double fx = 0.5 * cd.width / std::tan(0.5 * cd.hfov);
      const double fy = 0.5 * cd.height / std::tan(0.5 * cd.vfov);
      g.add_hfov(float(cd.hfov));
      g.add_vfov(float(cd.vfov));
      g.add_fx(float(fx));
      g.add_fy(float(fy));
      g.add_cy(float(0.5 * cd.height + fy * std::tan(cd.tilt)));
    }
    const auto body = g.Finish();
    return node_->ack(token, wire::Body::CameraGeometry, body.Union());
  }
  // The rate in force: what was asked for, or one image per step.
  const float rate = d.rate > 0 ? d.rate : float(1.0 / world_.interval());
  auto body = wire::CreateCameraConfig(b, uint16_t(cd.width), uint16_t(cd.height), rate, d.format);
  node_->ack(token, wire::Body::CameraConfig, body.Union());
}

}  // namespace troupe::sim
