// Which WebSocket handshakes the viewer accepts: its own page (under an
// address, localhost or this machine's name), clients that are not
// browsers, and origins allowed by option; never a foreign page, never a
// page under a rebound name.
#include "host-sim/viewer/origin_check.h"

#include <gtest/gtest.h>

namespace troupe::viewer {
namespace {

const std::vector<std::string> kNone;
const std::vector<std::string> kMachine = {"robot1"};

bool allowed(std::string_view host, std::string_view origin, const std::vector<std::string>& allow = kNone) {
  return check_origin(host, origin, allow, kMachine).allowed;
}

TEST(OriginCheck, TheViewersOwnPageIsAccepted) {
  EXPECT_TRUE(allowed("127.0.0.1:6680", "http://127.0.0.1:6680"));
  EXPECT_TRUE(allowed("localhost:6680", "http://localhost:6680"));
  EXPECT_TRUE(allowed("LOCALHOST:6680", "http://localhost:6680/"));
  EXPECT_TRUE(allowed("[::1]:6680", "http://[::1]:6680"));
  EXPECT_TRUE(allowed("10.0.0.7:6680", "http://10.0.0.7:6680"));
  EXPECT_TRUE(allowed("robot1:6680", "http://robot1:6680"));
  EXPECT_TRUE(allowed("localhost.:6680", "http://localhost.:6680"));
  EXPECT_TRUE(allowed("127.0.0.1", "http://127.0.0.1"));  // port 80
}

TEST(OriginCheck, ClientsThatAreNotBrowsersAreAccepted) {
  // No Origin: not a browser (it would send one), so no web page behind it.
  EXPECT_TRUE(allowed("127.0.0.1:6680", ""));
  EXPECT_TRUE(allowed("127.0.0.1", ""));
}

TEST(OriginCheck, ForeignPagesAreRefused) {
  for (const char* origin : {"http://evil.example", "null", "https://127.0.0.1:6680", "http://127.0.0.1:6681",
                             "http://127.0.0.1:6680.evil.example", "http://localhost:6680", "file://"}) {
    const OriginVerdict v = check_origin("127.0.0.1:6680", origin, kNone, kMachine);
    EXPECT_FALSE(v.allowed) << origin;
    EXPECT_NE(v.why.find("may not use this viewer"), std::string::npos) << v.why;
  }
}

TEST(OriginCheck, ReboundNamesAreRefused) {
  // DNS rebinding: the attacker's name points at this machine, so the
  // browser sends that name as Host and its own page as Origin.
  for (const char* host : {"evil.example:6680", "127.0.0.1.evil.example:6680", "localhost.evil.example:6680",
                           "robot1.evil.example:6680", "", "[evil.example]:6680", "[::1"}) {
    const OriginVerdict v = check_origin(host, "http://" + std::string(host), kNone, kMachine);
    EXPECT_FALSE(v.allowed) << host;
    EXPECT_FALSE(check_origin(host, "", kNone, kMachine).allowed) << host;
  }
  EXPECT_NE(check_origin("evil.example:6680", "", kNone, kMachine).why.find("DNS rebinding"),
            std::string::npos);
}

TEST(OriginCheck, AnAllowedOriginIsAcceptedWhateverTheHost) {
  const std::vector<std::string> allow = {"http://robots.lab:8080", "https://viewer.example/"};
  EXPECT_TRUE(allowed("robots.lab:8080", "http://robots.lab:8080", allow));
  EXPECT_TRUE(allowed("127.0.0.1:6680", "http://ROBOTS.lab:8080", allow));  // behind a proxy
  EXPECT_TRUE(allowed("viewer.example", "https://viewer.example", allow));
  EXPECT_FALSE(allowed("robots.lab:8080", "http://robots.lab:8081", allow));
  EXPECT_FALSE(allowed("robots.lab:8080", "", allow));  // the name still is not ours
}

}  // namespace
}  // namespace troupe::viewer
