// Interop over real TCP on loopback with flynn/noise, an independent Noise
// implementation (Debian's golang-github-flynn-noise-dev), as the peer
// noise_peer/noise_peer.go: our initiator against its responder and its
// initiator against our responder, frames both ways, one frame larger than
// a Noise message; and each side refusing the other's wrong key.
#include <arpa/inet.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <gtest/gtest.h>

#include <filesystem>

#include "tests/security/noise_test_util.h"
#include "tests/support/child_process.h"

namespace troupe::wire::noise {
namespace {

using testing::ChildProcess;
using testing::test_frame;
using testing::to_hex;

// Hang guards (bounds on a failing test, not measurements), ms.
constexpr int kWaitMs = 20'000;

const std::string kPeer = TROUPE_NOISE_PEER;

std::string prologue() { return std::string(kPrologue); }

// What noise_peer answers to a frame: every body byte one more.
std::vector<uint8_t> answer(std::vector<uint8_t> frame) {
  for (size_t i = kPrefixBytes; i < frame.size(); ++i) ++frame[i];
  return frame;
}

int tcp_socket() {
  int fd = ::socket(AF_INET, SOCK_STREAM | SOCK_CLOEXEC, 0);
  timeval tv{kWaitMs / 1000, 0};
  ::setsockopt(fd, SOL_SOCKET, SO_RCVTIMEO, &tv, sizeof tv);
  return fd;
}

sockaddr_in loopback(uint16_t port) {
  sockaddr_in a{};
  a.sin_family = AF_INET;
  a.sin_port = htons(port);
  a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  return a;
}

// A NoiseTransport driven over a blocking socket.
class SecureStream {
 public:
  SecureStream(int fd, SecureOptions options) : fd_(fd), t_(std::move(options)) {}
  ~SecureStream() { ::close(fd_); }

  // The handshake; false with error() when it fails or the peer closes.
  bool handshake() {
    t_.begin(out_);
    while (!t_.ready()) {
      if (!flush() || !pump()) return false;
    }
    return flush();
  }
  bool send(std::span<const uint8_t> frame) {
    t_.outbound(frame, out_);
    return flush();
  }
  // The next whole frame; empty when the peer closed or a message was refused.
  std::vector<uint8_t> receive() {
    for (;;) {
      auto f = frames_.next();
      if (!f.empty()) return {f.begin(), f.end()};
      if (!pump()) return {};
    }
  }
  const std::string& error() const { return error_; }
  NoiseTransport& transport() { return t_; }

 private:
  bool flush() {
    for (size_t at = 0; at < out_.size();) {
      ssize_t n = ::send(fd_, out_.data() + at, out_.size() - at, MSG_NOSIGNAL);
      if (n <= 0) {
        error_ = "send failed";
        return false;
      }
      at += static_cast<size_t>(n);
    }
    out_.clear();
    return true;
  }
  bool pump() {
    uint8_t buf[4096];
    ssize_t n = ::recv(fd_, buf, sizeof buf, 0);
    if (n <= 0) {
      error_ = n == 0 ? "peer closed" : "receive failed or timed out";
      return false;
    }
    return t_.inbound({buf, static_cast<size_t>(n)}, frames_, out_, error_) && flush();
  }

  int fd_;
  NoiseTransport t_;
  FrameReader frames_{1u << 22};
  std::vector<uint8_t> out_;
  std::string error_;
};

class NoiseInterop : public ::testing::Test {
 protected:
  void SetUp() override {
    if (!std::filesystem::exists(kPeer)) {
      GTEST_SKIP() << "no flynn/noise peer at '" << kPeer
                   << "' (apt-get install golang-go golang-github-flynn-noise-dev, then reconfigure)";
    }
    dir_ = testing::make_temp_dir("noise_interop");
    ASSERT_FALSE(dir_.empty());
  }
  void TearDown() override {
    if (!dir_.empty()) testing::remove_tree(dir_);
  }

  // Starts the Go responder with `node`'s secret; its port, 0 on failure.
  uint16_t start_go_node(const KeyPair& node) {
    std::string error;
    EXPECT_TRUE(peer_.start({kPeer, "-role", "responder", "-key", to_hex(node.secret), "-prologue", prologue()},
                            dir_, "peer", error))
        << error;
    if (!peer_.wait_for("listening ", false, kWaitMs) || !peer_.wait_for("\n", false, kWaitMs)) return 0;
    return static_cast<uint16_t>(std::stoi(peer_.out().substr(peer_.out().find(' ') + 1)));
  }
  std::unique_ptr<SecureStream> connect_to(uint16_t port, SecureOptions options) {
    int fd = tcp_socket();
    sockaddr_in a = loopback(port);
    EXPECT_EQ(::connect(fd, reinterpret_cast<sockaddr*>(&a), sizeof a), 0);
    return std::make_unique<SecureStream>(fd, std::move(options));
  }
  // Listens on 127.0.0.1, port 0; the socket and its port.
  std::pair<int, uint16_t> listen_ephemeral() {
    int fd = tcp_socket();
    sockaddr_in a = loopback(0);
    EXPECT_EQ(::bind(fd, reinterpret_cast<sockaddr*>(&a), sizeof a), 0);
    EXPECT_EQ(::listen(fd, 1), 0);
    socklen_t len = sizeof a;
    ::getsockname(fd, reinterpret_cast<sockaddr*>(&a), &len);
    return {fd, ntohs(a.sin_port)};
  }
  bool start_go_client(const KeyPair& client, const Key& node_key, uint16_t port, const std::string& sizes) {
    std::string error;
    bool ok = peer_.start({kPeer, "-role", "initiator", "-key", to_hex(client.secret), "-peer", to_hex(node_key),
                           "-prologue", prologue(), "-connect", "127.0.0.1:" + std::to_string(port), "-send", sizes},
                          dir_, "peer", error);
    EXPECT_TRUE(ok) << error;
    return ok;
  }

  std::string dir_;
  ChildProcess peer_;
};

// Body sizes: empty, small, exactly one full Noise message, several.
const std::vector<size_t> kSizes = {0, 1, 100, kMaxPlainBytes - kPrefixBytes, 200'000};

TEST_F(NoiseInterop, OurClientTheirNode) {
  const KeyPair node = generate_keypair(), client = generate_keypair();
  const uint16_t port = start_go_node(node);
  ASSERT_NE(port, 0) << peer_.out() << peer_.err();
  auto s = connect_to(port, {Role::Initiator, client, node.public_key, nullptr});
  ASSERT_TRUE(s->handshake()) << s->error() << "\n" << peer_.out();
  ASSERT_TRUE(peer_.wait_for("client " + to_hex(client.public_key), false, kWaitMs))
      << "the Go node must have learned our key: " << peer_.out();
  for (size_t i = 0; i < kSizes.size(); ++i) {
    const auto frame = test_frame(kSizes[i], static_cast<uint8_t>(i));
    ASSERT_TRUE(s->send(frame));
    EXPECT_EQ(s->receive(), answer(frame)) << "frame of " << kSizes[i] << " bytes: " << s->error() << peer_.out();
  }
  EXPECT_GT(s->transport().messages_out(), kSizes.size()) << "the largest frame spans several messages";
  s.reset();  // closes: the Go node ends cleanly
  EXPECT_EQ(peer_.wait_exit(kWaitMs), 0) << peer_.out();
  EXPECT_NE(peer_.out().find("peer closed"), std::string::npos) << peer_.out();
}

TEST_F(NoiseInterop, TheirClientOurNode) {
  const KeyPair node = generate_keypair(), client = generate_keypair();
  auto [listener, port] = listen_ephemeral();
  std::string sizes;
  for (size_t n : kSizes) sizes += (sizes.empty() ? "" : ",") + std::to_string(n);
  ASSERT_TRUE(start_go_client(client, node.public_key, port, sizes));
  int fd = ::accept4(listener, nullptr, nullptr, SOCK_CLOEXEC);
  ::close(listener);
  ASSERT_GE(fd, 0);
  Key seen{};
  SecureStream s(fd, {Role::Responder, node, {}, [&](const Key& k, std::string&) {
                        seen = k;
                        return true;
                      }});
  ASSERT_TRUE(s.handshake()) << s.error() << "\n" << peer_.out();
  EXPECT_EQ(seen, client.public_key);
  for (size_t i = 0; i < kSizes.size(); ++i) {
    auto frame = s.receive();
    ASSERT_EQ(frame, test_frame(kSizes[i], static_cast<uint8_t>(i))) << s.error() << peer_.out();
    ASSERT_TRUE(s.send(answer(frame)));
  }
  EXPECT_EQ(peer_.wait_exit(kWaitMs), 0) << peer_.out();
  EXPECT_NE(peer_.out().find("interop ok"), std::string::npos) << peer_.out();
}

TEST_F(NoiseInterop, TheirNodeRefusesAClientWithTheWrongNodeKey) {
  const KeyPair node = generate_keypair(), client = generate_keypair();
  const uint16_t port = start_go_node(node);
  ASSERT_NE(port, 0);
  auto s = connect_to(port, {Role::Initiator, client, generate_keypair().public_key, nullptr});
  EXPECT_FALSE(s->handshake());
  EXPECT_FALSE(s->transport().ready());
  EXPECT_EQ(peer_.wait_exit(kWaitMs), 1);
  EXPECT_NE(peer_.out().find("message 1 does not authenticate"), std::string::npos) << peer_.out();
}

TEST_F(NoiseInterop, OurNodeRefusesTheirClientWithTheWrongNodeKey) {
  const KeyPair node = generate_keypair(), client = generate_keypair();
  auto [listener, port] = listen_ephemeral();
  ASSERT_TRUE(start_go_client(client, generate_keypair().public_key, port, "10"));
  int fd = ::accept4(listener, nullptr, nullptr, SOCK_CLOEXEC);
  ::close(listener);
  ASSERT_GE(fd, 0);
  {
    SecureStream s(fd, {Role::Responder, node, {}, nullptr});
    EXPECT_FALSE(s.handshake());
    EXPECT_NE(s.error().find("does not hold this node's public key"), std::string::npos) << s.error();
  }
  EXPECT_EQ(peer_.wait_exit(kWaitMs), 1);
  EXPECT_NE(peer_.out().find("no handshake answer"), std::string::npos) << peer_.out();
}

}  // namespace
}  // namespace troupe::wire::noise
