// Real programs (troupe-sim, troupe-node, troupe-node under qemu-user) run
// by tests as child processes, their output in files the test reads while
// they run; killed and restarted the way a robot loses power.
#pragma once

#include <sys/types.h>

#include <cstdint>
#include <string>
#include <vector>

namespace troupe::testing {

class ChildProcess {
 public:
  ChildProcess() = default;
  /// Kills the child (SIGKILL) if it still runs.
  ~ChildProcess();
  ChildProcess(const ChildProcess&) = delete;
  ChildProcess& operator=(const ChildProcess&) = delete;

  /// Starts `argv` (argv[0] found on PATH or as a path) with stdout in
  /// `dir`/`tag`.out and stderr in `dir`/`tag`.err, both truncated. Stops
  /// the child this object ran before. False with `error` when it cannot
  /// be started.
  bool start(const std::vector<std::string>& argv, const std::string& dir, const std::string& tag,
             std::string& error);
  /// Like start(), with stdout and stderr both appended to `log_path`: a
  /// restarted program's log follows the previous run's.
  bool start_logged(const std::vector<std::string>& argv, const std::string& log_path, std::string& error);
  /// What the child wrote so far (out() and err() are the same file after
  /// start_logged()).
  std::string out() const;
  std::string err() const;
  /// Waits until stdout or stderr (`in_err`) holds `needle`, at most
  /// `timeout_ms` (a bound against hangs, not a measurement). False when
  /// it did not, or the child exited first.
  bool wait_for(const std::string& needle, bool in_err, int timeout_ms) const;
  /// False once the child has exited (or was never started).
  bool running() const;
  /// The child's process id (for /proc/PID; benchmarks read its CPU time), -1 before start().
  pid_t pid() const { return pid_; }
  /// Waits until the child exits, at most `timeout_ms`; its exit status,
  /// or -1 when it was killed by a signal or still runs.
  int wait_exit(int timeout_ms) const;
  /// SIGTERM, then waits (SIGKILL after 20 s). The exit status, or -1.
  int stop();
  /// SIGKILL: gone without a goodbye, as when a robot loses power.
  void kill_hard();

 private:
  bool spawn(const std::vector<std::string>& argv, int out_fd, int err_fd, std::string& error);
  void reap_now();

  pid_t pid_ = -1;
  mutable int status_ = -1;
  mutable bool exited_ = false;
  std::string out_path_, err_path_;
};

/// What a program run to its end left.
struct ProgramResult {
  /// exit status; -1 when it was killed by a signal or ran past the timeout
  int status = -1;
  std::string out, err;
};
/// Runs `argv` to its end (killed after `timeout_ms`, a bound against hangs),
/// as a user runs it, and returns its exit status and output.
ProgramResult run_to_end(const std::vector<std::string>& argv, int timeout_ms);

/// A TCP port on 127.0.0.1 nothing listens on right now.
uint16_t free_port();
/// True once something accepts connections on 127.0.0.1:`port`, within
/// `timeout_s` (which only bounds a failing test; 0: asks once).
bool wait_for_listener(uint16_t port, double timeout_s);
/// A new folder under the system's temporary folder, named `prefix` and a
/// unique suffix; "" when it cannot be made.
std::string make_temp_dir(const std::string& prefix);
/// Removes a folder and everything in it.
void remove_tree(const std::string& path);
/// The whole file, or "" when it cannot be read.
std::string read_text(const std::string& path);

}  // namespace troupe::testing
