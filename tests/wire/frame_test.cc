// FrameReader cuts streams into frames however the bytes arrive; the
// verifier refuses anything that is not a well-formed Message.
#include <gtest/gtest.h>

#include <cstring>
#include <random>
#include <vector>

#include "wire/frame.h"
#include "wire/writer.h"

namespace troupe::wire {
namespace {

std::vector<uint8_t> vel_frame(float vx, uint32_t seq) {
  MessageWriter w;
  auto& b = w.start();
  Pose2d vel(vx, 0, 0.5f);
  auto body = CreatePosition2dVel(b, &vel);
  auto f = w.finish(make_header(Address(0, uint16_t(Interface::Position2d), 0), Kind::Command, 1, seq, 123456789012ull),
                    Body::Position2dVel, body.Union());
  return {f.begin(), f.end()};
}

void feed(FrameReader& r, const uint8_t* data, size_t n) {
  auto space = r.write_space(n);
  ASSERT_GE(space.size(), n);
  std::memcpy(space.data(), data, n);
  r.commit(n);
}

TEST(FrameReader, WholeFrameYieldsOneVerifiedMessage) {
  auto f = vel_frame(0.25f, 7);
  FrameReader r(1024);
  feed(r, f.data(), f.size());
  auto frame = r.next();
  ASSERT_EQ(frame.size(), f.size());
  const Message* msg = verify_frame(frame, Limits{});
  ASSERT_NE(msg, nullptr);
  EXPECT_EQ(msg->header()->seq(), 7u);
  EXPECT_EQ(time_us(*msg->header()), 123456789012ull);
  EXPECT_FLOAT_EQ(msg->body_as_Position2dVel()->vel()->x(), 0.25f);
  EXPECT_TRUE(r.next().empty());
  EXPECT_EQ(r.pending_bytes(), 0u);
}

TEST(FrameReader, FramesSplitAtEveryByteReassemble) {
  auto f = vel_frame(1.5f, 3);
  FrameReader r(1024);
  for (size_t i = 0; i + 1 < f.size(); ++i) {
    feed(r, &f[i], 1);
    EXPECT_TRUE(r.next().empty()) << "frame complete after " << i + 1 << " bytes";
  }
  feed(r, &f.back(), 1);
  auto frame = r.next();
  ASSERT_FALSE(frame.empty());
  EXPECT_NE(verify_frame(frame, Limits{}), nullptr);
}

TEST(FrameReader, CoalescedFramesComeOutInOrder) {
  std::vector<uint8_t> stream;
  for (uint32_t i = 0; i < 50; ++i) {
    auto f = vel_frame(float(i), i);
    stream.insert(stream.end(), f.begin(), f.end());
  }
  // Feed in chunks of varying, seeded sizes: some cut frames, some hold several.
  std::mt19937 rng(42);
  FrameReader r(256);
  std::vector<uint32_t> seen;
  for (size_t pos = 0; pos < stream.size();) {
    size_t n = std::min<size_t>(stream.size() - pos, 1 + rng() % 200);
    feed(r, &stream[pos], n);
    pos += n;
    for (auto frame = r.next(); !frame.empty(); frame = r.next()) {
      const Message* msg = verify_frame(frame, Limits{});
      ASSERT_NE(msg, nullptr);
      seen.push_back(msg->header()->seq());
    }
  }
  ASSERT_EQ(seen.size(), 50u);
  for (uint32_t i = 0; i < 50; ++i) EXPECT_EQ(seen[i], i);
}

TEST(FrameReader, OversizedPrefixIsRefusedBeforeAllocating) {
  FrameReader r(4096);
  const uint8_t huge[4] = {0xFF, 0xFF, 0xFF, 0xFF};  // 4 GiB
  feed(r, huge, 4);
  EXPECT_TRUE(r.next().empty());
  EXPECT_TRUE(r.too_large());
  EXPECT_EQ(r.announced_bytes(), 0xFFFFFFFFu);
  // The buffer did not grow towards the announced size.
  EXPECT_LT(r.write_space(16).size(), 64u * 1024);
}

TEST(FrameReader, FrameExactlyAtTheLimitIsAccepted) {
  auto f = vel_frame(2, 1);
  FrameReader exact(uint32_t(f.size()));
  feed(exact, f.data(), f.size());
  EXPECT_FALSE(exact.next().empty());
  FrameReader smaller(uint32_t(f.size() - 1));
  feed(smaller, f.data(), f.size());
  EXPECT_TRUE(smaller.next().empty());
  EXPECT_TRUE(smaller.too_large());
}

TEST(FrameReader, PartialFrameIsReportedAsPending) {
  auto f = vel_frame(2, 1);
  FrameReader r(1024);
  feed(r, f.data(), f.size() - 5);
  EXPECT_TRUE(r.next().empty());
  EXPECT_EQ(r.pending_bytes(), f.size() - 5);
  EXPECT_EQ(r.pending_frame_bytes(), f.size());
}

TEST(Verify, GarbageIsRefused) {
  std::mt19937 rng(7);
  int refused = 0;
  for (int trial = 0; trial < 200; ++trial) {
    std::vector<uint8_t> junk(4 + rng() % 120);
    for (auto& b : junk) b = uint8_t(rng());
    uint32_t len = uint32_t(junk.size() - 4);
    std::memcpy(junk.data(), &len, 4);  // a consistent prefix: only the body is junk
    VerifyError why{};
    if (verify_frame(junk, Limits{}, &why) == nullptr) {
      ++refused;
      EXPECT_NE(why, VerifyError::None);
    }
  }
  EXPECT_GT(refused, 190);  // random bytes almost never form a valid Message
}

TEST(Verify, PrefixDisagreeingWithFrameIsRefused) {
  auto f = vel_frame(1, 1);
  f[0] += 1;
  VerifyError why{};
  EXPECT_EQ(verify_frame(f, Limits{}, &why), nullptr);
  EXPECT_EQ(why, VerifyError::LengthMismatch);
}

TEST(Verify, TruncatedBufferIsRefused) {
  auto f = vel_frame(1, 1);
  std::vector<uint8_t> cut(f.begin(), f.end() - 8);
  uint32_t len = uint32_t(cut.size() - 4);
  std::memcpy(cut.data(), &len, 4);
  VerifyError why{};
  EXPECT_EQ(verify_frame(cut, Limits{}, &why), nullptr);
  EXPECT_EQ(why, VerifyError::Verifier);
}

TEST(Verify, DepthAndTableLimitsApply) {
  // A device list with many entries: fine by default, refused with a low
  // table limit.
  MessageWriter w;
  auto& b = w.start();
  std::vector<flatbuffers::Offset<DeviceInfo>> infos;
  Address a(0, 1, 0);
  for (int i = 0; i < 100; ++i) infos.push_back(CreateDeviceInfo(b, &a));
  auto body = CreateDeviceList(b, b.CreateVector(infos));
  auto f = w.finish(make_header({}, Kind::DeviceList, 0, 1, 0), Body::DeviceList, body.Union());
  EXPECT_NE(verify_frame(f, Limits{}), nullptr);
  Limits tight;
  tight.max_tables = 10;
  EXPECT_EQ(verify_frame(f, tight), nullptr);
}

TEST(Verify, MessageWithoutHeaderIsRefused) {
  flatbuffers::FlatBufferBuilder b;
  MessageBuilder mb(b);  // no header set
  b.FinishSizePrefixed(mb.Finish());
  VerifyError why{};
  EXPECT_EQ(verify_frame({b.GetBufferPointer(), b.GetSize()}, Limits{}, &why), nullptr);
  EXPECT_EQ(why, VerifyError::NoHeader);
}

}  // namespace
}  // namespace troupe::wire
