// The ROS 2 bridge under a swarm: N robots (default 100) each publishing a
// laser scan at 10 Hz and odometry at 20 Hz, served by a node of this
// program, bridged by one troupe-ros2 to a ROS 2 subscriber (Fast DDS) that
// takes every topic. Reported: troupe-ros2's CPU, against a troupe-node that
// only passes the same devices through (what the bridge costs on top), and
// the rates in and out. Medians over repeats.
//
//   bench_ros2_swarm [--robots N] [--beams B] [--seconds S] [--repeats R]
#include <atomic>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <string>
#include <thread>
#include <vector>

#include "ros2_msgsPubSubTypes.h"
#include "runtime/node.h"
#include "tests/bench/runtime/bench_util.h"
#include "tests/ros2/dds_env.h"
#include "tests/ros2/fastdds_peer.h"
#include "tests/support/child_process.h"
#include "wire/cli/args.h"
#include "wire/client/client.h"

namespace {

using namespace troupe;
namespace fdds = eprosima::fastdds::dds;
const std::string kBin = std::string(TROUPE_BINARY_DIR) + "/bin";

// N robots: odometry every 50 ms, a scan of `beams` every 100 ms.
class Swarm : public Driver {
 public:
  Swarm(int beams) : ranges_(size_t(beams)) {}
  bool setup(Node& node, const DriverSetup& setup, std::string&) override {
    devices_.assign(setup.provides.begin(), setup.provides.end());
    return node.loop().start_timer(50'000, 50'000, this) != 0;
  }
  void on_timer(TimerId) override {
    tick_++;
    for (DeviceId id : devices_) {
      const wire::Address& a = node_->address(id);
      auto& b = node_->begin();
      if (a.iface() == uint16_t(wire::Interface::Position2d)) {
        const wire::Pose2d pose(float(tick_) * 0.01f, float(a.robot()), 0), vel(0.2f, 0, 0);
        node_->publish(id, 1, wire::Body::Position2dState,
                       wire::CreatePosition2dState(b, &pose, &vel).Union());
      } else if (tick_ % 2 == 0) {
        for (size_t i = 0; i < ranges_.size(); ++i) ranges_[i] = uint16_t(1000 + (i * 37 + tick_) % 3000);
        auto body = wire::CreateRangerScan(b, b.CreateVector(ranges_), 0.001f, -1.57f,
                                           3.14f / float(ranges_.size() - 1), 8.0f);
        node_->publish(id, 1, wire::Body::RangerScan, body.Union());
      }
    }
  }
  void on_request(DeviceId id, const wire::Message& req, RequestToken token) override {
    auto& b = node_->begin();
    if (req.header()->subtype() == uint8_t(wire::RangerReqSub::Geometry)) {
      const wire::Pose3d pose(0.1f, 0, 0.2f, 0, 0, 0);
      return node_->ack(token, wire::Body::RangerGeometry, wire::CreateRangerGeometry(b, &pose).Union());
    }
    if (req.header()->subtype() == uint8_t(wire::RangerReqSub::GetConfig)) {
      auto body = wire::CreateRangerConfig(b, -1.57f, 1.57f, 0.0175f, 0.02f, 8.0f, 0.001f, 10.0f);
      return node_->ack(token, wire::Body::RangerConfig, body.Union());
    }
    Driver::on_request(id, req, token);
  }

 private:
  std::vector<DeviceId> devices_;
  std::vector<uint16_t> ranges_;
  uint64_t tick_ = 0;
};

// Counts what reaches the ROS 2 side.
class Counter : public fdds::DataReaderListener {
 public:
  void on_data_available(fdds::DataReader* reader) override {
    fdds::SampleInfo info;
    if (scans_) {
      sensor_msgs::msg::dds_::LaserScan_ s;
      while (reader->take_next_sample(&s, &info) == eprosima::fastrtps::types::ReturnCode_t::RETCODE_OK)
        count++;
    } else {
      nav_msgs::msg::dds_::Odometry_ o;
      while (reader->take_next_sample(&o, &info) == eprosima::fastrtps::types::ReturnCode_t::RETCODE_OK)
        count++;
    }
  }
  explicit Counter(bool scans) : scans_(scans) {}
  std::atomic<uint64_t> count{0};

 private:
  bool scans_;
};

// Samples the bridge took from its devices so far (its status device,
// opaque:1 of troupe-ros2's own node: passthrough's status is opaque:0).
uint64_t bridged_samples(client::Client& c) {
  const client::Reply r = c.request(wire::Address(0, uint16_t(wire::Interface::Opaque), 1), 1);
  const wire::OpaqueBytes* b = r.ok() ? r.message()->body_as_OpaqueBytes() : nullptr;
  if (b == nullptr || b->bytes() == nullptr) return 0;
  const std::string text(b->bytes()->begin(), b->bytes()->end());
  const size_t at = text.find("\"samples\":");
  return at == std::string::npos ? 0 : std::strtoull(text.c_str() + at + 10, nullptr, 10);
}

// CPU of `pid` over `seconds`, % of one core.
double cpu_percent(pid_t pid, double seconds) {
  const double c0 = bench::cpu_seconds(pid), t0 = bench::monotonic_seconds();
  std::this_thread::sleep_for(std::chrono::duration<double>(seconds));
  return 100.0 * (bench::cpu_seconds(pid) - c0) / (bench::monotonic_seconds() - t0);
}

}  // namespace

int main(int argc, char** argv) {
  int robots = 100, beams = 181, repeats = 3;
  double seconds = 10;
  auto app = troupe::cli::make_app(
      "bench_ros2_swarm", {"bench_ros2_swarm [--robots N] [--beams N] [--seconds S] [--repeats N]",
                           "troupe-ros2's CPU for a swarm (scans at 10 Hz, odometry at 20 Hz), against a\n"
                           "passthrough alone; medians over the repeats.\n",
                           {"bench_ros2_swarm --robots 50 --seconds 5"}});
  app->add_option("--robots", robots, "robots in the swarm (default 100)")
      ->type_name("N")
      ->check(troupe::cli::at_least(1));
  app->add_option("--beams", beams, "beams per scan (default 181)")
      ->type_name("N")
      ->check(troupe::cli::at_least(2));
  app->add_option("--seconds", seconds, "length of one run, s (default 10)")
      ->type_name("S")
      ->check(troupe::cli::above(0));
  app->add_option("--repeats", repeats, "runs (default 3)")->type_name("N")->check(troupe::cli::at_least(1));
  if (int rc = troupe::cli::parse(*app, argc, argv); rc >= 0) return rc;
  testing::ros2::DdsDomain domain;
  const std::string dir = testing::make_temp_dir("bench-ros2-swarm");
  if (domain.id() < 0 || dir.empty()) return 1;
  setenv("CYCLONEDDS_URI", testing::ros2::cyclone_loopback_config().c_str(), 1);

  // The swarm's node, in a thread of this program.
  Node::Options options;
  options.port = 0;
  options.max_pending_requests = 1024;
  Node node(options);
  auto swarm = std::make_unique<Swarm>(beams);
  std::vector<DeviceId> ids;
  std::string remote, local;
  for (int r = 0; r < robots; ++r) {
    const std::string name = "r" + std::to_string(r);
    for (auto iface : {wire::Interface::Position2d, wire::Interface::Ranger}) {
      ids.push_back(
          node.add_device(wire::Address(uint16_t(r), uint16_t(iface), 0), swarm.get(), "swarm", name));
      const std::string what = std::string(wire::interface_name(uint16_t(iface))) + ":0";
      remote += std::string(remote.empty() ? "" : ", ") + "\"" + name + "/" + what + "\"";
      local += std::string(local.empty() ? "" : ", ") + "\"" + std::to_string(r) + "/" + what + "\"";
    }
  }
  DriverSetup setup;
  setup.name = "swarm";
  setup.provides = ids;
  std::string error;
  if (!node.add_driver(std::move(swarm), setup, error) || !node.start(error)) {
    std::fprintf(stderr, "%s\n", error.c_str());
    return 1;
  }
  const uint16_t port = node.port();
  std::thread serving([&] { node.run(); });
  auto fail = [&](const std::string& why) {
    std::fprintf(stderr, "bench_ros2_swarm: %s\n", why.c_str());
    node.stop();
    serving.join();
    testing::remove_tree(dir);
    return 1;
  };

  // The baseline: a troupe-node passing the same devices through, no bridge.
  std::ofstream(dir + "/passthrough.json")
      << R"({ "name": "baseline", "port": 0, "drivers": [ { "driver_type": "passthrough", "driver": { "host": "127.0.0.1", "port": )"
      << port << ", \"remote\": [" << remote << "] }, \"provides\": [" << local << "] } ] }";

  testing::ros2::FastDdsPeer peer(domain.id());
  std::vector<std::unique_ptr<Counter>> counters;
  const std::string scan_type = peer.register_type<sensor_msgs::msg::dds_::LaserScan_PubSubType>();
  const std::string odom_type = peer.register_type<nav_msgs::msg::dds_::Odometry_PubSubType>();
  for (int r = 0; r < robots; ++r) {
    for (bool scans : {false, true}) {
      counters.push_back(std::make_unique<Counter>(scans));
      const std::string topic = "rt/r" + std::to_string(r) + (scans ? "/scan" : "/odom");
      fdds::DataReader* rd = peer.reader(topic, scans ? scan_type : odom_type, {!scans, false, 10});
      if (rd == nullptr) return fail("cannot subscribe to " + topic);
      rd->set_listener(counters.back().get());
    }
  }
  auto received = [&] {
    uint64_t n = 0;
    for (const auto& c : counters) n += c->count;
    return n;
  };

  std::vector<double> base_cpu, bridge_cpu, in_rate, out_rate;
  for (int rep = 0; rep < repeats; ++rep) {
    testing::ChildProcess baseline;
    if (!baseline.start_logged({kBin + "/troupe-node", dir + "/passthrough.json"}, dir + "/baseline.log",
                               error) ||
        !baseline.wait_for("connected to", true, 30000)) {
      return fail("the passthrough node did not connect: " + error + baseline.out());
    }
    std::this_thread::sleep_for(std::chrono::seconds(2));
    base_cpu.push_back(cpu_percent(baseline.pid(), seconds));
    baseline.stop();

    testing::ChildProcess bridge;
    if (!bridge.start_logged({kBin + "/troupe-ros2", "127.0.0.1:" + std::to_string(port), "--domain",
                              std::to_string(domain.id())},
                             dir + "/bridge.log", error) ||
        !bridge.wait_for("serving the bridged devices", true, 30000)) {
      return fail(error);
    }
    // Until every topic delivers.
    for (int waited = 0; waited < 60000; waited += 100) {
      size_t live = 0;
      for (const auto& c : counters) live += c->count > 0;
      if (live == counters.size()) break;
      std::this_thread::sleep_for(std::chrono::milliseconds(100));
    }
    // Its own node's port, for its status device (the log holds every
    // repeat's: the last line is this one's).
    const std::string log = bridge.out();
    const size_t at = log.rfind("serving the bridged devices on 127.0.0.1:");
    if (at == std::string::npos) return fail("troupe-ros2 did not say where it serves: " + log);
    client::Client status("127.0.0.1", uint16_t(std::atoi(log.c_str() + at + 41)));
    if (!status.connect(5000)) return fail("cannot reach troupe-ros2's node");
    const uint64_t n0 = received(), b0 = bridged_samples(status);
    const double t0 = bench::monotonic_seconds();
    bridge_cpu.push_back(cpu_percent(bridge.pid(), seconds));
    const double dt = bench::monotonic_seconds() - t0;
    out_rate.push_back(double(received() - n0) / dt);
    in_rate.push_back(double(bridged_samples(status) - b0) / dt);
    bridge.stop();
    for (auto& c : counters) c->count = 0;
  }
  node.stop();
  serving.join();

  auto med = [](std::vector<double> v) { return bench::percentile(v, 50); };
  std::printf(
      "%d robots: odometry at 20 Hz, scans of %d beams at 10 Hz (%d samples/s); %d x %.0f s, medians\n\n",
      robots, beams, robots * 30, repeats, seconds);
  std::printf(
      "| process | CPU, %% of one core | samples/s bridged | samples/s received over DDS "
      "|\n|---|---:|---:|---:|\n");
  std::printf("| troupe-node, passthrough only | %.1f | - | - |\n", med(base_cpu));
  std::printf("| troupe-ros2 (passthrough + bridge) | %.1f | %.0f | %.0f |\n", med(bridge_cpu), med(in_rate),
              med(out_rate));
  std::printf("| the bridge's share | %.1f | | |\n", med(bridge_cpu) - med(base_cpu));
  testing::remove_tree(dir);
  return 0;
}
