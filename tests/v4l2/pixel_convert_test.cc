// The pixel conversions against BT.601 worked out independently: the
// floating-point formula written out here, and a few colours by hand.
#include "drivers/v4l2/pixel_convert.h"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

namespace troupe::drivers::v4l2 {
namespace {

// BT.601 Y'CbCr to R'G'B' in floating point (ITU-R BT.601: Kr = 0.299,
// Kb = 0.114): R = Y + 1.402 Pr, G = Y - 0.344136 Pb - 0.714136 Pr,
// B = Y + 1.772 Pb, with Y in 0..1 and Pb, Pr in -0.5..0.5. Limited range
// codes Y as 16 + 219 Y and Pb, Pr as 128 + 224 P.
void reference(int y, int cb, int cr, bool full, double rgb[3]) {
  const double Y = full ? y / 255.0 : (y - 16) / 219.0;
  const double pb = full ? (cb - 128) / 255.0 : (cb - 128) / 224.0;
  const double pr = full ? (cr - 128) / 255.0 : (cr - 128) / 224.0;
  const double v[3] = {Y + 1.402 * pr, Y - 0.344136 * pb - 0.714136 * pr, Y + 1.772 * pb};
  for (int i = 0; i < 3; ++i) rgb[i] = std::fmin(255.0, std::fmax(0.0, v[i] * 255.0));
}

TEST(PixelConvert, HandWorkedColours) {
  uint8_t rgb[3];
  // Limited range: Y' 235 is white, 16 black, whatever the grey chroma.
  ycbcr_to_rgb(235, 128, 128, false, rgb);
  EXPECT_EQ(rgb[0], 255);
  EXPECT_EQ(rgb[1], 255);
  EXPECT_EQ(rgb[2], 255);
  ycbcr_to_rgb(16, 128, 128, false, rgb);
  EXPECT_EQ(rgb[0], 0);
  EXPECT_EQ(rgb[1], 0);
  EXPECT_EQ(rgb[2], 0);
  // BT.601's red (81, 90, 240): Y = 65/219 = 0.2968, Pb = -38/224 = -0.1696,
  // Pr = 112/224 = 0.5; R = 0.2968 + 0.701 = 0.9978 (254.4), G = 0.2968 +
  // 0.0584 - 0.3571 < 0, B = 0.2968 - 0.3006 < 0.
  ycbcr_to_rgb(81, 90, 240, false, rgb);
  EXPECT_EQ(rgb[0], 254);
  EXPECT_EQ(rgb[1], 0);
  EXPECT_EQ(rgb[2], 0);
  // Full range (JPEG) red (76, 85, 255): R = 76 + 1.402 x 127 = 254.05,
  // G = 76 + 0.344136 x 43 - 0.714136 x 127 = 0.10, B = 76 - 1.772 x 43 < 0.
  ycbcr_to_rgb(76, 85, 255, true, rgb);
  EXPECT_EQ(rgb[0], 254);
  EXPECT_EQ(rgb[1], 0);
  EXPECT_EQ(rgb[2], 0);
  ycbcr_to_rgb(128, 128, 128, true, rgb);
  EXPECT_EQ(rgb[0], 128);
  EXPECT_EQ(rgb[1], 128);
  EXPECT_EQ(rgb[2], 128);
}

TEST(PixelConvert, EveryCodeWithinOneOfTheFormula) {
  for (bool full : {false, true}) {
    for (int y = 0; y < 256; y += 3) {
      for (int cb = 0; cb < 256; cb += 5) {
        for (int cr = 0; cr < 256; cr += 7) {
          uint8_t got[3];
          double want[3];
          ycbcr_to_rgb(uint8_t(y), uint8_t(cb), uint8_t(cr), full, got);
          reference(y, cb, cr, full, want);
          for (int i = 0; i < 3; ++i) {
            ASSERT_LE(std::fabs(got[i] - want[i]), 1.0) << "Y'CbCr " << y << " " << cb << " " << cr
                                                        << (full ? " full" : " limited") << " channel " << i;
          }
        }
      }
    }
  }
}

TEST(PixelConvert, Luma) {
  // 0.299 x 255 = 76.2, 0.587 x 255 = 149.7, 0.114 x 255 = 29.1.
  EXPECT_EQ(rgb_to_luma(255, 0, 0), 76);
  EXPECT_EQ(rgb_to_luma(0, 255, 0), 150);
  EXPECT_EQ(rgb_to_luma(0, 0, 255), 29);
  EXPECT_EQ(rgb_to_luma(255, 255, 255), 255);
  // Limited Y' 16..235 stretched to 0..255: 126 is (126 - 16) x 255 / 219 = 128.08.
  EXPECT_EQ(luma_to_grey(16, false), 0);
  EXPECT_EQ(luma_to_grey(235, false), 255);
  EXPECT_EQ(luma_to_grey(126, false), 128);
  EXPECT_EQ(luma_to_grey(5, false), 0);  // below black: clamped
  EXPECT_EQ(luma_to_grey(240, false), 255);
  EXPECT_EQ(luma_to_grey(126, true), 126);
}

// A 4 x 2 YUYV image with 4 bytes of padding after each row: pixel pairs
// share their chroma, and the padding is never read.
TEST(PixelConvert, YuyvImageWithPaddedRows) {
  const uint8_t pad = 0xEE;
  const std::vector<uint8_t> in = {
      235, 128, 16,  128, 81, 90,  81,  240, pad, pad, pad, pad,  // white, black | red, red
      126, 128, 126, 128, 16, 128, 235, 128, pad, pad, pad, pad,
  };
  std::vector<uint8_t> rgb(4 * 2 * 3, 0x55);
  convert_image(Fourcc::Yuyv, in.data(), 12, 4, 2, false, true, rgb.data());
  const std::vector<uint8_t> want_rgb = {255, 255, 255, 0,   0,   0,   254, 0, 0, 254, 0,   0,
                                         128, 128, 128, 128, 128, 128, 0,   0, 0, 255, 255, 255};
  EXPECT_EQ(rgb, want_rgb);
  std::vector<uint8_t> grey(8, 0x55);
  convert_image(Fourcc::Yuyv, in.data(), 12, 4, 2, false, false, grey.data());
  // Y' 81: 65 x 255 / 219 = 75.7.
  EXPECT_EQ(grey, (std::vector<uint8_t>{255, 0, 76, 76, 128, 128, 0, 255}));
}

TEST(PixelConvert, Rgb24AndGreyWithPaddedRows) {
  const std::vector<uint8_t> rgb_in = {255, 0, 0,   0,  255, 0,  9, 9,  // red, green, padding
                                       0,   0, 255, 10, 20,  30, 9, 9};
  std::vector<uint8_t> out(2 * 2 * 3);
  convert_image(Fourcc::Rgb24, rgb_in.data(), 8, 2, 2, false, true, out.data());
  EXPECT_EQ(out, (std::vector<uint8_t>{255, 0, 0, 0, 255, 0, 0, 0, 255, 10, 20, 30}));
  std::vector<uint8_t> mono(4);
  convert_image(Fourcc::Rgb24, rgb_in.data(), 8, 2, 2, false, false, mono.data());
  // 0.299 x 10 + 0.587 x 20 + 0.114 x 30 = 18.15.
  EXPECT_EQ(mono, (std::vector<uint8_t>{76, 150, 29, 18}));

  const std::vector<uint8_t> grey_in = {7, 200, 1, 0, 99, 1};  // 2 px + 1 byte padding
  std::vector<uint8_t> grey_rgb(2 * 2 * 3);
  convert_image(Fourcc::Grey, grey_in.data(), 3, 2, 2, false, true, grey_rgb.data());
  EXPECT_EQ(grey_rgb, (std::vector<uint8_t>{7, 7, 7, 200, 200, 200, 0, 0, 0, 99, 99, 99}));
  std::vector<uint8_t> grey_mono(4);
  convert_image(Fourcc::Grey, grey_in.data(), 3, 2, 2, false, false, grey_mono.data());
  EXPECT_EQ(grey_mono, (std::vector<uint8_t>{7, 200, 0, 99}));
}

}  // namespace
}  // namespace troupe::drivers::v4l2
