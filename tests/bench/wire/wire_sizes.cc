// Prints the table in wire/README.md: each data message's framed size next
// to Player 3's XDR encoding of the same data.
//
//   build/host-release/tests/bench/wire/wire_sizes
#include <cstdio>

#include "tests/bench/wire/sizes.h"

int main() {
  printf("| message | sample | Player 3 XDR (bytes) | Troupe framed (bytes) | Troupe / Player | target | met |\n");
  printf("|---|---|---:|---:|---:|---|---|\n");
  for (const auto& r : troupe::wire::sizes::rows()) {
    double ratio = double(r.troupe_bytes) / double(r.player_bytes);
    bool met = r.is_array ? 2 * r.troupe_bytes <= r.player_bytes : r.troupe_bytes <= r.player_bytes;
    printf("| %s | %s | %zu | %zu | %.2f | %s | %s |\n", r.message.c_str(), r.contents.c_str(), r.player_bytes,
           r.troupe_bytes, ratio, r.is_array ? "<= 0.50" : "<= 1.00", met ? "yes" : "**no**");
  }
  printf("\nPlayer sizes, derived from its XDR rules (40-byte header; 4 bytes per scalar, 8 per double):\n\n");
  for (const auto& r : troupe::wire::sizes::rows()) {
    printf("- %s, %s: %s = %zu\n", r.message.c_str(), r.contents.c_str(), r.player_how.c_str(), r.player_bytes);
  }
  return 0;
}
