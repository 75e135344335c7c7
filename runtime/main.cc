// troupe-node: serves the devices of one robot (or desktop) over the wire.
//
//   troupe-node CONFIG [--port N] [--listen ADDR] [--log-level LEVEL]
#include <signal.h>

#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <iterator>
#include <string>

#include "runtime/args.h"
#include "runtime/log.h"
#include "runtime/node_config.h"
#include "runtime/stop_signals.h"

namespace {

const char kUsage[] =
    "usage: troupe-node CONFIG [--port N] [--listen ADDR] [--log-level error|warn|info|debug]\n"
    "\n"
    "Serves the devices listed in the node config CONFIG (JSON, or the binary\n"
    "flatc compiles from it) to clients over TCP. Options override the config.\n"
    "\n"
    "examples:\n"
    "  troupe-node examples/nodes/kinematic.json\n"
    "  troupe-node examples/nodes/kinematic.json --port 7000 --listen 0.0.0.0\n";

}  // namespace

int main(int argc, char** argv) {
  troupe::set_log_program("troupe-node");
  signal(SIGPIPE, SIG_IGN);
  const char* config_path = nullptr;
  const char* port = nullptr;
  const char* listen = nullptr;
  const char* level = nullptr;
  const troupe::Flag flags[] = {{"--port", &port}, {"--listen", &listen}, {"--log-level", &level}};
  const troupe::CommandLine line{"troupe-node", kUsage, flags, std::size(flags), &config_path};
  if (int rc = troupe::parse_command_line(line, argc, argv); rc >= 0) return rc;

  std::string error;
  troupe::LoadedConfig cfg;
  if (!troupe::load_config(config_path, cfg, error)) {
    troupe::log_error("%s", error.c_str());
    return 1;
  }
  troupe::set_log_level(troupe::LogLevel(int(cfg.root->log_level())));
  troupe::LogLevel parsed{};
  if (level != nullptr) {
    if (!troupe::parse_log_level(level, parsed)) {
      fprintf(stderr, "troupe-node: bad log level '%s'\n%s", level, kUsage);
      return 2;
    }
    troupe::set_log_level(parsed);
  }
  troupe::Node::Options options = troupe::node_options(*cfg.root);
  if (port != nullptr) {
    char* end = nullptr;
    long p = strtol(port, &end, 10);
    if (*end != '\0' || p < 0 || p > 65535) {
      fprintf(stderr, "troupe-node: bad port '%s'\n", port);
      return 2;
    }
    options.port = uint16_t(p);
  }
  if (listen != nullptr) options.listen = listen;

  troupe::Node node(options);
  if (!troupe::build_node(node, cfg, error)) {
    troupe::log_error("%s", error.c_str());
    troupe::log_error("not starting: the config must be fixed first");
    return 1;
  }
  if (!node.start(error)) {
    troupe::log_error("%s", error.c_str());
    return 1;
  }
  troupe::StopOnSignal stop_on_signal(node.loop(), [&node] { node.stop(); });
  troupe::log_info("%s (board %s) serving %zu devices on %s:%u", options.name.c_str(), troupe::kBoardName,
                   node.device_count(), options.listen.c_str(), unsigned(node.port()));
  node.run();
  node.shutdown();
  troupe::log_info("stopped");
  return 0;
}
