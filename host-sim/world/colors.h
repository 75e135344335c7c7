// Colour names as world files write them (X11's database, as Stage reads it).
#pragma once

#include <cstdint>
#include <optional>
#include <string_view>

namespace troupe::world {

/// 0x00RRGGBB for an X11 colour name ("red", "gray30", "dark green",
/// "orange3"), case and spaces ignored, or for "#RRGGBB". nullopt when the
/// name is not known.
std::optional<uint32_t> lookup_color(std::string_view name);

/// Packs components in [0, 1] (clamped) as 0x00RRGGBB.
uint32_t pack_rgb(double r, double g, double b);

}  // namespace troupe::world
