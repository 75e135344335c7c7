#include "host-sim/world/colors.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <string>

namespace troupe::world {
namespace {

struct Named {
  const char* name;
  uint32_t rgb;
};

// The X11 names worlds use most; numbered variants (red1..red4) and the
// grey levels (gray0..gray100) are computed below.
constexpr Named kColors[] = {
    {"black", 0x000000},          {"white", 0xFFFFFF},         {"red", 0xFF0000},
    {"green", 0x00FF00},          {"blue", 0x0000FF},          {"yellow", 0xFFFF00},
    {"cyan", 0x00FFFF},           {"magenta", 0xFF00FF},       {"orange", 0xFFA500},
    {"purple", 0xA020F0},         {"gray", 0xBEBEBE},          {"grey", 0xBEBEBE},
    {"brown", 0xA52A2A},          {"pink", 0xFFC0CB},          {"darkgray", 0xA9A9A9},
    {"darkgrey", 0xA9A9A9},       {"darkblue", 0x00008B},      {"darkgreen", 0x006400},
    {"darkred", 0x8B0000},        {"darkorange", 0xFF8C00},    {"darkcyan", 0x008B8B},
    {"darkmagenta", 0x8B008B},    {"navy", 0x000080},          {"navyblue", 0x000080},
    {"lightgray", 0xD3D3D3},      {"lightgrey", 0xD3D3D3},     {"lightblue", 0xADD8E6},
    {"lightgreen", 0x90EE90},     {"lightyellow", 0xFFFFE0},   {"lightpink", 0xFFB6C1},
    {"gold", 0xFFD700},           {"violet", 0xEE82EE},        {"tan", 0xD2B48C},
    {"khaki", 0xF0E68C},          {"salmon", 0xFA8072},        {"coral", 0xFF7F50},
    {"tomato", 0xFF6347},         {"orchid", 0xDA70D6},        {"turquoise", 0x40E0D0},
    {"beige", 0xF5F5DC},          {"maroon", 0xB03060},        {"limegreen", 0x32CD32},
    {"forestgreen", 0x228B22},    {"skyblue", 0x87CEEB},       {"steelblue", 0x4682B4},
    {"royalblue", 0x4169E1},      {"dodgerblue", 0x1E90FF},    {"seagreen", 0x2E8B57},
    {"olivedrab", 0x6B8E23},      {"chocolate", 0xD2691E},     {"sienna", 0xA0522D},
    {"firebrick", 0xB22222},      {"hotpink", 0xFF69B4},       {"deeppink", 0xFF1493},
    {"yellowgreen", 0x9ACD32},    {"slategray", 0x708090},     {"slategrey", 0x708090},
    {"dimgray", 0x696969},        {"dimgrey", 0x696969},       {"midnightblue", 0x191970},
    {"cornflowerblue", 0x6495ED}, {"ivory", 0xFFFFF0},         {"wheat", 0xF5DEB3},
    {"goldenrod", 0xDAA520},      {"plum", 0xDDA0DD},          {"aquamarine", 0x7FFFD4},
    {"chartreuse", 0x7FFF00},     {"springgreen", 0x00FF7F},   {"lawngreen", 0x7CFC00},
    {"peru", 0xCD853F},           {"indianred", 0xCD5C5C},     {"orangered", 0xFF4500},
    {"lightcyan", 0xE0FFFF},      {"lavender", 0xE6E6FA},      {"mediumblue", 0x0000CD},
    {"darkviolet", 0x9400D3},     {"darkslategray", 0x2F4F4F}, {"darkslategrey", 0x2F4F4F},
    {"cadetblue", 0x5F9EA0},      {"deepskyblue", 0x00BFFF},   {"lightslategray", 0x778899},
    {"snow", 0xFFFAFA},           {"mintcream", 0xF5FFFA},     {"linen", 0xFAF0E6},
};

std::optional<uint32_t> base_color(const std::string& n) {
  for (const Named& c : kColors) {
    if (n == c.name) return c.rgb;
  }
  return std::nullopt;
}

}  // namespace

uint32_t pack_rgb(double r, double g, double b) {
  auto c = [](double v) { return uint32_t(std::lround(std::clamp(v, 0.0, 1.0) * 255.0)); };
  return (c(r) << 16) | (c(g) << 8) | c(b);
}

std::optional<uint32_t> lookup_color(std::string_view name) {
  std::string n;
  for (char ch : name) {
    if (ch != ' ' && ch != '\t') n += char(std::tolower(static_cast<unsigned char>(ch)));
  }
  if (n.size() == 7 && n[0] == '#' && n.find_first_not_of("0123456789abcdef", 1) == std::string::npos) {
    return uint32_t(std::stoul(n.substr(1), nullptr, 16));
  }
  if (auto c = base_color(n)) return c;
  // Trailing digits: grey levels or X11's four shades of a colour.
  size_t d = n.find_last_not_of("0123456789");
  if (d == std::string::npos || d + 1 == n.size() || n.size() - d - 1 > 3) return std::nullopt;
  std::string stem = n.substr(0, d + 1);
  int level = std::stoi(n.substr(d + 1));
  if (stem == "gray" || stem == "grey") {
    if (level > 100) return std::nullopt;
    uint32_t v = uint32_t(std::lround(level * 2.55));
    return (v << 16) | (v << 8) | v;
  }
  auto base = base_color(stem);
  if (!base || level < 1 || level > 4) return std::nullopt;
  static constexpr double kShade[] = {1.0, 0.932, 0.804, 0.545};
  double s = kShade[level - 1];
  auto ch = [&](int shift) { return uint32_t(std::lround(((*base >> shift) & 0xFF) * s)); };
  return (ch(16) << 16) | (ch(8) << 8) | ch(0);
}

}  // namespace troupe::world
