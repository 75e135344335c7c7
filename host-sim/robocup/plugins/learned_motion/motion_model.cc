#include "host-sim/robocup/plugins/learned_motion/motion_model.h"

#include <Eigen/Dense>
#include <algorithm>
#include <fstream>
#include <sstream>

namespace troupe::robocup {
namespace {

// m/s (or rad/s) at which the ramps of the velocity error and of the
// command clip: from a single cycle's acceleration step to top speed.
constexpr double kErrorScales[8] = {0.005, 0.02, 0.05, 0.1, 0.2, 0.5, 1, 2};
constexpr double kCommandScales[4] = {0.5, 1, 2, 4};
constexpr const char* kMagic = "troupe-learned-motion";

double ramp(double x, double s) {
  return std::clamp(x, -s, s);
}

double axis(const Twist& t, int k) {
  return k == 0 ? t.vx : k == 1 ? t.vy : t.w;
}
double axis(const MotionCommand& c, int k) {
  return k == 0 ? c.vx : k == 1 ? c.vy : c.w;
}

}  // namespace

void MotionModel::features(const Twist& v, const MotionCommand& c, double* phi) {
  int n = 0;
  phi[n++] = 1;
  for (int k = 0; k < 3; ++k) phi[n++] = axis(v, k);
  for (int k = 0; k < 3; ++k) phi[n++] = axis(c, k);
  phi[n++] = v.vx * v.w;
  phi[n++] = v.vy * v.w;
  for (int k = 0; k < 3; ++k) {
    for (double s : kErrorScales) phi[n++] = ramp(axis(c, k) - axis(v, k), s);
  }
  for (int k = 0; k < 3; ++k) {
    for (double s : kCommandScales) phi[n++] = ramp(axis(c, k), s);
  }
}

bool MotionModel::fit(std::span<const MotionSample> samples, double cycle_s, MotionModel& out,
                      std::string& error) {
  if (samples.size() < size_t(4 * kFeatures)) {
    error =
        "need at least " + std::to_string(4 * kFeatures) + " samples, got " + std::to_string(samples.size());
    return false;
  }
  Eigen::MatrixXd a(samples.size(), kFeatures);
  Eigen::MatrixXd b(samples.size(), 3);
  for (size_t i = 0; i < samples.size(); ++i) {
    double phi[kFeatures];
    features(samples[i].velocity, samples[i].command, phi);
    for (int j = 0; j < kFeatures; ++j) a(Eigen::Index(i), j) = phi[j];
    for (int k = 0; k < 3; ++k)
      b(Eigen::Index(i), k) = axis(samples[i].next, k) - axis(samples[i].velocity, k);
  }
  // Ridge: features that never vary in the log (a diff drive's vy) get
  // weight zero instead of an arbitrary one.
  Eigen::MatrixXd normal = a.transpose() * a;
  normal.diagonal().array() += 1e-6 * (1 + normal.diagonal().mean());
  const Eigen::MatrixXd w = normal.ldlt().solve(a.transpose() * b);
  if (!w.allFinite()) {
    error = "the fit did not converge";
    return false;
  }
  out.cycle_s_ = cycle_s;
  for (int k = 0; k < 3; ++k) {
    for (int j = 0; j < kFeatures; ++j) out.weights_[k][j] = w(j, k);
  }
  return true;
}

Twist MotionModel::predict(const Twist& v, const MotionCommand& c) const {
  double phi[kFeatures];
  features(v, c, phi);
  double d[3] = {0, 0, 0};
  for (int k = 0; k < 3; ++k) {
    for (int j = 0; j < kFeatures; ++j) d[k] += weights_[k][j] * phi[j];
  }
  return {v.vx + d[0], v.vy + d[1], v.w + d[2]};
}

bool MotionModel::save(const std::string& path, std::string& error) const {
  std::ofstream f(path);
  if (!f) {
    error = path + ": cannot write";
    return false;
  }
  f.precision(17);
  f << kMagic << " 1\n# velocity one cycle later = velocity + weights . features (motion_model.h)\n";
  f << "cycle " << cycle_s_ << "\n";
  const char* names[3] = {"vx", "vy", "w"};
  for (int k = 0; k < 3; ++k) {
    f << names[k];
    for (double x : weights_[k]) f << ' ' << x;
    f << '\n';
  }
  if (!f) {
    error = path + ": write failed";
    return false;
  }
  return true;
}

bool MotionModel::load(const std::string& path, MotionModel& out, std::string& error) {
  std::ifstream f(path);
  if (!f) {
    error = path + ": cannot open";
    return false;
  }
  MotionModel m;
  std::string line;
  int number = 0;
  bool header = false, cycle = false, rows[3] = {false, false, false};
  auto bad = [&](const std::string& why) {
    error = path + ":" + std::to_string(number) + ": " + why;
    return false;
  };
  while (std::getline(f, line)) {
    ++number;
    if (line.empty() || line[0] == '#') continue;
    std::istringstream in(line);
    std::string key;
    in >> key;
    if (!header) {
      int version = 0;
      if (key != kMagic || !(in >> version) || version != 1)
        return bad("not a learned motion model (version 1)");
      header = true;
    } else if (key == "cycle") {
      if (!(in >> m.cycle_s_) || !(m.cycle_s_ > 0)) return bad("cycle must be a time > 0 s");
      cycle = true;
    } else if (key == "vx" || key == "vy" || key == "w") {
      const int k = key == "vx" ? 0 : key == "vy" ? 1 : 2;
      for (int j = 0; j < kFeatures; ++j) {
        if (!(in >> m.weights_[k][j]) || !std::isfinite(m.weights_[k][j])) {
          return bad(key + ": expected " + std::to_string(kFeatures) + " finite weights");
        }
      }
      std::string extra;
      if (in >> extra) return bad(key + ": more than " + std::to_string(kFeatures) + " weights");
      rows[k] = true;
    } else {
      return bad("unknown line '" + key + "'");
    }
  }
  if (!header || !cycle || !rows[0] || !rows[1] || !rows[2]) {
    error = path + ": incomplete model (needs the header, cycle, vx, vy and w)";
    return false;
  }
  out = m;
  return true;
}

bool read_motion_log(const std::string& path, std::vector<MotionSample>& out, double& cycle_s,
                     std::string& error) {
  std::ifstream f(path);
  if (!f) {
    error = path + ": cannot open";
    return false;
  }
  std::string line;
  int number = 0;
  bool have_prev = false;
  double prev_t = 0;
  MotionSample prev;
  std::vector<double> gaps;
  while (std::getline(f, line)) {
    ++number;
    if (line.empty() || line[0] == '#') continue;
    if (line == "break") {
      have_prev = false;
      continue;
    }
    std::istringstream in(line);
    double t;
    MotionSample s;
    if (!(in >> t >> s.velocity.vx >> s.velocity.vy >> s.velocity.w >> s.command.vx >> s.command.vy >>
          s.command.w)) {
      error = path + ":" + std::to_string(number) + ": expected `time vx vy w cmd_vx cmd_vy cmd_w`";
      return false;
    }
    if (have_prev) {
      if (!(t > prev_t)) {
        error = path + ":" + std::to_string(number) + ": time does not increase";
        return false;
      }
      prev.next = s.velocity;
      out.push_back(prev);
      gaps.push_back(t - prev_t);
    }
    prev = s;
    prev_t = t;
    have_prev = true;
  }
  if (gaps.empty()) {
    error = path + ": no consecutive samples";
    return false;
  }
  std::nth_element(gaps.begin(), gaps.begin() + long(gaps.size() / 2), gaps.end());
  cycle_s = gaps[gaps.size() / 2];
  return true;
}

}  // namespace troupe::robocup
