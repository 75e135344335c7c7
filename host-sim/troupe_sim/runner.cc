#include "host-sim/troupe_sim/runner.h"

#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>

#include "host-sim/sim/loader.h"
#include "host-sim/sim/profile.h"
#include "host-sim/sim/snapshot.h"
#include "runtime/clock.h"
#include "runtime/log.h"

namespace troupe::sim {
namespace {

// A Step request's steps run in slices of about this much wall time, with
// every client served between two slices.
constexpr uint64_t kStepSliceUs = 10000;
// troupe-sim answers every request at once except Step, which is answered
// once its steps ran: its deadline is the Step's, as long as the clients'
// own wait for a Step (the C++ and Python clients wait 60 s).
constexpr uint32_t kRequestTimeoutMs = 60000;

uint64_t sim_clock_us(void* ctx) {
  return uint64_t(std::llround(static_cast<World*>(ctx)->time() * 1e6));
}

// Stage honours a world's `paused 1` in its GUI only, where a person can
// resume; headless it runs. Here too: paused only when served.
bool starts_paused(const SimOptions& options, const WorldDesc& d) {
  if (!d.paused) return false;
  if (!options.serve) {
    log_info("%s: the world says paused; a headless run (--no-serve) ignores it and runs",
             d.paused_at.c_str());
    return false;
  }
  const std::string port = options.port == 0 ? "PORT" : std::to_string(options.port);
  log_info(
      "%s: the world starts paused; resume it with `troupe req %s:%s simulation:0 resume` or from the viewer",
      d.paused_at.c_str(), options.listen.c_str(), port.c_str());
  return true;
}

}  // namespace

Runner::~Runner() {
  for (auto& n : nodes_) n->shutdown();
}

bool Runner::init(const SimOptions& options, world::Diagnostics& diags, std::string& error,
                  Division* division) {
  WorldDesc desc;
  if (!load_world_file(options.world, desc, diags)) return false;
  return init(options, desc, diags, error, division);
}

bool Runner::init(const SimOptions& options, const WorldDesc& desc, world::Diagnostics& diags,
                  std::string& error, Division* division) {
  options_ = options;
  if (division) {
    // Devices presented as hardware live beside their robot's process.
    const char* refused = !options.emulate.empty()     ? "--emulate"
                          : options.p2os_tcp_port >= 0 ? "--p2os-tcp"
                          : options.port_per_robot     ? "--port-per-robot"
                                                       : nullptr;
    if (refused) {
      error = std::string("under mpirun troupe-sim does not do ") + refused + " yet";
      return false;
    }
  }
  world_ = std::make_unique<World>(desc, Random(options.seed));

  ControllerHost::Options copts;
  copts.search_path =
      plugin::search_path(options.plugin_path, std::filesystem::path(options.world).parent_path().string());
  copts.ignore_missing = options.ignore_missing_ctrl;
  if (!options.no_ctrl && !controllers_.load(*world_, copts, diags)) return false;

  // Before the servers: the sensors the emulators read stay computed
  // whether or not a client reads them over the wire.
  if (!start_emulation(error)) return false;

  const WorldDesc& d = world_->desc();
  control_.paused = options.paused || starts_paused(options, d);
  control_.speed = options.fast ? 0 : (options.speed >= 0 ? options.speed : std::max(0.0, d.speedup));
  control_.start_steps = [this](uint32_t n, RequestToken token) { queued_steps_.push_back({token, n, n}); };
  control_.reset = [this] { reset(); };
  quit_time_ = options.quit_time >= 0 ? options.quit_time : d.quit_time;
  next_snapshot_ = options.snapshot_every;

  // One node serves everything; with --port-per-robot, one more per robot.
  const int extra = options.port_per_robot ? int(world_->robot_count()) : 0;
  // In a divided run the leader alone serves, the whole world.
  const bool serves = options.serve && (!division || division->first());
  bool serve_failed = false;
  for (int i = -1; i < extra; ++i) {
    Node::Options no;
    no.name = i < 0 ? "troupe-sim" : "troupe-sim/" + world_->robot(RobotId(i)).name;
    no.listen = options.listen;
    no.port = options.port == 0 ? 0 : uint16_t(options.port + (i + 1));
    no.max_clients = uint16_t(std::min<size_t>(4096, 64 + 2 * world_->robot_count()));
    no.request_timeout_ms = kRequestTimeoutMs;
    options.secure.apply(no);
    auto node = std::make_unique<Node>(no);
    node->set_clock(sim_clock_us, world_.get());
    // A run that serves nothing (--no-serve) registers no devices: none
    // could be read, and its robots need no wire address, so worlds beyond
    // the 16-bit robot numbers run too. Its node only keeps the loop.
    SimServer* raw = nullptr;
    if (options.serve) {
      auto server = std::make_unique<SimServer>(*world_, control_, i);
      raw = server.get();
      if (!node->add_driver(std::move(server), DriverSetup{}, error)) return false;
    }
    if (serves && !node->start(error)) {
      error = "cannot serve on " + options.listen + ":" + std::to_string(no.port) + ": " + error;
      // The other processes of a divided run learn it below.
      if (!division) return false;
      serve_failed = true;
      break;
    }
    if (raw) servers_.push_back(raw);
    nodes_.push_back(std::move(node));
    if (!serves) break;
  }
  // A divided run's log is written by its first process alone.
  const bool writes_log = !division || division->first();
  const bool ready = !serve_failed && (options.log.empty() || !writes_log || log_.open(options.log, error));
  // One process failing stops them all, rather than leaving them waiting.
  if (division && division->any(!ready)) {
    if (ready) error = "another process of the run failed (its error is above)";
    return false;
  }
  if (!ready) return false;
  for (SimServer* s : servers_) s->sync_wanted();
  if (division && !division->start(*world_, error)) return false;
  division_ = division;
  // The leader serves and draws every robot: the others' states come to it.
  mirror_ = division && (options.serve || !options.snapshot.empty());
  world_->refresh_sensors();
  if (mirror_) division_->mirror(*world_);
  return true;
}

bool Runner::start_emulation(std::string& error) {
  for (const std::string& spec : options_.emulate) {
    if (!emulation_.add(*world_, spec, error)) return false;
  }
  if (options_.p2os_tcp_port >= 0) {
    if (!emulation_.empty()) {
      error = "--p2os-tcp serves every robot's base already; it does not mix with --emulate";
      return false;
    }
    if (!p2os_tcp_.open(*world_, options_.listen, options_.p2os_tcp_port, error)) return false;
    emulation_wall_us_ = monotonic_us();
    return true;
  }
  if (emulation_.empty()) return true;
  if (!emulation_.open(options_.emulate_links, error)) return false;
  if (!options_.emulate_info.empty()) {
    // Written aside and renamed, so a script that waits for the file reads
    // it whole.
    const std::string tmp = options_.emulate_info + ".tmp";
    FILE* f = std::fopen(tmp.c_str(), "w");
    const std::string text = emulation_.info();
    const bool written = f && std::fwrite(text.data(), 1, text.size(), f) == text.size();
    if (f && std::fclose(f) != 0) f = nullptr;
    if (!written || !f || std::rename(tmp.c_str(), options_.emulate_info.c_str()) != 0) {
      error = "--emulate-info: cannot write " + options_.emulate_info;
      std::remove(tmp.c_str());
      return false;
    }
  }
  emulation_wall_us_ = monotonic_us();
  return true;
}

void Runner::step_emulation() {
  if (emulation_.empty() && p2os_tcp_.empty()) return;
  const uint64_t now = monotonic_us();
  const bool real_time = !control_.paused && control_.speed > 0;
  emulation_clock_us_ += double(now - emulation_wall_us_) * (real_time ? control_.speed : 1.0);
  emulation_wall_us_ = now;
  emulation_.step(uint64_t(emulation_clock_us_));
  p2os_tcp_.step(uint64_t(emulation_clock_us_));
}

uint16_t Runner::port() const {
  return options_.serve && !nodes_.empty() ? nodes_.front()->port() : 0;
}

uint16_t Runner::robot_port(RobotId id) const {
  return options_.serve && options_.port_per_robot && id + 1 < nodes_.size() ? nodes_[id + 1]->port() : 0;
}

void Runner::serve(int64_t wait_us) {
  // Emulated devices are stepped between polls: often enough that a driver's
  // request is answered within a few milliseconds, as hardware would.
  const int64_t kEmulationWaitUs = 4000;
  if (!emulation_.empty() || !p2os_tcp_.empty()) wait_us = std::min(wait_us, kEmulationWaitUs);
  for (size_t i = 1; i < nodes_.size(); ++i) nodes_[i]->poll(0);
  nodes_.front()->poll(wait_us);
  step_emulation();
  // A sensor someone started reading is computed at once while paused, so
  // the reader does not wait for the next step.
  bool woke = false;
  for (SimServer* s : servers_) woke = s->sync_wanted() || woke;
  // A divided run's inputs (a teleport, a sensor wanted) reach the robots'
  // processes with the next step; while paused, at once.
  if (division_) woke = division_->pending();
  if (woke && control_.paused) {
    if (division_) division_->sync(*world_, Division::Order::Refresh);
    // Robots moved while paused (a teleport, a reset): every reader gets
    // the new readings. Otherwise only the new readers' sensors are new:
    // a thousand clients connecting to a paused world cost a thousand
    // sensors and samples, not a thousand times the world's.
    const bool moved = world_->changed_since_step();
    refresh();
    for (SimServer* s : servers_) {
      if (moved) {
        s->publish();
      } else {
        s->publish_woken();
      }
    }
  }
}

bool Runner::quit_time_reached() const {
  return quit_time_ > 0 && world_->time() + 1e-9 >= quit_time_;
}

void Runner::run_step_slice() {
  const uint64_t until = monotonic_us() + kStepSliceUs;
  while (!queued_steps_.empty() && !stop_) {
    QueuedSteps& q = queued_steps_.front();
    if (node().request_device(q.token) == kNoDevice) {
      // The node answered it Timeout: its client has given up waiting.
      log_warn("simulation:0: a Step of %u steps stopped after %u: its deadline (%u s) passed", q.asked,
               q.asked - q.left, kRequestTimeoutMs / 1000);
      queued_steps_.pop_front();
      continue;
    }
    if (q.left == 0) {
      ack_clock(node(), control_, q.token, {world_->time(), world_->steps()});
      queued_steps_.pop_front();
      continue;
    }
    if (quit_time_reached() || monotonic_us() >= until) return;
    step(1);
    --q.left;
  }
}

void Runner::refuse_queued_steps(const std::string& why) {
  for (const QueuedSteps& q : queued_steps_) {
    node().nack(q.token, wire::ErrorCode::BadArgument,
                "stopped after " + std::to_string(q.asked - q.left) + " of " + std::to_string(q.asked) +
                    " steps: " + why);
  }
  queued_steps_.clear();
}

void Runner::step(uint32_t n) {
  for (uint32_t i = 0; i < n && !stop_; ++i) {
    for (SimServer* s : servers_) s->sync_wanted();
    if (division_) division_->sync(*world_, Division::Order::Step);
    step_once();
    for (SimServer* s : servers_) s->publish();
    for (const std::string& e : controllers_.take_errors()) log_warn("%s", e.c_str());
    if (!options_.snapshot.empty() && next_snapshot_ > 0 && world_->time() + 1e-9 >= next_snapshot_) {
      std::string err;
      if (!write_snapshot(*world_, options_.snapshot, err)) log_warn("%s", err.c_str());
      next_snapshot_ += options_.snapshot_every;
    }
  }
}

void Runner::step_once() {
  controllers_.update(*world_);
  if (!division_) {
    world_->step();
    log_.record(*world_);
    return;
  }
  world_->step(*division_);
  division_->after_step(*world_);
  if (mirror_) {
    // The leader's world holds every robot's state now: the log reads it
    // there rather than gathering the poses a second time.
    division_->mirror(*world_);
    log_.record(*world_);
  } else if (!options_.log.empty() && division_->gather_poses(*world_, gathered_)) {
    log_.record(*world_, gathered_);
  }
}

void Runner::refresh() {
  if (division_) division_->ghosts(*world_);
  world_->refresh_new_sensors();
  if (mirror_) division_->mirror(*world_);
}

void Runner::reset() {
  if (division_) division_->sync(*world_, Division::Order::Reset);
  reset_world();
  for (SimServer* s : servers_) s->publish();
  next_snapshot_ = options_.snapshot_every;
}

void Runner::reset_world() {
  world_->reset();
  if (division_) division_->restart(*world_);
  world_->refresh_sensors();
  if (mirror_) division_->mirror(*world_);
}

void Runner::release_followers() {
  if (!division_ || !division_->first()) return;
  // What follow() does after a Stop, the collective steps matched.
  division_->sync(*world_, Division::Order::Stop);
  if (options_.profile) division_->report(*world_);
  division_->any(false);
}

int Runner::follow() {
  for (;;) {
    switch (division_->sync(*world_, Division::Order::Stop)) {
      case Division::Order::Step:
        step_once();
        break;
      case Division::Order::Refresh:
        refresh();
        break;
      case Division::Order::Reset:
        reset_world();
        break;
      case Division::Order::Stop:
        if (options_.profile) division_->report(*world_);
        job_signalled_ = division_->any(false);  // the leader says whether it was
        return 0;
    }
  }
}

void Runner::progress(bool final) {
  const uint64_t now = monotonic_us();
  if (final) rate_.update(control_, world_->time(), now, true);
  // A progress line for fast runs on a terminal.
  if (control_.speed != 0 || !isatty(STDERR_FILENO)) return;
  if (!final && now - progress_wall_us_ < 250000) return;
  progress_wall_us_ = now;
  char eta[48] = "";
  if (quit_time_ > 0 && control_.real_time_factor > 0) {
    std::snprintf(eta, sizeof eta, "  ETA %.0f s", (quit_time_ - world_->time()) / control_.real_time_factor);
  }
  std::fprintf(stderr, "\rsim time %.1f s  %.0fx real time%s   ", world_->time(), control_.real_time_factor,
               eta);
  if (final) std::fprintf(stderr, "\n");
  progress_shown_ = true;
}

int Runner::run() {
  if (division_ && !division_->first()) return follow();
  LoopParts parts;
  parts.time_s = [this] { return world_->time(); };
  parts.serve = [this](int64_t wait_us) { serve(wait_us); };
  parts.step = [this] { step(1); };
  parts.done = [this] { return quit_time_reached(); };
  parts.slice = [this] {
    if (queued_steps_.empty()) return false;
    run_step_slice();
    return true;
  };
  // The run's own time, without loading the world, for --profile's last line.
  const double start_sim_s = world_->time();
  const uint64_t start_steps = world_->steps(), start_ns = now_ns(), start_cpu_ns = process_cpu_ns();
  run_paced(control_, stop_, parts, rate_, [this] { progress(false); });
  // The others stop and report (every process takes part in the table).
  std::string divided;
  if (division_) division_->sync(*world_, Division::Order::Stop);
  const double run_wall_s = double(now_ns() - start_ns) * 1e-9,
               run_cpu_s = double(process_cpu_ns() - start_cpu_ns) * 1e-9;
  if (division_ && options_.profile) divided = division_->report(*world_);
  if (division_) job_signalled_ = division_->any(signalled_);
  progress(true);
  if (quit_time_reached()) {
    char why[96];
    std::snprintf(why, sizeof why, "the world's quit time (%g s) was reached: troupe-sim ends", quit_time_);
    refuse_queued_steps(why);
    log_info("quit time %g s reached after %llu steps: the run ends", quit_time_,
             static_cast<unsigned long long>(world_->steps()));
  } else {
    refuse_queued_steps("troupe-sim is stopping");
  }
  if (!options_.snapshot.empty()) {
    std::string err;
    if (!write_snapshot(*world_, options_.snapshot, err)) {
      log_error("%s", err.c_str());
      return 1;
    }
    log_info("snapshot: %s", options_.snapshot.c_str());
  }
  if (!log_.close()) {
    log_error("the trajectory log %s could not be written completely", options_.log.c_str());
    return 1;
  }
  if (options_.profile) {
    std::fprintf(stderr, "%s%s", world_->profile().table().c_str(), divided.c_str());
    // One line for scripts (tests/bench/sim/mpi_scaling reads it). CPU is
    // this process's; a divided run's other processes are in the table.
    std::fprintf(stderr, "run: %llu steps, %.3f simulated s, %.3f wall s, %.3f CPU s\n",
                 static_cast<unsigned long long>(world_->steps() - start_steps), world_->time() - start_sim_s,
                 run_wall_s, run_cpu_s);
  }
  return 0;
}

}  // namespace troupe::sim
