// Robots: a position model and everything mounted on it, flattened into one
// body outline and lists of sensors with poses in the robot's frame.
#include <algorithm>
#include <cmath>
#include <cstdio>

#include "host-sim/sim/loader.h"
#include "host-sim/sim/loader_internal.h"
#include "host-sim/world/colors.h"

namespace troupe::sim {

using world::Entity;
using world::Property;

void Loader::robot(const Entity& e, WorldDesc& out) {
  ModelCommon c = common(e, ModelKind::Position);
  RobotDesc r;
  r.name = c.name;
  // Numbered among robots only, so pucks (also in out.robots) do not shift
  // the names robots had when pucks were static.
  if (r.name.empty()) r.name.append("r").append(std::to_string(robots_));
  ++robots_;
  r.pose = c.pose;
  r.size = c.size;
  r.look = c.look;
  r.mass = read_.number(e, "mass", r.mass);
  r.polygons = body(e, c, true);
  if (const Property* p = e.find("bitmap"))
    diags().warn(p->loc, "a bitmap on a robot is not simulated; ignored");
  e.find("boundary");

  if (auto d = read_.string(e, "drive")) {
    if (*d == "diff") {
      r.drive = Drive::Diff;
    } else if (*d == "omni") {
      r.drive = Drive::Omni;
    } else if (*d == "car") {
      r.drive = Drive::Car;
    } else {
      diags().warn(e.find("drive")->loc,
                   "drive \"" + *d + "\" is not \"diff\", \"omni\" or \"car\"; \"diff\" is used");
    }
  }
  r.wheelbase = read_.length(e, "wheelbase", r.wheelbase);
  if (!(r.wheelbase > 0)) {
    diags().error(e.find("wheelbase")->loc, "wheelbase must be > 0 m");
    r.wheelbase = 1;
  }
  for (const char* key : {"velocity_bounds", "acceleration_bounds"}) {
    Range* bounds = key[0] == 'v' ? r.velocity : r.acceleration;
    double v[8] = {bounds[0].min, bounds[0].max, bounds[1].min, bounds[1].max, 0, 0,
                   bounds[2].min, bounds[2].max};
    if (read_.tuple(e, key, "llllllaa", v) == 0) continue;
    bounds[0] = {v[0], v[1]};
    bounds[1] = {v[2], v[3]};
    bounds[2] = {v[6], v[7]};
  }
  Pose v0 = read_.pose(e, "velocity", {});
  r.initial_velocity = v0;
  if (auto loc = read_.string(e, "localization")) {
    if (*loc == "gps") {
      r.localization = Localization::Gps;
    } else if (*loc == "odom") {
      r.localization = Localization::Odom;
    } else {
      diags().warn(e.find("localization")->loc,
                   "localization \"" + *loc + "\" is not \"gps\" or \"odom\"; \"gps\" is used");
    }
  }
  if (e.find("localization_origin") != nullptr) {
    r.localization_origin = read_.pose(e, "localization_origin", {});
    r.has_localization_origin = true;
  }
  if (const Property* p = e.find("odom_error")) {
    double err[4] = {r.odom_error.x, r.odom_error.y, 0, r.odom_error.a};
    if (p->values.size() == 3) {
      double e3[3] = {r.odom_error.x, r.odom_error.y, r.odom_error.a};
      read_.tuple(e, "odom_error", "fff", e3);
      r.odom_error = {e3[0], e3[1], e3[2]};
    } else {
      read_.tuple(e, "odom_error", "ffff", err);
      r.odom_error = {err[0], err[1], err[3]};
    }
  }
  if (const Property* p = e.find("odom")) {
    diags().warn(p->loc, "'odom' was removed in Stage 1.6.5 and is ignored; use localization_origin");
  }
  if (auto ctrl = read_.string(e, "ctrl")) {
    r.ctrl = *ctrl;
    r.ctrl_loc = e.find("ctrl")->loc;
  }
  power(e, r);
  for (const Entity& child : e.children) robot_part(child, {}, r);
  // Robots of one type, written one after another, share their rangers.
  if (r.rangers == last_rangers_) {
    r.rangers = last_rangers_;
  } else {
    last_rangers_ = r.rangers;
  }
  out.robots.push_back(std::move(r));
}

bool Loader::robot_sensors(const Entity& model, RobotDesc& out) {
  const size_t errors_before = diags().error_count();
  read_.set_units(file_.root());
  // The sensors' bodies would join this outline; the model has its own.
  RobotDesc read;
  read.look.height = out.look.height;
  for (const Entity& c : model.children) {
    if (is_robot_sensor(c.type)) robot_part(c, {}, read);
  }
  auto take = [](auto& to, auto& from) { to.insert(to.end(), from.begin(), from.end()); };
  take(out.rangers, read.rangers);
  take(out.blobfinders, read.blobfinders);
  take(out.fiducials, read.fiducials);
  take(out.bumpers, read.bumpers);
  take(out.cameras, read.cameras);
  take(out.grippers, read.grippers);
  return diags().error_count() == errors_before;
}

void Loader::robot_part(const Entity& e, const Pose& parent, RobotDesc& r) {
  const ModelKind kind = model_kind(e.type);
  if (kind == ModelKind::Block) return;  // the parent's outline, read by body()
  const ModelCommon c = common(e, kind);
  const Pose at = compose(parent, c.pose);
  bool default_block = false;
  switch (kind) {
    case ModelKind::Ranger:
    case ModelKind::Laser:
      ranger(e, c, at, kind, r);
      break;
    case ModelKind::Blobfinder:
      blobfinder(e, at, r);
      break;
    case ModelKind::Fiducial:
      fiducial(e, c, at, r);
      break;
    case ModelKind::Bumper:
      bumper(e, at, r);
      break;
    case ModelKind::Camera:
      camera(e, c, at, r);
      break;
    case ModelKind::Gripper:
      // Its paddles hold what it carries: their body is not the robot's
      // outline, or a puck between them would block the robot.
      gripper(e, c, at, r);
      break;
    case ModelKind::Kicker:
      // Its plate is part of the robot's body, as a RoboCup kicker's at
      // rest: the robot pushes the ball with it, and a ball resting on it
      // is the one a kick sends away.
      kicker(e, c, at, r);
      default_block = true;
      break;
    case ModelKind::Ball:
      diags().warn(e.loc, "a ball inside a model is ignored; a ball is a top-level model");
      for (const Property& p : e.properties) p.used = true;
      return;
    case ModelKind::Sensor:
      diags().warn(e.loc, "a sensor( ... ) belongs inside a ranger; ignored");
      for (const Property& p : e.properties) p.used = true;
      return;
    case ModelKind::Window:
      diags().warn(e.loc, "a window inside a model is ignored");
      for (const Property& p : e.properties) p.used = true;
      return;
    case ModelKind::Position:
      diags().warn(e.loc, "a position model inside a robot moves with it, not on its own");
      default_block = true;
      break;
    case ModelKind::NotSimulated:
      diags().warn(e.loc, "model type '" + e.type + "' is not simulated; its body is part of the robot");
      for (const Property& p : e.properties) p.used = true;
      default_block = true;
      break;
    case ModelKind::Unknown:
      diags().warn(e.loc, "unknown model type '" + e.type + "'; its body is part of the robot");
      default_block = true;
      break;
    default:
      default_block = true;
      break;
  }
  // What it is made of joins the robot's outline (sensors have a body only
  // when they list blocks, like Stage's sicklaser).
  Polygons polys = body(e, c, default_block);
  if (c.look.obstacle) {
    for (auto& poly : polys) {
      for (Vec2& p : poly) p = transform(at, p);
      r.polygons.push_back(std::move(poly));
    }
  }
  for (const Entity& child : e.children) {
    if (model_kind(child.type) == ModelKind::Sensor &&
        (kind == ModelKind::Ranger || kind == ModelKind::Laser)) {
      continue;  // read by ranger()
    }
    robot_part(child, at, r);
  }
}

void Loader::ranger(const Entity& e, const ModelCommon& c, const Pose& at, ModelKind kind, RobotDesc& r) {
  RangerDesc rd;
  rd.name = c.name;
  rd.pose = at;
  rd.size = c.size;
  if (kind == ModelKind::Laser) {
    // Stage 3's laser: one scanning transducer at the model.
    TransducerDesc t;
    t.pose = at;
    t.range_min = read_.length(e, "range_min", 0);
    t.range_max = read_.length(e, "range_max", 8);
    t.fov = read_.angle(e, "fov", kPi);
    t.samples = read_.integer(e, "samples", 361);
    rd.transducers.push_back(t);
  }
  for (const Entity& s : e.children) {
    if (model_kind(s.type) == ModelKind::Sensor) rd.transducers.push_back(transducer(s, at));
  }
  if (int count = read_.integer(e, "scount", 0); count > 0) {
    // Stage 3's transducer arrays: common view, one pose per transducer.
    double view[3] = {0, 5, kPi / count};
    read_.tuple(e, "sview", "lla", view);
    e.find("ssize");
    e.find("sraycount");
    for (int i = 0; i < count && i < 4096; ++i) {
      double p[3] = {0, 0, 0};
      read_.tuple(e, "spose[" + std::to_string(i) + "]", "lla", p);
      TransducerDesc t;
      t.pose = compose(at, {p[0], p[1], p[2]});
      t.range_min = view[0];
      t.range_max = view[1];
      t.fov = view[2];
      rd.transducers.push_back(t);
    }
  }
  for (const TransducerDesc& t : rd.transducers) {
    if (!(t.range_max > t.range_min && t.range_min >= 0) || t.samples < 1 || t.samples > 100000) {
      diags().error(e.loc, "ranger '" + e.written_type +
                               "': a sensor needs 0 <= range min < max and 1..100000 samples");
      return;
    }
  }
  if (rd.transducers.empty())
    diags().warn(e.loc, "ranger '" + e.written_type + "' has no sensor( ... ); it measures nothing");
  r.rangers.push_back(std::move(rd));
}

TransducerDesc Loader::transducer(const Entity& s, const Pose& at) {
  TransducerDesc t;
  t.pose = compose(at, read_.pose(s, "pose", {}));
  read_.size(s, "size", {0.01, 0.01});
  double range[2] = {t.range_min, t.range_max};
  read_.tuple(s, "range", "ll", range);
  double view[3] = {range[0], range[1], t.fov};
  if (read_.tuple(s, "view", "lla", view) > 0) {  // an older form: [min max fov]
    range[0] = view[0];
    range[1] = view[1];
    t.fov = view[2];
  }
  t.range_min = range[0];
  t.range_max = range[1];
  t.fov = read_.angle(s, "fov", t.fov);
  t.samples = read_.integer(s, "samples", 1);
  double noise[3] = {0, 0, 0};
  read_.tuple(s, "noise", "ffa", noise);
  t.noise_variance = noise[0];
  t.noise_proportional = noise[1];
  t.noise_angle = noise[2];
  read_.color(s);
  return t;
}

void Loader::blobfinder(const Entity& e, const Pose& at, RobotDesc& r) {
  BlobfinderDesc b;
  b.pose = at;
  double image[2] = {double(b.width), double(b.height)};
  read_.tuple(e, "image", "ff", image);
  b.width = int(image[0]);
  b.height = int(image[1]);
  if (b.width < 1 || b.height < 1 || b.width > 10000 || b.height > 10000) {
    diags().error(e.find("image")->loc, "image must be 1..10000 pixels each way");
    b.width = 80;
    b.height = 60;
  }
  b.range = read_.length(e, "range_max", b.range);
  b.range = read_.length(e, "range", b.range);
  b.fov = read_.angle(e, "fov", b.fov);
  b.pan = read_.angle(e, "pan", b.pan);
  int count = read_.integer(e, "colors_count", -1);
  if (const Property* p = e.find("colors")) {
    for (size_t i = 0; i < p->values.size() && (count < 0 || int(i) < count); ++i) {
      const world::Value& v = p->values[i];
      auto col = v.is_string ? world::lookup_color(v.text) : std::nullopt;
      if (!col) {
        diags().warn(v.loc, "unknown colour " + v.text + " in colors; skipped");
        continue;
      }
      b.colors.push_back(*col);
    }
  }
  r.blobfinders.push_back(std::move(b));
}

void Loader::fiducial(const Entity& e, const ModelCommon& c, const Pose& at, RobotDesc& r) {
  FiducialDesc f;
  f.pose = at;
  f.range_min = read_.length(e, "range_min", f.range_min);
  f.range_max = read_.length(e, "range_max", f.range_max);
  f.range_max_id = read_.length(e, "range_max_id", f.range_max_id);
  f.fov = read_.angle(e, "fov", f.fov);
  f.key = c.look.fiducial_key;
  e.find("ignore_zloc");
  r.fiducials.push_back(f);
}

void Loader::bumper(const Entity& e, const Pose& at, RobotDesc& r) {
  BumperDesc b;
  b.pose = at;
  const double len = read_.length(e, "blength", 0.1);
  const int count = std::clamp(read_.integer(e, "bcount", 0), 0, 32);
  for (int i = 0; i < count; ++i) {
    double p[3] = {0, 0, 0};
    read_.tuple(e, "bpose[" + std::to_string(i) + "]", "lla", p);
    b.segments.push_back({{p[0], p[1], p[2]}, len});
  }
  r.bumpers.push_back(std::move(b));
}

void Loader::camera(const Entity& e, const ModelCommon& c, const Pose& at, RobotDesc& r) {
  CameraDesc d;
  double res[2] = {double(d.width), double(d.height)};
  if (read_.tuple(e, "resolution", "ff", res) > 0 &&
      !(res[0] >= 1 && res[1] >= 1 && res[0] <= kMaxCameraSide && res[1] <= kMaxCameraSide &&
        res[0] == std::floor(res[0]) && res[1] == std::floor(res[1]))) {
    diags().error(e.find("resolution")->loc, "camera resolution must be whole numbers of pixels, 1.." +
                                                 std::to_string(kMaxCameraSide) + " each way");
    return;
  }
  d.width = int(res[0]);
  d.height = int(res[1]);
  double range[2] = {d.near, d.far};
  if (read_.tuple(e, "range", "ll", range) > 0 && !(range[0] > 0 && range[1] > range[0])) {
    diags().error(e.find("range")->loc, "camera range [near far] needs 0 < near < far (m)");
    return;
  }
  d.near = range[0];
  d.far = range[1];
  double fov[2] = {d.hfov, d.vfov};
  if (read_.tuple(e, "fov", "aa", fov) > 0 && !(fov[0] > 0 && fov[0] < kPi && fov[1] > 0 && fov[1] < kPi)) {
    diags().error(e.find("fov")->loc,
                  "camera fov [horizontal vertical] must each be above 0 and below 180 degrees");
    return;
  }
  d.hfov = fov[0];
  d.vfov = fov[1];
  double pantilt[2] = {0, 0};
  read_.tuple(e, "pantilt", "aa", pantilt);
  if (!(std::fabs(pantilt[1]) < kPi / 2)) {
    diags().error(e.find("pantilt")->loc, "camera tilt must be within +-90 degrees");
    return;
  }
  d.pose = {at.x, at.y, at.a + pantilt[0]};
  d.tilt = pantilt[1];
  if (!omni_mirror(e, d)) return;
  d.color_noise = read_.number(e, "color_noise", d.color_noise);
  d.depth_noise = read_.length(e, "depth_noise", d.depth_noise);
  if (!(d.color_noise >= 0 && d.color_noise <= 255)) {
    diags().error(e.find("color_noise")->loc, "camera color_noise must be in [0, 255] (levels of 255)");
    return;
  }
  if (!(d.depth_noise >= 0 && std::isfinite(d.depth_noise))) {
    diags().error(e.find("depth_noise")->loc, "camera depth_noise must be 0 or more (m)");
    return;
  }
  if (e.find("size") != nullptr) {  // else Stage's camera size, not a model's
    d.size = c.size;
    d.size_z = c.look.height;
  }
  // Stage stacks a model on its parent: the camera sits on top of the robot.
  d.z = r.look.height + 0.5 * d.size_z;
  r.cameras.push_back(d);
}

bool Loader::omni_mirror(const Entity& e, CameraDesc& d) {
  const std::optional<std::string> mirror = read_.string(e, "mirror");
  if (!mirror) return true;
  if (*mirror != "isometric") {
    diags().error(e.find("mirror")->loc,
                  "camera mirror '" + *mirror + "': the one mirror modelled is \"isometric\"");
    return false;
  }
  d.projection = CameraProjection::Omni;
  if (e.find("resolution") == nullptr) d.width = d.height = kOmniDefaultSide;
  d.mirror_range = read_.length(e, "mirror_range", d.mirror_range);
  d.mirror_ground = read_.number(e, "mirror_ground", d.mirror_ground);
  d.mirror_top = read_.angle(e, "mirror_top", d.mirror_top);
  if (!(d.mirror_range > 0)) {
    diags().error(e.find("mirror_range")->loc, "camera mirror_range must be above 0 (m)");
    return false;
  }
  if (!(d.mirror_ground > 0 && d.mirror_ground <= 1)) {
    diags().error(e.find("mirror_ground")->loc,
                  "camera mirror_ground must be in (0, 1] (of the image's half side)");
    return false;
  }
  if (!(d.mirror_top > -kPi / 2 && d.mirror_top < kPi / 2)) {
    diags().error(e.find("mirror_top")->loc, "camera mirror_top must be within +-90 degrees");
    return false;
  }
  return true;
}

void Loader::power(const Entity& e, RobotDesc& r) {
  double joules = read_.number(e, "joules", -1);
  if (e.find("kjoules") != nullptr) joules = read_.number(e, "kjoules", 0) * 1e3;
  double capacity = read_.number(e, "joules_capacity", -1);
  if (e.find("kjoules_capacity") != nullptr) capacity = read_.number(e, "kjoules_capacity", 0) * 1e3;
  r.power.watts = read_.number(e, "watts", 0);
  if (joules < 0) return;
  r.power.enabled = true;
  r.power.charge = joules;
  r.power.capacity = capacity > 0 ? capacity : joules;
}

void Loader::gripper(const Entity& e, const ModelCommon& c, const Pose& at, RobotDesc& r) {
  GripperDesc g;
  g.pose = at;
  g.size = c.size;
  if (const Property* p = e.find("paddle_state")) {
    // Stage: ["open"|"closed" "up"|"down"]; only the first is simulated.
    const std::string state = p->values.empty() ? "" : p->values[0].text;
    if (state == "closed") {
      g.closed = true;
    } else if (state != "open") {
      diags().error(p->loc, "paddle_state's first value must be \"open\" or \"closed\"");
    }
  }
  for (const char* key : {"paddle_size", "autosnatch"}) e.find(key);
  r.grippers.push_back(g);
}

void Loader::kicker(const Entity& e, const ModelCommon& c, const Pose& at, RobotDesc& r) {
  if (!needs_rigid(e, "a kicker")) return;
  KickerDesc k;
  k.pose = at;
  k.size = c.size;
  k.height = c.look.height;
  // Bounds as a RoboCup kicker's: a kick state's accel, contact and hold,
  // the kicker's reach.
  struct Key {
    const char* name;
    double* value;
    double min, max;
    const char* unit;
  };
  const Key keys[] = {{"accel", &k.accel, 0, 1e5, "m/s^2"},
                      {"contact", &k.contact, 0, 1, "s"},
                      {"reach", &k.reach, 0, 1, "m"},
                      {"hold", &k.hold, 0, 60, "s"}};
  for (const Key& key : keys) {
    // reach is a length (the world's unit_length applies); the rest are not.
    const double v =
        key.name[0] == 'r' ? read_.length(e, key.name, *key.value) : read_.number(e, key.name, *key.value);
    if (v >= key.min && v <= key.max) {
      *key.value = v;
    } else {
      char bounds[64];
      std::snprintf(bounds, sizeof bounds, " must be in [%g, %g] ", key.min, key.max);
      diags().error(e.find(key.name)->loc, std::string("a kicker's ") + key.name + bounds + key.unit);
    }
  }
  r.kickers.push_back(k);
}

}  // namespace troupe::sim
