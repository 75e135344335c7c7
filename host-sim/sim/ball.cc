#include "host-sim/sim/ball.h"

#include <algorithm>
#include <cmath>

namespace troupe::sim {

RobotDesc ball_robot(const BallDesc& b) {
  RobotDesc r;
  r.name = b.name;
  r.pose = b.pose;
  r.puck = true;
  const robocup::Shape round = robocup::make_circle({0, 0}, b.radius);
  r.polygons.push_back(robocup::outline(round));
  double reach = 0;
  for (Vec2 p : r.polygons.back()) reach = std::max({reach, std::fabs(p.x), std::fabs(p.y)});
  r.size = {2 * reach, 2 * reach};
  r.look.color = b.color;
  r.look.height = 2 * b.radius;
  r.mass = b.mass;
  RigidDesc rigid;
  rigid.shapes = {robocup::with_height(round, 0, 2 * b.radius)};
  // A solid sphere rolling on the floor.
  rigid.inertia = 0.4 * b.mass * b.radius * b.radius;
  rigid.linear_deceleration = b.deceleration;
  rigid.angular_deceleration = b.deceleration / b.radius;
  rigid.user_data = b.user_data;
  // Nothing drives it: the physics, kicks and grippers move it.
  rigid.driven = false;
  r.rigid = std::move(rigid);
  return r;
}

}  // namespace troupe::sim
