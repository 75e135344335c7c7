// Data over UDP: a client that names a UDP port in its Hello gets Data as
// datagrams (latest wins) while replies stay on TCP.
#include <arpa/inet.h>
#include <gtest/gtest.h>
#include <netinet/in.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include "tests/runtime/node_fixture.h"
#include "wire/client/proxies.h"

namespace troupe::testing {
namespace {

using wire::Interface;
using wire::Kind;

TEST(Udp, DataArrivesAsDatagramsAndRepliesOnTcp) {
  NodeThread n(test_options());
  auto* rec = new Recorder;
  n.add_device(Interface::Ranger, 0, rec);
  n.start();

  int udp = socket(AF_INET, SOCK_DGRAM, 0);
  sockaddr_in a{};
  a.sin_family = AF_INET;
  a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  ASSERT_EQ(bind(udp, reinterpret_cast<sockaddr*>(&a), sizeof a), 0);
  socklen_t len = sizeof a;
  getsockname(udp, reinterpret_cast<sockaddr*>(&a), &len);

  RawConnection tcp(n.port());
  ASSERT_FALSE(tcp.read_until(Kind::Hello).empty());
  wire::MessageWriter w;
  auto& b = w.start();
  auto hello = wire::CreateHello(b, wire::kProtocolVersion, b.CreateString("udp-test"), 0, ntohs(a.sin_port));
  ASSERT_TRUE(tcp.send_bytes(w.finish(wire::make_header({}, Kind::Hello, 0, 0, 0), wire::Body::Hello, hello.Union())));
  auto& ob = w.start();
  auto open = wire::CreateOpen(ob, wire::Access::Read);
  ASSERT_TRUE(tcp.send_bytes(
      w.finish(wire::make_header(addr(Interface::Ranger), Kind::Open, 0, 1, 0), wire::Body::Open, open.Union())));
  ASSERT_FALSE(tcp.read_until(Kind::Ack).empty());  // the reply: TCP

  rec->burst(3);
  int datagrams = 0;
  uint32_t last_seq = 0;
  uint8_t buf[65536];
  pollfd p{udp, POLLIN, 0};
  while (datagrams < 3 && poll(&p, 1, 3000) > 0) {
    ssize_t got = recv(udp, buf, sizeof buf, 0);
    ASSERT_GT(got, 0);
    const wire::Message* m = wire::verify_frame({buf, size_t(got)}, wire::Limits{});
    ASSERT_NE(m, nullptr) << "each datagram is one whole frame";
    EXPECT_EQ(m->header()->kind(), Kind::Data);
    EXPECT_EQ(m->body_type(), wire::Body::RangerScan);
    EXPECT_GT(m->header()->seq(), last_seq);
    last_seq = m->header()->seq();
    ++datagrams;
  }
  EXPECT_EQ(datagrams, 3);
  // Nothing of the data came over TCP: the next TCP frame is the reply to this.
  ASSERT_TRUE(tcp.send_bytes(empty_frame({}, Kind::DeviceList, 0, 2)));
  auto next = tcp.read_frame();
  ASSERT_FALSE(next.empty());
  EXPECT_EQ(wire::trusted_message(next)->header()->kind(), Kind::DeviceList);
  close(udp);
}

TEST(Udp, ClientLibraryProxiesWorkOverUdp) {
  NodeThread n(test_options());
  auto* rec = new Recorder;
  n.add_device(Interface::Ranger, 0, rec);
  n.start();
  client::Client::Options options;
  options.udp_data = true;
  client::Client c("127.0.0.1", n.port(), options);
  ASSERT_TRUE(c.connect());
  client::RangerProxy scans(c);
  ASSERT_TRUE(scans.is_open());
  rec->burst(1);
  for (int i = 0; i < 300 && scans.samples() == 0; ++i) c.spin_once(10);
  EXPECT_EQ(scans.samples(), 1u);
  EXPECT_EQ(scans.count(), 181u);
}

TEST(PollLoop, ClientRunsInsideTheCallersOwnPoll) {
  RecorderNode n(Interface::Ranger);
  Recorder* rec = n.recorder;
  client::Client& c = *n.client;
  client::RangerProxy scans(c);
  rec->stream(5);
  // The caller's loop: its own descriptor (a pipe it never writes) beside the client's.
  int own[2];
  ASSERT_EQ(pipe(own), 0);
  for (int i = 0; i < 400 && scans.samples() < 5; ++i) {
    pollfd fds[3];
    int k = c.poll_fds(fds, 2);
    fds[k] = pollfd{own[0], POLLIN, 0};
    int timeout = c.next_timeout_ms();
    poll(fds, nfds_t(k + 1), timeout < 0 ? 10 : std::min(timeout, 10));
    c.process(fds, k);
    EXPECT_EQ(fds[k].revents, 0);
  }
  EXPECT_GE(scans.samples(), 5u);
  close(own[0]);
  close(own[1]);
}

}  // namespace
}  // namespace troupe::testing
