#include "host-sim/robocup/game/robot_spec.h"

namespace troupe::robocup {
namespace {

bool fail(const Statement& st, const std::string& why, std::string& error) {
  error = st.where() + ": " + st.keyword + ": " + why;
  return false;
}

bool no_children(const Statement& st, std::string& error) {
  return st.children.empty() || fail(st, "takes no block", error);
}

bool read_kicker(const Statement& st, KickerSpec& k, std::string& error) {
  Options o = st.reader();
  k.direction = o.number("direction", 0, -2 * kPi, 2 * kPi);
  k.reach = o.number("reach", k.reach, 0, 1);
  if (!o.finish(error) || !st.args.empty())
    return fail(st, st.args.empty() ? error : "unexpected words", error);
  for (const Statement& c : st.children) {
    if (c.keyword != "state") return fail(c, "only `state` statements belong in a kicker", error);
    if (c.args.size() != 1) return fail(c, "a state needs a name: name \"rest\"", error);
    KickerState s;
    s.name = c.args[0];
    Options so = c.reader();
    s.accel = so.number("accel", 0, 0, 1e5);
    s.contact_s = so.number("contact", s.contact_s, 0, 1);
    s.hold_s = so.number("hold", 0, 0, 60);
    s.next = so.text("next", "");
    if (!so.finish(error)) return fail(c, error, error);
    for (const Statement& sh : c.children) {
      if (sh.keyword != "shape") return fail(sh, "only `shape` statements belong in a kicker state", error);
      Shape shape;
      if (!read_shape(sh, shape, error)) return false;
      shape.tag = kKickerShapeTag;
      s.shapes.push_back(shape);
    }
    for (const KickerState& other : k.states) {
      if (other.name == s.name) return fail(c, "state '" + s.name + "' defined twice", error);
    }
    k.states.push_back(std::move(s));
  }
  if (k.states.size() < 2) return fail(st, "a kicker needs a rest state and a kick state", error);
  for (KickerState& s : k.states) {
    if (s.next.empty()) continue;
    for (size_t i = 0; i < k.states.size(); ++i) {
      if (k.states[i].name == s.next) s.next_index = int(i);
    }
    if (s.next_index < 0) return fail(st, "state '" + s.name + "': no state named '" + s.next + "'", error);
  }
  return true;
}

}  // namespace

bool read_shape(const Statement& st, Shape& out, std::string& error) {
  if (st.args.size() != 1) return fail(st, "say which: kind \"rect\" (or circle, ellipse, triangle, polygon)", error);
  Options o = st.reader();
  const std::string& kind = st.args[0];
  const Vec2 at{o.number("x", 0), o.number("y", 0)};
  const double a = o.number("a", 0);
  std::string why;
  if (kind == "rect") {
    out = make_rect(at, o.number("length", 0, 1e-6, 1e3), o.number("width", 0, 1e-6, 1e3), a);
    if (!o.has("length") || !o.has("width")) o.fail("length", "a rect needs length= and width=");
  } else if (kind == "circle") {
    out = make_circle(at, o.number("r", 0, 1e-6, 1e3));
    if (!o.has("r")) o.fail("r", "a circle needs r=");
  } else if (kind == "ellipse") {
    out = make_ellipse(at, o.number("rx", 0, 1e-6, 1e3), o.number("ry", 0, 1e-6, 1e3), a);
    if (!o.has("rx") || !o.has("ry")) o.fail("rx", "an ellipse needs rx= and ry=");
  } else if (kind == "triangle" || kind == "polygon") {
    std::vector<double> p = o.numbers("points");
    if (o.ok() && (p.size() % 2 != 0 || p.empty())) o.fail("points", "expected x,y pairs: x0,y0,x1,y1,...");
    if (o.ok() && kind == "triangle" && p.size() != 6) o.fail("points", "a triangle has three corners");
    if (o.ok()) {
      std::vector<Vec2> pts;
      for (size_t i = 0; i + 1 < p.size(); i += 2)
        pts.push_back(Pose2{at.x, at.y, a}.to_world({p[i], p[i + 1]}));
      if (!make_polygon(pts, out, why)) o.fail("points", why);
    }
  } else {
    return fail(st, "unknown shape '" + kind + "' (rect, circle, ellipse, triangle, polygon)", error);
  }
  std::vector<double> z = o.numbers("z", 2);
  if (!z.empty()) {
    if (!(z[0] >= 0 && z[0] < z[1])) o.fail("z", "expected bottom,top with 0 <= bottom < top (m)");
    out.z_min = z[0];
    out.z_max = z[1];
  }
  if (!o.finish(error)) return fail(st, error, error);
  if (!validate(out, why)) return fail(st, why, error);
  return no_children(st, error);
}

bool read_plugin(const Statement& st, PluginSpec& p, std::string& error) {
  if (st.args.size() != 1) return fail(st, "name the plugin: plugin \"NAME\"", error);
  p.plugin = st.args[0];
  p.where = st.where();
  p.name = p.plugin;
  p.options = Options(st.where(), folder_of(st.file));
  Options reserved = Options(st.where(), "");
  for (const auto& [k, v] : st.options) {
    if (k == "name" || k == "x" || k == "y" || k == "a" || k == "z" || k == "period") {
      reserved.set(k, v);
    } else {
      p.options.set(k, v);
    }
  }
  p.name = reserved.text("name", p.plugin);
  p.mount = {reserved.number("x", 0), reserved.number("y", 0), reserved.number("a", 0, -2 * kPi, 2 * kPi)};
  p.mount_z = reserved.number("z", p.mount_z, 0, 10);
  p.period = int(reserved.integer("period", 1, 1, 100000));
  if (!reserved.finish(error)) return fail(st, error, error);
  return no_children(st, error);
}

bool read_robot(const std::vector<Statement>& statements, const std::string& file, RobotSpec& r,
                std::string& error) {
  r.file = file;
  for (const Statement& st : statements) {
    if (st.keyword == "mass") {
      Options o = st.reader();
      if (st.args.size() != 1 || !Options::parse_number(st.args[0], r.mass) || !(r.mass > 0)) {
        return fail(st, "expected `mass KG [inertia=KG_M2]` with a mass > 0", error);
      }
      r.inertia = o.number("inertia", 0, 0, 1e6);
      if (!o.finish(error)) return fail(st, error, error);
    } else if (st.keyword == "shape") {
      Shape s;
      if (!read_shape(st, s, error)) return false;
      r.shapes.push_back(s);
    } else if (st.keyword == "kicker") {
      if (r.has_kicker) return fail(st, "a robot has one kicker", error);
      if (!read_kicker(st, r.kicker, error)) return false;
      r.has_kicker = true;
    } else if (st.keyword == "motion") {
      if (r.has_motion) return fail(st, "a robot has one motion plugin", error);
      if (!read_plugin(st, r.motion, error)) return false;
      r.has_motion = true;
    } else if (st.keyword == "sensor") {
      PluginSpec p;
      if (!read_plugin(st, p, error)) return false;
      for (const PluginSpec& other : r.sensors) {
        if (other.name == p.name)
          return fail(st, "two sensors named '" + p.name + "' (give one name=)", error);
      }
      r.sensors.push_back(std::move(p));
    } else {
      return fail(st, "unknown statement (mass, shape, kicker, motion, sensor)", error);
    }
  }
  if (r.shapes.empty()) {
    error = file + ": a robot needs at least one shape";
    return false;
  }
  return true;
}

}  // namespace troupe::robocup
