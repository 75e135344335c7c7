// What plugins see of the RoboCup world: the field's landmarks and lines,
// the ball, the robots, the game, and rays. Players may also move the ball
// and robots (WorldControl). Plain structs and abstract classes only, so a
// plugin built as its own shared library needs nothing else.
#pragma once

#include <cstdint>
#include <string_view>
#include <vector>

#include "host-sim/robocup/physics/vec2.h"

namespace troupe::robocup {

/// Blue defends the goal at -x, yellow the goal at +x.
enum class Team : uint8_t { Blue = 0, Yellow = 1 };

inline const char* team_name(Team t) {
  return t == Team::Blue ? "blue" : "yellow";
}
inline Team opponent(Team t) {
  return t == Team::Blue ? Team::Yellow : Team::Blue;
}

/// What a sensor can report, and what a ray can hit.
enum class ObjectKind : uint8_t {
  Ball = 0,
  /// id 0: the blue goal (-x), 1: the yellow goal (+x); at the mouth's centre.
  Goal = 1,
  /// id 0/1: blue goal's right/left post (seen from the field), 2/3: yellow's.
  GoalPost = 2,
  /// id 0..3 counter-clockwise from the (+x, +y) corner.
  CornerPost = 3,
  /// id: index into FieldGeometry::lines; -1 for the centre circle.
  Line = 4,
  /// id: the robot's index.
  Robot = 5,
  /// Walls, barrier, goal walls: anything static that is not a landmark.
  Structure = 6,
};

struct Landmark {
  ObjectKind kind;
  int id;
  /// World, m.
  Vec2 position;
  /// The landmark's own radius (corner posts), m; 0 for points.
  double radius = 0;
};

struct LineSegment {
  /// World, m.
  Vec2 a, b;
};

/// The field as plugins see it. Dimensions in m.
struct FieldGeometry {
  double length = 0, width = 0;
  double goal_width = 0, goal_depth = 0;
  double center_circle_radius = 0;
  /// Floor beyond the lines before the barrier, m.
  double border = 0;
  std::vector<Landmark> landmarks;
  /// The white lines (touch, goal, halfway, penalty areas).
  std::vector<LineSegment> lines;
};

struct Score {
  int blue = 0, yellow = 0;
  bool operator==(const Score&) const = default;
};

enum class GamePhase : uint8_t {
  /// The ball is in play.
  Play = 0,
  /// A goal was scored; the referee resets the field after a pause.
  GoalPause = 1,
  /// Time is up, or the game was halted.
  Stopped = 2,
};

struct GameInfo {
  Score score;
  GamePhase phase = GamePhase::Play;
  /// Simulated time, s.
  double time_s = 0;
};

struct BallInfo {
  /// World: m, m/s.
  Vec2 position, velocity;
  /// m.
  double radius = 0;
};

struct RobotInfo {
  std::string_view name;
  Team team = Team::Blue;
  int index = -1;
  /// Ground truth, world frame: m, rad; m/s, rad/s (of the robot's origin).
  Pose2 pose;
  Twist velocity;
  /// The farthest point of the robot's shapes from its origin, m.
  double radius = 0;
};

/// What a ray hit.
struct RayResult {
  ObjectKind kind = ObjectKind::Structure;
  /// Robot index for robots, landmark id for posts, -1 otherwise.
  int id = -1;
  /// m along the ray.
  double distance = 0;
};

class WorldView {
 public:
  virtual ~WorldView() = default;
  /// Simulated time, s, and the fixed step, s.
  virtual double time_s() const = 0;
  virtual double cycle_s() const = 0;
  virtual const FieldGeometry& field() const = 0;
  virtual BallInfo ball() const = 0;
  virtual int robot_count() const = 0;
  virtual RobotInfo robot(int index) const = 0;
  /// -1 when there is no such robot.
  virtual int find_robot(std::string_view name) const = 0;
  virtual GameInfo game() const = 0;
  /// The first object a ray from `origin` (world, m) at `angle_rad` (world)
  /// meets within `max_range` m, at height `z` m (shapes whose height range
  /// misses z are not seen). Robot `ignore_robot` (its own) is skipped.
  virtual bool raycast(Vec2 origin, double angle_rad, double max_range, double z, int ignore_robot,
                       RayResult& out) const = 0;
  /// True when nothing at height `z` m blocks the segment from `from` to
  /// the point `clearance` m short of `to` (world, m; the target's own
  /// size), ignoring robot `ignore_robot` and the target robot
  /// `target_robot` (-1 for none); the ball never blocks.
  virtual bool line_of_sight(Vec2 from, Vec2 to, double z, int ignore_robot, int target_robot,
                             double clearance) const = 0;
};

/// The world as player plugins may change it.
class WorldControl : public WorldView {
 public:
  /// Moves the ball: world, m and m/s.
  virtual void place_ball(Vec2 position, Vec2 velocity) = 0;
  /// Teleports a robot (world, m, rad) and stops it.
  virtual void place_robot(int index, Pose2 pose) = 0;
};

}  // namespace troupe::robocup
