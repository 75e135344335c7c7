#include "tests/odrive/test_client.h"

namespace troupe::testing {

bool TestClient::connect(uint16_t port, std::string& error) {
  connected_ = client_.connect(port, error);
  return connected_;
}

uint32_t TestClient::request_motor_power(const wire::Address& addr, bool on) {
  return client_.request_switch(addr, uint8_t(wire::Position2dReqSub::MotorPower), on);
}

uint32_t TestClient::request_reset_odometry(const wire::Address& addr) {
  return client_.request(addr, uint8_t(wire::Position2dReqSub::ResetOdometry));
}

uint32_t TestClient::request_set_odometry(const wire::Address& addr, float x, float y, float a) {
  auto& b = client_.begin();
  wire::Pose2d pose(x, y, a);
  auto body = wire::CreatePosition2dSetOdom(b, &pose);
  return client_.request(addr, uint8_t(wire::Position2dReqSub::SetOdometry), wire::Body::Position2dSetOdom,
                         body.Union());
}

uint32_t TestClient::request_geometry(const wire::Address& addr) {
  geometry_seq_ = client_.request(addr, uint8_t(wire::Position2dReqSub::Geometry));
  return geometry_seq_;
}

bool TestClient::pump() {
  client_.poll();
  if (const wire::Message* m = geometry_seq_ ? client_.reply(geometry_seq_) : nullptr) {
    if (const auto* g = m->body_as_Position2dGeometry(); g && g->size()) {
      geometry_length = g->size()->x();
      geometry_width = g->size()->y();
    }
  }
  return connected();
}

PositionSample TestClient::position(const wire::Address& addr) const {
  PositionSample p;
  const wire::Message* m = client_.last(addr);
  const wire::Position2dState* s = m ? m->body_as_Position2dState() : nullptr;
  if (s == nullptr) return p;
  p.count = client_.count(addr);
  p.seq = m->header()->seq();
  if (s->pose()) p.x = s->pose()->x(), p.y = s->pose()->y(), p.a = s->pose()->a();
  if (s->vel()) p.vx = s->vel()->x(), p.va = s->vel()->a();
  p.stall = s->stall();
  p.fault = s->fault() ? s->fault()->str() : std::string();
  return p;
}

PowerSample TestClient::power(const wire::Address& addr) const {
  PowerSample p;
  const wire::Message* m = client_.last(addr);
  const wire::PowerState* s = m ? m->body_as_PowerState() : nullptr;
  if (s == nullptr) return p;
  p.count = client_.count(addr);
  p.volts = s->volts().value_or(0);
  return p;
}

Reply TestClient::reply(uint32_t seq) const {
  Reply r;
  const wire::Message* m = client_.reply(seq);
  if (m == nullptr) return r;
  r.kind = m->header()->kind();
  if (const auto* e = m->body_as_Error(); e && e->text()) r.text = e->text()->str();
  return r;
}

}  // namespace troupe::testing
