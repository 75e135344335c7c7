// What a passthrough hop costs: request round trips to a kinematic robot
// node, straight and through one and two passthroughs, all real troupe-node
// processes on loopback. Medians over repeats, as ratios to the straight
// path measured in the same run.
//
//   bench_passthrough [--requests N] [--repeats R]
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <fstream>
#include <string>
#include <vector>

#include "tests/support/child_process.h"
#include "wire/cli/args.h"
#include "wire/client/client.h"

using namespace troupe;

namespace {

const std::string kNode = std::string(TROUPE_BINARY_DIR) + "/bin/troupe-node";

bool start(testing::ChildProcess& p, const std::string& dir, const std::string& name, const std::string& json,
           uint16_t port) {
  std::string path = dir + "/" + name + ".json";
  std::ofstream(path) << json;
  std::string error;
  if (!p.start_logged({kNode, path, "--port", std::to_string(port), "--log-level", "warn"},
                      dir + "/" + name + ".log", error)) {
    std::fprintf(stderr, "%s\n", error.c_str());
    return false;
  }
  return testing::wait_for_listener(port, 30);
}

std::string passthrough(uint16_t port, int index_from, int index_to) {
  return R"({ "name": "hop", "drivers": [ { "driver_type": "passthrough", "driver": { "host": "127.0.0.1", "port": )" +
         std::to_string(port) + R"(, "remote": ["position2d:)" + std::to_string(index_from) +
         R"("] }, "provides": ["position2d:)" + std::to_string(index_to) + R"("] } ] })";
}

// Median round trip of `n` Geometry requests, us; 0 on failure.
double round_trip_us(uint16_t port, uint16_t index, int n) {
  client::Client c("127.0.0.1", port);
  if (!c.connect(5000)) return 0;
  wire::Address a(0, uint16_t(wire::Interface::Position2d), index);
  // The passthroughs connect on their own schedule: wait for the first Ack.
  for (int i = 0; i < 500 && !c.request(a, uint8_t(wire::Position2dReqSub::Geometry)).ok(); ++i)
    c.spin_for(20);
  std::vector<double> t;
  for (int i = 0; i < n; ++i) {
    auto t0 = std::chrono::steady_clock::now();
    if (!c.request(a, uint8_t(wire::Position2dReqSub::Geometry)).ok()) return 0;
    t.push_back(std::chrono::duration<double, std::micro>(std::chrono::steady_clock::now() - t0).count());
  }
  std::nth_element(t.begin(), t.begin() + long(t.size() / 2), t.end());
  return t[t.size() / 2];
}

}  // namespace

int main(int argc, char** argv) {
  int requests = 2000, repeats = 5;
  auto app = troupe::cli::make_app("bench_passthrough",
                                   {"bench_passthrough [--requests N] [--repeats R]",
                                    "Request round trips straight to a troupe-node and through one and two\n"
                                    "passthrough hops (real processes); medians.\n",
                                    {"bench_passthrough --requests 500 --repeats 3"}});
  app->add_option("--requests", requests, "requests per run (default 2000)")
      ->type_name("N")
      ->check(troupe::cli::at_least(10));
  app->add_option("--repeats", repeats, "runs per row; the median is reported (default 5)")
      ->type_name("R")
      ->check(troupe::cli::at_least(1));
  if (int rc = troupe::cli::parse(*app, argc, argv); rc >= 0) return rc;
  std::string dir = testing::make_temp_dir("bench-passthrough-");
  if (dir.empty()) return 1;
  testing::ChildProcess robot, hop1, hop2;
  uint16_t p0 = testing::free_port(), p1 = testing::free_port(), p2 = testing::free_port();
  bool ok =
      start(
          robot, dir, "robot",
          R"({ "name": "robot", "drivers": [ { "driver_type": "kinematic", "provides": ["position2d:0"] } ] })",
          p0) &&
      start(hop1, dir, "hop1", passthrough(p0, 0, 1), p1) &&
      start(hop2, dir, "hop2", passthrough(p1, 1, 2), p2);
  if (!ok) {
    std::fprintf(stderr, "bench_passthrough: a node did not start (logs in %s)\n", dir.c_str());
    return 1;
  }
  struct Path {
    const char* name;
    uint16_t port, index;
    std::vector<double> medians;
  } paths[] = {
      {"straight to the robot", p0, 0, {}}, {"one passthrough", p1, 1, {}}, {"two passthroughs", p2, 2, {}}};
  for (int r = 0; r < repeats; ++r) {
    for (Path& p : paths) p.medians.push_back(round_trip_us(p.port, p.index, requests));
  }
  std::printf(
      "Request round trip (position2d Geometry to the kinematic driver), %d requests x %d repeats\n\n",
      requests, repeats);
  std::printf("| path | median us | ratio |\n|---|---:|---:|\n");
  double base = 0;
  for (Path& p : paths) {
    std::sort(p.medians.begin(), p.medians.end());
    double m = p.medians[p.medians.size() / 2];
    if (base == 0) base = m;
    std::printf("| %s | %.0f | x%.2f |\n", p.name, m, base > 0 ? m / base : 0.0);
  }
  hop2.stop();
  hop1.stop();
  robot.stop();
  testing::remove_tree(dir);
  return 0;
}
