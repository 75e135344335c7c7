// troupe-frame-tool: the target's half of the endianness test. Built for
// the target (powerpc is big-endian) and run under qemu-user.
//
//   troupe-frame-tool write FILE   writes the sample frames
//   troupe-frame-tool check FILE   verifies and decodes frames another
//                                  machine wrote; exit 0 when all match
#include <cstdio>
#include <cstring>
#include <vector>

#include "tests/cross/frame_samples.h"

namespace {

bool read_all(const char* path, std::vector<uint8_t>& out) {
  FILE* f = fopen(path, "rb");
  if (f == nullptr) return false;
  uint8_t chunk[4096];
  size_t n = 0;
  while ((n = fread(chunk, 1, sizeof chunk, f)) > 0) out.insert(out.end(), chunk, chunk + n);
  bool ok = ferror(f) == 0;
  fclose(f);
  return ok;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 3 || (strcmp(argv[1], "write") != 0 && strcmp(argv[1], "check") != 0)) {
    fputs("usage: troupe-frame-tool write|check FILE\n", stderr);
    return 2;
  }
  const char* path = argv[2];
  std::vector<uint8_t> bytes;
  if (strcmp(argv[1], "write") == 0) {
    troupe::cross::write_samples(bytes);
    FILE* f = fopen(path, "wb");
    bool ok = f != nullptr && fwrite(bytes.data(), 1, bytes.size(), f) == bytes.size();
    if (f != nullptr && fclose(f) != 0) ok = false;
    if (!ok) {
      fprintf(stderr, "troupe-frame-tool: cannot write %s: %s\n", path, strerror(errno));
      return 1;
    }
    printf("wrote %d frames, %zu bytes\n", troupe::cross::sample_count(), bytes.size());
    return 0;
  }
  if (!read_all(path, bytes)) {
    fprintf(stderr, "troupe-frame-tool: cannot read %s: %s\n", path, strerror(errno));
    return 1;
  }
  std::string error = troupe::cross::check_samples(bytes);
  if (!error.empty()) {
    fprintf(stderr, "troupe-frame-tool: %s: %s\n", path, error.c_str());
    return 1;
  }
  printf("ok: %d frames, %zu bytes\n", troupe::cross::sample_count(), bytes.size());
  return 0;
}
