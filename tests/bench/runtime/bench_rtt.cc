// Request/reply round trip through a node, against a raw TCP echo of the same
// bytes in the same run. Prints medians, p99 and the ratio to the echo.
//
//   build/host-release/tests/bench/runtime/bench_rtt [ROUND_TRIPS] [REPEATS]
//
// Three paths, each a separate process pair on loopback:
//   echo        a blocking server that sends every frame straight back
//   node        troupe-node's loop: verify, route, the kinematic driver's
//               reply, the Ack (client: a blocking socket, like the echo's)
//   node+client the same through the C++ client library (poll, verify)
//   secure      the same with a secure session (Noise IK: every frame sealed
//               and opened on both sides), where libsodium is
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cstdio>
#include <cstdlib>

#include "runtime/node.h"
#include "tests/bench/runtime/bench_util.h"
#include "tests/bench/runtime/kinematic_node.h"
#include "wire/client/client.h"
#ifdef TROUPE_HAVE_NOISE
#include "wire/noise/noise_transport.h"
#endif

using namespace troupe;

namespace {

const wire::Address& kBase = bench::kBenchBase;
constexpr uint8_t kResetOdometry = uint8_t(wire::Position2dReqSub::ResetOdometry);

void serve_echo(const std::function<void(uint16_t)>& report) {
  int ls = socket(AF_INET, SOCK_STREAM, 0);
  sockaddr_in a{};
  a.sin_family = AF_INET;
  a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  bind(ls, reinterpret_cast<sockaddr*>(&a), sizeof a);
  listen(ls, 4);
  socklen_t len = sizeof a;
  getsockname(ls, reinterpret_cast<sockaddr*>(&a), &len);
  report(ntohs(a.sin_port));
  for (;;) {
    int fd = accept(ls, nullptr, nullptr);
    int one = 1;
    setsockopt(fd, IPPROTO_TCP, 1 /*TCP_NODELAY*/, &one, sizeof one);
    std::vector<uint8_t> frame;
    while (bench::read_frame(fd, frame) && bench::write_all(fd, frame)) {
    }
    close(fd);
  }
}

std::vector<double> client_round_trips(client::Client& c, int count) {
  std::vector<double> out;
  for (int i = 0; i < count; ++i) {
    double t0 = bench::monotonic_seconds();
    client::Reply r = c.request(kBase, kResetOdometry);
    out.push_back((bench::monotonic_seconds() - t0) * 1e6);
    if (!r.ok()) {
      fprintf(stderr, "bench_rtt: request failed: %s\n", r.text.c_str());
      exit(1);
    }
  }
  return out;
}

struct Path {
  const char* name;
  std::vector<double> all;      // every sample, us
  std::vector<double> medians;  // one per repeat, us
};

}  // namespace

int main(int argc, char** argv) {
  int count = argc > 1 ? atoi(argv[1]) : 5000;
  int repeats = argc > 2 ? atoi(argv[2]) : 5;
  uint16_t echo_port = 0, node_port = 0;
  pid_t echo = bench::spawn_server(serve_echo, echo_port);
  pid_t node = bench::spawn_server(bench::serve_kinematic_node, node_port);
  if (echo_port == 0 || node_port == 0) return 1;
  int echo_fd = bench::connect_loopback(echo_port);
  int node_fd = bench::connect_loopback(node_port);
  std::vector<uint8_t> hello;
  bench::read_frame(node_fd, hello);  // the node speaks first
  client::Client c("127.0.0.1", node_port);
  if (echo_fd < 0 || node_fd < 0 || !c.connect()) return 1;
  std::vector<Path> paths = {
      {"raw TCP echo (baseline)", {}, {}}, {"troupe-node", {}, {}}, {"troupe-node, C++ client", {}, {}}};
#ifdef TROUPE_HAVE_NOISE
  // The node knows the client's key and the client the node's, as a
  // deployed pair would (keys made here: nothing is read from disk).
  namespace noise = wire::noise;
  const noise::KeyPair node_key = noise::generate_keypair(), client_key = noise::generate_keypair();
  uint16_t secure_port = 0;
  pid_t secure_node = bench::spawn_server(
      [&](const std::function<void(uint16_t)>& report) {
        bench::serve_kinematic_node_through(report, [&]() -> std::unique_ptr<wire::Transport> {
          noise::SecureOptions o;
          o.role = noise::Role::Responder;
          o.identity = node_key;
          o.accept = [&](const noise::Key& k, std::string&) { return k == client_key.public_key; };
          return std::make_unique<noise::NoiseTransport>(std::move(o));
        });
      },
      secure_port);
  client::Client::Options so;
  noise::SecureOptions co;
  co.identity = client_key;
  co.peer_key = node_key.public_key;
  so.transport = std::make_shared<noise::NoiseTransport>(std::move(co));
  client::Client secure("127.0.0.1", secure_port, so);
  if (secure_port == 0 || !secure.connect()) return 1;
  paths.push_back({"secure troupe-node, C++ client", {}, {}});
#endif
  auto take = [&](int n) {
    std::vector<std::vector<double>> samples = {bench::blocking_round_trips(echo_fd, n),
                                                bench::blocking_round_trips(node_fd, n), client_round_trips(c, n)};
#ifdef TROUPE_HAVE_NOISE
    samples.push_back(client_round_trips(secure, n));
#endif
    return samples;
  };
  // Warm up every path, then interleave the repeats so that machine noise
  // falls on all of them alike.
  take(500);
  for (int r = 0; r < repeats; ++r) {
    std::vector<std::vector<double>> samples = take(count);
    for (size_t p = 0; p < paths.size(); ++p) {
      paths[p].all.insert(paths[p].all.end(), samples[p].begin(), samples[p].end());
      paths[p].medians.push_back(bench::percentile(samples[p], 50));
    }
  }
  double base = bench::percentile(paths[0].medians, 50);
  printf(
      "Request/reply round trip on loopback, %d round trips x %d repeats (frame of %zu bytes each way)\n\n",
      count, repeats, bench::request_frame(1).size());
  printf("| path | median (us) | p99 (us) | median / echo |\n|---|---:|---:|---:|\n");
  for (Path& p : paths) {
    double med = bench::percentile(p.medians, 50);
    printf("| %s | %.1f | %.1f | %.2f |\n", p.name, med, bench::percentile(p.all, 99), med / base);
  }
#ifdef TROUPE_HAVE_NOISE
  printf("\nsecure / plain, C++ client: %.2f\n",
         bench::percentile(paths[3].medians, 50) / bench::percentile(paths[2].medians, 50));
  bench::stop_server(secure_node);
#endif
  close(echo_fd);
  close(node_fd);
  bench::stop_server(echo);
  bench::stop_server(node);
  return 0;
}
