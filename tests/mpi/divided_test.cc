// The real troupe-sim under mpirun, its world divided between 1 to 4
// processes (4 oversubscribed on a 2-core machine), against the same run in
// one process: the trajectory logs must be the same bytes. The worlds hold
// what a division can get wrong: robots colliding across a cut, a robot
// crossing a cut every step, a crowd on the corner where four regions meet,
// regions redrawn every few steps, and controllers whose memory travels.
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cstdlib>
#include <fstream>
#include <random>
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
    w << "  block ( points 4 point[0] [" << a << " " << a << "] point[1] [" << b << " " << a << "] point[2] ["
      << b << " " << b << "] point[3] [" << a << " " << b << "] )\n";
  }
  w << ")\n"
       "define sonar sensor ( range [ 0 3 ] fov 20 samples 1 )\n"
       "define ring ranger ( sonar ( pose [ 0.15 0 0 0 ] ) sonar ( pose [ 0 0.15 0 90 ] )\n"
       "  sonar ( pose [ -0.15 0 0 180 ] ) sonar ( pose [ 0 -0.15 0 270 ] ) )\n"
       "define bot position ( size [ 0.3 0.3 0.2 ] ring ( ) ctrl \"wander speed=0.6 turn=1.0 avoid=0.6\" )\n";
  int n = 0;
  for (int i = -4; i <= 4; ++i) {
    for (int j = -4; j <= 4; ++j) {
      w << "bot ( name \"w" << n << "\" pose [ " << 6.0 * i + 3 << " " << 6.0 * j + 3 << " 0 "
        << (n * 53) % 360 << " ] )\n";
      ++n;
    }
  }
  return w.str();
}

// 1,000 of swarm100.world's robots (its definitions, read from it, with
// fiducial finders of 2 m instead of 4 m: a thousand 4 m finders in a
// crowd cost 80 ms a step) in a walled 50 x 50 m hall, one in each cell of
// a 32 x 32 grid but the last 24, placed within their cells by a seeded
// generator: wandering and gathering in clusters. And one robot more,
// without sensors (swarm-clients drives none such), driving east at a
// steady 1 m/s along the empty strip by the north wall from x = -6 m: the
// cut between two ranks falls near x = 0 (at the robots' median x, within
// column 15 or 16 of the grid, |x| < 1.3 m), so it crosses within 8
// simulated seconds, whatever the swarm does.
std::string swarm1000_world() {
  std::string swarm = read_file(std::string(TROUPE_SOURCE_DIR) + "/examples/worlds/swarm100.world");
  const size_t from = swarm.find("define sonar "), to = swarm.find("swarmbot ( name");
  const std::string finder = "range_max 4 range_max_id 4";
  const size_t range = swarm.find(finder);
  if (from == std::string::npos || to == std::string::npos || range == std::string::npos) return "";
  swarm.replace(range, finder.size(), "range_max 2 range_max_id 2");
  std::ostringstream w;
  w << "resolution 0.02\ninterval_sim 100\n"
       "define wall model ( color \"gray30\" )\n"
       "wall ( name \"north\" size [ 50.4 0.2 1 ] pose [ 0 25.1 0 0 ] )\n"
       "wall ( name \"south\" size [ 50.4 0.2 1 ] pose [ 0 -25.1 0 0 ] )\n"
       "wall ( name \"east\" size [ 0.2 50 1 ] pose [ 25.1 0 0 0 ] )\n"
       "wall ( name \"west\" size [ 0.2 50 1 ] pose [ -25.1 0 0 0 ] )\n"
    << swarm.substr(from, to - from);
  const double cell = 50.0 / 32;  // m
  std::mt19937 rng(1000);
  std::uniform_real_distribution<double> within(-0.5, 0.5), heading(0, 360);
  for (int n = 0; n < 1000; ++n) {
    const double x = -25 + cell * (n % 32 + 0.5) + within(rng), y = -25 + cell * (n / 32 + 0.5) + within(rng);
    w << "swarmbot ( name \"b" << n << "\" pose [ " << x << " " << y << " 0 " << int(heading(rng))
      << " ] )\n";
  }
  // The last row holds 8 robots, all west of x = -12 m: the strip is empty.
  w << "position ( name \"crosser\" size [ 0.3 0.3 0.2 ] pose [ -6 24.6 0 0 ] velocity [ 1 0 0 0 ]\n"
       "  acceleration_bounds [ 0 0 0 0 0 0 0 0 ] velocity_bounds [ -1 1 0 0 0 0 -90 90 ] )\n";
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
    return run_under(ranks > 0 ? mpirun(ranks) : std::vector<std::string>{}, world, more, report);
  }
  // The same, started by `launcher` (an mpirun command line, or nothing).
  std::string run_under(const std::vector<std::string>& launcher, const std::string& world,
                        const std::vector<std::string>& more, std::string* report = nullptr) {
    const std::string log = dir_ + "/log" + std::to_string(++runs_) + ".csv";
    std::vector<std::string> argv = launcher;
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
  int runs_ = 0;
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
  // Redrawn by measured step time: wherever the cuts fall, the same bytes.
  const std::vector<std::string> timed = {"--quit-time",    "20",  "--rebalance-every", "3",
                                          "--rebalance-by", "time"};
  EXPECT_TRUE(run(world, 4, timed) == one) << "4 ranks, rebalanced by time: the logs differ";
  EXPECT_TRUE(run(world, 2, timed) == one) << "2 ranks, rebalanced by time: the logs differ";
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
  // One rank holds the whole map.
  std::string whole_report;
  EXPECT_TRUE(run(world, 1, more, &whole_report) == one) << "1 rank: the logs differ";
  const std::vector<double> whole = world_mb(whole_report);
  ASSERT_EQ(whole.size(), 1u) << whole_report;
  double largest_at_two = 0;
  for (int ranks : {2, 4}) {
    std::string report;
    EXPECT_TRUE(run(world, ranks, more, &report) == one) << ranks << " ranks: the logs differ";
    // Unserved, every rank, the leader too, holds its region's part of the
    // map and its surroundings (5.3 m of distance field and twice the
    // halo each way, on a 72 m map): well under the whole at 2 ranks, less
    // still at 4.
    const std::vector<double> mb = world_mb(report);
    ASSERT_EQ(mb.size(), size_t(ranks)) << report;
    const double largest = *std::max_element(mb.begin(), mb.end());
    EXPECT_LT(largest, 0.8 * whole[0]) << report;
    if (ranks == 2) largest_at_two = largest;
    if (ranks == 4) {
      EXPECT_LT(largest, 0.8 * largest_at_two) << report;
    }
  }
  // Drawing a snapshot (or served: the viewer draws from it), the leader
  // holds the whole map.
  std::string served;
  EXPECT_TRUE(run(world, 2, join(more, {"--snapshot", dir_ + "/whole.png"}), &served) == one);
  const std::vector<double> mb = world_mb(served);
  ASSERT_EQ(mb.size(), 2u) << served;
  EXPECT_EQ(mb[0], whole[0]) << served;
  EXPECT_LT(mb[1], 0.8 * whole[0]) << served;
}

TEST_F(Divided, WhatCannotBeDividedIsRefusedByEveryRankWithItsReason) {
  const std::string forage = std::string(TROUPE_SOURCE_DIR) + "/examples/worlds/forage.world";
  testing::ProgramResult r = testing::run_to_end(
      join(mpirun(2), {kSim, forage, "--no-serve", "--no-ctrl", "--quit-time", "1"}), kRefusalMs);
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
  ASSERT_TRUE(first.start({kSim, swarm, "--port", "0", "--no-view", "--paused"}, dir_, "first", error))
      << error;
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

// Two "machines" on this one: two network namespaces, each with its own
// loopback and one end of a veth pair (10.231.0.1 and .2), so the only way
// between them is TCP over the pair. mpirun runs in the first and starts
// its daemon in the second through a launch agent standing in for ssh.
// Removed (with the pair) when this object goes, whatever the test did.
class TwoMachines {
 public:
  static constexpr const char* kFirst = "10.231.0.1";
  static constexpr const char* kSecond = "10.231.0.2";

  ~TwoMachines() {
    for (const std::string& ns : made_) testing::run_to_end({"ip", "netns", "delete", ns}, kRunMs);
  }
  // False with the reason when this machine cannot make them (not root,
  // no CAP_SYS_ADMIN, no iproute2, no veth).
  bool make(const std::string& dir, std::string& why) {
    const std::string id = std::to_string(getpid());
    ns_[0] = "troupe-mpi-a-" + id;
    ns_[1] = "troupe-mpi-b-" + id;
    const std::string link[2] = {"trmpa" + id, "trmpb" + id};  // at most 15 characters
    for (const std::string& ns : ns_) {
      if (!ip({"netns", "add", ns}, why)) return false;
      made_.push_back(ns);
      if (!ip({"-n", ns, "link", "set", "lo", "up"}, why)) return false;
    }
    if (!ip({"link", "add", link[0], "type", "veth", "peer", "name", link[1]}, why)) return false;
    const char* address[2] = {kFirst, kSecond};
    for (int i = 0; i < 2; ++i) {
      if (!ip({"link", "set", link[i], "netns", ns_[i]}, why) ||
          !ip({"-n", ns_[i], "addr", "add", std::string(address[i]) + "/24", "dev", link[i]}, why) ||
          !ip({"-n", ns_[i], "link", "set", link[i], "up"}, why))
        return false;
    }
    // What mpirun runs for a remote host: ssh would hand the command line
    // to a shell there, so the agent does the same in that host's namespace.
    agent_ = dir + "/netns-agent.sh";
    std::ofstream(agent_) << "#!/bin/sh\n"
                          << "case \"$1\" in " << kSecond << ") ns=" << ns_[1] << " ;; *) ns=" << ns_[0]
                          << " ;; esac\nshift\nexec ip netns exec \"$ns\" sh -c \"$*\"\n";
    return chmod(agent_.c_str(), 0755) == 0 || (why = "cannot make " + agent_ + " executable", false);
  }
  // mpirun, run in the first namespace, placing one rank on each machine
  // and keeping both MPI's messages and its own control traffic on TCP
  // over the pair.
  std::vector<std::string> launcher() const {
    return {"ip",
            "netns",
            "exec",
            ns_[0],
            "env",
            "ASAN_OPTIONS=detect_leaks=0",  // as mpirun() above says
            MPIEXEC,
            "--host",
            std::string(kFirst) + ":1," + kSecond + ":1",
            "-np",
            "2",
            "--mca",
            "plm_rsh_agent",
            agent_,
            "--mca",
            "btl",
            "tcp,self",
            "--mca",
            "btl_tcp_if_include",
            "10.231.0.0/24",
            "--mca",
            "oob_tcp_if_include",
            "10.231.0.0/24"};
  }

 private:
  static bool ip(const std::vector<std::string>& args, std::string& why) {
    std::vector<std::string> argv = {"ip"};
    argv.insert(argv.end(), args.begin(), args.end());
    const testing::ProgramResult r = testing::run_to_end(argv, kRunMs);
    if (r.status == 0) return true;
    why = "ip";
    for (const std::string& a : args) why += " " + a;
    why += ": " + (r.err.empty() ? "exit status " + std::to_string(r.status) : r.err);
    return false;
  }

  std::string ns_[2];
  std::vector<std::string> made_;
  std::string agent_;
};

TEST_F(Divided, TwoMachinesOverTcpGiveTheSameBytesAsOneProcess) {
  TwoMachines machines;
  std::string why;
  if (!machines.make(dir_, why)) {
    GTEST_SKIP() << "network namespaces cannot be made here (needs root with CAP_SYS_ADMIN and iproute2): "
                 << why;
  }
  // Each rank sees only its own machine's network: the ranks really are apart.
  std::vector<std::string> argv = machines.launcher();
  for (const char* a : {"ip", "-o", "-4", "addr", "show"}) argv.push_back(a);
  const testing::ProgramResult where = testing::run_to_end(argv, kRunMs);
  ASSERT_EQ(where.status, 0) << where.err;
  EXPECT_NE(where.out.find(std::string("inet ") + TwoMachines::kFirst + "/"), std::string::npos) << where.out;
  EXPECT_NE(where.out.find(std::string("inet ") + TwoMachines::kSecond + "/"), std::string::npos)
      << where.out;

  const std::string world = std::string(TROUPE_SOURCE_DIR) + "/examples/worlds/swarm100.world";
  const std::vector<std::string> more = {"--quit-time", "30", "--rebalance-every", "25", "--profile"};
  const std::string one = run(world, 0, more);
  ASSERT_GT(one.size(), 100u * 300u * 20u);
  std::string report;
  EXPECT_TRUE(run_under(machines.launcher(), world, more, &report) == one) << "the logs differ";
  EXPECT_NE(report.find("2 ranks"), std::string::npos) << report;
  EXPECT_GT(migrations(report), 0) << report;
}

// Who a client session drives and reads: robots' names and one device.
struct Cast {
  std::string mover;    // driven, teleported across the cuts, driven on
  std::string left;     // driven on one side of the first cut
  std::string right;    // driven on the other side
  std::string watched;  // a device echoed once ("b50/fiducial:0")
};

// What a client sees of a world, paused and driven by the troupe CLI:
// commands to robots in different regions, steps, sensors read, a robot
// teleported across the cuts and driven on, a reset. Everything the CLI
// prints, in order.
std::string client_session(const std::string& host, const Cast& c) {
  const std::string troupe = std::string(TROUPE_BINARY_DIR) + "/bin/troupe";
  const std::string mover = c.mover + "/position2d:0", ranger = c.mover + "/ranger:0";
  const std::vector<std::vector<std::string>> session = {
      {"cmd", host, mover, "vel", "0.3", "0", "0.5"},
      {"cmd", host, c.left + "/position2d:0", "vel", "0.4", "0", "0"},
      {"cmd", host, c.right + "/position2d:0", "vel", "0.2", "0", "-0.3"},
      {"req", host, "simulation:0", "step", "30"},
      {"echo", host, mover, "--count", "1"},
      {"echo", host, ranger, "--count", "1"},
      {"echo", host, c.watched, "--count", "1"},
      {"req", host, "simulation:0", "setpose", c.mover, "-6.2", "6.5", "2.5"},
      {"req", host, "simulation:0", "getpose", c.mover},
      {"cmd", host, mover, "vel", "0.4", "0", "-0.2"},
      {"req", host, "simulation:0", "step", "40"},
      {"req", host, "simulation:0", "getpose", c.left},
      {"req", host, "simulation:0", "getpose", c.right},
      {"echo", host, mover, "--count", "1"},
      {"echo", host, ranger, "--count", "1"},
      {"req", host, "simulation:0", "reset"},
      {"req", host, "simulation:0", "step", "3"},
      {"req", host, "simulation:0", "getpose", c.mover},
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

// The port troupe-sim printed it listens on, as HOST:PORT on 127.0.0.1.
std::string served_at(const testing::ChildProcess& sim) {
  const std::string out = sim.out();
  const std::string at = out.substr(out.find("listening on ") + 13);
  return "127.0.0.1:" + std::to_string(std::atoi(at.c_str() + at.find(':') + 1));
}

// troupe-sim serving `world` paused on a free port, in `ranks` processes
// (0: without mpirun), with `options` added.
void serve(testing::ChildProcess& sim, const std::string& dir, const std::string& world, int ranks,
           const std::vector<std::string>& options) {
  std::vector<std::string> argv = ranks > 0 ? mpirun(ranks) : std::vector<std::string>{};
  for (const std::string& a : {kSim, world, std::string("--port"), std::string("0"), std::string("--no-view"),
                               std::string("--no-ctrl")})
    argv.push_back(a);
  argv.insert(argv.end(), options.begin(), options.end());
  std::string error;
  ASSERT_TRUE(sim.start(argv, dir, "sim" + std::to_string(ranks), error)) << error;
  ASSERT_TRUE(sim.wait_for("listening on ", false, kRunMs)) << sim.err();
}

// The session on `world` served by `ranks` processes.
std::string session_at(const std::string& dir, const std::string& world, int ranks, const Cast& cast) {
  testing::ChildProcess sim;
  serve(sim, dir, world, ranks, {"--paused"});
  if (::testing::Test::HasFatalFailure()) return "";
  const std::string seen = client_session(served_at(sim), cast);
  // mpirun passes the SIGTERM on and reports the job ended by a signal
  // (status 1); troupe-sim alone ends with 0. Neither hangs.
  EXPECT_EQ(sim.stop(), ranks > 0 ? 1 : 0) << sim.err();
  return seen;
}

TEST_F(Divided, ClientsSeeOneWorldOnOnePortAtAnyRankCount) {
  const std::string world = std::string(TROUPE_SOURCE_DIR) + "/examples/worlds/swarm100.world";
  const Cast cast{"b7", "b0", "b99", "b50/fiducial:0"};
  const std::string one = session_at(dir_, world, 0, cast);
  // The session did what it says: b7 was teleported, then drove on.
  EXPECT_NE(one.find("\"x\": -6.2"), std::string::npos) << one;
  EXPECT_NE(one.find("ranges="), std::string::npos) << one;
  for (int ranks : {2, 3}) EXPECT_EQ(session_at(dir_, world, ranks, cast), one) << ranks << " ranks";
}

// The same session with --log: what the leader's clients did (commands,
// steps, a teleport across the cuts, a reset) reaches the robots' processes
// as its journal, and the log, written by the leader from its mirror of
// every robot, is the same bytes as one process's. The run then goes on
// to its quit time unpaced and ends by itself.
std::string served_log_at(const std::string& dir, const std::string& world, int ranks, const Cast& cast) {
  const std::string log = dir + "/served" + std::to_string(ranks) + ".csv";
  testing::ChildProcess sim;
  serve(sim, dir, world, ranks, {"--paused", "--seed", "5", "--quit-time", "12", "--log", log});
  if (::testing::Test::HasFatalFailure()) return "";
  const std::string host = served_at(sim);
  client_session(host, cast);
  const std::string troupe = std::string(TROUPE_BINARY_DIR) + "/bin/troupe";
  for (const char* order : {"speed", "resume"}) {
    std::vector<std::string> argv = {troupe, "req", host, "simulation:0", order};
    if (std::string(order) == "speed") argv.push_back("0");
    const testing::ProgramResult r = testing::run_to_end(argv, kRunMs);
    EXPECT_EQ(r.status, 0) << order << ": " << r.err;
  }
  EXPECT_EQ(sim.wait_exit(kRunMs), 0) << sim.err();
  return read_file(log);
}

TEST_F(Divided, AServedRunLogsTheSameBytesAtOneTwoAndThreeRanksWhileClientsDriveIt) {
  const std::string world = std::string(TROUPE_SOURCE_DIR) + "/examples/worlds/swarm100.world";
  const Cast cast{"b7", "b0", "b99", "b50/fiducial:0"};
  const std::string one = served_log_at(dir_, world, 0, cast);
  // 73 steps of the session (30 + 40, a reset, 3), then to 12 s: 120.
  ASSERT_GT(one.size(), 100u * (73 + 120) * 20) << "a line per robot per step";
  // The commanded robots moved, and b7 was teleported: the log shows it.
  EXPECT_NE(one.find(",b7,-6.2"), std::string::npos) << "no teleport in the log";
  for (int ranks : {2, 3})
    EXPECT_TRUE(served_log_at(dir_, world, ranks, cast) == one) << ranks << " ranks: the logs differ";
}

// mpirun stopped by SIGTERM (what Ctrl-C's SIGINT does too) passes SIGTERM
// to every process: the run ends as one process's does. The leader stops,
// sends the others its Stop order, the division's table is printed with
// every process's row (it is collective: each ran its Stop), the log is
// whole, and the processes leave without waiting on mpirun (before, one
// of MPI's threads took the signal and each process died at once, table
// and log lost). mpirun itself reports a job it was told to stop with
// status 1, whatever its processes did; strace shows each exit with 0,
// but a wrapper writing their statuses would race mpirun, which kills
// what is left of the job as it ends.
TEST_F(Divided, StoppedBySigtermTheLeaderStopsEveryProcessAndPrintsItsTable) {
  const std::string world = std::string(TROUPE_SOURCE_DIR) + "/examples/worlds/swarm100.world";
  // The controllers' run, 25 steps, in one process to its quit time.
  const std::string one = run(world, 0, {"--quit-time", "2.5"});
  const std::string log = dir_ + "/stopped.csv";
  testing::ChildProcess sim;
  std::string error;
  ASSERT_TRUE(sim.start(join(mpirun(2), {kSim, world, "--port", "0", "--no-view", "--paused", "--seed", "5",
                                         "--log", log, "--profile"}),
                        dir_, "stopped", error))
      << error;
  ASSERT_TRUE(sim.wait_for("listening on ", false, kRunMs)) << sim.err();
  const testing::ProgramResult steps = testing::run_to_end(
      {std::string(TROUPE_BINARY_DIR) + "/bin/troupe", "req", served_at(sim), "simulation:0", "step", "25"},
      kRunMs);
  ASSERT_EQ(steps.status, 0) << steps.err;

  EXPECT_EQ(sim.stop(), 1) << sim.err();
  const std::string report = sim.err();
  EXPECT_NE(report.find("Terminated: stopping"), std::string::npos) << report;  // SIGTERM, as strsignal says
  EXPECT_NE(report.find("2 ranks"), std::string::npos) << "no division table: " << report;
  EXPECT_EQ(world_mb(report).size(), 2u) << report;
  EXPECT_NE(report.find("run: 25 steps"), std::string::npos) << report;
  EXPECT_TRUE(read_file(log) == one) << "the log is not the 25 steps one process logs";
}

// packed1000.world: 1,000 robots in one block 0.25 m apart, 12 sonars
// each; the first cut at 2 ranks falls at x = 0, between columns r19 and
// r20 of its rows of 40.
const std::string kPacked = std::string(TROUPE_SOURCE_DIR) + "/examples/worlds/packed1000.world";

TEST_F(Divided, AThousandRobotsServedByTwoRanksAnswerAsInOneProcess) {
  const Cast cast{"r7", "r19", "r20", "r999/ranger:0"};
  const std::string one = session_at(dir_, kPacked, 0, cast);
  EXPECT_NE(one.find("\"x\": -6.2"), std::string::npos) << one;
  EXPECT_EQ(session_at(dir_, kPacked, 2, cast), one);
}

// swarm-clients, one connection per robot, gathers a thousand robots in
// clusters while two ranks run them: every robot keeps answering at its
// address while robots move between the ranks. In lockstep (--steps): the
// world is stepped once every robot decided, so the run is the same
// however slow the machine (the sanitizer build included).
TEST_F(Divided, SwarmClientsDriveAThousandRobotsSplitOverTwoRanks) {
  const std::string world = write("swarm1000.world", swarm1000_world());
  // Paused until swarm-clients steps it; then run out to the quit time,
  // where the leader prints the division's table.
  testing::ChildProcess sim;
  serve(sim, dir_, world, 2, {"--paused", "--quit-time", "12", "--rebalance-every", "0", "--profile"});
  ASSERT_FALSE(HasFatalFailure());
  const std::string host = served_at(sim);
  const std::string troupe = std::string(TROUPE_BINARY_DIR) + "/bin/troupe";
  auto request = [&](const std::vector<std::string>& args) {
    std::vector<std::string> argv = {troupe};
    argv.insert(argv.end(), args.begin(), args.end());
    const testing::ProgramResult r = testing::run_to_end(argv, kRunMs);
    EXPECT_EQ(r.status, 0) << args[2] << ": " << r.err;
    return r.out;
  };

  testing::ChildProcess clients;
  std::string error;
  ASSERT_TRUE(clients.start({SWARM_CLIENTS, host, "--steps", "100"}, dir_, "clients", error)) << error;
  EXPECT_EQ(clients.wait_exit(kRunMs), 0) << clients.out() << clients.err();
  const std::string seen = clients.out();
  // Every robot's ranger delivered each step's scan to its client.
  EXPECT_NE(seen.find("1000 of 1000 robots decided at each of 100 steps"), std::string::npos) << seen;
  // They gathered: each robot is nearer its nearest neighbour.
  const size_t start = seen.find("mean distance at the start "), end = seen.find("mean distance at the end ");
  ASSERT_NE(start, std::string::npos) << seen;
  ASSERT_NE(end, std::string::npos) << seen;
  EXPECT_LT(std::stod(seen.substr(end + 25)), std::stod(seen.substr(start + 27))) << seen;

  // Addressed by name after the run, robots on both sides still answer.
  for (const char* robot : {"b0", "b7", "b500", "b999"}) {
    const std::string pose = request({"echo", host, std::string(robot) + "/position2d:0", "--count", "1"});
    EXPECT_NE(pose.find("pose="), std::string::npos) << robot << ": " << pose;
  }
  // Exactly 100 steps ran, and the crosser drove 10 m east, past the cut.
  const std::string crosser = request({"req", host, "simulation:0", "getpose", "crosser"});
  const size_t x = crosser.find("\"x\": ");
  ASSERT_NE(x, std::string::npos) << crosser;
  EXPECT_NEAR(std::stod(crosser.substr(x + 5)), 4.0, 1e-3) << crosser;
  request({"req", host, "simulation:0", "speed", "0"});
  request({"req", host, "simulation:0", "resume"});
  EXPECT_EQ(sim.wait_exit(kRunMs), 0) << sim.err();
  // Robots crossed the cut (the regions stay where they were drawn).
  EXPECT_GT(migrations(sim.err()), 0) << sim.err();
}

}  // namespace
}  // namespace troupe::sim
