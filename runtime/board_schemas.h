// The node config schema of every board of the tree (config.fbs with the
// board's driver options), built by the host build for `troupe config`: a
// binary config is only read right by a node of the board it was compiled
// for, since each board numbers its drivers in its own union.
#pragma once

namespace troupe {

struct BoardSchema {
  const char* board;            // folder name under boards/
  const char* drivers;          // its drivers, comma-separated ("" for none)
  const unsigned char* schema;  // flatc --schema -b
  const unsigned* size;         // bytes
};

/// Every board, by name; ended by an entry whose board is nullptr.
extern const BoardSchema kBoardSchemas[];

}  // namespace troupe
