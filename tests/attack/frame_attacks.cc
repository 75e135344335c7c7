// Hostile frames: malformed ones of every kind, null bodies of every kind
// and type, and well-formed commands and requests carrying NaN or infinity.
#include <cmath>
#include <limits>
#include <random>

#include "tests/attack/attacks.h"
#include "tests/attack/wire_peer.h"
#include "wire/address.h"

namespace troupe::attack {
namespace {

constexpr int kProbeMs = 5000;  // bounds a hung target, not a requirement
constexpr uint32_t kProbeSeq = 0xFFFF0000u;
constexpr uint64_t kSeed = 12;

// Every kind the schema has, and two it does not.
std::vector<wire::Kind> all_kinds() {
  std::vector<wire::Kind> kinds;
  for (int k = 0; k <= int(wire::Kind::MAX); ++k) kinds.push_back(wire::Kind(k));
  kinds.push_back(wire::Kind(int(wire::Kind::MAX) + 1));
  kinds.push_back(wire::Kind(255));
  return kinds;
}

std::string describe(wire::Kind k) {
  return k <= wire::Kind::MAX ? std::string(wire::kind_name(k)) : "kind " + std::to_string(int(k));
}

// A hostile sender: one frame at a time, each followed by a DeviceList
// probe, reconnecting whenever the target closed the connection.
class Thrower {
 public:
  explicit Thrower(uint16_t port) : port_(port) {}

  // Sends `frame` and reads until the probe's reply. True when the target
  // acknowledged the frame (an Ack came back before the probe's reply).
  bool acked(const Bytes& frame) {
    if ((!peer_.socket().open() || peer_.closed()) && !peer_.connect(port_)) return false;
    const uint32_t probe = kProbeSeq + ++probes_;
    if (!peer_.send(frame) || !peer_.send(frames_.bare({}, wire::Kind::DeviceList, 0, probe))) {
      peer_.socket().close();
      return false;
    }
    bool ack = false;
    const Deadline deadline = deadline_in(kProbeMs);
    while (auto f = peer_.read_frame(ms_left(deadline))) {
      const wire::Message* m = message(*f);
      if (m == nullptr) break;
      if (m->header()->kind() == wire::Kind::Ack) ack = true;
      if (m->header()->kind() == wire::Kind::Error) break;
      if (m->header()->kind() == wire::Kind::DeviceList && m->header()->seq() == probe) return ack;
    }
    // Refused and closed (an Error), or no probe reply: start afresh.
    peer_.socket().close();
    return ack;
  }

  // Sends raw bytes, says "that was all" and reads until the target closes.
  void then_hang_up(const Bytes& bytes) {
    WirePeer p;
    if (!p.connect(port_)) return;
    p.send(bytes);
    p.socket().shutdown_write();
    while (p.read_frame(kProbeMs)) {
    }
  }

 private:
  uint16_t port_;
  WirePeer peer_;
  Frames frames_;
  uint32_t probes_ = 0;
};

// A well-formed frame of kind `k` to `addr`, with the body that kind takes.
Bytes base_frame(Frames& f, wire::Kind k, wire::Address addr, uint32_t seq) {
  switch (k) {
    case wire::Kind::Hello:
      return f.with_body({}, k, 0, seq, wire::Body::Hello);
    case wire::Kind::Open:
      return f.with_body(addr, k, 0, seq, wire::Body::Open);
    case wire::Kind::TimeSync:
      return f.with_body({}, k, 0, seq, wire::Body::TimeSync);
    case wire::Kind::Error:
      return f.with_body(addr, k, 0, seq, wire::Body::Error);
    case wire::Kind::Command:
      return f.with_body(addr, k, uint8_t(wire::Position2dCmdSub::Vel), seq, wire::Body::Position2dVel);
    default:
      return f.bare(addr, k, 1, seq);
  }
}

float nan_f() {
  return std::numeric_limits<float>::quiet_NaN();
}
float inf_f() {
  return std::numeric_limits<float>::infinity();
}

// The latest position2d:0 state of robot 0 that `peer` (which opened it)
// receives within `ms`; false when none came.
bool latest_state(WirePeer& peer, wire::Pose2d& pose, wire::Pose2d& vel, int ms) {
  bool got = false;
  const Deadline deadline = deadline_in(ms);
  while (auto f = peer.read_frame(got ? 0 : ms_left(deadline))) {
    const wire::Message* m = message(*f);
    const wire::Position2dState* s = m ? m->body_as_Position2dState() : nullptr;
    if (m && m->header()->kind() == wire::Kind::Data && s && s->pose() &&
        wire::address_key(m->header()->addr()) == wire::address_key(kPosition0)) {
      pose = *s->pose();
      vel = s->vel() ? *s->vel() : wire::Pose2d();
      got = true;
    }
  }
  return got;
}

bool finite(const wire::Pose2d& p) {
  return std::isfinite(p.x()) && std::isfinite(p.y()) && std::isfinite(p.a());
}

}  // namespace

void malformed_frames(Target& t, int scale, Outcome& out) {
  out.unit = "frames";
  std::mt19937_64 rng(kSeed);
  Thrower thrower(t.port());
  Frames f;
  const wire::Limits limits;
  uint32_t seq = 1000;
  auto refuse = [&](const Bytes& frame, const std::string& what) {
    ++out.volume;
    if (thrower.acked(frame)) out.got_through(what + " was acknowledged");
  };
  for (wire::Kind k : all_kinds()) {
    const std::string kind = describe(k);
    // Well-formed FlatBuffers that the protocol does not allow.
    const wire::Body wrong = k == wire::Kind::Hello ? wire::Body::SimPoses : wire::Body::Hello;
    refuse(f.with_body(kPosition0, k, 1, ++seq, wrong),
           kind + " with a " + wire::EnumNameBody(wrong) + " body");
    refuse(f.bare(wire::Address(999, 999, 999), k, 1, ++seq), kind + " to a device that does not exist");
    if (k == wire::Kind::Request) refuse(f.bare(kPosition0, k, 250, ++seq), "a request with subtype 250");
    // Frames the verifier refuses: the root offset out of the buffer,
    // random bytes behind a right prefix, bit flips.
    Bytes bad_root = base_frame(f, k, kPosition0, ++seq);
    bad_root[4] = 0xF0, bad_root[5] = 0xFF, bad_root[6] = 0xFF, bad_root[7] = 0x7F;
    refuse(bad_root, kind + " with its root offset out of the buffer");
    Bytes garbage(4 + 40 + rng() % 200);
    for (size_t i = 4; i < garbage.size(); ++i) garbage[i] = uint8_t(rng());
    const uint32_t n = uint32_t(garbage.size() - 4);
    garbage[0] = uint8_t(n), garbage[1] = uint8_t(n >> 8), garbage[2] = garbage[3] = 0;
    refuse(garbage, "random bytes");
    for (int flips = 0; flips < 8 * scale;) {
      Bytes frame = base_frame(f, k, kPosition0, ++seq);
      for (int b = 0; b < 1 + int(rng() % 3); ++b) {
        const size_t at = 4 + rng() % (frame.size() - 4);
        frame[at] ^= uint8_t(1u << (rng() % 8));
      }
      // A flip that still verifies is a different valid frame, not a bad one.
      if (wire::verify_frame(frame, limits) != nullptr) continue;
      ++flips;
      refuse(frame, kind + " with flipped bits");
    }
    // Lengths: over the limit, zero, and a frame cut short at hang-up.
    Bytes frame = base_frame(f, k, kPosition0, ++seq);
    Bytes huge = frame;
    huge[0] = huge[1] = huge[2] = 0xFF, huge[3] = 0x7F;
    refuse(huge, "a length prefix of 2 GiB");
    refuse(Bytes{0, 0, 0, 0}, "a zero length prefix");
    Bytes cut = frame;
    cut[0] = uint8_t(cut[0] + 100);
    thrower.then_hang_up(cut);
    ++out.volume;
    thrower.then_hang_up(Bytes(frame.begin(), frame.begin() + 3));
    ++out.volume;
  }
}

namespace {

// Requests that cannot be carried out without their body: acknowledging
// one is taking an absent value for a real one.
void add_requests_needing_bodies(TargetKind kind, Frames& f, uint32_t& seq, std::vector<HostileFrame>& list) {
  auto needs = [&](wire::Address addr, uint8_t sub, wire::Body type, const std::string& what) {
    list.push_back({f.null_body(addr, wire::Kind::Request, sub, ++seq, type), what + " without its body"});
  };
  needs(kPosition0, uint8_t(wire::Position2dReqSub::MotorPower), wire::Body::Switch, "MotorPower");
  needs(kPosition0, uint8_t(wire::Position2dReqSub::SetOdometry), wire::Body::Position2dSetOdom,
        "SetOdometry");
  if (kind == TargetKind::Sim) {
    needs(kSimulation, uint8_t(wire::SimulationReqSub::SetSpeed), wire::Body::SimSpeed, "SetSpeed");
    needs(kSimulation, uint8_t(wire::SimulationReqSub::SetPose), wire::Body::SimPose, "SetPose");
    needs(kSimulation, uint8_t(wire::SimulationReqSub::GetPose), wire::Body::SimModel, "GetPose");
  }
}

}  // namespace

std::vector<HostileFrame> null_body_frames(TargetKind kind) {
  Frames f;
  std::vector<HostileFrame> list;
  std::vector<wire::Address> to = {kPosition0};
  if (kind == TargetKind::Sim) to.push_back(kSimulation);
  uint32_t seq = 2000;
  // Every kind with every body type, to a device that exists so that the
  // frame reaches its handler; requests with each of the first subtypes.
  for (const wire::Address& addr : to) {
    for (wire::Kind k : all_kinds()) {
      const int subtypes = k == wire::Kind::Request ? 8 : 1;
      for (int sub = 1; sub <= subtypes; ++sub) {
        for (int type = 1; type <= int(wire::Body::MAX); ++type) {
          list.push_back({f.null_body(addr, k, uint8_t(sub), ++seq, wire::Body(type)), {}});
        }
      }
    }
  }
  add_requests_needing_bodies(kind, f, seq, list);
  return list;
}

std::vector<HostileFrame> null_body_sample(TargetKind kind) {
  Frames f;
  std::vector<HostileFrame> list;
  uint32_t seq = 3000;
  // Each kind with the body it would carry (Hello and TimeSync are the
  // ones that took every program down).
  for (wire::Kind k : all_kinds()) {
    wire::Body type = wire::Body::Hello;
    if (k == wire::Kind::TimeSync) type = wire::Body::TimeSync;
    if (k == wire::Kind::Open) type = wire::Body::Open;
    if (k == wire::Kind::DeviceList) type = wire::Body::DeviceList;
    if (k == wire::Kind::Error || k == wire::Kind::Nack) type = wire::Body::Error;
    if (k == wire::Kind::Command) type = wire::Body::Position2dVel;
    if (k == wire::Kind::Data) type = wire::Body::Position2dState;
    list.push_back({f.null_body(kPosition0, k, 1, ++seq, type), {}});
  }
  add_requests_needing_bodies(kind, f, seq, list);
  return list;
}

void null_bodies(Target& t, int scale, Outcome& out) {
  out.unit = "frames";
  Thrower thrower(t.port());
  const std::vector<HostileFrame> frames = null_body_frames(t.kind());
  for (int round = 0; round < scale && t.alive(); ++round) {
    for (const HostileFrame& h : frames) {
      if (!t.alive()) break;
      ++out.volume;
      if (thrower.acked(h.frame) && !h.if_acked.empty()) out.got_through(h.if_acked + " was acknowledged");
    }
  }
}

void non_finite_values(Target& t, int scale, Outcome& out) {
  out.unit = "frames";
  WirePeer peer;
  Frames f;
  if (!peer.connect(t.port()) || !peer.send(f.hello(0)) || !peer.ask(f.open(kPosition0, 1), 1, kProbeMs)) {
    out.got_through("could not open position2d:0 to watch it");
    return;
  }
  const float bad[] = {nan_f(), inf_f(), -inf_f()};
  uint32_t seq = 10;
  for (int round = 0; round < scale; ++round) {
    for (float v : bad) {
      for (int field = 0; field < 3; ++field) {
        const float x = field == 0 ? v : 0.1f, y = field == 1 ? v : 0, a = field == 2 ? v : 0;
        const std::string what =
            "(" + std::to_string(x) + ", " + std::to_string(y) + ", " + std::to_string(a) + ")";
        peer.send(f.vel(kPosition0, x, y, a));
        peer.send(f.go_to(kPosition0, x, y, a));
        out.volume += 3;
        ++seq;
        if (reply_kind(peer.ask(f.set_odometry(kPosition0, seq, x, y, a), seq, kProbeMs)) == wire::Kind::Ack)
          out.got_through("SetOdometry " + what + " was acknowledged");
        if (t.kind() == TargetKind::Sim) {
          out.volume += 2;
          ++seq;
          if (reply_kind(peer.ask(f.sim_set_pose(seq, "r1", x, y, a), seq, kProbeMs)) == wire::Kind::Ack)
            out.got_through("SetPose " + what + " was acknowledged");
          ++seq;
          if (reply_kind(peer.ask(f.sim_speed(seq, v), seq, kProbeMs)) == wire::Kind::Ack)
            out.got_through("SetSpeed " + std::to_string(v) + " was acknowledged");
        }
      }
    }
  }
  // The device must still report finite values and still obey a good
  // command: it moves forward (the pose's x grows) within a bound.
  wire::Pose2d pose, vel;
  if (!latest_state(peer, pose, vel, kProbeMs)) {
    out.got_through("position2d:0 stopped publishing");
    return;
  }
  if (!finite(pose) || !finite(vel)) {
    out.got_through("position2d:0 reports non-finite values");
    return;
  }
  const float start_x = pose.x();
  peer.send(f.vel(kPosition0, 0.3f, 0, 0));
  bool moved = false;
  const Deadline deadline = deadline_in(20000);
  while (!moved && ms_left(deadline) > 0 && latest_state(peer, pose, vel, ms_left(deadline))) {
    moved = finite(pose) && pose.x() > start_x + 0.01f;
  }
  peer.send(f.vel(kPosition0, 0, 0, 0));
  if (!moved) out.got_through("position2d:0 no longer obeys a good velocity command");
}

}  // namespace troupe::attack
