// landmark_learner: learns the perceptual model for feature-based
// localization. It places its robot on every pose of a grid over the field,
// one per cycle, records where its sensor sees the goals, goal posts and
// corner posts, and writes the expectation table the desktop MCL reads
// (drivers/common_desktop/landmark_model.h has the format). Then it stands
// still.
//
//   player landmark_learner out=field.landmarks step=0.25 headings=8 [sensor=omni] [margin=0]
//
// out: the table's file (relative to the current folder, like a tool's
// output, so the source tree stays clean); step: grid
// spacing, m; headings: grid headings per turn; sensor: the instance whose
// detections are recorded (default: the robot's first that reports any);
// margin: how far beyond the touch and goal lines the grid reaches, m
// (default: the field's border). Learn with a noise-free sensor: the table
// is what the sensor should see.
#include <cmath>
#include <cstdio>
#include <numbers>

#include "host-sim/robocup/api/fiducial_key.h"
#include "host-sim/robocup/api/plugin.h"

namespace troupe::robocup::plugins {
namespace {

bool is_landmark(ObjectKind k) {
  return k == ObjectKind::Goal || k == ObjectKind::GoalPost || k == ObjectKind::CornerPost;
}

class LandmarkLearner final : public PlayerPlugin {
 public:
  bool configure(Options& o, std::string& error) override {
    out_ = o.text("out", "");
    step_ = o.number("step", 0.25, 0.02, 5);
    headings_ = int(o.integer("headings", 8, 1, 360));
    sensor_ = o.text("sensor", "");
    margin_ = o.number("margin", -1, 0, 10);
    if (!o.finish(error)) return false;
    if (out_.empty()) {
      error = "option 'out': the table's file is required";
      return false;
    }
    return true;
  }

  void start(WorldControl& world, const PlayerContext&) override {
    const FieldGeometry& f = world.field();
    const double margin = margin_ >= 0 ? margin_ : f.border;
    x0_ = -(f.length / 2 + margin);
    y0_ = -(f.width / 2 + margin);
    nx_ = int(std::floor(-2 * x0_ / step_ + 1e-9)) + 1;
    ny_ = int(std::floor(-2 * y0_ / step_ + 1e-9)) + 1;
    for (const Landmark& l : f.landmarks) {
      if (is_landmark(l.kind)) keys_.push_back(*fiducial_key(l.kind, l.id));
    }
    cells_.assign(size_t(nx_) * size_t(ny_) * size_t(headings_) * keys_.size() * 2, NAN);
    next_ = 0;
    placed_s_ = -1;
  }

  void act(WorldControl& world, const PlayerContext& c, const PlayerInput& in, PlayerOutput& out) override {
    out.command = {};
    const size_t total = size_t(nx_) * size_t(ny_) * size_t(headings_);
    if (next_ > total) return;  // done
    if (placed_s_ >= 0) {
      const SensorReading* r = reading(in);
      // The sensor measures at the end of a cycle, every `period` cycles:
      // wait for a measurement of the pose placed.
      if (r == nullptr || r->time_s <= placed_s_ + 1e-9) return;
      record(*r, next_ - 1);
    }
    if (next_ == total) {
      write();
      ++next_;
      return;
    }
    const size_t ix = next_ % size_t(nx_), iy = (next_ / size_t(nx_)) % size_t(ny_);
    const size_t ia = next_ / (size_t(nx_) * size_t(ny_));
    world.place_robot(c.index, {x0_ + double(ix) * step_, y0_ + double(iy) * step_,
                                double(ia) * 2 * std::numbers::pi / headings_});
    placed_s_ = world.time_s();
    ++next_;
  }

 private:
  const SensorReading* reading(const PlayerInput& in) const {
    for (const SensorReading& r : in.readings) {
      if (r.kind != ReadingKind::Detections || !r.valid) continue;
      if (sensor_.empty() || r.name == sensor_) return &r;
    }
    return nullptr;
  }

  void record(const SensorReading& r, size_t pose) {
    float* row = &cells_[pose * keys_.size() * 2];
    for (const Detection& d : r.detections) {
      if (!is_landmark(d.kind)) continue;
      for (size_t k = 0; k < keys_.size(); ++k) {
        if (keys_[k] != fiducial_key(d.kind, d.id)) continue;
        row[2 * k] = float(d.x);
        row[2 * k + 1] = float(d.y);
      }
    }
  }

  void write() {
    FILE* f = std::fopen(out_.c_str(), "w");
    if (f == nullptr) {
      std::fprintf(stderr, "landmark_learner: cannot write %s\n", out_.c_str());
      return;
    }
    std::fprintf(f, "troupe-landmarks 2\ngrid %.6f %.6f %.6f %d %d %d\nlandmarks %zu", x0_, y0_, step_, nx_, ny_,
                 headings_, keys_.size());
    for (const FiducialKey& k : keys_) std::fprintf(f, " %s", to_string(k).c_str());
    std::fprintf(f, "\n");
    for (size_t i = 0; i < cells_.size(); i += 2) {
      std::fprintf(f, std::isnan(cells_[i]) ? "nan nan" : "%.4f %.4f", double(cells_[i]),
                   double(cells_[i + 1]));
      std::fprintf(f, (i + 2) % (keys_.size() * 2) == 0 ? "\n" : " ");
    }
    if (std::fclose(f) != 0) {
      std::fprintf(stderr, "landmark_learner: writing %s failed\n", out_.c_str());
    } else {
      std::fprintf(stderr, "landmark_learner: %s: %d x %d positions x %d headings, %zu landmarks\n",
                   out_.c_str(), nx_, ny_, headings_, keys_.size());
    }
  }

  std::string out_, sensor_;
  double step_ = 0.25, margin_ = -1, x0_ = 0, y0_ = 0;
  int headings_ = 8, nx_ = 0, ny_ = 0;
  std::vector<FiducialKey> keys_;
  std::vector<float> cells_;
  size_t next_ = 0;
  double placed_s_ = -1;
};

}  // namespace
}  // namespace troupe::robocup::plugins

TROUPE_PLUGIN_EXPORT const TroupePluginInfo* troupe_plugin_v1() {
  using namespace troupe::robocup;
  return plugin_info<PlayerPlugin, plugins::LandmarkLearner>(PluginKind::Player, "landmark_learner");
}
