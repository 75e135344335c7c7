// troupe-sim: simulates a Stage world and serves its robots over the wire.
// See options.cc for the command line.
#include <cstdio>
#include <cstring>
#include <memory>

#include "host-sim/troupe_sim/runner.h"
#include "host-sim/viewer/view_server.h"
#include "runtime/log.h"
#include "runtime/stop_signals.h"

int main(int argc, char** argv) {
  troupe::set_log_program("troupe-sim");
  troupe::sim::SimOptions options;
  std::string error;
  bool help = false;
  if (!troupe::sim::parse_sim_options(argc, argv, options, error, help)) {
    std::fprintf(stderr, "troupe-sim: %s\n\n%s", error.c_str(), troupe::sim::sim_usage());
    return 2;
  }
  if (help) {
    std::printf("%s", troupe::sim::sim_usage());
    return 0;
  }
  troupe::LogLevel level;
  if (!troupe::parse_log_level(options.log_level.c_str(), level)) {
    std::fprintf(stderr, "troupe-sim: unknown log level %s\n", options.log_level.c_str());
    return 2;
  }
  troupe::set_log_level(level);

  troupe::sim::Runner runner;
  troupe::world::Diagnostics diags;
  const bool ok = runner.init(options, diags, error);
  // Warnings (unknown keys, ...) and errors, each with file:line.
  for (const auto& d : diags.items()) std::fprintf(stderr, "%s\n", d.str().c_str());
  if (!ok) {
    if (!error.empty()) std::fprintf(stderr, "troupe-sim: %s\n", error.c_str());
    return 1;
  }
  troupe::StopOnSignal stop_on_signal(runner.node().loop(), [&runner] { runner.request_stop(); });
  const troupe::sim::World& w = runner.world();
  size_t controlled = 0;
  // --no-ctrl leaves every robot to the wire, whatever the world file names.
  if (!options.no_ctrl) {
    for (const auto& r : w.desc().robots) controlled += r.ctrl.empty() ? 0 : 1;
  }
  troupe::log_info("%s: %zu robots (%zu with controllers), step %.0f ms, seed %llu", options.world.c_str(),
                   w.robot_count(), controlled, w.interval() * 1e3,
                   static_cast<unsigned long long>(options.seed));
  if (options.serve) {
    // The port goes to stdout on its own line, so scripts and tests that
    // asked for port 0 can read it.
    std::printf("listening on %s\n", runner.node().listen_text().c_str());
    std::fflush(stdout);
    troupe::log_info("try: troupe ls %s:%u", options.listen.c_str(), unsigned(runner.port()));
  }
  // The emulated devices, one "ROBOT DEVICE PATH" line each, for scripts.
  if (!runner.emulation().empty()) {
    std::fputs(runner.emulation().info().c_str(), stdout);
    std::fflush(stdout);
    for (const auto& d : runner.emulation().devices()) {
      troupe::log_info("robot %s emulated as %s hardware on %s", d.robot_name.c_str(),
                       troupe::sim::emulated_kind_name(d.kind), d.path.c_str());
    }
  }
  std::unique_ptr<troupe::viewer::ViewServer> viewer;
  if (options.serve && options.view) {
    troupe::viewer::ViewOptions vo;
    vo.listen = options.view_listen;
    vo.http_port = options.view_port;
    // The bridge reaches the node over loopback unless it listens elsewhere.
    const bool any = options.listen == "0.0.0.0" || options.listen == "::";
    vo.node_host = any ? "127.0.0.1" : options.listen;
    vo.node_port = runner.port();
    vo.web_root = troupe::viewer::default_web_root();
    viewer = std::make_unique<troupe::viewer::ViewServer>(vo);
    if (!viewer->open(error)) {
      viewer.reset();
      if (options.view_asked) {
        std::fprintf(stderr, "troupe-sim: viewer: %s\n", error.c_str());
        return 1;
      }
      troupe::log_warn("no browser viewer: %s (--view P picks another port)", error.c_str());
    } else {
      // Its own line on stdout, like the port: tests read it.
      std::printf("viewer at %s\n", viewer->url().c_str());
      std::fflush(stdout);
      viewer->start_thread();
    }
  }
  return runner.run();
}
