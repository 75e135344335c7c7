#include "tests/attack/wire_peer.h"

#include <algorithm>
#include <chrono>
#include <thread>
#include <utility>

#include "wire/address.h"

namespace troupe::attack {

bool WirePeer::connect(uint16_t port) {
  reader_ = wire::FrameReader(2u << 20);
  transport_.reset();
  sent_.clear();
  session_error_.clear();
  return socket_.connect(port);
}

bool WirePeer::connect_secure(uint16_t port, wire::noise::SecureOptions options, std::string* why,
                              int timeout_ms) {
  if (!connect(port)) return false;
  options.role = wire::noise::Role::Initiator;
  transport_ = std::make_unique<wire::noise::NoiseTransport>(std::move(options));
  Bytes first;
  transport_->begin(first);
  sent_ = first;
  if (!socket_.send(first, timeout_ms)) return false;
  const Deadline deadline = deadline_in(timeout_ms);
  while (!transport_->ready()) {
    if (!receive(deadline)) {
      if (why != nullptr) *why = session_error_.empty() ? "the node closed during the handshake" : session_error_;
      return false;
    }
  }
  return true;
}

bool WirePeer::send(std::span<const uint8_t> bytes, int timeout_ms) {
  if (transport_ == nullptr) return socket_.send(bytes, timeout_ms);
  Bytes sealed;
  transport_->outbound(bytes, sealed);
  sent_.insert(sent_.end(), sealed.begin(), sealed.end());
  return socket_.send(sealed, timeout_ms);
}

Bytes WirePeer::seal(std::span<const uint8_t> bytes) {
  Bytes sealed;
  if (transport_ != nullptr) transport_->outbound(bytes, sealed);
  return sealed;
}

bool WirePeer::receive(Deadline deadline) {
  if (transport_ == nullptr) {
    const long n = socket_.recv_some(reader_.write_space(), ms_left(deadline));
    if (n <= 0) return false;
    reader_.commit(size_t(n));
    return true;
  }
  uint8_t buf[16384];
  const long n = socket_.recv_some(buf, ms_left(deadline));
  if (n <= 0) return false;
  Bytes reply;
  if (!transport_->inbound(std::span<const uint8_t>(buf, size_t(n)), reader_, reply, session_error_)) {
    socket_.close();
    return false;
  }
  return reply.empty() || socket_.send(reply);
}

std::optional<Bytes> WirePeer::read_frame(int timeout_ms) {
  const Deadline deadline = deadline_in(timeout_ms);
  for (;;) {
    if (std::span<const uint8_t> f = reader_.next(); !f.empty()) return Bytes(f.begin(), f.end());
    if (!socket_.open() || reader_.too_large()) return std::nullopt;
    if (!receive(deadline)) return std::nullopt;
  }
}

std::optional<Bytes> WirePeer::ask(const Bytes& frame, uint32_t seq, int timeout_ms) {
  if (!send(frame, timeout_ms)) return std::nullopt;
  return wait_reply(seq, timeout_ms);
}

bool is_reply_to(const wire::Message& m, uint32_t seq) {
  const wire::Kind k = m.header()->kind();
  if (k == wire::Kind::Error) return true;
  const bool reply = k == wire::Kind::Ack || k == wire::Kind::Nack || k == wire::Kind::DeviceList ||
                     k == wire::Kind::TimeSync;
  return reply && m.header()->seq() == seq;
}

std::optional<Bytes> WirePeer::wait_reply(uint32_t seq, int timeout_ms) {
  const Deadline deadline = deadline_in(timeout_ms);
  while (auto f = read_frame(ms_left(deadline))) {
    const wire::Message* m = message(*f);
    if (m == nullptr) return std::nullopt;  // the target sent a frame that does not verify
    if (is_reply_to(*m, seq)) return f;
  }
  return std::nullopt;
}

Bytes Frames::bare(wire::Address addr, wire::Kind kind, uint8_t subtype, uint32_t seq) {
  return take(w_.empty(wire::make_header(addr, kind, subtype, seq, 0)));
}

Bytes Frames::null_body(wire::Address addr, wire::Kind kind, uint8_t subtype, uint32_t seq, wire::Body type) {
  w_.start();
  return take(w_.finish(wire::make_header(addr, kind, subtype, seq, 0), type));
}

Bytes Frames::with_body(wire::Address addr, wire::Kind kind, uint8_t subtype, uint32_t seq, wire::Body type) {
  auto& b = w_.start();
  flatbuffers::Offset<void> body;
  const wire::Pose2d pose(1, 2, 3);
  switch (type) {
    case wire::Body::Hello:
      body = wire::CreateHello(b, wire::kProtocolVersion, b.CreateString("attack"), 1u << 20).Union();
      break;
    case wire::Body::Open:
      body = wire::CreateOpen(b).Union();
      break;
    case wire::Body::TimeSync:
      body = wire::CreateTimeSync(b, 1).Union();
      break;
    case wire::Body::Error:
      body = wire::CreateError(b, wire::ErrorCode::Unknown, b.CreateString("attack")).Union();
      break;
    case wire::Body::Position2dVel:
      body = wire::CreatePosition2dVel(b, &pose).Union();
      break;
    case wire::Body::SimPoses:
      body = wire::CreateSimPoses(b, 1, b.CreateVectorOfStructs(&pose, 1)).Union();
      break;
    default:
      type = wire::Body::NONE;
  }
  return take(w_.finish(wire::make_header(addr, kind, subtype, seq, 0), type, body));
}

Bytes Frames::hello(uint32_t seq) {
  auto& b = w_.start();
  auto body = wire::CreateHello(b, wire::kProtocolVersion, b.CreateString("attack"), 1u << 20);
  return take(
      w_.finish(wire::make_header({}, wire::Kind::Hello, 0, seq, 0), wire::Body::Hello, body.Union()));
}

Bytes Frames::open(wire::Address addr, uint32_t seq, wire::Access access, wire::Delivery delivery) {
  auto& b = w_.start();
  auto body = wire::CreateOpen(b, access, delivery);
  return take(
      w_.finish(wire::make_header(addr, wire::Kind::Open, 0, seq, 0), wire::Body::Open, body.Union()));
}

Bytes Frames::vel(wire::Address addr, float x, float y, float a) {
  auto& b = w_.start();
  const wire::Pose2d v(x, y, a);
  return pose_command(addr, wire::Position2dCmdSub::Vel, wire::Body::Position2dVel,
                      wire::CreatePosition2dVel(b, &v).Union());
}

Bytes Frames::go_to(wire::Address addr, float x, float y, float a) {
  auto& b = w_.start();
  const wire::Pose2d p(x, y, a);
  return pose_command(addr, wire::Position2dCmdSub::Goto, wire::Body::Position2dGoto,
                      wire::CreatePosition2dGoto(b, &p).Union());
}

Bytes Frames::pose_command(wire::Address addr, wire::Position2dCmdSub sub, wire::Body type,
                           flatbuffers::Offset<void> body) {
  return take(w_.finish(wire::make_header(addr, wire::Kind::Command, uint8_t(sub), 0, 0), type, body));
}

Bytes Frames::set_odometry(wire::Address addr, uint32_t seq, float x, float y, float a) {
  auto& b = w_.start();
  const wire::Pose2d p(x, y, a);
  auto body = wire::CreatePosition2dSetOdom(b, &p);
  return take(w_.finish(
      wire::make_header(addr, wire::Kind::Request, uint8_t(wire::Position2dReqSub::SetOdometry), seq, 0),
      wire::Body::Position2dSetOdom, body.Union()));
}

Bytes Frames::sim_step(uint32_t seq, uint32_t steps) {
  auto& b = w_.start();
  auto body = wire::CreateSimStep(b, steps);
  return take(w_.finish(
      wire::make_header(kSimulation, wire::Kind::Request, uint8_t(wire::SimulationReqSub::Step), seq, 0),
      wire::Body::SimStep, body.Union()));
}

Bytes Frames::sim_speed(uint32_t seq, float speed) {
  auto& b = w_.start();
  auto body = wire::CreateSimSpeed(b, speed);
  return take(w_.finish(
      wire::make_header(kSimulation, wire::Kind::Request, uint8_t(wire::SimulationReqSub::SetSpeed), seq, 0),
      wire::Body::SimSpeed, body.Union()));
}

Bytes Frames::sim_set_pose(uint32_t seq, const std::string& model, float x, float y, float a) {
  auto& b = w_.start();
  const wire::Pose2d p(x, y, a);
  auto body = wire::CreateSimPose(b, b.CreateString(model), &p);
  return take(w_.finish(
      wire::make_header(kSimulation, wire::Kind::Request, uint8_t(wire::SimulationReqSub::SetPose), seq, 0),
      wire::Body::SimPose, body.Union()));
}

Bytes Frames::sim_get_pose(uint32_t seq, const std::string& model) {
  auto& b = w_.start();
  auto body = wire::CreateSimModel(b, b.CreateString(model));
  return take(w_.finish(
      wire::make_header(kSimulation, wire::Kind::Request, uint8_t(wire::SimulationReqSub::GetPose), seq, 0),
      wire::Body::SimModel, body.Union()));
}

Bytes Frames::sim_request(uint32_t seq, wire::SimulationReqSub sub) {
  return bare(kSimulation, wire::Kind::Request, uint8_t(sub), seq);
}

const wire::Message* message(const Bytes& frame) {
  return wire::verify_frame(frame, {});
}

wire::Kind reply_kind(const std::optional<Bytes>& reply) {
  const wire::Message* m = reply ? message(*reply) : nullptr;
  return m ? m->header()->kind() : wire::Kind::Invalid;
}

bool served(uint16_t port, std::string& why, int timeout_ms, const wire::noise::SecureOptions* secure) {
  WirePeer peer;
  Frames f;
  if (secure != nullptr ? !peer.connect_secure(port, *secure, &why) : !peer.connect(port)) {
    why = "cannot connect" + (why.empty() ? "" : ": " + why);
    return false;
  }
  if (!peer.send(f.hello(0)) || !peer.send(f.bare({}, wire::Kind::DeviceList, 0, 1))) {
    why = "the connection broke while sending Hello";
    return false;
  }
  const auto list = peer.wait_reply(1, timeout_ms);
  const wire::Message* m = list ? message(*list) : nullptr;
  const wire::DeviceList* devices = m ? m->body_as_DeviceList() : nullptr;
  if (devices == nullptr || devices->devices() == nullptr || devices->devices()->size() == 0 ||
      devices->devices()->Get(0)->addr() == nullptr) {
    why = peer.closed() ? "closed before the device list came" : "no device list";
    return false;
  }
  // Subtype 1 is each interface's first request (Geometry, Pause, Info...).
  const wire::Address first = *devices->devices()->Get(0)->addr();
  if (!peer.send(f.bare(first, wire::Kind::Request, 1, 2))) {
    why = "the connection broke while sending a request";
    return false;
  }
  const auto reply = peer.wait_reply(2, timeout_ms);
  const wire::Message* r = reply ? message(*reply) : nullptr;
  if (r == nullptr || (r->header()->kind() != wire::Kind::Ack && r->header()->kind() != wire::Kind::Nack)) {
    why = "a request to " + wire::format_address(first) + " got no answer";
    return false;
  }
  return true;
}

bool served_eventually(uint16_t port, std::string& why, int timeout_ms,
                       const wire::noise::SecureOptions* secure) {
  const Deadline deadline = deadline_in(timeout_ms);
  for (;;) {
    if (served(port, why, std::max(1000, std::min(ms_left(deadline), 5000)), secure)) return true;
    if (ms_left(deadline) == 0) return false;
    std::this_thread::sleep_for(std::chrono::milliseconds(200));
  }
}

}  // namespace troupe::attack
