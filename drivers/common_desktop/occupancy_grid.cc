#include "drivers/common_desktop/occupancy_grid.h"

#include <png.h>

#include <cstring>

namespace troupe::desktop {

OccupancyGrid::OccupancyGrid(uint32_t width, uint32_t height, double resolution, Pose2 origin, CellState fill)
    : width_(width),
      height_(height),
      resolution_(resolution),
      origin_(origin),
      cos_(std::cos(origin.a)),
      sin_(std::sin(origin.a)),
      cells_(size_t(width) * height, uint8_t(fill)) {}

void OccupancyGrid::pack(uint32_t col, uint32_t row, uint32_t w, uint32_t h,
                         std::vector<uint8_t>& out) const {
  size_t n = size_t(w) * h;
  out.assign((n + 3) / 4, 0);
  size_t i = 0;
  for (uint32_t r = 0; r < h; ++r) {
    const uint8_t* src = &cells_[size_t(row + r) * width_ + col];
    for (uint32_t c = 0; c < w; ++c, ++i) out[i / 4] |= uint8_t((src[c] & 3u) << (2 * (i % 4)));
  }
}

bool OccupancyGrid::unpack(uint32_t col, uint32_t row, uint32_t w, uint32_t h, const uint8_t* packed,
                           size_t bytes) {
  if (uint64_t(col) + w > width_ || uint64_t(row) + h > height_) return false;
  size_t n = size_t(w) * h;
  if (bytes < (n + 3) / 4) return false;
  size_t i = 0;
  for (uint32_t r = 0; r < h; ++r) {
    uint8_t* dst = &cells_[size_t(row + r) * width_ + col];
    for (uint32_t c = 0; c < w; ++c, ++i) {
      uint8_t code = (packed[i / 4] >> (2 * (i % 4))) & 3u;
      // Code 3 is not a state: read it as unknown rather than trust it.
      dst[c] = code > uint8_t(CellState::Unknown) ? uint8_t(CellState::Unknown) : code;
    }
  }
  return true;
}

bool load_png_map(const std::string& path, const PngMapOptions& opt, OccupancyGrid& out, std::string& error) {
  if (!(opt.resolution > 0) || !std::isfinite(opt.resolution)) {
    error = path + ": resolution must be > 0 m";
    return false;
  }
  if (!(opt.free_thresh >= 0 && opt.free_thresh <= opt.occupied_thresh && opt.occupied_thresh <= 1)) {
    error = path + ": need 0 <= free_thresh <= occupied_thresh <= 1";
    return false;
  }
  // libpng's simplified API: no setjmp, errors come back in image.message.
  png_image image;
  std::memset(&image, 0, sizeof image);
  image.version = PNG_IMAGE_VERSION;
  if (!png_image_begin_read_from_file(&image, path.c_str())) {
    error = path + ": not a readable PNG: " + image.message;
    return false;
  }
  if (uint64_t(image.width) * image.height > kMaxGridCells) {
    error = path + ": " + std::to_string(image.width) + "x" + std::to_string(image.height) +
            " pixels is more than the " + std::to_string(kMaxGridCells) + " cells a map may have";
    png_image_free(&image);
    return false;
  }
  image.format = PNG_FORMAT_RGBA;
  std::vector<uint8_t> rgba(PNG_IMAGE_SIZE(image));
  if (!png_image_finish_read(&image, nullptr, rgba.data(), 0, nullptr)) {
    error = path + ": PNG data is corrupt: " + image.message;
    png_image_free(&image);
    return false;
  }
  OccupancyGrid grid(image.width, image.height, opt.resolution, opt.origin);
  for (uint32_t y = 0; y < image.height; ++y) {
    const uint8_t* px = &rgba[size_t(y) * image.width * 4];
    uint32_t row = image.height - 1 - y;  // PNG rows run top to bottom
    for (uint32_t x = 0; x < image.width; ++x, px += 4) {
      CellState s = CellState::Unknown;
      if (px[3] != 0) {
        double v = (double(px[0]) + px[1] + px[2]) / 3.0;
        double p = opt.negate ? v / 255.0 : (255.0 - v) / 255.0;
        if (p > opt.occupied_thresh) {
          s = CellState::Occupied;
        } else if (p < opt.free_thresh) {
          s = CellState::Free;
        }
      }
      grid.set(x, row, s);
    }
  }
  out = std::move(grid);
  return true;
}

bool save_png_map(const std::string& path, const OccupancyGrid& grid, std::string& error) {
  std::vector<uint8_t> grey(size_t(grid.width()) * grid.height());
  for (uint32_t row = 0; row < grid.height(); ++row) {
    uint8_t* dst = &grey[size_t(grid.height() - 1 - row) * grid.width()];
    for (uint32_t col = 0; col < grid.width(); ++col) {
      switch (grid.at(col, row)) {
        case CellState::Occupied:
          dst[col] = 0;
          break;
        case CellState::Free:
          dst[col] = 254;
          break;
        case CellState::Unknown:
          dst[col] = 205;
          break;
      }
    }
  }
  png_image image;
  std::memset(&image, 0, sizeof image);
  image.version = PNG_IMAGE_VERSION;
  image.width = grid.width();
  image.height = grid.height();
  image.format = PNG_FORMAT_GRAY;
  if (!png_image_write_to_file(&image, path.c_str(), 0, grey.data(), 0, nullptr)) {
    error = path + ": cannot write PNG: " + image.message;
    return false;
  }
  return true;
}

}  // namespace troupe::desktop
