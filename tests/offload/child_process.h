// Real programs (troupe-node, troupe-sim) run as child processes by the
// offload tests, which kill and restart them the way a robot loses power.
#pragma once

#include <sys/types.h>

#include <cstdint>
#include <string>
#include <vector>

namespace troupe::testing {

class ChildProcess {
 public:
  ChildProcess() = default;
  ~ChildProcess() { stop(); }
  ChildProcess(const ChildProcess&) = delete;
  ChildProcess& operator=(const ChildProcess&) = delete;

  /// Starts `argv[0]` with its output appended to `log_path`. False with
  /// `error` when it cannot be started.
  bool start(const std::vector<std::string>& argv, const std::string& log_path, std::string& error);
  /// SIGTERM, then waits for it to end.
  void stop();
  /// SIGKILL: gone without a goodbye, as when a robot loses power.
  void kill_hard();
  bool running() const { return pid_ > 0; }

 private:
  pid_t pid_ = -1;
};

/// A TCP port on 127.0.0.1 nothing listens on right now.
uint16_t free_port();
/// True once something accepts connections on 127.0.0.1:`port`, within
/// `timeout_s` (which only bounds a failing test).
bool wait_for_listener(uint16_t port, double timeout_s);
/// A new folder under the system's temporary folder, named `prefix` and a
/// unique suffix; "" when it cannot be made.
std::string make_temp_dir(const std::string& prefix);
/// Removes a folder and everything in it.
void remove_tree(const std::string& path);
/// The whole file, or "" when it cannot be read.
std::string read_text(const std::string& path);

}  // namespace troupe::testing
