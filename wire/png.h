// PNG encoding of camera images (CameraImage.compression = Png): the
// simulator, the CLI, the viewer bridge and the recorder compress with it.
// Host code only: it deflates with zlib, which a board node does not carry
// (a board camera sends raw rows; a reader that asked for PNG reads them).
#pragma once

#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "wire/schemas/message_generated.h"

namespace troupe::wire {

/// An uncompressed image as the wire carries it (camera.fbs): `height` rows
/// of `stride` bytes, multi-byte pixels little-endian.
struct ImageView {
  uint32_t width = 0;   // px
  uint32_t height = 0;  // px
  PixelFormat format = PixelFormat::Rgb8;
  uint32_t stride = 0;            // bytes from one row to the next, >= width x bytes per pixel
  std::span<const uint8_t> data;  // at least stride x (height - 1) + width x bytes per pixel bytes
};

/// Encodes `image` as one PNG file into `png` (replacing its contents, keeping
/// its capacity): Rgb8 as 8-bit RGB, Mono8 as 8-bit grey, DepthU16 as 16-bit
/// grey (millimetres; big-endian, as PNG stores samples). DepthF32 has no
/// lossless PNG form and is refused: ask the camera for DepthU16 instead.
/// False, with `why` naming the problem, for that, an empty or oversized
/// image (PNG allows at most 2^31 - 1 pixels each way), or `data` shorter
/// than the size and stride say. Deterministic: same image, same bytes.
bool encode_png(const ImageView& image, std::vector<uint8_t>& png, std::string& why);

/// Writes a received image to the file `path` as PNG: a PNG image's bytes as
/// they came, raw rows through encode_png(). False, with `why` naming the
/// file or the image's problem (no PNG form, rows shorter than it says, an
/// unknown compression, a file that cannot be written).
bool save_png(const CameraImage& image, const std::string& path, std::string& why);

}  // namespace troupe::wire
