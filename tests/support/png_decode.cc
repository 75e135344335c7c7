#include "tests/support/png_decode.h"

#include <png.h>

#include <csetjmp>
#include <cstring>

namespace troupe::test {
namespace {

struct Source {
  const std::vector<uint8_t>* file;
  size_t at = 0;
  std::string* why;
};

void read_bytes(png_structp png, png_bytep data, png_size_t n) {
  auto* s = static_cast<Source*>(png_get_io_ptr(png));
  if (s->at + n > s->file->size()) png_error(png, "the file ends early");
  std::memcpy(data, s->file->data() + s->at, n);
  s->at += n;
}

void on_error(png_structp png, png_const_charp message) {
  *static_cast<Source*>(png_get_io_ptr(png))->why = message;
  png_longjmp(png, 1);
}

}  // namespace

bool decode_png(const std::vector<uint8_t>& file, DecodedPng& out, std::string& why) {
  out = DecodedPng{};
  Source source{&file, 0, &why};
  png_structp png = png_create_read_struct(PNG_LIBPNG_VER_STRING, nullptr, nullptr, nullptr);
  png_infop info = png_create_info_struct(png);
  png_set_read_fn(png, &source, read_bytes);
  png_set_error_fn(png, png_get_error_ptr(png), on_error, nullptr);
  if (setjmp(png_jmpbuf(png))) {
    png_destroy_read_struct(&png, &info, nullptr);
    return false;
  }
  png_read_info(png, info);
  out.width = png_get_image_width(png, info);
  out.height = png_get_image_height(png, info);
  out.bit_depth = png_get_bit_depth(png, info);
  out.colour_type = png_get_color_type(png, info);
  const size_t row_bytes = png_get_rowbytes(png, info);
  out.pixels.resize(row_bytes * out.height);
  for (uint32_t y = 0; y < out.height; ++y) png_read_row(png, out.pixels.data() + y * row_bytes, nullptr);
  png_read_end(png, nullptr);
  png_destroy_read_struct(&png, &info, nullptr);
  if (out.bit_depth == 16) {
    for (size_t i = 0; i + 1 < out.pixels.size(); i += 2) std::swap(out.pixels[i], out.pixels[i + 1]);
  }
  return true;
}

}  // namespace troupe::test
