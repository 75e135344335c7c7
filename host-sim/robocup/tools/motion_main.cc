// troupe-robocup-motion: records motion logs and trains the learned motion
// model from them (`troupe robocup-motion` through the CLI). record drives
// the robot ROBOT_FILE defines (`define NAME robocup_robot`, NAME the file's
// name without extension; its motion plugin) with seeded random commands; a
// log from a real robot in the same format
// (plugins/learned_motion/motion_model.h) trains just as well. check prints
// how well a model predicts a log against assuming the velocity stays.
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>

#include "host-sim/robocup/game/motion_log.h"
#include "host-sim/robocup/plugins/learned_motion/motion_model.h"
#include "runtime/log.h"
#include "wire/cli/args.h"

using namespace troupe::robocup;

namespace {

int record(const std::string& robot_file, const MotionLogSettings& s, const std::string& out_file) {
  WorldSpec world;
  std::string error;
  // The robot file defines a robot type named as the file.
  const std::string type = std::filesystem::path(robot_file).stem().string();
  const std::string text = "include \"" + robot_file + "\"\nseed " + std::to_string(s.seed) +
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

int fit(const std::string& log_file, const std::string& model_file) {
  std::vector<MotionSample> samples;
  double cycle = 0;
  std::string error;
  MotionModel model;
  if (!read_motion_log(log_file, samples, cycle, error) || !MotionModel::fit(samples, cycle, model, error) ||
      !model.save(model_file, error)) {
    fprintf(stderr, "troupe-robocup-motion: %s\n", error.c_str());
    return 1;
  }
  printf("fitted %zu samples at %.4f s cycles into %s\n", samples.size(), cycle, model_file.c_str());
  return 0;
}

int check(const std::string& model_file, const std::string& log_file) {
  MotionModel model;
  std::vector<MotionSample> samples;
  double cycle = 0;
  std::string error;
  if (!MotionModel::load(model_file, model, error) || !read_motion_log(log_file, samples, cycle, error)) {
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
  std::string command, out_file;
  std::vector<std::string> files;
  MotionLogSettings settings;
  auto app = troupe::cli::make_app(
      "troupe-robocup-motion",
      {"troupe-robocup-motion record ROBOT_FILE [--seconds S] [--seed N] [--out LOG]\n"
       "       troupe-robocup-motion fit LOG --out MODEL\n"
       "       troupe-robocup-motion check MODEL LOG",
       "The learned motion model: `record` drives the robot of ROBOT_FILE with seeded\n"
       "random commands and pushes and writes a motion log (a line per cycle: time_s\n"
       "vx vy w cmd_vx cmd_vy cmd_w, robot frame, SI; a real robot's log trains the\n"
       "same way); `fit` trains a model on a log; `check` prints how well a model\n"
       "predicts a log against assuming the velocity stays (RMS per axis).\n",
       {"troupe-robocup-motion record examples/robocup/robots/pioneer.inc --seed 1 --out run.log",
        "troupe robocup-motion fit run.log --out pioneer.motion",
        "troupe robocup-motion check pioneer.motion other-run.log"}});
  app->add_option("COMMAND", command, "record, fit or check")
      ->required()
      ->check(CLI::IsMember({"record", "fit", "check", "help"}));
  app->add_option("FILE", files, "the command's files");
  auto* seconds = app->add_option("--seconds", settings.seconds, "simulated time to record, s (default 120)")
                      ->type_name("S")
                      ->check(troupe::cli::above(0));
  auto* seed = app->add_option("--seed", settings.seed, "seed of the commands and pushes (default 1)")
                   ->type_name("N")
                   ->check(troupe::cli::at_least(0));
  auto* out =
      app->add_option("--out", out_file, "where the log (record) or the model (fit) goes")->type_name("FILE");
  if (int rc = troupe::cli::parse(*app, argc, argv); rc >= 0) return rc;
  if (command == "help") {
    fputs(app->help().c_str(), stdout);
    return 0;
  }
  auto mistake = [&](const std::string& what) {
    return troupe::cli::usage_error(*app, command + ": " + what);
  };
  const bool record_options = seconds->count() > 0 || seed->count() > 0;
  if (command == "record") {
    if (files.size() != 1) return mistake("needs one ROBOT_FILE");
    return record(files[0], settings, out_file);
  }
  if (record_options) return mistake("--seconds and --seed are record's");
  if (command == "fit") {
    if (files.size() != 1 || out->count() == 0) return mistake("needs LOG --out MODEL");
    return fit(files[0], out_file);
  }
  if (files.size() != 2 || out->count() > 0) return mistake("needs MODEL LOG");
  return check(files[0], files[1]);
}
