// `troupe echo ADDR --png FILE` against the real troupe-sim serving the
// camera example: the file it writes, decoded by libpng, holds the pixels a
// C++ client reads raw from the same paused step. And wire::save_png() on
// raw images (what echo does when a camera cannot compress).
#include <gtest/gtest.h>

#include <fstream>
#include <iterator>

#include "tests/support/child_process.h"
#include "tests/support/png_decode.h"
#include "wire/client/proxies.h"
#include "wire/png.h"

namespace troupe {
namespace {

const std::string kBin = TROUPE_BINARY_DIR;
const std::string kWorld = std::string(TROUPE_SOURCE_DIR) + "/examples/worlds/camera.world";

std::vector<uint8_t> read_file(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

class EchoPng : public ::testing::Test {
 protected:
  void SetUp() override {
    port_ = testing::free_port();
    host_ = "127.0.0.1:" + std::to_string(port_);
    dir_ = testing::make_temp_dir("troupe-echo-png-");
    std::string error;
    ASSERT_TRUE(sim_.start(
        {kBin + "/bin/troupe-sim", kWorld, "--paused", "--no-view", "--port", std::to_string(port_)}, dir_,
        "troupe-sim", error))
        << error;
    ASSERT_TRUE(testing::wait_for_listener(port_, 10)) << "troupe-sim did not start: " << sim_.err();
  }
  void TearDown() override {
    sim_.stop();
    testing::remove_tree(dir_);
  }
  testing::ProgramResult echo(const std::string& args) {
    return testing::run_to_end({"/bin/sh", "-c", kBin + "/bin/troupe echo " + host_ + " " + args}, 60000);
  }

  testing::ChildProcess sim_;
  uint16_t port_ = 0;
  std::string host_, dir_;
};

TEST_F(EchoPng, WritesTheCamerasImageAsAPngWithTheSamePixels) {
  client::Client c("127.0.0.1", port_);
  ASSERT_TRUE(c.connect()) << c.error();
  client::CameraProxy raw(c, 0, 0);
  client::SimulationProxy sim(c);
  ASSERT_TRUE(raw.is_open() && sim.is_open()) << c.error();
  for (auto format : {wire::PixelFormat::Rgb8, wire::PixelFormat::DepthU16}) {
    SCOPED_TRACE(wire::EnumNamePixelFormat(format));
    client::CameraSettings s;
    s.format = format;
    ASSERT_TRUE(raw.configure(s)) << c.error();
    ASSERT_TRUE(sim.step(1)) << c.error();
    ASSERT_TRUE(c.sync());
    ASSERT_EQ(raw.image().compression, wire::ImageCompression::None);
    // Paused: echo's image is of the step the raw one is.
    const std::string file = dir_ + "/view.png";
    const testing::ProgramResult r = echo("cam/camera:0 --png " + file);
    ASSERT_EQ(r.status, 0) << r.err;
    EXPECT_NE(r.out.find("image=160x120"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("compression=Png"), std::string::npos) << r.out;
    test::DecodedPng d;
    std::string why;
    ASSERT_TRUE(test::decode_png(read_file(file), d, why)) << why;
    EXPECT_EQ(d.width, 160u);
    EXPECT_EQ(d.height, 120u);
    EXPECT_EQ(d.pixels, raw.image().data);
  }
}

TEST_F(EchoPng, RefusesANonCameraAddressAndAnUnwritableFile) {
  const testing::ProgramResult not_camera = echo("cam/position2d:0 --png " + dir_ + "/x.png");
  EXPECT_NE(not_camera.status, 0);
  EXPECT_NE(not_camera.err.find("--png saves camera images; cam/position2d:0 is a position2d device"),
            std::string::npos)
      << not_camera.err;
  client::Client c("127.0.0.1", port_);
  ASSERT_TRUE(c.connect());
  client::SimulationProxy sim(c);
  ASSERT_TRUE(sim.step(1));  // an image to write
  const testing::ProgramResult unwritable = echo("cam/camera:0 --png " + dir_ + "/no/such/dir/x.png");
  EXPECT_NE(unwritable.status, 0);
  EXPECT_NE(unwritable.err.find("cannot write " + dir_ + "/no/such/dir/x.png: No such file or directory"),
            std::string::npos)
      << unwritable.err;
  // The simulator serves on: the camera still answers.
  client::CameraProxy cam(c, 0, 0);
  client::CameraModel g;
  EXPECT_TRUE(cam.geometry(g)) << c.error();
}

// A raw image as a device sends it, built with FlatBuffers.
struct RawImage {
  flatbuffers::FlatBufferBuilder b;
  const wire::CameraImage* image;
  RawImage(uint16_t w, uint16_t h, wire::PixelFormat format, uint32_t stride,
           const std::vector<uint8_t>& pixels) {
    b.Finish(wire::CreateCameraImage(b, w, h, format, stride, wire::ImageCompression::None,
                                     b.CreateVector(pixels)));
    image = flatbuffers::GetRoot<wire::CameraImage>(b.GetBufferPointer());
  }
};

TEST(SavePng, RawRowsAreEncodedAndPaddingDropped) {
  const std::string dir = testing::make_temp_dir("troupe-save-png-");
  std::vector<uint8_t> pixels(4 * 7);  // 2x4 Mono8 in rows of 7 bytes (5 of padding)
  for (size_t i = 0; i < pixels.size(); ++i) pixels[i] = uint8_t(i * 9);
  RawImage raw(2, 4, wire::PixelFormat::Mono8, 7, pixels);
  std::string why;
  ASSERT_TRUE(wire::save_png(*raw.image, dir + "/m.png", why)) << why;
  test::DecodedPng d;
  ASSERT_TRUE(test::decode_png(read_file(dir + "/m.png"), d, why)) << why;
  EXPECT_EQ(d.pixels, (std::vector<uint8_t>{0, 9, 63, 72, 126, 135, 189, 198}));

  RawImage depth(2, 2, wire::PixelFormat::DepthF32, 8, std::vector<uint8_t>(16));
  EXPECT_FALSE(wire::save_png(*depth.image, dir + "/d.png", why));
  EXPECT_NE(why.find("DepthF32 image has no lossless PNG form"), std::string::npos) << why;
  RawImage short_rows(4, 4, wire::PixelFormat::Rgb8, 12, std::vector<uint8_t>(40));
  EXPECT_FALSE(wire::save_png(*short_rows.image, dir + "/s.png", why));
  EXPECT_NE(why.find("needs 48 bytes, it has 40"), std::string::npos) << why;
  testing::remove_tree(dir);
}

}  // namespace
}  // namespace troupe
