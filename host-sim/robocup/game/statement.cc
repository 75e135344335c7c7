#include "host-sim/robocup/game/statement.h"

#include <algorithm>
#include <cstdio>
#include <span>

#include "host-sim/robocup/physics/vec2.h"
#include "host-sim/sim/loader.h"

namespace troupe::robocup {
namespace {

struct Token {
  enum class Kind { Word, Open, Close, End, EndOfFile } kind;
  std::string text;
  /// Where an '=' outside quotes splits key from value, or npos.
  size_t eq = std::string::npos;
  int line = 0;
};

class Lexer {
 public:
  Lexer(const std::string& text, int first_line = 1) : text_(text), line_(first_line) {}

  bool next(Token& t, std::string& error) {
    while (pos_ < text_.size()) {
      char c = text_[pos_];
      if (c == '#') {
        while (pos_ < text_.size() && text_[pos_] != '\n') ++pos_;
      } else if (c == '\n' || c == ';') {
        t = {Token::Kind::End, "", std::string::npos, line_};
        if (c == '\n') ++line_;
        ++pos_;
        return true;
      } else if (c == ' ' || c == '\t' || c == '\r') {
        ++pos_;
      } else if (c == '{' || c == '}') {
        t = {c == '{' ? Token::Kind::Open : Token::Kind::Close, std::string(1, c), std::string::npos, line_};
        ++pos_;
        return true;
      } else {
        return word(t, error);
      }
    }
    t = {Token::Kind::EndOfFile, "", std::string::npos, line_};
    return true;
  }

  int line() const { return line_; }

 private:
  // A word, possibly with quoted parts: key="a b" is one word.
  bool word(Token& t, std::string& error) {
    t = {Token::Kind::Word, "", std::string::npos, line_};
    while (pos_ < text_.size()) {
      char c = text_[pos_];
      if (c == '"') {
        size_t end = text_.find('"', pos_ + 1);
        size_t newline = text_.find('\n', pos_ + 1);
        if (end == std::string::npos || end > newline) {
          error = std::to_string(line_) + ": unterminated quote";
          return false;
        }
        t.text += text_.substr(pos_ + 1, end - pos_ - 1);
        pos_ = end + 1;
      } else if (c == ' ' || c == '\t' || c == '\r' || c == '\n' || c == ';' || c == '{' || c == '}' ||
                 c == '#') {
        break;
      } else {
        if (c == '=' && t.eq == std::string::npos) t.eq = t.text.size();
        t.text += c;
        ++pos_;
      }
    }
    return true;
  }

  const std::string& text_;
  size_t pos_ = 0;
  int line_;
};

// Commands: words until the end of the line or `;`; no blocks.
bool parse_lines(const std::string& text, const std::string& name, int first_line,
                 std::vector<Statement>& out, std::string& error) {
  Lexer lex(text, first_line);
  Token t;
  Statement s;
  auto flush = [&] {
    if (!s.keyword.empty()) out.push_back(std::move(s));
    s = Statement{};
  };
  for (;;) {
    if (!lex.next(t, error)) {
      error = name + ":" + error;
      return false;
    }
    switch (t.kind) {
      case Token::Kind::EndOfFile:
        flush();
        return true;
      case Token::Kind::End:
        flush();
        break;
      case Token::Kind::Open:
      case Token::Kind::Close:
        error = name + ":" + std::to_string(t.line) + ": '" + t.text + "': commands take no block";
        return false;
      case Token::Kind::Word:
        if (s.keyword.empty()) {
          s.keyword = t.text;
          s.file = name;
          s.line = t.line;
        } else if (t.eq == 0) {
          error = name + ":" + std::to_string(t.line) + ": '" + t.text + "' has no key";
          return false;
        } else if (t.eq != std::string::npos) {
          s.options.emplace_back(t.text.substr(0, t.eq), t.text.substr(t.eq + 1));
        } else {
          s.args.push_back(t.text);
        }
        break;
    }
  }
}

// ---- Stage world files --------------------------------------------------

std::string file_of(const world::SourceLoc& loc) {
  return loc.file ? *loc.file : std::string();
}

// A property's values as an option value: "0.6", or "0,0.6" for a tuple.
std::string joined(const world::Property& p) {
  std::string v;
  for (size_t i = 0; i < p.values.size(); ++i) v += (i ? "," : "") + p.values[i].text;
  return v;
}

class StageReader {
 public:
  StageReader(const world::WorldFile& file, std::string& error) : file_(file), error_(error) {}

  // The root's properties and `models` (top-level models of the root).
  bool world(const world::Entity& root, std::span<const world::Entity* const> models,
             std::vector<Statement>& out) {
    Statement physics = at("world", root.loc);
    for (const world::Property& p : root.properties) {
      p.used = true;
      // The world's statement is where its first property was written.
      if (physics.line == 0 && p.name != "unit_angle" && p.name != "plugin_path")
        physics = at("world", p.loc);
      if (p.name == "unit_angle") {
        if (p.values.size() != 1 || (p.values[0].text != "degrees" && p.values[0].text != "radians"))
          return fail(p.loc, "unit_angle: \"degrees\" or \"radians\"");
        radians_ = p.values[0].text == "radians";
      } else if (p.name == "plugin_path") {
        if (p.values.size() != 1) return fail(p.loc, "plugin_path: expected one folder");
        Statement st = at("plugin_path", p.loc);
        st.args.push_back(p.values[0].text);
        out.push_back(std::move(st));
      } else if (p.name == "interval_sim") {
        double ms = 0;
        if (p.values.size() != 1 || !Options::parse_number(p.values[0].text, ms))
          return fail(p.loc, "interval_sim: expected a number of ms");
        char cycle[32];
        std::snprintf(cycle, sizeof cycle, "%.17g", ms / 1000.0);
        physics.options.emplace_back("cycle", cycle);
      } else {
        physics.options.emplace_back(p.name, joined(p));
      }
    }
    if (!physics.options.empty()) out.push_back(std::move(physics));
    for (const world::Entity* model : models) {
      const world::Entity& e = *model;
      if (e.type == "robocup_field") {
        out.push_back(plain(e, "field"));
      } else if (e.type == "referee") {
        out.push_back(plain(e, "referee"));
      } else if (e.type == "ball") {
        // The engine's reader, as a Stage world's ball is read.
        Statement st = at("ball", e.loc);
        auto ball = std::make_shared<sim::BallDesc>();
        world::Diagnostics diags;
        if (!sim::load_ball(file_, e, *ball, diags)) {
          for (const world::Diagnostic& d : diags.items()) {
            if (d.severity == world::Severity::Error) return fail(d.loc, d.message);
          }
        }
        st.ball = std::move(ball);
        out.push_back(std::move(st));
      } else if (e.type == "robocup_robot") {
        Statement st;
        if (!robot(e, st)) return false;
        out.push_back(std::move(st));
      } else {
        return fail(e.loc, "'" + e.written_type +
                               "' is no RoboCup model (robocup_field, ball, referee, robocup_robot)");
      }
    }
    return true;
  }

 private:
  static Statement at(std::string keyword, const world::SourceLoc& loc) {
    Statement st;
    st.keyword = std::move(keyword);
    st.file = file_of(loc);
    st.line = loc.line;
    return st;
  }

  bool fail(const world::SourceLoc& loc, const std::string& why) {
    error_ = loc.str() + ": " + why;
    return false;
  }

  // Every property as an option, but `arg_key`'s value, which becomes the
  // statement's word (a robot's name, a shape's kind, a plugin).
  Statement plain(const world::Entity& e, std::string keyword, const char* arg_key = nullptr) {
    Statement st = at(std::move(keyword), e.loc);
    for (const world::Property& p : e.properties) {
      p.used = true;
      if (arg_key && p.name == arg_key) {
        st.args.push_back(joined(p));
      } else {
        st.options.emplace_back(p.name, joined(p));
      }
    }
    return st;
  }

  // `pose [x y z a]` as x, y and a (rad) options.
  bool posed(const world::Entity& e, std::string keyword, Statement& st, const char* arg_key) {
    st = plain(e, std::move(keyword), arg_key);
    for (auto it = st.options.begin(); it != st.options.end(); ++it) {
      if (it->first != "pose") continue;
      const world::Property* p = e.find("pose");
      double v[4];
      if (p->values.size() != 4) return fail(p->loc, "pose: expected [x y z a]");
      for (int i = 0; i < 4; ++i) {
        if (!Options::parse_number(p->values[size_t(i)].text, v[i]))
          return fail(p->loc, "pose: expected numbers");
      }
      st.options.erase(it);
      st.options.emplace_back("x", p->values[0].text);
      st.options.emplace_back("y", p->values[1].text);
      char a[32];
      std::snprintf(a, sizeof a, "%.17g", radians_ ? v[3] : v[3] * kPi / 180);
      st.options.emplace_back("a", a);
      break;
    }
    return true;
  }

  bool robot(const world::Entity& e, Statement& st) {
    if (!posed(e, "robot", st, "name")) return false;
    if (st.args.empty()) return fail(e.loc, "a robocup_robot needs a name");
    // mass and inertia are the robot file's `mass M inertia=I`.
    Statement mass = at("mass", e.loc);
    std::vector<std::pair<std::string, std::string>> rest;
    for (auto& [k, v] : st.options) {
      if (k == "mass") {
        mass.args.push_back(v);
      } else if (k == "inertia") {
        mass.options.emplace_back(k, v);
      } else {
        rest.emplace_back(k, v);
      }
    }
    st.options = std::move(rest);
    if (!mass.options.empty() && mass.args.empty()) return fail(e.loc, "inertia without mass");
    if (!mass.args.empty()) st.children.push_back(std::move(mass));
    if (std::any_of(e.children.begin(), e.children.end(),
                    [](const world::Entity& c) { return sim::is_robot_sensor(c.type); })) {
      // The engine's own reading of Stage's sensor models, so they mean
      // here what they mean on a Stage robot.
      auto sensors = std::make_shared<sim::RobotDesc>();
      sensors->look.height = 0;
      world::Diagnostics diags;
      if (!sim::load_robot_sensors(file_, e, *sensors, diags)) {
        error_ = diags.str();
        while (!error_.empty() && error_.back() == '\n') error_.pop_back();
        return false;
      }
      st.stage_sensors = std::move(sensors);
    }
    for (const world::Entity& c : e.children) {
      if (sim::is_robot_sensor(c.type)) continue;  // read above
      if (c.type == "shape") {
        st.children.push_back(plain(c, "shape", "kind"));
      } else if (c.type == "kicker") {
        Statement k = plain(c, "kicker");
        for (const world::Entity& s : c.children) {
          if (s.type != "state") return fail(s.loc, "a kicker holds states");
          Statement state = plain(s, "state", "name");
          for (const world::Entity& sh : s.children) {
            if (sh.type != "shape") return fail(sh.loc, "a kicker state holds shapes");
            state.children.push_back(plain(sh, "shape", "kind"));
          }
          k.children.push_back(std::move(state));
        }
        st.children.push_back(std::move(k));
      } else if (c.type == "motion_plugin") {
        st.children.push_back(plain(c, "motion", "plugin"));
      } else if (c.type == "sensor_plugin") {
        st.children.push_back(plain(c, "sensor", "plugin"));
      } else if (c.type == "player") {
        st.children.push_back(plain(c, "player", "plugin"));
      } else {
        return fail(c.loc,
                    "'" + c.written_type +
                        "' in a robocup_robot (shape, kicker, motion_plugin, sensor_plugin, player, or "
                        "a Stage sensor: ranger, laser, camera, fiducial, blobfinder, bumper, gripper)");
      }
    }
    return true;
  }

  const world::WorldFile& file_;
  std::string& error_;
  bool radians_ = false;
};

bool finish_stage(bool parsed, const world::WorldFile& file, const world::Diagnostics& diags,
                  std::vector<Statement>& out, std::string& error) {
  if (!parsed || diags.has_errors()) {
    error = diags.str();
    while (!error.empty() && error.back() == '\n') error.pop_back();
    return false;
  }
  return from_stage(file, out, error);
}

}  // namespace

Options Statement::reader() const {
  Options o(where(), folder_of(file));
  for (const auto& [k, v] : options) o.set(k, v);
  return o;
}

std::string folder_of(const std::string& path) {
  size_t slash = path.rfind('/');
  return slash == std::string::npos ? "" : path.substr(0, slash);
}

bool from_stage(const world::WorldFile& file, std::vector<Statement>& out, std::string& error) {
  std::vector<const world::Entity*> models;
  for (const world::Entity& e : file.root().children) models.push_back(&e);
  return from_stage(file, models, out, error);
}

bool from_stage(const world::WorldFile& file, std::span<const world::Entity* const> models,
                std::vector<Statement>& out, std::string& error) {
  return StageReader(file, error).world(file.root(), models, out);
}

bool load_stage_file(const std::string& path, std::vector<Statement>& out, std::string& error) {
  world::WorldFile file;
  world::Diagnostics diags;
  const bool parsed = file.load(path, diags);
  return finish_stage(parsed, file, diags, out, error);
}

bool parse_stage_text(const std::string& text, const std::string& file, std::vector<Statement>& out,
                      std::string& error) {
  world::WorldFile wf;
  world::Diagnostics diags;
  const bool parsed = wf.parse(text, file, diags);
  return finish_stage(parsed, wf, diags, out, error);
}

bool parse_commands(const std::string& text, const std::string& name, std::vector<Statement>& out,
                    std::string& error, int first_line) {
  return parse_lines(text, name, first_line, out, error);
}

}  // namespace troupe::robocup
