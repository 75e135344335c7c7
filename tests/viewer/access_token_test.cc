// The viewer's token (host-sim/viewer/access_token.h): where a request may
// carry it, and that nothing else passes for it.
#include "host-sim/viewer/access_token.h"

#include <gtest/gtest.h>

namespace troupe::viewer {
namespace {

TEST(AccessToken, IsThirtyTwoHexDigitsAndNewEachTime) {
  const std::string a = make_token(), b = make_token();
  EXPECT_EQ(a.size(), 32u);
  EXPECT_EQ(a.find_first_not_of("0123456789abcdef"), std::string::npos) << a;
  EXPECT_NE(a, b);
}

TEST(AccessToken, ComesFromTheQueryElseTheCookie) {
  EXPECT_EQ(presented_token("/?token=abc", ""), "abc");
  EXPECT_EQ(presented_token("/index.html?x=1&token=abc#top", ""), "abc");
  EXPECT_EQ(presented_token("/viewer.js", "theme=dark; troupe_view_token=abc"), "abc");
  EXPECT_EQ(presented_token("/?token=abc", "troupe_view_token=other"), "abc") << "the URL's token wins";
  EXPECT_EQ(presented_token("/?tokens=abc&mytoken=abc", "xtroupe_view_token=abc"), "")
      << "only the exact names count";
  EXPECT_EQ(presented_token("/ws", ""), "");
}

TEST(AccessToken, MatchesOnlyItself) {
  EXPECT_TRUE(token_matches("0123abcd", "0123abcd"));
  EXPECT_FALSE(token_matches("0123abce", "0123abcd"));
  EXPECT_FALSE(token_matches("0123abc", "0123abcd"));
  EXPECT_FALSE(token_matches("", "")) << "no token set lets nothing in by this check";
}

}  // namespace
}  // namespace troupe::viewer
