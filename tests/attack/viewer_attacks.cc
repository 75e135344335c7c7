// Attacks on troupe-sim's browser viewer: WebSockets opened by pages that
// are not the viewer's own (a foreign origin, DNS rebinding), hostile HTTP,
// and bad messages over a WebSocket the viewer accepted.
#include <thread>

#include "tests/attack/attacks.h"
#include "tests/attack/web_peer.h"

namespace troupe::attack {
namespace {

constexpr int kReplyMs = 10000;  // bounds a hung target, not a requirement

// One WebSocket message of the viewer's own page at a time, each followed
// by a DeviceList probe, reconnecting whenever the viewer closed the socket.
class PageThrower {
 public:
  explicit PageThrower(uint16_t port) : port_(port), self_("127.0.0.1:" + std::to_string(port)) {}

  // True when the message was acknowledged (an Ack before the probe's reply).
  bool acked(const Bytes& payload, bool text = false) {
    if (!open_ && page_.handshake(port_, self_, "http://" + self_) != 101) return false;
    open_ = true;
    const uint32_t probe = 0xFFFF0000u + ++probes_;
    if (!page_.send_message(payload, text) ||
        !page_.send_message(f_.bare({}, wire::Kind::DeviceList, 0, probe))) {
      open_ = false;
      return false;
    }
    bool ack = false;
    const Deadline deadline = deadline_in(kReplyMs);
    while (auto m = page_.read_message(ms_left(deadline))) {
      const wire::Message* msg = message(*m);
      if (msg == nullptr) break;
      if (msg->header()->kind() == wire::Kind::Ack) ack = true;
      if (msg->header()->kind() == wire::Kind::DeviceList && msg->header()->seq() == probe) return ack;
    }
    open_ = false;  // closed by the viewer (or the node behind it)
    page_.socket().close();
    return ack;
  }

 private:
  uint16_t port_;
  std::string self_;
  WebPeer page_;
  Frames f_;
  bool open_ = false;
  uint32_t probes_ = 0;
};

}  // namespace

void viewer_foreign_origin(Target& t, int scale, Outcome& out) {
  out.unit = "handshakes";
  const std::string port = std::to_string(t.view_port());
  const std::string self = "127.0.0.1:" + port;
  // {Host, Origin}: foreign pages, then DNS rebinding (the attacker's name
  // pointed at this machine, so Host and Origin agree with each other).
  const std::vector<std::pair<std::string, std::string>> hostile = {
      {self, "http://evil.example"},
      {self, "null"},
      {self, "https://" + self},
      {self, "http://127.0.0.1:1"},
      {self, "http://127.0.0.1:" + port + ".evil.example"},
      {"localhost:" + port, "http://localhost.evil.example:" + port},
      {"evil.example:" + port, "http://evil.example:" + port},
      {"evil.example:" + port, ""},
      {"127.0.0.1.evil.example:" + port, "http://127.0.0.1.evil.example:" + port},
      {"", "http://evil.example"},
  };
  for (int i = 0; i < 20 * scale; ++i) {
    for (const auto& [host, origin] : hostile) {
      WebPeer page;
      ++out.volume;
      if (const int status = page.handshake(t.view_port(), host, origin); status == 101) {
        out.got_through("a WebSocket with Host '" + host + "' and Origin '" + origin + "' was accepted");
      }
    }
  }
}

void viewer_http(Target& t, int scale, Outcome& out) {
  out.unit = "requests";
  const uint16_t port = t.view_port();
  const std::vector<std::string> traversal = {
      "/../../../../etc/passwd",
      "/..%2f..%2f..%2fetc%2fpasswd",
      "/%2e%2e/%2e%2e/etc/passwd",
      "//etc/passwd",
      "/viewer.js/../../small.world",
      "/.%2e/small.world",
      "/..\\..\\etc\\passwd",
      "/%00index.html",
      "http://127.0.0.1/../../etc/passwd",
      "/index.html%00.js",
      "/~/.bashrc",
      "/.git/config",
  };
  for (int i = 0; i < 10 * scale; ++i) {
    for (const std::string& target : traversal) {
      ++out.volume;
      const HttpReply r = http_get(port, target);
      if (r.status == 200) out.got_through("GET " + target + " was served");
    }
    // Headers far past any browser's: refused, never served.
    ++out.volume;
    const std::string big(64 * 1024, 'a');
    if (http_exchange(port, "GET / HTTP/1.1\r\nHost: 127.0.0.1\r\nX-Big: " + big + "\r\n\r\n").status == 200)
      out.got_through("a request with a 64 KiB header was served");
    ++out.volume;
    std::string many = "GET / HTTP/1.1\r\nHost: 127.0.0.1\r\n";
    for (int h = 0; h < 2000; ++h) many += "X-H" + std::to_string(h) + ": v\r\n";
    if (http_exchange(port, many + "\r\n").status == 200)
      out.got_through("a request with 2000 headers was served");
  }
  // Slowloris: partial requests held open while a legitimate visitor comes.
  std::vector<TcpSocket> held(size_t(50 * scale));
  const std::string partial = "GET / HTTP/1.1\r\nHost: 127.0.0.1\r\nX-Slow: ";
  for (TcpSocket& s : held) {
    if (s.connect(port) && s.send({reinterpret_cast<const uint8_t*>(partial.data()), partial.size()}))
      ++out.volume;
  }
  if (http_get(port, "/").status == 0)
    out.got_through("the page was not served while partial requests were held");
}

void viewer_malformed_messages(Target& t, int scale, Outcome& out) {
  out.unit = "messages";
  PageThrower thrower(t.view_port());
  Frames f;
  auto refuse = [&](const Bytes& payload, const std::string& what, bool text = false) {
    ++out.volume;
    if (thrower.acked(payload, text)) out.got_through(what + " was acknowledged");
  };
  for (int i = 0; i < scale; ++i) {
    refuse(Bytes{0xde, 0xad, 0xbe, 0xef, 1, 2, 3}, "garbage");
    refuse(f.bare(kPosition0, wire::Kind::Request, 1, 1), "a frame as a text message", true);
    Bytes two = f.bare({}, wire::Kind::DeviceList, 0, 2);
    const Bytes second = two;
    two.insert(two.end(), second.begin(), second.end());
    refuse(two, "two frames in one message");
    Bytes lying = f.bare(kPosition0, wire::Kind::Request, 1, 3);
    lying[0] = uint8_t(lying[0] + 8);
    refuse(lying, "a prefix longer than the message");
    refuse(Bytes(2u << 20, 0), "a 2 MiB message");
    // The 44-byte frames the bridge's verifier passes on to the node (the
    // node's own port gets them all: null_bodies).
    for (const HostileFrame& h : null_body_sample(TargetKind::Sim)) {
      if (!t.alive()) break;
      ++out.volume;
      if (thrower.acked(h.frame) && !h.if_acked.empty()) out.got_through(h.if_acked + " was acknowledged");
    }
  }
}

}  // namespace troupe::attack
