#include "host-sim/robocup/serve/serve_loop.h"

#include <algorithm>
#include <cmath>

#include "runtime/clock.h"

namespace troupe::robocup {
namespace {

uint64_t sim_clock_us(void* ctx) {
  return uint64_t(std::llround(static_cast<Simulation*>(ctx)->time_s() * 1e6));
}

}  // namespace

ServeLoop::ServeLoop(Simulation& sim) : sim_(sim) {}

ServeLoop::~ServeLoop() {
  if (node_) node_->shutdown();
}

bool ServeLoop::start(const ServeOptions& options, std::string& error) {
  options_ = options;
  control_.paused = options.paused;
  control_.speed = options.speed;
  control_.step = [this](uint32_t n) { step(n); };
  Node::Options no;
  no.name = "troupe-robocup";
  no.listen = options.listen;
  no.port = options.port;
  no.max_clients = uint16_t(std::min(4096, 64 + 2 * sim_.robot_count()));
  node_ = std::make_unique<Node>(no);
  // Data and replies carry simulated time: a client's TimeSync learns the
  // offset between its clock and the simulation's.
  node_->set_clock(sim_clock_us, &sim_);
  auto server = std::make_unique<RobocupServer>(sim_, control_);
  server_ = server.get();
  if (!node_->add_driver(std::move(server), DriverSetup{}, error)) return false;
  if (!node_->start(error)) {
    error = "cannot serve on " + options.listen + ":" + std::to_string(options.port) + ": " + error;
    return false;
  }
  server_->publish();  // the state before the first cycle, for early readers
  return true;
}

uint16_t ServeLoop::port() const {
  return node_ ? node_->port() : 0;
}

void ServeLoop::step(uint32_t n) {
  for (uint32_t i = 0; i < n && !stop_; ++i) {
    sim_.step();
    server_->publish();
  }
}

void ServeLoop::measure_rate() {
  const uint64_t now = monotonic_us();
  if (rate_wall_us_ == 0 || now - rate_wall_us_ >= 1000000) {
    if (rate_wall_us_ != 0)
      control_.real_time_factor = (sim_.time_s() - rate_sim_s_) / ((now - rate_wall_us_) * 1e-6);
    rate_wall_us_ = now;
    rate_sim_s_ = sim_.time_s();
  }
}

void ServeLoop::run() {
  const int64_t kMaxWaitUs = 50000;  // answer the network at least this often
  // Real-time pacing: simulated time anchor_sim was reached at anchor_wall.
  uint64_t anchor_wall = 0;
  double anchor_sim = 0, anchor_speed = -1;
  bool anchored = false;
  while (!stop_) {
    if (options_.seconds > 0 && sim_.time_s() + 1e-9 >= options_.seconds) break;
    if (sim_.phase() == GamePhase::Stopped) break;
    if (control_.paused) {
      anchored = false;
      node_->poll(kMaxWaitUs);
      continue;
    }
    if (control_.speed > 0) {
      const uint64_t now = monotonic_us();
      if (!anchored || anchor_speed != control_.speed) {
        anchor_wall = now;
        anchor_sim = sim_.time_s();
        anchor_speed = control_.speed;
        anchored = true;
      }
      const double due = double(anchor_wall) + (sim_.time_s() - anchor_sim) / control_.speed * 1e6;
      if (double(now) < due) {
        node_->poll(std::min<int64_t>(kMaxWaitUs, int64_t(due - double(now)) + 1));
        continue;
      }
    } else {
      anchored = false;
    }
    node_->poll(0);
    if (stop_ || control_.paused) continue;
    step(1);
    measure_rate();
  }
}

}  // namespace troupe::robocup
