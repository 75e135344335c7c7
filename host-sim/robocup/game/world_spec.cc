#include "host-sim/robocup/game/world_spec.h"

#include "host-sim/robocup/game/world_load.h"

namespace troupe::robocup {
namespace {

bool fail(const Statement& st, const std::string& why, std::string& error) {
  error = st.where() + ": " + st.keyword + ": " + why;
  return false;
}

bool good_name(const std::string& name) {
  if (name.empty() || name.size() > 32) return false;
  for (char c : name) {
    if (!std::isalnum(static_cast<unsigned char>(c)) && c != '_' && c != '-') return false;
  }
  return true;
}

bool read_physics(const Statement& st, WorldSpec& w, std::string& error) {
  Options o = st.reader();
  w.physics.cycle_s = o.number("cycle", w.physics.cycle_s, 1e-4, 1);
  w.physics.restitution = o.number("restitution", w.physics.restitution, 0, 1);
  w.physics.friction = o.number("friction", w.physics.friction, 0, 1);
  w.physics.restitution_threshold = o.number("restitution_threshold", w.physics.restitution_threshold, 0, 10);
  w.physics.contact_slop = o.number("contact_slop", w.physics.contact_slop, 1e-6, 0.05);
  w.seed = uint64_t(o.integer("seed", long(w.seed), 0, 1L << 53));
  if (!o.finish(error)) return fail(st, error, error);
  return true;
}

// The engine read the ball's keys (Statement::ball); the match takes its
// size, mass, slowing and kick-off spot.
BallSpec ball_spec(const sim::BallDesc& b) {
  BallSpec out;
  out.radius = b.radius;
  out.mass = b.mass;
  out.deceleration = b.deceleration;
  out.start = {b.pose.x, b.pose.y};
  return out;
}

bool read_robot_entry(const Statement& st, WorldSpec& w, std::string& error) {
  RobotEntry r;
  r.where = st.where();
  if (st.args.size() != 1 || !good_name(st.args[0])) {
    return fail(st, "expected a name of letters, digits, _ or -", error);
  }
  r.name = st.args[0];
  r.stage_sensors = st.stage_sensors;
  for (const RobotEntry& other : w.robots) {
    if (other.name == r.name) return fail(st, "robot '" + r.name + "' defined twice", error);
  }
  Options o = st.reader();
  const std::string team = o.choice("team", "blue", {"blue", "yellow"});
  r.team = team == "blue" ? Team::Blue : Team::Yellow;
  r.start = {o.number("x", 0), o.number("y", 0), o.number("a", 0, -2 * kPi, 2 * kPi)};
  if (!o.finish(error)) return fail(st, error, error);
  std::vector<Statement> body;
  for (const Statement& c : st.children) {
    if (c.keyword != "player") {
      body.push_back(c);
      continue;
    }
    if (r.has_player) return fail(c, "one player per robot", error);
    if (!read_plugin(c, r.player, error)) return false;
    r.has_player = true;
  }
  if (!read_robot(body, st.where(), r.spec, error)) {
    error = st.where() + ": robot " + r.name + ": " + error;
    return false;
  }
  w.robots.push_back(std::move(r));
  return true;
}

}  // namespace

bool read_world(const std::vector<Statement>& statements, const std::string& file, WorldSpec& w,
                std::string& error) {
  w.file = file;
  for (const Statement& st : statements) {
    if (st.keyword != "robot" && !st.children.empty()) return fail(st, "takes no block", error);
    if (st.keyword == "world") {
      if (!read_physics(st, w, error)) return false;
    } else if (st.keyword == "plugin_path") {
      if (st.args.size() != 1 || !st.options.empty()) return fail(st, "expected one folder", error);
      const std::string& dir = st.args[0];
      const std::string base = folder_of(st.file);
      w.plugin_path.push_back(dir[0] == '/' || base.empty() ? dir : base + "/" + dir);
    } else if (st.keyword == "field") {
      if (!read_field(st, w.field, error)) return false;
    } else if (st.keyword == "ball") {
      if (!st.ball) return fail(st, "a ball needs its model's keys", error);
      w.ball = ball_spec(*st.ball);
    } else if (st.keyword == "referee") {
      if (!read_referee(st, w.referee, error)) return false;
    } else if (st.keyword == "robot") {
      if (!read_robot_entry(st, w, error)) return false;
    } else {
      return fail(st, "unknown statement (world, plugin_path, field, ball, referee, robot)", error);
    }
  }
  return true;
}

bool load_world_file(const std::string& path, WorldSpec& out, std::string& error) {
  LoadedWorld world;
  world::Diagnostics diags;
  if (!load_any_world(path, world, diags)) {
    error = diags.str();
    while (!error.empty() && error.back() == '\n') error.pop_back();
    return false;
  }
  if (!world.game) {
    error = path + ": no RoboCup models (robocup_field, referee, robocup_robot): a Stage world";
    return false;
  }
  out = std::move(*world.game);
  return true;
}

bool parse_world_text(const std::string& text, const std::string& file, WorldSpec& out, std::string& error) {
  std::vector<Statement> st;
  if (!parse_stage_text(text, file, st, error)) return false;
  return read_world(st, file, out, error);
}

}  // namespace troupe::robocup
