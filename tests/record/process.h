// Programs run by the record/replay tests (troupe-node, room_node, troupe-sim
// and the troupe CLI's record and play, as a user runs them), started in one
// line each on top of the shared ChildProcess.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "tests/support/child_process.h"

namespace troupe::testing {

/// Paths of the built programs (from TROUPE_BINARY_DIR).
std::string bin(const std::string& relative);

class Process {
 public:
  /// Starts `argv`; stdout and stderr go to files read back by out() and
  /// err() (in a scratch folder removed with the object).
  explicit Process(std::vector<std::string> argv);
  ~Process();
  Process(const Process&) = delete;
  Process& operator=(const Process&) = delete;

  /// Waits up to `timeout_ms` for the process to exit; its exit code, or -1
  /// when it did not exit in time or was killed by a signal.
  int wait(int timeout_ms = 30000) { return child_.wait_exit(timeout_ms); }
  /// SIGTERM and waits for the exit; the exit code, or -1.
  int stop() { return child_.stop(); }
  /// Waits until it listens on `port`; false when it exited first or after 10 s.
  bool wait_listening(uint16_t port);
  bool running() const { return child_.running(); }
  std::string out() const { return child_.out(); }
  std::string err() const { return child_.err(); }

 private:
  std::string dir_;
  ChildProcess child_;
};

/// Runs a program to its end; its exit code, stdout and stderr.
struct Outcome {
  int rc = -1;
  std::string out, err;
};
Outcome run_program(std::vector<std::string> argv, int timeout_ms = 60000);

}  // namespace troupe::testing
