// troupe teleop: drive a position2d device with the keyboard.
#include <poll.h>
#include <signal.h>
#include <termios.h>
#include <unistd.h>

#include <algorithm>
#include <cstdio>

#include "wire/address.h"
#include "wire/cli/cli.h"
#include "wire/client/proxies.h"

namespace troupe::cli {
namespace {

termios g_saved;
bool g_raw = false;

void restore_terminal() {
  if (g_raw) tcsetattr(STDIN_FILENO, TCSANOW, &g_saved);
  g_raw = false;
}

void on_signal(int) {
  restore_terminal();
  _exit(0);
}

// Speeds change in steps per key press; the commanded velocity is re-sent
// every 100 ms so that a base with a command watchdog keeps moving.
constexpr float kSpeedStep = 0.1f;  // m/s
constexpr float kTurnStep = 0.2f;   // rad/s
constexpr int kResendMs = 100;

}  // namespace

int cmd_teleop(const std::vector<std::string>& args) {
  std::string host, device;
  auto app = make_app(
      "troupe teleop",
      {"troupe teleop HOST[:PORT] ADDR",
       "Drives a position2d device from the keyboard: w/s (or up/down) change the\n"
       "speed by 0.1 m/s, a/d (or left/right) the turn rate by 0.2 rad/s, space stops,\n"
       "q quits (and stops the robot). The command is re-sent every 100 ms.\n",
       {"troupe teleop localhost position2d:0",
        "troupe teleop localhost:7000 r2/position2d:0   # robot r2 of troupe-sim --port 7000"}});
  add_host(*app, host);
  add_device(*app, device);
  if (int rc = parse(*app, args); rc >= 0) return rc;
  wire::DeviceSpec spec;
  std::string error;
  if (!wire::parse_device(device, spec, error)) return usage_error("teleop", error);
  if (spec.iface != wire::Interface::Position2d) return usage_error("teleop", "teleop drives position2d devices");
  auto c = connect(host, /*reconnect=*/true);
  if (!c) return kExitFailure;
  wire::Address addr;
  if (!resolve(*c, device, addr)) return kExitFailure;
  client::Position2dProxy base(*c, addr);
  if (!base.is_open()) return fail(wire::format_address(addr) + ": " + c->error());

  if (isatty(STDIN_FILENO) && tcgetattr(STDIN_FILENO, &g_saved) == 0) {
    termios raw = g_saved;
    raw.c_lflag &= ~tcflag_t(ICANON | ECHO);
    raw.c_cc[VMIN] = 0;
    raw.c_cc[VTIME] = 0;
    tcsetattr(STDIN_FILENO, TCSANOW, &raw);
    g_raw = true;
    signal(SIGINT, on_signal);
    signal(SIGTERM, on_signal);
  }
  fprintf(stderr, "teleop %s: w/s or up/down: faster/slower, a/d or left/right: turn, space: stop, q: quit\n",
          wire::format_address(addr).c_str());
  float v = 0, w = 0;
  bool quit = false;
  while (!quit) {
    pollfd fds[3];
    int n = c->poll_fds(fds, 2);
    fds[n++] = pollfd{STDIN_FILENO, POLLIN, 0};
    poll(fds, nfds_t(n), kResendMs);
    c->process(fds, n - 1);
    if (fds[n - 1].revents & POLLIN) {
      char keys[16];
      ssize_t got = read(STDIN_FILENO, keys, sizeof keys);
      if (got <= 0 && !g_raw) quit = true;  // end of piped input
      for (ssize_t i = 0; i < got; ++i) {
        char k = keys[i];
        // Arrow keys arrive as ESC [ A..D.
        if (k == 27 && i + 2 < got && keys[i + 1] == '[') {
          k = "wsda"[std::clamp(keys[i + 2] - 'A', 0, 3)];
          i += 2;
        }
        switch (k) {
          case 'w': v += kSpeedStep; break;
          case 's': v -= kSpeedStep; break;
          case 'a': w += kTurnStep; break;
          case 'd': w -= kTurnStep; break;
          case ' ': v = w = 0; break;
          case 'q': quit = true; break;
          default: break;
        }
      }
    }
    base.set_velocity(quit ? 0 : v, 0, quit ? 0 : w);
    fprintf(stderr, "\rcmd v=%+.2f m/s w=%+.2f rad/s | odom x=%+.3f y=%+.3f a=%+.3f %s   ", double(v), double(w),
            double(base.x()), double(base.y()), double(base.a()), c->connected() ? "" : "(reconnecting)");
  }
  c->sync();
  restore_terminal();
  fprintf(stderr, "\n");
  return 0;
}

}  // namespace troupe::cli
