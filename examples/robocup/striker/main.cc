// troupe-robocup-striker: drives one robot of a served RoboCup match as a
// striker (striker.h), printing what it does once a second.
//
//   troupe-robocup-striker [HOST[:PORT]] [--robot NAME] [--team blue|yellow]
//                          [--seconds S] [--pull] [--lockstep]
//
// --pull asks for each update instead of having data pushed. --lockstep
// pauses the simulator and steps it one cycle per decision, so a run
// repeats exactly. It stops after S seconds of simulated time (default: run
// until interrupted or the connection is lost for good) and prints a
// summary line.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

#include "examples/robocup/striker/striker.h"
#include "wire/address.h"
#include "wire/cli/args.h"

using namespace troupe;

int main(int argc, char** argv) {
  std::string node = "127.0.0.1";
  examples::StrikerOptions options;
  double seconds = 0;
  bool pull = false, lockstep = false;
  std::string team = "yellow";
  auto app = cli::make_app(
      "troupe robocup-striker",
      {"troupe robocup-striker [HOST[:PORT]] [--robot NAME] [--team blue|yellow] [--seconds S] [--pull]\n"
       "                              [--lockstep]",
       "Drives one robot of a RoboCup match served by troupe-sim (troupe sim WORLD) as\n"
       "a striker, printing what it does once a second, and a summary at the end.\n",
       {"troupe robocup-striker localhost", "troupe-robocup-striker localhost --robot blue2 --team blue --lockstep"}});
  app->add_option("HOST", node, "HOST[:PORT] of the match (default 127.0.0.1)");
  app->add_option("--robot", options.robot, "the robot to drive (default yellow3)")->type_name("NAME");
  app->add_option("--team", team, "its team: blue or yellow (default yellow)")
      ->type_name("TEAM")
      ->check(CLI::IsMember({"blue", "yellow"}));
  app->add_option("--seconds", seconds, "stop after S seconds of simulated time (default: run until interrupted)")
      ->type_name("S")
      ->check(cli::above(0));
  app->add_flag("--pull", pull, "ask for each update instead of having data pushed");
  app->add_flag("--lockstep", lockstep, "pause the simulator and step it one cycle per decision (runs repeat)");
  if (int rc = cli::parse(*app, argc, argv); rc >= 0) return rc;
  options.team = team == "blue" ? examples::Team::Blue : examples::Team::Yellow;
  wire::HostPort host;
  std::string error;
  if (!wire::parse_host(node, host, error)) return cli::usage_error(*app, error);
  client::Client client(host.host, host.port);
  if (!client.connect()) {
    std::fprintf(stderr, "troupe-robocup-striker: %s\n", client.error().c_str());
    return 1;
  }
  client::SimulationProxy sim(client);
  examples::Striker striker(client, options);
  if (!striker.start(error)) {
    std::fprintf(stderr, "troupe-robocup-striker: %s\n", error.c_str());
    return 1;
  }
  if (pull) {
    // Re-open every sensor for pulling: data then comes only on request.
    for (const std::string& model : striker.sensors().models()) {
      client.open(striker.sensors().model(model)->address(), wire::Access::All, wire::Delivery::Pull);
    }
  }
  std::printf("driving %s (team %s) on %s; simulated time %.2f s\n", options.robot.c_str(),
              options.team == examples::Team::Blue ? "blue" : "yellow", client.node_name().c_str(),
              double(sim.sim_time_us()) * 1e-6);
  if (lockstep && !sim.pause()) {
    std::fprintf(stderr, "troupe-robocup-striker: cannot pause the simulator: %s\n", client.error().c_str());
    return 1;
  }
  uint64_t next_report_us = 0;
  int disconnected_ticks = 0;
  double closest = INFINITY;
  while (true) {
    if (lockstep) {
      // One cycle, then everything it published has arrived.
      if (!sim.step(1) || !client.sync()) {
        std::fprintf(stderr, "troupe-robocup-striker: step: %s\n", client.error().c_str());
        return 1;
      }
    }
    if (pull) {
      if (!striker.sensors().update()) std::fprintf(stderr, "pull: %s\n", client.error().c_str());
      if (!lockstep) client.spin_once(10);  // one simulator cycle, about
    } else if (!lockstep) {
      client.spin_once(20);
    }
    const examples::StrikerAction a = striker.tick();
    if (lockstep) client.sync();  // the command is in effect before the next step
    if (const auto d = striker.sensors().feature("ballDistance")) closest = std::min(closest, d->value);
    const uint64_t now = sim.sim_time_us();
    if (now >= next_report_us) {
      char ball[32] = "unseen";
      if (const auto d = striker.sensors().feature("ballDistance"))
        std::snprintf(ball, sizeof ball, "%.2f m", d->value);
      std::printf("t=%6.2f s  %-8s  ball %-8s  kicks %u  score blue %u yellow %u\n", double(now) * 1e-6,
                  a.mode, ball, striker.kicks(), sim.game().score_blue, sim.game().score_yellow);
      std::fflush(stdout);
      next_report_us = now + 1000000;
    }
    if (seconds > 0 && double(now) * 1e-6 >= seconds) break;
    // The client reconnects by itself; a simulator gone for a few seconds
    // (the match is over) ends the run.
    disconnected_ticks = client.connected() ? 0 : disconnected_ticks + 1;
    if (disconnected_ticks > 200) {
      std::fprintf(stderr, "troupe-robocup-striker: connection lost: %s\n", client.error().c_str());
      return 1;
    }
  }
  std::printf("done: %.2f s simulated, kicks %u, closest to the ball %.2f m, score blue %u yellow %u\n",
              double(sim.sim_time_us()) * 1e-6, striker.kicks(), closest, sim.game().score_blue,
              sim.game().score_yellow);
  return 0;
}
