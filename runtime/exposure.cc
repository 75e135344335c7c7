#include "runtime/exposure.h"

#include <arpa/inet.h>

#include <cstring>

#include "runtime/log.h"

namespace troupe {
namespace {

constexpr uint64_t kWarnEveryUs = 60'000'000;  // a minute

}  // namespace

bool loopback_only(std::string_view listen) {
  if (listen.empty() || listen == "localhost") return true;  // empty: the default, localhost
  const std::string text(listen);
  in_addr v4{};
  if (inet_pton(AF_INET, text.c_str(), &v4) == 1) return (ntohl(v4.s_addr) >> 24) == 127;
  in6_addr v6{};
  return inet_pton(AF_INET6, text.c_str(), &v6) == 1 && std::memcmp(&v6, &in6addr_loopback, sizeof v6) == 0;
}

bool may_serve(const std::string& program, std::string_view listen, uint16_t port, bool secure, bool insecure,
               std::string& error) {
  if (secure || insecure || loopback_only(listen)) return true;
  error = program + ": serving " + std::string(listen) + ":" + std::to_string(port) +
          " in plain TCP would let any machine that reaches it read and command every device. Give it a key "
          "and its clients (troupe keygen; a node config's \"key\" and \"clients\", --secure FILE for "
          "troupe-sim and troupe play; wire/README.md, \"Secure sessions\"), listen on localhost, or say "
          "--insecure";
  return false;
}

PlainServiceWarning::PlainServiceWarning(EventLoop& loop, std::string where) : where_(std::move(where)) {
  on_timer(0);
  loop.start_timer(kWarnEveryUs, kWarnEveryUs, this);
}

void PlainServiceWarning::on_timer(TimerId) {
  log_warn("insecure: %s serves plain TCP; any machine that reaches it can read and command every device",
           where_.c_str());
}

}  // namespace troupe
