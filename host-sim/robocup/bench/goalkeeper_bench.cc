#include "host-sim/robocup/bench/goalkeeper_bench.h"

#include <algorithm>

#include "host-sim/robocup/game/simulation.h"

namespace troupe::robocup {
namespace {

enum class Outcome { Goal, Save, Miss, NoKick };

// One shot, from the field as the setup leaves it until it is decided.
Outcome take_shot(Simulation& sim, const BenchSettings& s, int keeper) {
  const BodyId keeper_body = sim.robot_body(keeper), ball_body = sim.ball_body();
  const double forward = sim.robot(keeper).team == Team::Blue ? 1 : -1;
  const double start = sim.time_s();
  bool kicked = false, touched = false;
  double away_since = -1;
  for (;;) {
    sim.step();
    for (const RefereeEvent& e : sim.events()) {
      if (e.kind == RefereeEventKind::Goal) return Outcome::Goal;
      if (e.kind == RefereeEventKind::BallOut) return touched ? Outcome::Save : Outcome::Miss;
    }
    for (const ContactEvent& c : sim.physics().contacts()) {
      if ((c.a == keeper_body && c.b == ball_body) || (c.a == ball_body && c.b == keeper_body))
        touched = true;
    }
    const Vec2 v = sim.ball().velocity;
    if (!kicked && length(v) > 1.0) kicked = true;
    if (kicked) {
      if (length(v) < 0.2) return touched ? Outcome::Save : Outcome::Miss;
      // Rolling back out of the goal area for a while: the shot is over.
      if (forward * v.x > 0.1) {
        if (away_since < 0) away_since = sim.time_s();
        if (sim.time_s() - away_since > 0.3) return touched ? Outcome::Save : Outcome::Miss;
      } else {
        away_since = -1;
      }
    }
    if (sim.time_s() - start > s.shot_timeout_s) {
      if (!kicked) return Outcome::NoKick;
      return touched ? Outcome::Save : Outcome::Miss;
    }
  }
}

Options options_of(const std::vector<std::pair<std::string, std::string>>& extra, const std::string& where) {
  Options o(where, "");
  for (const auto& [k, v] : extra) o.set(k, v);
  return o;
}

}  // namespace

std::vector<ShotSetup> shot_setups(const BenchSettings& s, const FieldSpec& field, uint64_t seed) {
  // Its own generator: the shots of a seed do not depend on the policy.
  Rng rng(seed * 0x9E3779B97F4A7C15ull + 0x5EED);
  std::vector<ShotSetup> out;
  const double margin = 0.45;
  for (int i = 0; i < s.shots; ++i) {
    const double d = rng.uniform(s.min_distance, s.max_distance);
    const double a = rng.uniform(-s.max_angle, s.max_angle);
    ShotSetup shot;
    shot.ball = {-field.length / 2 + d * std::cos(a),
                 std::clamp(d * std::sin(a), -field.width / 2 + margin, field.width / 2 - margin)};
    shot.aim_y = rng.uniform(-s.max_aim, s.max_aim);
    out.push_back(shot);
  }
  return out;
}

bool run_goalkeeper_bench(const WorldSpec& world, const BenchSettings& s, std::vector<BenchCell>& out,
                          std::string& error, FILE* progress) {
  for (uint64_t seed : s.seeds) {
    for (const std::string& policy : s.policies) {
      WorldSpec spec = world;
      spec.seed = seed;
      spec.referee.goal_pause_s = 0;
      for (RobotEntry& r : spec.robots) r.has_player = false;
      PluginLoader loader(plugin::search_path(s.plugin_path));
      std::unique_ptr<Simulation> sim = Simulation::create(std::move(spec), std::move(loader), error);
      if (!sim) return false;
      const int keeper = sim->find_robot(s.keeper_robot), striker = sim->find_robot(s.striker_robot);
      if (keeper < 0 || striker < 0) {
        error = "the world needs robots named '" + s.keeper_robot + "' and '" + s.striker_robot + "'";
        return false;
      }
      if (sim->robot(keeper).team == sim->robot(striker).team) {
        error = "keeper and striker must play for different teams";
        return false;
      }
      // Shots are laid out for a keeper defending -x; mirror them for +x.
      const double side = sim->robot(keeper).team == Team::Blue ? 1 : -1;
      const double goal_x = -side * sim->field().length / 2;
      BenchCell cell;
      cell.policy = policy;
      cell.seed = seed;
      for (const ShotSetup& shot : shot_setups(s, world.field, seed)) {
        const Vec2 ball{side * shot.ball.x, shot.ball.y};
        const Vec2 aim{goal_x, shot.aim_y};
        const Vec2 dir = normalized(aim - ball);
        const double behind = sim->robot(striker).radius + sim->ball().radius + 0.1;
        const Vec2 at = ball - dir * behind;
        sim->stop_player(s.striker_robot);
        sim->stop_player(s.keeper_robot);
        sim->place_ball(ball, {0, 0});
        sim->place_robot(striker, {at.x, at.y, std::atan2(dir.y, dir.x)});
        sim->place_robot(keeper, {goal_x + side * 0.35, 0, side > 0 ? 0 : kPi});
        sim->referee().restart();
        Options keeper_options = options_of(s.keeper_options, "benchmark keeper options");
        keeper_options.set("policy", policy);
        if (!sim->start_player(s.keeper_robot, s.keeper_plugin, keeper_options, error)) return false;
        Options striker_options = options_of(s.striker_options, "benchmark striker options");
        striker_options.set("aim_y", std::to_string(shot.aim_y));
        if (!sim->start_player(s.striker_robot, s.striker_plugin, striker_options, error)) return false;
        ++cell.shots;
        switch (take_shot(*sim, s, keeper)) {
          case Outcome::Goal:
            ++cell.goals;
            break;
          case Outcome::Save:
            ++cell.saves;
            break;
          case Outcome::Miss:
            ++cell.misses;
            break;
          case Outcome::NoKick:
            ++cell.no_kick;
            break;
        }
      }
      if (progress) {
        fprintf(progress, "  %-10s seed %llu: %d/%d goals\n", policy.c_str(),
                static_cast<unsigned long long>(seed), cell.goals, cell.shots);
      }
      out.push_back(cell);
    }
  }
  return true;
}

void print_bench_table(const std::vector<BenchCell>& cells, const BenchSettings& s, FILE* to) {
  fprintf(to,
          "goalkeeper benchmark: %d shots per seed, %.1f-%.1f m from the goal, within %.0f deg, aim within "
          "%.2f m\n",
          s.shots, s.min_distance, s.max_distance, s.max_angle * 180 / kPi, s.max_aim);
  fprintf(to, "%-10s %6s %6s %6s %6s %7s %8s %12s\n", "policy", "seed", "shots", "goals", "saves", "misses",
          "no-kick", "goals/shots");
  auto row = [to](const std::string& policy, const std::string& seed, const BenchCell& c) {
    fprintf(to, "%-10s %6s %6d %6d %6d %7d %8d %12.3f\n", policy.c_str(), seed.c_str(), c.shots, c.goals,
            c.saves, c.misses, c.no_kick, c.shots ? double(c.goals) / c.shots : 0.0);
  };
  for (const std::string& policy : s.policies) {
    BenchCell total;
    for (const BenchCell& c : cells) {
      if (c.policy != policy) continue;
      row(policy, std::to_string(c.seed), c);
      total.shots += c.shots;
      total.goals += c.goals;
      total.saves += c.saves;
      total.misses += c.misses;
      total.no_kick += c.no_kick;
    }
    row(policy, "all", total);
  }
}

}  // namespace troupe::robocup
