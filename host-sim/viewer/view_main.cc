// troupe-view: the browser viewer for any live node. Serves the page and
// bridges it to HOST[:PORT]; `troupe view HOST` runs it (it sits beside the
// troupe CLI).
#include <signal.h>

#include <cstdio>
#include <cstdlib>
#include <string>

#include "host-sim/viewer/view_server.h"
#include "runtime/log.h"
#include "wire/address.h"

namespace {

const char* kUsage =
    "usage: troupe-view HOST[:PORT] [options]\n"
    "\n"
    "Serves the browser viewer bridged to the node at HOST[:PORT] (default port 6665)\n"
    "and prints its URL. The page shows the node's devices: laser scans, odometry\n"
    "trails, the map of a map device; with troupe-sim, the whole world.\n"
    "\n"
    "options:\n"
    "  --http-port P     HTTP port (default 6680; 0: any free port)\n"
    "  --listen ADDR     address to serve the page on (default 127.0.0.1)\n"
    "  --root DIR        folder with the page's files (default: viewer/ beside this program)\n"
    "  --allow-origin O  also accept WebSockets from pages of origin O (http://host:port;\n"
    "                    repeatable); by default only the page it served itself, under an\n"
    "                    address or this machine's name\n";

bool port_number(const char* text, uint16_t& out) {
  char* end = nullptr;
  const long v = std::strtol(text, &end, 10);
  if (end == text || *end != '\0' || v < 0 || v > 65535) return false;
  out = uint16_t(v);
  return true;
}

}  // namespace

int main(int argc, char** argv) {
  troupe::set_log_program("troupe-view");
  troupe::viewer::ViewOptions options;
  options.web_root = troupe::viewer::default_web_root();
  std::string node;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    const bool has_value = i + 1 < argc;
    if (a == "-h" || a == "--help") {
      std::printf("%s", kUsage);
      return 0;
    } else if (a == "--http-port" && has_value) {
      if (!port_number(argv[++i], options.http_port)) {
        std::fprintf(stderr, "troupe-view: --http-port: not a port number (0..65535): %s\n", argv[i]);
        return 2;
      }
    } else if (a == "--listen" && has_value) {
      options.listen = argv[++i];
    } else if (a == "--root" && has_value) {
      options.web_root = argv[++i];
    } else if (a == "--allow-origin" && has_value) {
      options.allow_origins.push_back(argv[++i]);
    } else if (!a.empty() && a[0] == '-') {
      std::fprintf(stderr, "troupe-view: unknown option or missing value: %s\n\n%s", a.c_str(), kUsage);
      return 2;
    } else if (node.empty()) {
      node = a;
    } else {
      std::fprintf(stderr, "troupe-view: one node only; also got %s\n", a.c_str());
      return 2;
    }
  }
  if (node.empty()) {
    std::fprintf(stderr, "troupe-view: which node? (HOST[:PORT])\n\n%s", kUsage);
    return 2;
  }
  troupe::wire::HostPort hp;
  std::string error;
  if (!troupe::wire::parse_host(node, hp, error)) {
    std::fprintf(stderr, "troupe-view: %s\n", error.c_str());
    return 2;
  }
  options.node_host = hp.host;
  options.node_port = hp.port;

  // SIGINT/SIGTERM are waited for on this thread; the server runs on its own.
  sigset_t set;
  sigemptyset(&set);
  sigaddset(&set, SIGINT);
  sigaddset(&set, SIGTERM);
  pthread_sigmask(SIG_BLOCK, &set, nullptr);

  troupe::viewer::ViewServer server(options);
  if (!server.open(error)) {
    std::fprintf(stderr, "troupe-view: %s\n", error.c_str());
    return 1;
  }
  std::printf("viewer at %s (node %s:%u)\n", server.url().c_str(), hp.host.c_str(), unsigned(hp.port));
  std::fflush(stdout);
  server.start_thread();
  int sig = 0;
  sigwait(&set, &sig);
  troupe::log_info("stopping");
  return 0;
}
