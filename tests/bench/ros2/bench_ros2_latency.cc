// What the ROS 2 bridge adds to a sample's way: a kinematic base in a real
// troupe-node publishes its odometry; a Troupe client reads it straight from
// that node, and a ROS 2 subscriber (Fast DDS, as rmw_fastrtps would)
// reads the same samples from troupe-ros2 (passthrough, then the bridge, then
// Cyclone DDS). Every latency is from the sample's stamp (the node's
// monotonic clock, the same clock here) to its arrival; "added" pairs the
// two arrivals of each sample. Medians over repeats.
//
//   bench_ros2_latency [--seconds S] [--repeats R] [--rate HZ]
#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <map>
#include <mutex>
#include <string>
#include <vector>

#include "ros2_msgsPubSubTypes.h"
#include "runtime/clock.h"
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

// Arrival times by stamp, us (monotonic), from any thread.
struct Arrivals {
  std::mutex mutex;
  std::map<uint64_t, uint64_t> at;
  void add(uint64_t stamp_us) {
    const uint64_t now = monotonic_us();
    std::lock_guard<std::mutex> lock(mutex);
    at.emplace(stamp_us, now);
  }
};

// Takes each odometry sample as Fast DDS delivers it.
class OdomListener : public fdds::DataReaderListener {
 public:
  explicit OdomListener(Arrivals& a) : arrivals_(a) {}
  void on_data_available(fdds::DataReader* reader) override {
    nav_msgs::msg::dds_::Odometry_ o;
    fdds::SampleInfo info;
    while (reader->take_next_sample(&o, &info) == eprosima::fastrtps::types::ReturnCode_t::RETCODE_OK) {
      if (info.valid_data) {
        arrivals_.add(uint64_t(o.header().stamp().sec()) * 1'000'000u + o.header().stamp().nanosec() / 1000u);
      }
    }
  }

 private:
  Arrivals& arrivals_;
};

struct Stats {
  double median = 0, p99 = 0;
};
Stats stats(std::vector<double> v) {
  Stats s;
  if (v.empty()) return s;
  s.median = bench::percentile(v, 50);
  s.p99 = bench::percentile(v, 99);
  return s;
}

}  // namespace

int main(int argc, char** argv) {
  double seconds = 10, rate = 100;
  int repeats = 3;
  auto app = troupe::cli::make_app(
      "bench_ros2_latency", {"bench_ros2_latency [--seconds S] [--repeats N] [--rate HZ]",
                             "What troupe-ros2 adds to a sample's way, against a Troupe client reading\n"
                             "the same samples; medians over the repeats.\n",
                             {"bench_ros2_latency --seconds 5 --repeats 3"}});
  app->add_option("--seconds", seconds, "length of one run, s (default 10)")
      ->type_name("S")
      ->check(troupe::cli::above(0));
  app->add_option("--repeats", repeats, "runs (default 3)")->type_name("N")->check(troupe::cli::at_least(1));
  app->add_option("--rate", rate, "the odometry's rate, Hz (default 100)")
      ->type_name("HZ")
      ->check(troupe::cli::above(0));
  if (int rc = troupe::cli::parse(*app, argc, argv); rc >= 0) return rc;
  testing::ros2::DdsDomain domain;
  const std::string dir = testing::make_temp_dir("bench-ros2-latency");
  if (domain.id() < 0 || dir.empty()) return 1;
  setenv("CYCLONEDDS_URI", testing::ros2::cyclone_loopback_config().c_str(), 1);

  // The device: a kinematic base publishing its odometry at `rate`.
  const uint16_t port = testing::free_port();
  std::ofstream(dir + "/base.json")
      << R"({ "name": "base", "drivers": [ { "driver_type": "kinematic", "driver": { "rate_hz": )" << rate
      << R"( }, "provides": ["position2d:0"] } ] })";
  testing::ChildProcess node, bridge;
  std::string error;
  if (!node.start_logged({kBin + "/troupe-node", dir + "/base.json", "--port", std::to_string(port)},
                         dir + "/node.log", error) ||
      !testing::wait_for_listener(port, 30) ||
      !bridge.start_logged({kBin + "/troupe-ros2", "127.0.0.1:" + std::to_string(port), "--domain",
                            std::to_string(domain.id()), "--time", "sim", "--log-level", "warn"},
                           dir + "/bridge.log", error)) {
    std::fprintf(stderr, "cannot start the programs: %s\n", error.c_str());
    return 1;
  }

  Arrivals via_client, via_dds;
  testing::ros2::FastDdsPeer peer(domain.id());
  OdomListener listener(via_dds);
  fdds::DataReader* reader = peer.reader(
      "rt/odom", peer.register_type<nav_msgs::msg::dds_::Odometry_PubSubType>(), {true, false, 100});
  if (reader == nullptr) return 1;
  reader->set_listener(&listener);
  client::Client c("127.0.0.1", port);
  const wire::Address base(0, uint16_t(wire::Interface::Position2d), 0);
  if (!c.connect(5000) || !c.open(base, wire::Access::Read)) return 1;
  c.add_data_handler([&](const wire::Message& m) { via_client.add(wire::time_us(*m.header())); });

  // Until both paths deliver.
  for (int i = 0; i < 600 && via_dds.at.empty(); ++i) c.spin_for(50);
  if (via_dds.at.empty()) {
    std::fprintf(stderr, "no odometry over DDS; bridge log:\n%s", bridge.out().c_str());
    return 1;
  }

  std::vector<double> client_med, client_p99, dds_med, dds_p99, added_med, added_p99;
  size_t pairs = 0;
  for (int r = 0; r < repeats; ++r) {
    {
      std::lock_guard<std::mutex> a(via_client.mutex), b(via_dds.mutex);
      via_client.at.clear();
      via_dds.at.clear();
    }
    c.spin_for(int(seconds * 1000));
    std::lock_guard<std::mutex> a(via_client.mutex), b(via_dds.mutex);
    std::vector<double> lc, ld, la;
    for (const auto& [stamp, t_client] : via_client.at) {
      auto it = via_dds.at.find(stamp);
      if (it == via_dds.at.end()) continue;
      lc.push_back(double(t_client - stamp));
      ld.push_back(double(it->second - stamp));
      la.push_back(double(it->second) - double(t_client));
    }
    pairs += lc.size();
    const Stats sc = stats(lc), sd = stats(ld), sa = stats(la);
    client_med.push_back(sc.median);
    client_p99.push_back(sc.p99);
    dds_med.push_back(sd.median);
    dds_p99.push_back(sd.p99);
    added_med.push_back(sa.median);
    added_p99.push_back(sa.p99);
  }
  auto med = [](std::vector<double> v) { return bench::percentile(v, 50); };
  std::printf("odometry at %.0f Hz, %d x %.0f s, %zu samples seen by both (medians of the repeats)\n\n", rate,
              repeats, seconds, pairs);
  std::printf("| path | median us | p99 us |\n|---|---:|---:|\n");
  std::printf("| troupe-node -> Troupe client | %.0f | %.0f |\n", med(client_med), med(client_p99));
  std::printf("| troupe-node -> troupe-ros2 -> ROS 2 subscriber (Fast DDS) | %.0f | %.0f |\n", med(dds_med),
              med(dds_p99));
  std::printf("| added by the bridge (same sample, paired) | %.0f | %.0f |\n", med(added_med),
              med(added_p99));
  bridge.stop();
  node.stop();
  testing::remove_tree(dir);
  return 0;
}
