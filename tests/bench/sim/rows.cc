#include "tests/bench/sim/rows.h"

#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <random>
#include <vector>

#include "host-sim/sim/controller_host.h"
#include "host-sim/sim/loader.h"
#include "host-sim/sim/static_map.h"
#include "host-sim/sim/world.h"
#include "tests/bench/sim/arena.h"

namespace troupe::bench {
namespace {

using sim::ControllerHost;
using sim::World;

double cpu_s() {
  timespec ts{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return double(ts.tv_sec) + ts.tv_nsec * 1e-9;
}
double wall_s() {
  return sim::now_ns() * 1e-9;
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v.empty() ? 0 : v[v.size() / 2];
}

std::string shared(const std::string& file) {
  return std::string(TROUPE_SHARED_DATA) + "/stage/" + file;
}

bool have_shared(const char* row) {
  if (std::filesystem::exists(shared("simple.world"))) return true;
  std::printf("%s: skipped, no Stage data at %s\n", row, shared("").c_str());
  return false;
}

// Loads a world file as World::load does (seed 1), its static map kept as
// `storage` says.
std::unique_ptr<World> load(const std::string& path, ControllerHost& host, sim::MapStorage storage) {
  world::Diagnostics d;
  sim::WorldDesc desc;
  std::unique_ptr<World> w;
  if (sim::load_world_file(path, desc, d)) {
    desc.map_storage = storage;
    w = std::make_unique<World>(desc, sim::Random(1));
  }
  ControllerHost::Options o;
  o.search_path = {TROUPE_PLUGIN_DIR};
  if (!w || !host.load(*w, o, d)) {
    std::printf("cannot load %s:\n%s", path.c_str(), d.str().c_str());
    return nullptr;
  }
  return w;
}

void want_all_rangers(World& w) {
  for (sim::RobotId i = 0; i < w.robot_count(); ++i) {
    const sim::IndexRange r = w.robot(i).rangers;
    for (uint32_t k = r.first; k < r.first + r.count; ++k) w.set_wanted({sim::SensorKind::Ranger, k}, true);
  }
}

// Runs `repeats` chunks of `steps`; the medians go into `out`, and one more
// chunk with per-cell ray casting gives the same-run baseline.
void run_chunks(World& w, ControllerHost& host, int steps, const Settings& s, Summary& out) {
  for (int i = 0; i < 5; ++i) {
    host.update(w);
    w.step();
  }
  w.profile().reset();
  std::vector<double> cpu, wall;
  for (int r = 0; r < s.repeats; ++r) {
    const double c0 = cpu_s(), w0 = wall_s(), t0 = w.time();
    for (int i = 0; i < steps; ++i) {
      host.update(w);
      w.step();
    }
    cpu.push_back((w.time() - t0) / (cpu_s() - c0));
    wall.push_back((w.time() - t0) / (wall_s() - w0));
  }
  std::printf("%s", w.profile().table().c_str());
  out.rtf = median(cpu);
  out.rtf_wall = median(wall);
  if (s.baseline) {
    w.set_raycast_per_cell(true);
    const double c0 = cpu_s(), t0 = w.time();
    for (int i = 0; i < steps; ++i) {
      host.update(w);
      w.step();
    }
    out.baseline_rtf = (w.time() - t0) / (cpu_s() - c0);
    w.set_raycast_per_cell(false);
  }
}

// World-file lines of ring robots (arena.h's smallbot) at `poses`, named
// r0, r1, ..., wandering.
std::string wandering_smallbots(const std::vector<sim::Pose>& poses) {
  std::string text;
  for (size_t i = 0; i < poses.size(); ++i) {
    char line[200];
    std::snprintf(line, sizeof line,
                  "smallbot ( name \"r%zu\" pose [ %.3f %.3f 0 %.1f ] ctrl \"wander avoid=0.4\" )\n", i,
                  poses[i].x, poses[i].y, poses[i].a * 180 / sim::kPi);
    text += line;
  }
  return text;
}

// Writes a world's text as `dir`/`name`; its path.
std::string write_text(const std::string& dir, const char* name, const std::string& text) {
  const std::string path = (std::filesystem::path(dir) / name).string();
  std::ofstream(path, std::ios::binary) << text;
  return path;
}

// The cave of simple.world with `n` Pioneers (laser and sonars) wandering.
std::string cave_world(const Scratch& dir, int n) {
  world::GrayImage cave;
  std::string err;
  world::read_png(shared("bitmaps/cave.png"), cave, err);
  std::vector<sim::Pose> poses = place(cave, 16.0 / 500, size_t(n), 0.35, 0.9, 11);
  std::string text;
  for (const char* inc : {"pioneer.inc", "map.inc", "sick.inc"}) text += "include \"" + shared(inc) + "\"\n";
  text += "resolution 0.02\ninterval_sim 100\n";
  text += "floorplan ( name \"cave\" size [16 16 0.8] pose [0 0 0 0] bitmap \"" + shared("bitmaps/cave.png") +
          "\" )\n";
  for (size_t i = 0; i < poses.size(); ++i) {
    char line[256];
    std::snprintf(
        line, sizeof line,
        "pioneer2dx ( name \"r%zu\" pose [ %.3f %.3f 0 %.1f ] sicklaser ( pose [ 0 0 0 0 ] ) ctrl \"wander\" "
        "localization \"gps\" )\n",
        i, poses[i].x, poses[i].y, poses[i].a * 180 / sim::kPi);
    text += line;
  }
  return dir.write("cave.world", text);
}

}  // namespace

bool row_simple(const Settings& s, Summary& out) {
  if (!have_shared("simple")) return false;
  out = {"simple.world", "2 Pioneers, 180-beam 8 m lasers, wander", 0, 0, 0, 440, 5000};
  ControllerHost host;
  auto w = load(shared("simple.world"), host, s.storage);
  if (!w) return false;
  std::printf("== simple.world: %zu robots, %zu controllers\n", w->robot_count(), host.size());
  run_chunks(*w, host, int(10000 * s.scale), s, out);
  return true;
}

bool row_crowd(const Settings& s, Summary& out) {
  out = {"crowd 1000", "1,000 robots, 12-beam 2 m rangers, 140 x 60 m at 0.02 m", 0, 0, 0, 3, 30};
  Scratch dir;
  const double t0 = wall_s();
  world::GrayImage map = office(140, 60, 0.02, 7);
  std::string err;
  if (!world::write_png(dir.path("office.png"), map, err)) {
    std::printf("crowd: %s\n", err.c_str());
    return false;
  }
  std::vector<sim::Pose> poses = place(map, 0.02, 1000, 0.3, 0.8, 3);
  std::string text = "resolution 0.02\ninterval_sim 100\n" + ring_robot_define();
  text += "model ( name \"office\" size [140 60 1] color \"gray30\" bitmap \"office.png\" )\n";
  text += wandering_smallbots(poses);
  map = {};
  const double t1 = wall_s();
  ControllerHost host;
  auto w = load(dir.write("crowd.world", text), host, s.storage);
  if (!w) return false;
  out.load_s = wall_s() - t1;
  std::printf("== crowd: %zu robots; map generated in %.1f s, world loaded in %.1f s; engine holds %.1f MB\n",
              w->robot_count(), t1 - t0, wall_s() - t1, w->memory_bytes() / 1e6);
  run_chunks(*w, host, int(200 * s.scale), s, out);
  return true;
}

std::string write_campus(const std::string& dir, std::string& err) {
  // 2,000 x 1,400 px, half a metre each, scaled by the floorplan's size to
  // 50,000 x 35,000 cells of 0.02 m, as Stage's large.world scales its
  // campus bitmap.
  const world::GrayImage map = campus(2000, 1400, 17);
  const std::string png = (std::filesystem::path(dir) / "campus.png").string();
  if (!world::write_png(png, map, err)) return "";
  std::vector<sim::Pose> poses = place(map, 0.5, 1000, 0.3, 0.8, 4);
  std::string text =
      "# A campus-sized world (Stage's large.world layout), written by sim_bench --write-campus.\n"
      "resolution 0.02\ninterval_sim 100\n" +
      ring_robot_define();
  text +=
      "model ( name \"campus\" size [1000 700 1] color \"gray30\" obstacle_return 1 bitmap \"campus.png\" "
      ")\n";
  return write_text(dir, "campus.world", text + wandering_smallbots(poses));
}

bool row_campus(const Settings& s, Summary& out) {
  out = {"campus 1000", "1,000 robots, 12-beam 2 m rangers, 1,000 x 700 m at 0.02 m", 0, 0, 0, 0, 0};
  Scratch dir;
  std::string err;
  const std::string path = write_campus(dir.path(""), err);
  if (path.empty()) {
    std::printf("campus: %s\n", err.c_str());
    return false;
  }
  const double c0 = cpu_s(), t0 = wall_s();
  ControllerHost host;
  auto w = load(path, host, s.storage);
  if (!w) return false;
  out.load_s = wall_s() - t0;
  const sim::StaticMap& map = w->map();
  std::printf(
      "== campus: %zu robots; %d x %d cells (%.2f billion), %s; loaded in %.1f s (%.1f CPU s); engine holds "
      "%.0f MB, the map %.0f MB\n",
      w->robot_count(), map.width(), map.height(), double(map.width()) * map.height() * 1e-9,
      map.sparse() ? "sparse" : "dense", out.load_s, cpu_s() - c0, w->memory_bytes() / 1e6,
      map.memory_bytes() / 1e6);
  run_chunks(*w, host, int(200 * s.scale), s, out);
  return true;
}

std::string write_scale_world(const std::string& dir, int robots, std::string& err) {
  // The scale row's world, written out: 8.4 m^2 of office per robot (so
  // the map grows with the swarm), 7:3 wide, the ring robots wandering. The
  // loader reads bitmaps of at most 2^28 pixels, so the office is drawn at
  // 0.1 m a pixel (its 0.1 m walls a pixel thick) and the model's size
  // scales it onto the world's 0.05 m cells.
  constexpr double kPx = 0.1;  // m per bitmap pixel
  const double area = 8.4 * robots, width = std::sqrt(area * 7 / 3), height = area / width;
  std::vector<sim::Pose> poses;
  {
    const world::GrayImage map = office(width, height, kPx, 5);
    const std::string png = (std::filesystem::path(dir) / "office.png").string();
    if (!world::write_png(png, map, err)) return "";
    poses = place(map, kPx, size_t(robots), 0.3, 0.8, 9);
  }
  char head[256];
  std::snprintf(head, sizeof head,
                "# %d robots, 8.4 m^2 of office each: sim_bench's scale rows as a world file, written by\n"
                "# sim_bench --write-scale DIR.\nresolution 0.05\ninterval_sim 100\n",
                robots);
  std::string text = head + ring_robot_define();
  char floor[160];
  std::snprintf(floor, sizeof floor,
                "model ( name \"office\" size [%.3f %.3f 1] color \"gray30\" bitmap \"office.png\" )\n",
                width, height);
  return write_text(dir, "office.world", text + floor + wandering_smallbots(poses));
}

bool row_scale100k(const Settings& s, Summary& out) {
  out = {"scale 100000", "100,000 robots, 12-beam 2 m rangers, 0.05 m office (1,400 x 600 m)", 0, 0, 0, 0, 1};
  Scratch dir;
  // Written by a child process, so this one's peak memory is the
  // simulation's, not the bitmap's and the placement's.
  std::fflush(stdout);
  const pid_t pid = fork();
  if (pid == 0) {
    std::string err;
    const bool ok = !write_scale_world(dir.path(""), 100000, err).empty();
    if (!ok) std::printf("scale100k: %s\n", err.c_str());
    std::fflush(stdout);
    _exit(ok ? 0 : 1);
  }
  int status = 1;
  if (pid < 0 || waitpid(pid, &status, 0) != pid || !WIFEXITED(status) || WEXITSTATUS(status) != 0)
    return false;
  const double c0 = cpu_s(), t0 = wall_s();
  ControllerHost host;
  auto w = load(dir.path("office.world"), host, s.storage);
  if (!w) return false;
  out.load_s = wall_s() - t0;
  const sim::StaticMap& map = w->map();
  std::printf(
      "== scale100k: %zu robots; %d x %d cells (%.0f million), %s; loaded in %.1f s (%.1f CPU s); engine "
      "holds "
      "%.0f MB, the map %.0f MB\n",
      w->robot_count(), map.width(), map.height(), double(map.width()) * map.height() * 1e-6,
      map.sparse() ? "sparse" : "dense", out.load_s, cpu_s() - c0, w->memory_bytes() / 1e6,
      map.memory_bytes() / 1e6);
  // 10 steps a chunk, as the scale row's 10,000 robots.
  Settings chunks = s;
  chunks.baseline = false;  // the per-cell walk would take minutes here
  run_chunks(*w, host, 10, chunks, out);
  return true;
}

bool row_packed(const Settings& s, Summary& out) {
  out = {"packed 1000", "1,000 robots 0.25 m apart in one block, 12-beam 2 m rangers", 0, 0, 0, 0, 30};
  // Stage's own 1,000-robot benchmark start (examples/worlds/packed_world.py
  // writes it): the crowd row's sensors, packed so every beam has a few
  // hundred robots within its reach. The load is part of the figure the
  // issue sets the target on: a run of a minute of simulated time, from
  // reading the file to the last step.
  const double c0 = cpu_s();
  ControllerHost host;
  auto w = load(std::string(TROUPE_SOURCE_DIR) + "/examples/worlds/packed1000.world", host, s.storage);
  if (!w) return false;
  const double load_cpu = cpu_s() - c0;
  std::printf("== packed: %zu robots; world loaded in %.2f CPU s; engine holds %.1f MB\n", w->robot_count(),
              load_cpu, w->memory_bytes() / 1e6);
  run_chunks(*w, host, int(200 * s.scale), s, out);
  constexpr double kRun = 60;  // s of simulated time
  std::printf("a %.0f s run, load included: %.1f sim s per CPU s (target 30)\n", kRun,
              kRun / (load_cpu + kRun / out.rtf));
  return true;
}

bool row_cave(const Settings& s, Summary& out) {
  if (!have_shared("cave")) return false;
  out = {"cave 100", "100 Pioneers, 180-beam 8 m laser + 16 sonars, cave", 0, 0, 0, 2, 20};
  Scratch dir;
  ControllerHost host;
  auto w = load(cave_world(dir, 100), host, s.storage);
  if (!w) return false;
  want_all_rangers(*w);  // the sonars too, as a client reading them would
  std::printf("== cave: %zu robots\n", w->robot_count());
  run_chunks(*w, host, int(100 * s.scale), s, out);
  return true;
}

bool row_scale(const Settings& s, Summary& out) {
  out = {"scale 10000", "10,000 robots, 12-beam rangers (0.05 m map)", 0, 0, 0, 0, 3};
  std::printf("== scaling: 8.4 m^2 of office per robot, 0.05 m cells, wander\n");
  std::printf("%8s %12s %8s %12s %14s %10s\n", "robots", "map cells", "steps", "sim s/CPU s", "us/robot-step",
              "vs 100");
  double first = 0, worst = 1, best = 1;
  for (int n : {100, 300, 1000, 3000, 10000}) {
    const double area = 8.4 * n, width = std::sqrt(area * 7 / 3), height = area / width;
    sim::WorldDesc d;
    d.resolution = 0.05;
    sim::StaticDesc floor;
    floor.name = "office";
    floor.size = {width, height};
    floor.bitmap = std::make_shared<sim::BitmapDesc>();
    auto img = std::make_shared<world::GrayImage>(office(width, height, 0.05, 5));
    std::vector<sim::Pose> poses = place(*img, 0.05, size_t(n), 0.3, 0.8, 9);
    floor.bitmap->image = img;
    d.statics.push_back(floor);
    for (size_t i = 0; i < poses.size(); ++i) {
      std::string name = "r";  // appended: GCC 12 warns falsely (-Wrestrict) on "r" + std::string
      name.append(std::to_string(i));
      d.robots.push_back(ring_robot(name, poses[i], "wander avoid=0.4"));
    }
    d.map_storage = s.storage;
    World w(d, sim::Random(1));
    ControllerHost host;
    world::Diagnostics diags;
    ControllerHost::Options o;
    o.search_path = {TROUPE_PLUGIN_DIR};
    if (!host.load(w, o, diags)) {
      std::printf("%s", diags.str().c_str());
      return false;
    }
    Settings one = s;
    one.baseline = false;
    one.repeats = 3;
    Summary r;
    const int steps = std::max(10, int(40000.0 / n * s.scale));
    std::printf("-- %d robots\n", n);
    run_chunks(w, host, steps, one, r);
    const double us = 1e6 * w.interval() / r.rtf / double(w.robot_count());
    if (first == 0) first = us;
    worst = std::max(worst, us / first);
    best = std::min(best, us / first);
    std::printf("%8zu %12lld %8d %12.1f %14.2f %9.2fx\n", w.robot_count(),
                static_cast<long long>(w.map().width()) * w.map().height(), steps * 3, r.rtf, us, us / first);
    if (n == 10000) {
      out.rtf = r.rtf;
      out.rtf_wall = r.rtf_wall;
    }
  }
  std::printf("time per robot-step from 100 to 10,000 robots: within %.2fx (target 1.5x)\n", worst / best);
  return true;
}

bool row_rays(const Settings& s, Summary& out) {
  if (!have_shared("rays")) return false;
  out = {"rays", "cave, 100 robots present", 0, 0, 0, 0, 0};
  Scratch dir;
  ControllerHost host;
  auto w = load(cave_world(dir, 100), host, s.storage);
  if (!w) return false;
  for (int i = 0; i < 20; ++i) {
    host.update(*w);
    w->step();
  }
  // (a) The static grid alone: a laser's 180 beams from each robot, turned
  // by a random angle, 8 m.
  const sim::StaticMap& map = w->map();
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> ang(-sim::kPi, sim::kPi);
  std::vector<sim::RayQuery> rays;
  for (int round = 0; round < int(20 * s.scale) + 1; ++round) {
    for (sim::RobotId i = 0; i < w->robot_count(); ++i) {
      const sim::Pose& p = w->state(i).pose;
      const double a0 = ang(rng);
      for (int b = 0; b < 180; ++b) {
        const double a = a0 + b * sim::kPi / 179;
        rays.push_back({{p.x, p.y}, {std::cos(a), std::sin(a)}, 8.0f});
      }
    }
  }
  std::vector<float> r1(rays.size()), r2(rays.size());
  std::vector<double> fast, slow;
  for (int rep = 0; rep < s.repeats; ++rep) {
    double c0 = cpu_s();
    map.cast_batch(rays, sim::StaticMap::kRangerMask, r1.data());
    fast.push_back(rays.size() / (cpu_s() - c0));
    c0 = cpu_s();
    for (size_t i = 0; i < rays.size(); ++i) r2[i] = map.cast_per_cell(rays[i].origin, rays[i].dir, 8.0f);
    slow.push_back(rays.size() / (cpu_s() - c0));
  }
  size_t same = 0;
  for (size_t i = 0; i < rays.size(); ++i) same += std::fabs(r1[i] - r2[i]) < 1e-4;
  std::printf("== rays: %zu rays from 100 robots' poses in the cave, 8 m\n", rays.size());
  std::printf("%-34s %12s %10s\n", "", "Mrays/s", "vs per-cell");
  std::printf("%-34s %12.2f %9.2fx\n", "static grid, per-cell walk", median(slow) * 1e-6, 1.0);
  std::printf("%-34s %12.2f %9.2fx\n", "static grid, distance-field march", median(fast) * 1e-6,
              median(fast) / median(slow));
  std::printf("same range as the per-cell walk: %.4f%% of rays\n", 100.0 * same / rays.size());
  // (b) Whole ranger updates with the robots in the beams: lasers and sonars.
  want_all_rangers(*w);
  size_t beams = 0;
  for (sim::RobotId i = 0; i < w->robot_count(); ++i) {
    const sim::IndexRange r = w->robot(i).rangers;
    for (uint32_t k = r.first; k < r.first + r.count; ++k) beams += w->ranger(k).ranges.size();
  }
  std::vector<double> full, full_slow;
  for (int rep = 0; rep < s.repeats; ++rep) {
    const int calls = int(50 * s.scale) + 1;
    double c0 = cpu_s();
    for (int c = 0; c < calls; ++c) w->refresh_sensors();
    full.push_back(double(beams) * calls / (cpu_s() - c0));
    w->set_raycast_per_cell(true);
    c0 = cpu_s();
    for (int c = 0; c < calls; ++c) w->refresh_sensors();
    full_slow.push_back(double(beams) * calls / (cpu_s() - c0));
    w->set_raycast_per_cell(false);
  }
  std::printf("%-34s %12.2f %9.2fx\n", "rangers with robots, per-cell walk", median(full_slow) * 1e-6, 1.0);
  std::printf("%-34s %12.2f %9.2fx\n", "rangers with robots, march", median(full) * 1e-6,
              median(full) / median(full_slow));
  out.rtf = median(fast) * 1e-6;
  out.baseline_rtf = median(slow) * 1e-6;
  return true;
}

}  // namespace troupe::bench
