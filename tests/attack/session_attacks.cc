// Attacks on the connections themselves: idle ones past the client limit,
// readers that never read, churn, floods of valid commands, and
// simulation:0 steps long enough to hold the loop.
#include <thread>

#include "tests/attack/attacks.h"
#include "tests/attack/wire_peer.h"
#include "wire/address.h"

namespace troupe::attack {
namespace {

constexpr int kReplyMs = 10000;  // bounds a hung target, not a requirement
// A client locked out by idle connections or readers that do not read tries
// again for this long: the server's idle timeout, Hello deadline and the
// eviction of stalled readers must free a slot within it.
constexpr int kLockoutMs = 45000;

// The device that publishes the most: what a slow reader opens.
wire::Address busiest(const Target& t) {
  return t.kind() == TargetKind::Sim ? wire::Address(0, uint16_t(wire::Interface::Ranger), 0) : kPosition0;
}

// Counts a lockout: the legitimate client not served within the bound.
void legit_served_now(const Target& t, Outcome& out, int timeout_ms) {
  std::string why;
  if (!served_eventually(t.port(), why, timeout_ms, t.legit_session()))
    out.got_through("a legitimate client was locked out: " + why);
}

}  // namespace

void idle_flood(Target& t, int scale, Outcome& out) {
  out.unit = "connections";
  // Past any client limit the targets use (64, and 64 + 2 per robot).
  const int count = 100 + 100 * scale;
  std::vector<TcpSocket> idle(static_cast<size_t>(count));
  for (TcpSocket& s : idle) {
    if (s.connect(t.port())) ++out.volume;
  }
  legit_served_now(t, out, kLockoutMs);
}

void slow_readers(Target& t, int scale, Outcome& out) {
  out.unit = "connections";
  Frames f;
  // Past any client limit the targets use, even at scale 1.
  std::vector<WirePeer> readers(size_t(100 + 35 * scale));
  for (WirePeer& r : readers) {
    if (!r.connect(t.port())) continue;
    r.socket().shrink_receive_buffer(1024);
    r.send(f.hello(0));
    r.send(f.open(busiest(t), 1));
    ++out.volume;
  }
  // Requests whose replies are never read: the target must drop such a
  // client rather than queue for it without bound.
  std::vector<WirePeer> deaf(4);
  uint32_t seq = 0;
  for (WirePeer& d : deaf) {
    if (!d.connect(t.port())) continue;
    d.socket().shrink_receive_buffer(1024);
    ++out.volume;
    for (int i = 0; i < 5000 * scale; ++i) {
      if (!d.socket().send_now(f.bare(kPosition0, wire::Kind::Request, 1, ++seq))) break;
    }
  }
  // Data piles up for the readers meanwhile (the targets publish at 10 to
  // 100 Hz). A reader gives up its slot once its socket has stopped taking
  // data, which at 10 Hz takes seconds: the same bound as for idle ones.
  legit_served_now(t, out, kLockoutMs);
}

void connection_churn(Target& t, int scale, Outcome& out) {
  out.unit = "connections";
  Frames f;
  const Bytes hello = f.hello(0);
  const Bytes list = f.bare({}, wire::Kind::DeviceList, 0, 1);
  for (int i = 0; i < 200 * scale; ++i) {
    TcpSocket s;
    if (!s.connect(t.port())) continue;
    ++out.volume;
    switch (i % 4) {
      case 0:
        s.close();
        break;
      case 1:
        s.reset();
        break;
      case 2:  // half a frame, then gone
        s.send(std::span(hello.data(), hello.size() / 2));
        s.reset();
        break;
      case 3:  // a question, and no one left to hear the answer
        s.send(hello);
        s.send(list);
        s.close();
        break;
    }
  }
  legit_served_now(t, out, kReplyMs);
  // Every connection is gone: the target holds no more descriptors than
  // before (given a moment to notice the last hang-ups).
  const Deadline deadline = deadline_in(5000);
  while (t.usage().fds > out.before.fds && ms_left(deadline) > 0) {
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  }
  if (const int leaked = t.usage().fds - out.before.fds; leaked > 0) {
    out.got_through(std::to_string(leaked) + " descriptors still held after the churn");
  }
}

void command_flood(Target& t, int scale, Outcome& out) {
  out.unit = "commands";
  Frames f;
  const Bytes forward = f.vel(kPosition0, 0.1f, 0, 0), back = f.vel(kPosition0, -0.1f, 0, 0);
  std::vector<WirePeer> peers(4);
  for (WirePeer& p : peers) p.connect(t.port());
  // Batches of commands, as fast as the sockets take them.
  Bytes batch;
  for (int i = 0; i < 100; ++i) {
    const Bytes& one = i % 2 ? back : forward;
    batch.insert(batch.end(), one.begin(), one.end());
  }
  for (int round = 0; round < 500 * scale; ++round) {
    for (WirePeer& p : peers) {
      if (p.send(batch, kReplyMs)) out.volume += 100;
    }
  }
  for (WirePeer& p : peers) p.send(f.vel(kPosition0, 0, 0, 0));
  legit_served_now(t, out, kReplyMs);
}

void huge_step(Target& t, int scale, Outcome& out) {
  out.unit = "requests";
  Frames f;
  WirePeer attacker, other;
  if (!attacker.connect(t.port()) || !other.connect(t.port())) {
    out.got_through("could not connect");
    return;
  }
  uint32_t seq = 0;
  // The clock's step count in a reply, or nothing.
  auto steps_in = [](const std::optional<Bytes>& reply) -> std::optional<uint64_t> {
    const wire::Message* m = reply ? message(*reply) : nullptr;
    const wire::SimClock* c = m ? m->body_as_SimClock() : nullptr;
    return c ? std::optional<uint64_t>(c->steps()) : std::nullopt;
  };
  ++seq;
  attacker.ask(f.sim_request(seq, wire::SimulationReqSub::Pause), seq, kReplyMs);
  for (int i = 0; i < scale; ++i) {
    for (uint32_t steps : {1000001u, 0xFFFFFFFFu}) {
      ++out.volume;
      ++seq;
      if (reply_kind(attacker.ask(f.sim_step(seq, steps), seq, kReplyMs)) == wire::Kind::Ack)
        out.got_through("step " + std::to_string(steps) + " was run");
    }
  }
  // The largest step allowed: while it runs, another client is answered,
  // and what it is told shows the step under way (neither before it
  // started nor after it ended).
  ++seq;
  const uint64_t start =
      steps_in(other.ask(f.sim_request(seq, wire::SimulationReqSub::GetClock), seq, kReplyMs)).value_or(0);
  ++out.volume;
  attacker.send(f.sim_step(++seq, 1000000));
  bool answered_during = false;
  for (int tries = 0; tries < 100 && !answered_during; ++tries) {
    ++seq;
    const auto now = steps_in(other.ask(f.sim_request(seq, wire::SimulationReqSub::GetClock), seq, kReplyMs));
    if (!now) break;
    const uint64_t steps = *now;
    if (steps >= start + 1000000) break;  // the step ended before anyone else was served
    answered_during = steps > start;
  }
  if (!answered_during)
    out.got_through("step 1000000 held the loop: another client was not served meanwhile");
}

}  // namespace troupe::attack
