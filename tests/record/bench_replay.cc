// How faithfully troupe play keeps the recorded pace: a client measures the
// jitter of each replayed frame's arrival against its slot (the recorded
// receive times divided by the speed), next to the same measurement of a
// driver that publishes on the event loop's own periodic timer (the
// baseline: the best any driver of the node can do). Prints a table;
// asserts nothing.
//
//   build/host-release/tests/record/bench_replay
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdio>
#include <memory>
#include <string>
#include <thread>
#include <vector>

#include "runtime/clock.h"
#include "runtime/node.h"
#include "wire/client/client.h"
#include "wire/record/log_file.h"
#include "drivers/replay/replay_driver.h"
#include "wire/writer.h"

namespace {

using namespace troupe;

const wire::Address kLaser(0, uint16_t(wire::Interface::Ranger), 0);
constexpr int kFrames = 200;
constexpr int kRepeats = 3;
constexpr int kBeams = 181;

std::vector<uint8_t> scan_frame(uint32_t seq) {
  wire::MessageWriter w;
  auto& b = w.start();
  std::vector<uint16_t> ranges(kBeams, uint16_t(1000 + seq));
  auto body = wire::CreateRangerScan(b, b.CreateVector(ranges), 0.001f, -1.5708f, 0.0175f, 8.0f);
  auto f = w.finish(wire::make_header(kLaser, wire::Kind::Data, 1, seq, 1000000u + seq),
                    wire::Body::RangerScan, body.Union());
  return {f.begin(), f.end()};
}

// Publishes a scan on every tick of a periodic timer.
class TimerPublisher : public Driver {
 public:
  explicit TimerPublisher(uint64_t period_us) : period_us_(period_us) {}
  bool setup(Node&, const DriverSetup& setup, std::string&) override {
    device_ = setup.provides[0];
    return true;
  }
  void start() { node_->loop().start_timer(period_us_, period_us_, this); }
  void on_timer(TimerId) override {
    if (!node_->has_readers(device_) || sent_ >= kFrames) return;
    std::vector<uint16_t> ranges(kBeams, uint16_t(1000 + ++sent_));
    auto& b = node_->begin();
    auto body = wire::CreateRangerScan(b, b.CreateVector(ranges), 0.001f, -1.5708f, 0.0175f, 8.0f);
    node_->publish(device_, 1, wire::Body::RangerScan, body.Union());
  }

 private:
  uint64_t period_us_;
  DeviceId device_ = kNoDevice;
  int sent_ = 0;
};

struct Lateness {
  double median_us = 0, p99_us = 0;
  size_t frames = 0;
};

// Runs `node` in a thread, receives kFrames frames with a client, and
// compares each arrival (relative to the first) with `period_us` * i.
Lateness measure(Node& node, double period_us) {
  std::atomic<bool> stop{false};
  std::thread loop([&] {
    while (!stop) node.poll(2000);
  });
  client::Client c("127.0.0.1", node.port());
  c.connect();
  std::vector<uint64_t> arrivals;
  c.add_data_handler([&](const wire::Message&) { arrivals.push_back(monotonic_us()); });
  c.open(kLaser, wire::Access::Read);
  uint64_t deadline = monotonic_us() + uint64_t(period_us * kFrames * 2) + 5000000u;
  while (arrivals.size() < size_t(kFrames) && monotonic_us() < deadline) c.spin_once(50);
  stop = true;
  loop.join();
  // Jitter: each frame's offset from its slot, less the median offset (a
  // constant delay, e.g. the timer's wake-up latency that the first frame
  // of a replay does not have, is no error of pace).
  std::vector<double> offsets;
  for (size_t i = 1; i < arrivals.size(); ++i) {
    offsets.push_back(double(arrivals[i] - arrivals[0]) - period_us * double(i));
  }
  std::vector<double> sorted = offsets;
  std::sort(sorted.begin(), sorted.end());
  double typical = sorted.empty() ? 0 : sorted[sorted.size() / 2];
  std::vector<double> late;
  for (double o : offsets) late.push_back(std::abs(o - typical));
  std::sort(late.begin(), late.end());
  Lateness out;
  out.frames = arrivals.size();
  if (!late.empty()) {
    out.median_us = late[late.size() / 2];
    out.p99_us = late[std::min(late.size() - 1, late.size() * 99 / 100)];
  }
  return out;
}

Lateness timer_baseline(uint64_t period_us) {
  Node::Options o;
  o.port = 0;
  Node node(o);
  auto* pub = new TimerPublisher(period_us);
  DeviceId id = node.add_device(kLaser, pub, "timer");
  DriverSetup setup;
  setup.provides = {&id, 1};
  std::string error;
  node.add_driver(std::unique_ptr<Driver>(pub), setup, error);
  node.start(error);
  pub->start();  // before the node's thread runs: the loop is not thread-safe
  Lateness l = measure(node, double(period_us));
  node.shutdown();
  return l;
}

Lateness replay(const std::string& path, uint64_t period_us, double speed) {
  Node::Options o;
  o.port = 0;
  Node node(o);
  drivers::replay::ReplayDriver::Options ro;
  ro.path = path;
  ro.speed = speed;
  ro.wait_for_readers = true;
  auto* driver = new drivers::replay::ReplayDriver(ro);
  DeviceId id = node.add_device(kLaser, driver, "replay");
  DriverSetup setup;
  setup.provides = {&id, 1};
  std::string error;
  if (!node.add_driver(std::unique_ptr<Driver>(driver), setup, error) || !node.start(error)) {
    fprintf(stderr, "%s\n", error.c_str());
    return {};
  }
  Lateness l = measure(node, double(period_us) / speed);
  node.shutdown();
  return l;
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v.empty() ? 0 : v[v.size() / 2];
}

}  // namespace

int main() {
  std::string path = std::string(P_tmpdir) + "/troupe-bench-replay-XXXXXX";
  int fd = mkstemp(path.data());
  close(fd);
  printf(
      "%d frames of a 181-beam scan per run; jitter = |arrival - first arrival - i * period - median of "
      "that| at a client;\n"
      "medians over %d runs of each run's median and 99th percentile, us\n\n",
      kFrames, kRepeats);
  printf(
      "| period as played (ms) | speed | loop timer: median jitter | p99 | troupe play: median jitter | p99 "
      "| play / timer |\n");
  printf("|---:|---:|---:|---:|---:|---:|---:|\n");
  for (uint64_t period_us : {50000u, 10000u}) {
    record::LogWriter w;
    std::string error;
    w.open(path, 0, error);
    for (int i = 0; i < kFrames; ++i) w.write(uint64_t(i) * period_us, scan_frame(uint32_t(i + 1)), error);
    w.close(error);
    for (double speed : {1.0, 4.0}) {
      uint64_t played = uint64_t(double(period_us) / speed);
      std::vector<double> tm, tp, rm, rp;
      for (int r = 0; r < kRepeats; ++r) {
        Lateness base = timer_baseline(played);
        Lateness rep = replay(path, period_us, speed);
        if (base.frames != size_t(kFrames) || rep.frames != size_t(kFrames)) fprintf(stderr, "frames lost\n");
        tm.push_back(base.median_us);
        tp.push_back(base.p99_us);
        rm.push_back(rep.median_us);
        rp.push_back(rep.p99_us);
      }
      printf("| %.1f | %.0f | %.0f | %.0f | %.0f | %.0f | %.2f |\n", double(played) / 1000, speed, median(tm),
             median(tp), median(rm), median(rp), median(rm) / std::max(median(tm), 1.0));
    }
  }
  unlink(path.c_str());
  return 0;
}
