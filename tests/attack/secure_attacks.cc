// Attacks on secure sessions (wire/README.md, "Secure sessions", "Rights"),
// against a secure troupe-node whose config accepts three keys with
// different rights: no handshake at all, keys it does not know, a client
// that does not hold the node's key, a recorded session replayed, a live
// session's messages replayed, reordered, truncated, bit-flipped and
// oversized, handshakes left half-open by the hundred, and known clients
// stepping outside their rights.
#include <optional>

#include "tests/attack/attacks.h"
#include "tests/attack/wire_peer.h"
#include "wire/address.h"

namespace troupe::attack {
namespace {

namespace noise = wire::noise;

constexpr int kReplyMs = 10000;  // bounds a hung target, not a requirement
const wire::Address kArm{0, uint16_t(wire::Interface::Position2d), 1};

// Hello, then what the session is for: a peer ready to ask.
bool open_session(WirePeer& peer, const Target& t, const noise::KeyPair& who, std::string* why = nullptr) {
  Frames f;
  return peer.connect_secure(t.port(), t.session_as(who), why) && peer.send(f.hello(0));
}

// The state of a base as the laptop (every right) reads it: its first
// sample after the laptop opens it.
std::optional<wire::Pose2d> pose_and_speed(const Target& t, wire::Address base, wire::Pose2d* speed) {
  WirePeer laptop;
  Frames f;
  if (!open_session(laptop, t, t.keys().laptop) || !laptop.send(f.open(base, 9))) return std::nullopt;
  const Deadline deadline = deadline_in(kReplyMs);
  while (auto frame = laptop.read_frame(ms_left(deadline))) {
    const wire::Message* m = message(*frame);
    if (m == nullptr) return std::nullopt;
    const wire::Position2dState* s = m->body_as_Position2dState();
    if (m->header()->kind() == wire::Kind::Data && s != nullptr && s->pose() != nullptr) {
      if (s->vel() && speed) *speed = *s->vel();
      return *s->pose();
    }
  }
  return std::nullopt;
}

// Counts it as let in when `base` moves or was moved: commands and
// requests that must have been refused.
void expect_still(const Target& t, wire::Address base, Outcome& out, const std::string& what) {
  wire::Pose2d v;
  const std::optional<wire::Pose2d> p = pose_and_speed(t, base, &v);
  if (!p) {
    out.got_through("the laptop could not read " + wire::format_address(base) + " after " + what);
  } else if (p->x() != 0 || p->y() != 0 || p->a() != 0 || v.x() != 0 || v.a() != 0) {
    out.got_through(what + " moved " + wire::format_address(base));
  }
}

// A session the node must end at the first message that does not open: a
// request sealed after it must get no answer.
void expect_session_ends(WirePeer& peer, uint32_t seq, Outcome& out, const std::string& what) {
  if (auto reply = peer.wait_reply(seq, kReplyMs)) out.got_through(what + ": the session went on");
}

}  // namespace

void no_handshake(Target& t, int scale, Outcome& out) {
  out.unit = "connections";
  Frames f;
  for (int i = 0; i < 10 * scale; ++i) {
    WirePeer plain;
    if (!plain.connect(t.port())) continue;
    ++out.volume;
    plain.send(f.hello(0));
    plain.send(f.vel(kPosition0, 0.3f, 0, 0));
    plain.send(f.bare({}, wire::Kind::DeviceList, 0, 1));
    if (auto frame = plain.read_frame(kReplyMs); frame && message(*frame) != nullptr) {
      out.got_through("a plain client got a frame");
    }
  }
  expect_still(t, kPosition0, out, "a plain client's velocity command");
}

void wrong_keys(Target& t, int scale, Outcome& out) {
  out.unit = "handshakes";
  // A key the node does not list (never issued, or revoked by taking it
  // out of the config), and a known client that does not hold this node's
  // key (it would seal its first message to another node).
  noise::SecureOptions stranger = t.session_as(t.keys().stranger);
  noise::SecureOptions misled = t.session_as(t.keys().laptop);
  misled.peer_key = t.keys().stranger.public_key;
  for (int i = 0; i < 10 * scale; ++i) {
    for (const noise::SecureOptions* o : {&stranger, &misled}) {
      WirePeer peer;
      ++out.volume;
      if (peer.connect_secure(t.port(), *o)) out.got_through(o == &stranger ? "an unknown key" : "a wrong node key");
    }
  }
}

void replayed_session(Target& t, int scale, Outcome& out) {
  out.unit = "sessions";
  Frames f;
  // The laptop's session, recorded from the wire: it moves the arm's
  // odometry to x = 7 m.
  WirePeer laptop;
  if (!open_session(laptop, t, t.keys().laptop) ||
      reply_kind(laptop.ask(f.set_odometry(kArm, 1, 7, 0, 0), 1, kReplyMs)) != wire::Kind::Ack) {
    return out.got_through("the laptop's own session failed");
  }
  const Bytes recording = laptop.sent();
  laptop.socket().close();
  WirePeer reset;
  if (!open_session(reset, t, t.keys().laptop) ||
      reply_kind(reset.ask(f.set_odometry(kArm, 1, 0, 0, 0), 1, kReplyMs)) != wire::Kind::Ack) {
    return out.got_through("the laptop could not reset the arm");
  }
  for (int i = 0; i < 5 * scale; ++i) {
    // The node answers the replayed first message with a fresh ephemeral
    // key, so the recorded transport messages cannot open.
    WirePeer replay;
    if (!replay.connect(t.port()) || !replay.socket().send(recording)) continue;
    ++out.volume;
    while (replay.read_frame(kReplyMs)) {
    }
    if (!replay.closed()) out.got_through("a replayed session stayed open");
  }
  wire::Pose2d v;
  const std::optional<wire::Pose2d> arm = pose_and_speed(t, kArm, &v);
  if (!arm || arm->x() != 0) out.got_through("a replayed request set the arm's odometry");
}

void tampered_messages(Target& t, int scale, Outcome& out) {
  out.unit = "messages";
  Frames f;
  enum class Tamper { Replayed, Reordered, Truncated, BitFlipped, Oversized };
  for (int i = 0; i < scale; ++i) {
    for (Tamper how : {Tamper::Replayed, Tamper::Reordered, Tamper::Truncated, Tamper::BitFlipped,
                       Tamper::Oversized}) {
      WirePeer peer;
      if (!open_session(peer, t, t.keys().laptop)) return out.got_through("the laptop's own session failed");
      // Two sealed messages: a request, then a request whose answer would
      // show the session survived the tampering.
      const Bytes a = peer.seal(f.bare(kPosition0, wire::Kind::Request, 1, 1));
      const Bytes b = peer.seal(f.bare(kPosition0, wire::Kind::Request, 1, 2));
      Bytes wire_bytes;
      switch (how) {
        case Tamper::Replayed:
          wire_bytes = a;
          wire_bytes.insert(wire_bytes.end(), a.begin(), a.end());
          break;
        case Tamper::Reordered:
          wire_bytes = b;
          break;
        case Tamper::Truncated:
          wire_bytes.assign(a.begin(), a.end() - 3);
          break;
        case Tamper::BitFlipped:
          wire_bytes = a;
          wire_bytes[wire_bytes.size() / 2] ^= 0x10;
          break;
        case Tamper::Oversized:
          wire_bytes.assign(2 + 65535, 0xA5);  // the longest message the prefix can announce, garbage
          wire_bytes[0] = wire_bytes[1] = 0xFF;
          break;
      }
      wire_bytes.insert(wire_bytes.end(), b.begin(), b.end());
      ++out.volume;
      if (!peer.socket().send(wire_bytes)) continue;  // ended already
      expect_session_ends(peer, 2, out, "a tampered message");
    }
  }
}

void half_open_handshakes(Target& t, int scale, Outcome& out) {
  out.unit = "connections";
  // Half of a first handshake message each, never finished: what a node
  // holds for each must stay bounded, and the laptop must get in.
  WirePeer model;
  Bytes first;
  if (model.connect_secure(t.port(), t.session_as(t.keys().laptop))) first = model.sent();
  model.socket().close();
  if (first.empty()) return out.got_through("the laptop's own handshake failed");
  first.resize(first.size() / 2);
  std::vector<TcpSocket> half(size_t(100 * scale));
  for (TcpSocket& s : half) {
    if (s.connect(t.port()) && s.send(first)) ++out.volume;
  }
  std::string why;
  if (!served_eventually(t.port(), why, 45000, t.legit_session())) {
    out.got_through("the laptop was locked out: " + why);
  }
}

void outside_rights(Target& t, int scale, Outcome& out) {
  out.unit = "messages";
  Frames f;
  // The monitor reads everything and commands nothing; the operator
  // commands the base, not the arm, and sends no requests.
  WirePeer monitor, op;
  if (!open_session(monitor, t, t.keys().monitor) || !open_session(op, t, t.keys().operator_)) {
    return out.got_through("a known client could not open its session");
  }
  uint32_t seq = 0;
  auto forbidden = [&](WirePeer& who, const Bytes& request, uint32_t s, const char* what) {
    ++out.volume;
    const std::optional<Bytes> reply = who.ask(request, s, kReplyMs);
    const wire::Message* m = reply ? message(*reply) : nullptr;
    const wire::Error* e = m ? m->body_as_Error() : nullptr;
    if (m == nullptr || m->header()->kind() != wire::Kind::Nack || e == nullptr ||
        e->code() != wire::ErrorCode::Forbidden) {
      out.got_through(std::string(what) + " was not refused Forbidden");
    }
  };
  for (int i = 0; i < 10 * scale; ++i) {
    monitor.send(f.vel(kPosition0, 0.3f, 0, 0.2f));
    op.send(f.vel(kArm, 0.3f, 0, 0.2f));
    out.volume += 2;
    ++seq;
    forbidden(monitor, f.set_odometry(kPosition0, seq, 3, 0, 0), seq, "the monitor's request");
    forbidden(op, f.set_odometry(kArm, seq, 3, 0, 0), seq, "the operator's request");
  }
  // The replies above came after the commands were handled: neither base
  // may have moved.
  expect_still(t, kPosition0, out, "the monitor's velocity commands");
  expect_still(t, kArm, out, "the operator's commands to the arm");
}

}  // namespace troupe::attack
