// Turning a WorldDesc into the engine's arrays: statics rasterized into the
// grid, robots and sensors laid out flat.
#include <algorithm>
#include <cmath>

#include "host-sim/sim/engine.h"

namespace troupe::sim {
namespace {

std::vector<Vec2> rect(double x0, double y0, double x1, double y1) {
  return {{x0, y0}, {x1, y0}, {x1, y1}, {x0, y1}};
}

void grow(Vec2& lo, Vec2& hi, Vec2 p) {
  lo = {std::min(lo.x, p.x), std::min(lo.y, p.y)};
  hi = {std::max(hi.x, p.x), std::max(hi.y, p.y)};
}

// Rasterizes the dark pixels of a bitmap, a row run at a time, scaled so the
// box of dark pixels fills the footprint (Stage's convention).
void rasterize_bitmap(StaticMap& map, const StaticDesc& s, const Pose& frame) {
  const world::GrayImage& img = *s.bitmap->image;
  const uint8_t thr = s.bitmap->threshold;
  int x0 = img.width, y0 = img.height, x1 = -1, y1 = -1;
  for (int y = 0; y < img.height; ++y) {
    for (int x = 0; x < img.width; ++x) {
      if (img.at(x, y) <= thr) {
        x0 = std::min(x0, x);
        x1 = std::max(x1, x);
        y0 = std::min(y0, y);
        y1 = std::max(y1, y);
      }
    }
  }
  if (x1 < 0) return;  // nothing dark
  const double sx = s.size.x / (x1 + 1 - x0), sy = s.size.y / (y1 + 1 - y0);
  const double cx = 0.5 * (x0 + x1 + 1), cy = 0.5 * (y0 + y1 + 1);
  const bool axis_aligned = std::fabs(wrap_angle(frame.a)) < 1e-12;
  const bool obstacle = s.look.obstacle, visible = s.look.ranger_return >= 0;
  for (int y = y0; y <= y1; ++y) {
    for (int x = x0; x <= x1; ++x) {
      if (img.at(x, y) > thr) continue;
      int end = x;
      while (end + 1 <= x1 && img.at(end + 1, y) <= thr) ++end;
      // Image rows grow downwards; the world's y grows upwards.
      double lx0 = (x - cx) * sx, lx1 = (end + 1 - cx) * sx;
      double ly0 = (cy - (y + 1)) * sy, ly1 = (cy - y) * sy;
      if (axis_aligned) {
        map.fill_box({frame.x + lx0, frame.y + ly0}, {frame.x + lx1, frame.y + ly1}, obstacle, visible);
      } else {
        std::vector<Vec2> poly = rect(lx0, ly0, lx1, ly1);
        for (Vec2& p : poly) p = transform(frame, p);
        map.fill_polygon(poly, obstacle, visible);
      }
      x = end;
    }
  }
}

}  // namespace

Engine::Engine(const WorldDesc& d, Random r) : desc(d), random(r) {
  ph_control = profile.define("control");
  ph_integrate = profile.define("integrate");
  ph_broadphase = profile.define("broadphase");
  ph_collide = profile.define("collide");
  ph_grippers = profile.define("grippers");
  ph_odometry = profile.define("odometry");
  ph_rangers = profile.define("rangers");
  ph_blobfinders = profile.define("blobfinders");
  ph_fiducials = profile.define("fiducials");
  ph_bumpers = profile.define("bumpers");
  ph_cameras = profile.define("cameras");
  build();
}

void Engine::build() {
  build_statics();
  for (const RobotDesc& r : desc.robots) build_robot(r);
  for (RobotId i = 0; i < bodies.size(); ++i) start_robot(i);

  // The hash covers the map and every robot's start, with room to roam.
  Vec2 lo = map.origin(),
       hi = {lo.x + map.width() * map.resolution(), lo.y + map.height() * map.resolution()};
  double max_radius = 0;
  for (const Body& b : bodies) {
    grow(lo, hi, {b.pose.x, b.pose.y});
    max_radius = std::max(max_radius, b.radius);
  }
  lo = lo - Vec2{2, 2};
  hi = hi + Vec2{2, 2};
  // Cells a few robots wide; coarser when robots are spread so far apart
  // that a fine grid would be mostly empty memory.
  const double area = (hi.x - lo.x) * (hi.y - lo.y);
  hash.reset(lo, hi, std::max({0.5, 4 * max_radius, std::sqrt(area / 4e6)}));
  hash_centres.resize(bodies.size());
  hash_radii.resize(bodies.size());
  hash_flags.resize(bodies.size());
  accept.resize(bodies.size());
  if (desc.physics == Physics::Rigid) build_rigid();
  publish_states();
  broadphase();  // sensors may run before the first step
}

void Engine::build_statics() {
  Vec2 lo{1e300, 1e300}, hi{-1e300, -1e300};
  for (const StaticDesc& s : desc.statics) {
    Pose frame = compose(s.pose, s.origin);
    Vec2 slo{1e300, 1e300}, shi{-1e300, -1e300};
    for (Vec2 c : rect(-s.size.x / 2, -s.size.y / 2, s.size.x / 2, s.size.y / 2))
      grow(slo, shi, transform(frame, c));
    for (const auto& poly : s.polygons) {
      for (Vec2 p : poly) grow(slo, shi, transform(frame, p));
    }
    grow(lo, hi, slo);
    grow(lo, hi, shi);
    statics.push_back({slo, shi, (shi.x - slo.x) * (shi.y - slo.y), s.pose, s.look});
  }
  const double res = desc.resolution;
  if (desc.statics.empty()) {
    lo = {-res, -res};
    hi = {res, res};
  }
  map_lo = lo - Vec2{2 * res, 2 * res};
  map_hi = hi + Vec2{2 * res, 2 * res};
  build_map(nullptr);
}

void Engine::build_map(const Vec2* window) {
  const double res = desc.resolution;
  MapStorage storage = desc.map_storage;
  if (window && storage == MapStorage::Sparse) {
    // A sparse map always reads its coarse level: a map too small to read
    // it dense would read other steps sparse, and rays must not change by
    // a bit. Such a map is held whole (a few MB), dense.
    const double cells = std::ceil((map_hi.x - map_lo.x) / res) * std::ceil((map_hi.y - map_lo.y) / res);
    if (cells < double(StaticMap::kCoarseFromCells)) {
      window = nullptr;
      storage = MapStorage::Dense;
    }
  }
  map.reset(map_lo, map_hi, res, storage, window);
  for (size_t k = 0; k < desc.statics.size(); ++k) {
    const StaticDesc& s = desc.statics[k];
    const Pose frame = compose(s.pose, s.origin);
    const bool obstacle = s.look.obstacle, visible = s.look.ranger_return >= 0;
    for (const auto& poly : s.polygons) {
      std::vector<Vec2> w(poly.size());
      for (size_t i = 0; i < poly.size(); ++i) w[i] = transform(frame, poly[i]);
      map.fill_polygon(w, obstacle, visible);
    }
    if (s.bitmap && s.bitmap->image) rasterize_bitmap(map, s, frame);
    if (s.boundary) {
      const double hx = s.size.x / 2, hy = s.size.y / 2, t = res;
      for (auto side : {rect(-hx, -hy, -hx + t, hy), rect(hx - t, -hy, hx, hy), rect(-hx, -hy, hx, -hy + t),
                        rect(-hx, hy - t, hx, hy)}) {
        for (Vec2& p : side) p = transform(frame, p);
        map.fill_polygon(side, obstacle, visible);
      }
    }
  }
  map.finish();
}

bool World::keep_map_within(Vec2 lo, Vec2 hi) {
  Engine& e = *e_;
  // The distance field saturates at 253 cells, a coarse block adds one
  // block: cells farther than that from the window do not change a code
  // within it, so rays and collisions inside read what the whole map holds.
  const double margin = (256 + StaticMap::kTile) * e.desc.resolution;
  const Vec2 window[2] = {lo - Vec2{margin, margin}, hi + Vec2{margin, margin}};
  e.build_map(window);
  return e.map.windowed();
}

void Engine::build_robot(const RobotDesc& r) {
  const RobotId id = RobotId(bodies.size());
  RobotInfo ri;
  ri.name = r.name;
  ri.has_power = r.power.enabled;
  ri.puck = r.puck;

  Body b;
  b.poly_first = uint32_t(polys.size());
  Polygons outline = r.polygons;
  if (outline.empty()) outline.push_back(rect(-r.size.x / 2, -r.size.y / 2, r.size.x / 2, r.size.y / 2));
  for (const auto& poly : outline) {
    polys.push_back({uint32_t(verts.size()), uint32_t(poly.size())});
    for (Vec2 p : poly) {
      verts.push_back(p);
      b.radius = std::max(b.radius, length(p));
    }
  }
  b.poly_count = uint32_t(polys.size()) - b.poly_first;
  b.obstacle = r.look.obstacle;
  b.ranger_visible = r.look.ranger_return >= 0;
  b.ranger_return = float(std::max(0.0, r.look.ranger_return));
  bodies.push_back(b);

  Kinematics k;
  k.drive = r.drive;
  k.wheelbase = r.wheelbase;
  for (int a = 0; a < 3; ++a) {
    k.velocity[a] = r.velocity[a];
    k.acceleration[a] = r.acceleration[a];
  }
  k.localization = r.localization;
  kinematics.push_back(k);

  Odometry o;
  const uint64_t stream = Random::stream(uint64_t(RandomKind::OdomError), id);
  o.error = {random.uniform(stream, 0) * r.odom_error.x - r.odom_error.x / 2,
             random.uniform(stream, 1) * r.odom_error.y - r.odom_error.y / 2,
             random.uniform(stream, 2) * r.odom_error.a - r.odom_error.a / 2};
  odom.push_back(o);
  power.push_back({r.power.enabled, r.power.charge, r.power.capacity, r.power.watts, 0});
  states.emplace_back();

  ri.rangers.first = uint32_t(rangers.size());
  for (const RangerDesc& rd : r.rangers) {
    RangerState rs;
    rs.robot = id;
    rs.beam_first = uint32_t(ranges.size());
    std::vector<Transducer> ts;
    uint32_t beams = 0;
    for (const TransducerDesc& td : rd.transducers) {
      Transducer t;
      t.pose = td.pose;
      t.samples = uint32_t(std::max(1, td.samples));
      t.start = t.samples > 1 ? float(-td.fov / 2) : 0.0f;
      t.incr = t.samples > 1 ? float(td.fov / (t.samples - 1)) : 0.0f;
      t.range_min = float(td.range_min);
      t.range_max = float(td.range_max);
      t.noise_sd = float(std::sqrt(std::max(0.0, td.noise_variance)));
      t.noise_prop = float(td.noise_proportional);
      t.noise_angle = float(td.noise_angle);
      t.beam_offset = beams;
      const double a0 = td.pose.a + t.start;
      t.first_dir = {std::cos(a0), std::sin(a0)};
      t.incr_rot = {std::cos(double(t.incr)), std::sin(double(t.incr))};
      beams += t.samples;
      rs.reach = std::max(rs.reach, std::hypot(td.pose.x, td.pose.y) + td.range_max);
      ts.push_back(t);
    }
    rs.beam_count = beams;
    ranges.insert(ranges.end(), beams, 0.0f);
    intensities.insert(intensities.end(), beams, 0.0f);
    for (const Transducer& t : ts) {
      std::fill(ranges.begin() + rs.beam_first + t.beam_offset,
                ranges.begin() + rs.beam_first + t.beam_offset + t.samples, t.range_max);
    }
    // The same transducers as an earlier ranger: share them.
    auto same = [](const Transducer& a, const Transducer& c) {
      return a.pose.x == c.pose.x && a.pose.y == c.pose.y && a.pose.a == c.pose.a && a.start == c.start &&
             a.incr == c.incr && a.range_min == c.range_min && a.range_max == c.range_max &&
             a.noise_sd == c.noise_sd && a.noise_prop == c.noise_prop && a.noise_angle == c.noise_angle &&
             a.samples == c.samples;
    };
    rs.transducer_count = uint32_t(ts.size());
    rs.transducer_first = uint32_t(transducers.size());
    for (const IndexRange& set : transducer_sets) {
      if (set.count != ts.size()) continue;
      bool equal = true;
      for (size_t m = 0; m < ts.size() && equal; ++m) equal = same(transducers[set.first + m], ts[m]);
      if (equal) {
        rs.transducer_first = set.first;
        break;
      }
    }
    if (rs.transducer_first == transducers.size()) {
      transducer_sets.push_back({rs.transducer_first, rs.transducer_count});
      transducers.insert(transducers.end(), ts.begin(), ts.end());
    }
    rangers.push_back(rs);
  }
  ri.rangers.count = uint32_t(rangers.size()) - ri.rangers.first;
  robot_rangers.push_back(ri.rangers);
  ri.blobfinders = {uint32_t(blobfinders.size()), uint32_t(r.blobfinders.size())};
  for (size_t k2 = 0; k2 < r.blobfinders.size(); ++k2) blobfinders.push_back({id, false, UINT64_MAX, {}});
  ri.fiducials = {uint32_t(fiducials.size()), uint32_t(r.fiducials.size())};
  for (size_t k2 = 0; k2 < r.fiducials.size(); ++k2) fiducials.push_back({id, false, UINT64_MAX, {}});
  ri.bumpers = {uint32_t(bumpers.size()), uint32_t(r.bumpers.size())};
  for (size_t k2 = 0; k2 < r.bumpers.size(); ++k2) bumpers.push_back({id, false, UINT64_MAX, 0});
  ri.cameras = {uint32_t(cameras.size()), uint32_t(r.cameras.size())};
  for (size_t k2 = 0; k2 < r.cameras.size(); ++k2) cameras.push_back({id, false, UINT64_MAX, 0, 0, {}, {}});
  ri.grippers = {uint32_t(grippers.size()), uint32_t(r.grippers.size())};
  for (const GripperDesc& g : r.grippers) {
    GripperState gs;
    gs.robot = id;
    gs.robot_gripper = uint32_t(grippers.size()) - ri.grippers.first;
    gs.pose = g.pose;
    gs.half_size = 0.5 * g.size;
    gs.closed = gs.want_closed = g.closed;
    grippers.push_back(gs);
  }
  info.push_back(std::move(ri));
}

void Engine::start_robot(RobotId i) {
  const RobotDesc& r = desc.robots[i];
  Body& b = bodies[i];
  b.pose = {r.pose.x, r.pose.y, wrap_angle(r.pose.a)};
  b.proposed = b.pose;
  b.vel = r.initial_velocity;
  b.cmd = Command::velocity(r.initial_velocity.x, r.initial_velocity.y, r.initial_velocity.a);
  b.moved = b.stalled = b.disabled = false;
  Odometry& o = odom[i];
  o.origin = r.has_localization_origin ? r.localization_origin : b.pose;
  o.estimate = relative(o.origin, b.pose);
  PowerState& p = power[i];
  p.joules = r.power.charge;
  p.watts = 0;
}

}  // namespace troupe::sim
