// Bad input from one client gets that client an Error and a close; every
// other client and driver goes on untouched.
#include <gtest/gtest.h>

#include <cstring>
#include <random>

#include "tests/runtime/node_fixture.h"
#include "tests/wire/samples.h"
#include "wire/client/proxies.h"

namespace troupe::testing {
namespace {

using wire::ErrorCode;
using wire::Interface;
using wire::Kind;

class BadInput : public ::testing::Test {
 protected:
  void SetUp() override {
    recorder_ = new Recorder;
    node_.add_device(Interface::Ranger, 0, recorder_);
    node_.add_device(Interface::Position2d, 0, new Recorder);
    node_.start();
    recorder_->stream(5);
    good_ = std::make_unique<client::Client>("127.0.0.1", node_.port());
    ASSERT_TRUE(good_->connect());
    scans_ = std::make_unique<client::RangerProxy>(*good_);
    ASSERT_TRUE(scans_->is_open());
  }

  // The offender gets an Error with `code` and is closed.
  void expect_error_and_close(RawConnection& raw, ErrorCode code) {
    auto f = raw.read_until(Kind::Error);
    ASSERT_FALSE(f.empty()) << "no Error frame";
    const wire::Error* e = wire::trusted_message(f)->body_as_Error();
    ASSERT_NE(e, nullptr);
    EXPECT_EQ(e->code(), code) << (e->text() ? e->text()->c_str() : "");
    EXPECT_TRUE(raw.wait_closed());
  }

  // The well-behaved client still gets data and answers.
  void expect_others_served() {
    uint64_t before = scans_->samples();
    for (int i = 0; i < 300 && scans_->samples() < before + 3; ++i) good_->spin_once(10);
    EXPECT_GE(scans_->samples(), before + 3);
    EXPECT_TRUE(good_->sync());
    std::vector<client::DeviceEntry> list;
    EXPECT_TRUE(good_->device_list(list));
    EXPECT_EQ(list.size(), 2u);
  }

  RawConnection connect_raw() {
    RawConnection raw(node_.port());
    EXPECT_TRUE(raw.ok());
    EXPECT_FALSE(raw.read_until(Kind::Hello).empty());
    return raw;
  }

  NodeThread node_{test_options()};
  Recorder* recorder_ = nullptr;
  std::unique_ptr<client::Client> good_;
  std::unique_ptr<client::RangerProxy> scans_;
};

TEST_F(BadInput, GarbageBytes) {
  RawConnection raw = connect_raw();
  // A sane length prefix followed by random bytes: the verifier refuses it.
  std::mt19937 rng(1);
  std::vector<uint8_t> junk(64);
  for (auto& b : junk) b = uint8_t(rng());
  uint32_t len = 60;
  std::memcpy(junk.data(), &len, 4);
  ASSERT_TRUE(raw.send_bytes(junk));
  expect_error_and_close(raw, ErrorCode::VerifyFailed);
  expect_others_served();
}

TEST_F(BadInput, FourGibibyteLengthPrefix) {
  RawConnection raw = connect_raw();
  const uint8_t huge[] = {0xFF, 0xFF, 0xFF, 0xFF, 1, 2, 3, 4};
  ASSERT_TRUE(raw.send_bytes(huge));
  expect_error_and_close(raw, ErrorCode::BadFrame);
  expect_others_served();
}

TEST_F(BadInput, TruncatedFrame) {
  RawConnection raw = connect_raw();
  auto f = vel_frame(addr(Interface::Position2d), 1, 1);
  ASSERT_TRUE(raw.send_bytes(std::span(f).first(f.size() - 10)));
  raw.shutdown_write();  // the stream ends inside the frame
  expect_error_and_close(raw, ErrorCode::BadFrame);
  expect_others_served();
}

TEST_F(BadInput, BodyOfTheWrongInterface) {
  RawConnection raw = connect_raw();
  // A position2d velocity sent as a command to a ranger.
  ASSERT_TRUE(raw.send_bytes(vel_frame(addr(Interface::Ranger), 1, 1)));
  expect_error_and_close(raw, ErrorCode::BadBody);
  expect_others_served();
}

TEST_F(BadInput, BodyThatDoesNotFitTheKind) {
  RawConnection raw = connect_raw();
  wire::MessageWriter w;
  auto& b = w.start();
  wire::Pose2d vel(1, 0, 0);
  auto body = wire::CreatePosition2dVel(b, &vel);
  auto f = w.finish(wire::make_header(addr(Interface::Position2d), Kind::Open, 0, 1, 0), wire::Body::Position2dVel,
                    body.Union());
  ASSERT_TRUE(raw.send_bytes(f));
  expect_error_and_close(raw, ErrorCode::BadBody);
  expect_others_served();
}

TEST_F(BadInput, UnionTypeOutOfRangeIsRefusedPolitely) {
  // A body type this node does not know (a newer peer's): Nack, and the
  // connection stays.
  RawConnection raw = connect_raw();
  wire::MessageWriter w;
  auto& b = w.start();
  auto body = wire::CreateSwitch(b, true);
  auto f = w.finish(wire::make_header(addr(Interface::Position2d), Kind::Request, 1, 42, 0), wire::Body(200),
                    body.Union());
  ASSERT_TRUE(raw.send_bytes(f));
  auto nack = raw.read_until(Kind::Nack);
  ASSERT_FALSE(nack.empty());
  const wire::Message* m = wire::trusted_message(nack);
  EXPECT_EQ(m->header()->seq(), 42u);
  EXPECT_EQ(m->body_as_Error()->code(), ErrorCode::Unsupported);
  ASSERT_TRUE(raw.send_bytes(empty_frame({}, Kind::DeviceList, 0, 43)));
  EXPECT_FALSE(raw.read_until(Kind::DeviceList).empty());
  expect_others_served();
}

TEST_F(BadInput, ClientsDoNotSendData) {
  RawConnection raw = connect_raw();
  wire::MessageWriter w;
  auto& b = w.start();
  auto body = wire::CreateRangerScan(b, b.CreateVector(std::vector<uint16_t>{1, 2, 3}));
  ASSERT_TRUE(raw.send_bytes(w.finish(wire::make_header(addr(Interface::Ranger), Kind::Data, 1, 1, 0),
                                      wire::Body::RangerScan, body.Union())));
  expect_error_and_close(raw, ErrorCode::BadBody);
  expect_others_served();
}

TEST_F(BadInput, WrongProtocolVersion) {
  RawConnection raw = connect_raw();
  wire::MessageWriter w;
  auto& b = w.start();
  auto hello = wire::CreateHello(b, 99, b.CreateString("from the future"));
  ASSERT_TRUE(raw.send_bytes(w.finish(wire::make_header({}, Kind::Hello, 0, 0, 0), wire::Body::Hello, hello.Union())));
  expect_error_and_close(raw, ErrorCode::VersionMismatch);
  expect_others_served();
}

// A union type with no body behind it passes the FlatBuffers verifier (an
// absent table is valid). A Hello or TimeSync like that, 44 bytes, once
// crashed the node through a null pointer.
std::vector<uint8_t> body_type_without_body(const wire::Address& a, Kind kind, uint8_t subtype, uint32_t seq,
                                            wire::Body type) {
  flatbuffers::FlatBufferBuilder b;
  wire::Header h = wire::make_header(a, kind, subtype, seq, 5);
  wire::MessageBuilder mb(b);
  mb.add_body_type(type);
  mb.add_header(&h);
  b.FinishSizePrefixed(mb.Finish());
  return {b.GetBufferPointer(), b.GetBufferPointer() + b.GetSize()};
}

TEST_F(BadInput, HelloWithoutItsBody) {
  RawConnection raw = connect_raw();
  auto f = body_type_without_body({}, Kind::Hello, 0, 7, wire::Body::Hello);
  EXPECT_EQ(f.size(), 44u);
  ASSERT_TRUE(raw.send_bytes(f));
  expect_error_and_close(raw, ErrorCode::BadBody);
  expect_others_served();
}

TEST_F(BadInput, TimeSyncWithoutItsBody) {
  RawConnection raw = connect_raw();
  ASSERT_TRUE(raw.send_bytes(body_type_without_body({}, Kind::TimeSync, 0, 8, wire::Body::TimeSync)));
  expect_error_and_close(raw, ErrorCode::BadBody);
  expect_others_served();
}

// Every command and request the schemas define, its body type set with no
// body behind it, left out where it is required, or of another type: a Nack
// BadBody echoing its seq, and the connection goes on.
TEST_F(BadInput, EveryDeviceMessageWithAMissingOrWrongBody) {
  RawConnection raw = connect_raw();
  uint32_t seq = 100;
  auto expect_nack = [&](std::span<const uint8_t> f, ErrorCode code, const std::string& what) {
    ASSERT_TRUE(raw.send_bytes(f));
    ASSERT_TRUE(raw.send_bytes(empty_frame({}, Kind::DeviceList, 0, 1)));  // after any reply
    auto nack = raw.read_until(Kind::Nack);
    ASSERT_FALSE(nack.empty()) << what << ": no Nack";
    const wire::Message* m = wire::trusted_message(nack);
    EXPECT_EQ(m->header()->seq(), seq) << what;
    EXPECT_EQ(m->header()->subtype(), wire::trusted_message(f)->header()->subtype()) << what;
    EXPECT_TRUE(m->header()->addr() == wire::trusted_message(f)->header()->addr()) << what;
    EXPECT_EQ(m->body_as_Error()->code(), code) << what << ": " << m->body_as_Error()->text()->str();
    ASSERT_FALSE(raw.read_until(Kind::DeviceList).empty()) << what;
  };
  wire::MessageWriter w;
  for (const wire::BodyRule& r : wire::body_rules()) {
    const wire::Address a(0, uint16_t(r.iface), 0);
    const std::string what = std::string(wire::interface_name(uint16_t(r.iface))) + " " +
                             std::string(wire::kind_name(r.kind)) + " " + std::to_string(r.subtype);
    if (r.body != wire::Body::NONE) {
      ++seq;
      expect_nack(body_type_without_body(a, r.kind, r.subtype, seq, r.body), ErrorCode::BadBody, what + " (null body)");
    }
    if (r.required) {
      ++seq;
      expect_nack(empty_frame(a, r.kind, r.subtype, seq), ErrorCode::BadBody, what + " (no body)");
    }
    // A body of its interface that is not the one the subtype takes.
    for (const wire::BodyRule& other : wire::body_rules()) {
      if (other.iface != r.iface || other.body == r.body || other.body == wire::Body::NONE) continue;
      auto& b = w.start();
      auto body = sample_body(b, other.body);
      ++seq;
      auto f = w.finish(wire::make_header(a, r.kind, r.subtype, seq, 0), other.body, body);
      expect_nack(f, ErrorCode::BadBody, what + " carrying " + wire::EnumNameBody(other.body));
      break;
    }
  }
  expect_others_served();
}

// A command of a subtype its interface does not define was dropped without
// a word; now it is answered.
TEST_F(BadInput, CommandOfAnUnknownSubtypeIsAnswered) {
  RawConnection raw = connect_raw();
  wire::MessageWriter w;
  auto& b = w.start();
  wire::Pose2d vel(0.1f, 0, 0);
  auto body = wire::CreatePosition2dVel(b, &vel);
  auto f = w.finish(wire::make_header(addr(Interface::Position2d), Kind::Command, 77, 55, 0),
                    wire::Body::Position2dVel, body.Union());
  ASSERT_TRUE(raw.send_bytes(f));
  auto nack = raw.read_until(Kind::Nack);
  ASSERT_FALSE(nack.empty());
  const wire::Message* m = wire::trusted_message(nack);
  EXPECT_EQ(m->header()->seq(), 55u);
  EXPECT_EQ(m->header()->subtype(), 77);
  EXPECT_EQ(m->body_as_Error()->code(), ErrorCode::Unsupported);
  // A ranger takes no commands at all.
  ASSERT_TRUE(raw.send_bytes(empty_frame(addr(Interface::Ranger), Kind::Command, 1, 56)));
  nack = raw.read_until(Kind::Nack);
  ASSERT_FALSE(nack.empty());
  EXPECT_EQ(wire::trusted_message(nack)->header()->seq(), 56u);
  expect_others_served();
}

// An Error names the frame it answers: its address, subtype and seq (they
// were all zero), whenever the header itself could be read.
TEST_F(BadInput, ErrorsEchoTheOffendingHeader) {
  {
    RawConnection raw = connect_raw();
    ASSERT_TRUE(raw.send_bytes(vel_frame(addr(Interface::Ranger, 0, 3), 1, 4242)));
    auto f = raw.read_until(Kind::Error);
    ASSERT_FALSE(f.empty());
    const wire::Header& h = *wire::trusted_message(f)->header();
    EXPECT_EQ(h.seq(), 4242u);
    EXPECT_EQ(h.subtype(), 1);
    EXPECT_TRUE(h.addr() == addr(Interface::Ranger, 0, 3));
  }
  {
    // A sound header over a broken body: a string whose length runs past the
    // end of the frame.
    RawConnection raw = connect_raw();
    wire::MessageWriter w;
    auto& b = w.start();
    auto body = wire::CreateSimModel(b, b.CreateString("r0"));
    auto built = w.finish(wire::make_header(addr(Interface::Simulation), Kind::Request, 5, 4343, 0),
                          wire::Body::SimModel, body.Union());
    std::vector<uint8_t> f(built.begin(), built.end());
    const auto* name = wire::trusted_message(f)->body_as_SimModel()->name();
    const size_t length_at = size_t(reinterpret_cast<const uint8_t*>(name) - f.data());
    const uint32_t huge = 100000;
    std::memcpy(f.data() + length_at, &huge, 4);
    ASSERT_TRUE(raw.send_bytes(f));
    auto e = raw.read_until(Kind::Error);
    ASSERT_FALSE(e.empty());
    const wire::Message* m = wire::trusted_message(e);
    EXPECT_EQ(m->body_as_Error()->code(), ErrorCode::VerifyFailed);
    EXPECT_EQ(m->header()->seq(), 4343u);
    EXPECT_TRUE(m->header()->addr() == addr(Interface::Simulation));
  }
  expect_others_served();
}

TEST_F(BadInput, ManyOffendersInARow) {
  for (int i = 0; i < 20; ++i) {
    RawConnection raw = connect_raw();
    const uint8_t junk[] = {8, 0, 0, 0, 0xde, 0xad, 0xbe, 0xef, 0, 0, 0, 0};
    ASSERT_TRUE(raw.send_bytes(junk));
    expect_error_and_close(raw, ErrorCode::VerifyFailed);
  }
  expect_others_served();
}

}  // namespace
}  // namespace troupe::testing
