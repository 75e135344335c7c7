// The programs under attack, run as a user runs them, each in its own
// process on loopback: troupe-node serving examples/nodes/kinematic.json,
// troupe-sim on a small world (with its viewer), troupe play serving a
// recording in a loop, and a secure troupe-node (keys, clients with rights).
#pragma once

#include <sys/types.h>

#include <cstdint>
#include <string>

#include "tests/support/child_process.h"
#include "wire/noise/noise_transport.h"

namespace troupe::attack {

enum class TargetKind { Node, Sim, Play, SecureNode };
const char* target_name(TargetKind kind);

/// What a process holds, from /proc.
struct Usage {
  long rss_kib = -1;  // resident memory
  int fds = -1;       // open descriptors
};
Usage usage_of(pid_t pid);

/// The sim target's world: a 10 x 10 m room, r0 with a 181-beam laser, r1.
extern const char* const kSmallWorld;

/// The secure node's keys, each written to the target's folder by name.
/// Its config accepts laptop (every right), monitor (reads everything) and
/// operator (reads everything, commands position2d:0, nothing else); it
/// serves two kinematic bases, position2d:0 and position2d:1.
struct SecureKeys {
  wire::noise::KeyPair node, laptop, monitor, operator_, stranger;
};

class Target {
 public:
  Target() = default;
  ~Target();
  Target(const Target&) = delete;
  Target& operator=(const Target&) = delete;

  /// Starts the program with its scratch files in a new temporary folder
  /// and waits until it serves (bounded). False with `error`.
  bool start(TargetKind kind, std::string& error);
  TargetKind kind() const { return kind_; }
  uint16_t port() const { return port_; }
  /// troupe-sim's viewer (HTTP and WebSocket), 0 for the others.
  uint16_t view_port() const { return view_port_; }
  /// Still running (not crashed, not exited).
  bool alive() const { return proc_.running(); }
  Usage usage() const { return usage_of(proc_.pid()); }
  /// What it logged so far (stderr).
  std::string log() const { return proc_.err(); }
  /// The scratch folder (removed with the target).
  const std::string& dir() const { return dir_; }
  /// SIGTERM and the exit status (-1: killed by a signal or hung).
  int stop() { return proc_.stop(); }
  /// The secure node's keys (all zero for the other targets).
  const SecureKeys& keys() const { return keys_; }
  /// How `who` opens a session with the secure node.
  wire::noise::SecureOptions session_as(const wire::noise::KeyPair& who) const;
  /// The legitimate client's session (the laptop's) for the secure node;
  /// null for a plain target.
  const wire::noise::SecureOptions* legit_session() const {
    return kind_ == TargetKind::SecureNode ? &legit_ : nullptr;
  }

 private:
  TargetKind kind_ = TargetKind::Node;
  testing::ChildProcess proc_;
  std::string dir_;
  uint16_t port_ = 0, view_port_ = 0;
  SecureKeys keys_;
  wire::noise::SecureOptions legit_;
};

/// A built program's path: <bin>/<name>, where bin is this build's
/// (TROUPE_BINARY_DIR/bin) unless set_program_dir() chose another (to
/// attack another build of the same programs, e.g. an older one).
std::string program(const std::string& name);
void set_program_dir(const std::string& dir);

}  // namespace troupe::attack
