// The viewer's server over real sockets: the page files over HTTP, and a
// WebSocket client speaking the wire protocol through the bridge to
// troupe-sim's node (run in-process on its own thread), as the page does.
// Bad input closes only the WebSocket that sent it.
#include <gtest/gtest.h>

#include <boost/asio/connect.hpp>
#include <boost/asio/io_context.hpp>
#include <boost/asio/ip/tcp.hpp>
#include <boost/beast/core.hpp>
#include <boost/beast/http.hpp>
#include <boost/beast/websocket.hpp>
#include <optional>
#include <thread>

#include "host-sim/troupe_sim/runner.h"
#include "host-sim/viewer/view_server.h"
#include "tests/attack/web_peer.h"
#include "tests/sim/temp_dir.h"
#include "tests/viewer/page.h"
#include "wire/frame.h"
#include "wire/writer.h"

namespace troupe::viewer {
namespace {

namespace net = boost::asio;
namespace beast = boost::beast;
namespace http = beast::http;
namespace websocket = beast::websocket;
using net::ip::tcp;

// A 10 x 6 m room with r0 (a laser) and r1.
const char* kWorld = R"(
resolution 0.05
interval_sim 100
model ( name "room" size [10.4 6.4] color "gray30"
  block ( points 4 point[0] [0 0] point[1] [10.4 0] point[2] [10.4 0.2] point[3] [0 0.2] )
  block ( points 4 point[0] [0 6.2] point[1] [10.4 6.2] point[2] [10.4 6.4] point[3] [0 6.4] ) )
define bot position ( size [0.4 0.3] )
bot ( name "r0" pose [0 0 0 0] color "red" ranger ( sensor ( range [0 8] fov 180 samples 181 ) ) )
bot ( name "r1" pose [-3 2 0 90] )
)";

// The bridge's frame limit in these tests, bytes.
constexpr uint32_t kFrameLimit = 64 * 1024;

const wire::Message* msg(const std::vector<uint8_t>& f) {
  return wire::trusted_message(f);
}

class BridgeTest : public ::testing::Test {
 protected:
  void SetUp() override {
    sim::SimOptions o;
    o.world = dir_.write("w.world", kWorld);
    o.port = 0;
    o.paused = true;
    world::Diagnostics d;
    std::string error;
    ASSERT_TRUE(runner_.init(o, d, error)) << d.str() << error;
    thread_ = std::thread([this] { runner_.run(); });
    dir_.write("web/index.html", "<title>the page</title>");
    ViewOptions vo;
    vo.http_port = 0;
    vo.node_port = runner_.port();
    vo.web_root = dir_.path("web");
    vo.limits.max_frame_bytes = kFrameLimit;
    server_ = std::make_unique<ViewServer>(vo);
    ASSERT_TRUE(server_->open(error)) << error;
    server_->start_thread();
  }
  void TearDown() override {
    server_.reset();
    runner_.request_stop();
    if (thread_.joinable()) thread_.join();
  }

  std::span<const uint8_t> hello() {
    auto& b = w_.start();
    auto body = wire::CreateHello(b, wire::kProtocolVersion, b.CreateString("bridge-test"), 1u << 20);
    return w_.finish(wire::make_header({}, wire::Kind::Hello, 0, 0, 0), wire::Body::Hello, body.Union());
  }
  std::span<const uint8_t> simple(wire::Address a, wire::Kind kind, uint8_t sub, uint32_t seq) {
    w_.start();
    return w_.finish(wire::make_header(a, kind, sub, seq, 0));
  }

  test::TempDir dir_;
  sim::Runner runner_;
  std::thread thread_;
  std::unique_ptr<ViewServer> server_;
  wire::MessageWriter w_;
  const wire::Address sim_{0, uint16_t(wire::Interface::Simulation), 0};
  const wire::Address map_{0, uint16_t(wire::Interface::Map), 0};
};

http::response<http::string_body> get(uint16_t port, const std::string& target) {
  net::io_context io;
  beast::tcp_stream s(io);
  tcp::resolver resolver(io);
  s.connect(resolver.resolve("127.0.0.1", std::to_string(port)));
  http::request<http::empty_body> req(http::verb::get, target, 11);
  req.set(http::field::host, "127.0.0.1");
  http::write(s, req);
  beast::flat_buffer buf;
  http::response<http::string_body> res;
  http::read(s, buf, res);
  return res;
}

TEST_F(BridgeTest, ServesThePageAndNothingElse) {
  auto res = get(server_->port(), "/");
  EXPECT_EQ(res.result(), http::status::ok);
  EXPECT_EQ(res.body(), "<title>the page</title>");
  EXPECT_EQ(res[http::field::content_type], "text/html; charset=utf-8");
  EXPECT_EQ(get(server_->port(), "/../w.world").result(), http::status::not_found);
  EXPECT_EQ(get(server_->port(), "/missing.js").result(), http::status::not_found);
  EXPECT_EQ(server_->url(), "http://127.0.0.1:" + std::to_string(server_->port()) + "/");
}

TEST_F(BridgeTest, APageSeesTheRobotsTheMapAndTheirPoses) {
  Page page(server_->port());
  page.send(hello());
  page.send(simple({}, wire::Kind::DeviceList, 0, 1));
  auto list = page.reply(1);
  ASSERT_FALSE(list.empty());
  std::vector<std::pair<uint16_t, uint16_t>> ifaces;
  for (const auto* d : *msg(list)->body_as_DeviceList()->devices()) {
    ifaces.emplace_back(d->addr()->robot(), d->addr()->iface());
  }
  EXPECT_NE(std::find(ifaces.begin(), ifaces.end(), std::pair<uint16_t, uint16_t>(0, 11)), ifaces.end());
  EXPECT_NE(std::find(ifaces.begin(), ifaces.end(), std::pair<uint16_t, uint16_t>(0, 10)), ifaces.end());

  page.send(simple(sim_, wire::Kind::Request, uint8_t(wire::SimulationReqSub::Models), 2));
  auto models = page.reply(2);
  ASSERT_FALSE(models.empty());
  const auto* list2 = msg(models)->body_as_SimModelList();
  ASSERT_NE(list2, nullptr);
  ASSERT_EQ(list2->models()->size(), 2u);
  EXPECT_EQ(list2->models()->Get(0)->name()->str(), "r0");
  EXPECT_EQ(list2->models()->Get(1)->robot(), 1);
  EXPECT_FLOAT_EQ(list2->models()->Get(0)->size_x(), 0.4f);
  EXPECT_FLOAT_EQ(list2->models()->Get(0)->size_y(), 0.3f);
  EXPECT_EQ(list2->models()->Get(0)->color(), 0xFF0000u);

  // The map covers the room (10.4 x 6.4 m around the origin, 5 cm cells);
  // its bottom wall (y from -3.2 to -3.0) is occupied, the middle is free.
  page.send(simple(map_, wire::Kind::Request, uint8_t(wire::MapReqSub::Info), 3));
  auto info = page.reply(3);
  ASSERT_FALSE(info.empty());
  const auto* mi = msg(info)->body_as_MapInfo();
  ASSERT_NE(mi, nullptr);
  EXPECT_FLOAT_EQ(mi->resolution(), 0.05f);
  const double x0 = mi->origin()->x(), y0 = mi->origin()->y();
  EXPECT_LE(x0, -5.2);
  EXPECT_LE(y0, -3.2);
  EXPECT_GE(x0 + mi->width() * mi->resolution(), 5.2);
  EXPECT_GE(y0 + mi->height() * mi->resolution(), 3.2);
  auto cell_at = [&](double x, double y, uint32_t seq) {
    auto& b = w_.start();
    const auto col = uint32_t((x - x0) / mi->resolution()), row = uint32_t((y - y0) / mi->resolution());
    auto tile_req = wire::CreateMapTileRequest(b, col, row, 1, 1);
    page.send(w_.finish(wire::make_header(map_, wire::Kind::Request, uint8_t(wire::MapReqSub::Tile), seq, 0),
                        wire::Body::MapTileRequest, tile_req.Union()));
    auto tile = page.reply(seq);
    const wire::MapTile* t = tile.empty() ? nullptr : msg(tile)->body_as_MapTile();
    return t && t->cells() && t->cells()->size() == 1 ? int(t->cells()->Get(0) & 3) : -1;
  };
  EXPECT_EQ(cell_at(0, -3.1, 40), int(wire::Cell::Occupied));
  EXPECT_EQ(cell_at(0, 0, 41), int(wire::Cell::Free));
  EXPECT_EQ(cell_at(2, 3.1, 42), int(wire::Cell::Occupied));

  // Ground truth at once for a new reader of simulation:0, then after each
  // step while someone reads it.
  auto& ob = w_.start();
  auto open = wire::CreateOpen(ob, wire::Access::All);
  page.send(w_.finish(wire::make_header(sim_, wire::Kind::Open, 0, 5, 0), wire::Body::Open, open.Union()));
  ASSERT_FALSE(page.reply(5).empty());
  auto current = page.data(wire::Body::SimPoses);
  ASSERT_FALSE(current.empty());
  EXPECT_EQ(msg(current)->body_as_SimPoses()->sim_time_us(), 0u);
  auto& sb = w_.start();
  auto step = wire::CreateSimStep(sb, 1);
  page.send(
      w_.finish(wire::make_header(sim_, wire::Kind::Request, uint8_t(wire::SimulationReqSub::Step), 6, 0),
                wire::Body::SimStep, step.Union()));
  auto poses = page.data(wire::Body::SimPoses);
  ASSERT_FALSE(poses.empty());
  const auto* p = msg(poses)->body_as_SimPoses();
  ASSERT_EQ(p->poses()->size(), 2u);
  EXPECT_NEAR(p->poses()->Get(1)->x(), -3, 1e-5);
  EXPECT_NEAR(p->poses()->Get(1)->y(), 2, 1e-5);
  EXPECT_EQ(p->sim_time_us(), 100000u);
}

TEST_F(BridgeTest, BadInputClosesOnlyThatPage) {
  Page good(server_->port());
  good.send(hello());
  good.send(simple({}, wire::Kind::DeviceList, 0, 1));
  ASSERT_FALSE(good.reply(1).empty());

  Page garbage(server_->port());
  const std::vector<uint8_t> junk = {0xde, 0xad, 0xbe, 0xef, 1, 2, 3};
  garbage.send(junk);
  EXPECT_TRUE(garbage.closed());
  EXPECT_EQ(garbage.close_reason().code, websocket::close_code::bad_payload);
  EXPECT_NE(reason(garbage).find("one size-prefixed frame"), std::string::npos) << reason(garbage);

  // A correct prefix over bytes the verifier refuses.
  Page forged(server_->port());
  std::vector<uint8_t> bad = {12, 0, 0, 0, 0xff, 0xff, 0xff, 0x7f, 0, 0, 0, 0, 0, 0, 0, 0};
  forged.send(bad);
  EXPECT_TRUE(forged.closed());
  EXPECT_EQ(forged.close_reason().code, websocket::close_code::bad_payload);
  EXPECT_NE(reason(forged).find("frame refused"), std::string::npos) << reason(forged);

  // A message over the frame limit is refused before it is buffered.
  Page huge(server_->port());
  huge.send(std::vector<uint8_t>(kFrameLimit + 1, 0));
  EXPECT_TRUE(huge.closed());
  EXPECT_EQ(huge.close_reason().code, websocket::close_code::too_big);

  // Not HTTP at all on the page's port.
  {
    net::io_context io;
    tcp::socket s(io);
    tcp::resolver resolver(io);
    net::connect(s, resolver.resolve("127.0.0.1", std::to_string(server_->port())));
    net::write(s, net::buffer(std::string("\x16\x03\x01 not http\r\n\r\n")));
    beast::error_code ec;
    std::array<char, 256> sink;
    while (!ec) s.read_some(net::buffer(sink), ec);  // the server closes it
    EXPECT_TRUE(ec == net::error::eof || ec == net::error::connection_reset) << ec.message();
  }

  // The first page goes on, and the page is still served.
  good.send(simple({}, wire::Kind::DeviceList, 0, 2));
  EXPECT_FALSE(good.reply(2).empty());
  EXPECT_EQ(get(server_->port(), "/").result(), http::status::ok);
}

// The status of a WebSocket handshake with these Host and Origin headers
// (no Origin when empty), and the body of a refusal: a hand-made handshake,
// as a hostile page's browser sends it.
int handshake_status(uint16_t port, const std::string& host, const std::string& origin,
                     std::string* body = nullptr) {
  attack::WebPeer page;
  return page.handshake(port, host, origin, body);
}

TEST_F(BridgeTest, OnlyTheViewersOwnPagesMayOpenAWebSocket) {
  const std::string self = "127.0.0.1:" + std::to_string(server_->port());
  EXPECT_EQ(handshake_status(server_->port(), self, "http://" + self), 101);
  EXPECT_EQ(handshake_status(server_->port(), "localhost:" + std::to_string(server_->port()),
                             "http://localhost:" + std::to_string(server_->port())),
            101);
  // A page from elsewhere, opened in the same browser.
  std::string body;
  EXPECT_EQ(handshake_status(server_->port(), self, "http://evil.example", &body), 403);
  EXPECT_NE(body.find("may not use this viewer"), std::string::npos) << body;
  EXPECT_EQ(handshake_status(server_->port(), self, "null"), 403);
  // DNS rebinding: evil.example made to resolve to this machine, so its
  // page and the Host it sends agree.
  const std::string rebound = "evil.example:" + std::to_string(server_->port());
  EXPECT_EQ(handshake_status(server_->port(), rebound, "http://" + rebound, &body), 403);
  EXPECT_NE(body.find("DNS rebinding"), std::string::npos) << body;
  // The page itself is still served, and its WebSocket still works.
  EXPECT_EQ(get(server_->port(), "/").result(), http::status::ok);
  Page page(server_->port());
  page.send(hello());
  page.send(simple({}, wire::Kind::DeviceList, 0, 1));
  EXPECT_FALSE(page.reply(1).empty());
}

TEST_F(BridgeTest, AnOriginAllowedByOptionIsAccepted) {
  ViewOptions vo;
  vo.http_port = 0;
  vo.node_port = runner_.port();
  vo.allow_origins = {"http://robots.lab:8080"};
  ViewServer proxied(vo);
  std::string error;
  ASSERT_TRUE(proxied.open(error)) << error;
  proxied.start_thread();
  EXPECT_EQ(handshake_status(proxied.port(), "robots.lab:8080", "http://robots.lab:8080"), 101);
  EXPECT_EQ(handshake_status(proxied.port(), "robots.lab:8080", "http://robots.lab:9090"), 403);
}

// A viewer listening beyond loopback is a remote control for every robot
// to anyone who reaches its port: it answers only requests that show the
// token printed in its URL, and hands the page a cookie with it.
TEST_F(BridgeTest, AViewerBeyondLoopbackAsksEveryRequestForItsToken) {
  ViewOptions vo;
  vo.listen = "0.0.0.0";
  vo.http_port = 0;
  vo.node_port = runner_.port();
  vo.web_root = dir_.path("web");
  ViewServer lab(vo);
  std::string error;
  ASSERT_TRUE(lab.open(error)) << error;
  lab.start_thread();
  const uint16_t port = lab.port();
  const std::string url = lab.url();
  const size_t at = url.find("/?token=");
  ASSERT_NE(at, std::string::npos) << url;
  const std::string token = url.substr(at + 8);
  EXPECT_EQ(token.size(), 32u) << url;

  // Without it: neither the page nor a WebSocket.
  const std::string self = "127.0.0.1:" + std::to_string(port);
  auto refused = get(port, "/");
  EXPECT_EQ(refused.result(), http::status::forbidden);
  EXPECT_NE(refused.body().find("open the URL it printed"), std::string::npos) << refused.body();
  EXPECT_EQ(get(port, "/?token=" + std::string(32, '0')).result(), http::status::forbidden);
  EXPECT_EQ(handshake_status(port, self, "http://" + self), 403);

  // With it: the page, and the cookie the page's other requests carry.
  auto page = get(port, "/?token=" + token);
  EXPECT_EQ(page.result(), http::status::ok);
  EXPECT_EQ(page.body(), "<title>the page</title>");
  const std::string cookie(page[http::field::set_cookie]);
  EXPECT_EQ(cookie, "troupe_view_token=" + token + "; Path=/; HttpOnly; SameSite=Strict");
  const std::string upgrade =
      "GET /ws HTTP/1.1\r\nHost: " + self + "\r\nOrigin: http://" + self +
      "\r\nUpgrade: websocket\r\nConnection: Upgrade\r\nSec-WebSocket-Key: dGhlIHNhbXBsZSBub25jZQ==\r\n"
      "Sec-WebSocket-Version: 13\r\nCookie: troupe_view_token=" +
      token + "\r\n\r\n";
  EXPECT_EQ(attack::http_exchange(port, upgrade).status, 101);
}

// The 44-byte frame (a Hello whose body is absent) passes the bridge's
// verifier and reaches the node: the simulator must refuse it and go on.
TEST_F(BridgeTest, ANullBodyFrameThroughTheBridgeLeavesTheSimulatorServing) {
  Page bad(server_->port());
  w_.start();
  bad.send(w_.finish(wire::make_header({}, wire::Kind::Hello, 0, 0, 0), wire::Body::Hello));
  w_.start();
  bad.send(w_.finish(wire::make_header({}, wire::Kind::TimeSync, 0, 1, 0), wire::Body::TimeSync));
  bad.send(simple({}, wire::Kind::DeviceList, 0, 2));
  bad.reply(2);  // answered, or the WebSocket closed: either way, no crash
  Page good(server_->port());
  good.send(hello());
  good.send(simple({}, wire::Kind::DeviceList, 0, 3));
  EXPECT_FALSE(good.reply(3).empty());
}

TEST(BridgeNoNode, APageLearnsTheNodeIsUnreachable) {
  // A port nothing listens on: bind one, note it, close it.
  net::io_context io;
  tcp::acceptor a(io, tcp::endpoint(net::ip::make_address("127.0.0.1"), 0));
  const uint16_t dead = a.local_endpoint().port();
  a.close();
  ViewOptions vo;
  vo.http_port = 0;
  vo.node_port = dead;
  ViewServer server(vo);
  std::string error;
  ASSERT_TRUE(server.open(error)) << error;
  server.start_thread();
  Page page(server.port());
  EXPECT_TRUE(page.closed());
  EXPECT_EQ(page.close_reason().code, websocket::close_code::try_again_later);
  EXPECT_NE(reason(page).find("cannot reach the node"), std::string::npos);
}

TEST(BridgeNoNode, ABusyPortIsAClearError) {
  net::io_context io;
  tcp::acceptor a(io, tcp::endpoint(net::ip::make_address("127.0.0.1"), 0));
  ViewOptions vo;
  vo.http_port = a.local_endpoint().port();
  ViewServer server(vo);
  std::string error;
  EXPECT_FALSE(server.open(error));
  EXPECT_NE(error.find("cannot listen on 127.0.0.1:" + std::to_string(vo.http_port)), std::string::npos)
      << error;
}

}  // namespace
}  // namespace troupe::viewer
