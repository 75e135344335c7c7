#include "wire/image.h"

#include <cstdio>

namespace troupe::wire {

size_t bytes_per_pixel(PixelFormat format) {
  switch (format) {
    case PixelFormat::Rgb8: return 3;
    case PixelFormat::Mono8: return 1;
    case PixelFormat::DepthF32: return 4;
    case PixelFormat::DepthU16: return 2;
  }
  return 0;
}

size_t image_frame_bytes(uint32_t width, uint32_t height, PixelFormat format) {
  return size_t(width) * size_t(height) * bytes_per_pixel(format) + kImageEnvelopeBytes;
}

bool image_fits(uint32_t width, uint32_t height, PixelFormat format, size_t max_frame_bytes, std::string& why) {
  const size_t need = image_frame_bytes(width, height, format);
  if (bytes_per_pixel(format) != 0 && need <= max_frame_bytes) return true;
  char text[200];
  snprintf(text, sizeof text,
           "a %ux%u %s image needs a %zu-byte frame, over the %zu-byte frame limit: it is not sent (ask for "
           "fewer pixels or a smaller format)",
           unsigned(width), unsigned(height), EnumNamePixelFormat(format), need, max_frame_bytes);
  why = text;
  return false;
}

bool image_complete(const CameraImage& image, std::string& why) {
  const size_t have = image.data() ? image.data()->size() : 0;
  char text[200];
  if (image.compression() != ImageCompression::None) {
    if (have > 0) return true;
    why = "a compressed image without data";
    return false;
  }
  const size_t row = size_t(image.width()) * bytes_per_pixel(image.format());
  if (row == 0 && image.width() > 0) {
    snprintf(text, sizeof text, "an image of unknown pixel format %u", unsigned(image.format()));
    why = text;
    return false;
  }
  if (image.stride() < row) {
    snprintf(text, sizeof text, "a %ux%u %s image with a stride of %u bytes, under its %zu-byte rows",
             unsigned(image.width()), unsigned(image.height()), EnumNamePixelFormat(image.format()),
             unsigned(image.stride()), row);
    why = text;
    return false;
  }
  const size_t need = image.height() == 0 ? 0 : size_t(image.height() - 1) * image.stride() + row;
  if (have >= need) return true;
  snprintf(text, sizeof text, "a %ux%u %s image with %zu bytes of pixels, %zu short of its %zu",
           unsigned(image.width()), unsigned(image.height()), EnumNamePixelFormat(image.format()), have,
           need - have, need);
  why = text;
  return false;
}

}  // namespace troupe::wire
