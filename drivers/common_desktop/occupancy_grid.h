// A two-dimensional occupancy grid: what the map interface serves, what the
// localizer measures against, what troupe-logmap draws.
//
// Cell (0, 0) is the bottom-left cell; its outer corner sits at `origin` in
// the map frame, and columns grow along the origin's x axis, rows along its y
// axis. (A PNG's first row is the top of the map: the loaders flip it.)
#pragma once

#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include "drivers/common_desktop/pose2.h"

namespace troupe::desktop {

/// The states a cell can be in; the same codes as wire::Cell.
enum class CellState : uint8_t { Free = 0, Occupied = 1, Unknown = 2 };

/// Grids larger than this many cells are refused (a 10 km square at 1 m, or
/// 500 m square at 5 cm) so that a hostile file cannot exhaust memory.
inline constexpr uint64_t kMaxGridCells = 100'000'000;

class OccupancyGrid {
 public:
  OccupancyGrid() = default;
  /// A grid of `width` x `height` cells of `resolution` m, every cell `fill`.
  OccupancyGrid(uint32_t width, uint32_t height, double resolution, Pose2 origin,
                CellState fill = CellState::Unknown);

  uint32_t width() const { return width_; }
  uint32_t height() const { return height_; }
  /// Cell side, m.
  double resolution() const { return resolution_; }
  /// Pose of cell (0, 0)'s outer corner in the map frame: m, m, rad.
  const Pose2& origin() const { return origin_; }
  bool empty() const { return cells_.empty(); }

  bool contains(int64_t col, int64_t row) const {
    return col >= 0 && row >= 0 && col < int64_t(width_) && row < int64_t(height_);
  }
  CellState at(uint32_t col, uint32_t row) const { return CellState(cells_[size_t(row) * width_ + col]); }
  void set(uint32_t col, uint32_t row, CellState s) { cells_[size_t(row) * width_ + col] = uint8_t(s); }
  /// Raw cell codes, row-major from row 0 (bottom).
  const std::vector<uint8_t>& cells() const { return cells_; }

  /// The cell holding map point (x, y) (m), which may lie outside the grid.
  void world_to_cell(double x, double y, int64_t& col, int64_t& row) const {
    double dx = x - origin_.x, dy = y - origin_.y;
    double gx = cos_ * dx + sin_ * dy, gy = -sin_ * dx + cos_ * dy;
    col = int64_t(std::floor(gx / resolution_));
    row = int64_t(std::floor(gy / resolution_));
  }
  /// The centre of a cell in the map frame, m.
  void cell_center(int64_t col, int64_t row, double& x, double& y) const {
    double gx = (double(col) + 0.5) * resolution_, gy = (double(row) + 0.5) * resolution_;
    x = origin_.x + cos_ * gx - sin_ * gy;
    y = origin_.y + sin_ * gx + cos_ * gy;
  }

  /// Packs a block of cells two bits each, four to a byte (cell i in bits
  /// 2*(i%4).., row-major from (col, row)), as wire::MapTile carries them.
  /// The block must lie inside the grid.
  void pack(uint32_t col, uint32_t row, uint32_t w, uint32_t h, std::vector<uint8_t>& out) const;
  /// The inverse of pack(): writes a block into the grid. False when the
  /// block leaves the grid or `packed` is too short.
  bool unpack(uint32_t col, uint32_t row, uint32_t w, uint32_t h, const uint8_t* packed, size_t bytes);

 private:
  uint32_t width_ = 0, height_ = 0;
  double resolution_ = 0;
  Pose2 origin_;
  double cos_ = 1, sin_ = 0;
  std::vector<uint8_t> cells_;
};

/// How a PNG's pixels become cells: map_server's YAML fields, as options.
struct PngMapOptions {
  /// Cell side, m per pixel.
  double resolution = 0.05;
  /// Pose of the image's bottom-left corner in the map frame: m, m, rad.
  Pose2 origin;
  /// False: dark is occupied (p = (255 - v) / 255). True: light is occupied.
  bool negate = false;
  /// p above it: occupied (0..1).
  double occupied_thresh = 0.65;
  /// p below it: free (0..1); between the two: unknown.
  double free_thresh = 0.196;
};

/// Loads a PNG (any bit depth or colour type; colour channels are averaged,
/// fully transparent pixels are unknown). False with `error` naming the file.
bool load_png_map(const std::string& path, const PngMapOptions& options, OccupancyGrid& out,
                  std::string& error);

/// Writes the grid as an 8-bit grey PNG the way map_server's tools draw
/// maps: occupied 0, free 254, unknown 205. Top row = highest row.
bool save_png_map(const std::string& path, const OccupancyGrid& grid, std::string& error);

}  // namespace troupe::desktop
