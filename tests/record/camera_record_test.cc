// Cameras recorded and played: troupe-sim serves the camera robot of
// examples/worlds/camera.world, paused; a client steps it and reads the
// images live while `troupe record` records them; `troupe play` then serves
// the same images (same stamps, same bytes) and answers Geometry and
// GetConfig as the camera did. A recording with an image that lacks pixels
// plays without it, and one cut inside an image record plays what came
// before.
#include <gtest/gtest.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <string>
#include <thread>
#include <vector>

#include "tests/record/process.h"
#include "wire/client/client.h"
#include "wire/client/proxies.h"
#include "wire/record/log_file.h"
#include "wire/writer.h"

namespace troupe::testing {
namespace {

const std::string kCameraWorld = std::string(TROUPE_SOURCE_DIR) + "/examples/worlds/camera.world";
constexpr int kImages = 4;

/// One image as a client reads it off the wire.
struct Seen {
  uint64_t header_us = 0, stamp_us = 0;
  unsigned width = 0, height = 0, stride = 0;
  wire::PixelFormat format = wire::PixelFormat::Rgb8;
  std::vector<uint8_t> data;
  bool operator==(const Seen&) const = default;
};

Seen seen_of(const wire::Message& msg) {
  const wire::CameraImage* im = msg.body_as_CameraImage();
  Seen s{wire::time_us(*msg.header()),
         im->stamp_us(),
         im->width(),
         im->height(),
         im->stride(),
         im->format(),
         {}};
  if (im->data()) s.data.assign(im->data()->begin(), im->data()->end());
  return s;
}

/// What the camera answers to Geometry and GetConfig, as numbers.
std::vector<float> camera_answers(client::Client& c, const wire::Address& cam) {
  std::vector<float> out;
  client::Reply g = c.request(cam, uint8_t(wire::CameraReqSub::Geometry));
  const wire::CameraGeometry* geo = g.ok() ? g.message()->body_as_CameraGeometry() : nullptr;
  EXPECT_NE(geo, nullptr) << c.error();
  if (geo != nullptr) {
    out = {geo->hfov(), geo->vfov(), geo->fx(), geo->fy(), geo->cx(), geo->cy(), geo->near(), geo->far()};
    if (geo->pose()) out.insert(out.end(), {geo->pose()->x(), geo->pose()->z(), geo->pose()->yaw()});
  }
  client::Reply k = c.request(cam, uint8_t(wire::CameraReqSub::GetConfig));
  const wire::CameraConfig* cfg = k.ok() ? k.message()->body_as_CameraConfig() : nullptr;
  EXPECT_NE(cfg, nullptr) << c.error();
  if (cfg != nullptr) out.insert(out.end(), {float(cfg->width()), float(cfg->height()), cfg->rate()});
  return out;
}

/// Connects `c` and finds the camera robot's camera.
bool connect_camera(client::Client& c, wire::Address& cam) {
  return c.connect() && c.resolve("cam/camera:0", cam);
}

/// Waits until `troupe record` says it has the camera open (it says so on
/// stderr), or has ended.
bool recording(Process& rec) {
  for (int i = 0; i < 500 && rec.running(); ++i) {
    if (rec.err().find("recording 1 device") != std::string::npos) return true;
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  return rec.err().find("recording 1 device") != std::string::npos;
}

class CameraRecordReplay : public ::testing::Test {
 protected:
  ~CameraRecordReplay() override { remove_tree(dir_); }
  std::string file(const std::string& name) const { return dir_ + "/" + name; }

  /// Plays `log` (held open), reads `want` images and the camera's answers
  /// through a client, then stops the player; its stderr in `err`.
  std::vector<Seen> play(const std::string& log, size_t want, std::vector<float>* answers, std::string& err) {
    uint16_t port = free_port();
    Process player({bin("bin/troupe"), "play", log, "--port", std::to_string(port), "--wait", "--hold"});
    EXPECT_TRUE(player.wait_listening(port)) << player.err();
    client::Client c("127.0.0.1", port);
    wire::Address cam;
    EXPECT_TRUE(connect_camera(c, cam)) << c.error();
    // Asked before opening for reading, as the recorder asks.
    if (answers != nullptr) *answers = camera_answers(c, cam);
    std::vector<Seen> seen;
    c.add_data_handler([&](const wire::Message& msg) {
      if (msg.body_as_CameraImage() != nullptr) seen.push_back(seen_of(msg));
    });
    EXPECT_TRUE(c.open(cam, wire::Access::Read)) << c.error();
    // Bounded by the player's pace: 0.1 s between images as recorded.
    auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(30);
    while (seen.size() < want && std::chrono::steady_clock::now() < deadline) c.spin_once(50);
    c.spin_for(300);  // nothing more arrives than the log holds
    EXPECT_EQ(player.stop(), 0);
    err = player.err();
    return seen;
  }

  /// The live side: troupe-sim on the camera world, paused (so a client
  /// steps it image by image), and a client that found its camera.
  void SetUp() override {
    ASSERT_TRUE(sim_.wait_listening(port_)) << sim_.err();
    ASSERT_TRUE(connect_camera(live_, cam_)) << live_.error();
  }

  const std::string dir_ = make_temp_dir("troupe-camera-record-");
  const uint16_t port_ = free_port();
  Process sim_{{bin("bin/troupe-sim"), kCameraWorld, "--port", std::to_string(port_), "--paused"}};
  client::Client live_{"127.0.0.1", port_};
  wire::Address cam_;
};

TEST_F(CameraRecordReplay, PlayServesTheImagesAClientReadLiveAndTheCamerasAnswers) {
  const std::vector<float> live_answers = camera_answers(live_, cam_);
  ASSERT_EQ(live_answers.size(), 14u);

  std::string log = file("camera.trl");
  Process rec({bin("bin/troupe"), "record", "127.0.0.1:" + std::to_string(port_), "cam/camera:0", "-o", log,
               "--count", std::to_string(kImages)});
  ASSERT_TRUE(recording(rec)) << rec.err();

  std::vector<Seen> seen_live;
  live_.add_data_handler([&](const wire::Message& msg) {
    if (msg.body_as_CameraImage() != nullptr) seen_live.push_back(seen_of(msg));
  });
  ASSERT_TRUE(live_.open(cam_, wire::Access::Read)) << live_.error();
  client::SimulationProxy step(live_);
  // The robot turns, so every image differs from the one before.
  ASSERT_EQ(run_program({bin("bin/troupe"), "cmd", "127.0.0.1:" + std::to_string(port_), "cam/position2d:0",
                         "vel", "0", "0", "1.0"})
                .rc,
            0);
  // One image per step; the recorder stops after kImages of them.
  for (int i = 0; i < 3 * kImages && rec.running(); ++i) {
    ASSERT_TRUE(step.step(1)) << live_.error();
    ASSERT_TRUE(live_.sync()) << live_.error();
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  ASSERT_EQ(rec.wait(), 0) << rec.err();
  EXPECT_NE(rec.err().find("recorded 4 frames"), std::string::npos) << rec.err();
  EXPECT_EQ(sim_.stop(), 0);
  ASSERT_GE(seen_live.size(), size_t(kImages));
  seen_live.resize(kImages);
  EXPECT_EQ(seen_live[0].width, 160u);
  EXPECT_EQ(seen_live[0].data.size(), 160u * 120u * 3u);
  EXPECT_NE(seen_live[0].data, seen_live[1].data);
  // The first image is taken at 0 s simulated (its header says 0, which a
  // replay must keep), the next at the first step.
  EXPECT_EQ(seen_live[0].header_us, 0u);
  EXPECT_EQ(seen_live[1].header_us, 100000u);

  std::string err;
  std::vector<float> played_answers;
  EXPECT_EQ(play(log, kImages, &played_answers, err), seen_live) << err;
  EXPECT_EQ(played_answers, live_answers);

  // An image record whose pixels were cut short (its checksum is right: the
  // damage happened before it was written) is skipped, the rest plays.
  record::LogReader reader;
  std::string error;
  ASSERT_TRUE(reader.open(log, error)) << error;
  std::string short_log = file("short.trl");
  record::LogWriter writer;
  ASSERT_TRUE(writer.open(short_log, 0, error)) << error;
  record::LogRecord r;
  int images = 0;
  uint64_t damaged_at = 0, third_at = 0;
  while (reader.next(r)) {
    const wire::CameraImage* im = r.message->body_as_CameraImage();
    if (im != nullptr && ++images == 2) {
      damaged_at = writer.bytes();
      wire::MessageWriter w;
      auto& b = w.start();
      auto data = b.CreateVector(im->data()->data(), im->data()->size() / 2);
      auto body = wire::CreateCameraImage(b, im->width(), im->height(), im->format(), im->stride(),
                                          im->compression(), data, im->stamp_us());
      const wire::Header& h = *r.message->header();
      ASSERT_TRUE(
          writer.write(r.time_us,
                       w.finish(wire::make_header(h.addr(), h.kind(), h.subtype(), h.seq(), wire::time_us(h)),
                                wire::Body::CameraImage, body.Union()),
                       error))
          << error;
      continue;
    }
    if (im != nullptr && images == 3) third_at = writer.bytes();
    ASSERT_TRUE(writer.write(r.time_us, r.frame, error)) << error;
  }
  ASSERT_TRUE(writer.close(error)) << error;
  ASSERT_EQ(images, kImages);
  std::vector<Seen> without_second = seen_live;
  without_second.erase(without_second.begin() + 1);
  EXPECT_EQ(play(short_log, kImages - 1, nullptr, err), without_second);
  EXPECT_NE(err.find("byte " + std::to_string(damaged_at) +
                     ": a 160x120 Rgb8 image with 28800 bytes of pixels, 28800 short of its 57600: skipping"),
            std::string::npos)
      << err;

  // A file cut inside the third image's record: the two before it play, and
  // play names where the file ends.
  std::string cut = file("cut.trl");
  ASSERT_EQ(truncate(short_log.c_str(), off_t(third_at + 1000)), 0);
  ASSERT_EQ(rename(short_log.c_str(), cut.c_str()), 0);
  EXPECT_EQ(play(cut, 1, nullptr, err), std::vector<Seen>(seen_live.begin(), seen_live.begin() + 1));
  EXPECT_NE(err.find("byte " + std::to_string(third_at) + ": record of"), std::string::npos) << err;
  EXPECT_NE(err.find("truncated"), std::string::npos) << err;
}

// --image-compression png: the recorder's Open asks for PNG, troupe-sim
// encodes each image once for every PNG reader, so the recording holds the
// very files a live PNG reader got, and play serves them unchanged.
TEST_F(CameraRecordReplay, PngImagesAreRecordedAsTheCameraPackedThem) {
  std::string log = file("png.trl");
  Process rec({bin("bin/troupe"), "record", "127.0.0.1:" + std::to_string(port_), "cam/camera:0", "-o", log,
               "--count", "2", "--image-compression", "png"});
  ASSERT_TRUE(recording(rec)) << rec.err();

  std::vector<Seen> seen_live;
  std::vector<wire::ImageCompression> packing;
  live_.add_data_handler([&](const wire::Message& msg) {
    if (const wire::CameraImage* im = msg.body_as_CameraImage()) {
      seen_live.push_back(seen_of(msg));
      packing.push_back(im->compression());
    }
  });
  ASSERT_TRUE(live_.open(cam_, wire::Access::Read, wire::Delivery::Push, wire::ImageCompression::Png))
      << live_.error();
  client::SimulationProxy step(live_);
  for (int i = 0; i < 6 && rec.running(); ++i) {
    ASSERT_TRUE(step.step(1)) << live_.error();
    ASSERT_TRUE(live_.sync()) << live_.error();
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  ASSERT_EQ(rec.wait(), 0) << rec.err();
  EXPECT_EQ(sim_.stop(), 0);
  ASSERT_GE(seen_live.size(), 2u);
  seen_live.resize(2);
  EXPECT_EQ(packing[0], wire::ImageCompression::Png);
  // A PNG file, far smaller than the 160x120 Rgb8 rows it holds.
  ASSERT_GE(seen_live[0].data.size(), 8u);
  EXPECT_EQ(std::vector<uint8_t>(seen_live[0].data.begin(), seen_live[0].data.begin() + 8),
            (std::vector<uint8_t>{0x89, 'P', 'N', 'G', '\r', '\n', 0x1A, '\n'}));
  EXPECT_LT(seen_live[0].data.size(), 160u * 120u * 3u / 4);

  std::string err;
  EXPECT_EQ(play(log, 2, nullptr, err), seen_live) << err;

  Outcome bad = run_program({bin("bin/troupe"), "record", "127.0.0.1:1", "cam/camera:0", "-o",
                             file("never.trl"), "--image-compression", "jpeg"});
  EXPECT_EQ(bad.rc, 2);
  EXPECT_NE(bad.err.find("jpeg"), std::string::npos) << bad.err;
}

}  // namespace
}  // namespace troupe::testing
