// troupe-play (`troupe play`): serves a troupe log again as a node.
#include <signal.h>
#include <sys/epoll.h>

#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include "drivers/replay/replay_driver.h"
#include "runtime/clock.h"
#include "runtime/exposure.h"
#include "runtime/log.h"
#include "runtime/node.h"
#include "runtime/secure_file.h"
#include "runtime/stop_signals.h"
#include "wire/address.h"
#include "wire/cli/args.h"

namespace {

// After the last frame, the node serves this long more so that clients
// receive what is still queued for them, us.
constexpr uint64_t kDrainUs = 500000;

class StopWatch final : public troupe::FdHandler {
 public:
  StopWatch(troupe::Node& node, troupe::StopSignals& signals) : node_(node), signals_(signals) {
    if (signals_.fd() >= 0) node_.loop().watch(signals_.fd(), EPOLLIN, this);
  }
  void on_fd(int, uint32_t) override {
    if (const char* sig = signals_.take()) troupe::log_info("%s: stopping", sig);
    node_.stop();
  }

 private:
  troupe::Node& node_;
  troupe::StopSignals& signals_;
};

struct Recorded {
  troupe::wire::Address addr;
  std::string robot_name, driver;
};

std::vector<Recorded> recorded_devices(const troupe::record::LogSummary& summary) {
  std::vector<Recorded> out;
  if (summary.device_list.empty()) return out;
  const troupe::wire::DeviceList* list =
      troupe::wire::trusted_message(summary.device_list)->body_as_DeviceList();
  if (list->devices() == nullptr) return out;
  for (const troupe::wire::DeviceInfo* d : *list->devices()) {
    if (d->addr() == nullptr) continue;
    out.push_back(
        {*d->addr(), d->robot_name() ? d->robot_name()->str() : "", d->driver() ? d->driver()->str() : ""});
  }
  return out;
}

void print_info(const std::string& path, const troupe::record::LogSummary& s,
                const std::vector<Recorded>& devices, uint64_t max_gap_us) {
  printf("file      %s\n", path.c_str());
  printf("node      %s\n", s.node_name.c_str());
  printf("records   %llu (%llu data)\n", static_cast<unsigned long long>(s.records),
         static_cast<unsigned long long>(s.data_records));
  printf("duration  %.3f s\n", double(s.play_us) * 1e-6);
  if (s.jump_count > 0) {
    printf("jumps     %llu (pauses over %.0f s or steps back in the record times, not kept)\n",
           static_cast<unsigned long long>(s.jump_count), double(max_gap_us) * 1e-6);
  }
  for (const troupe::record::TimeJump& j : s.jumps) {
    const bool back = j.to_us < j.from_us;
    printf("jump      byte %llu: %.6f s to %.6f s (%s%.6f s)\n", static_cast<unsigned long long>(j.offset),
           double(j.from_us) * 1e-6, double(j.to_us) * 1e-6, back ? "-" : "+",
           double(back ? j.from_us - j.to_us : j.to_us - j.from_us) * 1e-6);
  }
  if (s.jump_count > s.jumps.size()) {
    printf("jump      ... and %llu more\n", static_cast<unsigned long long>(s.jump_count - s.jumps.size()));
  }
  for (const Recorded& d : devices) {
    printf("device    %s\t%s\n", troupe::wire::format_address(d.addr, d.robot_name).c_str(),
           d.driver.c_str());
  }
  printf("status    %s\n", s.problem.empty() ? "complete" : s.problem.c_str());
}

}  // namespace

int main(int argc, char** argv) {
  troupe::set_log_program("troupe-play");
  signal(SIGPIPE, SIG_IGN);
  troupe::drivers::replay::ReplayDriver::Options replay;
  troupe::Node::Options node_options;
  bool hold = false, info = false;
  double max_gap_s = double(replay.max_gap_us) * 1e-6;
  auto app = troupe::cli::make_app(
      "troupe play", {"troupe play FILE [--speed X] [--port P] [--listen ADDR] [--secure FILE] [--loop]\n"
                      "                        [--wait] [--hold] [--max-gap S]\n"
                      "       troupe play FILE --info [--max-gap S]",
                      "Serves a troupe log (made by `troupe record`) again as a node: the recorded\n"
                      "devices, with their data at the recorded pace and with the timestamps the\n"
                      "recorded node gave it. Clients connect to it as to the node that was\n"
                      "recorded. It ends after the last frame unless --loop or --hold. A truncated\n"
                      "or corrupt file is reported with the byte offset where it goes wrong, and\n"
                      "everything before that offset plays. Where the record times jump (back, or\n"
                      "forward by more than --max-gap) the pause is not kept: the jump is reported\n"
                      "with its byte offset and play goes on at once.\n",
                      {"troupe play run1.trl",
                       "troupe play run1.trl --speed 4 --port 7000 & troupe echo localhost:7000 ranger:0",
                       "troupe play laser.trl --loop --listen 0.0.0.0 --secure keys.json"}});
  app->add_option("FILE", replay.path, "the log to play")->required();
  app->add_option("--speed", replay.speed, "play X times as fast as recorded (default 1; 0.5: half speed)")
      ->type_name("X")
      ->check(troupe::cli::above(0));
  troupe::cli::add_port(*app, "--port", node_options.port,
                        "TCP port (default 6665; 0: any free port, printed)");
  app->add_option("--listen", node_options.listen,
                  "address to listen on (default localhost: 127.0.0.1 and ::1)")
      ->type_name("ADDR");
  std::string secure_file;
  auto* secure = app->add_option("--secure", secure_file, troupe::kSecureFlagHelp)->type_name("FILE");
  bool insecure = false;
  app->add_flag("--insecure", insecure,
                "allow --listen beyond loopback without --secure: any machine\n"
                "that reaches the port can read what was recorded (logged\n"
                "every minute)")
      ->excludes(secure);
  app->add_flag("--loop", replay.loop, "start over after the last frame");
  app->add_flag("--wait", replay.wait_for_readers, "hold the start until every recorded device has a reader");
  app->add_flag("--hold", hold, "keep serving after the last frame, until Ctrl-C");
  app->add_option("--max-gap", max_gap_s, "longest pause between two frames that is kept, s (default 60)")
      ->type_name("S")
      ->check(troupe::cli::above(0) & troupe::cli::at_most(1e9));
  app->add_flag("--info", info, "print what the file holds and exit");
  troupe::cli::add_log_level(*app);
  if (int rc = troupe::cli::parse(*app, argc, argv); rc >= 0) return rc;
  replay.max_gap_us = uint64_t(max_gap_s * 1e6);

  std::string error;
  troupe::SecureSessions sessions;
  if (!secure_file.empty() && !info && !troupe::load_secure_sessions(secure_file, sessions, error)) {
    std::fprintf(stderr, "troupe play: --secure %s\n", error.c_str());
    return 2;
  }
  sessions.apply(node_options);
  if (!info && !troupe::may_serve("troupe play", node_options.listen, node_options.port, sessions.on(),
                                  insecure, error)) {
    std::fprintf(stderr, "%s\n", error.c_str());
    return 2;
  }
  troupe::record::LogSummary summary;
  if (!troupe::record::summarize_log(replay.path, summary, error, replay.max_gap_us)) {
    troupe::log_error("%s", error.c_str());
    return 1;
  }
  std::vector<Recorded> devices = recorded_devices(summary);
  if (info) {
    print_info(replay.path, summary, devices, replay.max_gap_us);
    return 0;
  }
  if (!summary.problem.empty()) {
    troupe::log_warn("%s; playing the %llu data frames before it", summary.problem.c_str(),
                     static_cast<unsigned long long>(summary.data_records));
  }
  if (devices.empty()) {
    troupe::log_error("%s: no device list before byte %llu: nothing to serve", replay.path.c_str(),
                      static_cast<unsigned long long>(summary.valid_bytes));
    return 1;
  }

  node_options.name = summary.node_name.empty() ? "troupe-play" : summary.node_name + " (replay)";
  troupe::Node node(node_options);
  auto* driver = new troupe::drivers::replay::ReplayDriver(replay);
  std::vector<troupe::DeviceId> ids;
  for (const Recorded& d : devices) {
    troupe::DeviceId id =
        node.add_device(d.addr, driver, d.driver.empty() ? "replay" : d.driver + " (replay)", d.robot_name);
    if (id == troupe::kNoDevice) {
      troupe::log_error("%s: device %s is listed twice", replay.path.c_str(),
                        troupe::wire::format_address(d.addr, d.robot_name).c_str());
      delete driver;
      return 1;
    }
    ids.push_back(id);
  }
  troupe::DriverSetup setup;
  setup.name = "replay";
  setup.provides = ids;
  if (!node.add_driver(std::unique_ptr<troupe::Driver>(driver), setup, error)) {
    troupe::log_error("%s", error.c_str());
    return 1;
  }
  if (!node.start(error)) {
    troupe::log_error("%s", error.c_str());
    return 1;
  }
  troupe::StopSignals signals;
  StopWatch stop(node, signals);
  std::unique_ptr<troupe::PlainServiceWarning> plain_warning;
  if (sessions.on()) {
    troupe::log_info("secure sessions only; this player's key is %s", sessions.key_hex.c_str());
  } else if (!troupe::loopback_only(node_options.listen)) {
    plain_warning = std::make_unique<troupe::PlainServiceWarning>(node.loop(), "troupe play on " + node.listen_text());
  }
  troupe::log_info("playing %s (%llu frames of %zu devices, %.1f s) at speed %g on %s:%u",
                   replay.path.c_str(), static_cast<unsigned long long>(summary.data_records), devices.size(),
                   double(summary.play_us) * 1e-6, replay.speed, node_options.listen.c_str(),
                   unsigned(node.port()));
  uint64_t drain_until = 0;
  while (!node.loop().stopped()) {
    node.poll(100000);
    if (hold || !driver->finished()) continue;
    if (drain_until == 0) drain_until = troupe::monotonic_us() + kDrainUs;
    if (troupe::monotonic_us() >= drain_until) break;
  }
  troupe::log_info("played %llu frames", static_cast<unsigned long long>(driver->published()));
  node.shutdown();
  return 0;
}
