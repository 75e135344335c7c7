// A client that stops reading loses old data; it never blocks the loop,
// never delays another client, never makes the node's memory grow.
#include <gtest/gtest.h>

#include "tests/runtime/node_fixture.h"
#include "wire/client/proxies.h"

namespace troupe::testing {
namespace {

using wire::Interface;
using wire::Kind;

TEST(SlowClient, DoesNotDelayOthersAndGetsTheNewestWhenItCatchesUp) {
  Node::Options options = test_options();
  options.socket_send_bytes = 16 * 1024;  // keep the kernel's share small and known
  NodeThread n(options);
  auto* rec = new Recorder;
  n.add_device(Interface::Ranger, 0, rec);
  n.start();

  // The slow client opens the scans and then reads nothing.
  RawConnection slow(n.port(), /*rcvbuf_bytes=*/4096);
  ASSERT_FALSE(slow.read_until(Kind::Hello).empty());
  wire::MessageWriter w;
  auto& b = w.start();
  auto open = wire::CreateOpen(b, wire::Access::Read, wire::Delivery::Push);
  ASSERT_TRUE(slow.send_bytes(
      w.finish(wire::make_header(addr(Interface::Ranger), Kind::Open, 0, 1, 0), wire::Body::Open, open.Union())));
  ASSERT_FALSE(slow.read_until(Kind::Ack).empty());
  size_t read_before = slow.bytes_read();

  client::Client fast("127.0.0.1", n.port());
  ASSERT_TRUE(fast.connect());
  client::RangerProxy scans(fast);
  ASSERT_TRUE(scans.is_open());

  // 2,000 scans of ~420 bytes: 50 times the slow client's buffers. After each
  // burst the fast client receives the newest scan.
  constexpr int kRounds = 50, kPerRound = 40;
  for (int round = 1; round <= kRounds; ++round) {
    rec->burst(kPerRound);
    uint32_t want = uint32_t(round * kPerRound);
    for (int i = 0; i < 2000 && scans.seq() < want; ++i) fast.spin_once(10);
    ASSERT_EQ(scans.seq(), want) << "round " << round;
  }
  ASSERT_EQ(rec->published.load(), uint32_t(kRounds * kPerRound));
  EXPECT_TRUE(fast.sync());

  // The slow client now reads what is there: a bounded amount, in order,
  // ending with the newest scan; most of the old ones were dropped.
  std::vector<uint32_t> seqs;
  size_t scan_bytes = 0;
  for (auto f = slow.read_frame(1000); !f.empty(); f = slow.read_frame(1000)) {
    const wire::Message* m = wire::verify_frame(f, wire::Limits{});
    ASSERT_NE(m, nullptr);
    if (m->header()->kind() == Kind::Data) {
      seqs.push_back(m->header()->seq());
      scan_bytes = f.size();
    }
  }
  ASSERT_FALSE(seqs.empty());
  EXPECT_EQ(seqs.back(), uint32_t(kRounds * kPerRound));
  EXPECT_TRUE(std::is_sorted(seqs.begin(), seqs.end()));
  EXPECT_LT(seqs.size(), size_t(kRounds * kPerRound) / 4);
  size_t produced = size_t(kRounds * kPerRound) * scan_bytes;
  EXPECT_LT(slow.bytes_read() - read_before, produced / 4);
}

}  // namespace
}  // namespace troupe::testing
