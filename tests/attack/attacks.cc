#include "tests/attack/attacks.h"

#include <thread>

#include "tests/attack/web_peer.h"
#include "tests/attack/wire_peer.h"

namespace troupe::attack {

void Outcome::got_through(const std::string& what) {
  if (let_in++ == 0) first_let_in = what;
}

const std::vector<Attack>& attacks() {
  using K = TargetKind;
  static const std::vector<Attack> list = {
      {"malformed frames",
       "every kind: wrong body, bad kind, unknown device and subtype, verifier failures, "
       "bit flips, over-limit, zero and truncated lengths",
       {K::Node, K::Sim, K::Play},
       malformed_frames},
      {"null bodies",
       "every kind x every body type, the type set and the body absent (44 bytes)",
       {K::Node, K::Sim, K::Play},
       null_bodies},
      {"non-finite values",
       "NaN and +-inf in every field of velocity, goto, odometry, teleport, speed",
       {K::Node, K::Sim},
       non_finite_values},
      {"idle flood",
       "connections that never speak, past the client limit",
       {K::Node, K::Sim, K::Play},
       idle_flood},
      {"slow readers",
       "readers of the busiest device that never read; requests whose replies are never read",
       {K::Node, K::Sim, K::Play},
       slow_readers},
      {"connect churn",
       "connect and close, reset, half a frame, Hello then gone",
       {K::Node, K::Sim, K::Play},
       connection_churn},
      {"command flood",
       "valid velocity commands as fast as the socket takes them",
       {K::Node, K::Sim, K::Play},
       command_flood},
      {"huge step",
       "simulation:0 step 1000001, 2^32-1, and 1000000 while another client asks",
       {K::Sim},
       huge_step},
      {"viewer foreign origin",
       "WebSocket handshakes from foreign origins and DNS-rebinding Hosts",
       {K::Sim},
       viewer_foreign_origin},
      {"viewer http", "path traversal, oversized headers, held-open partial requests", {K::Sim}, viewer_http},
      {"viewer bad messages",
       "garbage, text, null bodies, oversized messages over an accepted WebSocket",
       {K::Sim},
       viewer_malformed_messages},
      {"corrupt recordings",
       "bit flips, truncations, forged lengths and checksums; --info and play",
       {K::Play},
       corrupt_recordings,
       true},
      {"time-jump recordings",
       "record times jumping to 2^40 us, back, and to 2^64-1; --info and play",
       {K::Play},
       time_jump_recordings,
       true},
      {"no handshake", "plain frames (Hello, a velocity command, DeviceList) to a secure node", {K::SecureNode},
       no_handshake},
      {"wrong keys", "handshakes with a key the node does not list, and to another node's key", {K::SecureNode},
       wrong_keys},
      {"replayed session", "a recorded session (handshake and a request) played again", {K::SecureNode},
       replayed_session},
      {"tampered messages",
       "a live session's message replayed, reordered, truncated, bit-flipped; a 65,535-byte forgery",
       {K::SecureNode},
       tampered_messages},
      {"half-open handshakes", "half a first handshake message, then silence, by the hundred", {K::SecureNode},
       half_open_handshakes},
      {"outside rights",
       "a read-only client's commands and requests; an operator's to a device it may not use",
       {K::SecureNode},
       outside_rights},
  };
  return list;
}

const Attack* find_attack(const std::string& name) {
  for (const Attack& a : attacks()) {
    if (name == a.name) return &a;
  }
  return nullptr;
}

Outcome run_attack(const Attack& attack, TargetKind kind, int scale, std::string& error) {
  Outcome out;
  Target target;
  if (!target.start(kind, error)) return out;
  // The baseline after one visit: the target has served a client once.
  std::string why;
  served(target.port(), why, 20000, target.legit_session());
  out.before = target.usage();
  attack.run(target, scale, out);
  out.survived = out.survived && target.alive();
  out.served =
      target.alive() && served_eventually(target.port(), out.why_not_served, 20000, target.legit_session());
  if (out.served && target.view_port() != 0)
    out.served = served_by_viewer(target.view_port(), out.why_not_served);
  if (!target.alive()) out.why_not_served = std::string(target_name(kind)) + " is gone: " + target.log();
  // For the table: the connections of the attack and the visit are closed
  // by now, given the target a moment to notice.
  for (const Deadline settle = deadline_in(2000);
       target.usage().fds > out.before.fds && ms_left(settle) > 0;) {
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  out.after = target.usage();
  out.has_usage = !attack.own_programs;
  return out;
}

}  // namespace troupe::attack
