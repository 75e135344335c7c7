#include "host-sim/viewer/view_server.h"

#include <unistd.h>

#include <boost/asio/io_context.hpp>
#include <boost/beast/core.hpp>
#include <boost/beast/http.hpp>
#include <boost/beast/websocket.hpp>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "host-sim/viewer/access_token.h"
#include "host-sim/viewer/bridge_session.h"
#include "host-sim/viewer/origin_check.h"
#include "host-sim/viewer/server_state.h"
#include "host-sim/viewer/web_files.h"
#include "runtime/exposure.h"
#include "runtime/log.h"

namespace troupe::viewer {

namespace beast = boost::beast;
namespace http = beast::http;
using boost::asio::ip::tcp;

namespace {

// Page files are small; a bigger file in the web root is not served.
constexpr uintmax_t kMaxFileBytes = 16u << 20;
// Browsers send a few KiB of headers; a request beyond this is refused.
constexpr uint32_t kMaxRequestBytes = 16u << 10;

// One HTTP connection: files by GET, or the upgrade to a bridge on /ws.
class HttpSession : public std::enable_shared_from_this<HttpSession> {
 public:
  HttpSession(tcp::socket socket, std::shared_ptr<ServerState> server)
      : stream_(std::move(socket)), server_(std::move(server)) {}

  void read() {
    parser_.emplace();
    parser_->header_limit(kMaxRequestBytes);
    parser_->body_limit(kMaxRequestBytes);
    stream_.expires_after(std::chrono::seconds(30));
    http::async_read(stream_, buffer_, *parser_,
                     beast::bind_front_handler(&HttpSession::on_read, shared_from_this()));
  }

 private:
  void on_read(beast::error_code ec, size_t) {
    if (ec) return;  // closed, timed out or malformed: the socket closes
    http::request<http::string_body> req = parser_->release();
    set_cookie_.clear();
    if (const std::string& token = server_->options.token; !token.empty()) {
      const std::string_view target(req.target().data(), req.target().size());
      if (!token_matches(presented_token(target, field(req, http::field::cookie)), token)) {
        if (log_this_one(server_->refused_tokens)) {
          log_warn("viewer: request without the viewer's token refused (%llu so far)",
                   static_cast<unsigned long long>(server_->refused_tokens));
        }
        return reply(req, http::status::forbidden,
                     "This viewer serves a network: open the URL it printed, with its token.\n");
      }
      // The page's files and its WebSocket then carry it as a cookie.
      set_cookie_ = std::string(kTokenCookie) + "=" + token + "; Path=/; HttpOnly; SameSite=Strict";
    }
    if (beast::websocket::is_upgrade(req)) {
      if (req.target() != "/ws") return reply(req, http::status::not_found, "WebSockets are served on /ws\n");
      const OriginVerdict verdict =
          check_origin(field(req, http::field::host), field(req, http::field::origin),
                       server_->options.allow_origins, server_->machine_names);
      if (!verdict.allowed) {
        if (log_this_one(server_->refused_origins)) {
          log_warn("viewer: WebSocket refused (%llu so far): %s",
                   static_cast<unsigned long long>(server_->refused_origins), verdict.why.c_str());
        }
        return reply(req, http::status::forbidden, verdict.why + "\n");
      }
      if (server_->sessions >= server_->options.max_sessions) {
        return reply(req, http::status::service_unavailable, "too many viewers connected\n");
      }
      auto bridge = std::make_shared<BridgeSession>(stream_.release_socket(), server_);
      return bridge->start(std::move(req));
    }
    if (req.method() != http::verb::get && req.method() != http::verb::head) {
      return reply(req, http::status::method_not_allowed, "only GET\n");
    }
    const std::string name = web_file_name(std::string_view(req.target().data(), req.target().size()));
    if (name.empty()) return reply(req, http::status::not_found, "no such file\n");
    const std::filesystem::path path = std::filesystem::path(server_->options.web_root) / name;
    std::error_code fec;
    const uintmax_t size = std::filesystem::file_size(path, fec);
    if (fec || !std::filesystem::is_regular_file(path) || size > kMaxFileBytes) {
      if (name == "index.html") {
        return reply(req, http::status::not_found,
                     "The viewer's page is not in " + server_->options.web_root +
                         " (was the build able to run npm? see host-sim/viewer/README.md)\n");
      }
      return reply(req, http::status::not_found, "no such file\n");
    }
    std::ifstream in(path, std::ios::binary);
    std::ostringstream body;
    body << in.rdbuf();
    reply(req, http::status::ok, body.str(), content_type(name));
  }

  static std::string_view field(const http::request<http::string_body>& req, http::field f) {
    const auto it = req.find(f);
    return it == req.end() ? std::string_view() : std::string_view(it->value().data(), it->value().size());
  }

  void reply(const http::request<http::string_body>& req, http::status status, std::string body,
             std::string_view type = "text/plain; charset=utf-8") {
    auto res = std::make_shared<http::response<http::string_body>>(status, req.version());
    res->set(http::field::server, "troupe-viewer");
    res->set(http::field::content_type, std::string(type));
    res->set(http::field::cache_control, "no-store");
    if (!set_cookie_.empty()) res->set(http::field::set_cookie, set_cookie_);
    res->keep_alive(req.keep_alive());
    if (req.method() != http::verb::head) res->body() = std::move(body);
    res->prepare_payload();
    http::async_write(stream_, *res, [self = shared_from_this(), res](beast::error_code ec, size_t) {
      if (ec || !res->keep_alive()) {
        beast::error_code ignored;
        self->stream_.socket().shutdown(tcp::socket::shutdown_send, ignored);
        return;
      }
      self->read();
    });
  }

  beast::tcp_stream stream_;
  beast::flat_buffer buffer_;
  std::optional<http::request_parser<http::string_body>> parser_;
  std::shared_ptr<ServerState> server_;
  std::string set_cookie_;  // for the reply to a request that showed the token
};

}  // namespace

struct ViewServer::Impl {
  boost::asio::io_context io{1};
  tcp::acceptor acceptor{io};
  std::shared_ptr<ServerState> state = std::make_shared<ServerState>();

  void accept() {
    // The handler holds no owner: pending handlers die with `io`, which
    // this object owns.
    acceptor.async_accept(io, [this](beast::error_code ec, tcp::socket socket) {
      if (!acceptor.is_open()) return;
      if (!ec) std::make_shared<HttpSession>(std::move(socket), state)->read();
      accept();
    });
  }
};

std::string default_web_root() {
  std::error_code ec;
  const std::filesystem::path exe = std::filesystem::read_symlink("/proc/self/exe", ec);
  if (ec) return "viewer";
  return (exe.parent_path().parent_path() / "share" / "troupe" / "viewer").string();
}

ViewServer::ViewServer(ViewOptions options) : impl_(std::make_unique<Impl>()) {
  if (options.token.empty() && !loopback_only(options.listen)) options.token = make_token();
  impl_->state->options = std::move(options);
  impl_->state->machine_names = this_machine_names();
}

ViewServer::~ViewServer() {
  stop();
  if (thread_.joinable()) thread_.join();
}

bool ViewServer::open(std::string& error) {
  const ViewOptions& o = impl_->state->options;
  beast::error_code ec;
  tcp::resolver resolver(impl_->io);
  impl_->state->node = resolver.resolve(o.node_host, std::to_string(o.node_port), ec);
  if (ec) {
    error = "cannot resolve the node's address " + o.node_host + ": " + ec.message();
    return false;
  }
  if (o.keys.secure()) {
    auto secure = std::make_shared<wire::noise::SecureOptions>();
    if (!wire::noise::client_options(o.keys, o.node_host, o.node_port, *secure, error)) return false;
    impl_->state->secure = std::move(secure);
  }
  const auto address = boost::asio::ip::make_address(o.listen, ec);
  if (ec) {
    error = "bad listen address '" + o.listen + "': " + ec.message();
    return false;
  }
  const tcp::endpoint endpoint(address, o.http_port);
  tcp::acceptor& a = impl_->acceptor;
  if (a.open(endpoint.protocol(), ec); !ec) a.set_option(boost::asio::socket_base::reuse_address(true), ec);
  if (!ec) a.bind(endpoint, ec);
  if (!ec) a.listen(boost::asio::socket_base::max_listen_connections, ec);
  if (ec) {
    error = "cannot listen on " + o.listen + ":" + std::to_string(o.http_port) + ": " + ec.message();
    return false;
  }
  impl_->accept();
  return true;
}

uint16_t ViewServer::port() const {
  beast::error_code ec;
  const tcp::endpoint e = impl_->acceptor.local_endpoint(ec);
  return ec ? 0 : e.port();
}

std::string ViewServer::url() const {
  const std::string& host = impl_->state->options.listen;
  const bool any = host == "0.0.0.0" || host == "::";
  const std::string shown =
      any ? "127.0.0.1" : (host.find(':') != std::string::npos ? "[" + host + "]" : host);
  const std::string& token = impl_->state->options.token;
  return "http://" + shown + ":" + std::to_string(port()) + "/" + (token.empty() ? "" : "?token=" + token);
}

void ViewServer::run() {
  impl_->io.run();
}

void ViewServer::start_thread() {
  thread_ = std::thread([impl = impl_.get()] { impl->io.run(); });
}

void ViewServer::stop() {
  boost::asio::post(impl_->io, [impl = impl_.get()] {
    beast::error_code ignored;
    impl->acceptor.close(ignored);
  });
  impl_->io.stop();
}

}  // namespace troupe::viewer
