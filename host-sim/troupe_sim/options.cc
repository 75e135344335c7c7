#include "host-sim/troupe_sim/options.h"

#include "runtime/exposure.h"
#include "runtime/secure_file.h"
#include "wire/cli/args.h"

namespace troupe::sim {
namespace {

// `--view [P]` and `--p2os-tcp [PORT]` take the next word only when it is a
// number: `troupe-sim --view WORLD` serves WORLD with the viewer on its
// default port. CLI11 would take any word, so a flag standing alone gets its
// default written into it.
std::vector<std::string> with_optional_ports(int argc, const char* const* argv, const SimOptions& defaults) {
  std::vector<std::string> args(argv + 1, argv + argc);
  for (size_t i = 0; i < args.size(); ++i) {
    if (args[i] == "--") break;
    const bool number_follows = i + 1 < args.size() && !args[i + 1].empty() &&
                                args[i + 1].find_first_not_of("0123456789") == std::string::npos;
    if (number_follows) continue;
    if (args[i] == "--view") args[i] += "=" + std::to_string(defaults.view_port);
    if (args[i] == "--p2os-tcp") args[i] += "=" + std::to_string(kMobileSimPort);
  }
  return args;
}

const char* const kExitText =
    "exit status: 0 when the run reached its quit time (also when a client's Step\n"
    "request got there; the log says so), the referee's time was up, the console's\n"
    "commands ran, or SIGINT/SIGTERM stopped it; 1 when the world, a controller, the\n"
    "snapshot, the log, the console's script or one of its commands failed; 2 on a\n"
    "bad command line.\n";

cli::Help sim_help() {
  return {"troupe-sim WORLD [options]",
          std::string("Simulates the Stage world file WORLD and serves every robot's devices over the\n"
                      "wire: robot i's devices are ROBOT/INTERFACE:INDEX (r0/position2d:0, r0/ranger:1)\n"
                      "on one port, and simulation:0 pauses, steps, teleports and resets. A RoboCup\n"
                      "match written as a Stage world (robocup_field, ball, referee, robocup_robot)\n"
                      "runs on rigid-body physics, served the same way, with players and a score; its\n"
                      "referee's events and the final score are printed on standard output, and\n"
                      "--script or --interactive run console commands instead of serving it.\n"
                      "troupe-robocup is this program with --fast --no-serve.\n"
                      "\n") +
              kExitText,
          {"troupe-sim examples/worlds/swarm100.world --fast --quit-time 60 --snapshot out.png",
           "troupe-sim simple.world --port 7000 & troupe ls localhost:7000",
           "troupe-sim examples/worlds/sitl_room.world --emulate r0=p2os,sicklms200",
           "troupe-sim examples/worlds/sitl_room.world --p2os-tcp      # ARIA: localhost:8101",
           "troupe-sim examples/robocup/match.world          # a RoboCup match, served and drawn",
           "troupe-sim examples/robocup/match.world --script moves.txt   # run 5, score, ..."}};
}

cli::Help alias_help() {
  return {"troupe-robocup WORLD [options]",
          std::string("troupe-sim --fast --no-serve under another name: runs the RoboCup world WORLD\n"
                      "flat out, unserved, printing the referee's events as they happen and the final\n"
                      "score. --script FILE or --interactive (standard input) run console commands\n"
                      "between cycles: run SECONDS, step [N], start ROBOT PLUGIN [key=value ...],\n"
                      "stop ROBOT, score, state, ball X Y, place ROBOT X Y A, kick ROBOT, quit, ...\n"
                      "To serve a match (real time, the viewer, clients), run troupe-sim WORLD.\n"
                      "\n") +
              kExitText,
          {"troupe-robocup examples/robocup/match.world --quit-time 120 --seed 4",
           "troupe robocup examples/robocup/match.world --interactive   # then: run 5, score, quit"}};
}

}  // namespace

bool started_as_robocup_alias(const char* argv0) {
  const std::string name = argv0 ? argv0 : "";
  return name.substr(name.rfind('/') + 1) == kRobocupAlias;
}

int parse_sim_options(int argc, const char* const* argv, SimOptions& out) {
  const bool alias = argc > 0 && started_as_robocup_alias(argv[0]);
  if (alias) {
    out.program = kRobocupAlias;
    out.fast = true;
  }
  auto app = cli::make_app(out.program, alias ? alias_help() : sim_help());
  bool no_view = false;
  app->add_option("WORLD", out.world, "the world file")->required();
  app->add_flag("--headless", out.headless, "no window (always; the viewer connects over the wire)");
  app->add_flag("--fast", out.fast, "run as fast as possible");
  app->add_option("--speed", out.speed, "run at X times real time (0: as fast as possible)")
      ->type_name("X")
      ->check(cli::at_least(0));
  app->add_option("--quit-time", out.quit_time, "stop after this much simulated time")
      ->type_name("SECONDS")
      ->check(cli::at_least(0));
  app->add_flag("--paused", out.paused, "start paused");
  auto* seed = app->add_option("--seed", out.seed,
                               "seed of every random number in the run, 0 included\n"
                               "(default: a RoboCup world's seed; 0 for a Stage world)")
                   ->type_name("N")
                   ->check(cli::at_least(0));
  cli::add_port(*app, "--port", out.port, "TCP port (default 6665; 0: any free port, printed)");
  app->add_option("--listen", out.listen, "address to listen on (default localhost: 127.0.0.1 and ::1)")
      ->type_name("ADDR");
  auto* secure = app->add_option("--secure", out.secure_file, kSecureFlagHelp)->type_name("FILE");
  app->add_option("--view-identity", out.view_identity,
                  "with --secure: the secret key the viewer's bridge connects\n"
                  "with, one of FILE's clients (its rights are the viewer's);\n"
                  "without it a secure troupe-sim starts no viewer")
      ->type_name("FILE")
      ->needs(secure);
  app->add_flag("--insecure", out.insecure,
                "allow --listen beyond loopback without --secure: any machine\n"
                "that reaches the port can read and command every robot\n"
                "(logged every minute)")
      ->excludes(secure);
  app->add_flag("--port-per-robot", out.port_per_robot, "also serve robot i alone as robot 0 on port P+1+i");
  bool no_serve = false;
  app->add_flag("--no-serve", no_serve, "no network at all (batch runs)");
  auto* view = cli::add_port(*app, "--view", out.view_port,
                             "browser viewer on HTTP port P (default 6680; 0: any free\n"
                             "port); on by default, its URL is printed")
                   ->type_name("[P]");
  auto* view_listen =
      app->add_option("--view-listen", out.view_listen, "address the viewer listens on (default 127.0.0.1)")
          ->type_name("ADDR");
  app->add_option("--view-allow-origin", out.view_allow_origins,
                  "also accept the viewer's WebSocket from pages of origin O\n"
                  "(http://host:port; repeatable); by default only the page\n"
                  "it served itself, under an address or this machine's name")
      ->type_name("O");
  app->add_flag("--no-view", no_view, "no browser viewer")->excludes(view)->excludes(view_listen);
  app->add_option("--snapshot", out.snapshot, "picture of the world at the end")->type_name("FILE.png");
  app->add_option("--snapshot-every", out.snapshot_every, "... and every S simulated seconds")
      ->type_name("S")
      ->check(cli::at_least(0));
  app->add_option("--log", out.log, "trajectory log: time,robot,x,y,a every step")->type_name("FILE.csv");
  app->add_option("--plugin-path", out.plugin_path,
                  "look for plugins (controllers: ctrl \"name\") in DIR first;\n"
                  "then ../lib/troupe beside troupe-sim, $TROUPE_PLUGIN_PATH,\n"
                  "the world's folder")
      ->type_name("DIR");
  app->add_flag("--ignore-missing-ctrl", out.ignore_missing_ctrl,
                "load anyway; robots whose controller is missing stay idle");
  app->add_flag("--no-ctrl", out.no_ctrl, "run no controllers: every robot waits for clients");
  app->add_flag("--profile", out.profile, "print the time spent in each phase of the step at the end");
  app->add_option("--rebalance-every", out.rebalance_every,
                  "under mpirun: redraw the processes' regions every N steps (0: never)")
      ->type_name("N")
      ->group("Divided between processes (mpirun -np N troupe-sim ...)");
  app->add_option("--rebalance-by", out.rebalance_by,
                  "under mpirun: draw regions of about equal measured step time (time) or robot count "
                  "(robots)")
      ->check(CLI::IsMember({"time", "robots"}))
      ->type_name("time|robots")
      ->group("Divided between processes (mpirun -np N troupe-sim ...)");

  cli::add_log_level(*app);

  const std::string robocup = "RoboCup worlds";
  auto* script = app->add_option("--script", out.script,
                                 "run console commands from FILE between cycles (run 10,\n"
                                 "start ROBOT PLUGIN, score, ...), flat out and unserved")
                     ->type_name("FILE")
                     ->group(robocup);
  auto* interactive = app->add_flag("--interactive", out.interactive, "the same, typed on standard input")
                          ->excludes(script)
                          ->group(robocup);
  app->add_flag("--quiet", out.quiet, "no referee event lines, only the final score")->group(robocup);
  // troupe-robocup's old run length: one rule now, --quit-time.
  std::string seconds;
  auto* old_seconds = app->add_option("--seconds", seconds)->group("");

  const std::string sitl = "hardware in the loop (SITL)";
  app->add_option("--emulate", out.emulate,
                  "present a robot (name or number) as hardware: DEVS is\n"
                  "p2os (its base as a Pioneer), sicklms200 (its laser as a\n"
                  "SICK LMS200) or both, comma-separated; each on a new\n"
                  "pseudo-terminal, printed as a line ROBOT DEVICE PATH\n"
                  "(repeatable, one per robot)")
      ->type_name("ROBOT=DEVS")
      ->group(sitl);
  app->add_option("--emulate-info", out.emulate_info,
                  "also write those lines to FILE (complete when it appears)")
      ->type_name("FILE")
      ->group(sitl);
  app->add_option("--emulate-links", out.emulate_links,
                  "also name each device DIR/ROBOT-DEVICE (a symbolic link)")
      ->type_name("DIR")
      ->group(sitl);
  auto* p2os_tcp = app->add_option("--p2os-tcp", out.p2os_tcp_port,
                                   "serve every robot's base as a Pioneer (P2OS) on TCP, as\n"
                                   "MobileSim does: robot i on PORT+i (default 8101), its\n"
                                   "laser in MobileSim's laser packets; unchanged ARIA\n"
                                   "programs connect to it (printed as lines ROBOT p2os-tcp\n"
                                   "HOST:PORT)")
                       ->type_name("[PORT]")
                       ->check(cli::between(0, 65535))
                       ->group(sitl);

  if (int rc = cli::parse(*app, with_optional_ports(argc, argv, out)); rc >= 0) return rc;
  if (old_seconds->count() > 0) {
    return cli::usage_error(*app, "--seconds is gone: --quit-time S stops the run after S simulated seconds");
  }
  const char* console = script->count() > 0        ? "--script"
                        : interactive->count() > 0 ? "--interactive"
                                                   : nullptr;
  if (console && out.quit_time >= 0) {
    return cli::usage_error(*app, std::string("--quit-time with ") + console +
                                      ": the commands say how far the match runs (run SECONDS, step N)");
  }
  // Why nothing is served, for the messages below: the console runs the
  // match itself, and the alias is --no-serve.
  const char* unserved = no_serve  ? "--no-serve"
                         : console ? console
                         : alias   ? "troupe-robocup, which is --no-serve"
                                   : nullptr;
  out.seed_given = seed->count() > 0;
  out.serve = unserved == nullptr;
  out.view_asked = view->count() > 0 || view_listen->count() > 0;
  out.view = !no_view;
  if (out.paused && !out.serve) {
    return cli::usage_error(*app, std::string("--paused with ") + unserved +
                                      ": nothing is served, so nothing could ever resume the simulation");
  }
  if (secure->count() > 0 && !out.serve) {
    return cli::usage_error(*app, std::string("--secure with ") + unserved + ": it opens no sockets");
  }
  if (secure->count() > 0 && p2os_tcp->count() > 0 && !loopback_only(out.listen)) {
    return cli::usage_error(*app,
                            "--p2os-tcp beyond loopback with --secure: P2OS has no secure sessions, "
                            "so anyone reaching its ports would drive the robots");
  }
  if (p2os_tcp->count() > 0 && !out.serve) {
    return cli::usage_error(*app, std::string("--p2os-tcp with ") + unserved + ": it opens no sockets");
  }
  return -1;
}

}  // namespace troupe::sim
