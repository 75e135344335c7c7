// MCL update time per scan: a table over particle counts and beams used.
//
//   bench_mcl_update [--repeats N]
//
// Each cell: the median over N repeats of the time of one full update
// (motion, weighing, KLD resampling at a fixed count, clustering) on the
// synthetic test map with a 361-beam laser, and its ratio to the 100
// particle, 60 beam cell measured in the same run.
#include <algorithm>
#include <chrono>
#include <cstdio>

#include "drivers/common_desktop/particle_filter.h"
#include "tests/desktop/synthetic_world.h"
#include "wire/cli/args.h"

using namespace troupe::desktop;

namespace {

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

// Median seconds per update with `particles` particles and `beams` beams.
double time_update(const OccupancyGrid& map, size_t particles, size_t beams, int repeats) {
  MclParams p;
  p.min_particles = p.max_particles = particles;
  p.max_beams = beams;
  p.laser_max_range = p.sensor.max_range = 8.0;
  p.update_min_d = p.update_min_a = 0;
  ParticleFilter filter(map, p);
  Rng rng(1);
  Pose2 truth{2.0, 3.0, 0.3};
  filter.init_pose(truth, Eigen::Vector3d(0.25, 0.25, 0.1).asDiagonal(), rng);
  testing::TestLaser laser;
  laser.beams = 361;
  std::vector<float> ranges = testing::cast_scan(map, truth, laser);
  ScanView scan{laser.start_angle(), laser.angular_res(), laser.max_range, ranges};
  std::vector<double> times;
  Pose2 odom{};
  for (int i = -3; i < repeats; ++i) {  // three warm-up updates
    odom.x += 0.01;
    auto t0 = std::chrono::steady_clock::now();
    filter.update(odom, scan, rng);
    double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    if (i >= 0) times.push_back(s);
  }
  return median(times);
}

}  // namespace

int main(int argc, char** argv) {
  int repeats = 21;
  auto app =
      troupe::cli::make_app("bench_mcl_update", {"bench_mcl_update [--repeats N]",
                                                 "MCL update time per scan, particles x beams (medians).\n",
                                                 {"bench_mcl_update --repeats 5"}});
  app->add_option("--repeats", repeats, "timed updates per cell; the median is reported (default 21)")
      ->type_name("N")
      ->check(troupe::cli::at_least(1));
  if (int rc = troupe::cli::parse(*app, argc, argv); rc >= 0) return rc;
  OccupancyGrid map = testing::make_test_map();
  const size_t counts[] = {100, 300, 1000, 3000, 10000};
  const size_t beams[] = {60, 120, 180, 360};
  double base = time_update(map, 100, 60, repeats);
  std::printf(
      "MCL update time per scan, median of %d (ms; x = ratio to 100 particles / 60 beams = %.3f ms)\n\n",
      repeats, base * 1e3);
  std::printf("| particles |");
  for (size_t b : beams) std::printf(" %zu beams |", b);
  std::printf("\n|---:|");
  for (size_t i = 0; i < std::size(beams); ++i) std::printf("---:|");
  std::printf("\n");
  for (size_t n : counts) {
    std::printf("| %zu |", n);
    for (size_t b : beams) {
      double t = time_update(map, n, b, repeats);
      std::printf(" %.2f (x%.0f) |", t * 1e3, t / base);
    }
    std::printf("\n");
  }
  return 0;
}
