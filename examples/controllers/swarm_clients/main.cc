// swarm-clients: the swarm controller over the wire. One client connection
// per robot (as if each robot's brain were a separate program), all in one
// poll loop through the C++ client library. Robots are every robot of the
// simulator that has position2d:0 and ranger:0 (and fiducial:0 to see its
// neighbours). At the end it stops the robots and prints how far each is from
// its nearest neighbour on average, from the simulator's ground truth.
//
// With --steps N it drives in lockstep instead of for a wall-clock time: the
// simulator paused and stepped N times through simulation:0, each step once
// every robot has decided on the last one's scan. The run is then the same
// however fast the machine (tests use it).
//
//   troupe-sim examples/worlds/swarm100.world --no-ctrl &
//   swarm-clients localhost --seconds 60
//   swarm-clients localhost --steps 300
#include <poll.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <functional>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include "examples/controllers/swarm/swarm_logic.h"
#include "wire/address.h"
#include "wire/cli/args.h"
#include "wire/client/proxies.h"

namespace {

using troupe::client::Client;
using troupe::examples::SwarmParams;

struct Robot {
  std::string name;
  uint16_t number = 0;
  std::unique_ptr<Client> client;
  std::unique_ptr<troupe::client::Position2dProxy> base;
  std::unique_ptr<troupe::client::RangerProxy> ranger;
  std::unique_ptr<troupe::client::FiducialProxy> fiducial;
  troupe::examples::SwarmInputs in;
  troupe::examples::SwarmState state;
  // When its ranger last delivered a scan: a robot that stopped answering
  // (its connection or its simulator's process lost) shows at the end.
  std::chrono::steady_clock::time_point heard;
  // Lockstep: the ranger's and fiducial finder's sample counts when the
  // robot last decided.
  uint64_t ranger_seen = 0, fiducial_seen = 0;
};

// Waits up to `ms` for traffic on every robot's connection and takes it.
void pump(std::vector<Robot>& robots, int ms) {
  std::vector<pollfd> fds;
  std::vector<int> counts;
  for (Robot& r : robots) {
    pollfd f[2];
    const int n = r.client->poll_fds(f, 2);
    counts.push_back(n);
    fds.insert(fds.end(), f, f + n);
  }
  poll(fds.data(), nfds_t(fds.size()), ms);
  size_t at = 0;
  for (size_t i = 0; i < robots.size(); ++i) {
    robots[i].client->process(fds.data() + at, counts[i]);
    at += size_t(counts[i]);
  }
}

// The swarm behaviour on the robot's latest scan and neighbours: its next
// velocity command.
void decide(const SwarmParams& params, Robot& r, const std::function<double(int)>& random) {
  r.heard = std::chrono::steady_clock::now();
  r.in.ranges = r.ranger->ranges();
  r.in.neighbours.clear();
  if (r.fiducial) {
    for (const auto& f : r.fiducial->fiducials()) r.in.neighbours.push_back({f.x(), f.y()});
  }
  const auto c = troupe::examples::swarm_decide(params, r.in, r.state, random);
  r.base->set_velocity(float(c.v), 0, float(c.w));
}

// Lockstep: the simulator paused and stepped `steps` times, each step once
// every robot decided on the previous one's scan and its command reached
// the simulator. False with a message when a robot's scan or a step does
// not come (the bound only ends a hang).
bool drive_in_lockstep(const SwarmParams& params, std::vector<Robot>& robots,
                       troupe::client::SimulationProxy& sim, uint32_t steps,
                       const std::function<double(int)>& random) {
  constexpr auto kHang = std::chrono::seconds(120);
  if (!sim.pause()) {
    std::fprintf(stderr, "swarm-clients: cannot pause the simulator\n");
    return false;
  }
  for (uint32_t step = 0; step <= steps; ++step) {
    // Each robot's scan (and neighbours) of this step: at step 0, the
    // samples it got when it opened its devices.
    const auto give_up = std::chrono::steady_clock::now() + kHang;
    for (Robot& r : robots) {
      auto has_scan = [&r] {
        return r.ranger->samples() > r.ranger_seen &&
               (!r.fiducial || r.fiducial->samples() > r.fiducial_seen);
      };
      while (!has_scan() && std::chrono::steady_clock::now() < give_up) pump(robots, 50);
      if (!has_scan()) {
        std::fprintf(stderr, "swarm-clients: %s: no scan of step %u\n", r.name.c_str(), step);
        return false;
      }
      r.ranger_seen = r.ranger->samples();
      r.fiducial_seen = r.fiducial ? r.fiducial->samples() : 0;
    }
    if (step == steps) return true;
    for (Robot& r : robots) decide(params, r, random);
    // A round trip on each connection: its command was handled before the
    // step is asked for on another.
    for (Robot& r : robots) {
      if (!r.client->sync()) {
        std::fprintf(stderr, "swarm-clients: %s: %s\n", r.name.c_str(), r.client->error().c_str());
        return false;
      }
    }
    if (!sim.step(1)) {
      std::fprintf(stderr, "swarm-clients: step %u: %s\n", step + 1, sim.client().error().c_str());
      return false;
    }
  }
  return true;
}

double mean_distance(troupe::client::SimulationProxy& sim, const std::vector<Robot>& robots) {
  std::vector<troupe::client::Pose2> p(robots.size());
  for (size_t i = 0; i < robots.size(); ++i) {
    if (!sim.get_pose(robots[i].name, p[i])) return -1;
  }
  // Each robot's distance to its nearest neighbour, averaged: it shrinks as
  // clusters form and grows as robots spread out.
  double sum = 0;
  for (size_t i = 0; i < p.size(); ++i) {
    double nearest = 1e9;
    for (size_t j = 0; j < p.size(); ++j) {
      if (j != i) nearest = std::min(nearest, double(std::hypot(p[i].x - p[j].x, p[i].y - p[j].y)));
    }
    sum += nearest;
  }
  return p.size() > 1 ? sum / double(p.size()) : 0;
}

}  // namespace

int main(int argc, char** argv) {
  std::string host = "localhost";
  double seconds = 30;
  SwarmParams params;
  params.spacing = 0.6;
  unsigned seed = 1;
  uint32_t steps = 0;
  auto app = troupe::cli::make_app(
      "swarm-clients",
      {"swarm-clients [HOST[:PORT]] [--seconds S | --steps N] [--disperse] [--spacing M] [--seed N]",
       "Drives every robot of a troupe-sim world with the swarm behaviour, one client\n"
       "connection each, then prints how far each robot is from its nearest neighbour.\n",
       {"swarm-clients localhost --seconds 60", "swarm-clients localhost:7000 --disperse --spacing 1.5"}});
  app->add_option("HOST", host, "HOST[:PORT] (default localhost)");
  app->add_option("--seconds", seconds, "how long to drive, s (default 30)")
      ->type_name("S")
      ->check(troupe::cli::above(0));
  app->add_option("--spacing", params.spacing, "the distance robots keep, m (default 0.6)")
      ->type_name("M")
      ->check(troupe::cli::above(0));
  app->add_option("--steps", steps,
                  "step the paused simulator N times, each once every robot decided (lockstep; "
                  "instead of --seconds)")
      ->type_name("N")
      ->check(troupe::cli::above(0));
  app->add_option("--seed", seed, "seeds each robot's random turns (default 1)")->type_name("N");
  bool disperse = false;
  app->add_flag("--disperse", disperse, "spread out instead of gathering");
  if (int rc = troupe::cli::parse(*app, argc, argv); rc >= 0) return rc;
  params.aggregate = !disperse;
  troupe::wire::HostPort hp;
  std::string error;
  if (!troupe::wire::parse_host(host, hp, error)) return troupe::cli::usage_error(*app, error);
  Client admin(hp.host, hp.port);
  if (!admin.connect()) {
    std::fprintf(stderr, "swarm-clients: cannot connect to %s: %s\n", host.c_str(), admin.error().c_str());
    return 1;
  }
  std::vector<troupe::client::DeviceEntry> devices;
  if (!admin.device_list(devices)) return 1;
  std::vector<Robot> robots;
  for (const auto& d : devices) {
    if (d.addr.iface() != uint16_t(troupe::wire::Interface::Position2d) || d.addr.index() != 0) continue;
    bool ranger = false, fiducial = false;
    for (const auto& e : devices) {
      if (e.addr.robot() != d.addr.robot() || e.addr.index() != 0) continue;
      ranger = ranger || e.addr.iface() == uint16_t(troupe::wire::Interface::Ranger);
      fiducial = fiducial || e.addr.iface() == uint16_t(troupe::wire::Interface::Fiducial);
    }
    if (!ranger || (params.aggregate && !fiducial)) continue;
    Robot r;
    r.name = d.robot_name;
    r.number = d.addr.robot();
    r.in.has_fiducial = fiducial;
    robots.push_back(std::move(r));
  }
  if (robots.empty()) {
    std::fprintf(stderr, "swarm-clients: no robot with position2d:0, ranger:0 and fiducial:0 at %s\n",
                 host.c_str());
    return 1;
  }
  // One connection per robot, each opening its robot's devices.
  for (Robot& r : robots) {
    Client::Options o;
    o.name = "swarm-" + r.name;
    r.client = std::make_unique<Client>(hp.host, hp.port, o);
    if (!r.client->connect()) {
      std::fprintf(stderr, "swarm-clients: %s: %s\n", r.name.c_str(), r.client->error().c_str());
      return 1;
    }
    r.base = std::make_unique<troupe::client::Position2dProxy>(*r.client, 0, r.number);
    r.ranger = std::make_unique<troupe::client::RangerProxy>(*r.client, 0, r.number);
    if (r.in.has_fiducial)
      r.fiducial = std::make_unique<troupe::client::FiducialProxy>(*r.client, 0, r.number);
    troupe::wire::Pose3d pose;
    std::vector<troupe::wire::Pose3d> elements;
    if (!r.ranger->geometry(pose, elements)) return 1;
    for (const auto& e : elements) r.in.bearings.push_back(e.yaw());
  }
  troupe::client::SimulationProxy sim(admin);
  const double before = mean_distance(sim, robots);
  std::printf("%zu robots, %zu connections; mean distance at the start %.2f m\n", robots.size(),
              robots.size() + 1, before);
  std::fflush(stdout);

  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> uniform(0, 1);
  auto random = [&](int) { return uniform(rng); };
  size_t answering = 0, decisions = 0;
  if (steps > 0) {
    if (!drive_in_lockstep(params, robots, sim, steps, random)) return 1;
    answering = robots.size();  // every robot, at every step, or it failed
    decisions = robots.size() * steps;
  } else {
    const auto end = std::chrono::steady_clock::now() + std::chrono::duration<double>(seconds);
    while (std::chrono::steady_clock::now() < end) {
      pump(robots, 50);
      // A decision whenever a robot's ranger has a new sample.
      for (Robot& r : robots) {
        if (!r.ranger->fresh()) continue;
        decide(params, r, random);
        ++decisions;
      }
    }
    for (const Robot& r : robots) answering += end - r.heard <= std::chrono::seconds(1) ? 1 : 0;
  }
  for (Robot& r : robots) r.base->set_velocity(0, 0, 0);
  for (Robot& r : robots) r.client->sync();
  const double after = mean_distance(sim, robots);
  std::printf("%zu decisions; mean distance at the end %.2f m (%s)\n", decisions, after,
              params.aggregate ? "aggregate" : "disperse");
  if (steps > 0) {
    std::printf("%zu of %zu robots decided at each of %u steps\n", answering, robots.size(), unsigned(steps));
  } else {
    std::printf("%zu of %zu robots answered in the last second\n", answering, robots.size());
  }
  return before < 0 || after < 0 ? 1 : 0;
}
