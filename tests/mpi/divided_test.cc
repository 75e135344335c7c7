// The real troupe-sim under mpirun, its world divided between 1 to 4
// processes (4 oversubscribed on a 2-core machine), against the same run in
// one process: the trajectory logs must be the same bytes. The worlds hold
// what a division can get wrong: robots colliding across a cut, a robot
// crossing a cut every step, a crowd on the corner where four regions meet,
// regions redrawn every few steps, and controllers whose memory travels.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdlib>
#include <fstream>
#include <sstream>

#include "tests/support/child_process.h"

namespace troupe::sim {
namespace {

constexpr int kRunMs = 300000;  // bounds a hung run, not a requirement
// A refusal takes a few seconds; a rank left waiting would hang until this.
constexpr int kRefusalMs = 60000;

const std::string kSim = std::string(TROUPE_BINARY_DIR) + "/bin/troupe-sim";

std::string read_file(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

// Point-symmetric pairs (every robot at (x, y, a) has a twin at
// (-x, -y, a + 180)), so the first cuts fall exactly at x = 0 and y = 0.
std::string corner_world() {
  std::ostringstream w;
  w << "resolution 0.02\ninterval_sim 100\n"
       "model ( name \"walls\" size [16 16] obstacle_return 1\n"
       "  block ( points 4 point[0] [-8 -8] point[1] [8 -8] point[2] [8 -7.8] point[3] [-8 -7.8] )\n"
       "  block ( points 4 point[0] [-8 7.8] point[1] [8 7.8] point[2] [8 8] point[3] [-8 8] ) )\n"
       "define sonar sensor ( range [ 0 1.5 ] fov 20 samples 1 )\n"
       "define ring ranger ( sonar ( pose [ 0.1 0 0 0 ] ) sonar ( pose [ 0 0.1 0 90 ] )\n"
       "  sonar ( pose [ -0.1 0 0 180 ] ) sonar ( pose [ 0 -0.1 0 270 ] ) )\n"
       "define bot position ( size [ 0.25 0.25 0.2 ] ring ( ) )\n";
  // A crowd of wanderers on the corner where four regions meet.
  int n = 0;
  for (double x : {-0.45, -0.15, 0.15, 0.45}) {
    for (double y : {-0.45, -0.15, 0.15, 0.45}) {
      w << "bot ( name \"c" << n << "\" pose [ " << x << " " << y << " 0 " << (n * 47) % 360
        << " ] ctrl \"wander speed=0.3 turn=1.5 avoid=0.3\" )\n";
      ++n;
    }
  }
  // Two pairs driving head on across the x cut at a constant 0.5 m/s (no
  // acceleration: the start velocity is kept), until they meet and stall.
  const char* steady = "acceleration_bounds [ 0 0 0 0 0 0 0 0 ] velocity_bounds [ -1 1 0 0 0 0 -1800 1800 ]";
  w << "bot ( name \"h0\" pose [ -1.2 -4 0 0 ] velocity [ 0.5 0 0 0 ] " << steady << " )\n"
    << "bot ( name \"h1\" pose [ 1.2 -4 0 180 ] velocity [ 0.5 0 0 0 ] " << steady << " )\n"
    << "bot ( name \"h2\" pose [ 1.2 4 0 180 ] velocity [ 0.5 0 0 0 ] " << steady << " )\n"
    << "bot ( name \"h3\" pose [ -1.2 4 0 0 ] velocity [ 0.5 0 0 0 ] " << steady << " )\n";
  // Robots turning half a circle per step on a circle centred on the x cut:
  // each step ends on the other side of it.
  const double r = 0.5 / (3.14159265358979 / 0.1);  // m: 0.5 m/s at pi rad per 0.1 s
  w << "bot ( name \"x0\" pose [ " << r << " 6 0 90 ] velocity [ 0.5 0 0 1800 ] " << steady << " )\n"
    << "bot ( name \"x1\" pose [ " << -r << " -6 0 270 ] velocity [ 0.5 0 0 1800 ] " << steady << " )\n";
  return w.str();
}

// 72 x 72 m at 0.02 m (13 million cells: the map reads its coarse level,
// so a rank holds only its part): pillars every 6 m, 81 wanderers with
// sonar rings between them, mirrored so the first cuts fall at 0.
std::string large_world() {
  std::ostringstream w;
  w << "resolution 0.02\ninterval_sim 100\n"
       "model ( name \"hall\" size [72 72] obstacle_return 1 boundary 1\n";
  for (int i = -5; i <= 5; ++i) {
    for (int j = -5; j <= 5; ++j) {
      const double x = 6.0 * i, y = 6.0 * j;
      w << "  block ( points 4 point[0] [" << x - 0.4 << " " << y - 0.4 << "] point[1] [" << x + 0.4 << " "
        << y - 0.4 << "] point[2] [" << x + 0.4 << " " << y + 0.4 << "] point[3] [" << x - 0.4 << " "
        << y + 0.4 << "] )\n";
    }
  }
  // Stage fits a model's blocks to its size: blocks in the far corners
  // make that fit the identity.
  for (int c : {-1, 1}) {
    const double a = 36.0 * c, b = a - 0.2 * c;
    w << "  block ( points 4 point[0] [" << a << " " << a << "] point[1] [" << b << " " << a << "] point[2] [" << b
      << " " << b << "] point[3] [" << a << " " << b << "] )\n";
  }
  w << ")\n"
       "define sonar sensor ( range [ 0 3 ] fov 20 samples 1 )\n"
       "define ring ranger ( sonar ( pose [ 0.15 0 0 0 ] ) sonar ( pose [ 0 0.15 0 90 ] )\n"
       "  sonar ( pose [ -0.15 0 0 180 ] ) sonar ( pose [ 0 -0.15 0 270 ] ) )\n"
       "define bot position ( size [ 0.3 0.3 0.2 ] ring ( ) ctrl \"wander speed=0.6 turn=1.0 avoid=0.6\" )\n";
  int n = 0;
  for (int i = -4; i <= 4; ++i) {
    for (int j = -4; j <= 4; ++j) {
      w << "bot ( name \"w" << n << "\" pose [ " << 6.0 * i + 3 << " " << 6.0 * j + 3 << " 0 " << (n * 53) % 360
        << " ] )\n";
      ++n;
    }
  }
  return w.str();
}

// mpirun starting `ranks` processes, more than the cores if need be. In
// the sanitizer build LeakSanitizer stays off in them: OpenMPI's plugins
// allocate and unload themselves before it reports, so it cannot even name
// them; the same code run as one process (every test here runs that too)
// keeps its leak check.
std::vector<std::string> mpirun(int ranks) {
  return {"env", "ASAN_OPTIONS=detect_leaks=0", MPIEXEC, "--oversubscribe", "-np", std::to_string(ranks)};
}

std::vector<std::string> join(std::vector<std::string> a, const std::vector<std::string>& b) {
  a.insert(a.end(), b.begin(), b.end());
  return a;
}

class Divided : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = testing::make_temp_dir("troupe-mpi-");
    ASSERT_FALSE(dir_.empty());
    // OpenMPI refuses root unless told twice (CI runs as root).
    if (geteuid() == 0) {
      setenv("OMPI_ALLOW_RUN_AS_ROOT", "1", 1);
      setenv("OMPI_ALLOW_RUN_AS_ROOT_CONFIRM", "1", 1);
    }
  }
  void TearDown() override { testing::remove_tree(dir_); }

  // troupe-sim on `world` in `ranks` processes (0: without mpirun), its
  // log returned; `report` gets the division's table (--profile).
  std::string run(const std::string& world, int ranks, const std::vector<std::string>& more,
                  std::string* report = nullptr) {
    const std::string log = dir_ + "/log" + std::to_string(ranks) + ".csv";
    std::vector<std::string> argv;
    if (ranks > 0) argv = mpirun(ranks);
    for (const std::string& a : {kSim, world, std::string("--no-serve"), std::string("--fast"),
                                 std::string("--seed"), std::string("5"), std::string("--log"), log})
      argv.push_back(a);
    argv.insert(argv.end(), more.begin(), more.end());
    const testing::ProgramResult r = testing::run_to_end(argv, kRunMs);
    EXPECT_EQ(r.status, 0) << r.err;
    if (report) *report = r.err;
    return read_file(log);
  }
  std::string write(const std::string& name, const std::string& text) {
    const std::string path = dir_ + "/" + name;
    std::ofstream(path) << text;
    return path;
  }

  std::string dir_;
};

// How many robots the ranks handed over, from the division's table.
long migrations(const std::string& report) {
  const size_t table = report.find("rank  robots");
  if (table == std::string::npos) return -1;
  std::istringstream rows(report.substr(report.find('\n', table) + 1));
  long total = 0;
  std::string line;
  while (std::getline(rows, line)) {
    std::istringstream f(line);
    long rank, robots, migrated;
    double bytes, messages;
    if (!(f >> rank >> robots >> bytes >> messages >> migrated)) break;
    total += migrated;
  }
  return total;
}

TEST_F(Divided, TheSwarmWorldGivesTheSameBytesAtOneToFourRanks) {
  const std::string world = std::string(TROUPE_SOURCE_DIR) + "/examples/worlds/swarm100.world";
  const std::vector<std::string> more = {"--quit-time", "30", "--rebalance-every", "25", "--profile"};
  const std::string one = run(world, 0, more);
  ASSERT_GT(one.size(), 100u * 300u * 20u);  // a line per robot per step
  for (int ranks = 1; ranks <= 4; ++ranks) {
    std::string report;
    EXPECT_TRUE(run(world, ranks, more, &report) == one) << ranks << " ranks: the logs differ";
    if (ranks > 1) {
      EXPECT_GT(migrations(report), 0) << report;
    }
  }
}

TEST_F(Divided, CollisionsCrossingsAndACornerCrowdGiveTheSameBytes) {
  const std::string world = write("corner.world", corner_world());
  const std::vector<std::string> fixed = {"--quit-time", "20", "--rebalance-every", "0", "--profile"};
  const std::string one = run(world, 0, fixed);
  // The head-on pairs met and stalled: h0 never passed h1.
  std::istringstream lines(one);
  std::string line;
  double h0 = 0, h1 = 0;
  int met = 0;
  while (std::getline(lines, line)) {
    if (line.find(",h0,") != std::string::npos) h0 = std::stod(line.substr(line.find(",h0,") + 4));
    if (line.find(",h1,") != std::string::npos) {
      h1 = std::stod(line.substr(line.find(",h1,") + 4));
      ASSERT_LT(h0, h1) << line;
      met += h1 - h0 < 0.35 ? 1 : 0;  // 0.25 m robots stall touching
    }
  }
  EXPECT_GT(met, 100) << "the pair never met";
  for (int ranks = 2; ranks <= 4; ++ranks) {
    std::string report;
    EXPECT_TRUE(run(world, ranks, fixed, &report) == one) << ranks << " ranks: the logs differ";
    // x0 and x1 cross the x cut at 0 every one of the 200 steps (three
    // ranks cut at the thirds, not there).
    if (ranks != 3) {
      EXPECT_GE(migrations(report), 2 * 200) << report;
    }
  }
  // Regions redrawn every 3 steps, around where the robots now are.
  const std::vector<std::string> moving = {"--quit-time", "20", "--rebalance-every", "3"};
  EXPECT_TRUE(run(world, 4, moving) == one) << "4 ranks, rebalanced: the logs differ";
  EXPECT_TRUE(run(world, 3, moving) == one) << "3 ranks, rebalanced: the logs differ";
}

// World memory of each rank, from the division's table.
std::vector<double> world_mb(const std::string& report) {
  std::vector<double> mb;
  const size_t table = report.find("rank  robots");
  if (table == std::string::npos) return mb;
  std::istringstream rows(report.substr(report.find('\n', table) + 1));
  std::string line;
  while (std::getline(rows, line)) {
    std::istringstream f(line);
    double v[8];
    bool ok = true;
    for (double& x : v) ok = ok && bool(f >> x);
    if (!ok) break;
    mb.push_back(v[7]);
  }
  return mb;
}

TEST_F(Divided, RanksHoldTheirPartOfALargeMapAndSeeWhatTheWholeMapHolds) {
  const std::string world = write("large.world", large_world());
  const std::vector<std::string> more = {"--quit-time", "15", "--rebalance-every", "40", "--profile"};
  const std::string one = run(world, 0, more);
  for (int ranks : {2, 4}) {
    std::string report;
    EXPECT_TRUE(run(world, ranks, more, &report) == one) << ranks << " ranks: the logs differ";
    // The leader holds the whole map (it serves and draws it); each other
    // rank less than half of it at 2 ranks, less still at 4.
    const std::vector<double> mb = world_mb(report);
    ASSERT_EQ(mb.size(), size_t(ranks)) << report;
    for (int r = 1; r < ranks; ++r) EXPECT_LT(mb[size_t(r)], 0.75 * mb[0]) << report;
  }
}

TEST_F(Divided, WhatCannotBeDividedIsRefusedByEveryRankWithItsReason) {
  const std::string forage = std::string(TROUPE_SOURCE_DIR) + "/examples/worlds/forage.world";
  testing::ProgramResult r = testing::run_to_end(
      join(mpirun(2), {kSim, forage, "--no-serve", "--no-ctrl", "--quit-time", "1"}),
      kRefusalMs);
  EXPECT_EQ(r.status, 1) << "mpirun ends with its ranks' status, not killed on a hang";
  EXPECT_NE(r.err.find("cannot be divided"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("rigid"), std::string::npos) << r.err;
  // A log nobody can write stops every rank, not the first alone.
  const std::string swarm = std::string(TROUPE_SOURCE_DIR) + "/examples/worlds/swarm100.world";
  r = testing::run_to_end(join(mpirun(2), {kSim, swarm, "--no-serve", "--quit-time", "1", "--log",
                                           dir_ + "/no/such/folder/log.csv"}),
                          kRefusalMs);
  EXPECT_EQ(r.status, 1) << "mpirun ends with its ranks' status, not killed on a hang";
  EXPECT_NE(r.err.find("cannot write"), std::string::npos) << r.err;
  // So does a port already taken, which only the leader would have served.
  testing::ChildProcess first;
  std::string error;
  ASSERT_TRUE(first.start({kSim, swarm, "--port", "0", "--no-view", "--paused"}, dir_, "first", error)) << error;
  ASSERT_TRUE(first.wait_for("listening on ", false, kRunMs)) << first.err();
  const std::string out = first.out();
  const std::string at = out.substr(out.find("listening on ") + 13);
  const std::string port = std::to_string(std::atoi(at.c_str() + at.find(':') + 1));
  r = testing::run_to_end(join(mpirun(2), {kSim, swarm, "--port", port, "--no-view", "--quit-time", "1"}),
                          kRefusalMs);
  EXPECT_EQ(r.status, 1) << "mpirun ends with its ranks' status, not killed on a hang";
  EXPECT_NE(r.err.find("cannot serve on"), std::string::npos) << r.err;
  first.stop();
}

// What a client sees of swarm100.world, paused and driven by the troupe
// CLI: commands to robots in different regions, steps, sensors read, a
// robot teleported across the cuts and driven on, a reset. Everything the
// CLI prints, in order.
std::string client_session(const std::string& host) {
  const std::string troupe = std::string(TROUPE_BINARY_DIR) + "/bin/troupe";
  const std::vector<std::vector<std::string>> session = {
      {"cmd", host, "b7/position2d:0", "vel", "0.3", "0", "0.5"},
      {"cmd", host, "b0/position2d:0", "vel", "0.4", "0", "0"},
      {"cmd", host, "b99/position2d:0", "vel", "0.2", "0", "-0.3"},
      {"req", host, "simulation:0", "step", "30"},
      {"echo", host, "b7/position2d:0", "--count", "1"},
      {"echo", host, "b7/ranger:0", "--count", "1"},
      {"echo", host, "b50/fiducial:0", "--count", "1"},
      {"req", host, "simulation:0", "setpose", "b7", "-6.2", "6.5", "2.5"},
      {"req", host, "simulation:0", "getpose", "b7"},
      {"cmd", host, "b7/position2d:0", "vel", "0.4", "0", "-0.2"},
      {"req", host, "simulation:0", "step", "40"},
      {"req", host, "simulation:0", "getpose", "b0"},
      {"req", host, "simulation:0", "getpose", "b99"},
      {"echo", host, "b7/position2d:0", "--count", "1"},
      {"echo", host, "b7/ranger:0", "--count", "1"},
      {"req", host, "simulation:0", "reset"},
      {"req", host, "simulation:0", "step", "3"},
      {"req", host, "simulation:0", "getpose", "b7"},
  };
  std::string out;
  for (const std::vector<std::string>& args : session) {
    std::vector<std::string> argv = {troupe};
    argv.insert(argv.end(), args.begin(), args.end());
    const testing::ProgramResult r = testing::run_to_end(argv, kRunMs);
    out += "$ troupe " + args[0] + " " + args[2] + "\n" + r.out + r.err;
    EXPECT_EQ(r.status, 0) << args[0] << " " << args[2] << ": " << r.err;
  }
  return out;
}

TEST_F(Divided, ClientsSeeOneWorldOnOnePortAtAnyRankCount) {
  const std::string world = std::string(TROUPE_SOURCE_DIR) + "/examples/worlds/swarm100.world";
  std::string one;
  for (int ranks : {0, 2, 3}) {
    std::vector<std::string> argv;
    if (ranks > 0) argv = mpirun(ranks);
    for (const char* a : {"--port", "0", "--no-view", "--paused", "--no-ctrl"}) argv.push_back(a);
    argv.insert(argv.begin() + (ranks > 0 ? 6 : 0), {kSim, world});
    testing::ChildProcess sim;
    std::string error;
    ASSERT_TRUE(sim.start(argv, dir_, "sim" + std::to_string(ranks), error)) << error;
    ASSERT_TRUE(sim.wait_for("listening on ", false, kRunMs)) << sim.err();
    const std::string out = sim.out();
    const std::string at = out.substr(out.find("listening on ") + 13);
    const std::string host = "127.0.0.1:" + std::to_string(std::atoi(at.c_str() + at.find(':') + 1));
    const std::string seen = client_session(host);
    // mpirun passes the SIGTERM on and reports the job ended by a signal
    // (status 1); troupe-sim alone ends with 0. Neither hangs.
    EXPECT_EQ(sim.stop(), ranks > 0 ? 1 : 0) << sim.err();
    if (ranks == 0) {
      one = seen;
      // The session did what it says: b7 was teleported, then drove on.
      EXPECT_NE(one.find("\"x\": -6.2"), std::string::npos) << one;
      EXPECT_NE(one.find("ranges="), std::string::npos) << one;
      continue;
    }
    EXPECT_EQ(seen, one) << ranks << " ranks";
  }
}

}  // namespace
}  // namespace troupe::sim
