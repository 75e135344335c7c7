#include "host-sim/troupe_sim/options.h"

#include <cerrno>
#include <cmath>
#include <cstdlib>

namespace troupe::sim {

const char* sim_usage() {
  return "usage: troupe-sim WORLD [options]\n"
         "\n"
         "Simulates the Stage world file WORLD and serves every robot's devices over the\n"
         "wire: robot i's devices are ROBOT/INTERFACE:INDEX (r0/position2d:0, r0/ranger:1)\n"
         "on one port, and simulation:0 pauses, steps, teleports and resets. A RoboCup\n"
         "match written as a Stage world (robocup_field, ball, referee, robocup_robot)\n"
         "runs on rigid-body physics, served the same way, with players and a score.\n"
         "\n"
         "options:\n"
         "  --headless              no window (always; the viewer connects over the wire)\n"
         "  --fast                  run as fast as possible\n"
         "  --speed X               run at X times real time (0: as fast as possible)\n"
         "  --quit-time SECONDS     stop after this much simulated time\n"
         "  --paused                start paused\n"
         "  --seed N                seed of every random number in the run (default 0)\n"
         "  --port P                TCP port (default 6665; 0: any free port, printed)\n"
         "  --listen ADDR           address to listen on (default 127.0.0.1)\n"
         "  --port-per-robot        also serve robot i alone as robot 0 on port P+1+i\n"
         "  --no-serve              no network at all (batch runs)\n"
         "  --view [P]              browser viewer on HTTP port P (default 6680; 0: any free\n"
         "                          port); on by default, its URL is printed\n"
         "  --view-listen ADDR      address the viewer listens on (default 127.0.0.1)\n"
         "  --no-view               no browser viewer\n"
         "  --snapshot FILE.png     picture of the world at the end\n"
         "  --snapshot-every S      ... and every S simulated seconds\n"
         "  --log FILE.csv          trajectory log: time,robot,x,y,a every step\n"
         "  --plugin-path DIR       look for plugins (controllers: ctrl \"name\") in DIR first;\n"
         "                          then ../lib/troupe beside troupe-sim, $TROUPE_PLUGIN_PATH,\n"
         "                          the world's folder\n"
         "  --ignore-missing-ctrl   load anyway; robots whose controller is missing stay idle\n"
         "  --no-ctrl               run no controllers: every robot waits for clients\n"
         "  --profile               print the time spent in each phase of the step at the end\n"
         "  --log-level LEVEL       error, warn, info (default) or debug\n"
         "\n"
         "hardware in the loop (SITL):\n"
         "  --emulate ROBOT=DEVS    present a robot (name or number) as hardware: DEVS is\n"
         "                          p2os (its base as a Pioneer), sicklms200 (its laser as a\n"
         "                          SICK LMS200) or both, comma-separated; each on a new\n"
         "                          pseudo-terminal, printed as a line ROBOT DEVICE PATH\n"
         "                          (repeatable, one per robot)\n"
         "  --emulate-info FILE     also write those lines to FILE (complete when it appears)\n"
         "  --emulate-links DIR     also name each device DIR/ROBOT-DEVICE (a symbolic link)\n"
         "  --p2os-tcp[=PORT]       serve every robot's base as a Pioneer (P2OS) on TCP, as\n"
         "                          MobileSim does: robot i on PORT+i (default 8101), its\n"
         "                          laser in MobileSim's laser packets; unchanged ARIA\n"
         "                          programs connect to it (printed as lines ROBOT p2os-tcp\n"
         "                          HOST:PORT)\n"
         "\n"
         "examples:\n"
         "  troupe-sim examples/worlds/swarm100.world --fast --quit-time 60 --snapshot out.png\n"
         "  troupe-sim simple.world --port 7000 & troupe ls localhost:7000\n"
         "  troupe-sim examples/worlds/sitl_room.world --emulate r0=p2os,sicklms200\n"
         "  troupe-sim examples/worlds/sitl_room.world --p2os-tcp      # ARIA: localhost:8101
"
         "  troupe-sim examples/robocup/match.world          # a RoboCup match, served and drawn
";
}

namespace {

bool number(const char* text, double& out) {
  char* end = nullptr;
  errno = 0;
  out = std::strtod(text, &end);
  return end != text && *end == '\0' && errno == 0 && std::isfinite(out);
}

}  // namespace

bool parse_sim_options(int argc, const char* const* argv, SimOptions& out, std::string& error, bool& help) {
  help = false;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    auto value = [&](const char*& v) {
      if (i + 1 >= argc) {
        error = a + " needs a value";
        return false;
      }
      v = argv[++i];
      return true;
    };
    auto real = [&](double& v, double min) {
      const char* t;
      if (!value(t)) return false;
      if (!number(t, v) || v < min) {
        error = a + ": not a number >= " + std::to_string(min) + ": " + t;
        return false;
      }
      return true;
    };
    const char* t = nullptr;
    double d = 0;
    if (a == "-h" || a == "--help") {
      help = true;
      return true;
    } else if (a == "--headless") {
      out.headless = true;
    } else if (a == "--fast") {
      out.fast = true;
    } else if (a == "--paused") {
      out.paused = true;
    } else if (a == "--port-per-robot") {
      out.port_per_robot = true;
    } else if (a == "--no-serve") {
      out.serve = false;
    } else if (a == "--ignore-missing-ctrl") {
      out.ignore_missing_ctrl = true;
    } else if (a == "--no-ctrl") {
      out.no_ctrl = true;
    } else if (a == "--profile") {
      out.profile = true;
    } else if (a == "--speed") {
      if (!real(out.speed, 0)) return false;
    } else if (a == "--quit-time") {
      if (!real(out.quit_time, 0)) return false;
    } else if (a == "--snapshot-every") {
      if (!real(out.snapshot_every, 0)) return false;
    } else if (a == "--seed") {
      if (!real(d, 0) || d != std::floor(d) || d > 1.8e19) {
        if (error.empty()) error = "--seed: not a whole number";
        return false;
      }
      out.seed = uint64_t(d);
    } else if (a == "--port") {
      if (!real(d, 0) || d > 65535 || d != std::floor(d)) {
        if (error.empty()) error = "--port: not a port number (0..65535)";
        return false;
      }
      out.port = uint16_t(d);
    } else if (a == "--view") {
      out.view = out.view_asked = true;
      // The port is optional: taken only when the next argument is a number.
      if (i + 1 < argc && number(argv[i + 1], d)) {
        if (d < 0 || d > 65535 || d != std::floor(d)) {
          error = "--view: not a port number (0..65535)";
          return false;
        }
        out.view_port = uint16_t(d);
        ++i;
      }
    } else if (a == "--no-view") {
      out.view = false;
    } else if (a == "--view-listen") {
      if (!value(t)) return false;
      out.view_listen = t;
      out.view = out.view_asked = true;
    } else if (a == "--listen") {
      if (!value(t)) return false;
      out.listen = t;
    } else if (a == "--snapshot") {
      if (!value(t)) return false;
      out.snapshot = t;
    } else if (a == "--log") {
      if (!value(t)) return false;
      out.log = t;
    } else if (a == "--plugin-path") {
      if (!value(t)) return false;
      out.plugin_path.push_back(t);
    } else if (a == "--emulate") {
      if (!value(t)) return false;
      out.emulate.push_back(t);
    } else if (a == "--emulate-info") {
      if (!value(t)) return false;
      out.emulate_info = t;
    } else if (a == "--emulate-links") {
      if (!value(t)) return false;
      out.emulate_links = t;
    } else if (a == "--p2os-tcp" || a.rfind("--p2os-tcp=", 0) == 0) {
      out.p2os_tcp_port = 8101;
      if (a.size() > 10) {
        char* end = nullptr;
        const std::string v = a.substr(11);
        unsigned long port = strtoul(v.c_str(), &end, 10);
        if (v.empty() || *end != '\0' || port > 65535) {
          error = "--p2os-tcp=PORT: not a port number (0..65535)";
          return false;
        }
        out.p2os_tcp_port = int(port);
      }
    } else if (a == "--log-level") {
      if (!value(t)) return false;
      out.log_level = t;
    } else if (!a.empty() && a[0] == '-') {
      error = "unknown option " + a;
      return false;
    } else if (out.world.empty()) {
      out.world = a;
    } else {
      error = "one world file only; also got " + a;
      return false;
    }
  }
  if (out.world.empty()) {
    error = "no world file given";
    return false;
  }
  if (out.paused && !out.serve) {
    error = "--paused with --no-serve: nothing could ever resume the simulation";
    return false;
  }
  if (out.p2os_tcp_port >= 0 && !out.serve) {
    error = "--p2os-tcp with --no-serve: --no-serve opens no sockets";
    return false;
  }
  return true;
}

}  // namespace troupe::sim
