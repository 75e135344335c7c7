// troupe-sim's command line.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "runtime/node_secure.h"

namespace troupe::sim {

/// MobileSim's first robot port, where `--p2os-tcp` serves robot 0.
inline constexpr int kMobileSimPort = 8101;

/// The name troupe-sim also answers to: `troupe-robocup ARGS` (a symbolic
/// link to it, `troupe robocup ARGS` through the CLI) is
/// `troupe-sim --fast --no-serve ARGS`, a match flat out from the console.
inline constexpr const char* kRobocupAlias = "troupe-robocup";

/// True when the program was started under the alias's name (argv[0]).
bool started_as_robocup_alias(const char* argv0);

struct SimOptions {
  std::string world;
  bool headless = true;  // there is no window; the browser viewer connects over the wire
  /// As fast as possible (overrides the world's speedup).
  bool fast = false;
  /// Multiple of real time; negative: the world file's speedup.
  double speed = -1;
  /// Stop after this much simulated time, s; negative: the world's quit_time.
  double quit_time = -1;
  /// Start paused (a client resumes it through simulation:0).
  bool paused = false;
  /// Seeds every random number of the run, 0 included, when seed_given;
  /// otherwise the world's own seed: a RoboCup world's `seed`, and 0 for a
  /// Stage world (it has no such key).
  uint64_t seed = 0;
  bool seed_given = false;
  std::string listen = "localhost";
  /// --secure FILE: the key and clients (with rights) of secure sessions,
  /// as in a node config (runtime/node_secure.h). Empty: plain TCP.
  std::string secure_file;
  /// What main() read from secure_file; every node the simulator serves
  /// runs it.
  SecureSessions secure;
  /// --view-identity FILE: the secret key its viewer's bridge opens secure
  /// sessions with, one of the clients in secure_file.
  std::string view_identity;
  /// Serve plain TCP beyond loopback (runtime/exposure.h): without
  /// secure_file, listening anywhere else must be asked for.
  bool insecure = false;
  /// TCP port; 0 picks a free one (printed at start).
  uint16_t port = 6665;
  /// Also serve robot i alone, as robot 0, on port + 1 + i.
  bool port_per_robot = false;
  bool serve = true;  // --no-serve: no sockets at all (batch runs)
  /// The browser viewer (HTTP + WebSocket bridge to the main port).
  bool view = true;
  /// --view given: failing to bind its port is then an error, not a warning.
  bool view_asked = false;
  /// Viewer HTTP port; 0 picks a free one (printed).
  uint16_t view_port = 6680;
  std::string view_listen = "127.0.0.1";
  /// Page origins ("http://host:port") whose WebSockets the viewer accepts
  /// besides its own (see viewer::ViewOptions::allow_origins).
  std::vector<std::string> view_allow_origins;
  std::string snapshot;       // PNG written at the end (and every snapshot_every s)
  double snapshot_every = 0;  // s of simulated time; 0: only at the end
  std::string log;            // trajectory CSV
  std::vector<std::string> plugin_path;
  bool ignore_missing_ctrl = false;
  /// Run no in-process controllers (the robots are driven over the wire).
  bool no_ctrl = false;
  bool profile = false;  // print the time per phase at the end
  /// Under mpirun: steps between redrawing the processes' regions around
  /// where the robots are (0: never).
  uint64_t rebalance_every = 100;
  /// Under mpirun: what the regions are drawn to share out evenly, "time"
  /// (each process's measured step time) or "robots".
  std::string rebalance_by = "robots";
  /// RoboCup worlds: console commands (robocup/game/console.h) from this
  /// file, or from standard input when `interactive`, run between cycles.
  /// The commands then decide how far the match runs, flat out, unserved.
  std::string script;
  bool interactive = false;
  /// RoboCup worlds: no referee event lines on standard output (the final
  /// score line stays).
  bool quiet = false;
  /// The name in messages and the log: troupe-sim, or kRobocupAlias.
  std::string program = "troupe-sim";

  bool console() const { return !script.empty() || interactive; }
  /// --emulate ROBOT=DEVICE[,DEVICE]: robots presented as hardware on
  /// pseudo-terminals (SITL); see emulation.h.
  std::vector<std::string> emulate;
  /// Also write the emulated devices' "ROBOT DEVICE PATH" lines here.
  std::string emulate_info;
  /// Give each emulated device a stable name in this folder: ROBOT-DEVICE.
  std::string emulate_links;
  /// --p2os-tcp[=PORT]: every robot's base as a Pioneer speaking P2OS on
  /// TCP, robot i on PORT + i (MobileSim's 8101 by default), its laser in
  /// MobileSim's SIM packets; 0 picks free ports. -1: off.
  int p2os_tcp_port = -1;
};

/// Parses troupe-sim's command line into `out`. Returns -1 when the program
/// goes on; otherwise its exit status, after printing the help (0) or a
/// one-line mistake (2).
int parse_sim_options(int argc, const char* const* argv, SimOptions& out);

}  // namespace troupe::sim
