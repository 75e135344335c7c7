// The Noise IK handshake and transport against the spec's behaviour: the
// test vectors Debian's flynn/noise package ships (an implementation nobody
// here wrote), then sessions of two NoiseTransports joined in memory, and
// every way a message can be tampered with ending the session.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <map>

#include "tests/security/noise_test_util.h"

namespace troupe::wire::noise {
namespace {

using testing::from_hex;
using testing::split_messages;
using testing::test_frame;
using testing::to_hex;

Key key_from_hex(const std::string& hex) {
  Key k{};
  auto bytes = from_hex(hex);
  std::copy_n(bytes.begin(), std::min(bytes.size(), k.size()), k.begin());
  return k;
}

// The vector blocks (blank-line separated "name=hex" lines) of one protocol.
std::vector<std::map<std::string, std::string>> read_vectors(const std::string& path, const std::string& protocol) {
  std::vector<std::map<std::string, std::string>> out;
  std::ifstream in(path);
  std::map<std::string, std::string> block;
  std::string line;
  auto flush = [&] {
    if (block["handshake"] == protocol) out.push_back(block);
    block.clear();
  };
  while (std::getline(in, line)) {
    if (line.empty()) {
      flush();
      continue;
    }
    auto eq = line.find('=');
    if (eq != std::string::npos) block[line.substr(0, eq)] = line.substr(eq + 1);
  }
  flush();
  return out;
}

TEST(NoiseVectors, MatchTheFlynnNoiseVectorsForIkChaChaPolyBlake2b) {
  const std::string path = TROUPE_NOISE_VECTORS;
  if (!std::filesystem::exists(path)) {
    GTEST_SKIP() << "no Noise test vectors at '" << path << "' (apt-get install golang-github-flynn-noise-dev)";
  }
  auto vectors = read_vectors(path, kProtocolName);
  ASSERT_GE(vectors.size(), 4u) << "the vector file holds no " << kProtocolName << " vectors";
  for (auto& v : vectors) {
    SCOPED_TRACE("prologue '" + v["prologue"] + "', first payload '" + v["msg_0_payload"] + "'");
    const KeyPair is = keypair_from_secret(key_from_hex(v["init_static"]));
    const KeyPair rs = keypair_from_secret(key_from_hex(v["resp_static"]));
    const KeyPair ie = keypair_from_secret(key_from_hex(v["gen_init_ephemeral"]));
    const KeyPair re = keypair_from_secret(key_from_hex(v["gen_resp_ephemeral"]));
    const auto prologue = from_hex(v["prologue"]);
    HandshakeIK initiator(Role::Initiator, is, prologue, &rs.public_key, &ie);
    HandshakeIK responder(Role::Responder, rs, prologue, nullptr, &re);
    std::string error;
    std::vector<uint8_t> msg, payload;

    ASSERT_TRUE(initiator.write_message(from_hex(v["msg_0_payload"]), msg, error)) << error;
    EXPECT_EQ(to_hex(msg), v["msg_0_ciphertext"]);
    ASSERT_TRUE(responder.read_message(msg, payload, error)) << error;
    EXPECT_EQ(to_hex(payload), v["msg_0_payload"]);
    EXPECT_EQ(responder.remote_static(), is.public_key);

    msg.clear();
    ASSERT_TRUE(responder.write_message(from_hex(v["msg_1_payload"]), msg, error)) << error;
    EXPECT_EQ(to_hex(msg), v["msg_1_ciphertext"]);
    ASSERT_TRUE(initiator.read_message(msg, payload, error)) << error;
    EXPECT_EQ(to_hex(payload), v["msg_1_payload"]);
    ASSERT_TRUE(initiator.complete() && responder.complete());
    EXPECT_EQ(initiator.handshake_hash(), responder.handshake_hash());

    // After the handshake: message 2 goes initiator to responder, 3 back.
    CipherState i_send, i_receive, r_send, r_receive;
    initiator.split(i_send, i_receive);
    responder.split(r_send, r_receive);
    for (auto [index, send, receive] : {std::tuple{2, &i_send, &r_receive}, std::tuple{3, &r_send, &i_receive}}) {
      const std::string n = std::to_string(index);
      const auto plain = from_hex(v["msg_" + n + "_payload"]);
      msg.clear();
      ASSERT_TRUE(send->encrypt_with_ad({}, plain, msg));
      EXPECT_EQ(to_hex(msg), v["msg_" + n + "_ciphertext"]);
      std::vector<uint8_t> opened(msg.size() - kTagBytes);
      ASSERT_TRUE(receive->decrypt_with_ad({}, msg, opened.data()));
      EXPECT_EQ(opened, plain);
    }
  }
}

TEST(NoiseHandshake, ProloguesMustMatch) {
  const KeyPair node = generate_keypair(), client = generate_keypair();
  const std::string a = "troupe secure session 1", b = "troupe secure session 2";
  HandshakeIK initiator(Role::Initiator, client, {reinterpret_cast<const uint8_t*>(a.data()), a.size()},
                        &node.public_key);
  HandshakeIK responder(Role::Responder, node, {reinterpret_cast<const uint8_t*>(b.data()), b.size()});
  std::vector<uint8_t> msg, payload;
  std::string error;
  ASSERT_TRUE(initiator.write_message({}, msg, error));
  EXPECT_FALSE(responder.read_message(msg, payload, error));
  EXPECT_TRUE(responder.failed());
  EXPECT_NE(error.find("does not authenticate"), std::string::npos) << error;
}

TEST(NoiseHandshake, OutOfTurnIsRefused) {
  const KeyPair node = generate_keypair();
  HandshakeIK responder(Role::Responder, node, {});
  std::vector<uint8_t> msg;
  std::string error;
  EXPECT_FALSE(responder.write_message({}, msg, error));
  EXPECT_NE(error.find("out of turn"), std::string::npos) << error;
}

// Two transports joined in memory; `deliver` hands what one wrote to the other.
struct Session {
  KeyPair node = generate_keypair();
  KeyPair client = generate_keypair();
  Key expected_node_key = node.public_key;
  std::function<bool(const Key&, std::string&)> accept;
  std::unique_ptr<NoiseTransport> c, n;
  FrameReader c_frames{1u << 22}, n_frames{1u << 22};
  std::vector<uint8_t> c_out, n_out;
  std::string c_error, n_error;

  void start() {
    c = std::make_unique<NoiseTransport>(SecureOptions{Role::Initiator, client, expected_node_key, nullptr});
    n = std::make_unique<NoiseTransport>(SecureOptions{Role::Responder, node, {}, accept});
    c->begin(c_out);
    n->begin(n_out);
  }
  // Client bytes to the node, in chunks of `chunk` bytes (0: at once).
  bool to_node(std::span<const uint8_t> bytes, size_t chunk = 0) {
    return feed(*n, bytes, n_frames, n_out, n_error, chunk);
  }
  bool to_client(std::span<const uint8_t> bytes, size_t chunk = 0) {
    return feed(*c, bytes, c_frames, c_out, c_error, chunk);
  }
  static bool feed(NoiseTransport& t, std::span<const uint8_t> bytes, FrameReader& frames, std::vector<uint8_t>& out,
                   std::string& error, size_t chunk) {
    if (chunk == 0) chunk = bytes.size();
    for (size_t at = 0; at < bytes.size(); at += chunk) {
      if (!t.inbound(bytes.subspan(at, std::min(chunk, bytes.size() - at)), frames, out, error)) return false;
    }
    return true;
  }
  // The whole handshake; true when both sides are ready.
  bool handshake(size_t chunk = 0) {
    start();
    auto first = take(c_out);
    if (!to_node(first, chunk)) return false;
    auto second = take(n_out);
    if (!to_client(second, chunk)) return false;
    return c->ready() && n->ready();
  }
  static std::vector<uint8_t> take(std::vector<uint8_t>& v) { return std::exchange(v, {}); }
  // What the client seals for `frames` (the wire bytes).
  std::vector<uint8_t> client_seals(std::span<const uint8_t> frames) {
    std::vector<uint8_t> out;
    c->outbound(frames, out);
    return out;
  }
};

std::vector<uint8_t> next_frame(FrameReader& r) {
  auto f = r.next();
  return {f.begin(), f.end()};
}

TEST(NoiseTransport, HandshakeThenFramesBothWays) {
  Session s;
  ASSERT_TRUE(s.handshake()) << s.c_error << s.n_error;
  EXPECT_EQ(s.c->peer_key(), s.node.public_key);
  EXPECT_EQ(s.n->peer_key(), s.client.public_key);
  const auto a = test_frame(100, 1), b = test_frame(3, 2);
  ASSERT_TRUE(s.to_node(s.client_seals(a)));
  EXPECT_EQ(next_frame(s.n_frames), a);
  std::vector<uint8_t> back;
  s.n->outbound(b, back);
  ASSERT_TRUE(s.to_client(back));
  EXPECT_EQ(next_frame(s.c_frames), b);
  EXPECT_EQ(s.c->messages_out(), 1u);
  EXPECT_EQ(s.c->messages_in(), 1u);
}

TEST(NoiseTransport, NothingIsSentBeforeTheHandshake) {
  Session s;
  s.start();
  std::vector<uint8_t> out;
  s.c->outbound(test_frame(10, 0), out);
  EXPECT_TRUE(out.empty());
  EXPECT_FALSE(s.c->ready());
}

TEST(NoiseTransport, ByteAtATime) {
  Session s;
  ASSERT_TRUE(s.handshake(1)) << s.c_error << s.n_error;
  const auto a = test_frame(70, 9);
  ASSERT_TRUE(s.to_node(s.client_seals(a), 1));
  EXPECT_EQ(next_frame(s.n_frames), a);
}

TEST(NoiseTransport, FramesOverOneMessageAreSplitAndReassembled) {
  Session s;
  ASSERT_TRUE(s.handshake());
  const auto big = test_frame(200'000, 5);
  const auto wire = s.client_seals(big);
  const auto messages = split_messages(wire);
  ASSERT_EQ(messages.size(), (big.size() + kMaxPlainBytes - 1) / kMaxPlainBytes);
  for (const auto& m : messages) EXPECT_LE(m.size(), 2 + kMaxMessageBytes);
  EXPECT_EQ(messages.front().size(), 2 + kMaxMessageBytes);
  ASSERT_TRUE(s.to_node(wire, 1000)) << s.n_error;
  EXPECT_EQ(next_frame(s.n_frames), big);
  EXPECT_EQ(s.n->messages_in(), messages.size());
}

// Two transport messages from the client, recorded.
struct Recorded {
  Session s;
  std::vector<std::vector<uint8_t>> m;
  Recorded() {
    EXPECT_TRUE(s.handshake());
    auto wire = s.client_seals(test_frame(40, 1));
    auto more = s.client_seals(test_frame(40, 2));
    wire.insert(wire.end(), more.begin(), more.end());
    m = split_messages(wire);
  }
  // The node refuses `bytes`, says why, and stays refusing afterwards.
  void expect_session_ended(std::span<const uint8_t> bytes, const std::string& why) {
    EXPECT_FALSE(s.to_node(bytes));
    EXPECT_NE(s.n_error.find(why), std::string::npos) << s.n_error;
    s.n_error.clear();
    auto fresh = s.client_seals(test_frame(10, 3));
    EXPECT_FALSE(s.to_node(fresh)) << "a session that refused a message must stay ended";
    EXPECT_NE(s.n_error.find(why), std::string::npos) << s.n_error;
  }
};

TEST(NoiseTransport, ReplayedMessageEndsTheSession) {
  Recorded r;
  ASSERT_TRUE(r.s.to_node(r.m[0]));
  ASSERT_FALSE(next_frame(r.s.n_frames).empty());
  r.expect_session_ended(r.m[0], "does not authenticate");
  EXPECT_TRUE(next_frame(r.s.n_frames).empty());
}

TEST(NoiseTransport, ReorderedOrDroppedMessageEndsTheSession) {
  Recorded r;
  r.expect_session_ended(r.m[1], "does not authenticate");
  EXPECT_TRUE(next_frame(r.s.n_frames).empty());
}

TEST(NoiseTransport, AlteredMessageEndsTheSession) {
  const size_t body = 2 + 44 + kTagBytes;  // prefix, frame, tag
  for (size_t at : {size_t{2}, size_t{20}, body - kTagBytes, body - 1}) {
    SCOPED_TRACE("byte " + std::to_string(at) + " flipped");
    Recorded r;
    ASSERT_EQ(r.m[0].size(), body);
    r.m[0][at] ^= 0x01;
    r.expect_session_ended(r.m[0], "does not authenticate");
    EXPECT_TRUE(next_frame(r.s.n_frames).empty());
  }
}

TEST(NoiseTransport, TruncatedMessageEndsTheSession) {
  Recorded r;
  auto cut = r.m[0];
  cut.erase(cut.end() - 5, cut.end());
  const size_t n = cut.size() - 2;
  cut[0] = static_cast<uint8_t>(n >> 8);
  cut[1] = static_cast<uint8_t>(n);
  r.expect_session_ended(cut, "does not authenticate");

  Recorded tiny;
  const std::vector<uint8_t> short_message = {0, 3, 1, 2, 3};
  tiny.expect_session_ended(short_message, "shorter than its 16-byte tag");
}

TEST(NoiseTransport, WrongNodeKeyIsRefusedByTheNode) {
  Session s;
  s.expected_node_key = generate_keypair().public_key;
  EXPECT_FALSE(s.handshake());
  EXPECT_NE(s.n_error.find("does not hold this node's public key"), std::string::npos) << s.n_error;
  EXPECT_TRUE(s.n_out.empty()) << "the node must not answer a client that does not know its key";
}

TEST(NoiseTransport, AlteredNodeAnswerIsRefusedByTheClient) {
  Session s;
  s.start();
  ASSERT_TRUE(s.to_node(Session::take(s.c_out)));
  auto answer = Session::take(s.n_out);
  answer.back() ^= 0x80;
  EXPECT_FALSE(s.to_client(answer));
  EXPECT_NE(s.c_error.find("does not hold the private key"), std::string::npos) << s.c_error;
  EXPECT_FALSE(s.c->ready());
}

TEST(NoiseTransport, AlteredFirstMessageIsRefused) {
  for (size_t at : {size_t{2}, size_t{40}, size_t{97}}) {
    SCOPED_TRACE("byte " + std::to_string(at) + " flipped");
    Session s;
    s.start();
    auto first = Session::take(s.c_out);
    ASSERT_EQ(first.size(), 2 + kMessage1Bytes);
    first[at] ^= 0x04;
    EXPECT_FALSE(s.to_node(first));
    EXPECT_NE(s.n_error.find("does not authenticate"), std::string::npos) << s.n_error;
    EXPECT_TRUE(s.n_out.empty());
  }
}

TEST(NoiseTransport, UnknownClientIsRefused) {
  Session s;
  const Key allowed = generate_keypair().public_key;
  s.accept = [&](const Key& client, std::string& why) {
    if (client == allowed) return true;
    why = "key " + to_hex(client) + " is not in the node's list";
    return false;
  };
  EXPECT_FALSE(s.handshake());
  EXPECT_NE(s.n_error.find("client refused: key " + to_hex(s.client.public_key)), std::string::npos) << s.n_error;
  EXPECT_TRUE(s.n_out.empty());

  Session known;
  known.accept = [&](const Key& client, std::string&) { return client == known.client.public_key; };
  EXPECT_TRUE(known.handshake()) << known.n_error;
}

TEST(NoiseTransport, SmallOrderEphemeralKeyIsRefused) {
  Session s;
  s.start();
  auto first = Session::take(s.c_out);
  std::fill(first.begin() + 2, first.begin() + 2 + kKeyBytes, 0);
  EXPECT_FALSE(s.to_node(first));
  EXPECT_NE(s.n_error.find("small order"), std::string::npos) << s.n_error;
}

TEST(NoiseTransport, PlainPeersGetOneClearError) {
  // A plain client's first frame at a secure node: refused on its first
  // two bytes, without waiting for the length they seem to announce.
  Session s;
  s.start();
  const auto hello = test_frame(120, 0);
  EXPECT_FALSE(s.to_node(std::span(hello).first(2)));
  EXPECT_NE(s.n_error.find("did not open a secure session"), std::string::npos) << s.n_error;

  // A plain node's first frame at a secure client.
  Session t;
  t.start();
  EXPECT_FALSE(t.to_client(hello));
  EXPECT_NE(t.c_error.find("did not answer with a secure handshake"), std::string::npos) << t.c_error;
}

TEST(NoiseTransport, BeginStartsAFreshSessionAfterAFailure) {
  Recorded r;
  EXPECT_FALSE(r.s.to_node(r.m[1]));
  ASSERT_TRUE(r.s.handshake()) << r.s.n_error;
  const auto a = test_frame(12, 4);
  ASSERT_TRUE(r.s.to_node(r.s.client_seals(a)));
  EXPECT_EQ(next_frame(r.s.n_frames), a);
}

TEST(NoiseTransport, EveryHandshakeUsesFreshKeys) {
  Session a, b;
  ASSERT_TRUE(a.handshake());
  b.node = a.node;
  b.client = a.client;
  b.expected_node_key = a.node.public_key;
  ASSERT_TRUE(b.handshake());
  const auto f = test_frame(16, 1);
  EXPECT_NE(a.client_seals(f), b.client_seals(f)) << "the same keys must give different sessions";
}

}  // namespace
}  // namespace troupe::wire::noise
