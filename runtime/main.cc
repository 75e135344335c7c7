// troupe-node: serves the devices of one robot (or desktop) over the wire.
//
//   troupe-node CONFIG [--set INSTANCE.KEY=VALUE]... [--print-config] [--port N] [--listen ADDR]
//               [--log-level LEVEL] [--max-clients N] [--max-clients-per-address N]
//               [--hello-timeout-ms MS] [--idle-timeout-ms MS] [--insecure]
//   troupe-node --keygen FILE
#include <signal.h>

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <iterator>
#include <memory>
#include <string>

#include "runtime/args.h"
#include "runtime/exit_status.h"
#include "runtime/exposure.h"
#include "runtime/log.h"
#include "runtime/node_config.h"
#ifdef TROUPE_HAVE_NOISE
#include <unistd.h>

#include "runtime/node_secure.h"
#include "wire/noise/key_file.h"
#endif
#include "runtime/stop_signals.h"

namespace {

const char kUsage[] =
    "usage: troupe-node CONFIG [--set INSTANCE.KEY=VALUE]... [--print-config]\n"
    "                   [--port N] [--listen ADDR] [--log-level error|warn|info|debug]\n"
    "                   [--max-clients N] [--max-clients-per-address N]\n"
    "                   [--hello-timeout-ms MS] [--idle-timeout-ms MS] [--insecure]\n"
#ifdef TROUPE_HAVE_NOISE
    "       troupe-node --keygen FILE\n"
#endif
    "\n"
    "Serves the devices listed in the node config CONFIG (JSON, or the binary\n"
    "`troupe config compile` makes of it) to clients over TCP. Options override\n"
    "the config.\n"
    "\n"
    "  --set INSTANCE.KEY=VALUE      option KEY of driver instance INSTANCE (its name,\n"
    "                                else its driver type); KEY=VALUE: a node setting\n"
    "  --print-config                print the config it would run, as JSON, and exit\n"
    "  --max-clients N               connections served at once (default 64)\n"
    "  --max-clients-per-address N   of them from one IP address (default 0: no limit)\n"
    "  --hello-timeout-ms MS         close a connection silent this long after connecting\n"
    "                                (default 5000; 0: never)\n"
    "  --idle-timeout-ms MS          close a connection that reads nothing and is silent\n"
    "                                this long (default 60000; 0: never)\n"
    "  --insecure                    serve plain TCP beyond loopback (no \"key\" in the\n"
    "                                config): anyone who reaches the port may command\n"
    "                                every device; logged every minute\n"
#ifdef TROUPE_HAVE_NOISE
    "  --keygen FILE                 write this node's key pair for secure sessions: FILE\n"
    "                                (secret, readable by its owner only) and FILE.pub;\n"
    "                                never overwrites; the config names FILE in \"key\"\n"
#endif
    "\n"
    "examples:\n"
    "  troupe-node examples/nodes/kinematic.json\n"
    "  troupe-node examples/nodes/kinematic.json --port 7000 --listen 0.0.0.0 --insecure\n"
    "  troupe-node examples/nodes/kinematic.json --set kinematic.max_speed=0.5 --print-config\n"
#ifdef TROUPE_HAVE_NOISE
    "  troupe-node --keygen /etc/troupe-node/node.key\n"
#endif
    ;

// --set words a command line takes: a robot's handful of changes, with room.
constexpr size_t kMaxSets = 32;

// Whether a numeric flag's value is one, min..max; false with the reason
// printed when it is not.
bool flag_number(const char* flag, const char* text, unsigned long min, unsigned long max) {
  char* end = nullptr;
  unsigned long out = strtoul(text, &end, 10);
  if (*text >= '0' && *text <= '9' && *end == '\0' && out >= min && out <= max) return true;
  fprintf(stderr, "troupe-node: bad %s '%s' (%lu to %lu)\n", flag, text, min, max);
  return false;
}

#ifdef TROUPE_HAVE_NOISE
// --keygen FILE: this node's key pair, FILE (the secret, mode 0600) and
// FILE.pub, named after this machine's host name (the .pub is what the
// desktop is given), printed as `troupe keygen` prints its pair. Refuses
// to overwrite either; false with `error`.
bool write_node_key(const std::string& path, std::string& error) {
  namespace noise = troupe::wire::noise;
  char host[256] = {};
  if (::gethostname(host, sizeof host - 1) != 0 || host[0] == '\0') {
    snprintf(host, sizeof host, "troupe-node");
  }
  noise::Key key;
  if (!noise::write_key_pair(path, host, error) || !noise::read_public_key(path + ".pub", key, error)) {
    return false;
  }
  printf("%s: secret key (readable by its owner only)\n%s.pub: public key %s\n", path.c_str(), path.c_str(),
         noise::key_hex(key).c_str());
  return true;
}
#endif

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
  const char* sets[kMaxSets] = {};
  size_t set_count = 0, print_config = 0, insecure = 0, keygen = 0;
  const troupe::Flag flags[] = {{"--set", sets, &set_count, kMaxSets},
                                {"--keygen", nullptr, &keygen},
                                {"--print-config", nullptr, &print_config},
                                {"--insecure", nullptr, &insecure},
                                {"--port", &port},
                                {"--listen", &listen},
                                {"--log-level", &level},
                                {"--max-clients", &max_clients},
                                {"--max-clients-per-address", &per_address},
                                {"--hello-timeout-ms", &hello_timeout},
                                {"--idle-timeout-ms", &idle_timeout}};
  const troupe::CommandLine line{"troupe-node", kUsage, flags, std::size(flags), &config_path};
  if (int rc = troupe::parse_command_line(line, argc, argv); rc >= 0) return rc;

  std::string error;
  // --keygen FILE: the word after it is the positional one. A robot board
  // has no `troupe` command, so its node makes its own key (the bundle's
  // postinst runs this). Where it has no secure sessions (the core: its
  // 64 KiB budget), the flag only says so, in as few bytes as it can.
  if (keygen != 0) {
#ifdef TROUPE_HAVE_NOISE
    if (argc != 3) {
      fprintf(stderr, "troupe-node: --keygen FILE takes no other argument\n%s", kUsage);
      return troupe::kExitUsage;
    }
    if (!write_node_key(config_path, error)) {
      troupe::log_error("%s", error.c_str());
      return 1;
    }
    return 0;
#else
    troupe::log_error("--keygen: board %s is built without secure sessions", troupe::kBoardName);
    return 1;
#endif
  }
  troupe::LoadedConfig cfg;
  if (!troupe::load_config(config_path, cfg, error)) {
    troupe::log_error("%s", error.c_str());
    return troupe::kExitConfig;
  }
  auto set = [&cfg, &error](const std::string& assignment) {
    if (troupe::set_config_value(cfg, assignment.c_str(), error)) return true;
    fprintf(stderr, "troupe-node: --set %s: %s\n", assignment.c_str(), error.c_str());
    return false;
  };
  for (size_t i = 0; i < set_count; ++i) {
    if (!set(sets[i])) return troupe::kExitUsage;
  }
  // The flags of node settings are --set of those settings, given last; they
  // change the config itself so that --print-config shows them too.
  troupe::LogLevel parsed{};
  if (level != nullptr) {
    if (!troupe::parse_log_level(level, parsed)) {
      fprintf(stderr, "troupe-node: bad log level '%s'\n%s", level, kUsage);
      return troupe::kExitUsage;
    }
    if (!set(std::string("log_level=") +
             troupe::config::EnumNameLogLevel(troupe::config::LogLevel(parsed)))) {
      return troupe::kExitUsage;
    }
  }
  // Their own checks first (--max-clients 0 is a mistake the schema allows).
  struct NumberFlag {
    const char* flag;
    const char* text;
    const char* key;
    unsigned long min, max;
  };
  const NumberFlag numbers[] = {{"--port", port, "port=", 0, 65535},
                                {"--max-clients", max_clients, "max_clients=", 1, 65535},
                                {"--max-clients-per-address", per_address, "max_clients_per_address=", 0, 65535},
                                {"--hello-timeout-ms", hello_timeout, "hello_timeout_ms=", 0, UINT32_MAX},
                                {"--idle-timeout-ms", idle_timeout, "idle_timeout_ms=", 0, UINT32_MAX}};
  for (const NumberFlag& f : numbers) {
    if (f.text != nullptr && (!flag_number(f.flag, f.text, f.min, f.max) || !set(std::string(f.key) + f.text))) {
      return troupe::kExitUsage;
    }
  }
  if (listen != nullptr && !set(std::string("listen=") + listen)) return troupe::kExitUsage;
  if (print_config != 0) {
    fputs(troupe::config_to_json(cfg).c_str(), stdout);
    return 0;
  }
  troupe::set_log_level(troupe::LogLevel(int(cfg.root->log_level())));
  troupe::Node::Options options = troupe::node_options(*cfg.root);

  const bool secure = cfg.root->key() != nullptr;
#ifdef TROUPE_HAVE_NOISE
  if (!troupe::secure_sessions(cfg, options, error)) {
    troupe::log_error("%s", error.c_str());
    return troupe::kExitConfig;
  }
  // Where secure sessions are built in, plain TCP beyond loopback must be
  // asked for. A board built without them can serve nothing else: it says
  // so every minute instead.
  if (!troupe::may_serve("troupe-node", options.listen, options.port, secure, insecure != 0, error)) {
    troupe::log_error("%s", error.c_str());
    return troupe::kExitUsage;
  }
#else
  if (cfg.root->key() != nullptr) {
    troupe::log_error("%s: \"key\": board %s is built without secure sessions (libsodium)", cfg.path.c_str(),
                      troupe::kBoardName);
    return troupe::kExitConfig;
  }
#endif

  troupe::Node node(options);
  troupe::SetupFailure failure = troupe::SetupFailure::Config;
  if (!troupe::build_node(node, cfg, error, &failure)) {
    troupe::log_error("%s", error.c_str());
    troupe::log_error(failure == troupe::SetupFailure::MissingDevice
                          ? "not starting: a device it drives is not there (the config is fine)"
                          : "not starting: the config must be fixed first");
    return failure == troupe::SetupFailure::MissingDevice ? troupe::kExitNotYet : troupe::kExitConfig;
  }
  if (!node.start(error)) {
    troupe::log_error("%s", error.c_str());
    return troupe::kExitNotYet;
  }
  troupe::StopOnSignal stop_on_signal(node.loop(), [&node] { node.stop(); });
  std::unique_ptr<troupe::PlainServiceWarning> plain_warning;
  if (!secure && !troupe::loopback_only(options.listen)) {
    plain_warning = std::make_unique<troupe::PlainServiceWarning>(node.loop(), "troupe-node on " + node.listen_text());
  }
  troupe::log_info("%s (board %s) serving %zu devices on %s", options.name.c_str(), troupe::kBoardName,
                   node.device_count(), node.listen_text().c_str());
  node.run();
  node.shutdown();
  troupe::log_info("stopped");
  return 0;
}
