#include "tests/attack/targets.h"

#include <dirent.h>

#include <cstdio>
#include <cstring>
#include <fstream>

#include "tests/attack/recordings.h"
#include "wire/noise/key_file.h"

namespace troupe::attack {
namespace {

constexpr int kStartMs = 30000;  // bounds a start that fails, not a requirement

// The number after `prefix` in `text`, 0 when absent.
uint16_t port_after(const std::string& text, const std::string& prefix) {
  const size_t at = text.find(prefix);
  return at == std::string::npos ? 0 : uint16_t(std::atoi(text.c_str() + at + prefix.size()));
}

// The secure node's key files and config in `dir`.
bool write_secure_config(const std::string& dir, SecureKeys& keys, std::string& error) {
  namespace noise = wire::noise;
  const std::pair<const char*, noise::KeyPair*> named[] = {{"node", &keys.node},
                                                            {"laptop", &keys.laptop},
                                                            {"monitor", &keys.monitor},
                                                            {"operator", &keys.operator_},
                                                            {"stranger", &keys.stranger}};
  for (const auto& [name, pair] : named) {
    const std::string path = dir + "/" + name;
    if (!noise::write_key_pair(path, name, error) || !noise::read_secret_key(path, *pair, error)) return false;
  }
  std::ofstream(dir + "/node.json") << R"({ "name": "secure-target", "listen": "127.0.0.1",
  "key": "node",
  "clients": [ { "key": "laptop.pub" },
               { "key": "monitor.pub", "read": ["*"] },
               { "key": "operator.pub", "read": ["*"], "command": ["position2d:0"] } ],
  "drivers": [ { "driver_type": "kinematic", "name": "base", "provides": ["position2d:0"] },
               { "driver_type": "kinematic", "name": "arm", "provides": ["position2d:1"] } ] })";
  return true;
}

}  // namespace

const char* const kSmallWorld = R"(
resolution 0.05
interval_sim 100
model ( name "room" size [10.4 10.4] obstacle_return 1
  block ( points 4 point[0] [0 0] point[1] [10.4 0] point[2] [10.4 0.2] point[3] [0 0.2] )
  block ( points 4 point[0] [0 10.2] point[1] [10.4 10.2] point[2] [10.4 10.4] point[3] [0 10.4] ) )
define bot position ( size [0.4 0.3] )
bot ( name "r0" pose [0 0 0 0] ranger ( sensor ( range [0 8] fov 180 samples 181 ) ) )
bot ( name "r1" pose [-3 2 0 90] )
)";

const char* target_name(TargetKind kind) {
  switch (kind) {
    case TargetKind::Node:
      return "troupe-node";
    case TargetKind::Sim:
      return "troupe-sim";
    case TargetKind::Play:
      return "troupe play";
    case TargetKind::SecureNode:
      return "secure troupe-node";
  }
  return "?";
}

std::string& program_dir() {
  static std::string dir = std::string(TROUPE_BINARY_DIR) + "/bin";
  return dir;
}

std::string program(const std::string& name) {
  return program_dir() + "/" + name;
}

void set_program_dir(const std::string& dir) {
  program_dir() = dir;
}

Usage usage_of(pid_t pid) {
  Usage u;
  if (pid <= 0) return u;
  const std::string proc = "/proc/" + std::to_string(pid);
  std::ifstream status(proc + "/status");
  for (std::string line; std::getline(status, line);) {
    if (line.compare(0, 6, "VmRSS:") == 0) u.rss_kib = std::atol(line.c_str() + 6);
  }
  if (DIR* d = opendir((proc + "/fd").c_str())) {
    u.fds = 0;
    while (const dirent* e = readdir(d)) u.fds += e->d_name[0] != '.';
    closedir(d);
  }
  return u;
}

Target::~Target() {
  proc_.kill_hard();
  testing::remove_tree(dir_);
}

bool Target::start(TargetKind kind, std::string& error) {
  kind_ = kind;
  dir_ = testing::make_temp_dir("troupe-attack-");
  if (dir_.empty()) {
    error = "cannot make a scratch folder";
    return false;
  }
  bool started = false;
  switch (kind) {
    case TargetKind::Node:
      port_ = testing::free_port();
      started = proc_.start(
          {program("troupe-node"), std::string(TROUPE_SOURCE_DIR) + "/examples/nodes/kinematic.json",
           "--port", std::to_string(port_)},
          dir_, "target", error);
      break;
    case TargetKind::Sim: {
      const std::string world = dir_ + "/small.world";
      std::ofstream(world) << kSmallWorld;
      started =
          proc_.start({program("troupe-sim"), world, "--port", "0", "--view", "0"}, dir_, "target", error);
      if (started && !proc_.wait_for("viewer at ", false, kStartMs)) {
        error = "troupe-sim did not start: " + proc_.err();
        return false;
      }
      port_ = port_after(proc_.out(), "listening on 127.0.0.1:");
      view_port_ = port_after(proc_.out(), "viewer at http://127.0.0.1:");
      break;
    }
    case TargetKind::Play: {
      const std::string log = dir_ + "/steady.trl";
      if (!write_recording(log, steady_times(200, 10000), error)) return false;
      port_ = testing::free_port();
      started = proc_.start({program("troupe-play"), log, "--port", std::to_string(port_), "--loop"}, dir_,
                            "target", error);
      break;
    }
    case TargetKind::SecureNode: {
      if (!write_secure_config(dir_, keys_, error)) return false;
      legit_ = session_as(keys_.laptop);
      port_ = testing::free_port();
      started = proc_.start({program("troupe-node"), dir_ + "/node.json", "--port", std::to_string(port_)}, dir_,
                            "target", error);
      break;
    }
  }
  if (!started) return false;
  if (port_ == 0 || !testing::wait_for_listener(port_, kStartMs / 1000.0)) {
    error = std::string(target_name(kind)) + " did not start serving: " + proc_.err();
    return false;
  }
  return true;
}

wire::noise::SecureOptions Target::session_as(const wire::noise::KeyPair& who) const {
  wire::noise::SecureOptions o;
  o.identity = who;
  o.peer_key = keys_.node.public_key;
  return o;
}

}  // namespace troupe::attack
