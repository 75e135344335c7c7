// troupe-ros2: every device of a node or simulator on ROS 2, in one command
// (`troupe ros2 HOST[:PORT]`). It reads HOST's device list, then runs a
// desktop node of two drivers: passthrough (the remote's devices, served
// here) and ros2 (those devices on DDS), as a node config would list them;
// --print-config prints that config for troupe-node.
#include <netdb.h>
#include <signal.h>
#include <sys/socket.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <set>
#include <string>
#include <vector>

#include "drivers/ros2/names.h"
#include "runtime/log.h"
#include "runtime/node_config.h"
#include "runtime/stop_signals.h"
#include "wire/address.h"
#include "wire/cli/args.h"
#include "wire/client/client.h"
#include "wire/noise/client_keys.h"
#include "wire/noise/key_file.h"
#include "wire/noise/noise_transport.h"

namespace {

// Interfaces the ros2 driver has a ROS 2 message for.
bool bridgeable(uint16_t iface) {
  using I = troupe::wire::Interface;
  switch (I(iface)) {
    case I::Position2d:
    case I::Ranger:
    case I::Power:
    case I::Imu:
    case I::Bumper:
    case I::Localize:
    case I::Map:
    case I::Simulation:
      return true;
    default:
      return false;
  }
}

// passthrough takes numeric addresses only (a name would need DNS inside
// the node's loop): resolve here, before the loop runs.
bool numeric_host(const std::string& host, std::string& out, std::string& error) {
  if (host == "localhost") {
    out = host;
    return true;
  }
  addrinfo hints{};
  hints.ai_socktype = SOCK_STREAM;
  addrinfo* res = nullptr;
  const int rc = getaddrinfo(host.c_str(), nullptr, &hints, &res);
  if (rc != 0 || res == nullptr) {
    error = "cannot resolve " + host + ": " + gai_strerror(rc);
    return false;
  }
  char text[NI_MAXHOST];
  getnameinfo(res->ai_addr, res->ai_addrlen, text, sizeof text, nullptr, 0, NI_NUMERICHOST);
  freeaddrinfo(res);
  out = text;
  return true;
}

std::string quoted(const std::string& s) {
  return "\"" + s + "\"";
}

std::string json_list(const std::vector<std::string>& items) {
  std::string out = "[";
  for (size_t i = 0; i < items.size(); ++i) out += (i ? ", " : "") + quoted(items[i]);
  return out + "]";
}

struct Settings {
  std::string host;
  uint16_t port = troupe::wire::kDefaultPort;
  int domain = -1;
  std::string node_name = "troupe_bridge";
  double max_linear = 1.5, max_angular = 3.0;
  std::string time = "Auto";  // ros2.fbs TimeSource
  uint16_t local_port = 0;
  /// A secure remote: our secret key file (absolute) and the remote's key
  /// as 64 hex digits, as passthrough's options take them; empty: plain.
  std::string identity, node_key_hex;
};

// The node config: passthrough of every bridgeable device, and ros2 using them.
std::string make_config(const Settings& s, const std::string& host,
                        const std::vector<troupe::client::DeviceEntry>& devices, size_t& bridged) {
  std::vector<std::string> remote, local, namespaces;
  uint16_t free_opaque = 0;
  for (const auto& d : devices) {
    if (d.addr.iface() == uint16_t(troupe::wire::Interface::Opaque)) {
      free_opaque = std::max<uint16_t>(free_opaque, uint16_t(d.addr.index() + 1));
    }
  }
  for (const auto& d : devices) {
    if (!bridgeable(d.addr.iface())) continue;
    const std::string where =
        std::string(troupe::wire::interface_name(d.addr.iface())) + ":" + std::to_string(d.addr.index());
    const bool named = troupe::drivers::ros2::valid_ros_token(d.robot_name);
    const std::string robot = std::to_string(d.addr.robot());
    // Robot names (troupe-sim's r0) are looked up again at each connection.
    remote.push_back((named ? d.robot_name : robot) + "/" + where);
    local.push_back(robot + "/" + where);
    namespaces.push_back(named ? d.robot_name : d.addr.robot() == 0 ? "" : "robot" + robot);
  }
  bridged = local.size();
  std::vector<std::string> provides = local;
  provides.push_back("opaque:" + std::to_string(free_opaque));
  char limits[160];
  std::snprintf(limits, sizeof limits,
                "\"domain_id\": %d, \"max_linear\": %g, \"max_angular\": %g, \"time\": \"%s\"", s.domain,
                s.max_linear, s.max_angular, s.time.c_str());
  return "{\n  \"name\": \"troupe-ros2\",\n  \"listen\": \"127.0.0.1\",\n  \"port\": " +
         std::to_string(s.local_port) +
         ",\n  \"drivers\": [\n    {\n      \"name\": \"remote\",\n      \"driver_type\": \"passthrough\",\n"
         "      \"driver\": { \"host\": " +
         quoted(host) + ", \"port\": " + std::to_string(s.port) + ", \"remote\": " + json_list(remote) +
         (s.identity.empty()
              ? std::string()
              : ", \"identity\": " + quoted(s.identity) + ", \"node_key\": " + quoted(s.node_key_hex)) +
         " },\n      \"provides\": " + json_list(provides) +
         "\n    },\n    {\n      \"name\": \"ros2\",\n      \"driver_type\": \"ros2\",\n      \"driver\": "
         "{ " +
         limits + ", \"node_name\": " + quoted(s.node_name) + ", \"namespaces\": " + json_list(namespaces) +
         " },\n      \"uses\": " + json_list(local) +
         ",\n      \"provides\": [\"opaque:" + std::to_string(free_opaque + 1) + "\"]\n    }\n  ]\n}\n";
}

}  // namespace

int main(int argc, char** argv) {
  troupe::set_log_program("troupe-ros2");
  signal(SIGPIPE, SIG_IGN);
  Settings s;
  std::string target;
  bool print_config = false;
  std::string time = "auto";
  auto app = troupe::cli::make_app(
      "troupe-ros2",
      {"troupe-ros2 HOST[:PORT] [options]",
       "Publishes every device of the node or simulator at HOST[:PORT] (default port\n"
       "6665) as ROS 2 topics over DDS (Cyclone DDS; no ROS installation needed), one\n"
       "namespace per robot (/r0/odom, /r0/scan, ...), and takes cmd_vel and\n"
       "initialpose back. ROS 2 tools see it as the node /troupe_bridge.\n"
       "\n"
       "DDS discovery uses multicast; where there is none (a loopback-only host),\n"
       "name the peers in CYCLONEDDS_URI (see drivers/ros2/README.md).\n",
       {"troupe ros2 localhost                       # e.g. troupe-sim examples/worlds/swarm100.world",
        "troupe ros2 192.168.1.20:6665 --domain 7",
        "troupe ros2 192.168.1.20 --identity laptop --node-key robot7.pub",
        "troupe ros2 localhost --print-config > bridge.json    # then: troupe-node bridge.json"}});
  app->add_option("HOST", target, "HOST[:PORT]")->required();
  app->add_option("--domain", s.domain, "DDS domain (default: ROS_DOMAIN_ID, else 0)")
      ->type_name("N")
      ->check(troupe::cli::between(0, 232));
  app->add_option("--node-name", s.node_name, "the ROS 2 node name (default troupe_bridge)")
      ->type_name("NAME")
      ->check(CLI::Validator(
          [](std::string& name) -> std::string {
            return troupe::drivers::ros2::valid_ros_token(name) ? "" : "'" + name + "' is no ROS 2 name";
          },
          "", "ros name"));
  app->add_option("--max-linear", s.max_linear, "cmd_vel speed limit, m/s (default 1.5)")
      ->type_name("V")
      ->check(troupe::cli::between(0, 1e3));
  app->add_option("--max-angular", s.max_angular, "cmd_vel turn rate limit, rad/s (default 3.0)")
      ->type_name("W")
      ->check(troupe::cli::between(0, 1e3));
  app->add_option("--time", time,
                  "the ROS clock of the stamps (default auto: simulated\n"
                  "time when HOST is a simulator; sim keeps the devices' stamps)")
      ->type_name("auto|sim|wall")
      ->check(CLI::IsMember({"auto", "sim", "wall"}));
  troupe::cli::add_port(*app, "--port", s.local_port,
                        "this node's own Troupe port (default 0: any free port)");
  troupe::wire::noise::ClientKeys keys;
  troupe::cli::add_secure_session(*app, keys);
  troupe::cli::add_log_level(*app);
  app->add_flag("--print-config", print_config, "print the node config (for troupe-node) and exit");
  if (int rc = troupe::cli::parse(*app, argc, argv); rc >= 0) return rc;
  s.time = time == "auto" ? "Auto" : time == "sim" ? "Sim" : "Wall";  // ros2.fbs TimeSource
  troupe::wire::HostPort hp;
  std::string error, host;
  if (!troupe::wire::parse_host(target, hp, error) || !numeric_host(hp.host, host, error)) {
    return troupe::cli::usage_error(*app, error);
  }
  s.host = hp.host;
  s.port = hp.port;
  // A secure remote: the keys are read here, once, for the device list and
  // for the passthrough (which gets them as an absolute path and hex digits,
  // so a printed config works from any folder).
  std::shared_ptr<troupe::wire::Transport> transport;
  if (keys.secure()) {
    troupe::wire::noise::SecureOptions secure;
    if (!troupe::wire::noise::client_options(keys, hp.host, hp.port, secure, error)) {
      troupe::log_error("%s", error.c_str());
      return 1;
    }
    s.identity = std::filesystem::absolute(keys.identity).lexically_normal().string();
    s.node_key_hex = troupe::wire::noise::key_hex(secure.peer_key);
    transport = std::make_shared<troupe::wire::noise::NoiseTransport>(std::move(secure));
  }

  // Signals are taken by the node's loop (StopOnSignal); DDS starts threads of
  // its own, which must not take them either: block them before any starts.
  sigset_t stop_set;
  sigemptyset(&stop_set);
  sigaddset(&stop_set, SIGINT);
  sigaddset(&stop_set, SIGTERM);
  pthread_sigmask(SIG_BLOCK, &stop_set, nullptr);

  // The remote's devices, once it answers.
  std::vector<troupe::client::DeviceEntry> devices;
  {
    troupe::client::Client::Options co;
    co.name = "troupe-ros2";
    co.reconnect = false;
    co.transport = transport;
    bool waiting_said = false;
    while (true) {
      troupe::client::Client client(host, s.port, co);
      if (client.connect(2000) && client.device_list(devices)) break;
      // A config is printed for a node that is there now: a one-shot
      // command that waited for ever would look hung.
      if (print_config) {
        troupe::log_error("cannot read the devices of %s:%u: %s", host.c_str(), s.port, client.error().c_str());
        return 1;
      }
      if (!waiting_said)
        troupe::log_info("waiting for %s:%u (%s)", host.c_str(), s.port, client.error().c_str());
      waiting_said = true;
      timespec pending{1, 0};
      siginfo_t info;
      if (sigtimedwait(&stop_set, &info, &pending) > 0) return 0;
    }
  }
  size_t bridged = 0;
  const std::string config = make_config(s, host, devices, bridged);
  if (print_config) {
    std::fputs(config.c_str(), stdout);
    return 0;
  }
  std::set<std::string> skipped;
  for (const auto& d : devices) {
    if (!bridgeable(d.addr.iface()))
      skipped.insert(std::string(troupe::wire::interface_name(d.addr.iface())));
  }
  if (bridged == 0) {
    troupe::log_error("%s:%u serves no device the bridge has a ROS 2 message for", host.c_str(), s.port);
    return 1;
  }
  std::string skipped_text;
  for (const auto& k : skipped) skipped_text += (skipped_text.empty() ? "" : ", ") + k;
  troupe::log_info("bridging %zu of %zu devices of %s:%u%s%s", bridged, devices.size(), host.c_str(), s.port,
                   skipped.empty() ? "" : "; no ROS 2 message for: ", skipped_text.c_str());

  troupe::LoadedConfig cfg;
  cfg.path = "troupe-ros2 " + target;
  if (!troupe::parse_config_json(config, cfg.path, cfg.bytes, error)) {
    troupe::log_error("%s", error.c_str());
    return 1;
  }
  cfg.root = troupe::config::GetNodeConfig(cfg.bytes.data());
  troupe::Node node(troupe::node_options(*cfg.root));
  if (!troupe::build_node(node, cfg, error) || !node.start(error)) {
    troupe::log_error("%s", error.c_str());
    return 1;
  }
  troupe::StopOnSignal stop_on_signal(node.loop(), [&node] { node.stop(); });
  troupe::log_info("serving the bridged devices on 127.0.0.1:%u", unsigned(node.port()));
  node.run();
  node.shutdown();
  troupe::log_info("stopped");
  return 0;
}
