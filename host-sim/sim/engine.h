// The engine behind World (private to host-sim/sim): robots and sensors as
// plain structs in flat arrays, walked linearly by the step's phases. Hot
// per-step data (Body) is kept apart from what the step rarely reads.
#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <span>
#include <vector>

#include "host-sim/sim/desc.h"
#include "host-sim/sim/profile.h"
#include "host-sim/sim/random.h"
#include "host-sim/sim/robot_layer.h"
#include "host-sim/sim/spatial_hash.h"
#include "host-sim/sim/static_map.h"
#include "host-sim/sim/world.h"

namespace troupe::sim {

// Flag bits of robots in the spatial hash.
inline constexpr uint32_t kHashRangerVisible = 1;
inline constexpr uint32_t kHashObstacle = 2;

struct PolyRef {
  uint32_t first = 0, count = 0;  // into Engine::verts
};

/// Everything the step touches for every robot, every step.
struct Body {
  Pose pose;        // ground truth, world: m, m, rad
  Pose vel;         // robot frame: m/s, m/s, rad/s
  Pose proposed;    // where integration would put it this step
  Pose blocked_at;  // the pose a refused move tried to reach (bumpers)
  Command cmd;
  double radius = 0;  // m, bounding circle about `pose`
  uint32_t poly_first = 0, poly_count = 0;
  // The intensity its outline returns to rangers (0..1): here, beside what
  // a ray test reads, not in the large RobotDesc.
  float ranger_return = 1;
  bool moved = false;     // proposed differs from pose
  bool stalled = false;   // the last move was refused
  bool disabled = false;  // battery empty
  bool obstacle = true;
  bool ranger_visible = true;
};

/// How a robot moves (copied out of RobotDesc so the control phase walks a
/// compact array).
struct Kinematics {
  Drive drive = Drive::Diff;
  double wheelbase = 1;
  Range velocity[3];
  Range acceleration[3];
  Localization localization = Localization::Gps;
};

struct Odometry {
  Pose estimate;  // odometry frame
  Pose origin;    // the odometry frame in the world
  Pose error;     // scale errors drawn at the start (x, y, a)
};

struct PowerState {
  bool enabled = false;
  double joules = 0, capacity = 0, base_watts = 0, watts = 0;
};

struct Transducer {
  Pose pose;                  // robot frame
  float start = 0, incr = 0;  // first beam's bearing and spacing, rad
  // The first beam's direction in the robot frame, and the rotation from one
  // beam to the next, so no step calls sin and cos per beam.
  Vec2 first_dir, incr_rot;
  float range_min = 0, range_max = 5;
  float noise_sd = 0, noise_prop = 0, noise_angle = 0;
  uint32_t samples = 1;
  uint32_t beam_offset = 0;  // first beam's place among its ranger's beams
};

struct RangerState {
  RobotId robot = 0;
  // Robots with the same ranger share its transducers (a swarm of identical
  // robots reads one small array, which stays in cache).
  uint32_t transducer_first = 0, transducer_count = 0;
  uint32_t beam_first = 0, beam_count = 0;
  double reach = 0;  // m from the robot's pose to the farthest beam end
  bool wanted = false;
  bool any_noise_angle = false;
  uint64_t step = UINT64_MAX;
  // Robots within reach at its last update: chooses how its beams find
  // robots (ranger.cc); the results do not depend on it.
  uint32_t robots_near = 0;
};

struct BlobState {
  RobotId robot = 0;
  bool wanted = false;
  uint64_t step = UINT64_MAX;
  std::vector<Blob> blobs;
};

struct FiducialState {
  RobotId robot = 0;
  bool wanted = false;
  uint64_t step = UINT64_MAX;
  std::vector<FiducialReading> readings;
};

struct BumperState {
  RobotId robot = 0;
  bool wanted = false;
  uint64_t step = UINT64_MAX;
  uint32_t pressed = 0;
};

struct CameraState {
  RobotId robot = 0;
  bool wanted = false;
  uint64_t step = UINT64_MAX;
  int width = 0, height = 0;  // px, of the images held (the desc may have changed since)
  std::vector<uint8_t> rgb;
  std::vector<float> depth;
};

struct GripperState {
  RobotId robot = 0;
  uint32_t robot_gripper = 0;  // its index among its robot's grippers
  /// Its footprint, robot frame, m: a puck with its centre inside is caught.
  Pose pose;
  Vec2 half_size;
  bool closed = false;
  bool want_closed = false;
  bool holding = false;
  RobotId held = 0;
  /// The held puck's pose in the robot's frame: m, m, rad.
  Pose offset;
};

struct RigidBodies;  // rigid.cc: the rigid-body model's world and handles
// Deletes it where its type is complete, so this header needs no physics.
struct RigidBodiesDelete {
  void operator()(RigidBodies* r) const;
};

/// A static model, for what the grid cannot say: which model a ray hit
/// (colour, reflectance) and fiducial landmarks.
struct StaticInfo {
  Vec2 lo, hi;  // world bounding box, m
  double area = 0;
  Pose pose;
  Appearance look;
};

struct Engine {
  Engine(WorldDesc d, Random r);

  // build.cc
  void build();
  void build_statics();
  /// Rasterizes the statics into `map` over [map_lo, map_hi]; with a
  /// window (lo, hi: two points), only the cells within it
  /// (World::keep_map_within).
  void build_map(const Vec2* window);
  void build_robot(const RobotDesc& r);
  void start_robot(RobotId i);

  // motion.cc
  void control();
  void integrate();
  /// Body b's proposed pose after dt s at its velocity.
  void integrate_body(Body& b, double dt);
  void odometry();
  // rigid.cc: the rigid-body model's integrate and collide phases
  void build_rigid();
  void rigid_integrate();
  void rigid_collide();
  /// Puts robot i's rigid body at its pose, velocity and obstacle flag
  /// (after a teleport, a reset, or a gripper taking or dropping it).
  void sync_rigid(RobotId i);
  /// An undriven body's velocity from the physics, into bodies[i].vel.
  void read_rigid_velocity(RobotId i);
  /// World::rigid_moved().
  void rigid_moved();
  robocup::World* rigid_world();
  robocup::BodyId rigid_body(RobotId i) const;
  robocup::BodyId rigid_static_body(size_t k) const;
  // gripper.cc
  void update_grippers();
  // collide.cc
  void broadphase();
  void collide();
  /// Moves every body whose move `accept` took to its proposed pose; the
  /// others stay put, stop and stall.
  void take_accepted_moves();
  bool hits_static(RobotId i, const Pose& from, const Pose& to);
  bool overlaps_robot(RobotId i, const Pose& pi, RobotId j, const Pose& pj);
  /// The same, reusing robot i's outline at pi in scratch_verts and
  /// scratch_polys when have_own says it is there (and setting it once it is).
  bool meets_robot(RobotId i, const Pose& pi, bool& have_own, RobotId j, const Pose& pj);
  // ranger.cc
  void update_rangers();
  /// A ranger waiting in the batch: its rays are ray_queries from
  /// query_first, its transducers' poses transducer_poses from pose_first.
  struct PendingRanger {
    uint32_t ranger, query_first, pose_first;
  };
  /// Updates ranger `index`: its rays join the batch (or, for the layer's
  /// way, are cast at once), to be finished when the batch is cast.
  void queue_ranger(uint32_t index);
  /// Appends ranger `index`'s rays and transducer poses to the batch's;
  /// true when its beams find robots through the layer.
  bool aim_ranger(uint32_t index);
  /// Casts every ray of the batch, then finishes each ranger in it.
  void cast_ranger_batch();
  /// With the walls' ranges (m) in the ranger's slice of `ranges`: the
  /// robots, intensities, noise and limits.
  void finish_ranger(const PendingRanger& p, bool layer);
  /// Starts loading what queue_ranger() will read for the robot `item`.
  void prefetch_rangers(const SpatialHash::Item& item) const;
  /// Distance along a ray to robot j's outline, m; negative when missed.
  double ray_robot(RobotId j, Vec2 origin, Vec2 dir) const;
  /// The same with the cosine and sine of its heading given (`turn`).
  double ray_robot(RobotId j, Vec2 turn, Vec2 origin, Vec2 dir) const;
  /// A robot seen from one ray origin, for the many rays from there: the
  /// origin in the robot's frame, its outline's vertices less it, and per
  /// polygon whether no ray from there can meet it first (`skip`: it lies
  /// inside another, convex one, and the origin outside that).
  struct SeenOutline {
    Vec2 turn, o;
    std::vector<Vec2> rel;
    std::vector<uint8_t> skip;
  };
  /// Fills poly_within for the polygons built since it was last filled.
  void nest_outlines();
  void seen_from(RobotId j, Vec2 turn, Vec2 origin, SeenOutline& seen);
  /// ray_robot from the origin `seen` was made for: the same result.
  double ray_robot(RobotId j, const SeenOutline& seen, Vec2 dir) const;
  /// Lowers the ranges (m) of ranger `rs`'s beams, cast as `queries` from
  /// its transducers' poses `poses` (world: m, m, rad), with the walls'
  /// ranges in `out`, to the robots they meet first, and sets those beams'
  /// intensities. Three ways to the same result: these
  /// two, and the layer's below.
  void beams_meet_candidates(const RangerState& rs, std::span<const RayQuery> queries,
                             std::span<const Pose> poses, float* out, float* inten);
  void beams_meet_every(const RangerState& rs, std::span<const RayQuery> queries, float* out, float* inten);
  /// The layer's way, before the walls are cast: finds the robots each of
  /// `queries` meets first (robot_hits, beam_hits), not counting robot
  /// self_robot, and shortens the queries to end just past them.
  void layer_hits_first(std::span<RayQuery> queries);
  /// After the walls are cast (out, m): lowers the ranges to the robots
  /// found first, and sets those beams' intensities.
  void settle_layer_hits(float* out, float* inten);
  /// The static model owning the occupied cell at `p` (smallest box wins).
  const StaticInfo* static_at(Vec2 p) const;
  // detectors.cc
  void update_blobfinders();
  void update_fiducials();
  void update_bumpers();
  // camera.cc
  void update_cameras();
  void render_camera(uint32_t index);
  /// Adds the camera's pixel noise (CameraDesc::color_noise, depth_noise)
  /// to the image render_camera just made.
  void add_camera_noise(uint32_t index);
  /// Renders into st's buffers, already sized; `at`: the camera, world frame.
  void render_omni(CameraState& st, const CameraDesc& d, const Pose& at);
  /// Robots other than the camera's own within `far` m of the camera at
  /// `at` (world), in index order, with where they are seen (into `sights`).
  void camera_sights(RobotId own, const Pose& at, double far);
  /// A camera ray's spans (into `spans`, unsorted): the first wall, `wall`
  /// m away, and the robots of camera_cols covering ray `ray` of `rays`
  /// that it meets before the wall, within `far` m.
  void ray_spans(Vec2 o, Vec2 dir, double wall, double far, int ray, int rays);

  /// The wanted sensors, each kind timed into its phase.
  void update_sensors(PhaseLaps& laps);
  /// World::step() and step(StepExchange&): `exchange` may be null.
  void step(World& world, World::StepExchange* exchange);
  /// This process steps robot i (World::Residence::Owned).
  bool owns(RobotId i) const { return residence.empty() || residence[i] == kOwned; }
  /// A sensor the update now under way computes: wanted, on a robot this
  /// process steps, and (World::refresh_new_sensors) not current already.
  template <typename SensorState>
  bool due(const SensorState& st) const {
    return st.wanted && owns(st.robot) && !(new_sensors_only && st.step == steps);
  }
  void publish_states();
  void outline(RobotId i, const Pose& at, std::vector<Vec2>& verts, std::vector<PolyRef>& polys) const;

  WorldDesc desc;
  Random random;
  StaticMap map;
  Vec2 map_lo, map_hi;  // the whole map's grid, world frame, m
  SpatialHash hash;
  Profile profile;
  size_t ph_control, ph_integrate, ph_broadphase, ph_collide, ph_grippers, ph_odometry, ph_rangers,
      ph_blobfinders, ph_fiducials, ph_bumpers, ph_cameras;
  /// Set in rigid mode (WorldDesc::physics) only.
  std::unique_ptr<RigidBodies, RigidBodiesDelete> rigid;
  double time = 0;  // s
  uint64_t steps = 0;
  // Something moved robots or changed a sensor since the last step (a
  // teleport, a reset, the game layer, a camera's new size): a reading
  // computed at this step may be out of date, so refresh_new_sensors()
  // computes every wanted sensor until the next step.
  bool changed_since_step = false;
  // Set during refresh_new_sensors(): only wanted sensors not computed at
  // this step are computed (due()).
  bool new_sensors_only = false;

  std::vector<RobotInfo> info;
  std::vector<IndexRange> robot_rangers;  // info[i].rangers, compact for the sensor loop
  std::vector<Body> bodies;
  std::vector<Kinematics> kinematics;
  std::vector<Odometry> odom;
  std::vector<PowerState> power;
  std::vector<RobotState> states;
  std::vector<Vec2> verts;  // robot-frame outlines
  std::vector<PolyRef> polys;
  // Per polygon, another polygon of the same robot, convex, holding it with
  // room to spare (`outer`, or -1), and that one's orientation (+1
  // counter-clockwise, -1 clockwise): ranger.cc's nest_outlines.
  struct Nest {
    int32_t outer;
    double turning;
  };
  std::vector<Nest> poly_within;

  std::vector<Transducer> transducers;
  std::vector<IndexRange> transducer_sets;  // the distinct transducer arrays
  std::vector<RangerState> rangers;
  std::vector<float> ranges, intensities;
  std::vector<BlobState> blobfinders;
  std::vector<FiducialState> fiducials;
  std::vector<BumperState> bumpers;
  std::vector<CameraState> cameras;
  std::vector<GripperState> grippers;
  std::vector<StaticInfo> statics;
  /// Each robot's controller memory. Bytes from operator new, which aligns
  /// them for any scalar type (asserted in world.cc), so a controller may
  /// keep any trivially copyable struct there.
  std::vector<std::vector<std::byte>> controller_memory;
  /// World::Residence per robot, as bytes; empty while the world is not
  /// divided (every robot owned), so an undivided step reads nothing more.
  std::vector<uint8_t> residence;
  /// World::set_journal(): where inputs are recorded, or nullptr.
  std::vector<std::byte>* journal = nullptr;
  static constexpr uint8_t kOwned = uint8_t(World::Residence::Owned);
  static constexpr uint8_t kAbsent = uint8_t(World::Residence::Absent);

  // Scratch, reused every step so the step does not allocate.
  std::vector<Vec2> hash_centres;
  std::vector<double> hash_radii;
  std::vector<uint32_t> hash_flags;
  std::vector<uint8_t> accept;
  std::vector<uint32_t> candidates;
  struct Candidate {
    uint32_t index;
    double x, y, r;  // a circle holding the robot this step, m
    // The cosine and sine of its heading, once a beam first needs them
    // (then every other beam reuses them): x is NaN before.
    Vec2 turn;
  };
  std::vector<Candidate> ranger_candidates;
  SeenOutline seen_outline;
  std::vector<RayQuery> ray_queries;
  World::RangerRobots ranger_robots = World::RangerRobots::Auto;
  // The robots for rangers as a layer of cells (robot_layer.h), built at
  // most once per update_rangers(), when a ranger first needs it; with the
  // cosine and sine of each listed robot's heading (robot_turns), and per
  // robot the last beam that tested it (robot_stamps: a robot listed in
  // several cells is tested once per beam).
  RobotLayer robot_layer;
  bool robot_layer_fresh = false;
  std::vector<Vec2> robot_turns;
  std::vector<uint32_t> robot_stamps;
  uint32_t beam_stamp = 0;
  struct RobotHit {
    uint32_t order;  // the robot's place in the hash's order
    RobotId robot;
    double t;  // m along the beam
  };
  std::vector<RobotHit> robot_hits;
  // Beam b's hits: robot_hits[beam_hits[b] .. beam_hits[b + 1]).
  std::vector<uint32_t> beam_hits;
  // Beam b's end (m) when no wall can be before its robots, so it is not
  // cast; 0 when it is.
  std::vector<float> beam_ends;
  RobotId self_robot = 0;  // the robot whose ranger layer_hits_first() casts for
  std::vector<float> wall_ranges;
  std::vector<Pose> transducer_poses;
  // Rangers whose rays wait to be cast together (update_rangers), and the
  // walls' ranges (m) of the batch's rays once cast.
  std::vector<PendingRanger> ranger_batch;
  std::vector<float> batch_ranges;
  // The batch is cast once it holds this many rays (64 and 1 ranger's
  // measured slower on the scale rows; README, "Rangers cast in batches").
  static constexpr size_t kRangerBatchRays = 256;
  std::vector<Vec2> scratch_verts, scratch_verts2;
  std::vector<PolyRef> scratch_polys, scratch_polys2;
  struct Span {
    double t;    // m along the column's horizontal direction
    double top;  // m above the floor
    uint32_t color;
  };
  std::vector<Span> spans;
  // A camera's rows per metre of height at one metre, per column, and the
  // robots it may see with the columns they may cover.
  std::vector<double> camera_k;
  struct CameraCandidate {
    RobotId robot;
    int u0, u1;  // columns, inclusive
  };
  std::vector<CameraCandidate> camera_cols;
  struct CameraSight {
    RobotId robot;
    double bearing, half;  // rad: its centre left of the camera's forward; its half width
    bool around;           // the camera stands in its bounding circle
  };
  std::vector<CameraSight> sights;
  // An omni camera's spans, nearest first, for each of its rays:
  // omni_spans[omni_first[i] .. omni_first[i + 1]).
  std::vector<Span> omni_spans;
  std::vector<uint32_t> omni_first;
  // What an omni camera's pixels look along, which depends only on its
  // description: kept for the last description seen (cameras of a world
  // mostly share one), rebuilt when another comes.
  struct OmniPixel {
    int32_t ray;    // index into the rays; -1 beyond the mirror's rim
    float rise;     // m the pixel's ray climbs per horizontal metre
    float stretch;  // m along the ray per horizontal metre
  };
  std::vector<OmniPixel> omni_pixels;
  std::array<double, 7> omni_pixels_for{};
  void omni_map(const CameraDesc& d, int rays);
};

}  // namespace troupe::sim
