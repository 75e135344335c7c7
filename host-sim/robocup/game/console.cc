#include "host-sim/robocup/game/console.h"

#include <cstdarg>
#include <cstdio>

namespace troupe::robocup {
namespace {

std::string format(const char* fmt, ...) __attribute__((format(printf, 1, 2)));
std::string format(const char* fmt, ...) {
  char buf[512];
  va_list args;
  va_start(args, fmt);
  vsnprintf(buf, sizeof buf, fmt, args);
  va_end(args);
  return buf;
}

const char* phase_name(GamePhase p) {
  switch (p) {
    case GamePhase::Play:
      return "play";
    case GamePhase::GoalPause:
      return "goal-pause";
    case GamePhase::Stopped:
      return "stopped";
  }
  return "?";
}

}  // namespace

std::string describe(const RefereeEvent& e, const Score& s) {
  switch (e.kind) {
    case RefereeEventKind::Goal:
      return format("t=%.3f goal %s (blue %d : yellow %d)", e.time_s, team_name(e.team), s.blue, s.yellow);
    case RefereeEventKind::BallOut:
      return format("t=%.3f ball-out at %.2f %.2f, back at %.2f %.2f", e.time_s, e.where.x, e.where.y, e.to.x,
                    e.to.y);
    default:
      return format("t=%.3f %s", e.time_s, event_name(e.kind));
  }
}

void Console::print_events() {
  if (!show_events_) return;
  for (const RefereeEvent& e : sim_.events()) print_(describe(e, sim_.score()));
}

void Console::run_steps(long steps) {
  for (long i = 0; i < steps; ++i) {
    sim_.step();
    print_events();
  }
}

bool Console::execute(const Statement& c, std::string& error) {
  const auto& a = c.args;
  auto bad = [&](const std::string& why) {
    error = c.where() + ": " + c.keyword + ": " + why;
    return false;
  };
  auto numbers = [&](size_t from, size_t count, double* out) {
    if (a.size() != from + count) return false;
    for (size_t i = 0; i < count; ++i) {
      if (!Options::parse_number(a[from + i], out[i])) return false;
    }
    return true;
  };
  auto robot = [&](int& index) {
    index = a.empty() ? -1 : sim_.find_robot(a[0]);
    return index >= 0;
  };
  int r = -1;
  double v[4] = {0, 0, 0, 0};
  if (c.keyword == "run") {
    if (!numbers(0, 1, v) || !(v[0] >= 0 && v[0] <= 1e6)) return bad("expected `run SECONDS`");
    run_steps(std::lround(v[0] / sim_.cycle_s()));
  } else if (c.keyword == "step") {
    v[0] = 1;
    if (!a.empty() && (!numbers(0, 1, v) || !(v[0] >= 0 && v[0] <= 1e8))) return bad("expected `step [N]`");
    run_steps(long(v[0]));
  } else if (c.keyword == "reset") {
    sim_.reset();
  } else if (c.keyword == "start") {
    if (a.size() != 2 || !robot(r))
      return bad("expected `start ROBOT PLUGIN [key=value ...]` with a known robot");
    if (!sim_.start_player(a[0], a[1], c.reader(), error)) return false;
    print_(format("started %s on %s", a[1].c_str(), a[0].c_str()));
  } else if (c.keyword == "stop") {
    if (a.size() != 1 || !robot(r)) return bad("expected `stop ROBOT` with a known robot");
    sim_.stop_player(a[0]);
  } else if (c.keyword == "score") {
    const GameInfo g = sim_.game();
    print_(format("score blue %d yellow %d phase %s t=%.3f", g.score.blue, g.score.yellow,
                  phase_name(g.phase), g.time_s));
  } else if (c.keyword == "state") {
    const BallInfo b = sim_.ball();
    print_(format("ball %.3f %.3f v %.3f %.3f", b.position.x, b.position.y, b.velocity.x, b.velocity.y));
    for (int i = 0; i < sim_.robot_count(); ++i) {
      const RobotInfo ri = sim_.robot(i);
      print_(format("robot %.*s %s %.3f %.3f %.3f player %s", int(ri.name.size()), ri.name.data(),
                    team_name(ri.team), ri.pose.x, ri.pose.y, ri.pose.a,
                    sim_.player_of(i).empty() ? "-" : sim_.player_of(i).c_str()));
    }
  } else if (c.keyword == "players") {
    for (int i = 0; i < sim_.robot_count(); ++i) {
      if (!sim_.player_of(i).empty()) {
        print_(format("%.*s %s", int(sim_.robot(i).name.size()), sim_.robot(i).name.data(),
                      sim_.player_of(i).c_str()));
      }
    }
  } else if (c.keyword == "problems") {
    for (const std::string& p : sim_.problems()) print_(p);
  } else if (c.keyword == "ball") {
    if (!numbers(0, 2, v) && !numbers(0, 4, v)) return bad("expected `ball X Y [VX VY]` (m, m/s)");
    sim_.place_ball({v[0], v[1]}, {v[2], v[3]});
  } else if (c.keyword == "place") {
    if (!robot(r) || !numbers(1, 3, v))
      return bad("expected `place ROBOT X Y A` (m, rad) with a known robot");
    sim_.place_robot(r, {v[0], v[1], v[2]});
  } else if (c.keyword == "kick") {
    if (a.size() != 1 || !robot(r)) return bad("expected `kick ROBOT` with a known robot");
    sim_.kick(r);
  } else if (c.keyword == "command") {
    if (!robot(r) || !numbers(1, 3, v)) return bad("expected `command ROBOT VX VY W` (m/s, rad/s)");
    sim_.command(r, {v[0], v[1], v[2]});
  } else if (c.keyword == "quit") {
    quit_ = true;
  } else {
    return bad(
        "unknown command (run, step, reset, start, stop, score, state, players, problems, ball, place, "
        "kick, command, quit)");
  }
  return true;
}

bool Console::execute_script(const std::string& text, const std::string& name, std::string& error) {
  std::vector<Statement> commands;
  if (!parse_commands(text, name, commands, error)) return false;
  for (const Statement& c : commands) {
    if (!execute(c, error)) return false;
    if (quit_) break;
  }
  return true;
}

}  // namespace troupe::robocup
