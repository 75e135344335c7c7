#include "host-sim/robocup/serve/serve_loop.h"

#include <algorithm>
#include <cmath>

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
  no.name = "troupe-sim";
  no.listen = options.listen;
  no.port = options.port;
  no.max_clients = uint16_t(std::min(4096, 64 + 2 * sim_.robot_count()));
  options.secure.apply(no);
  node_ = std::make_unique<Node>(no);
  // Data and replies carry simulated time: a client's TimeSync learns the
  // offset between its clock and the simulation's.
  node_->set_clock(sim_clock_us, &sim_);
  auto server = std::make_unique<RobocupServer>(sim_, control_);
  server_ = server.get();
  if (!node_->add_driver(std::move(server), DriverSetup{}, error)) return false;
  if (options.add_drivers && !options.add_drivers(*node_, control_, error)) return false;
  if (options.serve && !node_->start(error)) {
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
    if (options_.before_step) options_.before_step();
    sim_.step();
    server_->publish();
    if (options_.after_step) options_.after_step();
  }
}

void ServeLoop::run() {
  sim::LoopParts parts;
  parts.time_s = [this] { return sim_.time_s(); };
  parts.serve = [this](int64_t wait_us) { node_->poll(wait_us); };
  parts.step = [this] { step(1); };
  parts.done = [this] {
    return (options_.seconds > 0 && sim_.time_s() + 1e-9 >= options_.seconds) || sim_.phase() == GamePhase::Stopped;
  };
  sim::run_paced(control_, stop_, parts, rate_);
}

}  // namespace troupe::robocup
