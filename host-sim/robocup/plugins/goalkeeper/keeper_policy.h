// Where a goalkeeper stands, by policy. Pure functions of the ball and the
// clock (and a seeded generator for `random`), so the policies can be
// tested one by one; goalkeeper.cc drives the robot there.
#pragma once

#include <algorithm>
#include <cmath>
#include <string>

#include "host-sim/robocup/api/plugin.h"

namespace troupe::robocup::plugins {

enum class KeeperPolicy { None, Random, Pattern, Block, Intercept, Mixed };

inline bool parse_policy(const std::string& s, KeeperPolicy& out) {
  const std::pair<const char*, KeeperPolicy> names[] = {
      {"none", KeeperPolicy::None},           {"random", KeeperPolicy::Random},
      {"pattern", KeeperPolicy::Pattern},     {"block", KeeperPolicy::Block},
      {"intercept", KeeperPolicy::Intercept}, {"mixed", KeeperPolicy::Mixed}};
  for (const auto& [name, p] : names) {
    if (s == name) {
      out = p;
      return true;
    }
  }
  return false;
}

/// The keeper's goal and line, world frame.
struct KeeperGeometry {
  /// The goal line's x, m, and +1 when the field lies towards +x (blue), -1
  /// otherwise.
  double goal_x = -4.5, forward = 1;
  /// Distance of the keeper's line in front of the goal line, m.
  double line = 0.35;
  /// Half the goal mouth, m, and how far off centre the keeper goes, m.
  double goal_half_width = 1.0, reach = 0.8;

  double line_x() const { return goal_x + forward * line; }
};

struct KeeperSettings {
  /// random: a new spot every period s; pattern: one sweep there and back
  /// takes period s.
  double random_period_s = 1.0, pattern_period_s = 4.0;
  /// mixed: a new policy (block, intercept, pattern or random, equally
  /// likely) every period s: a mixed strategy a striker cannot learn to
  /// exploit.
  double mix_period_s = 2.0;
};

struct KeeperMemory {
  double next_pick_s = -1;
  double random_y = 0;
  double next_mix_s = -1;
  KeeperPolicy mixed = KeeperPolicy::Block;
  /// What the last decision used (for logs and tests).
  KeeperPolicy acting = KeeperPolicy::None;
};

/// The keeper's y on its line when blocking: on the segment from the ball
/// to the goal's centre.
inline double block_y(const KeeperGeometry& g, Vec2 ball) {
  const double dx = ball.x - g.goal_x;
  if (g.forward * dx <= g.line)
    return std::clamp(ball.y, -g.reach, g.reach);  // level with or behind the line
  return std::clamp(ball.y * (g.line * g.forward) / dx, -g.reach, g.reach);
}

/// Where the rolling ball crosses the keeper's line, if it is heading for
/// the goal (within a margin of the posts); false otherwise.
inline bool crossing_y(const KeeperGeometry& g, Vec2 ball, Vec2 v, double& y) {
  const double toward = -g.forward * v.x;  // speed towards the goal, m/s
  if (toward <= 0.05) return false;
  const double t = (g.line_x() - ball.x) / v.x;
  if (t < 0) return false;
  const double at_goal = ball.y + v.y * (g.goal_x - ball.x) / v.x;
  if (std::fabs(at_goal) > g.goal_half_width + 0.3) return false;
  y = std::clamp(ball.y + v.y * t, -g.reach, g.reach);
  return true;
}

/// The spot on the keeper's line the policy wants now (world, m). `me` is
/// where the keeper is (None stays there).
inline Vec2 keeper_target(KeeperPolicy p, const KeeperGeometry& g, const KeeperSettings& s, Vec2 me,
                          Vec2 ball, Vec2 ball_v, double time_s, KeeperMemory& m, Rng& rng) {
  m.acting = p;
  switch (p) {
    case KeeperPolicy::None:
      return me;
    case KeeperPolicy::Random:
      if (time_s >= m.next_pick_s) {
        m.random_y = rng.uniform(-g.reach, g.reach);
        m.next_pick_s = time_s + s.random_period_s;
      }
      return {g.line_x(), m.random_y};
    case KeeperPolicy::Pattern: {
      // A triangle wave: centre, one post, the other post, centre.
      const double phase = std::fmod(time_s / s.pattern_period_s + 0.25, 1.0);
      const double tri = phase < 0.5 ? 4 * phase - 1 : 3 - 4 * phase;
      return {g.line_x(), g.reach * tri};
    }
    case KeeperPolicy::Block:
      return {g.line_x(), block_y(g, ball)};
    case KeeperPolicy::Intercept: {
      double y;
      if (crossing_y(g, ball, ball_v, y)) return {g.line_x(), y};
      m.acting = KeeperPolicy::Block;
      return {g.line_x(), block_y(g, ball)};
    }
    case KeeperPolicy::Mixed: {
      if (time_s >= m.next_mix_s) {
        constexpr KeeperPolicy kChoices[4] = {KeeperPolicy::Block, KeeperPolicy::Intercept,
                                              KeeperPolicy::Pattern, KeeperPolicy::Random};
        m.mixed = kChoices[std::min(size_t(rng.uniform() * 4), size_t(3))];
        m.next_mix_s = time_s + s.mix_period_s;
      }
      const Vec2 target = keeper_target(m.mixed, g, s, me, ball, ball_v, time_s, m, rng);
      return target;
    }
  }
  return me;
}

}  // namespace troupe::robocup::plugins
