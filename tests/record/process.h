// Programs run as child processes by the record/replay tests: troupe-node,
// room_node, and the troupe CLI's record and play, as a user runs them.
#pragma once

#include <sys/types.h>

#include <cstdint>
#include <string>
#include <vector>

namespace troupe::testing {

/// Paths of the built programs (from TROUPE_BINARY_DIR).
std::string bin(const std::string& relative);
/// A TCP port nobody listens on right now.
uint16_t free_port();
/// True when something accepts connections on 127.0.0.1:port.
bool listening(uint16_t port);

class Process {
 public:
  /// Starts `argv[0]` with `argv`; stdout and stderr go to files read back
  /// by out() and err().
  explicit Process(std::vector<std::string> argv);
  ~Process();
  Process(const Process&) = delete;
  Process& operator=(const Process&) = delete;

  /// Waits up to `timeout_ms` for the process to exit; its exit code, or -1
  /// when it did not exit in time (it is still running).
  int wait(int timeout_ms = 30000);
  /// Sends `signal` and waits for the exit; the exit code (or -signal).
  int stop(int signal = 15);
  /// Waits until it listens on `port`; false when it exited first or after 10 s.
  bool wait_listening(uint16_t port);
  bool running();
  std::string out() const;
  std::string err() const;
  pid_t pid() const { return pid_; }

 private:
  pid_t pid_ = -1;
  int status_ = -1;
  std::string out_path_, err_path_;
};

/// Runs a program to its end; its exit code, stdout and stderr.
struct Outcome {
  int rc = -1;
  std::string out, err;
};
Outcome run_program(std::vector<std::string> argv, int timeout_ms = 60000);

}  // namespace troupe::testing
