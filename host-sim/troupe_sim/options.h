// troupe-sim's command line.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace troupe::sim {

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
  uint64_t seed = 0;
  std::string listen = "127.0.0.1";
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
  std::string snapshot;       // PNG written at the end (and every snapshot_every s)
  double snapshot_every = 0;  // s of simulated time; 0: only at the end
  std::string log;            // trajectory CSV
  std::vector<std::string> plugin_path;
  bool ignore_missing_ctrl = false;
  /// Run no in-process controllers (the robots are driven over the wire).
  bool no_ctrl = false;
  bool profile = false;  // print the time per phase at the end
  std::string log_level = "info";
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

/// Parses argv. False with `error` (which names the bad argument); `help`
/// set when -h/--help was given.
bool parse_sim_options(int argc, const char* const* argv, SimOptions& out, std::string& error, bool& help);

/// The usage text.
const char* sim_usage();

}  // namespace troupe::sim
