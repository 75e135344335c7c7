#include <gtest/gtest.h>

#include "wire/address.h"

namespace troupe::wire {
namespace {

TEST(ParseDevice, PlayerStyleAddresses) {
  DeviceSpec d;
  std::string err;
  ASSERT_TRUE(parse_device("position2d:0", d, err));
  EXPECT_EQ(d.robot, "");
  EXPECT_EQ(d.iface, Interface::Position2d);
  EXPECT_EQ(d.index, 0);
  ASSERT_TRUE(parse_device("r3/ranger:12", d, err));
  EXPECT_EQ(d.robot, "r3");
  EXPECT_EQ(d.iface, Interface::Ranger);
  EXPECT_EQ(d.index, 12);
  ASSERT_TRUE(parse_device("7/simulation:0", d, err));
  EXPECT_EQ(robot_number(d.robot), 7);
  EXPECT_EQ(robot_number("r3"), -1);
  EXPECT_EQ(robot_number(""), 0);
}

TEST(ParseDevice, BadAddressesSayWhy) {
  DeviceSpec d;
  std::string err;
  EXPECT_FALSE(parse_device("position2d", d, err));
  EXPECT_NE(err.find("INTERFACE:INDEX"), std::string::npos);
  EXPECT_FALSE(parse_device("laser:0", d, err));
  EXPECT_NE(err.find("unknown interface 'laser'"), std::string::npos);
  EXPECT_FALSE(parse_device("ranger:x", d, err));
  EXPECT_NE(err.find("bad index"), std::string::npos);
  EXPECT_FALSE(parse_device("ranger:70000", d, err));
  EXPECT_FALSE(parse_device("/ranger:0", d, err));
  EXPECT_FALSE(parse_device("ranger:-1", d, err));
}

TEST(FormatAddress, RoundTripsThroughParse) {
  EXPECT_EQ(format_address(Address(0, uint16_t(Interface::Position2d), 0)), "position2d:0");
  EXPECT_EQ(format_address(Address(4, uint16_t(Interface::Ranger), 1)), "4/ranger:1");
  EXPECT_EQ(format_address(Address(4, uint16_t(Interface::Ranger), 1), "r4"), "r4/ranger:1");
  DeviceSpec d;
  std::string err;
  ASSERT_TRUE(parse_device(format_address(Address(9, uint16_t(Interface::Fiducial), 2)), d, err));
  EXPECT_EQ(robot_number(d.robot), 9);
  EXPECT_EQ(d.iface, Interface::Fiducial);
  EXPECT_EQ(d.index, 2);
}

TEST(ParseHost, HostAndPortForms) {
  HostPort hp;
  std::string err;
  ASSERT_TRUE(parse_host("localhost", hp, err));
  EXPECT_EQ(hp.host, "localhost");
  EXPECT_EQ(hp.port, kDefaultPort);
  ASSERT_TRUE(parse_host("10.0.0.7:6670", hp, err));
  EXPECT_EQ(hp.host, "10.0.0.7");
  EXPECT_EQ(hp.port, 6670);
  ASSERT_TRUE(parse_host("[::1]:7000", hp, err));
  EXPECT_EQ(hp.host, "::1");
  EXPECT_EQ(hp.port, 7000);
  ASSERT_TRUE(parse_host("[::1]", hp, err));
  EXPECT_EQ(hp.port, kDefaultPort);
}

TEST(ParseHost, BadHostsSayWhy) {
  HostPort hp;
  std::string err;
  EXPECT_FALSE(parse_host("", hp, err));
  EXPECT_FALSE(parse_host("host:", hp, err));
  EXPECT_FALSE(parse_host("host:0", hp, err));
  EXPECT_FALSE(parse_host("host:99999", hp, err));
  EXPECT_NE(err.find("bad port"), std::string::npos);
  EXPECT_FALSE(parse_host("::1", hp, err));
  EXPECT_NE(err.find("brackets"), std::string::npos);
  EXPECT_FALSE(parse_host("[::1", hp, err));
}

}  // namespace
}  // namespace troupe::wire
