// Routing: one device publishing 181-beam laser scans at a fixed rate to 1,
// 10 and 100 clients. Prints messages/s, bytes/s, the node's CPU use and its
// CPU time per delivered message (the routing cost, which the machine's
// other load does not change much).
//
//   build/host-release/tests/bench/runtime/bench_fanout [SECONDS] [SCANS_PER_SECOND]
//
// Clients read with poll() in one process; a client that falls behind gets
// the newest scan when it catches up (the node's policy), so delivered may
// be less than published x clients when the readers are starved of CPU.
#include <poll.h>
#include <sys/epoll.h>
#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>

#include "runtime/node.h"
#include "tests/bench/runtime/bench_util.h"
#include "wire/frame.h"
#include "wire/writer.h"

using namespace troupe;

namespace {

const wire::Address kLaser(0, uint16_t(wire::Interface::Ranger), 0);

int g_rate_hz = 1000;

class Publisher final : public Driver {
 public:
  bool setup(Node& node, const DriverSetup& setup, std::string&) override {
    device_ = setup.provides[0];
    uint64_t period_us = uint64_t(1e6 / g_rate_hz);
    return node.loop().start_timer(period_us, period_us, this) != 0;
  }
  void on_timer(TimerId) override {
    if (node_->has_readers(device_)) {
      auto& b = node_->begin();
      uint16_t* r = nullptr;
      auto ranges = b.CreateUninitializedVector<uint16_t>(181, &r);
      for (int i = 0; i < 181; ++i) r[i] = uint16_t(1000 + (seq_ + i) % 5000);
      auto body = wire::CreateRangerScan(b, ranges, 0.001f, -1.5708f, 0.017453f, 8.0f);
      node_->publish(device_, uint8_t(wire::RangerDataSub::Scan), wire::Body::RangerScan, body.Union());
      ++seq_;
    }
  }

 private:
  DeviceId device_ = 0;
  uint32_t seq_ = 0;
};

void serve_node(const std::function<void(uint16_t)>& report) {
  Node::Options o;
  o.port = 0;
  o.max_clients = 128;
  Node node(o);
  auto* driver = new Publisher;
  DeviceId ids[1] = {node.add_device(kLaser, driver, "publisher")};
  DriverSetup setup;
  setup.provides = ids;
  std::string error;
  if (!node.add_driver(std::unique_ptr<Driver>(driver), setup, error) || !node.start(error)) {
    report(0);
    return;
  }
  report(node.port());
  node.run();
}

struct Reader {
  int fd;
  wire::FrameReader frames{1 << 20};
  uint64_t messages = 0, bytes = 0;
  uint32_t last_seq = 0;
};

}  // namespace

int main(int argc, char** argv) {
  double seconds = argc > 1 ? atof(argv[1]) : 3.0;
  g_rate_hz = argc > 2 ? atoi(argv[2]) : 1000;
  printf("One ranger device publishing 181-beam scans at %d Hz, %.0f s per row\n\n", g_rate_hz, seconds);
  printf("| clients | published msg/s | delivered msg/s (all clients) | delivered MB/s | node CPU %% | "
         "node CPU us / delivered msg | delivered / (published x clients) |\n"
         "|---:|---:|---:|---:|---:|---:|---:|\n");
  for (int clients : {1, 10, 100}) {
    uint16_t port = 0;
    pid_t node = bench::spawn_server(serve_node, port);
    if (port == 0) return 1;
    std::vector<Reader> readers(size_t(clients), Reader{-1});
    wire::MessageWriter w;
    for (Reader& r : readers) {
      r.fd = bench::connect_loopback(port);
      auto& b = w.start();
      auto open = wire::CreateOpen(b, wire::Access::Read, wire::Delivery::Push);
      bench::write_all(r.fd, w.finish(wire::make_header(kLaser, wire::Kind::Open, 0, 1, 0), wire::Body::Open, open.Union()));
    }
    std::vector<pollfd> fds;
    for (Reader& r : readers) fds.push_back({r.fd, POLLIN, 0});
    uint32_t first_seq = 0;
    double cpu0 = 0, t0 = 0;
    bool measuring = false;
    double warmup_end = bench::monotonic_seconds() + 0.5;
    double end = warmup_end + seconds;
    for (double now = bench::monotonic_seconds(); now < end; now = bench::monotonic_seconds()) {
      if (!measuring && now >= warmup_end) {
        measuring = true;
        cpu0 = bench::cpu_seconds(node);
        t0 = now;
        for (Reader& r : readers) r.messages = r.bytes = 0;
        for (Reader& r : readers) first_seq = std::max(first_seq, r.last_seq);
      }
      poll(fds.data(), fds.size(), 50);
      for (size_t i = 0; i < fds.size(); ++i) {
        if (!(fds[i].revents & POLLIN)) continue;
        Reader& r = readers[i];
        auto space = r.frames.write_space(64 * 1024);
        ssize_t n = read(r.fd, space.data(), space.size());
        if (n <= 0) continue;
        r.frames.commit(size_t(n));
        for (auto f = r.frames.next(); !f.empty(); f = r.frames.next()) {
          const wire::Message* m = wire::trusted_message(f);
          if (m->header()->kind() != wire::Kind::Data) continue;
          r.last_seq = m->header()->seq();
          // Count only scans published inside the window, not the backlog
          // that sat in socket buffers when it opened.
          if (measuring && r.last_seq > first_seq) {
            ++r.messages;
            r.bytes += f.size();
          }
        }
      }
    }
    double elapsed = bench::monotonic_seconds() - t0;
    double cpu = bench::cpu_seconds(node) - cpu0;
    uint64_t delivered = 0, bytes = 0;
    uint32_t last_seq = 0;
    for (Reader& r : readers) {
      delivered += r.messages;
      bytes += r.bytes;
      last_seq = std::max(last_seq, r.last_seq);
      close(r.fd);
    }
    double published = double(last_seq - first_seq) / elapsed;
    printf("| %d | %.0f | %.0f | %.1f | %.0f | %.2f | %.2f |\n", clients, published, double(delivered) / elapsed,
           double(bytes) / elapsed / 1e6, 100.0 * cpu / elapsed, 1e6 * cpu / double(std::max<uint64_t>(delivered, 1)),
           double(delivered) / elapsed / (published * double(clients)));
    bench::stop_server(node);
  }
  return 0;
}
