// room_node: a real troupe::Node for the Python client's tests (and the
// record tests): the kinematic base as position2d:0, standing in a square
// room with a square pillar, and a laser as ranger:0 that measures that room
// from the base's odometry, so that a controller sees walls come closer as
// it drives. The kinematic base is ideal, so its odometry is the truth the
// tests check the controller against.
#include <signal.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <limits>
#include <memory>
#include <string>
#include <vector>

#include "drivers/kinematic/kinematic.h"
#include "runtime/log.h"
#include "runtime/node.h"
#include "wire/cli/args.h"

namespace {

constexpr float kPi = 3.14159265358979f;
constexpr int kBeams = 181;
constexpr float kMaxRange = 8.0f;  // m

std::atomic<bool> g_stop{false};

/// An axis-aligned box: centre and half size, m.
struct Box {
  float x, y, half;
};

/// Distance along the ray (x, y, angle) to where it meets the box's border
/// from outside (`inside` false) or leaves it from inside (`inside` true), m;
/// infinity when it does not.
float ray_box(float x, float y, float a, const Box& b, bool inside) {
  float dx = std::cos(a), dy = std::sin(a);
  float t_near = -std::numeric_limits<float>::infinity(), t_far = std::numeric_limits<float>::infinity();
  const float origin[2] = {x, y}, dir[2] = {dx, dy}, centre[2] = {b.x, b.y};
  for (int k = 0; k < 2; ++k) {
    float lo = centre[k] - b.half, hi = centre[k] + b.half;
    if (std::fabs(dir[k]) < 1e-9f) {
      if (origin[k] < lo || origin[k] > hi) return std::numeric_limits<float>::infinity();
      continue;
    }
    float t1 = (lo - origin[k]) / dir[k], t2 = (hi - origin[k]) / dir[k];
    t_near = std::max(t_near, std::min(t1, t2));
    t_far = std::min(t_far, std::max(t1, t2));
  }
  if (t_near > t_far) return std::numeric_limits<float>::infinity();
  float t = inside ? t_far : t_near;
  return t >= 0 ? t : std::numeric_limits<float>::infinity();
}

/// A laser in the room: 181 beams over the front half-plane, measured from
/// the pose the base publishes.
class RoomLaser : public troupe::Driver {
 public:
  RoomLaser(Box room, Box pillar, float rate_hz) : room_(room), pillar_(pillar), rate_hz_(rate_hz) {}

  bool setup(troupe::Node& node, const troupe::DriverSetup& setup, std::string& error) override {
    device_ = setup.provides[0];
    node.subscribe(setup.required[0], this);
    uint64_t period = uint64_t(1e6f / rate_hz_);
    if (node.loop().start_timer(period, period, this) == 0) {
      error = "no timer left";
      return false;
    }
    return true;
  }

  void on_data(troupe::DeviceId, const troupe::wire::Message& msg) override {
    if (const auto* s = msg.body_as_Position2dState(); s && s->pose()) pose_ = *s->pose();
  }

  void on_timer(troupe::TimerId) override {
    uint16_t ranges[kBeams];
    for (int i = 0; i < kBeams; ++i) {
      float a = pose_.a() - kPi / 2 + float(i) * kPi / float(kBeams - 1);
      float r = std::min({ray_box(pose_.x(), pose_.y(), a, room_, true),
                          ray_box(pose_.x(), pose_.y(), a, pillar_, false), kMaxRange});
      ranges[i] = uint16_t(std::lround(r * 1000.0f));
    }
    auto& b = node_->begin();
    auto scan = troupe::wire::CreateRangerScan(b, b.CreateVector(ranges, kBeams), 0.001f, -kPi / 2,
                                               kPi / float(kBeams - 1), kMaxRange);
    node_->publish(device_, uint8_t(troupe::wire::RangerDataSub::Scan), troupe::wire::Body::RangerScan,
                   scan.Union());
  }

  void on_request(troupe::DeviceId device, const troupe::wire::Message& req,
                  troupe::RequestToken token) override {
    if (req.header()->subtype() != uint8_t(troupe::wire::RangerReqSub::Geometry)) {
      return Driver::on_request(device, req, token);
    }
    auto& b = node_->begin();
    troupe::wire::Pose3d pose(0, 0, 0.2f, 0, 0, 0);
    troupe::wire::Vec3 size(0.1f, 0.1f, 0.1f);
    auto geometry = troupe::wire::CreateRangerGeometry(b, &pose, &size);
    node_->ack(token, troupe::wire::Body::RangerGeometry, geometry.Union());
  }

 private:
  Box room_, pillar_;
  float rate_hz_;
  troupe::DeviceId device_ = troupe::kNoDevice;
  troupe::wire::Pose2d pose_{};
};

}  // namespace

int main(int argc, char** argv) {
  troupe::set_log_program("room_node");
  signal(SIGPIPE, SIG_IGN);
  signal(SIGTERM, [](int) { g_stop = true; });
  signal(SIGINT, [](int) { g_stop = true; });
  uint16_t port = 0;
  float size = 6.0f, rate = 10.0f;
  std::vector<float> pillar_xyh = {1.5f, 0.0f, 0.3f};
  auto app = troupe::cli::make_app(
      "room_node", {"room_node --port P [--size M] [--pillar X Y HALF] [--rate HZ]",
                    "A node for the Python client's and the record tests: a kinematic base\n"
                    "(position2d:0) in a square room with a square pillar, and a laser (ranger:0)\n"
                    "measuring that room from the base's odometry.\n",
                    {"room_node --port 0 --size 8 --pillar 2 -1 0.4"}});
  troupe::cli::add_port(*app, "--port", port, "TCP port (0: any free port, printed)");
  app->add_option("--size", size, "the room's side, m (default 6)")
      ->type_name("M")
      ->check(troupe::cli::above(1));
  app->add_option("--pillar", pillar_xyh, "the pillar's centre and half side, m (default 1.5 0 0.3)")
      ->type_name("X Y HALF")
      ->expected(3);
  app->add_option("--rate", rate, "scans per second (default 10)")
      ->type_name("HZ")
      ->check(troupe::cli::above(0) & troupe::cli::at_most(100));
  if (int rc = troupe::cli::parse(*app, argc, argv); rc >= 0) return rc;
  const Box pillar{pillar_xyh[0], pillar_xyh[1], pillar_xyh[2]};
  troupe::Node::Options options;
  options.name = "room";
  options.port = port;
  troupe::Node node(options);
  auto* base = new troupe::drivers::kinematic::Kinematic;
  auto* laser = new RoomLaser({0, 0, size / 2}, pillar, rate);
  troupe::DeviceId base_id = node.add_device(
      troupe::wire::Address(0, uint16_t(troupe::wire::Interface::Position2d), 0), base, "kinematic");
  troupe::DeviceId laser_id = node.add_device(
      troupe::wire::Address(0, uint16_t(troupe::wire::Interface::Ranger), 0), laser, "room-laser");
  std::string error;
  troupe::DriverSetup base_setup, laser_setup;
  base_setup.name = "kinematic";
  base_setup.provides = {&base_id, 1};
  laser_setup.name = "room-laser";
  laser_setup.provides = {&laser_id, 1};
  laser_setup.required = {&base_id, 1};
  if (!node.add_driver(std::unique_ptr<troupe::Driver>(base), base_setup, error) ||
      !node.add_driver(std::unique_ptr<troupe::Driver>(laser), laser_setup, error) || !node.start(error)) {
    troupe::log_error("%s", error.c_str());
    return 1;
  }
  // The port line is what tests wait for (with --port 0 it names the port).
  printf("room_node serving on port %u\n", unsigned(node.port()));
  fflush(stdout);
  while (!g_stop) node.poll(50000);
  node.shutdown();
  return 0;
}
