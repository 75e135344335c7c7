// A plain, blocking connection to a node for tools that need the frames
// themselves: the recorder keeps Data frames byte for byte, which the client
// library's handlers (given a decoded message) do not expose. It speaks the
// handshake and verifies every frame like the client does.
#pragma once

#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "wire/frame.h"
#include "wire/writer.h"

namespace troupe::record {

class Session {
 public:
  explicit Session(std::string client_name, wire::Limits limits = {});
  ~Session();
  Session(const Session&) = delete;
  Session& operator=(const Session&) = delete;

  /// Connects, sends Hello and waits for the node's, all within `timeout_ms`.
  bool connect(const std::string& host, uint16_t port, int timeout_ms, std::string& error);
  void close();
  bool connected() const { return fd_ >= 0; }
  int fd() const { return fd_; }
  /// The node's Hello frame as received, and the name in it.
  const std::vector<uint8_t>& hello_frame() const { return hello_; }
  const std::string& node_name() const { return node_name_; }

  /// Sends a frame whole; false with `error` when the connection broke.
  bool send(std::span<const uint8_t> frame, std::string& error);
  /// Sends a message without a body or with the body begun in begin().
  bool send(const wire::Address& addr, wire::Kind kind, uint32_t seq, std::string& error,
            wire::Body type = wire::Body::NONE, flatbuffers::Offset<void> body = 0);
  flatbuffers::FlatBufferBuilder& begin() { return writer_.start(); }

  enum class Read { Frame, Timeout, Closed };
  /// Waits up to `timeout_ms` (-1: no limit) for the next frame. Frame: `frame`
  /// and `msg` (verified) are valid until the next read. Closed: `error` says
  /// why (end of stream, a bad frame, the node's Error message).
  Read read(int timeout_ms, std::span<const uint8_t>& frame, const wire::Message*& msg, std::string& error);

 private:
  std::string name_;
  wire::Limits limits_;
  int fd_ = -1;
  std::string host_;
  wire::FrameReader reader_;
  wire::MessageWriter writer_;
  std::vector<uint8_t> hello_;
  std::string node_name_;
  std::string node_error_;
};

}  // namespace troupe::record
