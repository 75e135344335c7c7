// troupe-emulate-odrive: ODrive axes on a CAN bus, for trying the odrive_can
// driver without hardware: on a SocketCAN interface, a descriptor, or a
// socketpair whose other end a command it runs gets as descriptor 3.
#include <signal.h>
#include <sys/signalfd.h>
#include <sys/socket.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdio>
#include <cstring>
#include <string>
#include <vector>

#include "drivers/odrive_can/can_io.h"
#include "host-sim/emulators/odrive/fault_console.h"
#include "host-sim/emulators/odrive/odrive_emulator.h"
#include "runtime/log.h"
#include "wire/cli/args.h"

namespace {

using troupe::emulators::odrive::AxisConfig;
using troupe::emulators::odrive::EmulatorOptions;
using troupe::emulators::odrive::OdriveEmulator;

// Reads fault commands from standard input, prints the axes' state now and
// then, and stops the loop on a signal or when the child exits.
class Watch final : public troupe::FdHandler, public troupe::TimerHandler {
 public:
  Watch(troupe::EventLoop& loop, OdriveEmulator& emu) : loop_(loop), emu_(emu) {}
  int signal_fd = -1;
  pid_t child = -1;
  int exit_code = 0;

  void on_fd(int fd, uint32_t) override {
    if (fd == STDIN_FILENO) return read_commands();
    signalfd_siginfo info{};
    if (read(fd, &info, sizeof info) != sizeof info) return;
    if (info.ssi_signo == SIGCHLD) {
      int status = 0;
      if (child <= 0 || waitpid(child, &status, WNOHANG) != child) return;
      exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
      troupe::log_info("%d exited (%d)", int(child), exit_code);
      child = -1;
    } else if (child > 0) {
      kill(child, int(info.ssi_signo));  // let the command shut down first
      return;
    }
    loop_.stop();
  }
  void on_timer(troupe::TimerId) override {
    printf("%s\n", status_line().c_str());
    fflush(stdout);
  }

 private:
  std::string status_line() {
    std::string line;
    for (const AxisConfig& c : emu_.options().axes) {
      line += (line.empty() ? "" : " | ") + troupe::emulators::odrive::axis_status(*emu_.axis(c.node_id));
    }
    return line;
  }
  void read_commands() {
    char chunk[512];
    ssize_t n = read(STDIN_FILENO, chunk, sizeof chunk);
    if (n <= 0) {
      loop_.unwatch(STDIN_FILENO);  // no more commands; the emulator runs on
      return;
    }
    pending_.append(chunk, size_t(n));
    for (size_t end; (end = pending_.find('\n')) != std::string::npos; pending_.erase(0, end + 1)) {
      std::string reply = troupe::emulators::odrive::apply_fault_command(
          emu_, std::string_view(pending_).substr(0, end), loop_.now_us());
      if (!reply.empty()) printf("%s\n", reply.c_str());
    }
    if (pending_.size() > 4096) pending_.clear();  // a line that never ends is no command
    fflush(stdout);
  }

  troupe::EventLoop& loop_;
  OdriveEmulator& emu_;
  std::string pending_;
};

}  // namespace

int main(int argc, char** argv) {
  troupe::set_log_program("troupe-emulate-odrive");
  signal(SIGPIPE, SIG_IGN);
  std::string ifname;
  int descriptor = -1;
  uint32_t watchdog_ms = 500, status_ms = 1000;
  float ramp = 20, wrap = 0, volts = 24;
  double drop = 0;
  uint64_t seed = 1;
  // Everything after "--" is the command, not ours to parse.
  int ours = 1;
  while (ours < argc && strcmp(argv[ours], "--") != 0) ++ours;
  char** command = ours + 1 < argc ? argv + ours + 1 : nullptr;
  auto app = troupe::cli::make_app(
      "troupe-emulate-odrive",
      {"troupe-emulate-odrive [--can IFACE | --descriptor FD] [options] [-- COMMAND [ARGS...]]",
       "Emulates ODrive axes (CAN Simple protocol): heartbeats every 100 ms, encoder\n"
       "estimates every 10 ms, closed-loop velocity control with a wheel's physics.\n"
       "With -- COMMAND ARGS, runs COMMAND with the other end of a socketpair as\n"
       "descriptor 3 (a node config with \"descriptor\": 3).\n"
       "\n"
       "Fault commands on standard input, one a line: silent NODE on|off,\n"
       "error NODE BITS [keep], clear NODE, reboot NODE, drop P, garbage NODE N, status.\n",
       {"troupe-emulate-odrive -- troupe-node examples/nodes/odrive_emulated.json",
        "troupe-emulate-odrive --can vcan0 --nodes 0,1 --watchdog-ms 300"}});
  auto* can = app->add_option("--can", ifname, "SocketCAN interface (e.g. vcan0)")->type_name("IFACE");
  app->add_option("--descriptor", descriptor, "an open descriptor carrying struct can_frame bytes")
      ->type_name("FD")
      ->check(troupe::cli::at_least(0))
      ->excludes(can);
  std::vector<unsigned> node_ids = {0, 1};
  app->add_option("--nodes", node_ids, "node ids of the axes, 0..63 (default 0,1)")
      ->type_name("A,B,...")
      ->delimiter(',')
      ->check(troupe::cli::between(0, 63));
  app->add_option("--watchdog-ms", watchdog_ms, "axis watchdog timeout, ms (default 500; 0 disables)")
      ->type_name("N")
      ->check(troupe::cli::at_least(0));
  app->add_option("--ramp", ramp, "velocity ramp rate, turns/s^2 (default 20)")
      ->type_name("R")
      ->check(troupe::cli::above(0));
  app->add_option("--wrap-turns", wrap, "report positions within [0, T) (default 0: linear)")
      ->type_name("T")
      ->check(troupe::cli::at_least(0));
  app->add_option("--volts", volts, "supply voltage, V (default 24)")
      ->type_name("V")
      ->check(troupe::cli::above(0));
  app->add_option("--drop", drop, "drop each frame with probability P (default 0)")
      ->type_name("P")
      ->check(troupe::cli::between(0, 1));
  app->add_option("--seed", seed, "seed for the drop decisions (default 1)")
      ->type_name("N")
      ->check(troupe::cli::at_least(0));
  app->add_option("--status-ms", status_ms, "print the axes' state every N ms (default 1000; 0: never)")
      ->type_name("N")
      ->check(troupe::cli::at_least(0));
  if (int rc = troupe::cli::parse(*app, std::vector<std::string>(argv + 1, argv + ours)); rc >= 0) return rc;
  if (ours < argc && command == nullptr) return troupe::cli::usage_error(*app, "-- needs a command");
  if (int(!ifname.empty()) + int(descriptor >= 0) + int(command != nullptr) != 1) {
    return troupe::cli::usage_error(*app, "give exactly one of --can, --descriptor or -- COMMAND");
  }
  const std::vector<uint8_t> nodes(node_ids.begin(), node_ids.end());

  // Signals are read through a signalfd in the loop. Blocked before fork so
  // that a child exiting at once is not missed; the child unblocks them.
  sigset_t set;
  sigemptyset(&set);
  sigaddset(&set, SIGINT);
  sigaddset(&set, SIGTERM);
  sigaddset(&set, SIGCHLD);
  sigprocmask(SIG_BLOCK, &set, nullptr);

  std::string error;
  int fd = descriptor;
  pid_t child = -1;
  if (!ifname.empty()) {
    fd = troupe::cansimple::open_can_socket(ifname, {}, error);
    if (fd < 0) {
      fprintf(stderr, "troupe-emulate-odrive: %s\n", error.c_str());
      return 1;
    }
  } else if (command != nullptr) {
    int pair[2];
    if (socketpair(AF_UNIX, SOCK_SEQPACKET | SOCK_CLOEXEC, 0, pair) != 0) {
      perror("troupe-emulate-odrive: socketpair");
      return 1;
    }
    fd = pair[0];
    child = fork();
    if (child == 0) {
      sigprocmask(SIG_UNBLOCK, &set, nullptr);
      dup2(pair[1], 3);  // dup2 clears close-on-exec on the copy
      execvp(command[0], command);
      fprintf(stderr, "troupe-emulate-odrive: cannot run %s: %s\n", command[0], strerror(errno));
      _exit(127);
    }
    close(pair[1]);
    if (child < 0) {
      perror("troupe-emulate-odrive: fork");
      return 1;
    }
  }

  troupe::EventLoop loop;
  EmulatorOptions options;
  options.seed = seed;
  for (uint8_t n : nodes) {
    AxisConfig c;
    c.node_id = n;
    c.watchdog_timeout_ms = watchdog_ms;
    c.vel_ramp_rate = ramp;
    c.wrap_turns = wrap;
    c.supply_volts = volts;
    options.axes.push_back(c);
  }
  OdriveEmulator emu(loop, fd, options);
  emu.set_drop_probability(drop);
  if (!emu.start(error)) {
    fprintf(stderr, "troupe-emulate-odrive: %s\n", error.c_str());
    return 1;
  }

  Watch watch(loop, emu);
  watch.child = child;
  watch.signal_fd = signalfd(-1, &set, SFD_NONBLOCK | SFD_CLOEXEC);
  loop.watch(watch.signal_fd, 1 /*EPOLLIN*/, &watch);
  loop.watch(STDIN_FILENO, 1 /*EPOLLIN*/, &watch);  // fails quietly for a regular file: no commands then
  if (status_ms > 0) loop.start_timer(uint64_t(status_ms) * 1000u, uint64_t(status_ms) * 1000u, &watch);
  troupe::log_info("%zu axes on %s", nodes.size(),
                   !ifname.empty() ? ifname.c_str()
                   : command       ? command[0]
                                   : "the given descriptor");
  while (!loop.stopped()) loop.run_once(-1);
  emu.stop();
  if (!ifname.empty() || command != nullptr) close(fd);
  return watch.exit_code;
}
