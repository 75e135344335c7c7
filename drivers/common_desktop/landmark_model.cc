#include "drivers/common_desktop/landmark_model.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <fstream>
#include <sstream>

namespace troupe::desktop {
namespace {

// Tables larger than this many numbers are refused: a hostile file must not
// exhaust memory (a 0.05 m grid of a 12 x 8 m field, 64 headings and 16
// landmarks is 79 million).
constexpr uint64_t kMaxNumbers = 100'000'000;

}  // namespace

bool LandmarkTable::load(const std::string& path, std::string& error) {
  std::ifstream in(path);
  if (!in) {
    error = path + ": cannot open";
    return false;
  }
  std::stringstream text;
  text << in.rdbuf();
  return parse(text.str(), path, error);
}

bool LandmarkTable::parse(const std::string& text, const std::string& name, std::string& error) {
  std::istringstream in(text);
  std::string line;
  int number = 0;
  auto fail = [&](const std::string& why) {
    error = name + ":" + std::to_string(number) + ": " + why;
    return false;
  };
  auto next = [&](std::istringstream& words) {
    while (std::getline(in, line)) {
      ++number;
      if (!line.empty() && line[0] != '#') {
        // Reset in place: move-assigning a stream trips a GCC 12 false
        // -Wstringop-overflow at -O2.
        words.clear();
        words.str(line);
        return true;
      }
    }
    return false;
  };
  std::istringstream words;
  std::string word;
  int version = 0;
  if (!next(words) || !(words >> word >> version) || word != "troupe-landmarks")
    return fail("not a landmark table (expected 'troupe-landmarks 2')");
  if (version != 2) return fail("landmark table version " + std::to_string(version) + ", this build reads 2");
  if (!next(words) || !(words >> word >> x0_ >> y0_ >> step_ >> nx_ >> ny_ >> headings_) || word != "grid")
    return fail("expected 'grid X0 Y0 STEP NX NY HEADINGS'");
  if (!std::isfinite(x0_) || !std::isfinite(y0_) || !(step_ > 0) || !std::isfinite(step_) || nx_ < 2 ||
      ny_ < 2 || headings_ < 1)
    return fail("grid: the step must be > 0, at least 2 x 2 positions and 1 heading");
  size_t n = 0;
  if (!next(words) || !(words >> word >> n) || word != "landmarks")
    return fail("expected 'landmarks N KIND:ID ...'");
  if (n == 0 || n > 1000) return fail("landmarks: between 1 and 1000");
  keys_.resize(n);
  for (LandmarkKey& k : keys_) {
    if (!(words >> word)) return fail("landmarks: expected " + std::to_string(n) + " KIND:ID");
    if (!wire::parse_fiducial_key(word, k)) return fail("landmarks: '" + word + "' is not KIND:ID (kind: ball, goal, post, ...)");
  }
  const uint64_t total = uint64_t(nx_) * uint64_t(ny_) * uint64_t(headings_) * n * 2;
  if (total > kMaxNumbers) return fail("grid too large: " + std::to_string(total) + " numbers");
  cells_.assign(size_t(total), NAN);
  for (size_t row = 0; row < total / (n * 2); ++row) {
    if (!next(words))
      return fail("ends after " + std::to_string(row) + " of " + std::to_string(total / (n * 2)) +
                  " pose lines");
    for (size_t k = 0; k < n * 2; ++k) {
      // Written by strtod's rules: "nan" is a number.
      if (!(words >> word))
        return fail("expected " + std::to_string(n * 2) + " numbers, got " + std::to_string(k));
      char* end = nullptr;
      const float v = std::strtof(word.c_str(), &end);
      if (end == word.c_str() || *end != '\0') return fail("'" + word + "' is not a number");
      cells_[row * n * 2 + k] = v;
    }
  }
  return true;
}

int LandmarkTable::column(const LandmarkKey& key) const {
  for (size_t k = 0; k < keys_.size(); ++k) {
    if (keys_[k] == key) return int(k);
  }
  return -1;
}

bool LandmarkTable::expected(const Pose2& pose, int k, double& x, double& y) const {
  const double gx = (pose.x - x0_) / step_, gy = (pose.y - y0_) / step_;
  if (!(gx >= 0 && gy >= 0 && gx <= nx_ - 1 && gy <= ny_ - 1)) return false;
  const int ix = std::min(int(gx), nx_ - 2), iy = std::min(int(gy), ny_ - 2);
  const double fx = gx - ix, fy = gy - iy;
  const double heading_step = 2 * kPi / headings_;
  double turns = std::round(pose.a / heading_step);
  const int ia = int(((int64_t(turns) % headings_) + headings_) % headings_);
  const float* c[4] = {at(ix, iy, ia, k), at(ix + 1, iy, ia, k), at(ix, iy + 1, ia, k),
                       at(ix + 1, iy + 1, ia, k)};
  for (const float* p : c) {
    if (std::isnan(p[0])) return false;
  }
  const double w[4] = {(1 - fx) * (1 - fy), fx * (1 - fy), (1 - fx) * fy, fx * fy};
  double ex = 0, ey = 0;
  for (int i = 0; i < 4; ++i) ex += w[i] * c[i][0], ey += w[i] * c[i][1];
  // The grid's heading to the particle's: the landmark turns the other way.
  const double d = turns * heading_step - pose.a, cs = std::cos(d), sn = std::sin(d);
  x = cs * ex - sn * ey;
  y = sn * ex + cs * ey;
  return true;
}

void LandmarkLikelihood::set(std::span<const LandmarkObservation> observations) {
  used_.clear();
  for (const LandmarkObservation& o : observations) {
    const int k = table_.column(o.key);
    if (k < 0 || !std::isfinite(o.x) || !std::isfinite(o.y)) continue;
    used_.push_back({k, std::hypot(o.x, o.y), std::atan2(o.y, o.x)});
  }
}

double LandmarkLikelihood::log_likelihood(const Pose2& pose) const {
  double lw = 0;
  for (const Used& u : used_) {
    double ex, ey;
    if (!table_.expected(pose, u.column, ex, ey)) {
      lw += params_.log_unexpected;
      continue;
    }
    const double sd = params_.sigma_distance + params_.sigma_distance_per_m * std::hypot(ex, ey);
    const double dd = (u.distance - std::hypot(ex, ey)) / sd;
    const double db = wrap_angle(u.bearing - std::atan2(ey, ex)) / params_.sigma_bearing;
    // A seen landmark is never less likely than one seen where it should
    // not be: a gross outlier (a mismatched post) costs no more than that.
    lw += std::max(params_.log_unexpected, -0.5 * (dd * dd + db * db));
  }
  return lw;
}

}  // namespace troupe::desktop
