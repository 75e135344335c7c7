// troupe-sim: simulates a Stage world, or a RoboCup match written as one,
// and serves its robots over the wire. See options.cc for the command line.
// Started as troupe-robocup (a symbolic link to it), it is
// `troupe-sim --fast --no-serve`.
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <memory>

#include "host-sim/robocup/game/world_load.h"
#include "host-sim/troupe_sim/robocup_mode.h"
#include "host-sim/troupe_sim/runner.h"
#include "host-sim/viewer/view_server.h"
#include "runtime/exposure.h"
#include "runtime/log.h"
#include "runtime/secure_file.h"
#include "runtime/stop_signals.h"

#ifdef TROUPE_HAVE_MPI
#include "host-sim/mpi/divided_world.h"
#endif

int main(int argc, char** argv) {
  // Started by mpirun: this process steps its share of a world divided
  // between all of them (host-sim/mpi). Otherwise the whole world, as ever.
  troupe::sim::Division* division = nullptr;
#ifdef TROUPE_HAVE_MPI
  std::unique_ptr<troupe::sim::mpi::Comm> comm;
  std::unique_ptr<troupe::sim::mpi::DividedWorld> divided;
  if (troupe::sim::mpi::Comm::launched()) comm = std::make_unique<troupe::sim::mpi::Comm>(&argc, &argv);
#endif
  troupe::sim::SimOptions options;
  if (int rc = troupe::sim::parse_sim_options(argc, argv, options); rc >= 0) return rc;
  troupe::set_log_program(options.program.c_str());
  const char* program = options.program.c_str();
#ifdef TROUPE_HAVE_MPI
  if (comm) {
    divided = std::make_unique<troupe::sim::mpi::DividedWorld>(
        *comm, troupe::sim::mpi::DividedWorld::Options{
                   .rebalance_every = options.rebalance_every,
                   .balance_time = options.rebalance_by == "time",
                   // Served, the viewer draws the whole map from the leader.
                   .leader_holds_map = options.serve || !options.snapshot.empty()});
    division = divided.get();
    // One voice: the other processes say only what goes wrong.
    if (comm->rank() != 0) troupe::set_log_level(troupe::LogLevel::Warn);
  }
#else
  // mpirun sets this in every process it starts.
  if (std::getenv("OMPI_COMM_WORLD_SIZE") != nullptr) {
    troupe::log_warn(
        "this troupe-sim was built without MPI (-DTROUPE_MPI=OFF): every process mpirun "
        "started runs the whole world on its own");
  }
#endif
  std::string error;
  if (!options.secure_file.empty() &&
      !troupe::load_secure_sessions(options.secure_file, options.secure, error)) {
    std::fprintf(stderr, "%s: --secure %s\n", program, error.c_str());
    return 2;
  }
  if (options.serve && !troupe::may_serve("troupe-sim", options.listen, options.port, options.secure.on(),
                                          options.insecure, error)) {
    std::fprintf(stderr, "%s\n", error.c_str());
    return 2;
  }
  std::unique_ptr<troupe::PlainServiceWarning> plain_warning;

  // The viewer beside the node (its URL on stdout, like the port: tests
  // read it). False when it was asked for and cannot open.
  std::unique_ptr<troupe::viewer::ViewServer> viewer;
  auto start_viewer = [&](uint16_t node_port) {
    if (!options.serve || !options.view) return true;
    troupe::viewer::ViewOptions vo;
    vo.listen = options.view_listen;
    vo.http_port = options.view_port;
    // The bridge reaches the node over loopback unless it listens elsewhere.
    const bool any = options.listen == "0.0.0.0" || options.listen == "::";
    vo.node_host = any ? "127.0.0.1" : options.listen;
    vo.node_port = node_port;
    vo.web_root = troupe::viewer::default_web_root();
    vo.allow_origins = options.view_allow_origins;
    // A secure simulator's viewer is one of its clients, with that
    // client's rights; without a key of its own it cannot be.
    if (options.secure.on()) {
      if (options.view_identity.empty()) {
        if (options.view_asked) {
          std::fprintf(stderr, "troupe-sim: --view with --secure needs --view-identity FILE\n");
          return false;
        }
        troupe::log_warn("no browser viewer: a secure troupe-sim's viewer needs --view-identity FILE");
        return true;
      }
      vo.keys.identity = options.view_identity;
      vo.keys.node_key = options.secure.key_hex;
    }
    viewer = std::make_unique<troupe::viewer::ViewServer>(vo);
    if (!viewer->open(error)) {
      viewer.reset();
      if (options.view_asked) {
        std::fprintf(stderr, "troupe-sim: viewer: %s\n", error.c_str());
        return false;
      }
      troupe::log_warn("no browser viewer: %s (--view P picks another port)", error.c_str());
      return true;
    }
    std::printf("viewer at %s\n", viewer->url().c_str());
    std::fflush(stdout);
    viewer->start_thread();
    return true;
  };
  // The port goes to stdout on its own line, so scripts and tests that
  // asked for port 0 can read it.
  auto print_port = [&](troupe::Node& node) {
    if (!options.serve) return;
    std::printf("listening on %s\n", node.listen_text().c_str());
    std::fflush(stdout);
    troupe::log_info("try: troupe ls %s:%u", options.listen.c_str(), unsigned(node.port()));
    if (options.secure.on()) {
      troupe::log_info("secure sessions only; this simulator's key is %s", options.secure.key_hex.c_str());
    } else if (!troupe::loopback_only(options.listen)) {
      plain_warning =
          std::make_unique<troupe::PlainServiceWarning>(node.loop(), "troupe-sim on " + node.listen_text());
    }
  };

  // The one loader: a Stage world's description, or a match's game part.
  troupe::robocup::LoadedWorld loaded;
  troupe::world::Diagnostics diags;
  const bool loaded_ok = troupe::robocup::load_any_world(options.world, loaded, diags);
  // Warnings (unknown keys, ...) and errors, each with file:line: once,
  // when every process of a divided run read the same file.
  const bool speaks = !division || division->first();
  if (speaks) {
    for (const auto& d : diags.items()) std::fprintf(stderr, "%s\n", d.str().c_str());
  }
  if (!loaded_ok) return 1;
  if (loaded.game) {
    if (division) {
      if (speaks)
        std::fprintf(stderr, "%s: a RoboCup match runs in one process; start it without mpirun\n", program);
      return 1;
    }
    troupe::sim::RobocupMode match;
    if (!match.init(options, std::move(*loaded.game), error)) {
      std::fprintf(stderr, "%s: %s\n", program, error.c_str());
      return 1;
    }
    troupe::log_info("%s: a RoboCup match, %d robots, cycle %.0f ms, seed %llu", options.world.c_str(),
                     match.simulation().robot_count(), match.simulation().cycle_s() * 1e3,
                     static_cast<unsigned long long>(match.simulation().spec().seed));
    // A console runs the match itself, unserved, until its commands end.
    if (!match.serving()) return match.run();
    troupe::StopOnSignal stop_on_signal(match.node().loop(), [&match] { match.request_stop(); });
    print_port(match.node());
    if (!start_viewer(match.port())) return 1;
    return match.run();
  }
  // The console and the referee's events are a match's.
  if (const char* option = troupe::sim::robocup_only_option(options)) {
    std::fprintf(stderr, "%s: %s is for RoboCup worlds; %s is a Stage world\n", program, option,
                 options.world.c_str());
    return 1;
  }

  troupe::sim::Runner runner;
  diags = {};
  const bool ok = runner.init(options, loaded.desc, diags, error, division);
  if (speaks) {
    for (const auto& d : diags.items()) std::fprintf(stderr, "%s\n", d.str().c_str());
  }
  if (!ok) {
    if (!error.empty()) std::fprintf(stderr, "%s: %s\n", program, error.c_str());
    return 1;
  }
  troupe::StopOnSignal stop_on_signal(runner.node().loop(), [&runner] { runner.request_stop_by_signal(); });
  // A divided run ends by its run loop, on every process; stopped by a
  // signal, without MPI_Finalize (Runner::stopped_by_signal()): the table
  // and the log are out, what is left unsaid is goodbye to an mpirun that
  // no longer listens.
  auto finish = [&](int status) {
#ifdef TROUPE_HAVE_MPI
    if (comm && runner.stopped_by_signal()) {
      std::fflush(nullptr);
      std::_Exit(status);
    }
#endif
    return status;
  };
  // A divided run's other processes follow the leader, which alone
  // serves, prints and draws.
  if (division && !division->first()) return finish(runner.run());
  const troupe::sim::World& w = runner.world();
  size_t controlled = 0;
  // --no-ctrl leaves every robot to the wire, whatever the world file names.
  if (!options.no_ctrl) {
    for (const auto& r : w.desc().robots) controlled += r.ctrl.empty() ? 0 : 1;
  }
  troupe::log_info("%s: %zu robots (%zu with controllers), step %.0f ms, seed %llu", options.world.c_str(),
                   w.robot_count(), controlled, w.interval() * 1e3,
                   static_cast<unsigned long long>(options.seed));
  print_port(runner.node());
  // The emulated devices, one "ROBOT DEVICE PATH" line each, for scripts.
  if (!runner.emulation().empty()) {
    std::fputs(runner.emulation().info().c_str(), stdout);
    std::fflush(stdout);
    for (const auto& d : runner.emulation().devices()) {
      troupe::log_info("robot %s emulated as %s hardware on %s", d.robot_name.c_str(),
                       troupe::sim::emulated_kind_name(d.kind), d.path.c_str());
    }
  }
  // The robots served as Pioneers on TCP, one "ROBOT p2os-tcp HOST:PORT"
  // line each, for scripts.
  if (!runner.p2os_tcp().empty()) {
    std::fputs(runner.p2os_tcp().info().c_str(), stdout);
    std::fflush(stdout);
    troupe::log_info("ARIA programs connect to robot %s with -remoteHost %s -remoteRobotTcpPort %u",
                     w.robot(0).name.c_str(), options.listen.c_str(), unsigned(runner.p2os_tcp().port(0)));
  }
  if (!start_viewer(runner.port())) {
    runner.release_followers();
    return 1;
  }
  return finish(runner.run());
}
