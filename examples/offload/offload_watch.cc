// offload-watch: the client side of the offload example. Reads the desktop's
// mcl estimate (position2d:1) and belief (localize:0), asks troupe-sim for
// the robot's true pose, and prints the error about once a second.
//
//   offload-watch [DESKTOP[:PORT]] [SIM[:PORT]] [--robot NAME] [--seconds S]
//   (defaults: localhost:6665, localhost:7000, r0, until interrupted)
//
// Both clients reconnect by themselves: kill troupe-sim and start it again,
// and the lines resume once the desktop has the robot back.
#include <cmath>
#include <cstdio>
#include <string>

#include "wire/address.h"
#include "wire/cli/args.h"
#include "wire/client/proxies.h"
#include "wire/geometry.h"

using namespace troupe;

namespace {

using geometry::kPi;
using geometry::wrap_angle;

// HOST[:PORT], with a port of its own when none is given.
bool parse_host(const std::string& text, uint16_t default_port, wire::HostPort& out, std::string& error) {
  if (!wire::parse_host(text, out, error)) return false;
  if (text.find(':') == std::string::npos) out.port = default_port;
  return true;
}

}  // namespace

int main(int argc, char** argv) {
  std::string desktop_text = "localhost:6665", sim_text = "localhost:7000";
  std::string robot = "r0";
  double seconds = 0;  // 0: forever
  auto app = cli::make_app(
      "offload-watch",
      {"offload-watch [DESKTOP[:PORT]] [SIM[:PORT]] [--robot NAME] [--seconds S]",
       "Prints, about once a second, the desktop's mcl estimate (position2d:1 of\n"
       "DESKTOP, default localhost:6665) against the robot's true pose in troupe-sim\n"
       "(SIM, default localhost:7000), and the error.\n",
       {"offload-watch localhost localhost:7000", "offload-watch localhost localhost:7000 --robot r0 --seconds 30"}});
  app->add_option("DESKTOP", desktop_text, "the desktop node, HOST[:PORT] (port 6665 unless given)");
  app->add_option("SIM", sim_text, "troupe-sim, HOST[:PORT] (port 7000 unless given)");
  app->add_option("--robot", robot, "the simulated robot's name (default r0)")->type_name("NAME");
  app->add_option("--seconds", seconds, "stop after S seconds (default: when interrupted)")
      ->type_name("S")
      ->check(cli::above(0));
  if (int rc = cli::parse(*app, argc, argv); rc >= 0) return rc;
  wire::HostPort desktop, sim;
  std::string error;
  if (!parse_host(desktop_text, 6665, desktop, error) || !parse_host(sim_text, 7000, sim, error)) {
    return cli::usage_error(*app, error);
  }
  client::Client desk(desktop.host, desktop.port), world(sim.host, sim.port);
  if (!desk.connect(5000)) {
    std::fprintf(stderr, "offload-watch: desktop: %s\n", desk.error().c_str());
    return 1;
  }
  if (!world.connect(5000)) {
    std::fprintf(stderr, "offload-watch: simulator: %s\n", world.error().c_str());
    return 1;
  }
  client::Position2dProxy estimate(desk, 1);
  client::LocalizeProxy localize(desk, 0);
  client::SimulationProxy simulation(world, 0);
  std::printf("%10s %28s %28s %9s %8s %5s\n", "robot_t_s", "estimate x,y,a", "truth x,y,a", "error_m",
              "err_deg", "hyps");
  uint64_t last_print_us = 0, start_us = 0;
  for (;;) {
    desk.spin_once(50);
    world.spin_once(0);
    if (!estimate.fresh()) continue;
    uint64_t t = estimate.time_us();
    if (start_us == 0 || t < start_us) start_us = t;  // a restarted simulator starts its clock again
    if (t < last_print_us + 1'000'000 && t >= last_print_us) continue;
    last_print_us = t;
    client::Pose2 truth;
    if (!simulation.get_pose(robot, truth)) {
      std::printf("%10.1f (no ground truth: %s)\n", t * 1e-6, world.error().c_str());
      continue;
    }
    // The truth is read a moment after the scan the estimate is for: carry
    // the estimate forward over that moment with the robot's velocity.
    double dt = (double(simulation.sim_time_us()) - double(t)) * 1e-6;
    if (!(dt > 0 && dt < 1)) dt = 0;
    const client::Pose2& e = estimate.pose();
    const client::Pose2& v = estimate.velocity();
    double a = e.a + v.a * dt;
    double x = e.x + v.x * std::cos(a) * dt, y = e.y + v.x * std::sin(a) * dt;
    std::printf("%10.1f %9.3f,%8.3f,%8.3f %9.3f,%8.3f,%8.3f %9.3f %8.2f %5zu\n", t * 1e-6, x, y, a, truth.x,
                truth.y, truth.a, std::hypot(x - truth.x, y - truth.y),
                std::fabs(wrap_angle(a - truth.a)) * 180 / kPi, localize.hypotheses().size());
    std::fflush(stdout);
    if (seconds > 0 && double(t - start_us) * 1e-6 >= seconds) return 0;
  }
}
