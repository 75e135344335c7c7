// encode_png() against an independent decoder: libpng reads back every
// encoded image and its pixels must equal the input's, for each format,
// with padded rows, flat areas (which the filters and deflate shrink) and
// noise (which they cannot).
#include "wire/png.h"

#include <gtest/gtest.h>
#include <png.h>

#include <cstring>

#include "runtime/random.h"
#include "wire/image.h"

namespace troupe::wire {
namespace {

struct Decoded {
  uint32_t width = 0, height = 0;
  int bit_depth = 0, colour_type = 0;
  std::vector<std::vector<uint8_t>> rows;  // as libpng gives them: 16-bit samples big-endian
};

// libpng's simplified-free reading API over a memory buffer.
Decoded decode_with_libpng(const std::vector<uint8_t>& file) {
  Decoded out;
  png_structp png = png_create_read_struct(PNG_LIBPNG_VER_STRING, nullptr, nullptr, nullptr);
  png_infop info = png_create_info_struct(png);
  struct Reader {
    const std::vector<uint8_t>* file;
    size_t at = 0;
  } reader{&file};
  png_set_read_fn(png, &reader, [](png_structp p, png_bytep data, png_size_t n) {
    auto* r = static_cast<Reader*>(png_get_io_ptr(p));
    if (r->at + n > r->file->size()) png_error(p, "read past the end");
    std::memcpy(data, r->file->data() + r->at, n);
    r->at += n;
  });
  if (setjmp(png_jmpbuf(png))) {
    png_destroy_read_struct(&png, &info, nullptr);
    ADD_FAILURE() << "libpng refused the file";
    return Decoded{};
  }
  png_read_info(png, info);
  out.width = png_get_image_width(png, info);
  out.height = png_get_image_height(png, info);
  out.bit_depth = png_get_bit_depth(png, info);
  out.colour_type = png_get_color_type(png, info);
  out.rows.assign(out.height, std::vector<uint8_t>(png_get_rowbytes(png, info)));
  for (auto& row : out.rows) png_read_row(png, row.data(), nullptr);
  png_read_end(png, nullptr);
  png_destroy_read_struct(&png, &info, nullptr);
  return out;
}

// An image whose left half is flat colour bands and right half noise, with
// `pad` bytes of junk after each row.
std::vector<uint8_t> make_pixels(uint32_t w, uint32_t h, size_t bpp, size_t pad, uint64_t seed) {
  const Random random(seed);
  const size_t stride = w * bpp + pad;
  std::vector<uint8_t> pixels(stride * h);
  for (uint32_t y = 0; y < h; ++y) {
    for (size_t i = 0; i < stride; ++i) {
      const bool noise = i >= w * bpp / 2;
      pixels[y * stride + i] =
          noise ? uint8_t(random.bits(1, y * stride + i)) : uint8_t(40 * (y / 8) + i % bpp);
    }
  }
  return pixels;
}

void expect_round_trip(PixelFormat format, uint32_t w, uint32_t h, size_t pad, int bit_depth,
                       int colour_type) {
  const size_t bpp = bytes_per_pixel(format);
  const std::vector<uint8_t> pixels = make_pixels(w, h, bpp, pad, 7);
  const ImageView view{w, h, format, uint32_t(w * bpp + pad), pixels};
  std::vector<uint8_t> png;
  std::string why;
  ASSERT_TRUE(encode_png(view, png, why)) << why;
  const Decoded d = decode_with_libpng(png);
  ASSERT_EQ(d.width, w);
  ASSERT_EQ(d.height, h);
  EXPECT_EQ(d.bit_depth, bit_depth);
  EXPECT_EQ(d.colour_type, colour_type);
  for (uint32_t y = 0; y < h; ++y) {
    ASSERT_EQ(d.rows[y].size(), w * bpp);
    for (size_t i = 0; i < w * bpp; ++i) {
      // 16-bit samples: the wire's little-endian pair is PNG's big-endian one swapped.
      const size_t from = bit_depth == 16 ? (i ^ 1) : i;
      ASSERT_EQ(d.rows[y][i], pixels[y * view.stride + from]) << "row " << y << " byte " << i;
    }
  }
}

TEST(Png, Rgb8DecodesToTheSamePixels) {
  expect_round_trip(PixelFormat::Rgb8, 64, 48, 5, 8, PNG_COLOR_TYPE_RGB);
}

TEST(Png, Mono8DecodesToTheSamePixels) {
  expect_round_trip(PixelFormat::Mono8, 33, 17, 3, 8, PNG_COLOR_TYPE_GRAY);
}

TEST(Png, DepthU16IsSixteenBitGreyBigEndian) {
  expect_round_trip(PixelFormat::DepthU16, 40, 30, 2, 16, PNG_COLOR_TYPE_GRAY);
}

TEST(Png, AOnePixelImageRoundTrips) {
  expect_round_trip(PixelFormat::Rgb8, 1, 1, 0, 8, PNG_COLOR_TYPE_RGB);
}

TEST(Png, AFlatImageShrinks) {
  const std::vector<uint8_t> pixels(320 * 240 * 3, 90);
  std::vector<uint8_t> png;
  std::string why;
  ASSERT_TRUE(encode_png({320, 240, PixelFormat::Rgb8, 320 * 3, pixels}, png, why)) << why;
  EXPECT_LT(png.size(), pixels.size() / 50);
}

TEST(Png, TheSameImageGivesTheSameBytes) {
  const std::vector<uint8_t> pixels = make_pixels(20, 20, 3, 0, 3);
  std::vector<uint8_t> a, b;
  std::string why;
  ASSERT_TRUE(encode_png({20, 20, PixelFormat::Rgb8, 60, pixels}, a, why));
  ASSERT_TRUE(encode_png({20, 20, PixelFormat::Rgb8, 60, pixels}, b, why));
  EXPECT_EQ(a, b);
}

TEST(Png, DepthF32IsRefusedWithTheAlternative) {
  const std::vector<uint8_t> pixels(4 * 4 * 4);
  std::vector<uint8_t> png{1, 2, 3};
  std::string why;
  EXPECT_FALSE(encode_png({4, 4, PixelFormat::DepthF32, 16, pixels}, png, why));
  EXPECT_TRUE(png.empty());
  EXPECT_NE(why.find("DepthF32"), std::string::npos) << why;
  EXPECT_NE(why.find("DepthU16"), std::string::npos) << why;
}

TEST(Png, ShortDataAndEmptyImagesAreRefused) {
  const std::vector<uint8_t> pixels(10 * 10 * 3 - 1);
  std::vector<uint8_t> png;
  std::string why;
  EXPECT_FALSE(encode_png({10, 10, PixelFormat::Rgb8, 30, pixels}, png, why));
  EXPECT_NE(why.find("needs 300 bytes, it has 299"), std::string::npos) << why;
  EXPECT_FALSE(encode_png({10, 10, PixelFormat::Rgb8, 20, pixels}, png, why));  // stride under a row
  EXPECT_FALSE(encode_png({0, 10, PixelFormat::Rgb8, 30, pixels}, png, why));
  EXPECT_NE(why.find("0x10"), std::string::npos) << why;
}

}  // namespace
}  // namespace troupe::wire
