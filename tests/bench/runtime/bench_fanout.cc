// Routing: one device publishing 181-beam laser scans at a fixed rate to 1,
// 10 and 100 clients, in plain TCP and in secure sessions (Noise IK: every
// frame sealed by the node, once per client). Prints messages/s, bytes/s,
// the node's CPU use and its CPU time per delivered message (the routing
// cost, which the machine's other load does not change much), each the
// median of REPEATS runs, plain and secure runs interleaved; then the secure
// cost per delivered message as a ratio of the plain one.
//
//   build/host-release/tests/bench/runtime/bench_fanout [SECONDS] [SCANS_PER_SECOND] [REPEATS]
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
#include <memory>
#include <vector>

#include "runtime/log.h"
#include "runtime/node.h"
#include "tests/bench/runtime/bench_util.h"
#include "wire/frame.h"
#include "wire/noise/noise_transport.h"
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

namespace noise = wire::noise;

// The node's key pair in secure runs; any client key is let in (the
// benchmark measures sealing, not the key check).
noise::KeyPair g_node_key;

void serve_node(bool secure, const std::function<void(uint16_t)>& report) {
  set_log_level(LogLevel::Warn);  // not a line per client's session
  Node::Options o;
  o.port = 0;
  o.max_clients = 128;
  if (secure) {
    o.make_transport = [] {
      noise::SecureOptions so;
      so.role = noise::Role::Responder;
      so.identity = g_node_key;
      return std::make_unique<noise::NoiseTransport>(std::move(so));
    };
  }
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
  int fd = -1;
  std::unique_ptr<noise::NoiseTransport> session;  // nullptr: plain
  wire::FrameReader frames{1 << 20};
  uint64_t messages = 0, bytes = 0;
  uint32_t last_seq = 0;
};

// Connects `r`, runs its handshake when secure (blocking: before any
// measurement) and opens the laser. False when the node refused.
bool connect_reader(Reader& r, uint16_t port, bool secure) {
  r.fd = bench::connect_loopback(port);
  if (r.fd < 0) return false;
  wire::MessageWriter w;
  auto& b = w.start();
  auto open = wire::CreateOpen(b, wire::Access::Read, wire::Delivery::Push);
  const auto frame =
      w.finish(wire::make_header(kLaser, wire::Kind::Open, 0, 1, 0), wire::Body::Open, open.Union());
  if (!secure) return bench::write_all(r.fd, frame);
  r.session = std::make_unique<noise::NoiseTransport>(noise::SecureOptions{
      noise::Role::Initiator, noise::generate_keypair(), g_node_key.public_key, nullptr});
  std::vector<uint8_t> out;
  std::string error;
  r.session->begin(out);
  if (!bench::write_all(r.fd, out)) return false;
  uint8_t buf[512];
  while (!r.session->ready()) {
    const ssize_t n = read(r.fd, buf, sizeof buf);
    out.clear();
    if (n <= 0 || !r.session->inbound({buf, size_t(n)}, r.frames, out, error)) return false;
  }
  out.clear();
  r.session->outbound(frame, out);
  return bench::write_all(r.fd, out);
}

struct Run {
  double published = 0;  // msg/s
  double delivered = 0;  // msg/s, all clients
  double mb_per_s = 0;
  double cpu_percent = 0;
  double cpu_us_per_msg = 0;
  double share = 0;  // delivered / (published x clients)
};

bool run_once(int clients, bool secure, double seconds, Run& out) {
  uint16_t port = 0;
  pid_t node = bench::spawn_server([secure](const auto& report) { serve_node(secure, report); }, port);
  if (port == 0) return false;
  std::vector<Reader> readers(static_cast<size_t>(clients));
  for (Reader& r : readers) {
    if (!connect_reader(r, port, secure)) {
      std::fprintf(stderr, "bench_fanout: a client could not connect\n");
      bench::stop_server(node);
      return false;
    }
  }
  std::vector<pollfd> fds;
  for (Reader& r : readers) fds.push_back({r.fd, POLLIN, 0});
  uint32_t first_seq = 0;
  double cpu0 = 0, t0 = 0;
  bool measuring = false;
  double warmup_end = bench::monotonic_seconds() + 0.5;
  double end = warmup_end + seconds;
  std::vector<uint8_t> sealed(64 * 1024), reply;
  std::string error;
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
      if (r.session) {
        ssize_t n = read(r.fd, sealed.data(), sealed.size());
        if (n <= 0) continue;
        if (!r.session->inbound({sealed.data(), size_t(n)}, r.frames, reply, error)) {
          std::fprintf(stderr, "bench_fanout: %s\n", error.c_str());
          bench::stop_server(node);
          return false;
        }
      } else {
        auto space = r.frames.write_space(64 * 1024);
        ssize_t n = read(r.fd, space.data(), space.size());
        if (n <= 0) continue;
        r.frames.commit(size_t(n));
      }
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
  bench::stop_server(node);
  out.published = double(last_seq - first_seq) / elapsed;
  out.delivered = double(delivered) / elapsed;
  out.mb_per_s = double(bytes) / elapsed / 1e6;
  out.cpu_percent = 100.0 * cpu / elapsed;
  out.cpu_us_per_msg = 1e6 * cpu / double(std::max<uint64_t>(delivered, 1));
  out.share = out.delivered / (out.published * double(clients));
  return true;
}

// The run whose node CPU per delivered message is the median of `runs`,
// whole, so that a row's columns come from one run.
Run median_run(std::vector<Run> runs) {
  std::sort(runs.begin(), runs.end(),
            [](const Run& a, const Run& b) { return a.cpu_us_per_msg < b.cpu_us_per_msg; });
  return runs[runs.size() / 2];
}

}  // namespace

int main(int argc, char** argv) {
  double seconds = argc > 1 ? atof(argv[1]) : 3.0;
  g_rate_hz = argc > 2 ? atoi(argv[2]) : 1000;
  const int repeats = argc > 3 ? atoi(argv[3]) : 5;
  if (seconds <= 0 || g_rate_hz <= 0 || repeats <= 0) {
    std::fprintf(stderr, "usage: bench_fanout [SECONDS > 0] [SCANS_PER_SECOND > 0] [REPEATS > 0]\n");
    return 2;
  }
  g_node_key = noise::generate_keypair();
  printf("One ranger device publishing 181-beam scans at %d Hz, %.0f s per run, median of %d runs\n\n",
         g_rate_hz, seconds, repeats);
  printf(
      "| session | clients | published msg/s | delivered msg/s (all clients) | delivered MB/s | node CPU %% "
      "| "
      "node CPU us / delivered msg | delivered / (published x clients) |\n"
      "|---|---:|---:|---:|---:|---:|---:|---:|\n");
  struct Ratio {
    int clients;
    double plain, secure;
  };
  std::vector<Ratio> ratios;
  for (int clients : {1, 10, 100}) {
    std::vector<Run> plain, secure;
    for (int i = 0; i < repeats; ++i) {
      for (bool sealed : {false, true}) {
        Run r;
        if (!run_once(clients, sealed, seconds, r)) return 1;
        (sealed ? secure : plain).push_back(r);
      }
    }
    for (bool sealed : {false, true}) {
      const Run m = median_run(sealed ? secure : plain);
      printf("| %s | %d | %.0f | %.0f | %.1f | %.0f | %.2f | %.2f |\n", sealed ? "secure" : "plain", clients,
             m.published, m.delivered, m.mb_per_s, m.cpu_percent, m.cpu_us_per_msg, m.share);
    }
    ratios.push_back({clients, median_run(plain).cpu_us_per_msg, median_run(secure).cpu_us_per_msg});
  }
  printf(
      "\n| clients | node CPU us / delivered msg, plain | secure | secure / plain "
      "|\n|---:|---:|---:|---:|\n");
  for (const Ratio& r : ratios) {
    printf("| %d | %.2f | %.2f | %.2f |\n", r.clients, r.plain, r.secure, r.secure / r.plain);
  }
  return 0;
}
