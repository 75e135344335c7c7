// camera_bench: how many colour + depth images the simulator renders per
// CPU second with 100 robots in Stage's cave (its bitmap from the shared
// data; the benchmark's office floor when absent), every robot carrying a
// camera: a 320 x 240 pinhole, then an omnidirectional camera at its
// default 128 x 128; and on the RoboCup example match (its 8 robots with
// omni cameras, the field painted). Prints tables; it asserts nothing (see
// tests/sim/camera_test.cc, omni_camera_test.cc and
// tests/robocup/camera_scene_test.cc for what the images must hold).
//   cmake --build --preset host-release --target camera_bench
//   build/host-release/tests/bench/sim/camera_bench [--steps N]
#include <time.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "host-sim/robocup/game/camera_scene.h"
#include "host-sim/sim/world.h"
#include "tests/bench/sim/arena.h"

namespace troupe::bench {
namespace {

double cpu_s() {
  timespec ts{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return double(ts.tv_sec) + ts.tv_nsec * 1e-9;
}

struct Scene {
  std::string name;
  sim::WorldDesc desc;
};

// 100 robots with `camera` each on the cave (16 x 16 m, walls 0.8 m high)
// or, without it, a 40 x 30 m office.
bool build(Scene& out, const sim::CameraDesc& camera) {
  const std::string cave = std::string(TROUPE_SHARED_DATA) + "/stage/bitmaps/cave.png";
  auto img = std::make_shared<world::GrayImage>();
  sim::StaticDesc floor;
  floor.look.height = 0.8;
  floor.look.color = 0x4D4D4D;
  floor.bitmap = std::make_shared<sim::BitmapDesc>();
  double m_per_px = 0;
  std::string err;
  if (std::filesystem::exists(cave) && world::read_png(cave, *img, err)) {
    out.name = "cave (Stage's bitmap, 16 x 16 m)";
    floor.name = "cave";
    floor.size = {16, 16};
    m_per_px = 16.0 / img->width;
  } else {
    std::printf("no Stage cave bitmap at %s: the benchmark's 40 x 30 m office floor instead\n", cave.c_str());
    out.name = "office (generated, 40 x 30 m)";
    floor.name = "office";
    floor.size = {40, 30};
    m_per_px = 0.05;
    *img = office(40, 30, m_per_px, 5);
  }
  floor.bitmap->image = img;
  out.desc.resolution = 0.02;
  out.desc.statics.push_back(floor);
  const std::vector<sim::Pose> poses = place(*img, m_per_px, 100, 0.35, 0.9, 11);
  if (poses.size() < 100) {
    std::printf("only %zu robots fit the floor\n", poses.size());
    return false;
  }
  for (size_t i = 0; i < poses.size(); ++i) {
    std::string name = "r";  // appended: GCC 12 warns falsely (-Wrestrict) on "r" + std::string
    name.append(std::to_string(i));
    sim::RobotDesc r = ring_robot(name, poses[i], "");
    r.look.color = 0x2040C0 + uint32_t(i) * 0x010203u;
    r.look.height = 0.4;
    r.cameras.push_back(camera);
    out.desc.robots.push_back(r);
  }
  return true;
}

// A 320 x 240 pinhole (60 x 45 degrees, 8 m), and the omni camera at its
// Stage defaults (128 x 128, 4 m of floor in the ground ring, 8 m range).
sim::CameraDesc pinhole() {
  sim::CameraDesc c;
  c.width = 320;
  c.height = 240;
  c.hfov = 60 * sim::kPi / 180;
  c.vfov = 45 * sim::kPi / 180;
  c.far = 8;
  c.z = 0.45;
  return c;
}
sim::CameraDesc omni() {
  sim::CameraDesc c;
  c.projection = sim::CameraProjection::Omni;
  c.width = c.height = sim::kOmniDefaultSide;
  c.far = 8;
  c.z = 0.45;
  return c;
}

// CPU seconds for `steps` steps with the cameras of the first `read`
// camera-carrying robots wanted.
double run(const sim::WorldDesc& desc, size_t read, int steps, uint64_t& images) {
  sim::World w(desc, sim::Random(1));
  size_t wanted = 0;
  for (sim::RobotId i = 0; i < w.robot_count(); ++i) {
    w.command(i, sim::Command::velocity(0.3, 0, 0.2 * ((i % 3) - 1.0)));
    if (w.robot(i).cameras.count == 0) continue;
    w.set_wanted({sim::SensorKind::Camera, w.robot(i).cameras.first}, wanted < read);
    ++wanted;
  }
  w.step();  // first step out of the timing: buffers sized
  const double t0 = cpu_s();
  for (int s = 0; s < steps; ++s) w.step();
  const double t = cpu_s() - t0;
  images = uint64_t(steps) * std::min(read, wanted);
  return t;
}

// The step alone, then `reads` cameras read: images per CPU second of the
// cameras' own cost (the step without them taken off).
void table(const char* title, const sim::WorldDesc& desc, int steps, std::initializer_list<size_t> reads,
           size_t of) {
  std::printf("%s; %d steps\n", title, steps);
  std::printf("%-28s %10s %12s %14s\n", "cameras read", "images", "CPU s", "images/CPU s");
  uint64_t none_images = 0;
  const double none = run(desc, 0, steps, none_images);
  std::printf("%-28s %10llu %12.3f %14s\n", "none (the step alone)", 0ull, none, "-");
  for (size_t read : reads) {
    uint64_t images = 0;
    const double t = run(desc, read, steps, images);
    const double cameras = std::max(1e-9, t - none);
    std::printf("%-28s %10llu %12.3f %14.0f\n", (std::to_string(read) + " of " + std::to_string(of)).c_str(),
                static_cast<unsigned long long>(images), t, double(images) / cameras);
  }
}

}  // namespace
}  // namespace troupe::bench

int main(int argc, char** argv) {
  using namespace troupe::bench;
  int steps = 20;
  for (int i = 1; i + 1 < argc; ++i) {
    if (std::strcmp(argv[i], "--steps") == 0) steps = std::max(1, std::atoi(argv[i + 1]));
  }
  Scene scene;
  if (!build(scene, pinhole())) return 1;
  table(("== cameras: 100 robots on " + scene.name + ", 320 x 240 colour + depth, 60 x 45 deg, 8 m").c_str(),
        scene.desc, steps, {10, 100}, 100);
  Scene omni_scene;
  if (!build(omni_scene, omni())) return 1;
  table(("\n== omni cameras: 100 robots on " + omni_scene.name +
         ", 128 x 128 colour + depth, 4 m floor ring, 8 m")
            .c_str(),
        omni_scene.desc, steps, {10, 100}, 100);

  troupe::robocup::WorldSpec spec;
  std::string error;
  if (!troupe::robocup::load_world_file(TROUPE_SOURCE_DIR "/examples/robocup/match.world", spec, error)) {
    std::printf("%s\n", error.c_str());
    return 1;
  }
  troupe::sim::WorldDesc match = troupe::robocup::camera_scene(spec);
  // Each robot one omni camera, the benchmark's (in place of the one the
  // field players' robot file gives them), so every row measures the same.
  size_t carrying = 0;
  for (size_t i = 1; i < match.robots.size(); ++i, ++carrying) match.robots[i].cameras.assign(1, omni());
  table("\n== RoboCup: examples/robocup/match.world's 8 robots, omni 128 x 128, the field painted", match,
        steps * 5, {carrying}, carrying);
  return 0;
}
