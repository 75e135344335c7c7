// Addresses to try and their order: RFC 8305's interleaving of families,
// numeric addresses, and the node loop's resolver refusing names.
#include "wire/connection/resolver.h"

#include <gtest/gtest.h>

#include "tests/wire/hosts_resolver.h"

namespace troupe::wire {
namespace {

std::vector<std::string> texts(const std::vector<Endpoint>& endpoints) {
  std::vector<std::string> out;
  for (const Endpoint& e : endpoints) out.push_back(e.text());
  return out;
}

Endpoint at(const char* address) {
  Endpoint e;
  EXPECT_TRUE(parse_endpoint(address, 6665, e)) << address;
  return e;
}

TEST(Resolver, NumericAddressesInEveryForm) {
  EXPECT_EQ(at("127.0.0.1").text(), "127.0.0.1:6665");
  EXPECT_EQ(at("::1").text(), "[::1]:6665");
  EXPECT_EQ(at("[::1]").text(), "[::1]:6665");
  Endpoint e;
  EXPECT_FALSE(parse_endpoint("localhost", 1, e));
  EXPECT_FALSE(parse_endpoint("300.1.1.1", 1, e));
}

TEST(Resolver, FamiliesAlternateStartingWithTheFirst) {
  std::vector<Endpoint> e = {at("2001:db8::1"), at("2001:db8::2"), at("2001:db8::3"), at("192.0.2.1"),
                             at("192.0.2.2")};
  interleave_families(e);
  EXPECT_EQ(texts(e), (std::vector<std::string>{"[2001:db8::1]:6665", "192.0.2.1:6665", "[2001:db8::2]:6665",
                                                "192.0.2.2:6665", "[2001:db8::3]:6665"}));
  std::vector<Endpoint> v4_first = {at("192.0.2.1"), at("2001:db8::1")};
  interleave_families(v4_first);
  EXPECT_EQ(texts(v4_first), (std::vector<std::string>{"192.0.2.1:6665", "[2001:db8::1]:6665"}));
}

TEST(Resolver, TheNodeLoopsResolverTakesNumbersAndLocalhostOnly) {
  std::vector<Endpoint> out;
  std::string error;
  ASSERT_TRUE(resolve_numeric("::1", 7000, out, error));
  EXPECT_EQ(texts(out), std::vector<std::string>{"[::1]:7000"});
  ASSERT_TRUE(resolve_numeric("localhost", 7000, out, error)) << error;
  EXPECT_FALSE(out.empty());
  EXPECT_FALSE(resolve_numeric("robot.example", 7000, out, error));
  EXPECT_NE(error.find("not a numeric address"), std::string::npos) << error;
}

TEST(Resolver, TheSystemResolverSaysWhyANameFails) {
  std::vector<Endpoint> out;
  std::string error;
  EXPECT_FALSE(resolve_system("no-such-host.invalid", 1, out, error));
  EXPECT_EQ(error.rfind("cannot resolve host 'no-such-host.invalid': ", 0), 0u) << error;
}

TEST(Resolver, TheTestHostsFileGivesLocalhostAsDebianDoes) {
  std::vector<Endpoint> out;
  std::string error;
  ASSERT_TRUE(testing::hosts_resolver(testing::kDebianHosts)("localhost", 6665, out, error)) << error;
  EXPECT_EQ(texts(out), (std::vector<std::string>{"[::1]:6665", "127.0.0.1:6665"}));
}

}  // namespace
}  // namespace troupe::wire
