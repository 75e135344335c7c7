// A program the test runs as a child process (troupe-sim, troupe-node, or
// troupe-node under qemu-user), its stdout and stderr in files the test
// reads while it runs.
#pragma once

#include <sys/types.h>

#include <cstdint>
#include <string>
#include <vector>

namespace troupe::sitl {

class ChildProcess {
 public:
  ChildProcess() = default;
  /// Kills the child if it still runs.
  ~ChildProcess();
  ChildProcess(const ChildProcess&) = delete;
  ChildProcess& operator=(const ChildProcess&) = delete;

  /// Starts `argv` with its output in `dir`/`tag`.out and `tag`.err. False
  /// with `error` when it cannot be started.
  bool start(const std::vector<std::string>& argv, const std::string& dir, const std::string& tag,
             std::string& error);
  std::string out() const;
  std::string err() const;
  /// Waits until stdout or stderr (`in_err`) holds `needle`, at most
  /// `timeout_ms` (a bound against hangs, not a measurement). False when
  /// it did not, or the child exited first.
  bool wait_for(const std::string& needle, bool in_err, int timeout_ms) const;
  /// False once the child has exited.
  bool running() const;
  /// Waits until the child exits, at most `timeout_ms`; its exit status,
  /// or -1 when it was killed or still runs.
  int wait_exit(int timeout_ms) const;
  /// SIGTERM, then waits (SIGKILL after 20 s). The exit status, or -1.
  int stop();

 private:
  pid_t pid_ = -1;
  mutable int status_ = -1;
  mutable bool exited_ = false;
  std::string out_path_, err_path_;
};

}  // namespace troupe::sitl
