// What a fiducial detection is: its kind (wire/schemas/fiducial.fbs) and its
// id within that kind. Clients match detections by this pair, never by
// decoding an id; as text it is "goal:1" (the kind's name in lower case).
#pragma once

#include <cstdint>
#include <cstdlib>
#include <string>
#include <string_view>

#include "wire/schemas/fiducial_generated.h"

namespace troupe::wire {

struct FiducialKey {
  FiducialKind kind = FiducialKind::Generic;
  int32_t id = -1;
  bool operator==(const FiducialKey&) const = default;
};

/// "goal:1".
inline std::string to_string(const FiducialKey& k) {
  std::string text = EnumNameFiducialKind(k.kind);
  for (char& c : text) c = char(c >= 'A' && c <= 'Z' ? c - 'A' + 'a' : c);
  return text + ":" + std::to_string(k.id);
}

/// Reads "goal:1" (a kind's name in lower case, a colon, an id >= 0).
inline bool parse_fiducial_key(std::string_view text, FiducialKey& out) {
  const size_t colon = text.find(':');
  if (colon == std::string_view::npos || colon + 1 >= text.size()) return false;
  const std::string id_text(text.substr(colon + 1));
  char* end = nullptr;
  const long id = std::strtol(id_text.c_str(), &end, 10);
  if (*end != '\0' || id < 0 || id > INT32_MAX) return false;
  for (FiducialKind kind : EnumValuesFiducialKind()) {
    if (to_string({kind, 0}) == std::string(text.substr(0, colon)) + ":0") {
      out = {kind, int32_t(id)};
      return true;
    }
  }
  return false;
}

}  // namespace troupe::wire
