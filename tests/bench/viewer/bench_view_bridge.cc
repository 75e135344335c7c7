// What the viewer's WebSocket bridge costs: a request/reply round trip to a
// node through the bridge against the same round trip on the node's TCP
// port, in the same run; and the size of the ground-truth message the page
// receives every step.
//
//   build/host-release/tests/bench/viewer/bench_view_bridge [ROUND_TRIPS] [REPEATS]
#include <boost/asio/connect.hpp>
#include <boost/asio/io_context.hpp>
#include <boost/asio/ip/tcp.hpp>
#include <boost/beast/core.hpp>
#include <boost/beast/websocket.hpp>
#include <cstdio>
#include <cstdlib>

#include "host-sim/viewer/view_server.h"
#include "tests/bench/runtime/bench_util.h"
#include "tests/bench/runtime/kinematic_node.h"
#include "wire/writer.h"

using namespace troupe;
namespace net = boost::asio;
namespace websocket = boost::beast::websocket;

namespace {

std::vector<double> ws_round_trips(websocket::stream<net::ip::tcp::socket>& ws, int count) {
  std::vector<double> out;
  boost::beast::flat_buffer reply;
  for (int i = 0; i < count; ++i) {
    auto frame = bench::request_frame(uint32_t(i + 1));
    const double t0 = bench::monotonic_seconds();
    ws.write(net::buffer(frame));
    reply.clear();
    ws.read(reply);
    out.push_back((bench::monotonic_seconds() - t0) * 1e6);
  }
  return out;
}

size_t poses_frame_bytes(size_t robots) {
  wire::MessageWriter w;
  auto& b = w.start();
  std::vector<wire::Pose2d> poses(robots, wire::Pose2d(1.5f, -2.25f, 0.5f));
  auto body = wire::CreateSimPoses(b, 123456789, b.CreateVectorOfStructs(poses));
  return w
      .finish(wire::make_header({0, uint16_t(wire::Interface::Simulation), 0}, wire::Kind::Data,
                                uint8_t(wire::SimulationDataSub::Poses), 1, 0),
              wire::Body::SimPoses, body.Union())
      .size();
}

}  // namespace

int main(int argc, char** argv) {
  const int count = argc > 1 ? std::atoi(argv[1]) : 3000;
  const int repeats = argc > 2 ? std::atoi(argv[2]) : 5;
  uint16_t node_port = 0, view_port = 0;
  const pid_t node = bench::spawn_server(bench::serve_kinematic_node, node_port);
  if (node_port == 0) return 1;
  const pid_t view = bench::spawn_server(
      [node_port](const std::function<void(uint16_t)>& report) {
        viewer::ViewOptions o;
        o.http_port = 0;
        o.node_port = node_port;
        viewer::ViewServer server(o);
        std::string error;
        if (!server.open(error)) {
          std::fprintf(stderr, "bench_view_bridge: %s\n", error.c_str());
          report(0);
          return;
        }
        report(server.port());
        server.run();
      },
      view_port);
  if (view_port == 0) return 1;

  const int fd = bench::connect_loopback(node_port);
  std::vector<uint8_t> hello;
  bench::read_frame(fd, hello);  // the node speaks first
  net::io_context io;
  websocket::stream<net::ip::tcp::socket> ws(io);
  net::ip::tcp::resolver resolver(io);
  net::connect(ws.next_layer(), resolver.resolve("127.0.0.1", std::to_string(view_port)));
  ws.next_layer().set_option(net::ip::tcp::no_delay(true));
  ws.handshake("127.0.0.1", "/ws");
  ws.binary(true);
  boost::beast::flat_buffer first;
  ws.read(first);  // the node's Hello, through the bridge

  bench::blocking_round_trips(fd, 300);
  ws_round_trips(ws, 300);
  std::vector<double> tcp_medians, ws_medians, tcp_all, ws_all;
  for (int r = 0; r < repeats; ++r) {
    auto t = bench::blocking_round_trips(fd, count);
    auto w = ws_round_trips(ws, count);
    tcp_all.insert(tcp_all.end(), t.begin(), t.end());
    ws_all.insert(ws_all.end(), w.begin(), w.end());
    tcp_medians.push_back(bench::percentile(t, 50));
    ws_medians.push_back(bench::percentile(w, 50));
  }
  const double base = bench::percentile(tcp_medians, 50);
  const double bridged = bench::percentile(ws_medians, 50);
  std::printf("Request/reply round trip to troupe-node, %d round trips x %d repeats\n\n", count, repeats);
  std::printf("| path | median (us) | p99 (us) | median / TCP |\n|---|---:|---:|---:|\n");
  std::printf("| node's TCP port (baseline) | %.1f | %.1f | 1.00 |\n", base, bench::percentile(tcp_all, 99));
  std::printf("| WebSocket through the viewer's bridge | %.1f | %.1f | %.2f |\n\n", bridged,
              bench::percentile(ws_all, 99), bridged / base);

  std::printf(
      "Ground truth per step (simulation:0 Data/Poses), framed\n\n| robots | bytes | bytes per robot |\n"
      "|---:|---:|---:|\n");
  for (size_t n : {1, 10, 100, 1000, 10000}) {
    const size_t bytes = poses_frame_bytes(n);
    std::printf("| %zu | %zu | %.1f |\n", n, bytes, double(bytes) / double(n));
  }
  close(fd);
  bench::stop_server(view);
  bench::stop_server(node);
  return 0;
}
