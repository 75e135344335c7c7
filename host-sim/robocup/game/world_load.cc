#include "host-sim/robocup/game/world_load.h"

#include <cctype>
#include <vector>

#include "host-sim/robocup/game/world_desc.h"
#include "host-sim/sim/loader.h"

namespace troupe::robocup {
namespace {

// The models only a match has; any of them makes the world one.
bool is_match_model(const std::string& type) {
  return type == "robocup_field" || type == "referee" || type == "robocup_robot";
}

// The game reader's "path:line: why" as a diagnostic at that place.
void report(const std::string& error, world::Diagnostics& diags) {
  world::SourceLoc loc;
  std::string why = error;
  const size_t end = error.find(": ");
  const size_t colon = end == std::string::npos ? end : error.rfind(':', end - 1);
  if (colon != std::string::npos && colon + 1 < end &&
      std::isdigit(static_cast<unsigned char>(error[colon + 1]))) {
    loc.file = std::make_shared<const std::string>(error.substr(0, colon));
    loc.line = std::atoi(error.c_str() + colon + 1);
    why = error.substr(end + 2);
  }
  diags.error(loc, why);
}

// Takes a match's models from the engine's loader and reads them with the
// game layer's reader once the loader is through the file.
class MatchModels final : public sim::ModelHandoff {
 public:
  explicit MatchModels(const world::Entity& root) {
    for (const world::Entity& e : root.children) match_ = match_ || is_match_model(e.type);
  }

  bool take(const world::Entity& model) override {
    if (!match_) return false;
    if (is_match_model(model.type) || model.type == "ball") {
      taken_.push_back(&model);
    } else if (model.type != "window") {
      stage_.push_back(&model);
    }
    return true;
  }

  void finish(const world::WorldFile& file, world::Diagnostics& diags) override {
    if (!match_) return;
    for (const world::Entity* e : stage_) {
      diags.error(e->loc, "'" + e->written_type +
                              "' is no RoboCup model (robocup_field, ball, referee, robocup_robot): a match "
                              "does not hold Stage models yet");
      for (const world::Property& p : e->properties) p.used = true;
    }
    std::vector<Statement> statements;
    std::string error;
    WorldSpec spec;
    if (!from_stage(file, taken_, statements, error) || !read_world(statements, file.path(), spec, error)) {
      report(error, diags);
      return;
    }
    spec_ = std::move(spec);
  }

  bool match() const { return match_; }
  std::optional<WorldSpec>& spec() { return spec_; }

 private:
  bool match_ = false;
  std::vector<const world::Entity*> taken_, stage_;
  std::optional<WorldSpec> spec_;
};

}  // namespace

bool load_any_world(const world::WorldFile& file, LoadedWorld& out, world::Diagnostics& diags) {
  const size_t errors_before = diags.error_count();
  MatchModels match(file.root());
  sim::load_world(file, out.desc, diags, &match);
  if (diags.error_count() != errors_before) return false;
  if (match.match()) {
    out.game = std::move(match.spec());
    out.desc = world_desc(*out.game);
  }
  return true;
}

bool load_any_world(const std::string& path, LoadedWorld& out, world::Diagnostics& diags) {
  world::WorldFile file;
  if (!file.load(path, diags)) return false;
  return load_any_world(file, out, diags);
}

}  // namespace troupe::robocup
