// troupe-robocup-motion: records motion logs and trains the learned motion
// model from them (`troupe robocup-motion` through the CLI).
//
//   troupe-robocup-motion record ROBOT_FILE [--seconds S] [--seed N] [--out LOG]
//   troupe-robocup-motion fit LOG --out MODEL
//   troupe-robocup-motion check MODEL LOG
//
// record drives the robot ROBOT_FILE defines (`define NAME robocup_robot`, NAME
// the file's name without extension; its motion plugin) with seeded
// random commands; a log from a real robot in the same format
// (plugins/learned_motion/motion_model.h) trains just as well. check prints
// how well a model predicts a log against assuming the velocity stays.
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iostream>

#include "host-sim/robocup/game/motion_log.h"
#include "host-sim/robocup/plugins/learned_motion/motion_model.h"
#include "runtime/log.h"

using namespace troupe::robocup;

namespace {

const char kUsage[] =
    "usage: troupe-robocup-motion record ROBOT_FILE [--seconds S] [--seed N] [--out LOG]\n"
    "       troupe-robocup-motion fit LOG --out MODEL\n"
    "       troupe-robocup-motion check MODEL LOG\n";

const char kHelp[] =
    "\n"
    "The learned motion model: `record` drives the robot of ROBOT_FILE with seeded\n"
    "random commands and pushes and writes a motion log (a line per cycle: time_s\n"
    "vx vy w cmd_vx cmd_vy cmd_w, robot frame, SI; a real robot's log trains the\n"
    "same way); `fit` trains a model on a log; `check` prints how well a model\n"
    "predicts a log against assuming the velocity stays (RMS per axis).\n"
    "\n"
    "  --seconds S   simulated time to record, s (default 120)\n"
    "  --seed N      seed of the commands and pushes (default 1)\n"
    "  --out FILE    where the log (record) or the model (fit) goes\n"
    "\n"
    "examples:\n"
    "  troupe-robocup-motion record examples/robocup/robots/pioneer.inc --seed 1 --out run.log\n"
    "  troupe robocup-motion fit run.log --out pioneer.motion\n"
    "  troupe robocup-motion check pioneer.motion other-run.log\n";

/// The short usage to stderr for a mistake (exit 2); the whole help to
/// stdout when asked (exit 0).
int usage(bool asked = false) {
  fputs(kUsage, asked ? stdout : stderr);
  if (asked) fputs(kHelp, stdout);
  return asked ? 0 : 2;
}

int record(int argc, char** argv) {
  if (argc < 3) return usage();
  MotionLogSettings s;
  std::string out_file;
  for (int i = 3; i + 1 < argc; i += 2) {
    if (!strcmp(argv[i], "--seconds")) {
      s.seconds = std::atof(argv[i + 1]);
    } else if (!strcmp(argv[i], "--seed")) {
      s.seed = std::strtoull(argv[i + 1], nullptr, 10);
    } else if (!strcmp(argv[i], "--out")) {
      out_file = argv[i + 1];
    } else {
      return usage();
    }
  }
  WorldSpec world;
  std::string error;
  // The robot file defines a robot type named as the file.
  const std::string type = std::filesystem::path(argv[2]).stem().string();
  const std::string text = "include \"" + std::string(argv[2]) + "\"\nseed " + std::to_string(s.seed) +
                           "\nreferee ( enabled 0 )\n" + type + " ( name \"r\" team \"blue\" )\n";
  if (!parse_world_text(text, "record.world", world, error)) {
    fprintf(stderr, "troupe-robocup-motion: %s\n", error.c_str());
    return 2;
  }
  world.robots[0].spec.sensors.clear();  // only the motion matters
  auto sim = Simulation::create(std::move(world), PluginLoader(), error);
  if (!sim || !sim->problems().empty()) {
    fprintf(stderr, "troupe-robocup-motion: %s\n", sim ? sim->problems()[0].c_str() : error.c_str());
    return 2;
  }
  std::ofstream file;
  if (!out_file.empty()) file.open(out_file);
  std::ostream& out = out_file.empty() ? std::cout : file;
  if (!write_motion_log(*sim, 0, s, out, error)) {
    fprintf(stderr, "troupe-robocup-motion: %s\n", error.c_str());
    return 1;
  }
  return 0;
}

int fit(int argc, char** argv) {
  if (argc != 5 || strcmp(argv[3], "--out")) return usage();
  std::vector<MotionSample> samples;
  double cycle = 0;
  std::string error;
  MotionModel model;
  if (!read_motion_log(argv[2], samples, cycle, error) || !MotionModel::fit(samples, cycle, model, error) ||
      !model.save(argv[4], error)) {
    fprintf(stderr, "troupe-robocup-motion: %s\n", error.c_str());
    return 1;
  }
  printf("fitted %zu samples at %.4f s cycles into %s\n", samples.size(), cycle, argv[4]);
  return 0;
}

int check(int argc, char** argv) {
  if (argc != 4) return usage();
  MotionModel model;
  std::vector<MotionSample> samples;
  double cycle = 0;
  std::string error;
  if (!MotionModel::load(argv[2], model, error) || !read_motion_log(argv[3], samples, cycle, error)) {
    fprintf(stderr, "troupe-robocup-motion: %s\n", error.c_str());
    return 1;
  }
  double model_sq[3] = {0, 0, 0}, hold_sq[3] = {0, 0, 0};
  for (const MotionSample& s : samples) {
    const Twist p = model.predict(s.velocity, s.command);
    const double dm[3] = {p.vx - s.next.vx, p.vy - s.next.vy, p.w - s.next.w};
    const double dh[3] = {s.velocity.vx - s.next.vx, s.velocity.vy - s.next.vy, s.velocity.w - s.next.w};
    for (int k = 0; k < 3; ++k) {
      model_sq[k] += dm[k] * dm[k];
      hold_sq[k] += dh[k] * dh[k];
    }
  }
  const char* names[3] = {"vx m/s", "vy m/s", "w rad/s"};
  printf("%zu samples\n%-8s %14s %14s %8s\n", samples.size(), "axis", "model rms", "hold rms", "ratio");
  for (int k = 0; k < 3; ++k) {
    const double m = std::sqrt(model_sq[k] / samples.size()), h = std::sqrt(hold_sq[k] / samples.size());
    printf("%-8s %14.6f %14.6f %8.3f\n", names[k], m, h, h > 0 ? m / h : 0.0);
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  troupe::set_log_program("troupe-robocup-motion");
  if (argc < 2) return usage();
  if (!strcmp(argv[1], "help")) return usage(true);
  for (int i = 1; i < argc; ++i) {
    if (!strcmp(argv[i], "-h") || !strcmp(argv[i], "--help")) return usage(true);
  }
  if (!strcmp(argv[1], "record")) return record(argc, argv);
  if (!strcmp(argv[1], "fit")) return fit(argc, argv);
  if (!strcmp(argv[1], "check")) return check(argc, argv);
  return usage();
}
