#include "host-sim/sim/reader.h"

#include <cmath>
#include <functional>

#include "host-sim/world/colors.h"

namespace troupe::sim {

using world::Entity;
using world::Property;
using world::Value;

void Reader::set_units(const Entity& w) {
  if (auto u = string(w, "unit_length")) {
    if (*u == "m") {
      unit_length_ = 1;
    } else if (*u == "cm") {
      unit_length_ = 0.01;
    } else if (*u == "mm") {
      unit_length_ = 0.001;
    } else {
      diags_.error(w.find("unit_length")->loc,
                   "unit_length must be \"m\", \"cm\" or \"mm\", not \"" + *u + "\"");
    }
  }
  if (auto u = string(w, "unit_angle")) {
    if (*u == "degrees") {
      unit_angle_ = kPi / 180;
    } else if (*u == "radians") {
      unit_angle_ = 1;
    } else {
      diags_.error(w.find("unit_angle")->loc,
                   "unit_angle must be \"degrees\" or \"radians\", not \"" + *u + "\"");
    }
  }
}

const Value* Reader::scalar(const Entity& e, std::string_view key, bool want_string) {
  const Property* p = e.find(key);
  if (p == nullptr) return nullptr;
  if (p->values.empty()) {
    diags_.error(p->loc, "'" + p->name + "' is empty");
    return nullptr;
  }
  if (p->values.size() > 1) diags_.warn(p->loc, "'" + p->name + "' takes one value; the first is used");
  const Value& v = p->values[0];
  if (v.is_string != want_string) {
    diags_.error(v.loc, "'" + p->name + "' needs " + (want_string ? "a quoted string" : "a number") +
                            ", not " + (v.is_string ? "\"" + v.text + "\"" : v.text));
    return nullptr;
  }
  return &v;
}

double Reader::number(const Entity& e, std::string_view key, double fallback) {
  const Value* v = scalar(e, key, false);
  return v ? v->number : fallback;
}

namespace {

// Lengths and angles beyond these are typing mistakes (or hostile), and
// would overflow the grid arithmetic.
constexpr double kMaxLength = 1e6;  // m
constexpr double kMaxAngle = 1e6;   // rad

}  // namespace

bool Reader::in_range(const Value& v, const std::string& key, double converted, char kind) {
  const double limit = kind == 'l' ? kMaxLength : kind == 'a' ? kMaxAngle : 1e300;
  if (std::fabs(converted) <= limit) return true;
  diags_.error(v.loc, "'" + key + "' value " + v.text + " is out of range");
  return false;
}

double Reader::length(const Entity& e, std::string_view key, double fallback) {
  const Value* v = scalar(e, key, false);
  if (!v || !in_range(*v, std::string(key), v->number * unit_length_, 'l')) return fallback;
  return v->number * unit_length_;
}

double Reader::angle(const Entity& e, std::string_view key, double fallback) {
  const Value* v = scalar(e, key, false);
  if (!v || !in_range(*v, std::string(key), v->number * unit_angle_, 'a')) return fallback;
  return v->number * unit_angle_;
}

int Reader::integer(const Entity& e, std::string_view key, int fallback) {
  const Value* v = scalar(e, key, false);
  if (!v) return fallback;
  if (v->number != std::floor(v->number) || std::fabs(v->number) > 1e9) {
    std::string msg = "'";  // built in steps: GCC 12 warns falsely (-Wrestrict) on "'" + std::string(...)
    msg.append(key).append("' needs a whole number, not ").append(v->text);
    diags_.error(v->loc, msg);
    return fallback;
  }
  return int(v->number);
}

bool Reader::flag(const Entity& e, std::string_view key, bool fallback) {
  const Value* v = scalar(e, key, false);
  return v ? v->number != 0 : fallback;
}

std::optional<std::string> Reader::string(const Entity& e, std::string_view key) {
  const Value* v = scalar(e, key, true);
  if (!v) return std::nullopt;
  return v->text;
}

size_t Reader::tuple(const Entity& e, std::string_view key, std::string_view kinds, double* out) {
  const Property* p = e.find(key);
  if (p == nullptr) return 0;
  if (p->values.size() > kinds.size()) {
    diags_.warn(p->loc, "'" + p->name + "' takes at most " + std::to_string(kinds.size()) + " values; got " +
                            std::to_string(p->values.size()) + ", the rest are ignored");
  }
  size_t n = std::min(p->values.size(), kinds.size());
  for (size_t i = 0; i < n; ++i) {
    const Value& v = p->values[i];
    if (v.is_string) {
      diags_.error(v.loc, "'" + p->name + "' needs numbers, not \"" + v.text + "\"");
      return 0;
    }
    double scale = kinds[i] == 'l' ? unit_length_ : kinds[i] == 'a' ? unit_angle_ : 1.0;
    if (!in_range(v, p->name, v.number * scale, kinds[i])) return 0;
    out[i] = v.number * scale;
  }
  return n;
}

Pose Reader::pose(const Entity& e, std::string_view key, const Pose& fallback) {
  const Property* p = e.find(key);
  if (p == nullptr) return fallback;
  double v[4] = {fallback.x, fallback.y, 0, fallback.a};
  if (p->values.size() == 3) {
    double w[3] = {fallback.x, fallback.y, fallback.a};
    if (tuple(e, key, "lla", w) == 3) {
      diags_.warn(p->loc, "'" + p->name +
                              "' has 3 values: read as [x y angle] (Stage 3); Stage 4 writes [x y z angle]");
    }
    return {w[0], w[1], w[2]};
  }
  tuple(e, key, "llla", v);
  return {v[0], v[1], v[3]};
}

Vec2 Reader::size(const Entity& e, std::string_view key, Vec2 fallback, double* height) {
  double v[3] = {fallback.x, fallback.y, height ? *height : 0};
  size_t n = tuple(e, key, "lll", v);
  if (n >= 3 && height) *height = v[2];
  return {v[0], v[1]};
}

std::optional<uint32_t> Reader::color(const Entity& e) {
  std::optional<uint32_t> out;
  if (const Property* p = e.find("color"); p != nullptr) {
    if (auto name = string(e, "color")) {
      if (*name == "random") {
        // Stage draws from rand(); a hash of where it was written is just as
        // colourful and the same on every run.
        uint64_t h = std::hash<std::string>{}(p->loc.str());
        out = uint32_t(h & 0x7F7F7F) | 0x404040;
      } else if (auto c = world::lookup_color(*name)) {
        out = *c;
      } else {
        diags_.warn(p->loc, "unknown colour \"" + *name + "\"; red is used");
        out = 0xFF0000;
      }
    }
  }
  if (e.find("color_rgba") != nullptr) {
    double rgba[4] = {0, 0, 0, 1};
    if (tuple(e, "color_rgba", "ffff", rgba) > 0) out = world::pack_rgb(rgba[0], rgba[1], rgba[2]);
  }
  return out;
}

}  // namespace troupe::sim
