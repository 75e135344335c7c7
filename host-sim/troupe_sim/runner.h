// troupe-sim's main loop: a world, its controllers and the servers that put
// its robots on the wire, stepped in real time or as fast as possible,
// between polls of the network.
#pragma once

#include <atomic>
#include <deque>
#include <memory>
#include <string>
#include <vector>

#include "host-sim/sim/controller_host.h"
#include "host-sim/sim/division.h"
#include "host-sim/sim/trajectory_log.h"
#include "host-sim/sim/world.h"
#include "host-sim/sim_control/pacing.h"
#include "host-sim/troupe_sim/emulation.h"
#include "host-sim/troupe_sim/emulation_tcp.h"
#include "host-sim/troupe_sim/options.h"
#include "host-sim/troupe_sim/sim_server.h"
#include "runtime/node.h"

namespace troupe::sim {

class Runner {
 public:
  Runner() = default;
  ~Runner();
  Runner(const Runner&) = delete;
  Runner& operator=(const Runner&) = delete;

  /// Loads the world and its controllers and opens the servers. Problems
  /// with the world file go to `diags` (file:line); others to `error`.
  /// With `division` (troupe-sim under mpirun): this process steps its
  /// share of the world, exchanging with the others every step; it must
  /// outlive the runner.
  bool init(const SimOptions& options, world::Diagnostics& diags, std::string& error,
            Division* division = nullptr);
  /// The same for options.world's description, already loaded (by the one
  /// loader, host-sim/robocup/game/world_load.h).
  bool init(const SimOptions& options, const WorldDesc& desc, world::Diagnostics& diags, std::string& error,
            Division* division = nullptr);
  /// Runs until the quit time, request_stop(), or a fatal problem. Returns
  /// the process exit code: 0 when the run reached its quit time (however
  /// it got there, a client's Step included) or was asked to stop, 1 when
  /// the snapshot or the trajectory log could not be written.
  int run();
  /// Safe from any thread or a signal watcher.
  /// Safe from a signal handler. In a divided run the leader's stop ends
  /// the others' runs.
  void request_stop() { stop_ = true; }
  /// request_stop() for SIGINT or SIGTERM: under mpirun that signal means
  /// mpirun is ending the job (stopped_by_signal()).
  void request_stop_by_signal() {
    signalled_ = true;
    stop_ = true;
  }
  /// After run() of a divided run: true on every process when the leader
  /// stopped for a signal. mpirun, which passed it on, is then taking the
  /// job down and no longer answers: MPI_Finalize would wait for it until
  /// it kills the process, so the caller leaves without it.
  bool stopped_by_signal() const { return job_signalled_; }
  /// A divided run's leader giving up before run(): the others stop too.
  void release_followers();

  /// The bound TCP port of the main server (0 without one).
  uint16_t port() const;
  /// With --port-per-robot: the port serving robot `id` alone (0 otherwise).
  uint16_t robot_port(RobotId id) const;
  World& world() { return *world_; }
  Node& node() { return *nodes_.front(); }
  /// The robots presented as hardware (--emulate).
  const Emulation& emulation() const { return emulation_; }
  /// The robots served as Pioneers on TCP (--p2os-tcp).
  const P2osTcp& p2os_tcp() const { return p2os_tcp_; }

 private:
  void step(uint32_t n);
  /// Runs queued Step requests for one slice of wall time, acking each
  /// once its steps ran.
  void run_step_slice();
  /// Answers every queued Step request with a Nack saying `why`.
  void refuse_queued_steps(const std::string& why);
  bool quit_time_reached() const;
  void serve(int64_t wait_us);
  void progress(bool final);
  void reset();
  /// One step of the world (every process of a divided run takes part).
  void step_once();
  /// Sensors computed where the robots stand, without a step.
  void refresh();
  void reset_world();
  /// A divided run's other processes: the leader's orders until it stops.
  int follow();
  bool start_emulation(std::string& error);
  void step_emulation();

  SimOptions options_;
  std::unique_ptr<World> world_;
  ControllerHost controllers_;
  SimControl control_;
  std::vector<std::unique_ptr<Node>> nodes_;
  std::vector<SimServer*> servers_;  // owned by their nodes
  Emulation emulation_;
  P2osTcp p2os_tcp_;
  // The emulated devices' clock, us: it runs at the simulation's speed in
  // real-time mode (a SIP every 100 ms of simulated time) and at wall speed
  // while paused or running fast, so the devices keep answering their
  // drivers, whose timeouts are in wall time.
  double emulation_clock_us_ = 0;
  uint64_t emulation_wall_us_ = 0;
  TrajectoryLog log_;
  Division* division_ = nullptr;
  bool mirror_ = false;         // the leader's world gets every robot's state
  std::vector<Pose> gathered_;  // every robot's pose, first process, divided runs
  double quit_time_ = 0;
  // simulation:0 Step requests, oldest first, run in slices between polls.
  struct QueuedSteps {
    RequestToken token;
    uint32_t asked = 0;
    uint32_t left = 0;
  };
  std::deque<QueuedSteps> queued_steps_;
  double next_snapshot_ = 0;
  std::atomic<bool> stop_{false};
  std::atomic<bool> signalled_{false};  // request_stop_by_signal()
  bool job_signalled_ = false;          // stopped_by_signal()
  RateMeter rate_;
  uint64_t progress_wall_us_ = 0;
  bool progress_shown_ = false;
};

}  // namespace troupe::sim
