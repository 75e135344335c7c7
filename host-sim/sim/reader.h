// Typed reads of world-file properties, converting units once: lengths by
// the world's unit_length (metres by default), angles by unit_angle
// (degrees by default) into radians. A value of the wrong kind is an error
// naming the key and its file:line; reading marks a key as known.
#pragma once

#include <optional>
#include <string>
#include <string_view>

#include "host-sim/sim/geometry.h"
#include "host-sim/world/worldfile.h"

namespace troupe::sim {

class Reader {
 public:
  explicit Reader(world::Diagnostics& diags) : diags_(diags) {}

  /// Reads unit_length and unit_angle from the world entity.
  void set_units(const world::Entity& world);

  double number(const world::Entity& e, std::string_view key, double fallback);
  double length(const world::Entity& e, std::string_view key, double fallback);
  double angle(const world::Entity& e, std::string_view key, double fallback);
  int integer(const world::Entity& e, std::string_view key, int fallback);
  bool flag(const world::Entity& e, std::string_view key, bool fallback);
  std::optional<std::string> string(const world::Entity& e, std::string_view key);

  /// Reads a tuple's leading values into `out`, converting each by `kinds`
  /// ('l' length, 'a' angle, 'f' as written); values not given keep their
  /// fallback. Returns how many the file gave (0 when the key is absent).
  size_t tuple(const world::Entity& e, std::string_view key, std::string_view kinds, double* out);

  /// A pose [x y z a]; [x y a] (Stage 3's form) is read with a warning.
  Pose pose(const world::Entity& e, std::string_view key, const Pose& fallback);
  /// A size [x y (z)]: x, y in metres; z into `height` when given.
  Vec2 size(const world::Entity& e, std::string_view key, Vec2 fallback, double* height = nullptr);
  /// A colour from `color` (a name) or `color_rgba`; warns about unknown names.
  std::optional<uint32_t> color(const world::Entity& e);

  double unit_length() const { return unit_length_; }
  double unit_angle() const { return unit_angle_; }
  world::Diagnostics& diags() { return diags_; }

 private:
  const world::Value* scalar(const world::Entity& e, std::string_view key, bool want_string);
  bool in_range(const world::Value& v, const std::string& key, double converted, char kind);

  world::Diagnostics& diags_;
  double unit_length_ = 1.0;
  double unit_angle_ = kPi / 180;
};

}  // namespace troupe::sim
