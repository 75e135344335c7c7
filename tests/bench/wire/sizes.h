// Representative data messages, framed as Troupe sends them, next to Player
// 3's XDR encoding of the same data. Shared by the size table program and
// the test that holds the targets.
//
// Player 3's size of a message = 40-byte header + the XDR body, where every
// scalar takes 4 bytes (uint8 included), doubles take 8, a dynamic array is
// a 4-byte count followed by its elements (Player's structs also carry their
// own `_count` field before it), and uint8/char arrays are packed bytes
// padded to 4 (playerxdrgen uses xdr_bytes for them).
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace troupe::wire::sizes {

struct Row {
  std::string message;   // e.g. "ranger: laser scan"
  std::string contents;  // what the sample holds
  size_t player_bytes;   // Player 3 XDR, header included
  std::string player_how;
  size_t troupe_bytes;   // framed: 4-byte prefix + FlatBuffer
  bool is_array;         // carries an array: target is at most half of Player
};

std::vector<Row> rows();

/// A flat-shaded 320x240 Rgb8 scene as the simulator renders one (sky, a
/// wall, the floor, two boxes), rows of 960 bytes: the PNG row's image and
/// png_bench's.
std::vector<uint8_t> flat_scene_320x240();

}  // namespace troupe::wire::sizes
