// A simulated camera over the wire: troupe-sim serves camera:0 of a robot,
// the C++ client reads its images in every format, asks for its geometry
// and configuration, and is refused, with the reason, a configuration whose
// images would not fit a frame.
#include <gtest/gtest.h>

#include <cmath>
#include <thread>

#include "tests/sim/served_world.h"
#include "tests/support/png_decode.h"
#include "wire/client/proxies.h"
#include "wire/image.h"

namespace troupe::sim {
namespace {

// A red wall 1 m high across the world at x = 3 (a 0.2 m thick box), the
// camera robot at the origin facing it.
const char* kWorld = R"(
resolution 0.02
interval_sim 100
model ( name "wall" pose [3.1 0 0 0] size [0.2 8 1.0] color "red" )
position ( name "cam" size [0.4 0.4 0.3] localization "gps"
  camera ( resolution [40 30] range [0.1 8] fov [60 45] ) )
position ( name "omni" pose [0 2 0 0] size [0.4 0.4 0.3] localization "gps"
  camera ( mirror "isometric" resolution [60 60] mirror_range 3 mirror_ground 0.75 mirror_top 20 ) )
)";

class CameraWire : public test::ServedWorld {
 protected:
  CameraWire() : ServedWorld(kWorld) {}
};

TEST_F(CameraWire, ImagesGeometryAndConfigurationOverTheWire) {
  client::Client c("127.0.0.1", runner_.port());
  ASSERT_TRUE(c.connect()) << c.error();
  std::vector<client::DeviceEntry> devices;
  ASSERT_TRUE(c.device_list(devices));
  bool listed = false;
  for (const auto& d : devices) listed = listed || d.text() == "cam/camera:0";
  EXPECT_TRUE(listed);

  client::CameraProxy cam(c, 0, 0);
  client::SimulationProxy sim(c);
  ASSERT_TRUE(cam.is_open() && sim.is_open()) << c.error();
  ASSERT_TRUE(sim.step(1));
  ASSERT_TRUE(c.sync());
  const client::Image& im = cam.image();
  ASSERT_EQ(im.width, 40u);
  ASSERT_EQ(im.height, 30u);
  EXPECT_EQ(im.format, wire::PixelFormat::Rgb8);
  EXPECT_EQ(im.stride, 120u);
  EXPECT_EQ(im.stamp_us, 100000u);  // taken at the first step: 0.1 s simulated
  ASSERT_EQ(im.data.size(), 40u * 30u * 3u);
  // The middle pixel sees the wall: red.
  const size_t mid = (15u * 40u + 20u) * 3u;
  EXPECT_EQ(im.data[mid], 0xFF);
  EXPECT_EQ(im.data[mid + 1], 0);
  EXPECT_EQ(im.data[mid + 2], 0);

  client::CameraModel g;
  ASSERT_TRUE(cam.geometry(g)) << c.error();
  EXPECT_NEAR(g.hfov, 60 * kPi / 180, 1e-5);
  EXPECT_NEAR(g.fx, 20 / std::tan(30 * kPi / 180), 1e-3);
  EXPECT_NEAR(g.cx, 20, 1e-5);
  EXPECT_NEAR(g.far, 8, 1e-5);
  EXPECT_EQ(g.projection, wire::CameraProjection::Pinhole);

  // The omnidirectional camera says how its pixels map: the ground ring
  // 0.75 x 30 px wide showing 3 m of floor, 20 degrees up at the rim.
  client::CameraProxy omni(c, 0, 1);
  ASSERT_TRUE(omni.is_open()) << c.error();
  client::CameraModel og;
  ASSERT_TRUE(omni.geometry(og)) << c.error();
  EXPECT_EQ(og.projection, wire::CameraProjection::OmniIsometric);
  EXPECT_NEAR(og.hfov, 2 * kPi, 1e-5);
  EXPECT_NEAR(og.cx, 30, 1e-5);
  EXPECT_NEAR(og.cy, 30, 1e-5);
  EXPECT_NEAR(og.rim_radius, 30, 1e-5);
  EXPECT_NEAR(og.ground_radius, 22.5, 1e-5);
  EXPECT_NEAR(og.mirror_range, 3, 1e-5);
  EXPECT_NEAR(og.rim_elevation, 20 * kPi / 180, 1e-5);
  EXPECT_EQ(og.fx, 0);

  // Depth in metres: the wall's face at x = 3, straight ahead.
  client::CameraSettings s;
  s.format = wire::PixelFormat::DepthF32;
  ASSERT_TRUE(cam.configure(s)) << c.error();
  EXPECT_EQ(s.width, 40u);
  EXPECT_EQ(s.format, wire::PixelFormat::DepthF32);
  ASSERT_TRUE(sim.step(1));
  ASSERT_TRUE(c.sync());
  ASSERT_EQ(cam.image().format, wire::PixelFormat::DepthF32);
  const double fy = 15 / std::tan(22.5 * kPi / 180);
  const double k = fy / std::cos(std::atan2(0.5, 20 / std::tan(30 * kPi / 180)));
  const double slope = 0.5 / k;  // row 15's centre is half a pixel below the centre
  EXPECT_NEAR(cam.depth(20, 15), 3 * std::sqrt(1 + slope * slope) / std::cos(std::atan2(0.5, g.fx)), 0.03);
  EXPECT_TRUE(std::isinf(cam.depth(0, 0)));  // the sky

  // Millimetres, and grey levels.
  s = {};
  s.format = wire::PixelFormat::DepthU16;
  ASSERT_TRUE(cam.configure(s)) << c.error();
  ASSERT_TRUE(sim.step(1));
  ASSERT_TRUE(c.sync());
  ASSERT_EQ(cam.image().data.size(), 40u * 30u * 2u);
  EXPECT_NEAR(cam.depth(20, 15), 3.0, 0.03);
  s = {};
  s.format = wire::PixelFormat::Mono8;
  s.width = 20;
  s.height = 10;
  ASSERT_TRUE(cam.configure(s)) << c.error();
  EXPECT_EQ(s.width, 20u);
  ASSERT_TRUE(sim.step(1));
  ASSERT_TRUE(c.sync());
  ASSERT_EQ(cam.image().data.size(), 200u);
  EXPECT_EQ(cam.image().data[5 * 20 + 10], 76);  // red's luma: 0.299 x 255

  // Too large for a frame: refused with the reason, the old configuration kept.
  s = {};
  s.width = 1024;
  s.height = 768;
  s.format = wire::PixelFormat::Rgb8;
  EXPECT_FALSE(cam.configure(s));
  EXPECT_NE(c.error().find("1024x768 Rgb8 image needs a"), std::string::npos) << c.error();
  EXPECT_NE(c.error().find("frame limit"), std::string::npos) << c.error();
  ASSERT_TRUE(sim.step(1));
  ASSERT_TRUE(c.sync());
  EXPECT_EQ(cam.image().width, 20u);

  // Out-of-range values are refused before the device sees them.
  s = {};
  s.width = 5000;
  EXPECT_FALSE(cam.configure(s));
  EXPECT_NE(c.error().find("width is 5000"), std::string::npos) << c.error();
}

// A reader that asks for PNG gets the step's image as a PNG file whose
// pixels (decoded by libpng, not by us) are the raw reader's; each format
// with a PNG form, and DepthF32, which has none, raw.
TEST_F(CameraWire, PngReadersGetTheSameImageCompressed) {
  client::Client raw_client("127.0.0.1", runner_.port()), png_client("127.0.0.1", runner_.port()),
      other_png_client("127.0.0.1", runner_.port());
  ASSERT_TRUE(raw_client.connect() && png_client.connect() && other_png_client.connect());
  client::CameraProxy raw(raw_client, 0, 0);
  client::CameraProxy png(png_client, 0, 0, wire::ImageCompression::Png);
  client::CameraProxy other_png(other_png_client, 0, 0, wire::ImageCompression::Png);
  client::SimulationProxy sim(raw_client);
  ASSERT_TRUE(raw.is_open() && png.is_open() && other_png.is_open() && sim.is_open());
  struct Case {
    wire::PixelFormat format;
    int bit_depth, colour_type;
  };
  for (const Case& k : {Case{wire::PixelFormat::Rgb8, 8, 2}, Case{wire::PixelFormat::Mono8, 8, 0},
                        Case{wire::PixelFormat::DepthU16, 16, 0}}) {
    SCOPED_TRACE(wire::EnumNamePixelFormat(k.format));
    client::CameraSettings s;
    s.format = k.format;
    ASSERT_TRUE(raw.configure(s)) << raw_client.error();
    ASSERT_TRUE(sim.step(1));
    ASSERT_TRUE(raw_client.sync() && png_client.sync() && other_png_client.sync());
    ASSERT_EQ(raw.image().compression, wire::ImageCompression::None);
    // Both PNG readers got the one frame encoded for them (one sequence
    // number); the raw reader a frame of its own.
    EXPECT_EQ(other_png.seq(), png.seq());
    EXPECT_NE(raw.seq(), png.seq());
    EXPECT_EQ(other_png.image().data, png.image().data);
    ASSERT_EQ(png.image().compression, wire::ImageCompression::Png);
    EXPECT_EQ(png.time_us(), raw.time_us());  // the same step's image
    troupe::test::DecodedPng d;
    std::string why;
    ASSERT_TRUE(troupe::test::decode_png(png.image().data, d, why)) << why;
    EXPECT_EQ(d.width, 40u);
    EXPECT_EQ(d.height, 30u);
    EXPECT_EQ(d.bit_depth, k.bit_depth);
    EXPECT_EQ(d.colour_type, k.colour_type);
    EXPECT_EQ(d.pixels, raw.image().data);
    EXPECT_LT(png.image().data.size(), raw.image().data.size());  // a wall and the sky: it shrinks
  }
  // No PNG form: the PNG reader gets the raw rows, which say so.
  client::CameraSettings s;
  s.format = wire::PixelFormat::DepthF32;
  ASSERT_TRUE(raw.configure(s));
  ASSERT_TRUE(sim.step(1));
  ASSERT_TRUE(raw_client.sync() && png_client.sync());
  EXPECT_EQ(png.image().compression, wire::ImageCompression::None);
  EXPECT_EQ(png.image().format, wire::PixelFormat::DepthF32);
  EXPECT_EQ(png.image().data, raw.image().data);
}

TEST(ImageFits, RefusesWhatExceedsTheLimitAndSaysWhy) {
  std::string why;
  EXPECT_TRUE(wire::image_fits(320, 240, wire::PixelFormat::Rgb8, 1u << 20, why));
  EXPECT_TRUE(wire::image_fits(320, 240, wire::PixelFormat::DepthF32, 1u << 20, why));
  EXPECT_FALSE(wire::image_fits(640, 480, wire::PixelFormat::DepthF32, 1u << 20, why));
  EXPECT_NE(why.find("640x480 DepthF32"), std::string::npos) << why;
  EXPECT_NE(why.find("1048576-byte frame limit"), std::string::npos) << why;
  // The boundary: exactly the limit fits, one byte less does not.
  const size_t need = wire::image_frame_bytes(100, 100, wire::PixelFormat::Mono8);
  EXPECT_TRUE(wire::image_fits(100, 100, wire::PixelFormat::Mono8, need, why));
  EXPECT_FALSE(wire::image_fits(100, 100, wire::PixelFormat::Mono8, need - 1, why));
}

// An image that claims more pixels than it carries is told apart, with the
// sizes, whichever of its fields is short.
TEST(ImageComplete, SaysWhatAnImageLacks) {
  auto check = [](uint16_t w, uint16_t h, wire::PixelFormat f, uint32_t stride, size_t bytes, std::string& why) {
    flatbuffers::FlatBufferBuilder b;
    std::vector<uint8_t> data(bytes, 7);
    b.Finish(wire::CreateCameraImage(b, w, h, f, stride, wire::ImageCompression::None, b.CreateVector(data)));
    return wire::image_complete(*flatbuffers::GetRoot<wire::CameraImage>(b.GetBufferPointer()), why);
  };
  std::string why;
  EXPECT_TRUE(check(4, 3, wire::PixelFormat::Rgb8, 12, 36, why));
  // Padded rows: the last row may end after its pixels.
  EXPECT_TRUE(check(4, 3, wire::PixelFormat::Rgb8, 16, 16 * 2 + 12, why));
  EXPECT_FALSE(check(4, 3, wire::PixelFormat::Rgb8, 16, 16 * 2 + 11, why));
  EXPECT_EQ(why, "a 4x3 Rgb8 image with 43 bytes of pixels, 1 short of its 44");
  EXPECT_FALSE(check(4, 3, wire::PixelFormat::DepthF32, 12, 36, why));
  EXPECT_EQ(why, "a 4x3 DepthF32 image with a stride of 12 bytes, under its 16-byte rows");
  EXPECT_FALSE(check(4, 3, wire::PixelFormat(9), 12, 36, why));
  EXPECT_EQ(why, "an image of unknown pixel format 9");
  EXPECT_TRUE(check(0, 0, wire::PixelFormat::Mono8, 0, 0, why));
}

}  // namespace
}  // namespace troupe::sim
