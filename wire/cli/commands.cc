// troupe ls, echo, cmd, req.
#include <signal.h>

#include <cstdio>
#include <cstdlib>

#include "wire/address.h"
#include "wire/cli/cli.h"
#include "wire/cli/verbs.h"

namespace troupe::cli {
namespace {

volatile sig_atomic_t g_interrupted = 0;

void on_interrupt(int) { g_interrupted = 1; }

// Splits "--flag value" options from positional words.
struct Parsed {
  std::vector<std::string> words;
  long count = -1;
  bool json = false;
  bool pull = false;
  bool udp = false;
};

bool parse(std::string_view command, const std::vector<std::string>& args, Parsed& out, int& rc) {
  for (size_t i = 0; i < args.size(); ++i) {
    const std::string& a = args[i];
    if (a == "--json") {
      out.json = true;
    } else if (a == "--pull") {
      out.pull = true;
    } else if (a == "--udp") {
      out.udp = true;
    } else if (a == "--count") {
      char* end = nullptr;
      if (i + 1 >= args.size() || (out.count = strtol(args[i + 1].c_str(), &end, 10), *end != '\0') ||
          out.count < 1) {
        rc = usage_error(command, "--count needs a number of messages (at least 1)");
        return false;
      }
      ++i;
    } else if (a.size() > 1 && a[0] == '-' && !(a[1] >= '0' && a[1] <= '9') && a[1] != '.') {
      rc = usage_error(command, "unknown option '" + a + "'");
      return false;
    } else {
      out.words.push_back(a);
    }
  }
  return true;
}

}  // namespace

int cmd_ls(const std::vector<std::string>& args) {
  if (args.size() != 1) return usage_error("ls", "want exactly one HOST");
  auto c = connect(args[0]);
  if (!c) return kExitFailure;
  std::vector<client::DeviceEntry> devices;
  if (!c->device_list(devices)) return fail(c->error());
  for (const client::DeviceEntry& d : devices) printf("%s\t%s\n", d.text().c_str(), d.driver.c_str());
  return 0;
}

int cmd_echo(const std::vector<std::string>& args) {
  Parsed p;
  int rc = 0;
  if (!parse("echo", args, p, rc)) return rc;
  if (p.words.size() != 2) return usage_error("echo", "want HOST and ADDR");
  wire::HostPort hp;
  std::string error;
  if (!wire::parse_host(p.words[0], hp, error)) return fail(error);
  client::Client::Options options;
  options.name = "troupe-echo";
  options.udp_data = p.udp;
  client::Client c(hp.host, hp.port, options);
  if (!c.connect(3000)) return fail(c.error());
  wire::Address addr;
  if (!resolve(c, p.words[1], addr)) return kExitFailure;
  long printed = 0;
  c.add_data_handler([&](const wire::Message& msg) {
    if (!(msg.header()->addr() == addr) || (p.count > 0 && printed >= p.count)) return;
    std::string line = p.json ? to_json(msg) : summary(msg);
    printf("%s\n", line.c_str());
    fflush(stdout);
    ++printed;
  });
  wire::Delivery delivery = p.pull ? wire::Delivery::Pull : wire::Delivery::Push;
  if (!c.open(addr, wire::Access::Read, delivery)) return fail(c.error());
  signal(SIGINT, on_interrupt);
  signal(SIGTERM, on_interrupt);
  bool was_connected = true;
  while (!g_interrupted && (p.count < 0 || printed < p.count)) {
    if (p.pull && c.connected()) {
      c.pull(addr);
      c.spin_for(100);
    } else {
      c.spin_once(200);
    }
    // A lost node is waited for (the client reconnects and re-opens).
    if (was_connected != c.connected()) {
      fprintf(stderr, "troupe: %s\n", c.connected() ? "reconnected" : c.error().c_str());
      was_connected = c.connected();
    }
  }
  return 0;
}

int cmd_send(const std::vector<std::string>& args, wire::Kind kind) {
  const char* name = kind == wire::Kind::Command ? "cmd" : "req";
  Parsed p;
  int rc = 0;
  if (!parse(name, args, p, rc)) return rc;
  if (p.words.size() < 3) return usage_error(name, "want HOST ADDR VERB [ARGS]");
  // Check the verb before connecting: a typo should not need a node.
  wire::DeviceSpec spec;
  std::string error;
  if (!wire::parse_device(p.words[1], spec, error)) return usage_error(name, error);
  const Verb* verb = find_verb(spec.iface, kind, p.words[2]);
  if (verb == nullptr) {
    std::string verbs = verb_list(spec.iface, kind, /*names_only=*/true);
    return usage_error(name, "'" + p.words[2] + "' is not a " + name + " of " +
                                 std::string(wire::interface_name(uint16_t(spec.iface))) +
                                 (verbs.empty() ? " (it has none)" : " (it has: " + verbs + ")"));
  }
  std::vector<std::string> verb_args(p.words.begin() + 3, p.words.end());
  if (verb_args.size() < verb->min_args || verb_args.size() > verb->max_args) {
    return usage_error(name, std::string(verb->name) + " takes " + (*verb->args ? verb->args : "no arguments") +
                                 " (" + verb->help + ")");
  }
  auto c = connect(p.words[0]);
  if (!c) return kExitFailure;
  wire::Address addr;
  if (!resolve(*c, p.words[1], addr)) return kExitFailure;
  Built built;
  if (!verb->build(c->begin(), verb_args, built, error)) return usage_error(name, error);
  if (kind == wire::Kind::Command) {
    if (!c->command(addr, verb->subtype, built.type, built.body)) return fail(c->error());
    // Commands have no reply, but a refusal (denied, unknown body) comes as a
    // Nack before the answer to a round trip sent after the command.
    if (!c->sync()) return fail(c->error());
    if (!c->error().empty()) return fail(wire::format_address(addr) + ": " + c->error());
    return 0;
  }
  client::Reply reply = c->request(addr, verb->subtype, built.type, built.body, 5000);
  if (!reply.ok()) return fail(wire::format_address(addr) + " " + verb->name + ": " + reply.text);
  const wire::Message* msg = reply.message();
  printf("%s\n", msg->body_type() == wire::Body::NONE ? "ok" : (p.json ? body_json(*msg) : summary(*msg)).c_str());
  return 0;
}

}  // namespace troupe::cli
