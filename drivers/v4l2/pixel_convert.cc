#include "drivers/v4l2/pixel_convert.h"

#include <cstring>

namespace troupe::drivers::v4l2 {
namespace {

uint8_t clamp8(int v) {
  return uint8_t(v < 0 ? 0 : v > 255 ? 255 : v);
}

}  // namespace

size_t capture_bytes_per_pixel(Fourcc f) {
  switch (f) {
    case Fourcc::Rgb24:
      return 3;
    case Fourcc::Yuyv:
      return 2;
    case Fourcc::Grey:
      return 1;
  }
  return 0;
}

void ycbcr_to_rgb(uint8_t y, uint8_t cb, uint8_t cr, bool full_range, uint8_t rgb[3]) {
  // BT.601 in 16.16 fixed point: R = Y + 1.402 Cr, G = Y - 0.344136 Cb -
  // 0.714136 Cr, B = Y + 1.772 Cb over full-range values; limited range
  // first scales Y' by 255/219 and Cb, Cr by 255/224.
  const int d = cb - 128, e = cr - 128;
  int yy, r, g, b;
  if (full_range) {
    yy = y * 65536;
    r = 91881 * e;
    g = -22553 * d - 46802 * e;
    b = 116130 * d;
  } else {
    yy = (y - 16) * 76309;  // 65536 * 255 / 219
    r = 104597 * e;         // 65536 * 1.402 * 255 / 224
    g = -25675 * d - 53279 * e;
    b = 132201 * d;
  }
  rgb[0] = clamp8((yy + r + 32768) >> 16);
  rgb[1] = clamp8((yy + g + 32768) >> 16);
  rgb[2] = clamp8((yy + b + 32768) >> 16);
}

uint8_t rgb_to_luma(uint8_t r, uint8_t g, uint8_t b) {
  return uint8_t((299u * r + 587u * g + 114u * b + 500u) / 1000u);
}

uint8_t luma_to_grey(uint8_t y, bool full_range) {
  if (full_range) return y;
  return clamp8(((y - 16) * 255 * 2 + 219) / (2 * 219));
}

void convert_image(Fourcc in, const uint8_t* data, size_t in_stride, uint32_t width, uint32_t height,
                   bool full_range, bool out_rgb, uint8_t* out) {
  const size_t out_row = size_t(width) * (out_rgb ? 3 : 1);
  for (uint32_t row = 0; row < height; ++row) {
    const uint8_t* p = data + size_t(row) * in_stride;
    uint8_t* o = out + size_t(row) * out_row;
    switch (in) {
      case Fourcc::Rgb24:
        if (out_rgb) {
          std::memcpy(o, p, out_row);
        } else {
          for (uint32_t x = 0; x < width; ++x) o[x] = rgb_to_luma(p[3 * x], p[3 * x + 1], p[3 * x + 2]);
        }
        break;
      case Fourcc::Grey:
        if (out_rgb) {
          for (uint32_t x = 0; x < width; ++x) o[3 * x] = o[3 * x + 1] = o[3 * x + 2] = p[x];
        } else {
          std::memcpy(o, p, out_row);
        }
        break;
      case Fourcc::Yuyv:
        for (uint32_t x = 0; x < width; x += 2) {
          const uint8_t* q = p + 2 * size_t(x);  // Y0 U Y1 V
          if (out_rgb) {
            ycbcr_to_rgb(q[0], q[1], q[3], full_range, o + 3 * x);
            if (x + 1 < width) ycbcr_to_rgb(q[2], q[1], q[3], full_range, o + 3 * (x + 1));
          } else {
            o[x] = luma_to_grey(q[0], full_range);
            if (x + 1 < width) o[x + 1] = luma_to_grey(q[2], full_range);
          }
        }
        break;
    }
  }
}

}  // namespace troupe::drivers::v4l2
