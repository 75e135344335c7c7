#include "host-sim/world/png_image.h"

#include <png.h>

#include <cstring>

namespace troupe::world {

bool read_png(const std::string& path, GrayImage& out, std::string& error, uint64_t max_pixels) {
  png_image img;
  std::memset(&img, 0, sizeof img);
  img.version = PNG_IMAGE_VERSION;
  if (!png_image_begin_read_from_file(&img, path.c_str())) {
    error = img.message[0] ? img.message : "cannot read PNG";
    return false;
  }
  if (uint64_t(img.width) * img.height > max_pixels || img.width == 0 || img.height == 0) {
    error = "image is " + std::to_string(img.width) + " x " + std::to_string(img.height) + " pixels";
    png_image_free(&img);
    return false;
  }
  // Grey files are read as they are; colour ones as RGBA and reduced to red,
  // which is the channel Stage tests against its threshold.
  const bool gray = (img.format & PNG_FORMAT_FLAG_COLOR) == 0;
  img.format = gray ? PNG_FORMAT_GRAY : PNG_FORMAT_RGBA;
  const size_t channels = gray ? 1 : 4;
  std::vector<uint8_t> buffer(size_t(img.width) * img.height * channels);
  png_color background{255, 255, 255};
  if (!png_image_finish_read(&img, &background, buffer.data(), 0, nullptr)) {
    error = img.message[0] ? img.message : "cannot decode PNG";
    png_image_free(&img);
    return false;
  }
  out.width = int(img.width);
  out.height = int(img.height);
  if (gray) {
    out.pixels = std::move(buffer);
  } else {
    out.pixels.resize(size_t(img.width) * img.height);
    for (size_t i = 0; i < out.pixels.size(); ++i) out.pixels[i] = buffer[i * 4];
  }
  png_image_free(&img);
  return true;
}

namespace {

bool write(const std::string& path, int width, int height, uint32_t format, const void* data,
           std::string& error) {
  png_image img;
  std::memset(&img, 0, sizeof img);
  img.version = PNG_IMAGE_VERSION;
  img.width = png_uint_32(width);
  img.height = png_uint_32(height);
  img.format = format;
  if (!png_image_write_to_file(&img, path.c_str(), 0, data, 0, nullptr)) {
    error = img.message[0] ? img.message : "cannot write PNG";
    return false;
  }
  return true;
}

}  // namespace

bool write_png(const std::string& path, const RgbImage& image, std::string& error) {
  return write(path, image.width, image.height, PNG_FORMAT_RGB, image.pixels.data(), error);
}

bool write_png(const std::string& path, const GrayImage& image, std::string& error) {
  return write(path, image.width, image.height, PNG_FORMAT_GRAY, image.pixels.data(), error);
}

}  // namespace troupe::world
