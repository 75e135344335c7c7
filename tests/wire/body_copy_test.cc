// BodyCopier: a body copied through the embedded reflection schema into
// another builder is the same message: compared as the JSON text
// FlatBuffers' printer makes of the whole message, so every field counts;
// and the cross-build sample frames (every interface, every field with a
// known value) copied read back field for field.
#include "wire/body_copy.h"

#include <flatbuffers/idl.h>
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "tests/cross/frame_samples.h"
#include "wire/frame.h"
#include "wire/writer.h"

namespace troupe::wire {
namespace {

using Bytes = std::vector<uint8_t>;
using Build = flatbuffers::Offset<void> (*)(flatbuffers::FlatBufferBuilder&);

const wire::Address kAddr(3, 2, 1);

Bytes frame_of(wire::Body type, Build build) {
  wire::MessageWriter w;
  auto& b = w.start();
  auto body = build(b);
  auto f = w.finish(wire::make_header(kAddr, wire::Kind::Data, 1, 9, 123456789012ull), type, body);
  return Bytes(f.begin(), f.end());
}

std::string json(const Bytes& frame) {
  flatbuffers::Parser parser;
  EXPECT_TRUE(parser.Deserialize(message_schema().data(), message_schema().size()));
  std::string text;
  EXPECT_TRUE(flatbuffers::GenerateText(parser, frame.data() + wire::kPrefixBytes, &text));
  return text;
}

struct Case {
  const char* name;
  wire::Body type;
  Build build;
};

const Case kCases[] = {
    {"position2d with fault and covariance", wire::Body::Position2dState,
     [](flatbuffers::FlatBufferBuilder& b) {
       wire::Pose2d pose(1.5f, -2, 0.25f), vel(0.3f, 0, -0.1f);
       wire::Cov2d cov(0.01f, 0.002f, 0, 0.02f, 0, 0.003f);
       return wire::CreatePosition2dState(b, &pose, &vel, true, &cov, b.CreateString("left axis silent"))
           .Union();
     }},
    {"laser scan with intensities", wire::Body::RangerScan,
     [](flatbuffers::FlatBufferBuilder& b) {
       std::vector<uint16_t> ranges;
       std::vector<uint8_t> intensities;
       for (int i = 0; i < 181; ++i) {
         ranges.push_back(uint16_t(1000 + 7 * i));
         intensities.push_back(uint8_t(i));
       }
       return wire::CreateRangerScan(b, b.CreateVector(ranges), 0.002f, -1.57f, 0.0175f, 30,
                                     b.CreateVector(intensities))
           .Union();
     }},
    {"power with only some optional fields", wire::Body::PowerState,
     [](flatbuffers::FlatBufferBuilder& b) {
       wire::PowerStateBuilder p(b);
       p.add_volts(12.5f);
       p.add_charging(false);
       return p.Finish().Union();
     }},
    {"fiducials: a vector of structs", wire::Body::FiducialList,
     [](flatbuffers::FlatBufferBuilder& b) {
       std::vector<wire::Fiducial> f = {{1, 2.0f, 0.5f, 0.1f}, {-1, 4.0f, -1.0f, 3.0f}};
       return wire::CreateFiducialList(b, b.CreateVectorOfStructs(f)).Union();
     }},
    {"device list: a vector of tables with strings", wire::Body::DeviceList,
     [](flatbuffers::FlatBufferBuilder& b) {
       std::vector<flatbuffers::Offset<wire::DeviceInfo>> d;
       for (uint16_t i = 0; i < 3; ++i) {
         wire::Address a(i, 1, 0);
         d.push_back(
             wire::CreateDeviceInfo(b, &a, b.CreateString("r" + std::to_string(i)), b.CreateString("sim")));
       }
       return wire::CreateDeviceList(b, b.CreateVector(d)).Union();
     }},
    {"localize: a vector of structs of structs", wire::Body::LocalizeState,
     [](flatbuffers::FlatBufferBuilder& b) {
       std::vector<wire::Hypothesis> hyps = {
           wire::Hypothesis(wire::Pose2d(1.5f, -2.0f, 0.25f), wire::Cov2d(0.1f, 0, 0, 0.2f, 0, 0.01f), 0.75f),
           wire::Hypothesis(wire::Pose2d(-4.0f, 3.0f, -1.0f), wire::Cov2d(0.3f, 0, 0, 0.3f, 0, 0.05f), 0.25f)};
       return wire::CreateLocalizeState(b, b.CreateVectorOfStructs(hyps), 2, 123456789012ull).Union();
     }},
    {"sim clock: 64-bit fields", wire::Body::SimClock,
     [](flatbuffers::FlatBufferBuilder& b) {
       return wire::CreateSimClock(b, 0x123456789ABCull, 77, true, 2.0f, 1.9f).Union();
     }},
};

TEST(BodyCopier, CopiesEveryKindOfField) {
  BodyCopier copier;
  ASSERT_TRUE(copier.ok());
  for (const Case& c : kCases) {
    SCOPED_TRACE(c.name);
    Bytes original = frame_of(c.type, c.build);
    const wire::Message* msg = wire::verify_frame(original, wire::Limits{});
    ASSERT_NE(msg, nullptr);
    ASSERT_TRUE(copier.can_copy(c.type));
    wire::MessageWriter w;
    auto& b = w.start();
    auto body = copier.copy(b, *msg);
    ASSERT_FALSE(body.IsNull());
    auto f = w.finish(*msg->header(), msg->body_type(), body);
    Bytes copy(f.begin(), f.end());
    ASSERT_NE(wire::verify_frame(copy, wire::Limits{}), nullptr);
    std::string text = json(original);
    EXPECT_NE(text.find("body_type: \"" + std::string(wire::EnumNameBody(c.type)) + "\""), std::string::npos)
        << text;
    EXPECT_EQ(json(copy), text);
  }
}

TEST(BodyCopier, SampleFramesReadBackFieldForField) {
  std::vector<uint8_t> samples;
  cross::write_samples(samples);
  std::vector<uint8_t> copies;
  FrameReader reader(1u << 20);
  auto space = reader.write_space(samples.size());
  std::copy(samples.begin(), samples.end(), space.begin());
  reader.commit(samples.size());
  int n = 0;
  for (auto frame = reader.next(); !frame.empty(); frame = reader.next(), ++n) {
    const Message* msg = verify_frame(frame, Limits{});
    ASSERT_NE(msg, nullptr);
    MessageWriter w;
    auto& b = w.start();
    flatbuffers::Offset<void> body = body_copier().copy(b, *msg);
    std::span<const uint8_t> copy = w.finish(*msg->header(), body.IsNull() ? Body::NONE : msg->body_type(), body);
    copies.insert(copies.end(), copy.begin(), copy.end());
  }
  EXPECT_EQ(n, cross::sample_count());
  EXPECT_EQ(cross::check_samples(copies), "");
}

TEST(BodyCopier, NoBodyAndUnknownTypesGiveNothing) {
  BodyCopier copier;
  wire::MessageWriter w;
  auto f = w.finish(wire::make_header(kAddr, wire::Kind::Data, 1, 1, 1));
  Bytes empty(f.begin(), f.end());
  flatbuffers::FlatBufferBuilder b;
  EXPECT_TRUE(copier.copy(b, *wire::verify_frame(empty, wire::Limits{})).IsNull());
  EXPECT_FALSE(copier.can_copy(wire::Body(200)));
}

}  // namespace
}  // namespace troupe::wire
