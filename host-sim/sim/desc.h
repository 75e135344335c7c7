// A world described as plain data, SI units: what the loader makes of a
// world file, and what tests and benchmarks may build directly. World's
// constructor turns it into the engine's flat arrays.
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "host-sim/robocup/physics/world.h"
#include "host-sim/sim/geometry.h"
#include "host-sim/world/diagnostics.h"
#include "host-sim/world/png_image.h"
#include "host-sim/world/shared_list.h"

namespace troupe::sim {

using world::SharedList;

/// Closed polygons in the frame of the model that owns them, m.
using Polygons = std::vector<std::vector<Vec2>>;

/// What a model shows to the sensors and the collision test.
struct Appearance {
  /// 0x00RRGGBB.
  uint32_t color = 0xFF0000;
  /// Robots and walls stop at it (Stage's obstacle_return).
  bool obstacle = true;
  /// Reflectance seen by rangers, 0..1; negative: invisible to rangers.
  double ranger_return = 1;
  /// Blobfinders see its colour.
  bool blob = true;
  /// Fiducial id it shows (0: none).
  int fiducial_id = 0;
  /// Only fiducial finders with the same key see it.
  int fiducial_key = 0;
  /// Height, m (blob images; the plane ignores it).
  double height = 0.1;
};

/// A bitmap as obstacles: pixels darker than Stage's threshold are solid.
/// The box of dark pixels is scaled onto the model's footprint.
struct BitmapDesc {
  std::shared_ptr<const world::GrayImage> image;
  /// Pixels with a value at or below it are obstacles (Stage: 127).
  uint8_t threshold = 127;
};

/// A model that never moves: rasterized into the obstacle grid at load.
struct StaticDesc {
  std::string name;
  /// Where the model is, world frame.
  Pose pose;
  /// Offset of the footprint from `pose` (Stage's origin).
  Pose origin;
  /// Footprint size, m: polygons and bitmap are scaled to fill it.
  Vec2 size{1, 1};
  /// Polygons in the footprint frame (centred on `origin`), already scaled.
  Polygons polygons;
  /// A bitmap filling the footprint, when the model has one.
  std::shared_ptr<BitmapDesc> bitmap;
  /// Thin walls along the footprint's edges (Stage's boundary).
  bool boundary = false;
  Appearance look;
  /// Rigid worlds only: exact shapes (m, with height ranges) of a static
  /// rigid body in the frame of `pose` + `origin`, that bodies bounce off
  /// by the world's restitution. Empty: the model is only in the grid (a
  /// wall that refuses moves into it). Give such a model `look.obstacle`
  /// false, so the grid leaves collisions to the physics and rays and
  /// cameras still see it.
  std::vector<robocup::Shape> rigid_shapes;
  /// The owner's label for that body (robocup::World::user_data); the
  /// engine ignores it.
  uint64_t rigid_user_data = 0;
};

/// One ranging transducer (a sonar, an IR, or a laser's whole scan).
struct TransducerDesc {
  /// On the robot, robot frame: m, rad.
  Pose pose;
  double range_min = 0;  // m
  double range_max = 5;  // m
  /// Angle the samples spread over, rad; samples 1 points straight ahead.
  double fov = 0.1;
  int samples = 1;
  /// Range noise: Gaussian with this variance, m^2 (Stage's first noise
  /// value), applied to returns only.
  double noise_variance = 0;
  /// Range noise proportional to the range: uniform in +-this fraction.
  double noise_proportional = 0;
  /// Bearing noise: each beam's direction moves uniformly within +-half of
  /// this, rad.
  double noise_angle = 0;

  bool operator==(const TransducerDesc&) const = default;
};

struct RangerDesc {
  std::string name;
  /// The ranger model on the robot, robot frame (informational; the
  /// transducers carry their own poses).
  Pose pose;
  Vec2 size{0.15, 0.15};
  std::vector<TransducerDesc> transducers;

  bool operator==(const RangerDesc&) const = default;
};

struct BlobfinderDesc {
  Pose pose;                     // robot frame
  double range = 12;             // m
  double fov = kPi / 3;          // rad
  double pan = 0;                // rad, left of forward
  int width = 80;                // image, px
  int height = 60;               // image, px
  std::vector<uint32_t> colors;  // tracked 0x00RRGGBB; empty: every colour
};

/// How a camera's pixels look at the world.
enum class CameraProjection : uint8_t {
  /// A level (or tilted) pinhole camera.
  Pinhole = 0,
  /// 360 degrees through an isometric mirror, seen from above: the robot at
  /// the image centre, its forward up, its left to the left.
  Omni = 1,
};

/// A camera rendering the 2.5D world: footprints extruded to their heights
/// over a floor. Stage's syntax and defaults:
///   camera( resolution [32 32] range [0.2 8.0] fov [70.0 40.0]
///           pantilt [0 0] size [0.1 0.07 0.05] color "black" )
/// and, for an omnidirectional camera (128 x 128 px unless `resolution`
/// says otherwise; fov and pantilt's tilt are then unused):
///   camera( mirror "isometric" mirror_range 4.0 mirror_ground 0.8 mirror_top 30 )
struct CameraDesc {
  /// On the robot, robot frame: m, m, rad (the pan is added to a).
  Pose pose;
  /// Height of the optical centre above the floor, m (Stage stacks a camera
  /// on its robot: the robot's height plus half the camera's).
  double z = 0.5;
  /// Up from level, rad. Applied as a lens shift (rows move by
  /// fy tan(tilt)) so vertical edges stay vertical, as in the 2.5D world.
  double tilt = 0;
  int width = 32, height = 32;   // image, px
  double near = 0.2, far = 8.0;  // m along a pixel's ray
  double hfov = 70 * kPi / 180;  // rad across the image
  double vfov = 40 * kPi / 180;  // rad down the image
  Vec2 size{0.1, 0.07};          // body, m (for geometry requests)
  double size_z = 0.05;          // m
  /// How pixels map to rays. Pinhole uses hfov, vfov and tilt; Omni (an
  /// F2000 robot's camera looking up into an isometric mirror) uses the
  /// mirror_* fields below instead.
  CameraProjection projection = CameraProjection::Pinhole;
  /// Omni: the ground ring is the disc of `mirror_ground` times the image's
  /// half side (min(width, height) / 2), px over px; its pixel radius maps
  /// linearly to ground distance, 0 at the centre to `mirror_range` m at its
  /// edge. Beyond it, out to the half side, the elevation above level grows
  /// linearly from the ground at mirror_range to `mirror_top` rad, so
  /// obstacles show their heights there.
  double mirror_range = 4.0;           // m
  double mirror_ground = 0.8;          // fraction of the half side, 0..1
  double mirror_top = 30 * kPi / 180;  // rad above level
  /// Zero-mean Gaussian noise added to every pixel (none at 0, which costs
  /// nothing): the standard deviation of each colour channel, in levels of
  /// 255, and of each depth, m. Drawn from the run's counter-based
  /// generator by (camera, step, pixel), so an image's noise does not depend
  /// on which other cameras rendered, or in which order.
  double color_noise = 0;
  double depth_noise = 0;
};

/// An omni camera's image side when the world file gives no resolution, px.
inline constexpr int kOmniDefaultSide = 128;

/// Largest image side a world file or configuration may ask for, px.
inline constexpr int kMaxCameraSide = 4096;

struct FiducialDesc {
  Pose pose;                // robot frame
  double range_min = 0;     // m
  double range_max = 8;     // m, detected beyond it: never
  double range_max_id = 5;  // m, identified within it
  double fov = kPi;         // rad
  int key = 0;
};

struct BumperSegment {
  /// Centre of the segment, robot frame; the segment runs along the y axis
  /// of this pose (sideways), `length` long.
  Pose pose;
  double length = 0.1;  // m
};

struct BumperDesc {
  Pose pose;  // robot frame of the bumper model
  std::vector<BumperSegment> segments;
};

enum class Drive { Diff, Omni, Car };
enum class Localization { Gps, Odom };

struct Range {
  double min = -1, max = 1;
};

struct PowerDesc {
  bool enabled = false;
  double capacity = 0;  // J
  double charge = 0;    // J at the start
  /// Drawn all the time, W.
  double watts = 0;
};

/// A Stage gripper on a robot: two paddles in front of it that close on a
/// puck between them and carry it. Stage's keys: `paddle_size [x y z]`
/// (the paddles' reach, their span and height, m) and `paddle_state`.
struct GripperDesc {
  /// The gripper model's centre, robot frame: m, m, rad.
  Pose pose;
  /// The gripper's footprint, m: a puck whose centre lies in the part of it
  /// ahead of the robot's outline, between the paddles, is caught on closing.
  Vec2 size{0.2, 0.3};
  /// Paddles closed at the start (Stage's paddle_state "closed").
  bool closed = false;
};

/// A kicker on a robot (rigid worlds only): a plate that, fired, sends a
/// ball or puck touching it away (sim/kicker.h; RoboCup's kick rule,
/// robocup/physics/kick.h). Its world-file keys are those of a RoboCup kick
/// state: `accel`, `contact`, `hold`, and the kicker's `reach`.
struct KickerDesc {
  /// The plate's centre and heading, robot frame: m, m, rad. A kick goes
  /// along the heading.
  Pose pose;
  /// The plate's footprint (m, along and across the heading) and height
  /// (m, from the floor; 0: unbounded).
  Vec2 size{0.03, 0.3};
  double height = 0.1;
  /// What a kick gives a touching ball: accel (m/s^2) over contact (s).
  double accel = 250, contact = 0.02;
  /// A ball within this gap of the plate counts as touching it, m.
  double reach = 0.03;
  /// After a kick the kicker recovers for this long before the next, s.
  double hold = 0.3;
};

/// A ball (rigid worlds only): a movable round body that rolls to rest,
/// for robots to push and kick. World-file model `ball`; a RoboCup match's
/// ball is one too.
struct BallDesc {
  std::string name = "ball";
  /// m, kg.
  double radius = 0.11, mass = 0.43;
  /// Rolling friction on the floor, m/s^2.
  double deceleration = 0.4;
  /// Where it starts, world: m, m, rad.
  Pose pose;
  /// 0x00RRGGBB.
  uint32_t color = 0xFF8000;
  /// The owner's label for its rigid body (RigidDesc::user_data).
  uint64_t user_data = 0;
};

/// A robot's own rigid body in a rigid world (WorldDesc::physics), for what
/// outline polygons and Stage keys cannot say: a RoboCup robot, a ball.
struct RigidDesc {
  /// Exact shapes, robot frame: circles, ellipses and convex polygons (m)
  /// with height ranges. Empty: the outline polygons, unbounded in height.
  std::vector<robocup::Shape> shapes;
  /// About the centre of mass, kg m^2; 0: from the shapes at uniform
  /// density and RobotDesc::mass.
  double inertia = 0;
  /// Slowing by the floor (rolling or sliding friction), m/s^2 and rad/s^2.
  double linear_deceleration = 0;
  double angular_deceleration = 0;
  /// True: every step the engine sets the body's velocity to the one its
  /// Command asks (a Stage robot on its wheels). False: the body keeps the
  /// velocity the physics and its owner (through World::rigid()) give it;
  /// the engine reads it back after the step (a ball; a RoboCup robot whose
  /// motion plugin drives it).
  bool driven = true;
  /// The owner's label for the body (robocup::World::user_data); the engine
  /// ignores it.
  uint64_t user_data = 0;
};

struct RobotDesc {
  std::string name;
  /// A movable object (a Stage model with `gripper_return 1`), not a robot:
  /// no drive (its velocity bounds are zero), pushed in rigid mode, carried
  /// by grippers.
  bool puck = false;
  /// World pose at the start.
  Pose pose;
  /// Body outline (its own blocks and its children's), robot frame, scaled.
  Polygons polygons;
  Vec2 size{0.1, 0.1};
  Appearance look;
  double mass = 10;  // kg (motion's power drain)

  Drive drive = Drive::Diff;
  double wheelbase = 1.0;  // m, car drive
  /// Velocity bounds x, y (m/s) and turn (rad/s).
  Range velocity[3] = {{-1, 1}, {-1, 1}, {-kPi / 2, kPi / 2}};
  /// Acceleration bounds x, y (m/s^2) and turn (rad/s^2).
  Range acceleration[3] = {{-1, 1}, {-1, 1}, {-kPi / 2, kPi / 2}};
  /// Velocity at the start, robot frame: m/s, m/s, rad/s.
  Pose initial_velocity;

  Localization localization = Localization::Gps;
  /// Where the odometry frame is, world frame. Default: the start pose.
  Pose localization_origin;
  bool has_localization_origin = false;
  /// Largest odometry scale error per axis (x, y, a); each robot draws its
  /// own error uniformly in [-e/2, e/2] at the start.
  Pose odom_error{0.03, 0.03, 0.05};

  PowerDesc power;
  /// Shared by robots of one make-up (the loader gives robots of one type
  /// one list); change one robot's through edit().
  SharedList<RangerDesc> rangers;
  std::vector<BlobfinderDesc> blobfinders;
  std::vector<FiducialDesc> fiducials;
  std::vector<BumperDesc> bumpers;
  std::vector<CameraDesc> cameras;
  std::vector<GripperDesc> grippers;
  /// Rigid worlds only.
  std::vector<KickerDesc> kickers;
  /// Rigid worlds: the body's own shapes and mass properties. Absent: the
  /// outline polygons, `mass`, driven unless a puck (pucks slide to rest).
  std::optional<RigidDesc> rigid;

  /// Controller named in the world file ("wander arg1 ..."), and where.
  std::string ctrl;
  world::SourceLoc ctrl_loc;
};

/// The `window` block: kept for the viewer and snapshots.
struct WindowDesc {
  int width = 0, height = 0;  // px (0: not given)
  double scale = 0;           // px/m (0: not given)
  Vec2 center;                // m
};

/// How the step moves bodies (the world file's top-level `physics` key).
enum class Physics {
  /// Stage's model: a robot moves exactly as commanded unless the move would
  /// overlap something, then it stays put and stalls. Pucks are obstacles.
  Kinematic,
  /// Rigid bodies (host-sim/robocup/physics): robots are driven at their
  /// commanded velocities and push each other and pucks by impulses; walls
  /// of the static map stop them.
  Rigid,
};

/// Paint on the floor, as cameras see it (the obstacle grid ignores it).
/// Later marks cover earlier ones.
struct FloorMark {
  /// A stroke `width` m wide centred on the segment a-b (world, m), or,
  /// when `radius` > 0, on the circle of that radius (m) about a.
  Vec2 a, b;
  double radius = 0;
  double width = 0.1;
  uint32_t color = 0xFFFFFF;  // 0x00RRGGBB
};

struct FloorDesc {
  uint32_t color = 0x808080;  // 0x00RRGGBB, where nothing is painted
  std::vector<FloorMark> marks;
};

/// The colour of the floor at world point p (m).
uint32_t floor_color(const FloorDesc& floor, Vec2 p);

/// How the static map keeps its cells (StaticMap::reset). Dense: every
/// cell, a byte each. Sparse: only the 8 x 8 blocks that hold or border an
/// obstacle; every other block is one shared block of its distance code, so
/// a campus-sized floorplan costs what its walls cost, not what its area
/// does. Both give the same rays, collisions and sensors. Auto: sparse from
/// StaticMap::kSparseFromCells cells on; tests and benchmarks may force one.
enum class MapStorage : uint8_t { Auto, Dense, Sparse };

struct WorldDesc {
  Physics physics = Physics::Kinematic;
  MapStorage map_storage = MapStorage::Auto;
  /// Obstacle grid cell size, m.
  double resolution = 0.02;
  /// Simulated time per step, s.
  double interval_sim = 0.1;
  /// Wall time per step in real-time mode, s (Stage's interval_real).
  double interval_real = 0.1;
  /// Stop after this much simulated time, s; 0: never.
  double quit_time = 0;
  bool paused = false;
  /// Where the world file says `paused` ("file:line"); empty when it does not.
  std::string paused_at;
  /// Multiple of real time to run at; 0 or less: as fast as possible.
  double speedup = 1;
  /// Worker threads asked for. Results never depend on it.
  int threads = 1;
  /// Rigid worlds: restitution, friction, contact and impact settings of
  /// the physics. Its cycle_s is not read: the step is interval_sim. The
  /// defaults suit robots and pucks, heavy wheeled bases and sliding
  /// blocks that hardly bounce; a RoboCup world gives its own.
  robocup::WorldDef rigid{.restitution = 0.1, .friction = 0.3};
  WindowDesc window;
  FloorDesc floor;
  std::vector<StaticDesc> statics;
  std::vector<RobotDesc> robots;
};

}  // namespace troupe::sim
