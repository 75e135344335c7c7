// Proxies of things that move: position2d, actuator.
#include "wire/client/proxies.h"

namespace troupe::client {

using wire::Interface;

Position2dProxy::Position2dProxy(Client& client, uint16_t index, uint16_t robot)
    : Position2dProxy(client, address_of(Interface::Position2d, index, robot)) {}

Position2dProxy::Position2dProxy(Client& client, const wire::Address& addr) : Proxy(client, addr) { attach(); }

void Position2dProxy::update(const wire::Message& msg) {
  const wire::Position2dState* s = msg.body_as_Position2dState();
  if (s == nullptr) return;
  if (s->pose()) pose_ = {s->pose()->x(), s->pose()->y(), s->pose()->a()};
  if (s->vel()) vel_ = {s->vel()->x(), s->vel()->y(), s->vel()->a()};
  stall_ = s->stall();
  if (const wire::Cov2d* c = s->covariance()) {
    cov_ = std::array<float, 6>{c->xx(), c->xy(), c->xa(), c->yy(), c->ya(), c->aa()};
  } else {
    cov_.reset();
  }
}

bool Position2dProxy::set_velocity(float vx, float vy, float va) {
  auto& b = client().begin();
  wire::Pose2d vel(vx, vy, va);
  auto body = wire::CreatePosition2dVel(b, &vel);
  return command(uint8_t(wire::Position2dCmdSub::Vel), wire::Body::Position2dVel, body.Union());
}

bool Position2dProxy::go_to(float x, float y, float a) {
  auto& b = client().begin();
  wire::Pose2d pose(x, y, a);
  auto body = wire::CreatePosition2dGoto(b, &pose);
  return command(uint8_t(wire::Position2dCmdSub::Goto), wire::Body::Position2dGoto, body.Union());
}

bool Position2dProxy::set_motor_power(bool on) {
  auto& b = client().begin();
  auto body = wire::CreateSwitch(b, on);
  return request(uint8_t(wire::Position2dReqSub::MotorPower), wire::Body::Switch, body.Union()).ok();
}

bool Position2dProxy::set_odometry(float x, float y, float a) {
  auto& b = client().begin();
  wire::Pose2d pose(x, y, a);
  auto body = wire::CreatePosition2dSetOdom(b, &pose);
  return request(uint8_t(wire::Position2dReqSub::SetOdometry), wire::Body::Position2dSetOdom, body.Union()).ok();
}

bool Position2dProxy::reset_odometry() { return request(uint8_t(wire::Position2dReqSub::ResetOdometry)).ok(); }

bool Position2dProxy::geometry(wire::Vec3& size, wire::Pose3d& offset) {
  Reply r = request(uint8_t(wire::Position2dReqSub::Geometry));
  const wire::Position2dGeometry* g = r.ok() ? r.message()->body_as_Position2dGeometry() : nullptr;
  if (g == nullptr) return false;
  if (g->size()) size = *g->size();
  if (g->pose()) offset = *g->pose();
  return true;
}

ActuatorProxy::ActuatorProxy(Client& client, uint16_t index, uint16_t robot)
    : Proxy(client, address_of(Interface::Actuator, index, robot)) {
  attach();
}

void ActuatorProxy::update(const wire::Message& msg) {
  const wire::ActuatorState* s = msg.body_as_ActuatorState();
  if (s == nullptr) return;
  mode_ = s->mode();
  position_ = s->position();
  beams_ = s->beams();
  stored_ = s->stored();
}

bool ActuatorProxy::act(wire::ActuatorAction action, float value) {
  auto& b = client().begin();
  auto body = wire::CreateActuatorCommand(b, action, value);
  return command(uint8_t(wire::ActuatorCmdSub::Action), wire::Body::ActuatorCommand, body.Union());
}

bool ActuatorProxy::open() { return act(wire::ActuatorAction::Open, 0); }
bool ActuatorProxy::close() { return act(wire::ActuatorAction::Close, 0); }
bool ActuatorProxy::stop() { return act(wire::ActuatorAction::Stop, 0); }
bool ActuatorProxy::kick(float speed) { return act(wire::ActuatorAction::Kick, speed); }
bool ActuatorProxy::go_to(float position) { return act(wire::ActuatorAction::Goto, position); }

}  // namespace troupe::client
