// CPU cost of the odrive_can driver and the ODrive emulator at their nominal
// traffic (two axes: 200 encoder estimates, 20 heartbeats, 100 velocity
// frames a second, position2d at 50 Hz), against a node serving only a
// kinematic base, measured in the same run. Prints a table: CPU time per
// second of wall time, medians over repeats.
//
//   odrive_bench [SECONDS_PER_RUN] [REPEATS]
#include <sys/resource.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <vector>

#include "runtime/log.h"
#include "tests/odrive/odrive_rig.h"

namespace {

using troupe::testing::OdriveRig;

double cpu_seconds() {
  rusage u{};
  getrusage(RUSAGE_SELF, &u);
  return double(u.ru_utime.tv_sec + u.ru_stime.tv_sec) +
         1e-6 * double(u.ru_utime.tv_usec + u.ru_stime.tv_usec);
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

// CPU seconds per wall second while `poll` runs the loop for `seconds`.
template <typename Poll>
double measure(double seconds, troupe::EventLoop& loop, Poll poll) {
  const uint64_t end = loop.now_us() + uint64_t(seconds * 1e6);
  const double start = cpu_seconds();
  while (loop.now_us() < end) poll();
  return (cpu_seconds() - start) / seconds;
}

}  // namespace

int main(int argc, char** argv) {
  const double seconds = argc > 1 ? atof(argv[1]) : 3.0;
  const int repeats = argc > 2 ? atoi(argv[2]) : 5;
  troupe::set_log_level(troupe::LogLevel::Warn);
  std::vector<double> baseline, odrive;
  double frames_per_s = 0;
  for (int r = 0; r < repeats; ++r) {
    {
      troupe::Node::Options options;
      options.port = 0;
      options.udp = false;
      troupe::Node node(options);
      std::vector<uint8_t> bytes;
      std::string error;
      if (!troupe::testing::build_node_from_json(
              node,
              R"({"drivers": [{"driver_type": "kinematic", "driver": {"rate_hz": 50}, "provides": ["position2d:1"]}]})",
              bytes, error)) {
        fprintf(stderr, "odrive_bench: %s\n", error.c_str());
        return 1;
      }
      baseline.push_back(measure(seconds, node.loop(), [&] { node.poll(5000); }));
    }
    {
      OdriveRig rig;
      if (!rig.error().empty()) {
        fprintf(stderr, "odrive_bench: %s\n", rig.error().c_str());
        return 1;
      }
      rig.run_for(1.0);  // armed
      rig.client.command_vel(OdriveRig::kBase, 0.5f, 0.2f);
      const uint64_t frames0 = rig.emu->counters().frames_in + rig.emu->counters().frames_out;
      odrive.push_back(measure(seconds, rig.node.loop(), [&] {
        rig.node.poll(5000);
        rig.client.pump();
      }));
      frames_per_s =
          double(rig.emu->counters().frames_in + rig.emu->counters().frames_out - frames0) / seconds;
    }
  }
  const double base = median(baseline), with = median(odrive);
  printf("%-44s %12s %10s\n", "setup (median of runs)", "CPU ms/s", "ratio");
  printf("%-44s %12.2f %10.2f\n", "node + kinematic base at 50 Hz", base * 1e3, 1.0);
  printf("%-44s %12.2f %10.2f\n", "node + odrive_can + emulator + kinematic", with * 1e3, with / base);
  printf("CAN frames on the bus: %.0f per second; %d runs of %.1f s\n", frames_per_s, repeats, seconds);
  return 0;
}
