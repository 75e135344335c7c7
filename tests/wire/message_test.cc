#include <gtest/gtest.h>

#include "wire/message.h"

namespace troupe::wire {
namespace {

constexpr uint16_t kPos = uint16_t(Interface::Position2d);
constexpr uint16_t kRanger = uint16_t(Interface::Ranger);

TEST(Message, InterfaceNamesRoundTrip) {
  for (uint16_t i = 1; i <= uint16_t(Interface::MAX); ++i) {
    EXPECT_EQ(uint16_t(interface_from_name(interface_name(i))), i);
  }
  EXPECT_EQ(interface_from_name("nosuch"), Interface::None);
  EXPECT_EQ(interface_name(999), "unknown");
}

TEST(Message, HeaderTimeKeepsAll64Bits) {
  uint64_t t = 0x0123456789ABCDEFull;
  Header h = make_header(Address(), Kind::Data, 1, 2, t);
  EXPECT_EQ(time_us(h), t);
}

TEST(Message, BodiesFitTheirKindAndInterface) {
  EXPECT_TRUE(body_fits(Kind::Command, kPos, Body::Position2dVel));
  EXPECT_FALSE(body_fits(Kind::Command, kRanger, Body::Position2dVel));
  EXPECT_TRUE(body_fits(Kind::Request, kRanger, Body::Switch));  // any interface
  EXPECT_TRUE(body_fits(Kind::Request, kPos, Body::NONE));
  EXPECT_FALSE(body_fits(Kind::Data, kPos, Body::NONE));
  EXPECT_TRUE(body_fits(Kind::Open, kPos, Body::Open));
  EXPECT_FALSE(body_fits(Kind::Open, kPos, Body::Position2dVel));
  EXPECT_FALSE(body_fits(Kind::Hello, 0, Body::Error));
  EXPECT_FALSE(body_fits(Kind::Close, kPos, Body::Open));
  EXPECT_FALSE(body_fits(Kind::Command, kPos, Body(250)));
  EXPECT_FALSE(is_known_body(Body(250)));
}

TEST(Message, EveryBodyBelongsToAKnownInterface) {
  for (uint8_t b = 1; b <= uint8_t(Body::MAX); ++b) {
    uint16_t owner = body_interface(Body(b));
    EXPECT_TRUE(owner == kAnyInterface || owner <= uint16_t(Interface::MAX)) << EnumNameBody(Body(b));
  }
}

}  // namespace
}  // namespace troupe::wire
