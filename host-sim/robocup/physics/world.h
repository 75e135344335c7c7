// A 2D rigid-body world with a fixed step: bodies built from convex
// primitives with height ranges, impacts that conserve linear and angular
// momentum, restitution, tangential friction between frictionless and
// sticky, and continuous collision (the moment of impact is found inside
// the step by conservative advancement, so fast balls do not tunnel).
//
// The step is a fixed pipeline of named phases, timed into a profile:
//   floor     slow bodies down by their floor deceleration
//   overlap   push apart bodies that overlap (teleports, geometry swaps)
//   impacts   advance to each impact inside the step, resolve it, go on
// Contacts of a step are read after it (contacts()), never called back.
#pragma once

#include <cstdint>
#include <functional>
#include <span>
#include <string>
#include <vector>

#include "host-sim/robocup/physics/distance.h"
#include "host-sim/robocup/physics/shape.h"
#include "host-sim/sim/profile.h"

namespace troupe::robocup {

/// A body of a World: an index and a generation, so that a stale handle is
/// detected rather than followed.
struct BodyId {
  uint32_t index = 0xFFFFFFFFu;
  uint32_t generation = 0;
  constexpr bool operator==(const BodyId&) const = default;
};
inline constexpr BodyId kNoBody{};

/// What a body is made of and where it starts.
struct BodyDef {
  /// Pose of the body's origin, world frame: m, m, rad.
  Pose2 pose;
  /// Velocity of the centre of mass, world frame: m/s, m/s, rad/s.
  Twist velocity;
  /// kg; 0 makes the body static (walls, posts, goals): it never moves.
  double mass = 0;
  /// kg m^2 about the centre of mass; 0: from the shapes at uniform density.
  double inertia = 0;
  /// Centre of mass in the body frame, m, when `center_of_mass_given`;
  /// otherwise the area centroid of the shapes.
  Vec2 center_of_mass;
  bool center_of_mass_given = false;
  /// Slowing by the floor (rolling or sliding friction), m/s^2 and rad/s^2.
  double linear_deceleration = 0;
  double angular_deceleration = 0;
  /// The body's shapes, body frame. At least one.
  std::vector<Shape> shapes;
  /// The user's value (e.g. which robot this is); the physics ignores it.
  uint64_t user_data = 0;
};

/// The world's settings.
struct WorldDef {
  /// The fixed step, s.
  double cycle_s = 0.01;
  /// Ratio of the normal relative speed after an impact to before it.
  double restitution = 0.5;
  /// Tangential friction at contacts: the fraction of the tangential
  /// impulse that would stop the contact point slipping. 0 frictionless,
  /// 1 sticky (a ball leaves a wall rolling, without slip).
  double friction = 0.2;
  /// Impacts slower than this do not bounce (resting contact), m/s.
  double restitution_threshold = 0.02;
  /// A gap below this counts as touching, m.
  double contact_slop = 5e-4;
  /// Impacts resolved within one step before the rest of it is run without
  /// looking for more (a pathological pile-up cannot stall the world).
  int max_impacts_per_step = 64;
  /// Sequential-impulse passes over touching contacts.
  int solver_passes = 12;
};

/// One resolved contact of the last step.
struct ContactEvent {
  BodyId a, b;
  /// World, m.
  Vec2 point;
  /// Unit, from a towards b.
  Vec2 normal;
  /// Normal impulse applied to b (and its opposite to a), N s.
  double impulse = 0;
  /// Normal approach speed before the impact, m/s.
  double approach_speed = 0;
};

/// A ray's first hit on a body.
struct RayHit {
  BodyId body;
  /// m along the ray.
  double distance = 0;
  /// World, m; unit normal.
  Vec2 point, normal;
  /// Index of the shape hit within its body.
  int shape = -1;
};

class World {
 public:
  explicit World(const WorldDef& def = {});

  /// A new body; kNoBody with `error` when its definition is invalid.
  BodyId create_body(const BodyDef& def, std::string& error);
  void destroy_body(BodyId id);
  bool valid(BodyId id) const;

  /// Pose of the body origin, world: m, m, rad.
  Pose2 pose(BodyId id) const;
  /// Teleports the body; overlaps it makes are pushed apart next step.
  void set_pose(BodyId id, Pose2 pose);
  /// Velocity of the centre of mass, world: m/s, m/s, rad/s.
  Twist velocity(BodyId id) const;
  void set_velocity(BodyId id, Twist velocity);
  /// Sets the velocity so that the body origin moves at `origin_velocity`
  /// (world: m/s, m/s, rad/s), as a wheeled base drives it.
  void set_origin_velocity(BodyId id, Twist origin_velocity);
  /// Velocity of the body's material point at `point` (world, m), m/s.
  Vec2 velocity_at(BodyId id, Vec2 point) const;
  /// Centre of mass, world, m.
  Vec2 center_of_mass(BodyId id) const;
  /// An impulse (N s, world) at a point (world, m).
  void apply_impulse(BodyId id, Vec2 impulse, Vec2 point);
  /// kg and kg m^2 (0 for static bodies).
  double mass(BodyId id) const;
  double inertia(BodyId id) const;
  uint64_t user_data(BodyId id) const;
  std::span<const Shape> shapes(BodyId id) const;
  /// Replaces the body's shapes (a kicker changing state); its mass
  /// properties stay. False with `error` if a shape is invalid.
  bool set_shapes(BodyId id, std::vector<Shape> shapes, std::string& error);
  /// The nearest approach of two bodies over their shapes whose heights
  /// overlap; distance is +inf when no pair can touch.
  Separation distance(BodyId a, BodyId b) const;

  /// Runs one cycle.
  void step();
  /// Simulated time since the world was made, s, and steps run.
  double time_s() const { return double(steps_) * def_.cycle_s; }
  uint64_t steps() const { return steps_; }
  /// The settings; changes take effect at the next step.
  WorldDef& settings() { return def_; }
  const WorldDef& settings() const { return def_; }
  std::span<const ContactEvent> contacts() const { return events_; }
  /// Wall-clock time of each phase (floor, overlap, impacts), over every
  /// step so far and the latest one: the simulator's one Profile.
  const sim::Profile& profile() const { return profile_; }
  sim::Profile& profile() { return profile_; }

  /// The first body hit by a ray from `origin` along unit `dir` within
  /// `max_range` m, among shapes whose height range holds `z` (m). The body
  /// `ignore` is skipped (the sensor's own robot).
  bool raycast(Vec2 origin, Vec2 dir, double max_range, double z, BodyId ignore, RayHit& hit) const;
  /// Which bodies a ray may hit: true to consider the body.
  using RayFilter = std::function<bool(BodyId body, uint64_t user_data)>;
  /// The same, skipping every body `accept` refuses.
  bool raycast(Vec2 origin, Vec2 dir, double max_range, double z, const RayFilter& accept, RayHit& hit) const;

  /// Handles of the live bodies, in creation order.
  std::vector<BodyId> bodies() const;
  /// Totals over dynamic bodies: kg m^2/s^2 (J), N s, and N m s about
  /// `about` (world, m). For checks and metrics.
  double kinetic_energy() const;
  Vec2 linear_momentum() const;
  double angular_momentum(Vec2 about) const;
  /// A hash of every body's pose and velocity bits: equal runs hash equal.
  uint64_t state_hash() const;

 private:
  struct Body {
    uint32_t generation = 0;
    bool alive = false;
    Pose2 pose;      // origin
    Vec2 local_com;  // body frame
    Vec2 v;          // centre of mass, world
    double w = 0;
    double mass = 0, inertia = 0, inv_mass = 0, inv_inertia = 0;
    double linear_deceleration = 0, angular_deceleration = 0;
    double reach = 0;  // farthest shape point from the centre of mass, m
    std::vector<Shape> shapes;
    std::vector<PlacedShape> placed;
    Aabb box;
    uint64_t user_data = 0;
  };
  struct ContactPoint {
    Vec2 ra, rb;  // from each centre of mass, m
    double normal_mass = 0, tangent_mass = 0;
    double target_vn = 0;
    double approach = 0;
    double normal_impulse = 0, tangent_impulse = 0;
  };
  struct Contact {
    uint32_t a, b;
    Vec2 normal;
    int count = 0;
    Vec2 points[2];
    ContactPoint cp[2];
  };

  Body* get(BodyId id);
  const Body* get(BodyId id) const;
  static Vec2 com_world(const Body& b) { return b.pose.to_world(b.local_com); }
  static void place_body(Body& b);
  static Pose2 pose_after(const Body& b, double t);
  bool may_touch(const Body& a, const Body& b) const;

  // world_solver.cc
  void find_contacts(std::vector<Contact>& out) const;
  void solve(std::vector<Contact>& contacts);
  void resolve_overlaps();
  // world_toi.cc
  double time_of_impact(const Body& a, const Body& b, double horizon) const;
  double earliest_impact(double horizon) const;
  void advance(double dt);

  WorldDef def_;
  std::vector<Body> bodies_;
  std::vector<uint32_t> free_;
  std::vector<Contact> contacts_;
  std::vector<ContactEvent> events_;
  // The phases, in pipeline order; defined here, after profile_, so that
  // every constructor gets them.
  sim::Profile profile_;
  size_t ph_floor_ = profile_.define("floor");
  size_t ph_overlap_ = profile_.define("overlap");
  size_t ph_impacts_ = profile_.define("impacts");
  uint64_t steps_ = 0;
};

}  // namespace troupe::robocup
