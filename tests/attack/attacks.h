// The attack suite: hostile inputs thrown at troupe-node, troupe-sim (and its
// viewer) and troupe play over loopback, each followed by a legitimate
// client's visit. One list of cases serves the tests (attack_test.cc, small
// volumes, label `attack`) and the benchmark that prints the table
// (tests/bench/attack, large volumes).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "tests/attack/targets.h"

namespace troupe::attack {

/// What one attack did to one target.
struct Outcome {
  /// Hostile inputs sent (frames, connections, requests, files...).
  uint64_t volume = 0;
  std::string unit;
  /// Hostile inputs that got through: accepted when they must be refused
  /// (an Ack, a 101, a 200, a non-finite state), or that locked the
  /// legitimate client out. Zero when the defences held.
  uint64_t let_in = 0;
  /// The first thing that got through, for the failure message.
  std::string first_let_in;
  /// The target (or every program run by the case) still running, no crash.
  bool survived = true;
  /// A legitimate client was served afterwards (a request got its answer).
  bool served = false;
  std::string why_not_served;
  /// The target's memory and descriptors before and after (the cases that
  /// run one program per input have none).
  Usage before, after;
  bool has_usage = true;

  /// Counts one input that got through, keeping the first description.
  void got_through(const std::string& what);
};

struct Attack {
  const char* name;
  /// One line: what is thrown.
  const char* what;
  std::vector<TargetKind> targets;
  /// Throws the attack at `target` (already serving). `scale` multiplies
  /// the volume: 1 in the tests.
  void (*run)(Target& target, int scale, Outcome& out);
  /// The case runs its own programs (troupe play per file): the target's
  /// memory says nothing about it.
  bool own_programs = false;
};

/// A hostile frame and, when acknowledging it would be letting it in, what
/// to call that (empty: any answer is fine as long as the target lives).
struct HostileFrame {
  std::vector<uint8_t> frame;
  std::string if_acked;
};
/// Frames whose union type is set and whose body is absent (44 bytes each):
/// every kind with every body type to the target's devices, and the
/// requests that need their body.
std::vector<HostileFrame> null_body_frames(TargetKind kind);
/// Fewer of them: each kind with the body it would carry, and the requests
/// that need their body.
std::vector<HostileFrame> null_body_sample(TargetKind kind);

/// Every case, in the order of the table.
const std::vector<Attack>& attacks();
const Attack* find_attack(const std::string& name);

/// Starts a fresh target, measures it, throws the attack, visits it as a
/// legitimate client, measures it again. `error` when the target would not
/// start (then nothing was thrown).
Outcome run_attack(const Attack& attack, TargetKind kind, int scale, std::string& error);

// The cases, by topic (frame_attacks.cc, session_attacks.cc,
// viewer_attacks.cc, record_attacks.cc, secure_attacks.cc).
void malformed_frames(Target& t, int scale, Outcome& out);
void null_bodies(Target& t, int scale, Outcome& out);
void non_finite_values(Target& t, int scale, Outcome& out);
void idle_flood(Target& t, int scale, Outcome& out);
void slow_readers(Target& t, int scale, Outcome& out);
void connection_churn(Target& t, int scale, Outcome& out);
void command_flood(Target& t, int scale, Outcome& out);
void huge_step(Target& t, int scale, Outcome& out);
void viewer_foreign_origin(Target& t, int scale, Outcome& out);
void viewer_http(Target& t, int scale, Outcome& out);
void viewer_malformed_messages(Target& t, int scale, Outcome& out);
void corrupt_recordings(Target& t, int scale, Outcome& out);
void time_jump_recordings(Target& t, int scale, Outcome& out);
void no_handshake(Target& t, int scale, Outcome& out);
void wrong_keys(Target& t, int scale, Outcome& out);
void replayed_session(Target& t, int scale, Outcome& out);
void tampered_messages(Target& t, int scale, Outcome& out);
void half_open_handshakes(Target& t, int scale, Outcome& out);
void outside_rights(Target& t, int scale, Outcome& out);

}  // namespace troupe::attack
