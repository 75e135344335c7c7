#include "tests/bench/wire/sizes.h"

#include <algorithm>

#include "wire/png.h"
#include "wire/writer.h"

namespace troupe::wire::sizes {
namespace {

constexpr size_t kPlayerHeader = 40;  // host, robot, interf, index, type, subtype (4 each), double time, seq, size
size_t pad4(size_t n) { return (n + 3) / 4 * 4; }

Address at(Interface i) { return Address(0, uint16_t(i), 0); }

template <typename Build>
size_t framed(Interface iface, Body type, Build build) {
  MessageWriter w;
  auto& b = w.start();
  auto body = build(b);
  return w.finish(make_header(at(iface), Kind::Data, 1, 123456, 1700000000000000ull), type, body.Union()).size();
}

std::string n(size_t v) { return std::to_string(v); }

}  // namespace

std::vector<Row> rows() {
  std::vector<Row> out;
  Pose2d pose(1.25f, -3.5f, 0.7f), vel(0.3f, 0, 0.2f);

  out.push_back({"position2d", "pose, velocity, stall", kPlayerHeader + 24 + 24 + 4, "40 + pose 3x8 + vel 3x8 + stall 4",
                 framed(Interface::Position2d, Body::Position2dState,
                        [&](auto& b) { return CreatePosition2dState(b, &pose, &vel, false); }),
                 false});

  for (size_t beams : {16, 181, 361}) {
    bool laser = beams > 16;
    out.push_back({"ranger", laser ? n(beams) + "-beam laser scan" : n(beams) + " sonar ranges",
                   kPlayerHeader + 4 + 4 + 8 * beams, "40 + count 4 + array count 4 + " + n(beams) + " doubles",
                   framed(Interface::Ranger, Body::RangerScan,
                          [&](auto& b) {
                            std::vector<uint16_t> r(beams);
                            for (size_t i = 0; i < beams; ++i) r[i] = uint16_t(500 + 37 * i % 7000);
                            auto v = b.CreateVector(r);
                            return laser ? CreateRangerScan(b, v, 0.001f, -1.5708f, 3.14159f / float(beams - 1), 8.0f)
                                         : CreateRangerScan(b, v, 0.001f, 0, 0, 5.0f);
                          }),
                   true});
  }

  out.push_back({"power", "volts", kPlayerHeader + 24, "40 + valid, volts, percent, joules, watts, charging 6x4",
                 framed(Interface::Power, Body::PowerState, [&](auto& b) {
                   PowerStateBuilder p(b);
                   p.add_volts(12.6f);
                   return p.Finish();
                 }),
                 false});
  out.push_back({"power", "volts, percent, charging", kPlayerHeader + 24, "(same)",
                 framed(Interface::Power, Body::PowerState, [&](auto& b) {
                   PowerStateBuilder p(b);
                   p.add_volts(12.6f);
                   p.add_percent(80);
                   p.add_charging(false);
                   return p.Finish();
                 }),
                 false});

  out.push_back({"bumper", "10 bumpers", kPlayerHeader + 4 + 4 + pad4(10), "40 + count 4 + bytes 4 + 10 padded to 12",
                 framed(Interface::Bumper, Body::BumperState, [&](auto& b) { return CreateBumperState(b, 0x12, 10); }),
                 false});

  out.push_back({"actuator", "gripper state (Player gripper)", kPlayerHeader + 12, "40 + state 4 + beams 4 + stored 4",
                 framed(Interface::Actuator, Body::ActuatorState,
                        [&](auto& b) { return CreateActuatorState(b, ActuatorMode::Closed, 0.02f, 3, 1); }),
                 false});

  Vec3 g(0.01f, -0.02f, 0.3f), a(0.1f, 0.05f, 9.81f), o(0.01f, 0.02f, 1.2f);
  out.push_back({"imu", "gyro, accel (Player calib)", kPlayerHeader + 36, "40 + accel, gyro, magn 9x4",
                 framed(Interface::Imu, Body::ImuState, [&](auto& b) { return CreateImuState(b, &g, &a); }), false});
  out.push_back({"imu", "gyro, accel, roll/pitch/yaw (Player euler)", kPlayerHeader + 36 + 12,
                 "40 + calib 9x4 + orientation 3x4",
                 framed(Interface::Imu, Body::ImuState, [&](auto& b) { return CreateImuState(b, &g, &a, &o); }),
                 false});

  for (size_t count : {1, 4, 16}) {
    out.push_back({"blobfinder", n(count) + (count == 1 ? " blob" : " blobs"), kPlayerHeader + 12 + 4 + 40 * count,
                   "40 + width, height, count 12 + array count 4 + " + n(count) + " x 40",
                   framed(Interface::Blobfinder, Body::BlobList,
                          [&](auto& b) {
                            std::vector<Blob> blobs(count, Blob(0xff8000, 420, 40, 30, 30, 50, 20, 40, 2300, 1));
                            return CreateBlobList(b, b.CreateVectorOfStructs(blobs), 80, 60);
                          }),
                   true});
  }
  for (size_t count : {1, 4, 16}) {
    out.push_back({"fiducial", n(count) + (count == 1 ? " landmark" : " landmarks"),
                   kPlayerHeader + 4 + 4 + 100 * count,
                   "40 + count 4 + array count 4 + " + n(count) + " x (id 4 + pose 6x8 + uncertainty 6x8)",
                   framed(Interface::Fiducial, Body::FiducialList,
                          [&](auto& b) {
                            std::vector<Fiducial> f(count, Fiducial(7, 2.5f, -0.4f, 0.3f));
                            return CreateFiducialList(b, b.CreateVectorOfStructs(f));
                          }),
                   true});
  }
  for (size_t count : {1, 4, 16}) {
    out.push_back({"localize", n(count) + (count == 1 ? " hypothesis" : " hypotheses"),
                   kPlayerHeader + 4 + 8 + 4 + 4 + 80 * count,
                   "40 + pending 4 + time 8 + count 4 + array count 4 + " + n(count) + " x (mean 3x8 + cov 6x8 + weight 8)",
                   framed(Interface::Localize, Body::LocalizeState,
                          [&](auto& b) {
                            std::vector<Hypothesis> h(count, Hypothesis(pose, Cov2d(0.01f, 0, 0, 0.01f, 0, 0.003f),
                                                                        1.0f / float(count)));
                            return CreateLocalizeState(b, b.CreateVectorOfStructs(h));
                          }),
                   true});
  }
  for (size_t side : {64, 256}) {
    size_t cells = side * side;
    out.push_back({"map", n(side) + "x" + n(side) + " tile", kPlayerHeader + 20 + 4 + 4 + pad4(cells),
                   "40 + col, row, width, height, count 5x4 + range 4 + bytes 4 + " + n(cells) + " cells x 1",
                   framed(Interface::Map, Body::MapTile,
                          [&](auto& b) {
                            std::vector<uint8_t> packed((cells + 3) / 4, 0x41);
                            return CreateMapTile(b, 0, 0, uint32_t(side), uint32_t(side), b.CreateVector(packed));
                          }),
                   true});
  }
  // Player's camera data: width, height, bpp, format, fdiv, compression
  // (6x4), image_count 4, then the bytes (XDR count 4 + bytes padded to 4).
  struct Shot {
    uint16_t w, h;
    PixelFormat format;
    const char* name;
  };
  for (const Shot& s : {Shot{320, 240, PixelFormat::Rgb8, "320x240 RGB8 image"},
                        Shot{320, 240, PixelFormat::DepthU16, "320x240 depth (u16 mm)"},
                        Shot{640, 480, PixelFormat::Mono8, "640x480 MONO8 image"}}) {
    const size_t bpp = s.format == PixelFormat::Rgb8 ? 3 : s.format == PixelFormat::DepthU16 ? 2 : 1;
    const size_t bytes = size_t(s.w) * s.h * bpp;
    out.push_back({"camera", s.name, kPlayerHeader + 24 + 4 + 4 + pad4(bytes),
                   "40 + width..compression 6x4 + image_count 4 + bytes 4 + " + n(bytes) + " bytes",
                   framed(Interface::Camera, Body::CameraImage,
                          [&](auto& b) {
                            std::vector<uint8_t> pixels(bytes, 0x41);
                            auto data = b.CreateVector(pixels);
                            return CreateCameraImage(b, s.w, s.h, s.format, uint32_t(s.w * bpp),
                                                     ImageCompression::None, data);
                          }),
                   true});
  }
  // A PNG image (Open's compression = Png) against Player's raw bytes
  // (Player compresses only as JPEG, lossy): a flat-shaded 320x240 scene as
  // the simulator renders one (sky, a wall, the floor, two boxes), encoded
  // by wire/png.h.
  const std::vector<uint8_t> scene = flat_scene_320x240();
  std::vector<uint8_t> png;
  std::string why;
  encode_png({320, 240, PixelFormat::Rgb8, 320 * 3, scene}, png, why);
  out.push_back({"camera", "320x240 RGB8 as PNG (flat-shaded scene)",
                 kPlayerHeader + 24 + 4 + 4 + scene.size(),
                 "Player's raw 320x240 RGB8 (it has no PNG); Troupe: the " + n(png.size()) + "-byte PNG file",
                 framed(Interface::Camera, Body::CameraImage,
                        [&](auto& b) {
                          return CreateCameraImage(b, 320, 240, PixelFormat::Rgb8, 0, ImageCompression::Png,
                                                   b.CreateVector(png));
                        }),
                 true});
  return out;
}

std::vector<uint8_t> flat_scene_320x240() {
  std::vector<uint8_t> scene(320 * 240 * 3);
  for (size_t y = 0; y < 240; ++y) {
    for (size_t x = 0; x < 320; ++x) {
      const bool red_box = x >= 60 && x < 120 && y >= 100 && y < 170;
      const bool green_box = x >= 200 && x < 230 && y >= 60 && y < 150;
      const uint32_t rgb = red_box     ? 0xff0000
                           : green_box ? 0x00ff00
                           : y < 80    ? 0xcfe3ff
                           : y < 120   ? 0x666666
                                       : 0xb4b4a0;
      for (size_t k = 0; k < 3; ++k) scene[3 * (y * 320 + x) + k] = uint8_t(rgb >> (16 - 8 * k));
    }
  }
  return scene;
}

}  // namespace troupe::wire::sizes
