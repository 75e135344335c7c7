// The v4l2 driver against a real kernel video driver: vivid, in the VM of
// tests/vcan (TROUPE_TEST_VIDEO_DEVICE names its capture node,
// TROUPE_TEST_VIVID_PLATFORM its platform device). Skipped elsewhere.
//
// vivid's default picture is 75% colour bars, which tells real images from
// garbage: eight bars across the image, left to right white, yellow, cyan,
// green, magenta, red, blue, black, each channel either about 191 or 0.
#include <fcntl.h>
#include <linux/videodev2.h>
#include <sys/ioctl.h>
#include <unistd.h>

#include <cstdlib>

#include "tests/v4l2/camera_bench.h"

namespace troupe::testing {
namespace {

std::string env(const char* name) {
  const char* v = getenv(name);
  return v ? v : "";
}

#define REQUIRE_VIVID()                                              \
  if (env("TROUPE_TEST_VIDEO_DEVICE").empty())                       \
  GTEST_SKIP() << "needs the kernel's vivid (the vcan VM test sets " \
                  "TROUPE_TEST_VIDEO_DEVICE)"

// "" when `im` shows the eight bars at the size asked for; else what is
// wrong. `colour`: each bar's hue is checked; otherwise (a grey camera) its
// luma, which falls from bar to bar.
std::string check_bars(const wire::CameraImage* im, uint32_t width, uint32_t height, bool colour = true) {
  if (im == nullptr || im->data() == nullptr) return "no image";
  const uint32_t bpp = im->format() == wire::PixelFormat::Rgb8 ? 3 : 1;
  if (im->width() != width || im->height() != height) {
    return "image " + std::to_string(im->width()) + "x" + std::to_string(im->height()) + ", negotiated " +
           std::to_string(width) + "x" + std::to_string(height);
  }
  if (im->stride() != width * bpp || im->data()->size() != size_t(im->stride()) * height) {
    return "stride " + std::to_string(im->stride()) + " and " + std::to_string(im->data()->size()) + " bytes";
  }
  static const bool kOn[8][3] = {{1, 1, 1}, {1, 1, 0}, {0, 1, 1}, {0, 1, 0},
                                 {1, 0, 1}, {1, 0, 0}, {0, 0, 1}, {0, 0, 0}};
  // A row near the bottom: vivid writes lines of text (about 150 px of
  // them) over the top of the picture.
  const uint8_t* row = im->data()->data() + size_t(height * 7 / 8) * im->stride();
  int previous_luma = 256;
  for (uint32_t bar = 0; bar < 8; ++bar) {
    const uint8_t* p = row + size_t((2 * bar + 1) * width / 16) * bpp;
    if (colour) {
      if (bpp != 3) return "a colour check of a grey image";
      for (int c = 0; c < 3; ++c) {
        const bool ok = kOn[bar][c] ? p[c] >= 150 : p[c] <= 60;
        if (!ok) {
          return "bar " + std::to_string(bar) + " is (" + std::to_string(p[0]) + ", " + std::to_string(p[1]) +
                 ", " + std::to_string(p[2]) + ")";
        }
      }
      continue;
    }
    // Grey: the bars' luma falls from left to right, 13 or more apart.
    const int luma = bpp == 3 ? (299 * p[0] + 587 * p[1] + 114 * p[2] + 500) / 1000 : p[0];
    if (luma + 8 >= previous_luma) {
      return "bar " + std::to_string(bar) + " has luma " + std::to_string(luma) + " after " +
             std::to_string(previous_luma);
    }
    previous_luma = luma;
  }
  return "";
}

// The row check_bars() looks at, every width/32 pixels (first channel), for
// a failure message.
std::string row_text(const wire::CameraImage* im) {
  if (im == nullptr || im->data() == nullptr || im->width() < 32) return "";
  const uint32_t bpp = im->format() == wire::PixelFormat::Rgb8 ? 3 : 1;
  const uint8_t* row = im->data()->data() + size_t(im->height() * 7 / 8) * im->stride();
  std::string text = "row:";
  for (uint32_t x = 0; x < im->width(); x += im->width() / 32) text += " " + std::to_string(row[x * bpp]);
  return text;
}

// Presses one of vivid's button controls, found by its name, through a
// second file handle of the device (the driver's keeps streaming). "" or
// what failed.
std::string press_vivid_button(const std::string& device, const std::string& name) {
  const int fd = open(device.c_str(), O_RDWR);
  if (fd < 0) return "cannot open " + device;
  std::string error = "vivid has no control \"" + name + "\"";
  v4l2_queryctrl q{};
  q.id = V4L2_CTRL_FLAG_NEXT_CTRL;
  while (ioctl(fd, VIDIOC_QUERYCTRL, &q) == 0) {
    if (name == reinterpret_cast<const char*>(q.name)) {
      v4l2_control c{};
      c.id = q.id;
      c.value = 1;
      error = ioctl(fd, VIDIOC_S_CTRL, &c) == 0 ? "" : "VIDIOC_S_CTRL " + name + " failed";
      break;
    }
    q.id |= V4L2_CTRL_FLAG_NEXT_CTRL;
  }
  close(fd);
  return error;
}

class Vivid : public CameraBench {
 protected:
  // Waits for `n` more images; true when they came.
  bool images(uint32_t n) {
    const uint32_t from = client_.count(kCamera);
    return loop_.run_until([&] { return client_.count(kCamera) >= from + n; }, 60);
  }
  // The negotiated size, from GetConfig.
  bool config(uint32_t& width, uint32_t& height) {
    const wire::Message* m = ask(wire::CameraReqSub::GetConfig);
    if (m == nullptr || m->header()->kind() != wire::Kind::Ack) return false;
    width = m->body_as_CameraConfig()->width();
    height = m->body_as_CameraConfig()->height();
    return true;
  }
  static bool write_sysfs(const std::string& path, const std::string& text) {
    int fd = open(path.c_str(), O_WRONLY);
    if (fd < 0) return false;
    const bool ok = write(fd, text.data(), text.size()) == ssize_t(text.size());
    close(fd);
    return ok;
  }
  std::string device_options(const std::string& more) {
    return R"("device": ")" + env("TROUPE_TEST_VIDEO_DEVICE") +
           R"(", "rate": 10, "reopen_min_ms": 100, "reopen_max_ms": 400, )" + more;
  }
};

struct Formats {
  const char* capture;  // the capture_format option
  const char* format;   // the format option
};

void PrintTo(const Formats& f, std::ostream* out) {
  *out << f.capture << " to " << f.format;
}

class VividFormats : public Vivid, public ::testing::WithParamInterface<Formats> {};

TEST_P(VividFormats, ImagesShowTheColourBarsAtTheNegotiatedSize) {
  REQUIRE_VIVID();
  ASSERT_TRUE(start(device_options(std::string(R"("width": 640, "height": 480, "capture_format": ")") +
                                   GetParam().capture + R"(", "format": ")" + GetParam().format + "\"")))
      << error();
  ASSERT_TRUE(images(3));
  uint32_t w = 0, h = 0;
  ASSERT_TRUE(config(w, h));
  EXPECT_EQ(w, 640u);  // a size vivid's webcam input has
  EXPECT_EQ(h, 480u);
  EXPECT_EQ(image()->format(),
            std::string(GetParam().format) == "Rgb8" ? wire::PixelFormat::Rgb8 : wire::PixelFormat::Mono8);
  const bool colour = std::string(GetParam().capture) != "Grey" && std::string(GetParam().format) == "Rgb8";
  EXPECT_EQ(check_bars(image(), w, h, colour), "") << row_text(image());
}

INSTANTIATE_TEST_SUITE_P(Each, VividFormats,
                         ::testing::Values(Formats{"Rgb24", "Rgb8"}, Formats{"Yuyv", "Rgb8"},
                                           Formats{"Grey", "Mono8"}, Formats{"Yuyv", "Mono8"},
                                           Formats{"Rgb24", "Mono8"}, Formats{"Grey", "Rgb8"}),
                         [](const ::testing::TestParamInfo<Formats>& p) {
                           return std::string(p.param.capture) + "To" + p.param.format;
                         });

TEST_F(Vivid, SetConfigRenegotiatesTheSize) {
  REQUIRE_VIVID();
  ASSERT_TRUE(start(device_options(R"("width": 320, "height": 180)"))) << error();
  ASSERT_TRUE(images(1));
  auto& b = client_.begin();
  auto want = wire::CreateCameraConfig(b, 640, 360, 5, wire::PixelFormat::Rgb8);
  const wire::Message* m = ask(wire::CameraReqSub::SetConfig, wire::Body::CameraConfig, want.Union());
  ASSERT_NE(m, nullptr);
  ASSERT_EQ(m->header()->kind(), wire::Kind::Ack) << nack_text(m);
  EXPECT_EQ(m->body_as_CameraConfig()->width(), 640u);
  EXPECT_EQ(m->body_as_CameraConfig()->height(), 360u);
  EXPECT_LE(m->body_as_CameraConfig()->rate(), 5.0f);
  ASSERT_TRUE(loop_.run_until([&] { return image() && image()->width() == 640; }, 60));
  EXPECT_EQ(check_bars(image(), 640, 360), "") << row_text(image());
}

// vivid's error injection: the capture queue fails (vb2_queue_error: poll
// reports an error, DQBUF fails with EIO) while the device stays. The
// driver closes it and opens it again; images resume.
TEST_F(Vivid, FatalStreamingErrorReopensTheCamera) {
  REQUIRE_VIVID();
  ASSERT_TRUE(start(device_options(R"("width": 640, "height": 480)"))) << error();
  ASSERT_TRUE(images(2));
  ASSERT_EQ(press_vivid_button(env("TROUPE_TEST_VIDEO_DEVICE"), "Inject Fatal Streaming Error"), "");
  const uint32_t n = client_.count(kCamera);
  ASSERT_TRUE(loop_.run_until([&] { return client_.count(kCamera) >= n + 5; }, 60))
      << "images did not resume after the streaming error";
  uint32_t w = 0, h = 0;
  ASSERT_TRUE(config(w, h));
  EXPECT_EQ(check_bars(image(), w, h), "") << row_text(image());
}

// Unbinding vivid's platform device is an unplug: the device node goes.
TEST_F(Vivid, UnplugIsAClearErrorAndReplugResumes) {
  REQUIRE_VIVID();
  const std::string platform = env("TROUPE_TEST_VIVID_PLATFORM");
  ASSERT_FALSE(platform.empty()) << "TROUPE_TEST_VIVID_PLATFORM names vivid's platform device";
  ASSERT_TRUE(start(device_options(R"("width": 640, "height": 480)"))) << error();
  ASSERT_TRUE(images(2));

  ASSERT_TRUE(write_sysfs("/sys/bus/platform/drivers/vivid/unbind", platform));
  // The client is told: GetConfig is refused as a failed device (a hang
  // would leave ask() without a reply), and the other device is served.
  const wire::Message* m = nullptr;
  ASSERT_TRUE(loop_.run_until(
      [&] {
        m = ask(wire::CameraReqSub::GetConfig);
        return m != nullptr && m->header()->kind() == wire::Kind::Nack;
      },
      60));
  EXPECT_EQ(m->body_as_Error()->code(), wire::ErrorCode::DeviceFailed);
  EXPECT_NE(nack_text(m).find("camera unavailable"), std::string::npos) << nack_text(m);
  const uint32_t images_when_gone = client_.count(kCamera), other = client_.count(kOther);
  ASSERT_TRUE(loop_.run_until([&] { return client_.count(kOther) > other + 10; }, 60))
      << "the kinematic base stopped being served";
  EXPECT_EQ(client_.count(kCamera), images_when_gone) << "images while the camera was unplugged";

  ASSERT_TRUE(write_sysfs("/sys/bus/platform/drivers/vivid/bind", platform));
  ASSERT_TRUE(loop_.run_until([&] { return client_.count(kCamera) >= images_when_gone + 3; }, 60))
      << "images did not resume after the camera came back";
  uint32_t w = 0, h = 0;
  ASSERT_TRUE(config(w, h));
  EXPECT_EQ(check_bars(image(), w, h), "") << row_text(image());
}

}  // namespace
}  // namespace troupe::testing
