// Which URL paths the viewer's HTTP server turns into files: only plain
// names in its web root, never anything above it.
#include "host-sim/viewer/web_files.h"

#include <gtest/gtest.h>

namespace troupe::viewer {
namespace {

TEST(WebFiles, PlainNamesAreServed) {
  EXPECT_EQ(web_file_name("/"), "index.html");
  EXPECT_EQ(web_file_name("/?x=1"), "index.html");
  EXPECT_EQ(web_file_name("/viewer.js"), "viewer.js");
  EXPECT_EQ(web_file_name("/viewer.js.map#top"), "viewer.js.map");
}

TEST(WebFiles, NothingOutsideTheRoot) {
  for (const char* bad : {"", "viewer.js", "/../etc/passwd", "/..", "/.hidden", "/a/b.js", "/a%2fb", "/a\\b",
                          "//etc/passwd", "/x y"}) {
    EXPECT_EQ(web_file_name(bad), "") << bad;
  }
  EXPECT_EQ(web_file_name("/" + std::string(65, 'a')), "");
}

TEST(WebFiles, ContentTypes) {
  EXPECT_EQ(content_type("index.html"), "text/html; charset=utf-8");
  EXPECT_EQ(content_type("viewer.js"), "text/javascript; charset=utf-8");
  EXPECT_EQ(content_type("viewer.css"), "text/css; charset=utf-8");
  EXPECT_EQ(content_type("shot.png"), "image/png");
  EXPECT_EQ(content_type("blob"), "application/octet-stream");
}

}  // namespace
}  // namespace troupe::viewer
