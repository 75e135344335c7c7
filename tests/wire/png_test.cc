// encode_png() against an independent decoder: libpng reads back every
// encoded image and its pixels must equal the input's, for each format,
// with padded rows, flat areas (which the filters and deflate shrink) and
// noise (which they cannot).
#include "wire/png.h"

#include <gtest/gtest.h>
#include <png.h>  // colour type constants

#include <cstring>

#include "runtime/random.h"
#include "tests/support/png_decode.h"
#include "wire/image.h"

namespace troupe::wire {
namespace {

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
  test::DecodedPng d;
  ASSERT_TRUE(test::decode_png(png, d, why)) << why;
  ASSERT_EQ(d.width, w);
  ASSERT_EQ(d.height, h);
  EXPECT_EQ(d.bit_depth, bit_depth);
  EXPECT_EQ(d.colour_type, colour_type);
  ASSERT_EQ(d.pixels.size(), size_t(w) * h * bpp);
  for (uint32_t y = 0; y < h; ++y) {
    for (size_t i = 0; i < w * bpp; ++i) {
      ASSERT_EQ(d.pixels[y * w * bpp + i], pixels[y * view.stride + i]) << "row " << y << " byte " << i;
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
