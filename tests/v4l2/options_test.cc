// The v4l2 driver's options, read by the real node config parser: bad
// values stop the node naming the option; a camera that is not there does
// not, and clients get a clear refusal while the other device is served.
#include <gtest/gtest.h>

#include <cmath>

#include "tests/v4l2/camera_bench.h"

namespace troupe::testing {
namespace {

class CameraOptions : public CameraBench {};

// A device path nothing is at, on any machine.
const std::string kAbsent = R"("device": "/nonexistent/video9")";

TEST_F(CameraOptions, BadValuesStopTheNodeNamingTheOption) {
  struct Case {
    std::string options, expect;
  };
  const Case cases[] = {
      {R"("width": 320)", "option \"device\" is missing"},
      {kAbsent + R"(, "width": 0)", "\"width\" and \"height\""},
      {kAbsent + R"(, "height": 5000)", "1 to 4096 pixels"},
      // 1024 x 768 x 3 bytes is over the default 1 MiB frame limit.
      {kAbsent + R"(, "width": 1024, "height": 768)", "over the 1048576-byte frame limit"},
      {kAbsent + R"(, "rate": 0)", "option \"rate\""},
      {kAbsent + R"(, "rate": 2000)", "option \"rate\""},
      {kAbsent + R"(, "buffers": 1)", "option \"buffers\""},
      {kAbsent + R"(, "buffers": 17)", "option \"buffers\""},
      {kAbsent + R"(, "hfov": 0)", "\"hfov\""},
      {kAbsent + R"(, "hfov": 3.2)", "\"hfov\""},
      {kAbsent + R"(, "vfov": -0.1)", "\"vfov\""},
      {kAbsent + R"(, "near": 2, "far": 1)", "\"near\" and \"far\""},
      {kAbsent + R"(, "frame_timeout_ms": 100)", "\"frame_timeout_ms\""},
      {kAbsent + R"(, "reopen_min_ms": 500, "reopen_max_ms": 100)", "\"reopen_max_ms\""},
      // Enums are checked by the config parser itself, which names the value;
      // on the driver_type's line it is still an option, not a driver.
      {kAbsent + R"(, "format": "DepthF32")", "unknown enum value: DepthF32"},
      {kAbsent + R"(, "capture_format": "MJPEG")", "unknown enum value: MJPEG"},
  };
  for (const Case& c : cases) {
    NodeUnderTest node;
    std::string error;
    EXPECT_FALSE(node.start(camera_config(c.options), error)) << c.options;
    EXPECT_NE(error.find(c.expect), std::string::npos) << c.options << "\n  gave: " << error;
  }
}

TEST_F(CameraOptions, GoodValuesStart) {
  NodeUnderTest node;
  std::string error;
  EXPECT_TRUE(
      node.start(camera_config(kAbsent + R"(, "width": 320, "height": 240, "rate": 5, "format": "Mono8",
    "capture_format": "Yuyv", "buffers": 2, "hfov": 1.2, "near": 0.1, "far": 20)"),
                 error))
      << error;
}

TEST_F(CameraOptions, AbsentCameraIsRefusedClearlyAndTheNodeServesOn) {
  ASSERT_TRUE(start(kAbsent + R"(, "width": 320, "height": 240, "hfov": 1.5, "pose_x": 0.2, "pose_z": 0.5,
    "pose_pitch": 0.1, "reopen_min_ms": 100, "reopen_max_ms": 200)"))
      << error();
  const uint32_t other = client_.count(kOther);
  ASSERT_TRUE(loop_.run_until([&] { return client_.count(kOther) > other + 5; }, 30))
      << "the kinematic base is not served while the camera is missing";

  const wire::Message* get = ask(wire::CameraReqSub::GetConfig);
  ASSERT_NE(get, nullptr);
  EXPECT_EQ(get->header()->kind(), wire::Kind::Nack);
  EXPECT_EQ(get->body_as_Error()->code(), wire::ErrorCode::DeviceFailed);
  EXPECT_NE(nack_text(get).find("/nonexistent/video9: open: No such file or directory"), std::string::npos)
      << nack_text(get);

  auto& b = client_.begin();
  auto want = wire::CreateCameraConfig(b, 160, 120, 5, wire::PixelFormat::Rgb8);
  const wire::Message* set = ask(wire::CameraReqSub::SetConfig, wire::Body::CameraConfig, want.Union());
  ASSERT_NE(set, nullptr);
  EXPECT_EQ(set->body_as_Error()->code(), wire::ErrorCode::DeviceFailed) << nack_text(set);

  // The geometry is the configured one: fx from the 1.5 rad field of view
  // over 320 px, vfov from the image's 4:3 shape.
  const wire::Message* geo = ask(wire::CameraReqSub::Geometry);
  ASSERT_NE(geo, nullptr);
  ASSERT_EQ(geo->header()->kind(), wire::Kind::Ack);
  const wire::CameraGeometry* g = geo->body_as_CameraGeometry();
  ASSERT_NE(g, nullptr);
  const double fx = 160.0 / std::tan(0.75);
  EXPECT_NEAR(g->fx(), fx, 1e-3);
  EXPECT_NEAR(g->fy(), fx, 1e-3);  // square pixels
  EXPECT_NEAR(g->vfov(), 2 * std::atan(120.0 / fx), 1e-5);
  EXPECT_FLOAT_EQ(g->cx(), 160);
  EXPECT_FLOAT_EQ(g->cy(), 120);
  EXPECT_FLOAT_EQ(g->pose()->x(), 0.2f);
  EXPECT_FLOAT_EQ(g->pose()->z(), 0.5f);
  EXPECT_FLOAT_EQ(g->pose()->pitch(), 0.1f);
  EXPECT_EQ(client_.count(kCamera), 0u);
}

TEST_F(CameraOptions, SetConfigRefusesWhatCannotBeSent) {
  ASSERT_TRUE(start(kAbsent)) << error();
  auto& b = client_.begin();
  auto big = wire::CreateCameraConfig(b, 1024, 768, 0, wire::PixelFormat::Rgb8);
  const wire::Message* m = ask(wire::CameraReqSub::SetConfig, wire::Body::CameraConfig, big.Union());
  ASSERT_NE(m, nullptr);
  EXPECT_EQ(m->body_as_Error()->code(), wire::ErrorCode::BadArgument);
  EXPECT_NE(nack_text(m).find("1024x768 Rgb8"), std::string::npos) << nack_text(m);

  auto& b2 = client_.begin();
  auto depth = wire::CreateCameraConfig(b2, 0, 0, 0, wire::PixelFormat::DepthF32);
  m = ask(wire::CameraReqSub::SetConfig, wire::Body::CameraConfig, depth.Union());
  ASSERT_NE(m, nullptr);
  EXPECT_EQ(m->body_as_Error()->code(), wire::ErrorCode::BadArgument);
  EXPECT_NE(nack_text(m).find("Rgb8 or Mono8"), std::string::npos) << nack_text(m);
}

}  // namespace
}  // namespace troupe::testing
