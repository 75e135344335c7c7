// A troupe-node (or another target program) running under qemu-user, as a
// child process of the test. Its stderr goes to a file the test reads.
#pragma once

#include <sys/types.h>

#include <cstdint>
#include <string>
#include <vector>

#include "tests/cross/cross_build.h"

namespace troupe::cross {

class QemuNode {
 public:
  QemuNode() = default;
  ~QemuNode();
  QemuNode(const QemuNode&) = delete;
  QemuNode& operator=(const QemuNode&) = delete;

  /// How to start: a target library to preload, and a host program that
  /// runs the node as its child (e.g. {"troupe-emulate-odrive", "--"}).
  struct Extras {
    std::string preload;
    std::vector<std::string> wrapper;
  };

  /// Starts `binary` (a troupe-node of `build`, or one unpacked from a
  /// bundle) with `config` on a free loopback port, and waits until it says
  /// it serves. False with `error` (including the node's log) when it does
  /// not come up; exited() then tells whether it exited, and with what.
  bool start(const CrossBuild& build, const std::string& binary, const std::string& config,
             std::string& error, const Extras& extras = {});
  /// The exit status of a node that exited before serving, else -1.
  int exited() const { return exit_status_; }

  /// The TCP port the node listens on.
  uint16_t port() const { return port_; }
  pid_t pid() const { return pid_; }
  /// Everything the node wrote to stderr so far.
  std::string log() const;
  /// Waits until the log holds `count` lines containing `needle`, at most
  /// `timeout_ms` (a bound against hangs, not a measurement).
  bool wait_for_log(const std::string& needle, int count = 1, int timeout_ms = 20000) const;
  /// Sends a signal to the emulated program (qemu-user passes it on).
  void signal(int sig) const;
  /// SIGTERM, then waits. Returns the exit status, or -1 when killed.
  int stop();
  bool running() const { return pid_ > 0; }

 private:
  pid_t pid_ = -1;
  int exit_status_ = -1;
  uint16_t port_ = 0;
  std::string log_path_;
  std::string dir_;
};

/// The argv that runs a target program of `build` under qemu-user:
/// qemu -L <loader prefix> [-E LD_LIBRARY_PATH=..] [-E LD_PRELOAD=..] program.
std::vector<std::string> qemu_argv(const CrossBuild& build, const std::string& program,
                                   const std::string& preload = "");

/// qemu_argv() as one shell command line, for run().
std::string qemu_command(const CrossBuild& build, const std::string& program,
                         const std::vector<std::string>& args);

}  // namespace troupe::cross
