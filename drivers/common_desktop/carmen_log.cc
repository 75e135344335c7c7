#include "drivers/common_desktop/carmen_log.h"

#include <zlib.h>

#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstring>

namespace troupe::desktop {
namespace {

// Whitespace-separated fields of one line, without copying.
class Fields {
 public:
  explicit Fields(std::string_view line) {
    size_t i = 0;
    while (i < line.size()) {
      while (i < line.size() && (line[i] == ' ' || line[i] == '\t' || line[i] == '\r')) ++i;
      size_t start = i;
      while (i < line.size() && line[i] != ' ' && line[i] != '\t' && line[i] != '\r') ++i;
      if (i > start) fields_.push_back(line.substr(start, i - start));
    }
  }
  size_t size() const { return fields_.size(); }
  std::string_view operator[](size_t i) const { return fields_[i]; }

 private:
  std::vector<std::string_view> fields_;
};

// Reads fields as numbers in order; remembers the first that is not one.
class NumberCursor {
 public:
  NumberCursor(const Fields& f, size_t first) : f_(f), next_(first) {}

  double number() {
    if (next_ >= f_.size()) {
      if (bad_field_.empty()) bad_field_ = "<end of line>";
      ++next_;
      return 0;
    }
    std::string_view s = f_[next_++];
    double v = 0;
    // from_chars does not take a leading '+', which some writers emit.
    std::string_view t = !s.empty() && s[0] == '+' ? s.substr(1) : s;
    auto [end, ec] = std::from_chars(t.data(), t.data() + t.size(), v);
    if (ec != std::errc() || end != t.data() + t.size() || !std::isfinite(v)) {
      if (bad_field_.empty()) {
        bad_field_ = std::string(s);
        bad_index_ = next_ - 1;
      }
      return 0;
    }
    return v;
  }
  Pose2 pose() {
    Pose2 p;
    p.x = number();
    p.y = number();
    p.a = wrap_angle(number());
    return p;
  }
  bool ok() const { return bad_field_.empty(); }
  size_t position() const { return next_; }
  // "field 7 ('abc') is not a number"
  std::string problem() const {
    if (bad_field_ == "<end of line>") return "line ends early";
    return "field " + std::to_string(bad_index_ + 1) + " ('" + bad_field_ + "') is not a number";
  }

 private:
  const Fields& f_;
  size_t next_;
  size_t bad_index_ = 0;
  std::string bad_field_;
};

class Parser {
 public:
  Parser(std::string_view name, const CarmenOptions& options, CarmenLog& out)
      : name_(name), opt_(options), out_(out), flaser_max_(options.flaser_max_range) {}

  void line(std::string_view text, uint32_t number) {
    Fields f(text);
    if (f.size() == 0 || f[0][0] == '#') return;
    std::string_view type = f[0];
    if (type == "ODOM") {
      odom(f, number);
    } else if (type == "FLASER") {
      flaser(f, number);
    } else if (type == "ROBOTLASER1") {
      robotlaser(f, number);
    } else if (type == "TRUEPOS") {
      truepos(f, number);
    } else {
      if (type == "PARAM" && f.size() >= 3 && f[1] == "robot_front_laser_max") {
        double v = 0;
        auto [end, ec] = std::from_chars(f[2].data(), f[2].data() + f[2].size(), v);
        if (ec == std::errc() && end == f[2].data() + f[2].size() && v > 0) flaser_max_ = v;
      }
      ++out_.skipped_lines;
    }
  }

 private:
  void error(uint32_t number, std::string_view type, const std::string& what) {
    ++out_.error_count;
    if (out_.errors.size() < opt_.max_error_messages) {
      out_.errors.push_back(std::string(name_) + ":" + std::to_string(number) + ": " + std::string(type) +
                            ": " + what);
    }
  }

  // The trailing "timestamp host logger_timestamp" of every line type.
  bool timestamp(const Fields& f, size_t at, std::string_view type, uint32_t number, double& t) {
    if (f.size() != at + 3) {
      error(number, type,
            "expected " + std::to_string(at + 3) + " fields, found " + std::to_string(f.size()));
      return false;
    }
    NumberCursor c(f, at);
    t = c.number();
    if (!c.ok()) {
      error(number, type, "timestamp: " + c.problem());
      return false;
    }
    return true;
  }

  void odom(const Fields& f, uint32_t number) {
    OdomReading r;
    r.line = number;
    NumberCursor c(f, 1);
    r.pose = c.pose();
    r.tv = c.number();
    r.rv = c.number();
    c.number();  // acceleration: unused
    if (!c.ok()) return error(number, "ODOM", c.problem());
    if (!timestamp(f, c.position(), "ODOM", number, r.time_s)) return;
    out_.order.push_back({RecordKind::Odometry, uint32_t(out_.odometry.size())});
    out_.odometry.push_back(r);
  }

  // n ranges starting at field `at`; false (reported) when they do not parse.
  bool ranges(const Fields& f, size_t at, size_t n, std::string_view type, uint32_t number,
              std::vector<float>& out) {
    if (f.size() < at + n) {
      error(number, type,
            "announces " + std::to_string(n) + " ranges, line has " +
                std::to_string(f.size() > at ? f.size() - at : 0) + " fields after the count");
      return false;
    }
    NumberCursor c(f, at);
    out.resize(n);
    for (size_t i = 0; i < n; ++i) {
      double v = c.number();
      if (v < 0 && c.ok()) {
        error(number, type, "range " + std::to_string(i) + " is negative (" + std::string(f[at + i]) + ")");
        return false;
      }
      out[i] = float(v);
    }
    if (!c.ok()) {
      error(number, type, c.problem());
      return false;
    }
    return true;
  }

  // Reads a beam count field, refusing absurd values before any allocation.
  bool count(const Fields& f, size_t at, std::string_view type, uint32_t number, size_t& n) {
    NumberCursor c(f, at);
    double v = c.number();
    if (!c.ok() || v < 1 || v > 100000 || v != std::floor(v)) {
      error(number, type, "beam count '" + std::string(at < f.size() ? f[at] : "") + "' is not a count");
      return false;
    }
    n = size_t(v);
    return true;
  }

  void flaser(const Fields& f, uint32_t number) {
    LaserReading r;
    r.line = number;
    size_t n = 0;
    if (!count(f, 1, "FLASER", number, n) || !ranges(f, 2, n, "FLASER", number, r.ranges)) return;
    NumberCursor c(f, 2 + n);
    r.laser_pose = c.pose();
    r.robot_pose = c.pose();
    if (!c.ok()) return error(number, "FLASER", c.problem());
    if (!timestamp(f, c.position(), "FLASER", number, r.time_s)) return;
    r.angular_res = n % 2 == 1 ? opt_.flaser_fov / double(n - 1) : opt_.flaser_fov / double(n);
    r.start_angle = opt_.flaser_start_angle;
    r.max_range = flaser_max_;
    out_.order.push_back({RecordKind::Laser, uint32_t(out_.scans.size())});
    out_.scans.push_back(std::move(r));
  }

  void robotlaser(const Fields& f, uint32_t number) {
    LaserReading r;
    r.line = number;
    NumberCursor head(f, 1);
    head.number();  // laser type
    r.start_angle = head.number();
    double fov = head.number();
    r.angular_res = head.number();
    r.max_range = head.number();
    head.number();  // accuracy
    head.number();  // remission mode
    if (!head.ok()) return error(number, "ROBOTLASER1", head.problem());
    size_t n = 0;
    if (!count(f, 8, "ROBOTLASER1", number, n) || !ranges(f, 9, n, "ROBOTLASER1", number, r.ranges)) return;
    if (!(r.angular_res > 0) || !(r.max_range > 0) || fov <= 0) {
      return error(number, "ROBOTLASER1", "angular_res, fov and max_range must be positive");
    }
    size_t at = 9 + n;
    size_t n_rem = 0;
    if (at >= f.size()) return error(number, "ROBOTLASER1", "line ends before the remission count");
    if (f[at] != "0" && !count(f, at, "ROBOTLASER1", number, n_rem)) return;
    at += 1 + n_rem;  // remissions are not used
    if (at > f.size()) return error(number, "ROBOTLASER1", "line ends inside the remissions");
    NumberCursor c(f, at);
    r.laser_pose = c.pose();
    r.robot_pose = c.pose();
    for (int i = 0; i < 5; ++i) c.number();  // tv rv forward_safety side_safety turn_axis
    if (!c.ok()) return error(number, "ROBOTLASER1", c.problem());
    if (!timestamp(f, c.position(), "ROBOTLASER1", number, r.time_s)) return;
    out_.order.push_back({RecordKind::Laser, uint32_t(out_.scans.size())});
    out_.scans.push_back(std::move(r));
  }

  void truepos(const Fields& f, uint32_t number) {
    TruePoseReading r;
    r.line = number;
    NumberCursor c(f, 1);
    r.true_pose = c.pose();
    r.odom_pose = c.pose();
    if (!c.ok()) return error(number, "TRUEPOS", c.problem());
    if (!timestamp(f, c.position(), "TRUEPOS", number, r.time_s)) return;
    out_.order.push_back({RecordKind::TruePose, uint32_t(out_.true_poses.size())});
    out_.true_poses.push_back(r);
  }

  std::string_view name_;
  const CarmenOptions& opt_;
  CarmenLog& out_;
  double flaser_max_;
};

}  // namespace

CarmenLog parse_carmen(std::string_view text, std::string_view name, const CarmenOptions& options) {
  CarmenLog log;
  Parser parser(name, options, log);
  uint32_t number = 0;
  size_t pos = 0;
  while (pos < text.size()) {
    size_t end = text.find('\n', pos);
    if (end == std::string_view::npos) end = text.size();
    parser.line(text.substr(pos, end - pos), ++number);
    pos = end + 1;
  }
  log.line_count = number;
  return log;
}

bool read_maybe_gzip(const std::string& path, std::string& out, std::string& error) {
  gzFile f = gzopen(path.c_str(), "rb");
  if (f == nullptr) {
    error = path + ": cannot open: " + std::strerror(errno);
    return false;
  }
  out.clear();
  char chunk[1 << 16];
  int n = 0;
  while ((n = gzread(f, chunk, sizeof chunk)) > 0) out.append(chunk, size_t(n));
  // A truncated gzip stream ends like a whole one (n == 0) but leaves
  // Z_BUF_ERROR ("unexpected end of file") behind.
  int code = Z_OK;
  const char* why = gzerror(f, &code);
  if (n < 0 || code != Z_OK) {
    error = path + ": read error after " + std::to_string(out.size()) + " bytes: " + why;
    gzclose(f);
    return false;
  }
  gzclose(f);
  return true;
}

bool read_carmen(const std::string& path, CarmenLog& out, std::string& error, const CarmenOptions& options) {
  std::string text;
  if (!read_maybe_gzip(path, text, error)) return false;
  out = parse_carmen(text, path, options);
  return true;
}

}  // namespace troupe::desktop
