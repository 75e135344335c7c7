// camera-seek: steers a robot to a coloured object using only its camera.
// A client over the wire (so the same program drives a real robot's
// camera:0 and position2d:0): each Rgb8 image is searched for columns of the
// target colour (seek_logic.h), the robot turns towards their centroid and
// drives until the object fills enough of the image, then stops. While the
// object is not in view it turns on the spot.
//
// Against troupe-sim, --steps N runs in lockstep: the program pauses the
// simulator and steps it once per decision, at most N steps, so a run is
// the same every time and bounded in simulated time, however busy the
// machine. Without --steps it reacts to images as they come, in real time.
//
//   troupe-sim examples/worlds/camera_seek.world --paused &
//   camera-seek localhost --steps 600
#include <chrono>
#include <cstdio>
#include <string>
#include <vector>

#include "examples/controllers/camera_seek/seek_logic.h"
#include "wire/address.h"
#include "wire/cli/args.h"
#include "wire/client/proxies.h"

namespace {

using troupe::examples::SeekPhase;

// Exit status when the robot did not arrive within --steps or --seconds.
constexpr int kNotArrived = 3;

bool parse_colour(const std::string& text, uint32_t& out) {
  static const struct {
    const char* name;
    uint32_t rgb;
  } kNames[] = {{"red", 0xFF0000}, {"green", 0x00FF00}, {"blue", 0x0000FF}, {"yellow", 0xFFFF00}};
  for (const auto& n : kNames) {
    if (text == n.name) {
      out = n.rgb;
      return true;
    }
  }
  if (text.size() != 6 || text.find_first_not_of("0123456789abcdefABCDEF") != std::string::npos) return false;
  out = uint32_t(std::stoul(text, nullptr, 16));
  return true;
}

}  // namespace

int main(int argc, char** argv) {
  std::string host = "localhost", robot, colour = "red";
  troupe::examples::SeekParams params;
  unsigned steps = 0;
  double seconds = 60;
  auto app = troupe::cli::make_app(
      "camera-seek",
      {"camera-seek [HOST[:PORT]] [--robot NAME] [--target COLOUR] [--steps N | --seconds S]",
       "Turns a robot until its camera sees the target colour, then drives towards it\n"
       "and stops when it fills enough of the image. Uses camera:0 (Rgb8 images) and\n"
       "position2d:0 only. Exits 0 on arrival, 3 when it did not arrive in time.\n",
       {"camera-seek localhost:7000 --steps 600", "camera-seek robot7.local --robot r0 --target 00ff00"}});
  app->add_option("HOST", host, "HOST[:PORT] (default localhost)");
  app->add_option("--robot", robot, "the robot's name (default: the first robot with a camera)");
  app->add_option("--target", colour, "the colour sought: red, green, blue, yellow or RRGGBB (default red)")
      ->type_name("COLOUR");
  app->add_option("--tolerance", params.tolerance, "how far each channel may differ, 0..255 (default 40)")
      ->check(troupe::cli::at_least(0) & troupe::cli::at_most(255));
  app->add_option("--arrive", params.arrive_fraction,
                  "arrived when the target spans this fraction of the image width (default 0.85)")
      ->check(troupe::cli::above(0) & troupe::cli::at_most(1));
  app->add_option("--steps", steps, "lockstep with a simulator: step it once per decision, at most N steps")
      ->type_name("N")
      ->check(troupe::cli::at_least(1));
  app->add_option("--seconds", seconds, "without --steps: give up after S seconds (default 60)")
      ->type_name("S")
      ->check(troupe::cli::above(0));
  if (int rc = troupe::cli::parse(*app, argc, argv); rc >= 0) return rc;
  if (!parse_colour(colour, params.target)) {
    return troupe::cli::usage_error(*app, "--target " + colour + ": not a colour name nor six hex digits");
  }
  troupe::wire::HostPort hp;
  std::string error;
  if (!troupe::wire::parse_host(host, hp, error)) return troupe::cli::usage_error(*app, error);

  troupe::client::Client c(hp.host, hp.port);
  if (!c.connect()) {
    std::fprintf(stderr, "camera-seek: cannot connect to %s: %s\n", host.c_str(), c.error().c_str());
    return 1;
  }
  troupe::wire::Address cam_addr;
  if (!robot.empty()) {
    if (!c.resolve(robot + "/camera:0", cam_addr)) {
      std::fprintf(stderr, "camera-seek: %s\n", c.error().c_str());
      return 1;
    }
  } else {
    std::vector<troupe::client::DeviceEntry> devices;
    if (!c.device_list(devices)) return 1;
    bool found = false;
    for (const auto& d : devices) {
      if (d.addr.iface() != uint16_t(troupe::wire::Interface::Camera) || d.addr.index() != 0) continue;
      cam_addr = d.addr;
      found = true;
      break;
    }
    if (!found) {
      std::fprintf(stderr, "camera-seek: %s has no camera:0 on any robot\n", host.c_str());
      return 1;
    }
  }
  troupe::client::CameraProxy cam(c, 0, cam_addr.robot());
  troupe::client::Position2dProxy base(c, 0, cam_addr.robot());
  troupe::client::CameraModel model;
  if (!cam.is_open() || !base.is_open() || !cam.geometry(model)) {
    std::fprintf(stderr, "camera-seek: robot %u needs camera:0 and position2d:0: %s\n",
                 unsigned(cam_addr.robot()), c.error().c_str());
    return 1;
  }
  troupe::client::SimulationProxy sim(c);
  if (steps > 0 && !(sim.is_open() && sim.pause())) {
    std::fprintf(stderr, "camera-seek: --steps needs a simulator: %s\n", c.error().c_str());
    return 1;
  }

  const auto start = std::chrono::steady_clock::now();
  auto in_time = [&](unsigned done) {
    if (steps > 0) return done < steps;
    return std::chrono::steady_clock::now() - start < std::chrono::duration<double>(seconds);
  };
  troupe::examples::SeekDecision d;
  unsigned done = 0, images = 0;
  bool seen = false;
  while (d.phase != SeekPhase::Arrived && in_time(done)) {
    if (steps > 0) {
      if (!sim.step(1) || !c.sync()) break;
      ++done;
    } else {
      c.spin_once(50);
    }
    if (!cam.fresh()) continue;
    const troupe::client::Image& im = cam.image();
    if (im.format != troupe::wire::PixelFormat::Rgb8 ||
        im.compression != troupe::wire::ImageCompression::None ||
        im.data.size() < size_t(im.height) * im.stride || im.stride < im.width * 3) {
      std::fprintf(stderr, "camera-seek: the camera sends %ux%u %s images; this needs uncompressed Rgb8\n",
                   im.width, im.height, troupe::wire::EnumNamePixelFormat(im.format));
      break;
    }
    ++images;
    d = troupe::examples::seek_decide(params, {im.data.data(), im.width, im.height, im.stride}, model.fx,
                                      model.cx);
    if (d.phase != SeekPhase::Searching && !seen) {
      seen = true;
      std::printf("target in view after %u images (bearing %.2f rad)\n", images, d.bearing);
    }
    base.set_velocity(float(d.v), 0, float(d.w));
  }
  base.set_velocity(0, 0, 0);
  c.sync();
  if (d.phase == SeekPhase::Arrived) {
    std::printf("arrived after %u images%s: the target spans %.0f %% of the image\n", images,
                steps > 0 ? (" (" + std::to_string(done) + " steps)").c_str() : "", 100 * d.fraction);
    return 0;
  }
  std::printf("did not arrive after %u images%s (target %s)\n", images,
              steps > 0 ? (" (" + std::to_string(done) + " steps)").c_str() : "",
              seen ? "seen" : "never seen");
  return kNotArrived;
}
