#include "tests/attack/web_peer.h"

#include <algorithm>
#include <cctype>
#include <cstdlib>

namespace troupe::attack {
namespace {

std::span<const uint8_t> text_bytes(const std::string& s) {
  return {reinterpret_cast<const uint8_t*>(s.data()), s.size()};
}

// The header block's end, or npos.
size_t head_end(const std::string& s) {
  const size_t at = s.find("\r\n\r\n");
  return at == std::string::npos ? at : at + 4;
}

size_t content_length(const std::string& head) {
  std::string lower = head;
  std::transform(lower.begin(), lower.end(), lower.begin(),
                 [](unsigned char c) { return char(std::tolower(c)); });
  const size_t at = lower.find("\r\ncontent-length:");
  return at == std::string::npos ? 0 : size_t(std::strtoul(lower.c_str() + at + 17, nullptr, 10));
}

// Reads an HTTP reply's head (and its body, by Content-Length) from `s`;
// `rest` keeps what came after it (a WebSocket's first frames).
HttpReply read_reply(TcpSocket& s, Deadline deadline, Bytes* rest) {
  HttpReply r;
  std::string got;
  uint8_t chunk[4096];
  size_t end = std::string::npos;
  while ((end = head_end(got)) == std::string::npos) {
    const long n = s.recv_some(chunk, ms_left(deadline));
    if (n <= 0) return r;
    got.append(reinterpret_cast<const char*>(chunk), size_t(n));
  }
  r.head = got.substr(0, end);
  if (r.head.compare(0, 5, "HTTP/") == 0 && r.head.size() > 12) r.status = std::atoi(r.head.c_str() + 9);
  const size_t body = r.status == 101 ? 0 : content_length(r.head);
  while (got.size() < end + body) {
    const long n = s.recv_some(chunk, ms_left(deadline));
    if (n <= 0) break;
    got.append(reinterpret_cast<const char*>(chunk), size_t(n));
  }
  r.body = got.substr(end, body);
  if (rest) rest->assign(got.begin() + long(std::min(got.size(), end + body)), got.end());
  return r;
}

}  // namespace

HttpReply http_exchange(uint16_t port, const std::string& request, int timeout_ms) {
  TcpSocket s;
  if (!s.connect(port)) return {};
  const Deadline deadline = deadline_in(timeout_ms);
  // A server may answer (and close) before reading everything: what it
  // said still counts.
  s.send(text_bytes(request), ms_left(deadline));
  return read_reply(s, deadline, nullptr);
}

HttpReply http_get(uint16_t port, const std::string& target) {
  return http_exchange(port, "GET " + target + " HTTP/1.1\r\nHost: 127.0.0.1:" + std::to_string(port) +
                                 "\r\nConnection: close\r\n\r\n");
}

int WebPeer::handshake(uint16_t port, const std::string& host, const std::string& origin, std::string* body) {
  in_.clear();
  close_code_ = 0;
  if (!socket_.connect(port)) return 0;
  std::string req = "GET /ws HTTP/1.1\r\nHost: " + host +
                    "\r\nUpgrade: websocket\r\nConnection: Upgrade\r\n"
                    "Sec-WebSocket-Key: dGhlIHNhbXBsZSBub25jZQ==\r\nSec-WebSocket-Version: 13\r\n";
  if (!origin.empty()) req += "Origin: " + origin + "\r\n";
  req += "\r\n";
  const Deadline deadline = deadline_in(10000);
  if (!socket_.send(text_bytes(req), ms_left(deadline))) return 0;
  HttpReply reply = read_reply(socket_, deadline, &in_);
  if (body) *body = std::move(reply.body);
  return reply.status;
}

bool WebPeer::send_message(const Bytes& payload, bool text) {
  // A client's frame: FIN, the opcode, the mask bit, the length, the mask,
  // the payload XORed with the mask.
  Bytes f = {uint8_t(0x80 | (text ? 0x1 : 0x2))};
  const size_t n = payload.size();
  if (n < 126) {
    f.push_back(uint8_t(0x80 | n));
  } else if (n < 65536) {
    f.insert(f.end(), {0x80 | 126, uint8_t(n >> 8), uint8_t(n)});
  } else {
    f.push_back(0x80 | 127);
    for (int i = 7; i >= 0; --i) f.push_back(uint8_t(uint64_t(n) >> (8 * i)));
  }
  const uint8_t mask[4] = {0x12, 0x34, 0x56, 0x78};
  f.insert(f.end(), mask, mask + 4);
  for (size_t i = 0; i < n; ++i) f.push_back(payload[i] ^ mask[i % 4]);
  return socket_.send(f);
}

bool WebPeer::fill(size_t n, Deadline deadline) {
  uint8_t chunk[16384];
  while (in_.size() < n) {
    const long got = socket_.recv_some(chunk, ms_left(deadline));
    if (got <= 0) return false;
    in_.insert(in_.end(), chunk, chunk + got);
  }
  return true;
}

std::optional<Bytes> WebPeer::read_message(int timeout_ms) {
  const Deadline deadline = deadline_in(timeout_ms);
  for (;;) {
    // A server's frame is never masked; control frames are short.
    if (!fill(2, deadline)) return std::nullopt;
    const uint8_t opcode = in_[0] & 0x0F;
    uint64_t n = in_[1] & 0x7F;
    size_t head = 2;
    if (n == 126 || n == 127) {
      head += n == 126 ? 2 : 8;
      if (!fill(head, deadline)) return std::nullopt;
      n = 0;
      for (size_t i = 2; i < head; ++i) n = (n << 8) | in_[i];
    }
    if (n > (64u << 20) || !fill(head + size_t(n), deadline)) return std::nullopt;
    Bytes payload(in_.begin() + long(head), in_.begin() + long(head + n));
    in_.erase(in_.begin(), in_.begin() + long(head + n));
    if (opcode == 0x8) {  // close: the code, then the reason
      close_code_ = payload.size() >= 2 ? (payload[0] << 8) | payload[1] : 1005;
      return std::nullopt;
    }
    if (opcode == 0x2 || opcode == 0x1) return payload;
    // ping, pong: not for us to answer in a test
  }
}

std::optional<Bytes> WebPeer::wait_reply(uint32_t seq, int timeout_ms) {
  const Deadline deadline = deadline_in(timeout_ms);
  while (auto m = read_message(ms_left(deadline))) {
    const wire::Message* msg = message(*m);
    if (msg == nullptr) return std::nullopt;
    if (is_reply_to(*msg, seq)) return m;
  }
  return std::nullopt;
}

bool served_by_viewer(uint16_t port, std::string& why) {
  WebPeer page;
  const std::string self = "127.0.0.1:" + std::to_string(port);
  if (const int status = page.handshake(port, self, "http://" + self); status != 101) {
    why = "the viewer's own page was refused (HTTP " + std::to_string(status) + ")";
    return false;
  }
  Frames f;
  if (!page.send_message(f.hello(0)) || !page.send_message(f.bare({}, wire::Kind::DeviceList, 0, 7))) {
    why = "the WebSocket broke while sending";
    return false;
  }
  const auto list = page.wait_reply(7, 20000);
  const wire::Message* m = list ? message(*list) : nullptr;
  if (m == nullptr || m->body_as_DeviceList() == nullptr) {
    why = "no device list through the viewer (close code " + std::to_string(page.close_code()) + ")";
    return false;
  }
  return true;
}

}  // namespace troupe::attack
