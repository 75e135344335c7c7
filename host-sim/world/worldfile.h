// A Stage 4 world file, parsed: the tree of models (entities) with their
// properties, after `include` and `define` are resolved. Values keep their
// file:line and stay as written (degrees, millimetres, ...): the loader that
// knows what a key means converts it once (host-sim/sim/loader.h).
//
//   include "pioneer.inc"              # relative to the including file
//   define sicklaser ranger ( sensor( range [0 8] fov 180 samples 180 ) )
//   resolution 0.02                    # a world property
//   pioneer2dx ( name "r0" pose [1 2 0 45] sicklaser() )
//
// `define NAME PARENT ( body )` makes NAME a model type that starts as a
// PARENT (itself possibly defined) and then gets `body`: its properties
// (later assignments win) and its child models (appended). A model written as
// `NAME ( more )` adds `more` the same way, so an instance extends its type.
// As in Stage, a name is a macro only for models written after its define.
#pragma once

#include <cstddef>
#include <string>
#include <string_view>
#include <vector>

#include "host-sim/world/diagnostics.h"

namespace troupe::world {

/// One value of a property: a number or a string.
struct Value {
  bool is_string = false;
  double number = 0;
  /// The string, or the number as written.
  std::string text;
  SourceLoc loc;
};

struct Property {
  std::string name;
  std::vector<Value> values;
  /// Written as a tuple `[ ... ]` (even with one value).
  bool tuple = false;
  SourceLoc loc;
  /// Set by readers (Entity::find); properties nobody read are unknown keys.
  mutable bool used = false;
};

struct Entity {
  /// The model type after expanding defines: "position", "ranger", "model".
  std::string type;
  /// The type as written: "pioneer2dx" (equal to `type` without a define).
  std::string written_type;
  /// Where the model was written.
  SourceLoc loc;
  std::vector<Property> properties;
  std::vector<Entity> children;

  /// The property, marked as used, or nullptr.
  const Property* find(std::string_view name) const;
};

/// Limits that keep a hostile or broken file from exhausting the machine.
struct ParseLimits {
  size_t max_file_bytes = 256u << 20;
  int max_include_depth = 32;
  /// Models nested in models, and defines chained through parents.
  int max_depth = 64;
  /// Models in the expanded tree (a define used twice in a define used
  /// twice ... grows exponentially).
  size_t max_models = 4'000'000;
};

class WorldFile {
 public:
  /// Reads and parses `path`. Errors (syntax, missing include, limits) go to
  /// `diags` with file:line and make it return false.
  bool load(const std::string& path, Diagnostics& diags, const ParseLimits& limits = {});
  /// Parses `text` as if it were the file `path` (includes resolve next to it).
  bool parse(std::string_view text, const std::string& path, Diagnostics& diags,
             const ParseLimits& limits = {});

  /// The world: its properties are the world's (resolution, interval_sim ...),
  /// its children the top-level models. type "world".
  const Entity& root() const { return root_; }
  const std::string& path() const { return path_; }

  /// Warns "unknown key" for every property no reader used, with its file:line.
  void warn_unused(Diagnostics& diags) const;

  /// A path written in the file (a bitmap) resolved against the directory of
  /// the file the value was written in; when no file is there, against the
  /// world file's directory (where Stage looks). Absolute paths stay.
  std::string resolve_path(const Value& value) const;

 private:
  Entity root_;
  std::string path_;
};

}  // namespace troupe::world
