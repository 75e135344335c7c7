// An independent PNG decoder for tests: libpng reads what encode_png()
// (wire/png.h) wrote, so a test compares pixels without trusting our code.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace troupe::test {

struct DecodedPng {
  uint32_t width = 0, height = 0;  // px
  int bit_depth = 0;               // bits per sample
  int colour_type = 0;             // PNG's: 0 grey, 2 RGB
  /// Rows without padding, each sample as the wire holds it: 16-bit samples
  /// little-endian (PNG stores them big-endian).
  std::vector<uint8_t> pixels;
};

/// Decodes a whole PNG file; false with libpng's reason when it refuses it.
bool decode_png(const std::vector<uint8_t>& file, DecodedPng& out, std::string& why);

}  // namespace troupe::test
