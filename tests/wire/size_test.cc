// The wire sizes wire/README.md promises, measured from the real encoder.
#include <gtest/gtest.h>

#include "tests/bench/wire/sizes.h"

namespace troupe::wire::sizes {
namespace {

const Row& row(const std::string& message, const std::string& contents) {
  static const std::vector<Row> all = rows();
  for (const Row& r : all) {
    if (r.message == message && r.contents == contents) return r;
  }
  throw std::runtime_error("no row " + message + " / " + contents);
}

TEST(WireSize, Position2dIsSmallerThanPlayers) {
  const Row& r = row("position2d", "pose, velocity, stall");
  EXPECT_EQ(r.player_bytes, 92u);  // the figure the design quotes
  EXPECT_LE(r.troupe_bytes, 88u);
}

TEST(WireSize, PowerVoltsIsNoLargerThanPlayers) {
  const Row& r = row("power", "volts");
  EXPECT_LE(r.troupe_bytes, r.player_bytes);
}

TEST(WireSize, ScansTilesAndLandmarkListsAreAtMostHalfOfPlayers) {
  for (const char* c : {"181-beam laser scan", "361-beam laser scan"}) {
    const Row& r = row("ranger", c);
    EXPECT_LE(2 * r.troupe_bytes, r.player_bytes) << c;
  }
  for (const char* c : {"4 landmarks", "16 landmarks"}) {
    const Row& r = row("fiducial", c);
    EXPECT_LE(2 * r.troupe_bytes, r.player_bytes) << c;
  }
  for (const char* c : {"64x64 tile", "256x256 tile"}) {
    const Row& r = row("map", c);
    EXPECT_LE(2 * r.troupe_bytes, r.player_bytes) << c;
  }
  // Two bits a cell: a big tile is a quarter of Player's byte a cell.
  const Row& big = row("map", "256x256 tile");
  EXPECT_LT(double(big.troupe_bytes), 0.26 * double(big.player_bytes));
}

// Raw pixels are the same bytes in both protocols: an image can only be
// smaller through compression (PNG, below). A raw one's envelope is held to
// within a few dozen bytes of Player's.
TEST(WireSize, AnUncompressedImageCostsAtMostPlayersBytesPlusTheEnvelope) {
  int images = 0;
  for (const Row& r : rows()) {
    if (r.message != "camera" || r.contents.find("PNG") != std::string::npos) continue;
    ++images;
    EXPECT_LE(r.troupe_bytes, r.player_bytes + 24) << r.contents;
  }
  EXPECT_EQ(images, 3);
}

// A rendered scene as PNG: well under half of Player's raw image.
TEST(WireSize, APngImageOfARenderedSceneIsUnderHalfOfPlayersRawOne) {
  const Row& png = row("camera", "320x240 RGB8 as PNG (flat-shaded scene)");
  EXPECT_LT(double(png.troupe_bytes), 0.5 * double(png.player_bytes));
}

TEST(WireSize, EveryArrayMessageIsSmallerThanPlayersOnceItHoldsAFewElements) {
  for (const Row& r : rows()) {
    if (r.is_array && r.message != "camera" && r.contents.rfind("1 ", 0) != 0) {
      EXPECT_LT(r.troupe_bytes, r.player_bytes) << r.message << ", " << r.contents;
    }
  }
}

}  // namespace
}  // namespace troupe::wire::sizes
