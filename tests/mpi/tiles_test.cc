// What a divided world rests on, without MPI: the tiles that give every
// point one owner and find the ranks that must see a robot as a ghost, and
// a robot's running state as bytes, which a fresh copy of the world takes
// up and steps on to the same bits.
#include "host-sim/mpi/tiles.h"

#include <gtest/gtest.h>

#include <set>

#include "host-sim/sim/world.h"
#include "tests/sim/scenes.h"

namespace troupe::sim {
namespace {

using mpi::Tiles;

std::vector<Vec2> symmetric_points() {
  std::vector<Vec2> p;
  for (double x : {-3.0, -1.0, 1.0, 3.0}) {
    for (double y : {-2.0, -0.5, 0.5, 2.0}) p.push_back({x, y});
  }
  return p;
}

TEST(Tiles, FourRanksAreTwoByTwoCutWhereTheRobotsSplitEvenly) {
  const Tiles t = Tiles::balanced(4, symmetric_points());
  ASSERT_EQ(t.cols(), 2);
  ASSERT_EQ(t.rows(), 2);
  EXPECT_EQ(t.x_cuts(), std::vector<double>{0.0});
  EXPECT_EQ(t.y_cuts(), std::vector<double>{0.0});
  std::set<int> owners;
  for (const Vec2& p : symmetric_points()) owners.insert(t.owner(p));
  EXPECT_EQ(owners, (std::set<int>{0, 1, 2, 3}));
  // Each of the four holds a quarter of the robots.
  std::vector<int> count(4);
  for (const Vec2& p : symmetric_points()) ++count[size_t(t.owner(p))];
  EXPECT_EQ(count, (std::vector<int>{4, 4, 4, 4}));
}

TEST(Tiles, ShapesAreAsSquareAsTheRankCountAllows) {
  const std::vector<Vec2> p = symmetric_points();
  EXPECT_EQ(Tiles::balanced(1, p).ranks(), 1);
  EXPECT_EQ(Tiles::balanced(2, p).cols(), 2);
  EXPECT_EQ(Tiles::balanced(3, p).cols(), 3);
  EXPECT_EQ(Tiles::balanced(3, p).rows(), 1);
  EXPECT_EQ(Tiles::balanced(6, p).cols(), 3);
  EXPECT_EQ(Tiles::balanced(6, p).rows(), 2);
  // One rank owns everything, however far.
  EXPECT_EQ(Tiles::balanced(1, p).owner({1e6, -1e6}), 0);
}

TEST(Tiles, CostsMoveTheCutsTowardTheCostlyRobots) {
  // 100 robots 1 m apart along x; those beyond 50 m cost three times as
  // much: half the cost lies below 50 + 50 / 3 m.
  std::vector<Vec2> points;
  std::vector<double> costs;
  for (int i = 0; i < 100; ++i) {
    points.push_back({i + 0.5, 0});
    costs.push_back(i < 50 ? 1.0 : 3.0);
  }
  const Tiles t = Tiles::balanced(2, points, costs);
  ASSERT_EQ(t.x_cuts().size(), 1u);
  EXPECT_GT(t.x_cuts()[0], 65.0);
  EXPECT_LT(t.x_cuts()[0], 68.0);
  // Equal costs cut where counting does, within a robot's spacing.
  const Tiles even = Tiles::balanced(4, points, std::vector<double>(100, 0.25));
  const Tiles counted = Tiles::balanced(4, points);
  for (size_t k = 0; k < even.x_cuts().size(); ++k) EXPECT_NEAR(even.x_cuts()[k], counted.x_cuts()[k], 1.0);
  for (size_t k = 0; k < even.y_cuts().size(); ++k) EXPECT_NEAR(even.y_cuts()[k], counted.y_cuts()[k], 1.0);
  // Nothing measured yet (no cost at all): still increasing cuts.
  const Tiles none = Tiles::balanced(3, points, std::vector<double>(100, 0.0));
  ASSERT_EQ(none.x_cuts().size(), 2u);
  EXPECT_LT(none.x_cuts()[0], none.x_cuts()[1]);
}

TEST(Tiles, NearFindsEveryRegionWithinTheHaloAndOnlyThose) {
  const Tiles t = Tiles::balanced(4, symmetric_points());
  std::vector<int> near;
  t.near({0.1, 0.1}, 0.5, near);  // at the corner where the four meet
  EXPECT_EQ(near, (std::vector<int>{0, 1, 2, 3}));
  t.near({0.1, 5.0}, 0.5, near);  // beside the x cut, far from the y cut
  EXPECT_EQ(near.size(), 2u);
  t.near({5.0, 5.0}, 0.5, near);  // deep inside one region
  ASSERT_EQ(near.size(), 1u);
  EXPECT_EQ(near[0], t.owner({5.0, 5.0}));
}

TEST(Tiles, RobotsAllInOneLineStillGiveIncreasingCuts) {
  // Every robot at x = 2: the cuts cannot split them, but must still
  // increase so each point has exactly one owner.
  std::vector<Vec2> p(10, Vec2{2.0, 0.0});
  const Tiles t = Tiles::balanced(3, p);
  ASSERT_EQ(t.x_cuts().size(), 2u);
  EXPECT_LT(t.x_cuts()[0], t.x_cuts()[1]);
  const Tiles none = Tiles::balanced(4, {});
  EXPECT_LT(none.x_cuts()[0] - 1, none.x_cuts()[0]);
  EXPECT_GE(none.owner({0, 0}), 0);
}

// A robot with a laser, odometry with scale errors and a battery, in a
// room with a wall to see.
WorldDesc lone_robot() {
  WorldDesc w = test::room(4, 3);
  RobotDesc r = test::robot("r", {-2, 0, 0.3});
  r.rangers.push_back(test::laser(31, 3.0, 5.0));
  r.localization = Localization::Odom;
  r.odom_error = {0.2, 0.2, 0.2};
  r.power = {true, 1000, 1000, 2};
  w.robots.push_back(r);
  return w;
}

// Weaves for `steps` steps, from step `from` of the weave.
void drive(World& w, int steps, int from = 0) {
  for (int i = from; i < from + steps; ++i) {
    w.command(0, Command::velocity(0.4, 0, i % 20 < 10 ? 0.5 : -0.5));
    w.step();
  }
}

TEST(RobotState, AFreshWorldTakesUpASavedRobotAndStepsOnToTheSameBits) {
  World a(lone_robot(), Random(7));
  a.set_wanted({SensorKind::Ranger, 0}, true);
  a.set_controller_memory_size(0, 24);
  drive(a, 37);
  a.controller_memory(0)[5] = std::byte{0x5a};
  std::vector<std::byte> saved;
  a.save_robot(0, saved);

  // Another seed: its own odometry errors would differ; the saved ones win.
  World b(lone_robot(), Random(8));
  b.set_controller_memory_size(0, 24);
  std::span<const std::byte> in(saved);
  ASSERT_TRUE(b.restore_robot(0, in));
  EXPECT_TRUE(in.empty());
  EXPECT_TRUE(b.wanted({SensorKind::Ranger, 0}));
  EXPECT_EQ(b.controller_memory(0)[5], std::byte{0x5a});
  auto same = [&] {
    const RobotState &sa = a.state(0), &sb = b.state(0);
    EXPECT_EQ(sa.pose.x, sb.pose.x);
    EXPECT_EQ(sa.pose.a, sb.pose.a);
    EXPECT_EQ(sa.odometry.x, sb.odometry.x);
    EXPECT_EQ(sa.odometry.a, sb.odometry.a);
    EXPECT_EQ(a.power(0).joules, b.power(0).joules);
    const RangerView ra = a.ranger(0), rb = b.ranger(0);
    ASSERT_EQ(ra.ranges.size(), rb.ranges.size());
    for (size_t k = 0; k < ra.ranges.size(); ++k) EXPECT_EQ(ra.ranges[k], rb.ranges[k]) << k;
  };
  // The readings taken before the save travel too (a controller reads them
  // before the next step).
  same();
  // Both step on the same way.
  drive(a, 25, 37);
  drive(b, 25, 37);
  same();
  // Seed 8's own odometry errors give another estimate: b's came with the
  // robot.
  World c(lone_robot(), Random(8));
  drive(c, 62);
  EXPECT_EQ(c.state(0).pose.x, a.state(0).pose.x);
  EXPECT_NE(c.state(0).odometry.x, a.state(0).odometry.x);
}

TEST(RobotState, ShortOrForeignBytesAreRefusedAndChangeNothing) {
  World a(lone_robot(), Random(7));
  drive(a, 12);
  std::vector<std::byte> saved;
  a.save_robot(0, saved);
  World b(lone_robot(), Random(7));
  const Pose before = b.state(0).pose;
  for (size_t cut : {size_t(0), size_t(1), saved.size() / 2, saved.size() - 1}) {
    std::span<const std::byte> in(saved.data(), cut);
    EXPECT_FALSE(b.restore_robot(0, in)) << cut;
    EXPECT_EQ(b.state(0).pose.x, before.x) << cut;
  }
  // Controller memory of another size: not this world's robot.
  b.set_controller_memory_size(0, 8);
  std::span<const std::byte> in(saved);
  EXPECT_FALSE(b.restore_robot(0, in));
  EXPECT_EQ(b.state(0).pose.x, before.x);
}

TEST(RobotState, TheHaloCoversSensorsRadiiAndMoves) {
  WorldDesc d = lone_robot();
  World w(d, Random(1));
  // A 5 m laser at the centre, a 0.4 m square (radius 0.28 m), and 10 m/s
  // for 0.1 s.
  const double radius = std::hypot(0.2, 0.2);
  EXPECT_NEAR(w.interaction_reach(), 5.0 + 2 * radius + 3 * 10 * d.interval_sim, 1e-9);
  std::string why;
  EXPECT_TRUE(w.divisible(why));
  d.robots[0].grippers.emplace_back();
  EXPECT_FALSE(World(d, Random(1)).divisible(why));
  EXPECT_NE(why.find("grippers"), std::string::npos);
}

}  // namespace
}  // namespace troupe::sim
