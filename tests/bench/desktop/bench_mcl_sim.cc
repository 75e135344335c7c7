// MCL accuracy on troupe-sim's own engine: the simulator's laser, its
// drifting odometry (odom_error) and its wander controller, run in-process,
// feeding the particle filter the mcl driver runs. Two worlds:
//
//  - Stage's cave (TROUPE_SHARED_DATA/stage/bitmaps/cave.png, 16 x 16 m, as
//    simple.world lays it out; skipped when the data is absent), with a
//    Pioneer-like robot written here;
//  - the project's examples/worlds/office.world (the offload example).
//
//   bench_mcl_sim [--seeds N] [--seconds S] [--odom-error E] [--motion-noise A] [--sigma-hit M]
//                 [--surface-field]
//
// Per seed: pose tracking from the start pose (mean and largest position
// error, mean heading error, over every step) and global localization
// (seconds of motion until the error stays under 0.25 m to the end).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "drivers/common_desktop/occupancy_grid.h"
#include "drivers/common_desktop/particle_filter.h"
#include "host-sim/sim/controller_host.h"
#include "host-sim/sim/world.h"
#include "tests/support/build_tree.h"
#include "wire/cli/args.h"

using namespace troupe;
using desktop::kPi;

namespace {

struct Scene {
  std::string name;
  std::string world_path;             // a world file
  std::string map_png;                // its floor plan
  double resolution = 0;              // m per pixel
  double origin_x = 0, origin_y = 0;  // the image's bottom-left corner, m
  bool wall_border = false;           // the floor plan has boundary 1
};

struct Run {
  double mean_m = 0, max_m = 0, mean_deg = 0;
  double lock_s = -1;    // global: s until the error stays under 0.25 m; -1: never
  double said_lost = 0;  // share of the steps after which the filter said it was lost
};

double odom_error = 0.05;  // the robots' odom_error, each axis (x, y, heading)
double motion_noise = -1;  // all four alphas; < 0: the driver's defaults
double sigma_hit = -1;     // m; < 0: the driver's default
bool surface_field = false;

// A Pioneer-like robot in Stage's cave, as simple.world places r0, with
// sick.inc's laser and drifting odometry.
bool write_cave_world(const std::string& dir, const std::string& png, std::string& path) {
  path = dir + "/cave_mcl.world";
  std::ofstream out(path);
  out << "resolution 0.02\ninterval_sim 100\nquit_time 0\n"
      << "define floorplan model ( color \"gray30\" boundary 1 obstacle_return 1 ranger_return 1 )\n"
      << "floorplan ( name \"cave\" size [16 16 0.8] pose [0 0 0 0] bitmap \"" << png << "\" )\n"
      << "define laser ranger ( sensor ( range [0 8.0] fov 180 samples 180 noise [0.0001 0 0] ) "
         "size [0.156 0.155 0.19] )\n"
      << "define pioneer position ( size [0.44 0.38 0.22] drive \"diff\" localization \"odom\" "
      << "odom_error [" << odom_error << " " << odom_error << " 0 " << odom_error << "] "
      << "velocity_bounds [-0.5 0.5 0 0 0 0 -90 90] acceleration_bounds [-1 1 0 0 0 0 -180 180] "
      << "laser ( pose [0.13 0 0 0] ) )\n"
      << "pioneer ( name \"r0\" pose [-6.946 -6.947 0 45] ctrl \"wander speed=0.4 turn=1.0 avoid=0.6 "
         "ranger=0\" )\n";
  return bool(out);
}

// office.world with this run's odometry error.
bool write_office_world(const std::string& dir, std::string& path) {
  std::ifstream in(std::string(TROUPE_SOURCE_DIR) + "/examples/worlds/office.world");
  std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  size_t at = text.find("odom_error [ 0.03 0.03 0 0.05 ]");
  if (at == std::string::npos) return false;
  char e[96];
  std::snprintf(e, sizeof e, "odom_error [ %g %g 0 %g ]", odom_error, odom_error, odom_error);
  text.replace(at, std::strlen("odom_error [ 0.03 0.03 0 0.05 ]"), e);
  size_t bm = text.find("\"bitmaps/office.png\"");
  if (bm == std::string::npos) return false;
  // Appended piecewise: GCC 12 warns falsely (-Wrestrict) about "x" + string.
  std::string bitmap(1, '"');
  bitmap += TROUPE_SOURCE_DIR;
  bitmap += "/examples/worlds/bitmaps/office.png\"";
  text.replace(bm, std::strlen("\"bitmaps/office.png\""), bitmap);
  path = dir + "/office_mcl.world";
  std::ofstream(path) << text;
  return true;
}

Run run(const Scene& scene, const desktop::OccupancyGrid& map, uint64_t seed, bool global, double seconds) {
  world::Diagnostics diags;
  std::unique_ptr<sim::World> w = sim::World::load(scene.world_path, seed, diags);
  sim::ControllerHost host;
  sim::ControllerHost::Options copt;
  copt.search_path = {troupe::testing::kPluginDir};
  if (!w || !host.load(*w, copt, diags)) {
    std::fprintf(stderr, "%s: cannot load:\n%s\n", scene.world_path.c_str(), diags.str().c_str());
    std::exit(1);
  }
  const uint32_t laser = w->robot(0).rangers.first;
  w->set_wanted({sim::SensorKind::Ranger, laser}, true);
  const sim::TransducerDesc& t = w->ranger_desc(laser).transducers.at(0);

  desktop::MclParams p;  // the driver's defaults, with this laser
  p.sensor.max_range = p.laser_max_range = t.range_max;
  p.laser_pose = {t.pose.x, t.pose.y, t.pose.a};
  if (motion_noise >= 0) {
    p.motion.rot_rot = p.motion.rot_trans = p.motion.trans_trans = p.motion.trans_rot = motion_noise;
  }
  if (sigma_hit > 0) p.sensor.sigma_hit = sigma_hit;
  p.sensor.surface = surface_field;
  desktop::ParticleFilter filter(map, p);
  desktop::Rng rng(seed + 7);
  const sim::RobotState& s0 = w->state(0);
  if (global) {
    filter.init_global(rng);
  } else {
    filter.init_pose({s0.pose.x, s0.pose.y, s0.pose.a}, Eigen::Vector3d(0.01, 0.01, 0.0025).asDiagonal(),
                     rng);
  }
  // The odometry frame starts at the start pose: mcl only reads its changes.
  std::vector<float> ranges;
  std::vector<double> err;
  Run r;
  const size_t steps = size_t(seconds / w->interval());
  for (size_t i = 0; i < steps; ++i) {
    host.update(*w);
    w->step();
    const sim::RobotState& s = w->state(0);
    sim::RangerView view = w->ranger(laser);
    ranges.assign(view.ranges.begin(), view.ranges.end());
    desktop::ScanView scan{t.pose.a - t.fov / 2, t.fov / double(t.samples - 1), t.range_max, ranges};
    filter.update({s.odometry.x, s.odometry.y, s.odometry.a}, scan, rng);
    desktop::Pose2 best = filter.best();
    double e = std::hypot(best.x - s.pose.x, best.y - s.pose.y);
    err.push_back(e);
    r.said_lost += filter.lost() ? 1 : 0;
    r.mean_m += e;
    r.max_m = std::max(r.max_m, e);
    r.mean_deg += std::fabs(desktop::wrap_angle(best.a - s.pose.a)) * 180 / kPi;
  }
  r.mean_m /= double(err.size());
  r.mean_deg /= double(err.size());
  r.said_lost /= double(err.size());
  size_t lock = err.size();
  for (size_t i = err.size(); i-- > 0 && err[i] < 0.25;) lock = i;
  r.lock_s = lock < err.size() ? double(lock + 1) * w->interval() : -1;
  return r;
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v.empty() ? 0 : v[v.size() / 2];
}

void table(const Scene& scene, int seeds, double seconds) {
  desktop::PngMapOptions png;
  png.resolution = scene.resolution;
  png.origin = {scene.origin_x, scene.origin_y, 0.0};
  desktop::OccupancyGrid map;
  std::string error;
  if (!desktop::load_png_map(scene.map_png, png, map, error)) {
    std::printf("%s: skipped (%s)\n\n", scene.name.c_str(), error.c_str());
    return;
  }
  if (scene.wall_border) {  // boundary 1: the simulator walls the floor plan in
    for (uint32_t c = 0; c < map.width(); ++c) {
      map.set(c, 0, desktop::CellState::Occupied);
      map.set(c, map.height() - 1, desktop::CellState::Occupied);
    }
    for (uint32_t row = 0; row < map.height(); ++row) {
      map.set(0, row, desktop::CellState::Occupied);
      map.set(map.width() - 1, row, desktop::CellState::Occupied);
    }
  }
  char params[128] = "driver defaults";
  if (motion_noise >= 0 || sigma_hit > 0 || surface_field) {
    std::snprintf(params, sizeof params, "motion noise %g, sigma_hit %g m, %s field",
                  motion_noise >= 0 ? motion_noise : 0.2, sigma_hit > 0 ? sigma_hit : 0.2,
                  surface_field ? "surface" : "classic");
  }
  std::printf("%s: troupe-sim engine, wander controller, %.0f s at 10 Hz, odom_error %.2f, %s\n\n",
              scene.name.c_str(), seconds, odom_error, params);
  std::printf(
      "| seed | tracking mean_m | tracking max_m | tracking mean_deg | tracking said_lost "
      "| global: converged after s |\n");
  std::printf("|---:|---:|---:|---:|---:|---:|\n");
  std::vector<double> means, maxes, degs, locks, lost;
  for (int seed = 1; seed <= seeds; ++seed) {
    Run tr = run(scene, map, uint64_t(seed), false, seconds);
    Run gl = run(scene, map, uint64_t(seed), true, seconds);
    char lock[32];
    std::snprintf(lock, sizeof lock, gl.lock_s < 0 ? "never" : "%.1f", gl.lock_s);
    std::printf("| %d | %.3f | %.3f | %.2f | %.3f | %s |\n", seed, tr.mean_m, tr.max_m, tr.mean_deg,
                tr.said_lost, lock);
    std::fflush(stdout);
    lost.push_back(tr.said_lost);
    means.push_back(tr.mean_m);
    maxes.push_back(tr.max_m);
    degs.push_back(tr.mean_deg);
    locks.push_back(gl.lock_s < 0 ? INFINITY : gl.lock_s);
  }
  std::printf("| median | %.3f | %.3f | %.2f | %.3f | %.1f |\n", median(means), median(maxes), median(degs),
              median(lost), median(locks));
  std::printf("| worst | %.3f | %.3f | %.2f | %.3f | %.1f |\n\n",
              *std::max_element(means.begin(), means.end()), *std::max_element(maxes.begin(), maxes.end()),
              *std::max_element(degs.begin(), degs.end()), *std::max_element(lost.begin(), lost.end()),
              *std::max_element(locks.begin(), locks.end()));
}

}  // namespace

int main(int argc, char** argv) {
  int seeds = 5;
  double seconds = 120;
  auto app = troupe::cli::make_app("bench_mcl_sim",
                                   {"bench_mcl_sim [--seeds N] [--seconds S] [--odom-error E] "
                                    "[--motion-noise A] [--sigma-hit M] [--surface-field]",
                                    "MCL accuracy on troupe-sim's engine (laser, odometry error, wander\n"
                                    "controller): tables for the Stage cave and the office world.\n",
                                    {"bench_mcl_sim --seeds 3 --seconds 60"}});
  app->add_option("--seeds", seeds, "runs per world, seeds 1..N (default 5)")
      ->type_name("N")
      ->check(troupe::cli::at_least(1));
  app->add_option("--seconds", seconds, "simulated time per run, s (default 120)")
      ->type_name("S")
      ->check(troupe::cli::at_least(1));
  app->add_option("--odom-error", odom_error, "the robots' odom_error, each axis (default 0.05)")
      ->type_name("E")
      ->check(troupe::cli::at_least(0));
  app->add_option("--motion-noise", motion_noise,
                  "all four alphas of the filter's motion noise (default: the driver's)")
      ->type_name("A")
      ->check(troupe::cli::at_least(0));
  app->add_option("--sigma-hit", sigma_hit, "the filter's sigma_hit, m (default: the driver's)")
      ->type_name("M")
      ->check(troupe::cli::above(0));
  app->add_flag("--surface-field", surface_field,
                "the filter's surface likelihood field instead of the classic one");
  if (int rc = troupe::cli::parse(*app, argc, argv); rc >= 0) return rc;
  std::error_code ec;
  std::string dir = (std::filesystem::temp_directory_path(ec) / "bench-mcl-sim-XXXXXX").string();
  if (mkdtemp(dir.data()) == nullptr) return 1;

  std::string cave_png = std::string(TROUPE_SHARED_DATA) + "/stage/bitmaps/cave.png";
  Scene cave{"Stage cave (16 x 16 m)", "", cave_png, 16.0 / 500.0, -8.0, -8.0, true};
  if (!std::ifstream(cave_png)) {
    std::printf("Stage cave: skipped (%s not found)\n\n", cave_png.c_str());
  } else if (write_cave_world(dir, cave_png, cave.world_path)) {
    table(cave, seeds, seconds);
  }
  Scene office{"office.world (20 x 15 m)",
               "",
               std::string(TROUPE_SOURCE_DIR) + "/examples/worlds/bitmaps/office.png",
               0.05,
               -10.0,
               -7.5,
               false};
  if (write_office_world(dir, office.world_path)) table(office, seeds, seconds);
  std::filesystem::remove_all(dir, ec);
  return 0;
}
