#include "host-sim/sim/loader.h"

#include <algorithm>
#include <cmath>
#include <map>

#include "host-sim/sim/ball.h"
#include "host-sim/sim/loader_internal.h"
#include "host-sim/sim/static_map.h"
#include "host-sim/world/png_image.h"

namespace troupe::sim {

using world::Entity;
using world::Property;

namespace {

struct TypeEntry {
  const char* name;
  ModelKind kind;
};

// One line per model type.
constexpr TypeEntry kTypes[] = {
    {"model", ModelKind::Model},
    {"position", ModelKind::Position},
    {"ranger", ModelKind::Ranger},
    {"laser", ModelKind::Laser},
    {"sensor", ModelKind::Sensor},
    {"blobfinder", ModelKind::Blobfinder},
    {"fiducial", ModelKind::Fiducial},
    {"bumper", ModelKind::Bumper},
    {"block", ModelKind::Block},
    {"window", ModelKind::Window},
    {"camera", ModelKind::Camera},
    {"gripper", ModelKind::Gripper},
    {"kicker", ModelKind::Kicker},
    {"ball", ModelKind::Ball},
    {"actuator", ModelKind::NotSimulated},
    {"blinkenlight", ModelKind::NotSimulated},
    {"lightindicator", ModelKind::NotSimulated},
    {"loadcell", ModelKind::NotSimulated},
    {"wifi", ModelKind::NotSimulated},
    {"speech", ModelKind::NotSimulated},
};

// Keys every model may carry that only the viewer (or nobody) uses.
constexpr const char* kViewerKeys[] = {
    "gui_nose",     "gui_grid",       "gui_move",        "gui_outline",    "gui_movemask", "gui_boundary",
    "trail_length", "trail_interval", "stack_children",  "map_resolution", "alwayson",     "debug",
    "say",          "gripper_return", "update_interval", "watts_give",     "watts_take",   "give_watts",
    "take_watts",   "charging_bump",  "interval",
};

}  // namespace

ModelKind model_kind(const std::string& type) {
  for (const TypeEntry& t : kTypes) {
    if (type == t.name) return t.kind;
  }
  return ModelKind::Unknown;
}

bool is_robot_sensor(const std::string& type) {
  switch (model_kind(type)) {
    case ModelKind::Ranger:
    case ModelKind::Laser:
    case ModelKind::Blobfinder:
    case ModelKind::Fiducial:
    case ModelKind::Bumper:
    case ModelKind::Camera:
    case ModelKind::Gripper:
      return true;
    default:
      return false;
  }
}

bool load_robot_sensors(const world::WorldFile& file, const world::Entity& model, RobotDesc& out,
                        world::Diagnostics& diags) {
  Loader loader(file, diags);
  return loader.robot_sensors(model, out);
}

bool load_ball(const world::WorldFile& file, const world::Entity& model, BallDesc& out,
               world::Diagnostics& diags) {
  Loader loader(file, diags);
  return loader.ball_keys(model, out);
}

bool load_world(const world::WorldFile& file, WorldDesc& out, world::Diagnostics& diags) {
  return load_world(file, out, diags, nullptr);
}

bool load_world(const world::WorldFile& file, WorldDesc& out, world::Diagnostics& diags,
                ModelHandoff* handoff) {
  Loader loader(file, diags, handoff);
  return loader.run(out);
}

bool load_world_file(const std::string& path, WorldDesc& out, world::Diagnostics& diags) {
  world::WorldFile file;
  if (!file.load(path, diags)) return false;
  return load_world(file, out, diags);
}

bool Loader::run(WorldDesc& out) {
  const size_t errors_before = diags().error_count();
  const Entity& w = file_.root();
  read_.set_units(w);
  robots_ =
      size_t(std::count_if(out.robots.begin(), out.robots.end(), [](const RobotDesc& o) { return !o.puck; }));
  world_properties(w, out);
  physics_ = out.physics;
  // Room for every robot at once: growing by doubling would hold up to
  // twice the robots' descriptions, and both buffers while it moves them.
  // (Pucks, plain models until read, may still grow it.)
  const auto robot_models = std::count_if(w.children.begin(), w.children.end(), [](const Entity& e) {
    return model_kind(e.type) == ModelKind::Position || model_kind(e.type) == ModelKind::Ball;
  });
  out.robots.reserve(out.robots.size() + size_t(robot_models));
  std::map<std::string, world::SourceLoc> names;
  for (const Entity& e : w.children) {
    if (handoff_ && handoff_->take(e)) continue;
    const ModelKind kind = model_kind(e.type);
    switch (kind) {
      case ModelKind::Window:
        window(e, out.window);
        continue;
      case ModelKind::Position:
        robot(e, out);
        break;
      case ModelKind::Ball:
        ball(e, out);
        break;
      case ModelKind::Model:
        if (read_.flag(e, "gripper_return", false)) {
          puck(e, out);
        } else {
          static_model(e, {}, out);
        }
        break;
      case ModelKind::NotSimulated:
        diags().warn(e.loc, "model type '" + e.type + "' is not simulated; '" + e.written_type +
                                "' is loaded as a plain model");
        static_model(e, {}, out);
        break;
      case ModelKind::Unknown:
        diags().warn(e.loc, "unknown model type '" + e.type + "'; loaded as a plain model");
        static_model(e, {}, out);
        break;
      default:
        diags().warn(e.loc,
                     "a " + e.type + " outside a robot is not simulated; mount it on a position model");
        for (const Property& p : e.properties) p.used = true;
        continue;
    }
    const Property* name = e.find("name");
    if (name && !name->values.empty()) {
      auto [it, fresh] = names.emplace(name->values[0].text, name->loc);
      if (!fresh)
        diags().warn(name->loc, "a model is already named '" + it->first + "' at " + it->second.str());
    }
  }
  if (handoff_) handoff_->finish(file_, diags());
  check_grid_size(w, out);
  file_.warn_unused(diags());
  return diags().error_count() == errors_before;
}

void Loader::world_properties(const Entity& w, WorldDesc& out) {
  out.resolution = read_.length(w, "resolution", out.resolution);
  if (!(out.resolution > 0)) {
    diags().error(w.find("resolution")->loc, "resolution must be > 0 m");
    out.resolution = 0.02;
  }
  out.interval_sim = read_.number(w, "interval_sim", out.interval_sim * 1e3) * 1e-3;  // ms in the file
  if (!(out.interval_sim > 0)) {
    diags().error(w.find("interval_sim")->loc, "interval_sim must be > 0 ms");
    out.interval_sim = 0.1;
  }
  out.interval_real = read_.number(w, "interval_real", out.interval_real * 1e3) * 1e-3;
  out.quit_time = read_.number(w, "quit_time", out.quit_time);
  out.paused = read_.flag(w, "paused", out.paused);
  if (const auto* p = w.find("paused")) out.paused_at = p->loc.str();
  out.speedup = read_.number(w, "speedup", out.speedup);
  out.threads = read_.integer(w, "threads", out.threads);
  for (const char* key : {"show_clock", "show_clock_interval", "log", "name"}) w.find(key);
  if (auto physics = read_.string(w, "physics")) {
    if (*physics == "kinematic") {
      out.physics = Physics::Kinematic;
    } else if (*physics == "rigid") {
      out.physics = Physics::Rigid;
    } else {
      diags().error(
          w.find("physics")->loc,
          "physics \"" + *physics + "\" is neither \"kinematic\" (Stage's, the default) nor \"rigid\"");
    }
  }
}

void Loader::window(const Entity& e, WindowDesc& out) {
  double size[2] = {0, 0}, center[2] = {0, 0};
  if (read_.tuple(e, "size", "ff", size) == 2) {
    out.width = int(size[0]);
    out.height = int(size[1]);
  }
  if (read_.tuple(e, "center", "ll", center) == 2) out.center = {center[0], center[1]};
  out.scale = read_.number(e, "scale", out.scale);
  // Everything else in the window block is the viewer's business.
  for (const Property& p : e.properties) p.used = true;
}

ModelCommon Loader::common(const Entity& e, ModelKind kind) {
  ModelCommon c;
  if (auto n = read_.string(e, "name")) c.name = *n;
  c.pose = read_.pose(e, "pose", {});
  c.origin = read_.pose(e, "origin", {});
  c.size = read_.size(e, "size", c.size, &c.look.height);
  if (auto col = read_.color(e)) c.look.color = *col;
  c.look.obstacle = read_.flag(e, "obstacle_return", true);
  c.look.ranger_return = read_.number(e, "ranger_return", 1.0);
  if (e.find("laser_return") != nullptr) {
    // Stage 3: 0 invisible, 1 visible, 2 bright.
    double lr = read_.number(e, "laser_return", 1);
    c.look.ranger_return = lr <= 0 ? -1.0 : std::min(1.0, lr);
  }
  c.look.blob = read_.flag(e, "blob_return", true);
  c.look.fiducial_id = read_.integer(e, "fiducial_return", 0);
  c.look.fiducial_key = read_.integer(e, "fiducial_key", 0);
  for (const char* key : kViewerKeys) e.find(key);
  if (kind != ModelKind::Position && e.find("ctrl") != nullptr) {
    diags().warn(e.find("ctrl")->loc, "ctrl is only run on position models; ignored on a " + e.type);
  }
  if (c.size.x <= 0 || c.size.y <= 0) {
    diags().error(e.find("size") ? e.find("size")->loc : e.loc, "size must be > 0 m in x and y");
    c.size = {0.1, 0.1};
  }
  return c;
}

Polygons Loader::body(const Entity& e, const ModelCommon& c, bool default_block) {
  Polygons raw;
  for (const Entity& b : e.children) {
    if (model_kind(b.type) != ModelKind::Block) continue;
    std::vector<Vec2> poly;
    int count = read_.integer(b, "points", -1);
    for (int i = 0; count < 0 || i < count; ++i) {
      const std::string key = "point[" + std::to_string(i) + "]";
      double xy[2] = {0, 0};
      if (b.find(key) == nullptr) {
        if (count >= 0) diags().error(b.loc, "block has points " + std::to_string(count) + " but no " + key);
        break;
      }
      if (read_.tuple(b, key, "ll", xy) < 2) diags().error(b.find(key)->loc, key + " needs [x y]");
      poly.push_back({xy[0], xy[1]});
    }
    for (const char* key : {"z", "color", "color_rgba"}) b.find(key);
    if (poly.size() >= 2) raw.push_back(std::move(poly));
  }
  if (raw.empty()) {
    if (!default_block) return {};
    raw.push_back({{-0.5, -0.5}, {0.5, -0.5}, {0.5, 0.5}, {-0.5, 0.5}});
  }
  // Stage's convention: the blocks' joint bounding box is scaled to the
  // model's size and centred on its origin.
  Vec2 lo{1e300, 1e300}, hi{-1e300, -1e300};
  for (const auto& poly : raw) {
    for (Vec2 p : poly) {
      lo = {std::min(lo.x, p.x), std::min(lo.y, p.y)};
      hi = {std::max(hi.x, p.x), std::max(hi.y, p.y)};
    }
  }
  const double sx = hi.x > lo.x ? c.size.x / (hi.x - lo.x) : 1,
               sy = hi.y > lo.y ? c.size.y / (hi.y - lo.y) : 1;
  const Vec2 mid = 0.5 * (lo + hi);
  for (auto& poly : raw) {
    for (Vec2& p : poly) p = transform(c.origin, {(p.x - mid.x) * sx, (p.y - mid.y) * sy});
  }
  return raw;
}

std::shared_ptr<BitmapDesc> Loader::bitmap(const Entity& e) {
  const Property* p = e.find("bitmap");
  if (p == nullptr || p->values.empty()) return nullptr;
  if (!p->values[0].is_string) {
    diags().error(p->loc, "bitmap needs a quoted file name");
    return nullptr;
  }
  const std::string path = file_.resolve_path(p->values[0]);
  auto image = std::make_shared<world::GrayImage>();
  std::string why;
  if (!world::read_png(path, *image, why, 1ull << 28)) {
    diags().error(p->loc, "cannot read bitmap \"" + p->values[0].text + "\" (" + path + "): " + why);
    return nullptr;
  }
  auto out = std::make_shared<BitmapDesc>();
  out->image = std::move(image);
  return out;
}

void Loader::static_model(const Entity& e, const Pose& parent, WorldDesc& out) {
  const ModelKind kind = model_kind(e.type);
  ModelCommon c = common(e, kind);
  StaticDesc s;
  s.name = c.name;
  s.pose = compose(parent, c.pose);
  s.size = c.size;
  s.look = c.look;
  s.bitmap = bitmap(e);
  s.boundary = read_.flag(e, "boundary", false);
  // Polygons are kept in the footprint frame: the origin goes into `frame`.
  ModelCommon centred = c;
  centred.origin = {};
  s.origin = c.origin;
  s.polygons = body(e, centred, !s.bitmap);
  if (kind == ModelKind::NotSimulated || kind == ModelKind::Unknown) {
    for (const Property& p : e.properties) p.used = true;
  }
  out.statics.push_back(std::move(s));
  for (const Entity& child : e.children) {
    ModelKind ck = model_kind(child.type);
    if (ck == ModelKind::Block) continue;
    if (ck == ModelKind::Model || ck == ModelKind::NotSimulated || ck == ModelKind::Unknown) {
      static_model(child, out.statics.back().pose, out);
    } else {
      diags().warn(child.loc,
                   "a " + child.type + " on a static model is not simulated; mount it on a position model");
      for (const Property& p : child.properties) p.used = true;
    }
  }
}

void Loader::puck(const Entity& e, WorldDesc& out) {
  ModelCommon c = common(e, ModelKind::Model);
  RobotDesc r;
  r.puck = true;
  r.name = c.name.empty() ? "puck" + std::to_string(pucks_++) : c.name;
  r.pose = c.pose;
  r.size = c.size;
  r.look = c.look;
  r.mass = read_.number(e, "mass", r.mass);
  if (!(r.mass > 0)) {
    diags().error(e.find("mass")->loc, "a puck's mass must be > 0 kg");
    r.mass = 1;
  }
  r.polygons = body(e, c, true);
  // No drive: commands cannot move it; pushes (rigid mode) and grippers do.
  for (Range& v : r.velocity) v = {0, 0};
  r.odom_error = {};
  for (const Entity& child : e.children) {
    if (model_kind(child.type) == ModelKind::Block) continue;
    diags().warn(child.loc, "a " + child.type + " on a puck is not simulated");
    for (const Property& p : child.properties) p.used = true;
  }
  out.robots.push_back(std::move(r));
}

bool Loader::needs_rigid(const Entity& e, const char* what) {
  if (physics_ == Physics::Rigid) return true;
  diags().error(e.loc, std::string(what) +
                           " needs physics \"rigid\" (at the top of the world file): in Stage's kinematic "
                           "world nothing can be pushed or kicked");
  for (const Property& p : e.properties) p.used = true;
  return false;
}

void Loader::ball(const Entity& e, WorldDesc& out) {
  if (!needs_rigid(e, "a ball")) return;
  BallDesc b;
  if (e.find("name") == nullptr && balls_++ > 0) b.name = "ball" + std::to_string(balls_ - 1);
  ball_keys(e, b);
  out.robots.push_back(ball_robot(b));
}

bool Loader::ball_keys(const Entity& e, BallDesc& b) {
  const size_t errors_before = diags().error_count();
  read_.set_units(file_.root());
  if (auto n = read_.string(e, "name")) b.name = *n;
  b.pose = read_.pose(e, "pose", b.pose);
  if (auto col = read_.color(e)) b.color = *col;
  b.radius = read_.length(e, "radius", b.radius);
  b.mass = read_.number(e, "mass", b.mass);
  b.deceleration = read_.number(e, "deceleration", b.deceleration);
  if (!(b.radius >= 0.01 && b.radius <= 1)) {
    diags().error(e.find("radius")->loc, "a ball's radius must be in [0.01, 1] m");
    b.radius = 0.11;
  }
  if (!(b.mass >= 0.001 && b.mass <= 100)) {
    diags().error(e.find("mass")->loc, "a ball's mass must be in [0.001, 100] kg");
    b.mass = 0.43;
  }
  if (!(b.deceleration >= 0 && b.deceleration <= 100)) {
    diags().error(e.find("deceleration")->loc, "a ball's deceleration must be in [0, 100] m/s^2");
    b.deceleration = 0.4;
  }
  for (const Entity& child : e.children) {
    diags().warn(child.loc, "a " + child.type + " on a ball is not simulated");
    for (const Property& p : child.properties) p.used = true;
  }
  return diags().error_count() == errors_before;
}

void Loader::check_grid_size(const Entity& w, const WorldDesc& out) {
  Vec2 lo{1e300, 1e300}, hi{-1e300, -1e300};
  for (const StaticDesc& s : out.statics) {
    const double r = 0.5 * std::hypot(s.size.x, s.size.y) + std::hypot(s.origin.x, s.origin.y);
    lo = {std::min(lo.x, s.pose.x - r), std::min(lo.y, s.pose.y - r)};
    hi = {std::max(hi.x, s.pose.x + r), std::max(hi.y, s.pose.y + r)};
  }
  if (out.statics.empty()) return;
  // The grid is stored in blocks of 8 x 8 cells: up to 7 more each way.
  const double cells = ((hi.x - lo.x) / out.resolution + 12) * ((hi.y - lo.y) / out.resolution + 12);
  if (cells > double(StaticMap::kMaxCells)) {
    const Property* res = w.find("resolution");
    diags().error(res ? res->loc : w.loc,
                  "the obstacle grid would need " + std::to_string(int64_t(cells)) + " cells at resolution " +
                      std::to_string(out.resolution) + " m, more than even a sparse grid holds (" +
                      std::to_string(StaticMap::kMaxCells) + "); use a coarser resolution or smaller models");
  }
}

}  // namespace troupe::sim
