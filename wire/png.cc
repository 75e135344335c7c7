#include "wire/png.h"

#include <zlib.h>

#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>

#include "wire/image.h"

namespace troupe::wire {
namespace {

void put_u32_be(std::vector<uint8_t>& out, uint32_t v) {
  for (int shift = 24; shift >= 0; shift -= 8) out.push_back(uint8_t(v >> shift));
}

// A chunk: length, type, data, then the CRC-32 of type and data (PNG 1.2,
// section 5.3).
void put_chunk(std::vector<uint8_t>& out, const char type[4], const uint8_t* data, size_t size) {
  put_u32_be(out, uint32_t(size));
  const size_t type_at = out.size();
  out.insert(out.end(), type, type + 4);
  if (size != 0) out.insert(out.end(), data, data + size);
  put_u32_be(out, uint32_t(crc32(0, out.data() + type_at, uInt(size + 4))));
}

// The Paeth predictor (PNG 1.2, section 6.6).
uint8_t paeth(int a, int b, int c) {
  const int p = a + b - c;
  const int pa = std::abs(p - a), pb = std::abs(p - b), pc = std::abs(p - c);
  if (pa <= pb && pa <= pc) return uint8_t(a);
  return pb <= pc ? uint8_t(b) : uint8_t(c);
}

// The byte filter `type` predicts for row[i] from its left neighbour a,
// the byte above b and the one above-left c (PNG 1.2, section 6).
uint8_t predict(uint8_t type, const uint8_t* row, const uint8_t* above, size_t i, size_t bpp) {
  const int a = i >= bpp ? row[i - bpp] : 0;
  const int b = above ? above[i] : 0;
  const int c = above && i >= bpp ? above[i - bpp] : 0;
  switch (type) {
    case 1:
      return uint8_t(a);
    case 2:
      return uint8_t(b);
    case 4:
      return paeth(a, b, c);
    default:
      return 0;
  }
}

// Appends one row filtered with the filter whose bytes, read as signed, sum
// smallest (the heuristic the PNG specification suggests, which lets
// deflate find the runs in flat rendered surfaces). Up is tried first and a
// trial stops once it cannot win: a rendered row is often its upper
// neighbour again, which costs one pass.
void filter_row(const uint8_t* row, const uint8_t* above, size_t n, size_t bpp, std::vector<uint8_t>& out) {
  static constexpr uint8_t kTypes[] = {2, 1, 0, 4};  // Up, Sub, None, Paeth
  size_t best_sum = SIZE_MAX;
  uint8_t best = 0;
  for (uint8_t type : kTypes) {
    size_t sum = 0;
    for (size_t i = 0; i < n && sum < best_sum; ++i) {
      sum += size_t(std::abs(int(int8_t(uint8_t(row[i] - predict(type, row, above, i, bpp))))));
    }
    if (sum < best_sum) {
      best_sum = sum;
      best = type;
    }
    if (best_sum == 0) break;
  }
  out.push_back(best);
  for (size_t i = 0; i < n; ++i) out.push_back(uint8_t(row[i] - predict(best, row, above, i, bpp)));
}

}  // namespace

bool encode_png(const ImageView& image, std::vector<uint8_t>& png, std::string& why) {
  png.clear();
  uint8_t bit_depth = 8, colour_type = 0;  // PNG colour types: 0 grey, 2 RGB
  switch (image.format) {
    case PixelFormat::Rgb8:
      colour_type = 2;
      break;
    case PixelFormat::Mono8:
      break;
    case PixelFormat::DepthU16:
      bit_depth = 16;
      break;
    default:
      why = std::string("a ") + EnumNamePixelFormat(image.format) +
            " image has no lossless PNG form: ask the camera for DepthU16 (millimetres) to compress depth";
      return false;
  }
  const size_t bpp = bytes_per_pixel(image.format);
  const size_t row_bytes = size_t(image.width) * bpp;
  char text[160];
  if (image.width == 0 || image.height == 0 || image.width > 0x7fffffffu || image.height > 0x7fffffffu) {
    snprintf(text, sizeof text, "a %ux%u image cannot be a PNG (1 to 2^31-1 pixels each way)",
             unsigned(image.width), unsigned(image.height));
    why = text;
    return false;
  }
  const size_t need = size_t(image.stride) * (image.height - 1) + row_bytes;
  if (image.stride < row_bytes || image.data.size() < need) {
    snprintf(text, sizeof text, "a %ux%u %s image with stride %u needs %zu bytes, it has %zu",
             unsigned(image.width), unsigned(image.height), EnumNamePixelFormat(image.format),
             unsigned(image.stride), need, image.data.size());
    why = text;
    return false;
  }

  // The filtered scanlines, each with its filter byte. The wire's 16-bit
  // samples are little-endian; PNG's are big-endian, so they are swapped
  // into a row first and filtered from there.
  std::vector<uint8_t> raw, swapped(bit_depth == 16 ? 2 * row_bytes : 0);
  raw.reserve((row_bytes + 1) * image.height);
  for (uint32_t y = 0; y < image.height; ++y) {
    const uint8_t* row = image.data.data() + size_t(y) * image.stride;
    const uint8_t* above = y > 0 ? image.data.data() + size_t(y - 1) * image.stride : nullptr;
    if (bit_depth == 16) {
      uint8_t* now = swapped.data() + (y % 2) * row_bytes;
      for (size_t i = 0; i < row_bytes; i += 2) {
        now[i] = row[i + 1];
        now[i + 1] = row[i];
      }
      row = now;
      above = y > 0 ? swapped.data() + ((y + 1) % 2) * row_bytes : nullptr;
    }
    filter_row(row, above, row_bytes, bpp, raw);
  }

  uLongf packed_size = compressBound(uLong(raw.size()));
  std::vector<uint8_t> packed(packed_size);
  // Level 6, zlib's default: most of level 9's size for a fraction of its time.
  if (compress2(packed.data(), &packed_size, raw.data(), uLong(raw.size()), 6) != Z_OK) {
    why = "zlib could not compress the image";
    return false;
  }

  static constexpr uint8_t kSignature[] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
  png.reserve(sizeof kSignature + 25 + 12 + packed_size + 12);
  png.insert(png.end(), kSignature, kSignature + sizeof kSignature);
  // IHDR: width, height, bit depth, colour type, then compression, filter
  // and interlace methods (all 0: deflate, adaptive filters, none).
  std::vector<uint8_t> header;
  put_u32_be(header, image.width);
  put_u32_be(header, image.height);
  header.insert(header.end(), {bit_depth, colour_type, 0, 0, 0});
  put_chunk(png, "IHDR", header.data(), header.size());
  put_chunk(png, "IDAT", packed.data(), packed_size);
  put_chunk(png, "IEND", nullptr, 0);
  return true;
}

bool save_png(const CameraImage& image, const std::string& path, std::string& why) {
  std::vector<uint8_t> encoded;
  std::span<const uint8_t> bytes;
  if (image.data() != nullptr) bytes = {image.data()->data(), image.data()->size()};
  if (image.compression() == ImageCompression::None) {
    if (!encode_png({image.width(), image.height(), image.format(), image.stride(), bytes}, encoded, why)) {
      return false;
    }
    bytes = encoded;
  } else if (image.compression() != ImageCompression::Png) {
    why = std::string("an image compressed as ") + EnumNameImageCompression(image.compression()) +
          " cannot be saved as PNG";
    return false;
  }
  FILE* f = fopen(path.c_str(), "wb");
  if (f == nullptr) {
    why = "cannot write " + path + ": " + strerror(errno);
    return false;
  }
  const bool written = fwrite(bytes.data(), 1, bytes.size(), f) == bytes.size();
  const int write_errno = errno;
  if (fclose(f) != 0 || !written) {
    why = "cannot write " + path + ": " + strerror(written ? errno : write_errno);
    return false;
  }
  return true;
}

}  // namespace troupe::wire
