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
//
// Memory is linear in the file, not in the expanded world: a model a define
// brings (a robot type's ranger and its sensors) is expanded once and shared
// by every instance of the define, and a property's values are shared by
// every model that inherits them. A 100,000-robot world of one robot type
// costs what its 100,000 instance lines cost.
#pragma once

#include <cstddef>
#include <iterator>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "host-sim/world/diagnostics.h"
#include "host-sim/world/shared_list.h"

namespace troupe::world {

/// One value of a property: a number or a string.
struct Value {
  bool is_string = false;
  double number = 0;
  /// The string, or the number as written.
  std::string text;
  SourceLoc loc;
};

/// A property's values, shared by every model that inherits the property
/// from one define (copying it copies a pointer).
using ValueList = SharedList<Value>;

struct Property {
  std::string name;
  ValueList values;
  /// Written as a tuple `[ ... ]` (even with one value).
  bool tuple = false;
  SourceLoc loc;
  /// Set by readers (Entity::find); properties nobody read are unknown keys.
  /// A model shared by several instances shares this mark too: a key read
  /// in one of them is known in all (they are one text in the file).
  mutable bool used = false;
};

struct Entity;

/// A model's child models, in file order. A child that a define brings is
/// one object shared by every instance of that define; the list holds
/// shared pointers and iterates as plain `const Entity&`.
class EntityList {
 public:
  using Pointers = std::vector<std::shared_ptr<const Entity>>;
  class iterator {
   public:
    using iterator_category = std::forward_iterator_tag;
    using value_type = Entity;
    using difference_type = std::ptrdiff_t;
    using pointer = const Entity*;
    using reference = const Entity&;
    iterator() = default;
    explicit iterator(Pointers::const_iterator it) : it_(it) {}
    reference operator*() const { return **it_; }
    pointer operator->() const { return it_->get(); }
    iterator& operator++() {
      ++it_;
      return *this;
    }
    iterator operator++(int) { return iterator(it_++); }
    bool operator==(const iterator& o) const { return it_ == o.it_; }

   private:
    Pointers::const_iterator it_;
  };

  size_t size() const { return items_.size(); }
  bool empty() const { return items_.empty(); }
  const Entity& operator[](size_t i) const { return *items_[i]; }
  /// Throws std::out_of_range past the end, as std::vector::at.
  const Entity& at(size_t i) const { return *items_.at(i); }
  iterator begin() const { return iterator(items_.begin()); }
  iterator end() const { return iterator(items_.end()); }
  void push_back(std::shared_ptr<const Entity> e) { items_.push_back(std::move(e)); }

 private:
  Pointers items_;
};

struct Entity {
  /// The model type after expanding defines: "position", "ranger", "model".
  std::string type;
  /// The type as written: "pioneer2dx" (equal to `type` without a define).
  std::string written_type;
  /// Where the model was written.
  SourceLoc loc;
  std::vector<Property> properties;
  EntityList children;

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
