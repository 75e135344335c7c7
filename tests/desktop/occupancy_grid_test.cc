// PNG maps: thresholds, negate, orientation, the two-bit packing, and
// refusing bad files.
#include "drivers/common_desktop/occupancy_grid.h"

#include <gtest/gtest.h>
#include <png.h>

#include <cstring>
#include <fstream>

#include "tests/desktop/synthetic_world.h"

namespace troupe::desktop {
namespace {

// Writes an 8-bit grey PNG, rows top to bottom.
void write_grey(const std::string& path, uint32_t w, uint32_t h, const std::vector<uint8_t>& px) {
  png_image image;
  std::memset(&image, 0, sizeof image);
  image.version = PNG_IMAGE_VERSION;
  image.width = w;
  image.height = h;
  image.format = PNG_FORMAT_GRAY;
  ASSERT_TRUE(png_image_write_to_file(&image, path.c_str(), 0, px.data(), 0, nullptr)) << image.message;
}

TEST(OccupancyGrid, PngThresholdsLikeMapServer) {
  std::string path = testing::scratch_dir() + "/t.png";
  // Top row: black, dark grey, mid grey, light grey, white.
  // p = (255 - v) / 255: 1.0, 0.8, 0.5, 0.1, 0.0.
  write_grey(path, 5, 2, {0, 51, 128, 230, 255, 255, 255, 255, 255, 0});
  PngMapOptions opt;
  opt.resolution = 0.1;
  opt.origin = {2.0, -1.0, 0.0};
  OccupancyGrid g;
  std::string error;
  ASSERT_TRUE(load_png_map(path, opt, g, error)) << error;
  EXPECT_EQ(g.width(), 5u);
  EXPECT_EQ(g.height(), 2u);
  // The PNG's top row is the grid's highest row.
  EXPECT_EQ(g.at(0, 1), CellState::Occupied);
  EXPECT_EQ(g.at(1, 1), CellState::Occupied);
  EXPECT_EQ(g.at(2, 1), CellState::Unknown);
  EXPECT_EQ(g.at(3, 1), CellState::Free);
  EXPECT_EQ(g.at(4, 1), CellState::Free);
  EXPECT_EQ(g.at(4, 0), CellState::Occupied);
  EXPECT_EQ(g.at(0, 0), CellState::Free);
  // Map coordinates: cell (4, 0) spans x 2.4..2.5, y -1.0..-0.9.
  int64_t c = 0, r = 0;
  g.world_to_cell(2.45, -0.95, c, r);
  EXPECT_EQ(c, 4);
  EXPECT_EQ(r, 0);
  double x = 0, y = 0;
  g.cell_center(0, 1, x, y);
  EXPECT_NEAR(x, 2.05, 1e-12);
  EXPECT_NEAR(y, -0.85, 1e-12);

  opt.negate = true;  // now light pixels are obstacles
  ASSERT_TRUE(load_png_map(path, opt, g, error)) << error;
  EXPECT_EQ(g.at(0, 1), CellState::Free);
  EXPECT_EQ(g.at(4, 1), CellState::Occupied);
}

TEST(OccupancyGrid, SaveThenLoadGivesTheSameCells) {
  OccupancyGrid a = testing::make_test_map();
  a.set(3, 4, CellState::Unknown);
  std::string path = testing::scratch_dir() + "/m.png";
  std::string error;
  ASSERT_TRUE(save_png_map(path, a, error)) << error;
  PngMapOptions opt;
  opt.resolution = a.resolution();
  opt.origin = a.origin();
  OccupancyGrid b;
  ASSERT_TRUE(load_png_map(path, opt, b, error)) << error;
  EXPECT_EQ(a.cells(), b.cells());
}

TEST(OccupancyGrid, PackAndUnpackTwoBitsPerCell) {
  OccupancyGrid g(7, 3, 0.05, {});
  const CellState states[] = {CellState::Free, CellState::Occupied, CellState::Unknown};
  for (uint32_t r = 0; r < 3; ++r) {
    for (uint32_t c = 0; c < 7; ++c) g.set(c, r, states[(r * 7 + c * c) % 3]);
  }
  std::vector<uint8_t> packed;
  g.pack(1, 1, 5, 2, packed);
  ASSERT_EQ(packed.size(), 3u);  // 10 cells, four per byte
  // Cell i sits in bits 2*(i%4): the first byte holds cells (1,1) (2,1) (3,1) (4,1).
  uint8_t first = uint8_t(uint8_t(g.at(1, 1)) | uint8_t(g.at(2, 1)) << 2 | uint8_t(g.at(3, 1)) << 4 |
                          uint8_t(g.at(4, 1)) << 6);
  EXPECT_EQ(packed[0], first);
  OccupancyGrid copy(7, 3, 0.05, {}, CellState::Free);
  ASSERT_TRUE(copy.unpack(1, 1, 5, 2, packed.data(), packed.size()));
  for (uint32_t r = 1; r < 3; ++r) {
    for (uint32_t c = 1; c < 6; ++c) {
      EXPECT_EQ(copy.at(c, r), g.at(c, r)) << c << "," << r;
    }
  }
  EXPECT_FALSE(copy.unpack(3, 1, 5, 2, packed.data(), packed.size()));  // leaves the grid
  EXPECT_FALSE(copy.unpack(1, 1, 5, 2, packed.data(), 2));              // too short
}

TEST(OccupancyGrid, BadFilesAndOptionsAreRefused) {
  std::string dir = testing::scratch_dir();
  std::ofstream(dir + "/not.png") << "this is not a PNG";
  OccupancyGrid g;
  std::string error;
  EXPECT_FALSE(load_png_map(dir + "/not.png", {}, g, error));
  EXPECT_NE(error.find("not.png: not a readable PNG"), std::string::npos) << error;
  EXPECT_FALSE(load_png_map(dir + "/absent.png", {}, g, error));
  EXPECT_NE(error.find("absent.png"), std::string::npos) << error;
  write_grey(dir + "/ok.png", 2, 2, {0, 0, 0, 0});
  PngMapOptions opt;
  opt.resolution = 0;
  EXPECT_FALSE(load_png_map(dir + "/ok.png", opt, g, error));
  EXPECT_NE(error.find("resolution"), std::string::npos) << error;
  opt.resolution = 0.05;
  opt.free_thresh = 0.9;  // above occupied_thresh
  EXPECT_FALSE(load_png_map(dir + "/ok.png", opt, g, error));
  EXPECT_NE(error.find("free_thresh"), std::string::npos) << error;
  // A truncated PNG: header fine, data cut.
  write_grey(dir + "/big.png", 64, 64, std::vector<uint8_t>(64 * 64, 7));
  std::string bytes;
  {
    std::ifstream in(dir + "/big.png", std::ios::binary);
    bytes.assign(std::istreambuf_iterator<char>(in), {});
  }
  std::ofstream(dir + "/cut.png", std::ios::binary) << bytes.substr(0, bytes.size() - 20);
  EXPECT_FALSE(load_png_map(dir + "/cut.png", {}, g, error));
  EXPECT_NE(error.find("cut.png"), std::string::npos) << error;
}

}  // namespace
}  // namespace troupe::desktop
