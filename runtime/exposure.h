// Who can reach a node. A node that serves beyond loopback without secure
// sessions lets every machine that reaches its port read and command every
// device: it must be asked for (`--insecure`), and it keeps saying so.
#pragma once

#include <string>
#include <string_view>

#include "runtime/event_loop.h"

namespace troupe {

/// Whether a listen address reaches this machine only: "localhost",
/// 127.0.0.0/8, "::1". Any other name or address (0.0.0.0, ::, an
/// interface's address, a host name) may face a network.
bool loopback_only(std::string_view listen);

/// Whether a program may serve `listen` in plain TCP, `secure` saying
/// whether it runs secure sessions and `insecure` whether it was told
/// --insecure. False with `error` telling the three ways out.
bool may_serve(const std::string& program, std::string_view listen, uint16_t port, bool secure, bool insecure,
               std::string& error);

/// Logs now, and every minute while the loop runs, that anyone who reaches
/// `where` may read and command every device: a log read days later still
/// shows it.
class PlainServiceWarning final : public TimerHandler {
 public:
  PlainServiceWarning(EventLoop& loop, std::string where);
  void on_timer(TimerId id) override;

 private:
  std::string where_;
};

}  // namespace troupe
