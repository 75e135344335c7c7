// PNG files through libpng: world bitmaps in, snapshots out.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace troupe::world {

/// An 8-bit single-channel image, row 0 at the top. For colour PNGs the
/// channel is red, as Stage reads bitmaps (the first channel decides).
struct GrayImage {
  int width = 0;
  int height = 0;
  std::vector<uint8_t> pixels;  // width * height

  uint8_t at(int x, int y) const { return pixels[size_t(y) * size_t(width) + size_t(x)]; }
};

/// An 8-bit RGB image, row 0 at the top.
struct RgbImage {
  int width = 0;
  int height = 0;
  std::vector<uint8_t> pixels;  // width * height * 3

  void resize(int w, int h, uint8_t fill = 255) {
    width = w;
    height = h;
    pixels.assign(size_t(w) * size_t(h) * 3, fill);
  }
};

/// Reads a PNG. False with `error` (libpng's reason) when the file is missing,
/// not a PNG, truncated, or larger than `max_pixels`.
bool read_png(const std::string& path, GrayImage& out, std::string& error, uint64_t max_pixels = 1ull << 30);

/// Writes an RGB PNG. False with `error` when the file cannot be written.
bool write_png(const std::string& path, const RgbImage& image, std::string& error);
/// Writes a grey PNG (test maps, benchmark arenas).
bool write_png(const std::string& path, const GrayImage& image, std::string& error);

}  // namespace troupe::world
