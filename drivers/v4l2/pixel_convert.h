// Converting a V4L2 capture buffer into the wire's pixel formats (Rgb8,
// Mono8: tightly packed rows, wire/schemas/camera.fbs). Pure functions on
// memory, so they are tested on the host against values worked out by hand.
//
// YUYV (V4L2_PIX_FMT_YUYV) packs two pixels in four bytes, Y0 U Y1 V, the
// two sharing U (Cb) and V (Cr). Its colours are BT.601 Y'CbCr, limited
// range (Y' 16..235, Cb and Cr 16..240 around 128) unless the camera says
// full range (0..255).
#pragma once

#include <cstddef>
#include <cstdint>

namespace troupe::drivers::v4l2 {

/// The capture formats the driver understands.
enum class Fourcc : uint8_t { Rgb24, Yuyv, Grey };

/// Bytes per pixel of a capture format.
size_t capture_bytes_per_pixel(Fourcc f);

/// One BT.601 Y'CbCr sample to R'G'B' (each 0..255), in integers so every
/// host gives the same bytes. `full_range`: Y', Cb, Cr use 0..255.
void ycbcr_to_rgb(uint8_t y, uint8_t cb, uint8_t cr, bool full_range, uint8_t rgb[3]);

/// BT.601 luma of an R'G'B' pixel, rounded (0.299 R + 0.587 G + 0.114 B).
uint8_t rgb_to_luma(uint8_t r, uint8_t g, uint8_t b);

/// A limited-range Y' (16..235) stretched to 0..255; full range is kept.
uint8_t luma_to_grey(uint8_t y, bool full_range);

/// Converts a `width` x `height` image of format `in` with rows
/// `in_stride` bytes apart into `out` (Rgb8 when `out_rgb`, else Mono8),
/// rows packed. `out` holds width x height x (3 or 1) bytes. YUYV needs an
/// even width (V4L2 gives one: pixels come in pairs).
void convert_image(Fourcc in, const uint8_t* data, size_t in_stride, uint32_t width, uint32_t height,
                   bool full_range, bool out_rgb, uint8_t* out);

}  // namespace troupe::drivers::v4l2
