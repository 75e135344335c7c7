// libFuzzer target: arbitrary bytes through the frame reader, chunked as the
// input's first byte says, then the verifier; every frame the verifier
// accepts is read in full (rendered as JSON from the schema, which visits
// every field) and checked the way the node's router checks it. Anything the
// verifier lets through must be safe to read.
#include <cstddef>
#include <cstdint>
#include <string>

#include "flatbuffers/idl.h"
#include "wire/frame.h"

extern const unsigned char troupe_message_bfbs[];
extern const unsigned troupe_message_bfbs_size;

namespace {

flatbuffers::Parser& schema() {
  static flatbuffers::Parser* parser = [] {
    auto* p = new flatbuffers::Parser;
    p->Deserialize(troupe_message_bfbs, troupe_message_bfbs_size);
    return p;
  }();
  return *parser;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size == 0) return 0;
  size_t chunk = 1 + data[0] % 64;  // how the stream is cut into reads
  ++data;
  --size;
  troupe::wire::Limits limits;
  limits.max_frame_bytes = 64 * 1024;
  troupe::wire::FrameReader reader(limits.max_frame_bytes, 64);
  for (size_t pos = 0; pos < size && !reader.too_large();) {
    size_t n = std::min(chunk, size - pos);
    auto space = reader.write_space(n);
    std::copy(data + pos, data + pos + n, space.data());
    reader.commit(n);
    pos += n;
    for (auto frame = reader.next(); !frame.empty(); frame = reader.next()) {
      const troupe::wire::Message* msg = troupe::wire::verify_frame(frame, limits);
      if (msg == nullptr) continue;
      const troupe::wire::Header& h = *msg->header();
      (void)troupe::wire::body_fits(h.kind(), h.addr().iface(), msg->body_type());
      // Deep-read the body the way the CLI prints it: the typed body table
      // only (see wire/cli/format.cc for why never the whole Message).
      if (msg->body_type() != troupe::wire::Body::NONE && troupe::wire::is_known_body(msg->body_type()) &&
          msg->body() != nullptr) {
        std::string json;
        std::string name = std::string("troupe.wire.") + troupe::wire::EnumNameBody(msg->body_type());
        (void)GenerateTextFromTable(schema(), msg->body(), name, &json);
      }
    }
  }
  return 0;
}
