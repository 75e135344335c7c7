// The troupe-sim engine's public face: a world of robots stepped at a fixed
// interval, each with a command input and sensor outputs as plain structs.
// The serving layer, controllers, viewer and SITL emulators use only this.
//
//   World world(desc, Random(seed));         // or World::load(path, seed, diags)
//   world.set_wanted({SensorKind::Ranger, world.robot(r).rangers.first}, true);
//   world.command(r, Command::velocity(0.3, 0, 0.1));
//   world.step();                            // interval_sim of simulated time
//   RangerView scan = world.ranger(i);       // ranges computed in that step
//
// Deterministic: the same description and seed give the same trajectory on
// every run, whatever order sensors are read or wanted in.
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "host-sim/sim/desc.h"
#include "host-sim/sim/profile.h"
#include "host-sim/sim/random.h"
#include "host-sim/world/diagnostics.h"

namespace troupe::robocup {
class World;
struct BodyId;
}  // namespace troupe::robocup

namespace troupe::sim {

class StaticMap;
struct Engine;

/// A robot: index into the world's robots, 0..robot_count()-1, stable for
/// the world's life (robots are never added or removed after load).
using RobotId = uint32_t;

enum class SensorKind : uint8_t { Ranger, Blobfinder, Fiducial, Bumper, Camera };

/// One sensor of the world: its kind and its index among that kind's
/// sensors (world-wide; a robot's are contiguous, see RobotInfo).
struct SensorRef {
  SensorKind kind;
  uint32_t index;
};

/// A contiguous run of world-wide sensor indices.
struct IndexRange {
  uint32_t first = 0;
  uint32_t count = 0;
};

/// What a robot carries, by world-wide sensor index.
struct RobotInfo {
  std::string name;
  IndexRange rangers, blobfinders, fiducials, bumpers, cameras;
  /// Its grippers, by world-wide gripper index.
  IndexRange grippers;
  bool has_power = false;
  /// A movable object (a Stage model with `gripper_return 1`), not a robot:
  /// commands do not move it (RobotDesc::puck).
  bool puck = false;
};

enum class CommandMode : uint8_t { Velocity, Goto };

/// What a robot is told to do. The newest command replaces the last.
struct Command {
  CommandMode mode = CommandMode::Velocity;
  /// Velocity: x forward (m/s), y left (m/s; omni drive only) and turn rate
  /// a (rad/s); a car drive reads a as its steering angle (rad).
  /// Goto: the goal in the odometry frame (m, m, rad).
  Pose value;

  static Command velocity(double x, double y, double a) { return {CommandMode::Velocity, {x, y, a}}; }
  static Command go_to(double x, double y, double a) { return {CommandMode::Goto, {x, y, a}}; }
};

/// What a robot's position device reports.
struct RobotState {
  /// Ground truth, world frame: m, m, rad.
  Pose pose;
  /// Current velocity, robot frame: m/s, m/s, rad/s.
  Pose velocity;
  /// Localization estimate (gps: exact; odom: integrated with error) in the
  /// odometry frame: m, m, rad.
  Pose odometry;
  /// The last move was blocked by an obstacle or another robot.
  bool stalled = false;
  /// The battery is empty: the robot cannot move.
  bool disabled = false;
};

struct RangerView {
  /// One per beam, transducers in order, samples right to left: m. A beam
  /// that hit nothing reads its transducer's range_max.
  std::span<const float> ranges;
  /// Reflectance of what each beam hit (ranger_return), 0 for nothing.
  std::span<const float> intensities;
  /// The step the data was computed at (it is not recomputed while nobody
  /// wants it); UINT64_MAX before the first computation.
  uint64_t step = UINT64_MAX;
};

struct Blob {
  uint32_t color = 0;                            // 0x00RRGGBB
  uint32_t channel = 0;                          // index in the blobfinder's colour list
  int left = 0, right = 0, top = 0, bottom = 0;  // px, image x right, y down
  double x = 0, y = 0;                           // centroid, px
  uint32_t area = 0;                             // px
  double range = 0;                              // m, mean over the blob's columns
};

struct BlobView {
  std::span<const Blob> blobs;
  int width = 0, height = 0;  // px
  uint64_t step = UINT64_MAX;
};

struct FiducialReading {
  /// The landmark's fiducial_return; -1 when too far to identify.
  int id = 0;
  double range = 0;    // m, to the landmark's centre
  double bearing = 0;  // rad, left of the sensor's heading
  /// The landmark's pose in the sensor frame: m, m, rad.
  Pose pose;
};

struct FiducialView {
  std::span<const FiducialReading> readings;
  uint64_t step = UINT64_MAX;
};

struct BumperView {
  uint32_t pressed = 0;  // bit i: segment i touches something
  uint32_t count = 0;
  uint64_t step = UINT64_MAX;
};

/// A camera's latest rendering: both images, row by row from the top row,
/// each row left to right.
struct CameraView {
  int width = 0, height = 0;  // px
  /// width x height x 3 bytes: red, green, blue.
  std::span<const uint8_t> rgb;
  /// width x height distances along each pixel's ray, m; +infinity where
  /// nothing (floor included) is within the camera's far range.
  std::span<const float> depth;
  uint64_t step = UINT64_MAX;
};

/// A gripper's paddles and what they hold.
struct GripperView {
  bool closed = false;
  /// The puck held between the paddles, when `holding`.
  bool holding = false;
  RobotId held = 0;
};

struct PowerView {
  double joules = 0;    // J left
  double capacity = 0;  // J
  double watts = 0;     // W drawn in the last step
};

/// The farthest a teleport may put a robot from the origin on either axis,
/// m: a thousand kilometres, beyond any world, and at 1 mm cells still
/// inside the int range the engine's grids index with.
inline constexpr double kMaxCoordinate = 1e6;

/// True when every value of `p` is finite.
bool finite_pose(const Pose& p);

class World {
 public:
  /// Builds a world. `random` is the run's only source of randomness.
  World(const WorldDesc& desc, Random random);
  ~World();
  World(const World&) = delete;
  World& operator=(const World&) = delete;

  /// Loads a Stage world file. Warnings and errors go to `diags` (file:line);
  /// nullptr when there were errors.
  static std::unique_ptr<World> load(const std::string& path, uint64_t seed, world::Diagnostics& diags);

  // ---- Time ------------------------------------------------------------------

  /// Advances one interval_sim: commands, motion, collisions, odometry,
  /// power, then the wanted sensors.
  void step();
  /// Computes the wanted sensors for the current state without moving
  /// anything (after load, a teleport, or a sensor becoming wanted).
  void refresh_sensors();
  /// The same for the sensors that became wanted since they were last
  /// computed (a paused world's new readers): a reading already computed
  /// at this step stands, so each new reader costs its own sensor, not the
  /// whole world's. After a teleport, reset(), rigid_moved() or a camera's
  /// new size, every wanted sensor until the next step, as refresh_sensors().
  void refresh_new_sensors();
  /// True from a teleport, reset(), rigid_moved() or a camera's new size
  /// until the next step: readings of this step may be out of date.
  bool changed_since_step() const;
  /// Every robot back to its start (pose, velocity, odometry, battery) and
  /// the clock to 0.
  void reset();

  /// Simulated time since the start, s.
  double time() const;
  uint64_t steps() const;
  /// Simulated time per step, s.
  double interval() const;
  const WorldDesc& desc() const;

  // ---- Robots ----------------------------------------------------------------

  size_t robot_count() const;
  const RobotInfo& robot(RobotId id) const;
  std::optional<RobotId> find_robot(std::string_view name) const;
  const RobotState& state(RobotId id) const;
  // The three inputs below come from the wire, controllers and emulators.
  // Each refuses (returns false, changes nothing) a value the engine cannot
  // step: not finite, or a position beyond kMaxCoordinate. Callers say so;
  // the world never holds a NaN.

  /// Teleports a robot (ground truth, world frame; |x|, |y| at most
  /// kMaxCoordinate m). Its odometry follows in gps mode and keeps its
  /// estimate in odom mode, as a real robot's would.
  bool set_pose(RobotId id, const Pose& pose);
  /// Replaces the robot's command (held until the next one); every value
  /// finite.
  bool command(RobotId id, const Command& cmd);
  /// Restarts odometry at `pose` (odometry frame; finite).
  bool set_odometry(RobotId id, const Pose& pose);
  PowerView power(RobotId id) const;

  // ---- Sensors ---------------------------------------------------------------

  /// Only wanted sensors are computed; the serving layer sets this from
  /// whether anyone reads them.
  void set_wanted(SensorRef sensor, bool wanted);
  bool wanted(SensorRef sensor) const;
  /// The robot a sensor is on.
  RobotId owner(SensorRef sensor) const;

  const RangerDesc& ranger_desc(uint32_t index) const;
  RangerView ranger(uint32_t index) const;
  /// Each beam's origin and direction, world frame (m, m, rad), at the
  /// robot's current pose, in the order of RangerView::ranges.
  std::vector<Pose> ranger_beams(uint32_t index) const;
  const BlobfinderDesc& blobfinder_desc(uint32_t index) const;
  BlobView blobfinder(uint32_t index) const;
  const FiducialDesc& fiducial_desc(uint32_t index) const;
  FiducialView fiducial(uint32_t index) const;
  const BumperDesc& bumper_desc(uint32_t index) const;
  BumperView bumper(uint32_t index) const;
  const CameraDesc& camera_desc(uint32_t index) const;
  CameraView camera(uint32_t index) const;
  /// Changes a camera's image size (1..kMaxCameraSide px each way; false
  /// and nothing changed otherwise). The next rendering has the new size.
  bool set_camera_size(uint32_t index, int width, int height);

  // ---- Grippers --------------------------------------------------------------

  /// Grippers by world-wide index (a robot's are RobotInfo::grippers).
  size_t gripper_count() const;
  RobotId gripper_owner(uint32_t index) const;
  GripperView gripper(uint32_t index) const;
  /// Closes (catching a puck whose centre lies in the gripper's footprint,
  /// which is then carried) or opens (dropping it where it is) the paddles
  /// at the next step.
  void set_gripper(uint32_t index, bool closed);

  // ---- The rigid-body world -------------------------------------------------

  /// Rigid worlds (WorldDesc::physics): the one rigid-body world the step
  /// moves bodies in, for a game layer on top (RoboCup mode) to cast rays,
  /// kick, teleport and reshape the same bodies. nullptr in a kinematic
  /// world. Velocities set on undriven bodies (RigidDesc::driven false) are
  /// kept into the next step; after moving bodies itself (a teleport), the
  /// game layer calls rigid_moved().
  robocup::World* rigid();
  /// The rigid body of robot `id`, or of the static model `index` (in
  /// WorldDesc::statics); robocup::kNoBody where it has none.
  robocup::BodyId rigid_body(RobotId id) const;
  robocup::BodyId rigid_static_body(size_t index) const;
  /// Takes every rigid body's pose, and the undriven ones' velocities, into
  /// the robots' states, so states and sensors follow what the game layer
  /// did to the rigid world. Nothing in a kinematic world.
  void rigid_moved();

  // ---- Controller memory ------------------------------------------------------

  /// Gives the robot `bytes` of controller memory, all zero (what a
  /// controller remembers between steps: host-sim/sim/controller.h). It is
  /// the robot's, like its pose: reset() zeroes it, and whoever moves the
  /// robot elsewhere moves these bytes with it.
  void set_controller_memory_size(RobotId id, size_t bytes);
  /// The robot's controller memory (empty when none was given), aligned
  /// for any scalar type.
  std::span<std::byte> controller_memory(RobotId id);
  std::span<const std::byte> controller_memory(RobotId id) const;

  // ---- Divided between processes (host-sim/mpi) ------------------------------

  /// Under MPI every process holds the whole world's description but steps
  /// only the robots it owns. A ghost is another process's robot near
  /// enough to meet or be sensed by one of its own: its motion is copied in
  /// twice a step (StepExchange), never computed here. The rest are absent:
  /// nothing here reads them. A world nobody divides owns every robot.
  enum class Residence : uint8_t { Owned, Ghost, Absent };
  void set_residence(RobotId id, Residence residence);
  Residence residence(RobotId id) const;
  /// True when the world can be divided; otherwise `why` says what stops
  /// it (grippers carry pucks from robot to robot; rigid bodies push each
  /// other in one physics world).
  bool divisible(std::string& why) const;
  /// The farthest, m, a robot's centre can be from the centre of another
  /// robot it may meet or sense in one step: its largest sensor reach,
  /// both robots' radii, and both robots' largest move in a step. Ghosts
  /// are the robots within this of a process's region.
  double interaction_reach() const;

  /// A ghost's motion in one step: where it is, where it asks to go (pose,
  /// proposed: world frame, m, m, rad) and whether it moves at all.
  struct GhostMotion {
    Pose pose;
    Pose proposed;
    bool moved = false;
  };
  GhostMotion ghost_motion(RobotId id) const;
  void set_ghost_motion(RobotId id, const GhostMotion& motion);

  /// Called by step(StepExchange&) between its phases.
  class StepExchange {
   public:
    virtual ~StepExchange() = default;
    /// Owned robots' proposed moves are known; ghosts' must be set
    /// (set_ghost_motion, and set_residence for robots coming and going)
    /// before collisions are judged.
    virtual void proposed(World& world) = 0;
    /// Owned robots have ended their move; ghosts' must be set to where
    /// theirs ended (proposed = pose) before sensors are computed.
    virtual void moved(World& world) = 0;
  };
  /// step() for a divided world: the same phases, with the exchange.
  void step(StepExchange& exchange);

  /// Holds only the part of the static map within [lo, hi] (world frame,
  /// m) and as far around it as the distance field reaches, for a process
  /// that steps robots there alone: rays, collisions and sensors there
  /// read what the whole map holds, while memory falls with the window.
  /// The grid, its origin and size stay the whole map's. False when the
  /// window takes in the whole grid (or the map must be kept whole: a
  /// small map asked to be sparse).
  bool keep_map_within(Vec2 lo, Vec2 hi);

  /// Appends everything of robot `id` that changes as it runs (pose,
  /// velocity, command, odometry and its error, battery, its sensors' last
  /// readings and wanted flags, its controller memory) to `out`, for the
  /// process it migrates to.
  void save_robot(RobotId id, std::vector<std::byte>& out) const;
  /// Reads what save_robot() wrote for the same robot of the same world;
  /// false, and `in` left where the error was, when the bytes do not fit.
  bool restore_robot(RobotId id, std::span<const std::byte>& in);

  /// While `journal` is set, every input the world takes (command,
  /// set_pose, set_odometry, set_wanted, set_gripper, set_camera_size) is
  /// also appended to it, so the process serving clients can hand them to
  /// the processes that own the robots. nullptr stops it.
  void set_journal(std::vector<std::byte>* journal);
  /// The journal set_journal() set, or nullptr.
  std::vector<std::byte>* journal() const;
  /// Takes the inputs a journal holds, in their order (none is journaled
  /// again). False at the first record that is not one.
  bool replay(std::span<const std::byte> journal);

  // ---- Inspection ------------------------------------------------------------

  /// The robot's outline at its current pose, world frame (snapshots,
  /// viewer).
  std::vector<std::vector<Vec2>> outline(RobotId id) const;
  /// The static obstacles.
  const StaticMap& map() const;
  /// Time per phase of the step.
  const Profile& profile() const;
  Profile& profile();
  const Random& random() const;
  /// Bytes held by the engine's arrays (grid, hash, robots, sensors).
  size_t memory_bytes() const;
  /// Benchmarks only: cast every ray cell by cell (the baseline the
  /// distance-field marching is measured against). Results are the same.
  void set_raycast_per_cell(bool on);
  /// How rangers find the robots in their beams. Tests and benchmarks only:
  /// every choice gives the same ranges and intensities, bit for bit.
  enum class RangerRobots {
    Auto,        // by how many robots stand within the ranger's reach
    Candidates,  // each nearby robot against the beams its circle spans
    Layer,       // each beam through the per-step robot layer (robot_layer.h)
    Every,       // every robot against every beam: the plain reference
  };
  void set_ranger_robots(RangerRobots how);

 private:
  std::unique_ptr<Engine> e_;
};

}  // namespace troupe::sim
