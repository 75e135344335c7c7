#include "tests/bench/runtime/kinematic_node.h"

#include <cstdio>
#include <memory>

#include "drivers/kinematic/kinematic.h"
#include "runtime/node.h"
#include "tests/bench/runtime/bench_util.h"
#include "wire/writer.h"

namespace troupe::bench {

void serve_kinematic_node(const std::function<void(uint16_t)>& report) {
  serve_kinematic_node_through(report, {});
}

void serve_kinematic_node_through(const std::function<void(uint16_t)>& report,
                                  const std::function<std::unique_ptr<wire::Transport>()>& make_transport) {
  Node::Options o;
  o.port = 0;
  o.make_transport = make_transport;
  Node node(o);
  auto* driver = new drivers::kinematic::Kinematic;
  DeviceId ids[1] = {node.add_device(kBenchBase, driver, "kinematic")};
  DriverSetup setup;
  setup.provides = ids;
  std::string error;
  if (!node.add_driver(std::unique_ptr<Driver>(driver), setup, error) || !node.start(error)) {
    std::fprintf(stderr, "benchmark node: %s\n", error.c_str());
    report(0);
    return;
  }
  report(node.port());
  node.run();
}

std::vector<uint8_t> request_frame(uint32_t seq) {
  wire::MessageWriter w;
  auto f = w.empty(wire::make_header(kBenchBase, wire::Kind::Request,
                                     uint8_t(wire::Position2dReqSub::ResetOdometry), seq, 0));
  return {f.begin(), f.end()};
}

std::vector<double> blocking_round_trips(int fd, int count) {
  std::vector<double> out;
  std::vector<uint8_t> reply;
  for (int i = 0; i < count; ++i) {
    auto frame = request_frame(uint32_t(i + 1));
    const double t0 = monotonic_seconds();
    write_all(fd, frame);
    // Nothing is opened, so the node's reply is the first frame back (and an
    // echo's is the frame itself).
    read_frame(fd, reply);
    out.push_back((monotonic_seconds() - t0) * 1e6);
  }
  return out;
}

}  // namespace troupe::bench
