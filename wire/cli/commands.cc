// troupe ls, echo, cmd, req.
#include <signal.h>

#include <cstdio>
#include <cstdlib>

#include "wire/address.h"
#include "wire/check.h"
#include "wire/cli/cli.h"
#include "wire/cli/verbs.h"
#include "wire/png.h"

namespace troupe::cli {
namespace {

volatile sig_atomic_t g_interrupted = 0;

void on_interrupt(int) { g_interrupted = 1; }

}  // namespace

int cmd_ls(const std::vector<std::string>& args) {
  std::string host;
  auto app = make_app("troupe ls", {"troupe ls HOST[:PORT]",
                                    "Lists the devices of a node or simulator, one per line: the address, a tab,\n"
                                    "the driver providing it.\n",
                                    {"troupe ls localhost", "troupe ls robot7.local:6670"}});
  add_host(*app, host);
  if (int rc = parse(*app, args); rc >= 0) return rc;
  auto c = connect(host);
  if (!c) return kExitFailure;
  std::vector<client::DeviceEntry> devices;
  if (!c->device_list(devices)) return fail(c->error());
  for (const client::DeviceEntry& d : devices) printf("%s\t%s\n", d.text().c_str(), d.driver.c_str());
  return 0;
}

int cmd_echo(const std::vector<std::string>& args) {
  struct {
    std::string host, addr;
    std::string png;
    long count = -1;
    bool json = false, pull = false, udp = false;
  } p;
  auto app =
      make_app("troupe echo",
               {"troupe echo HOST[:PORT] ADDR [--count N] [--json] [--pull] [--udp] [--png FILE]",
                "Prints a device's data as it arrives, one line per message, until N messages\n"
                "or Ctrl-C. Lines start with the sender's time (s) and the sample number.\n"
                "If the node goes away, echo waits and resumes when it is back.\n"
                "With --png (cameras), the camera is asked for PNG images and each image is\n"
                "also written to FILE (raw ones encoded here); N is then 1 unless given.\n",
                {"troupe echo localhost position2d:0 --count 5", "troupe echo localhost r3/ranger:1 --json",
                 "troupe echo localhost cam/camera:0 --png view.png"}});
  add_host(*app, p.host);
  add_device(*app, p.addr);
  app->add_option("--count", p.count, "stop after N messages")->type_name("N")->check(at_least(1));
  app->add_flag("--json", p.json, "the whole message as JSON");
  app->add_flag("--pull", p.pull, "ask for each sample (pull mode) instead of having them pushed");
  app->add_flag("--udp", p.udp, "receive data as UDP datagrams (latest wins)");
  app->add_option("--png", p.png, "write each camera image to FILE as PNG (the last one stays)")
      ->type_name("FILE");
  if (int rc = parse(*app, args); rc >= 0) return rc;
  const bool save = !p.png.empty();
  if (save && p.count < 0) p.count = 1;
  wire::HostPort hp;
  std::string error;
  if (!wire::parse_host(p.host, hp, error)) return fail(error);
  client::Client::Options options;
  options.name = "troupe-echo";
  options.udp_data = p.udp;
  if (!secure_options(hp, options)) return kExitFailure;
  client::Client c(hp.host, hp.port, options);
  if (!c.connect(3000)) return fail(c.error());
  wire::Address addr;
  if (!resolve(c, p.addr, addr)) return kExitFailure;
  if (save && addr.iface() != uint16_t(wire::Interface::Camera)) {
    return fail("--png saves camera images; " + p.addr + " is a " +
                std::string(wire::interface_name(addr.iface())) + " device");
  }
  long printed = 0;
  std::string save_error;
  c.add_data_handler([&](const wire::Message& msg) {
    if (!(msg.header()->addr() == addr) || (p.count > 0 && printed >= p.count) || !save_error.empty()) return;
    if (save && msg.body_as_CameraImage() != nullptr &&
        !wire::save_png(*msg.body_as_CameraImage(), p.png, save_error)) {
      return;
    }
    std::string line = p.json ? to_json(msg) : summary(msg);
    printf("%s\n", line.c_str());
    fflush(stdout);
    ++printed;
  });
  wire::Delivery delivery = p.pull ? wire::Delivery::Pull : wire::Delivery::Push;
  const auto compression = save ? wire::ImageCompression::Png : wire::ImageCompression::None;
  if (!c.open(addr, wire::Access::Read, delivery, compression)) return fail(c.error());
  signal(SIGINT, on_interrupt);
  signal(SIGTERM, on_interrupt);
  bool was_connected = true;
  while (!g_interrupted && (p.count < 0 || printed < p.count) && save_error.empty()) {
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
  if (!save_error.empty()) return fail(save_error);
  return 0;
}

int cmd_send(const std::vector<std::string>& args, wire::Kind kind) {
  const bool is_cmd = kind == wire::Kind::Command;
  const char* name = is_cmd ? "cmd" : "req";
  struct {
    std::string host, addr, verb;
    std::vector<std::string> verb_args;
    bool json = false;
  } p;
  std::string about = is_cmd ? "Sends a command (no reply).\n"
                             : "Sends a request and prints the reply (\"ok\" when it has no body).\n";
  about += "\nverbs by interface:\n";
  for (uint16_t i = 1; i <= uint16_t(wire::Interface::MAX); ++i) {
    std::string verbs = verb_list(wire::Interface(i), kind);
    if (!verbs.empty()) about += std::string(wire::interface_name(i)) + ":\n" + verbs;
  }
  auto app = make_app(std::string("troupe ") + name,
                      is_cmd ? Help{"troupe cmd HOST[:PORT] ADDR VERB [ARGS...]",
                                    about,
                                    {"troupe cmd localhost position2d:0 vel 0.3 0 0.2",
                                     "troupe cmd localhost r2/position2d:0 goto 1 2 0"}}
                             : Help{"troupe req HOST[:PORT] ADDR VERB [ARGS...] [--json]",
                                    about,
                                    {"troupe req localhost position2d:0 geometry",
                                     "troupe req localhost simulation:0 step 10"}});
  add_host(*app, p.host);
  add_device(*app, p.addr);
  app->add_option("VERB", p.verb, "what to send")->required();
  app->add_option("ARGS", p.verb_args, "the verb's arguments");
  if (!is_cmd) app->add_flag("--json", p.json, "the reply's body as JSON");
  if (int rc = parse(*app, args); rc >= 0) return rc;
  // Check the verb before connecting: a typo should not need a node.
  wire::DeviceSpec spec;
  std::string error;
  if (!wire::parse_device(p.addr, spec, error)) return usage_error(name, error);
  const Verb* verb = find_verb(spec.iface, kind, p.verb);
  if (verb == nullptr) {
    std::string verbs = verb_list(spec.iface, kind, /*names_only=*/true);
    return usage_error(name, "'" + p.verb + "' is not a " + name + " of " +
                                 std::string(wire::interface_name(uint16_t(spec.iface))) +
                                 (verbs.empty() ? " (it has none)" : " (it has: " + verbs + ")"));
  }
  const std::vector<std::string>& verb_args = p.verb_args;
  if (verb_args.size() < verb->min_args || verb_args.size() > verb->max_args) {
    return usage_error(name, std::string(verb->name) + " takes " + (*verb->args ? verb->args : "no arguments") +
                                 " (" + verb->help + ")");
  }
  // The message is built and checked as the node will check it (wire/check.h)
  // before connecting: a value out of its range needs no node to be refused.
  Built built;
  wire::MessageWriter scratch;
  if (!verb->build(scratch.start(), verb_args, built, error)) return usage_error(name, error);
  wire::Refusal why;
  const wire::Address unresolved(0, uint16_t(spec.iface), spec.index);
  if (!wire::check_message(*wire::trusted_message(scratch.finish(
                               wire::make_header(unresolved, kind, verb->subtype, 0, 0), built.type, built.body)),
                           why)) {
    return usage_error(name, std::string(verb->name) + ": " + why.text);
  }
  auto c = connect(p.host);
  if (!c) return kExitFailure;
  wire::Address addr;
  if (!resolve(*c, p.addr, addr)) return kExitFailure;
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
