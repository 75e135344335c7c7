// copy_body: every body the passthrough forwards is rebuilt from the
// protocol's binary schema. The cross-build sample frames (every field with
// a known value) are copied and must read back field for field; bodies with
// vectors of tables, strings and structs are checked by hand.
#include "drivers/passthrough/body_copy.h"

#include <gtest/gtest.h>

#include <vector>

#include "tests/cross/frame_samples.h"
#include "wire/frame.h"
#include "wire/writer.h"

namespace troupe::drivers::passthrough {
namespace {

// Rebuilds `frame` with its header and a copy of its body.
std::vector<uint8_t> recopy(std::span<const uint8_t> frame) {
  const wire::Message* msg = wire::verify_frame(frame, wire::Limits{});
  EXPECT_NE(msg, nullptr);
  if (msg == nullptr) return {};
  wire::MessageWriter w;
  auto& b = w.start();
  flatbuffers::Offset<void> body = copy_body(b, *msg);
  std::span<const uint8_t> out =
      w.finish(*msg->header(), body.IsNull() ? wire::Body::NONE : msg->body_type(), body);
  return {out.begin(), out.end()};
}

TEST(BodyCopy, SampleFramesReadBackFieldForField) {
  std::vector<uint8_t> samples;
  cross::write_samples(samples);
  std::vector<uint8_t> copies;
  wire::FrameReader reader(1u << 20);
  auto space = reader.write_space(samples.size());
  std::copy(samples.begin(), samples.end(), space.begin());
  reader.commit(samples.size());
  int n = 0;
  for (auto frame = reader.next(); !frame.empty(); frame = reader.next(), ++n) {
    std::vector<uint8_t> copy = recopy(frame);
    copies.insert(copies.end(), copy.begin(), copy.end());
  }
  EXPECT_EQ(n, cross::sample_count());
  EXPECT_EQ(cross::check_samples(copies), "");
}

TEST(BodyCopy, VectorsOfTablesStringsAndStructsSurvive) {
  wire::MessageWriter w;
  auto& b = w.start();
  std::vector<flatbuffers::Offset<wire::DeviceInfo>> infos;
  for (uint16_t i = 0; i < 3; ++i) {
    wire::Address a(7, uint16_t(wire::Interface::Ranger), i);
    infos.push_back(
        wire::CreateDeviceInfo(b, &a, b.CreateString("r7"), b.CreateString("laser" + std::to_string(i))));
  }
  auto list = wire::CreateDeviceList(b, b.CreateVector(infos));
  std::span<const uint8_t> built =
      w.finish(wire::make_header({}, wire::Kind::DeviceList, 0, 5, 99), wire::Body::DeviceList, list.Union());
  std::vector<uint8_t> copy = recopy({built.begin(), built.end()});
  const wire::Message* m = wire::verify_frame(copy, wire::Limits{});
  ASSERT_NE(m, nullptr);
  const wire::DeviceList* d = m->body_as_DeviceList();
  ASSERT_NE(d, nullptr);
  ASSERT_EQ(d->devices()->size(), 3u);
  EXPECT_EQ(d->devices()->Get(2)->addr()->index(), 2);
  EXPECT_EQ(d->devices()->Get(2)->addr()->robot(), 7);
  EXPECT_EQ(d->devices()->Get(1)->driver()->str(), "laser1");
  EXPECT_EQ(d->devices()->Get(0)->robot_name()->str(), "r7");

  auto& lb = w.start();
  std::vector<wire::Hypothesis> hyps = {
      wire::Hypothesis(wire::Pose2d(1.5f, -2.0f, 0.25f), wire::Cov2d(0.1f, 0, 0, 0.2f, 0, 0.01f), 0.75f),
      wire::Hypothesis(wire::Pose2d(-4.0f, 3.0f, -1.0f), wire::Cov2d(0.3f, 0, 0, 0.3f, 0, 0.05f), 0.25f)};
  auto state = wire::CreateLocalizeState(lb, lb.CreateVectorOfStructs(hyps), 2, 123456789012ull);
  built =
      w.finish(wire::make_header({}, wire::Kind::Data, 1, 6, 100), wire::Body::LocalizeState, state.Union());
  copy = recopy({built.begin(), built.end()});
  m = wire::verify_frame(copy, wire::Limits{});
  ASSERT_NE(m, nullptr);
  const wire::LocalizeState* s = m->body_as_LocalizeState();
  ASSERT_NE(s, nullptr);
  ASSERT_EQ(s->hypotheses()->size(), 2u);
  EXPECT_EQ(s->hypotheses()->Get(1)->mean().x(), -4.0f);
  EXPECT_EQ(s->hypotheses()->Get(0)->cov().yy(), 0.2f);
  EXPECT_EQ(s->hypotheses()->Get(0)->weight(), 0.75f);
  EXPECT_EQ(s->pending(), 2);
  EXPECT_EQ(s->pending_time_us(), 123456789012ull);
}

TEST(BodyCopy, NoBodyGivesNoBody) {
  wire::MessageWriter w;
  std::span<const uint8_t> built = w.empty(wire::make_header({}, wire::Kind::Pull, 0, 1, 2));
  std::vector<uint8_t> copy = recopy({built.begin(), built.end()});
  const wire::Message* m = wire::verify_frame(copy, wire::Limits{});
  ASSERT_NE(m, nullptr);
  EXPECT_EQ(m->body_type(), wire::Body::NONE);
}

}  // namespace
}  // namespace troupe::drivers::passthrough
