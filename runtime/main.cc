// troupe-node: serves the devices of one robot (or desktop) over the wire.
//
//   troupe-node CONFIG [--port N] [--listen ADDR] [--log-level LEVEL] [--max-clients N]
//               [--max-clients-per-address N] [--hello-timeout-ms MS] [--idle-timeout-ms MS]
#include <signal.h>

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <iterator>
#include <string>

#include "runtime/args.h"
#include "runtime/log.h"
#include "runtime/node_config.h"
#ifdef TROUPE_HAVE_NOISE
#include "runtime/node_secure.h"
#endif
#include "runtime/stop_signals.h"

namespace {

const char kUsage[] =
    "usage: troupe-node CONFIG [--port N] [--listen ADDR] [--log-level error|warn|info|debug]\n"
    "                   [--max-clients N] [--max-clients-per-address N]\n"
    "                   [--hello-timeout-ms MS] [--idle-timeout-ms MS]\n"
    "\n"
    "Serves the devices listed in the node config CONFIG (JSON, or the binary\n"
    "flatc compiles from it) to clients over TCP. Options override the config.\n"
    "\n"
    "  --max-clients N               connections served at once (default 64)\n"
    "  --max-clients-per-address N   of them from one IP address (default 0: no limit)\n"
    "  --hello-timeout-ms MS         close a connection silent this long after connecting\n"
    "                                (default 5000; 0: never)\n"
    "  --idle-timeout-ms MS          close a connection that reads nothing and is silent\n"
    "                                this long (default 60000; 0: never)\n"
    "\n"
    "examples:\n"
    "  troupe-node examples/nodes/kinematic.json\n"
    "  troupe-node examples/nodes/kinematic.json --port 7000 --listen 0.0.0.0\n";

// A numeric flag's value, min..max; false (with the reason printed) when it
// is not one.
bool flag_number(const char* flag, const char* text, unsigned long min, unsigned long max, unsigned long& out) {
  char* end = nullptr;
  out = strtoul(text, &end, 10);
  if (*text >= '0' && *text <= '9' && *end == '\0' && out >= min && out <= max) return true;
  fprintf(stderr, "troupe-node: bad %s '%s' (%lu to %lu)\n", flag, text, min, max);
  return false;
}

}  // namespace

int main(int argc, char** argv) {
  troupe::set_log_program("troupe-node");
  signal(SIGPIPE, SIG_IGN);
  const char* config_path = nullptr;
  const char* port = nullptr;
  const char* listen = nullptr;
  const char* level = nullptr;
  const char* max_clients = nullptr;
  const char* per_address = nullptr;
  const char* hello_timeout = nullptr;
  const char* idle_timeout = nullptr;
  const troupe::Flag flags[] = {{"--port", &port},
                                {"--listen", &listen},
                                {"--log-level", &level},
                                {"--max-clients", &max_clients},
                                {"--max-clients-per-address", &per_address},
                                {"--hello-timeout-ms", &hello_timeout},
                                {"--idle-timeout-ms", &idle_timeout}};
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
  unsigned long n = 0;
  if (max_clients != nullptr) {
    if (!flag_number("--max-clients", max_clients, 1, 65535, n)) return 2;
    options.max_clients = uint16_t(n);
  }
  if (per_address != nullptr) {
    if (!flag_number("--max-clients-per-address", per_address, 0, 65535, n)) return 2;
    options.max_clients_per_address = uint16_t(n);
  }
  if (hello_timeout != nullptr) {
    if (!flag_number("--hello-timeout-ms", hello_timeout, 0, UINT32_MAX, n)) return 2;
    options.hello_timeout_ms = uint32_t(n);
  }
  if (idle_timeout != nullptr) {
    if (!flag_number("--idle-timeout-ms", idle_timeout, 0, UINT32_MAX, n)) return 2;
    options.idle_timeout_ms = uint32_t(n);
  }

#ifdef TROUPE_HAVE_NOISE
  if (!troupe::secure_sessions(cfg, options, error)) {
    troupe::log_error("%s", error.c_str());
    return 1;
  }
#else
  if (cfg.root->key() != nullptr) {
    troupe::log_error("%s: \"key\": board %s is built without secure sessions (libsodium)", cfg.path.c_str(),
                      troupe::kBoardName);
    return 1;
  }
#endif

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
  troupe::log_info("%s (board %s) serving %zu devices on %s", options.name.c_str(), troupe::kBoardName,
                   node.device_count(), node.listen_text().c_str());
  node.run();
  node.shutdown();
  troupe::log_info("stopped");
  return 0;
}
