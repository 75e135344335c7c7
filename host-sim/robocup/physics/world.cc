#include "host-sim/robocup/physics/world.h"

#include <algorithm>
#include <cstring>

#include "host-sim/robocup/physics/raycast.h"

namespace troupe::robocup {
World::World(const WorldDef& def) : def_(def) {}

World::Body* World::get(BodyId id) {
  if (id.index >= bodies_.size()) return nullptr;
  Body& b = bodies_[id.index];
  return b.alive && b.generation == id.generation ? &b : nullptr;
}

const World::Body* World::get(BodyId id) const {
  return const_cast<World*>(this)->get(id);
}

bool World::valid(BodyId id) const {
  return get(id) != nullptr;
}

void World::place_body(Body& b) {
  b.placed.resize(b.shapes.size());
  for (size_t i = 0; i < b.shapes.size(); ++i) {
    b.placed[i] = place(b.shapes[i], b.pose);
    Aabb s = bounds(b.placed[i]);
    if (i == 0) {
      b.box = s;
    } else {
      b.box.lo = {std::min(b.box.lo.x, s.lo.x), std::min(b.box.lo.y, s.lo.y)};
      b.box.hi = {std::max(b.box.hi.x, s.hi.x), std::max(b.box.hi.y, s.hi.y)};
    }
  }
}

BodyId World::create_body(const BodyDef& def, std::string& error) {
  if (def.shapes.empty()) {
    error = "a body needs at least one shape";
    return kNoBody;
  }
  for (size_t i = 0; i < def.shapes.size(); ++i) {
    if (!validate(def.shapes[i], error)) {
      error = "shape " + std::to_string(i) + ": " + error;
      return kNoBody;
    }
  }
  if (!(def.mass >= 0) || !(def.inertia >= 0) || !std::isfinite(def.mass)) {
    error = "mass and inertia must be >= 0";
    return kNoBody;
  }
  Body b;
  b.alive = true;
  b.pose = def.pose;
  b.shapes = def.shapes;
  b.user_data = def.user_data;
  b.linear_deceleration = def.linear_deceleration;
  b.angular_deceleration = def.angular_deceleration;
  // Uniform density over the shapes: centroid and second moment.
  double area = 0, second = 0;
  Vec2 moment;
  for (const Shape& s : def.shapes) {
    AreaProperties p = area_properties(s);
    area += p.area;
    moment += p.centroid * p.area;
    second += p.second_moment;
  }
  b.local_com = def.center_of_mass_given ? def.center_of_mass : moment / area;
  if (def.mass > 0) {
    b.mass = def.mass;
    // Parallel-axis theorem: from the body origin to the centre of mass.
    b.inertia = def.inertia > 0 ? def.inertia : def.mass * (second / area - length_squared(b.local_com));
    if (!(b.inertia > 0)) b.inertia = def.mass * 1e-6;
    b.inv_mass = 1 / b.mass;
    b.inv_inertia = 1 / b.inertia;
    b.v = def.velocity.linear();
    b.w = def.velocity.w;
  }
  for (const Shape& s : def.shapes) b.reach = std::max(b.reach, reach_from(s, b.local_com));
  place_body(b);
  uint32_t index;
  if (!free_.empty()) {
    index = free_.back();
    free_.pop_back();
    b.generation = bodies_[index].generation + 1;
    bodies_[index] = std::move(b);
  } else {
    index = uint32_t(bodies_.size());
    bodies_.push_back(std::move(b));
  }
  return {index, bodies_[index].generation};
}

void World::destroy_body(BodyId id) {
  if (Body* b = get(id)) {
    b->alive = false;
    b->shapes.clear();
    b->placed.clear();
    free_.push_back(id.index);
  }
}

Pose2 World::pose(BodyId id) const {
  const Body* b = get(id);
  return b ? b->pose : Pose2{};
}

void World::set_pose(BodyId id, Pose2 pose) {
  if (Body* b = get(id)) {
    b->pose = pose;
    place_body(*b);
  }
}

Twist World::velocity(BodyId id) const {
  const Body* b = get(id);
  return b ? Twist{b->v.x, b->v.y, b->w} : Twist{};
}

void World::set_velocity(BodyId id, Twist v) {
  Body* b = get(id);
  if (!b || b->inv_mass == 0) return;
  b->v = v.linear();
  b->w = v.w;
}

void World::set_origin_velocity(BodyId id, Twist v) {
  Body* b = get(id);
  if (!b || b->inv_mass == 0) return;
  b->w = v.w;
  b->v = v.linear() + cross(v.w, rotate(b->local_com, b->pose.a));
}

Vec2 World::velocity_at(BodyId id, Vec2 point) const {
  const Body* b = get(id);
  return b ? b->v + cross(b->w, point - com_world(*b)) : Vec2{};
}

Vec2 World::center_of_mass(BodyId id) const {
  const Body* b = get(id);
  return b ? com_world(*b) : Vec2{};
}

void World::apply_impulse(BodyId id, Vec2 impulse, Vec2 point) {
  Body* b = get(id);
  if (!b) return;
  b->v += impulse * b->inv_mass;
  b->w += cross(point - com_world(*b), impulse) * b->inv_inertia;
}

double World::mass(BodyId id) const {
  const Body* b = get(id);
  return b ? b->mass : 0;
}

double World::inertia(BodyId id) const {
  const Body* b = get(id);
  return b ? b->inertia : 0;
}

uint64_t World::user_data(BodyId id) const {
  const Body* b = get(id);
  return b ? b->user_data : 0;
}

std::span<const Shape> World::shapes(BodyId id) const {
  const Body* b = get(id);
  return b ? std::span<const Shape>(b->shapes) : std::span<const Shape>();
}

bool World::set_shapes(BodyId id, std::vector<Shape> shapes, std::string& error) {
  Body* b = get(id);
  if (!b) {
    error = "no such body";
    return false;
  }
  if (shapes.empty()) {
    error = "a body needs at least one shape";
    return false;
  }
  for (const Shape& s : shapes) {
    if (!validate(s, error)) return false;
  }
  b->shapes = std::move(shapes);
  b->reach = 0;
  for (const Shape& s : b->shapes) b->reach = std::max(b->reach, reach_from(s, b->local_com));
  place_body(*b);
  return true;
}

Separation World::distance(BodyId ia, BodyId ib) const {
  Separation best;
  best.distance = kUnboundedZ;
  const Body* a = get(ia);
  const Body* b = get(ib);
  if (!a || !b) return best;
  for (size_t i = 0; i < a->placed.size(); ++i) {
    for (size_t j = 0; j < b->placed.size(); ++j) {
      if (!heights_overlap(a->shapes[i], b->shapes[j])) continue;
      Separation s = separation(a->placed[i], b->placed[j]);
      if (s.distance < best.distance) best = s;
    }
  }
  return best;
}

void World::step() {
  const double dt = def_.cycle_s;
  events_.clear();
  sim::PhaseLaps laps(profile_);
  {  // floor
    for (Body& b : bodies_) {
      if (!b.alive || b.inv_mass == 0) continue;
      const double speed = length(b.v);
      if (b.linear_deceleration > 0 && speed > 0) {
        b.v = b.v * (std::max(0.0, speed - b.linear_deceleration * dt) / speed);
      }
      if (b.angular_deceleration > 0 && b.w != 0) {
        const double w = std::max(0.0, std::fabs(b.w) - b.angular_deceleration * dt);
        b.w = std::copysign(w, b.w);
      }
    }
    laps.lap(ph_floor_);
  }
  resolve_overlaps();
  laps.lap(ph_overlap_);
  {
    double t = 0;
    for (int impacts = 0;; ++impacts) {
      find_contacts(contacts_);
      solve(contacts_);
      const double remaining = dt - t;
      if (remaining <= 0) break;
      if (impacts >= def_.max_impacts_per_step) {
        advance(remaining);
        break;
      }
      const double toi = earliest_impact(remaining);
      if (toi >= remaining) {
        advance(remaining);
        break;
      }
      advance(toi);
      t += toi;
    }
    // Rotation can leave a sliver of overlap at resting contacts.
    resolve_overlaps();
    laps.lap(ph_impacts_);
  }
  profile_.count_step();
  ++steps_;
}

bool World::raycast(Vec2 origin, Vec2 dir, double max_range, double z, BodyId ignore, RayHit& hit) const {
  return raycast(
      origin, dir, max_range, z, [ignore](BodyId id, uint64_t) { return !(id == ignore); }, hit);
}

bool World::raycast(Vec2 origin, Vec2 dir, double max_range, double z, const RayFilter& accept,
                    RayHit& hit) const {
  bool found = false;
  hit.distance = max_range;
  for (uint32_t i = 0; i < bodies_.size(); ++i) {
    const Body& b = bodies_[i];
    if (!b.alive) continue;
    // Cheap rejection before the filter and the shapes: the ray's segment
    // against the body's box.
    const Vec2 end = origin + dir * hit.distance;
    if (std::max(origin.x, end.x) < b.box.lo.x || std::min(origin.x, end.x) > b.box.hi.x ||
        std::max(origin.y, end.y) < b.box.lo.y || std::min(origin.y, end.y) > b.box.hi.y) {
      continue;
    }
    if (accept && !accept({i, b.generation}, b.user_data)) continue;
    for (size_t k = 0; k < b.placed.size(); ++k) {
      if (z < b.shapes[k].z_min || z > b.shapes[k].z_max) continue;
      RayShapeHit h;
      if (robocup::raycast(b.placed[k], origin, dir, hit.distance, h) &&
          (!found || h.distance < hit.distance)) {
        found = true;
        hit.body = {i, b.generation};
        hit.distance = h.distance;
        hit.normal = h.normal;
        hit.shape = int(k);
      }
    }
  }
  if (found) hit.point = origin + dir * hit.distance;
  return found;
}

std::vector<BodyId> World::bodies() const {
  std::vector<BodyId> out;
  for (uint32_t i = 0; i < bodies_.size(); ++i) {
    if (bodies_[i].alive) out.push_back({i, bodies_[i].generation});
  }
  return out;
}

double World::kinetic_energy() const {
  double e = 0;
  for (const Body& b : bodies_) {
    if (b.alive && b.inv_mass > 0) e += 0.5 * (b.mass * length_squared(b.v) + b.inertia * b.w * b.w);
  }
  return e;
}

Vec2 World::linear_momentum() const {
  Vec2 p;
  for (const Body& b : bodies_) {
    if (b.alive && b.inv_mass > 0) p += b.v * b.mass;
  }
  return p;
}

double World::angular_momentum(Vec2 about) const {
  double l = 0;
  for (const Body& b : bodies_) {
    if (b.alive && b.inv_mass > 0) l += cross(com_world(b) - about, b.v * b.mass) + b.inertia * b.w;
  }
  return l;
}

uint64_t World::state_hash() const {
  // FNV-1a over the raw bits: any difference in any body shows.
  uint64_t h = 1469598103934665603ull;
  auto mix = [&h](double d) {
    uint64_t bits;
    std::memcpy(&bits, &d, sizeof bits);
    for (int i = 0; i < 8; ++i) {
      h ^= (bits >> (8 * i)) & 0xFF;
      h *= 1099511628211ull;
    }
  };
  for (const Body& b : bodies_) {
    if (!b.alive) continue;
    mix(b.pose.x);
    mix(b.pose.y);
    mix(b.pose.a);
    mix(b.v.x);
    mix(b.v.y);
    mix(b.w);
  }
  return h;
}

}  // namespace troupe::robocup
