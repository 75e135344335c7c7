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

}  // namespace troupe::wire::sizes
