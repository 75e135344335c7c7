// Camera pixel noise (`color_noise`, `depth_noise`): a noisy image against
// the noiseless one of the same world, pixel by pixel. The statistics are
// of one fixed seed, so they are the same numbers on every run; the bounds
// are several standard errors wide (about 9,000 samples per figure).
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "host-sim/sim/loader.h"
#include "host-sim/sim/world.h"
#include "tests/sim/camera_pixels.h"
#include "tests/sim/scenes.h"
#include "tests/sim/temp_dir.h"

namespace troupe::sim {
namespace {

using test::render;

// A camera facing a red box 3 m ahead in a room larger than its range, so
// its image holds the box, the floor and the sky.
WorldDesc scene(double color_noise, double depth_noise,
                CameraProjection projection = CameraProjection::Pinhole) {
  WorldDesc d = test::room(20, 20);
  StaticDesc box;
  box.name = "box";
  box.size = {0.4, 1.0};
  box.polygons = {test::box(3, -0.5, 3.4, 0.5)};
  box.look.color = 0xFF0000;
  box.look.height = 1.0;
  d.statics.push_back(box);
  RobotDesc r = test::robot("cam", {0, 0, 0});
  CameraDesc c;
  c.projection = projection;
  c.width = projection == CameraProjection::Omni ? 96 : 64;
  c.height = projection == CameraProjection::Omni ? 96 : 48;
  c.near = 0.05;
  c.far = 8;
  c.z = 0.5;
  c.color_noise = color_noise;
  c.depth_noise = depth_noise;
  r.cameras.push_back(c);
  d.robots.push_back(r);
  return d;
}

struct Image {
  std::vector<uint8_t> rgb;
  std::vector<float> depth;
};

Image image_of(World& w, uint32_t index = 0) {
  const CameraView v = render(w, index);
  return {{v.rgb.begin(), v.rgb.end()}, {v.depth.begin(), v.depth.end()}};
}

Image image_of(const WorldDesc& d, uint64_t seed) {
  World w(d, Random(seed));
  return image_of(w);
}

struct Moments {
  double mean = 0, sd = 0;
  size_t n = 0;
};

Moments moments(const std::vector<double>& xs) {
  Moments m;
  m.n = xs.size();
  for (double x : xs) m.mean += x;
  m.mean /= double(m.n);
  for (double x : xs) m.sd += (x - m.mean) * (x - m.mean);
  m.sd = std::sqrt(m.sd / double(m.n - 1));
  return m;
}

TEST(CameraNoise, ColourAndDepthNoiseHaveTheStandardDeviationsGiven) {
  const Image clean = image_of(scene(0, 0), 1), noisy = image_of(scene(8, 0.05), 1);
  ASSERT_EQ(clean.rgb.size(), noisy.rgb.size());
  // Channels far from 0 and 255, where clamping cannot bend the noise.
  std::vector<double> colour;
  for (size_t i = 0; i < clean.rgb.size(); ++i) {
    if (clean.rgb[i] >= 40 && clean.rgb[i] <= 215) colour.push_back(double(noisy.rgb[i]) - clean.rgb[i]);
  }
  std::vector<double> depth;
  size_t infinite = 0;
  for (size_t i = 0; i < clean.depth.size(); ++i) {
    if (std::isfinite(clean.depth[i])) {
      depth.push_back(double(noisy.depth[i]) - clean.depth[i]);
    } else {
      ++infinite;
      EXPECT_TRUE(std::isinf(noisy.depth[i])) << "pixel " << i << ": nothing seen has no depth to blur";
    }
  }
  ASSERT_GT(colour.size(), 3000u);
  ASSERT_GT(depth.size(), 1000u);
  ASSERT_GT(infinite, 0u);  // the sky
  const Moments c = moments(colour), z = moments(depth);
  EXPECT_NEAR(c.mean, 0, 0.4);
  EXPECT_NEAR(c.sd, 8, 0.4);
  EXPECT_NEAR(z.mean, 0, 0.004);
  EXPECT_NEAR(z.sd, 0.05, 0.004);
}

TEST(CameraNoise, ClampedToTheByteAndNeverANegativeDepth) {
  const Image noisy = image_of(scene(60, 2), 3);
  const Image clean = image_of(scene(0, 0), 3);
  // The box's red channel is 255 and its green 0: the half of the noise
  // that pushes them beyond the byte leaves them there (clamped, not
  // wrapped round), the other half moves them in.
  size_t box = 0, red_at_top = 0, green_at_bottom = 0;
  for (size_t i = 0; i < clean.rgb.size(); i += 3) {
    if (clean.rgb[i] != 255 || clean.rgb[i + 1] != 0) continue;
    ++box;
    red_at_top += noisy.rgb[i] == 255;
    green_at_bottom += noisy.rgb[i + 1] == 0;
  }
  ASSERT_GT(box, 200u);
  EXPECT_NEAR(double(red_at_top) / double(box), 0.5, 0.1);
  EXPECT_NEAR(double(green_at_bottom) / double(box), 0.5, 0.1);
  for (float z : noisy.depth) EXPECT_GE(z, 0.0f);
}

TEST(CameraNoise, SameSeedSameBytesAnotherSeedOrStepOtherBytes) {
  const WorldDesc d = scene(5, 0.02);
  const Image a = image_of(d, 7), b = image_of(d, 7), c = image_of(d, 8);
  EXPECT_EQ(a.rgb, b.rgb);
  EXPECT_EQ(a.depth, b.depth);
  EXPECT_NE(a.rgb, c.rgb);
  // Nothing moves, but every step draws new noise.
  World w(d, Random(7));
  const Image first = image_of(w);
  w.step();
  const Image next = image_of(w);
  EXPECT_NE(first.rgb, next.rgb);
}

TEST(CameraNoise, ACamerasNoiseDoesNotDependOnTheOtherCameras) {
  WorldDesc d = scene(5, 0.02);
  d.robots[0].cameras.push_back(d.robots[0].cameras[0]);
  World alone(d, Random(4)), both(d, Random(4));
  both.set_wanted({SensorKind::Camera, 0}, true);
  both.set_wanted({SensorKind::Camera, 1}, true);
  const Image second_alone = image_of(alone, 1), second_with_first = image_of(both, 1);
  EXPECT_EQ(second_alone.rgb, second_with_first.rgb);
  // The two cameras see the same scene through their own noise.
  EXPECT_NE(image_of(both, 0).rgb, second_with_first.rgb);
}

TEST(CameraNoise, AnOmniImageStaysBlackBeyondTheMirrorsRim) {
  const Image clean = image_of(scene(0, 0, CameraProjection::Omni), 2);
  const Image noisy = image_of(scene(20, 0.1, CameraProjection::Omni), 2);
  // The corner pixel lies beyond the rim; the centre row's middle does not.
  EXPECT_EQ(noisy.rgb[0], 0);
  EXPECT_EQ(noisy.rgb[1], 0);
  EXPECT_EQ(noisy.rgb[2], 0);
  EXPECT_TRUE(std::isinf(noisy.depth[0]));
  const size_t centre = (48 * 96 + 48) * 3;
  EXPECT_NE(std::vector<uint8_t>(clean.rgb.begin() + long(centre), clean.rgb.begin() + long(centre) + 3),
            std::vector<uint8_t>(noisy.rgb.begin() + long(centre), noisy.rgb.begin() + long(centre) + 3));
}

TEST(CameraNoise, WorldFileKeysLoadAndBadValuesAreErrorsWithFileAndLine) {
  {
    troupe::test::TempDir dir;
    world::Diagnostics diags;
    WorldDesc d;
    ASSERT_TRUE(load_world_file(dir.write("c.world", R"(
position ( name "r0" camera ( color_noise 4 depth_noise 0.02 ) )
)"),
                                d, diags))
        << diags.str();
    EXPECT_EQ(diags.str(), "");
    ASSERT_EQ(d.robots.size(), 1u);
    ASSERT_EQ(d.robots[0].cameras.size(), 1u);
    EXPECT_DOUBLE_EQ(d.robots[0].cameras[0].color_noise, 4);
    EXPECT_DOUBLE_EQ(d.robots[0].cameras[0].depth_noise, 0.02);
  }
  for (const char* bad : {"color_noise -1", "color_noise 300", "depth_noise -0.1", "color_noise \"lots\""}) {
    std::string diags;
    EXPECT_TRUE(test::camera_keys_refused_at_their_line(bad, diags)) << bad << ": " << diags;
  }
}

}  // namespace
}  // namespace troupe::sim
