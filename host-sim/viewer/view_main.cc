// troupe-view: the browser viewer for any live node. Serves the page and
// bridges it to HOST[:PORT]; `troupe view HOST` runs it (it sits beside the
// troupe CLI).
#include <signal.h>

#include <cstdio>
#include <string>

#include "host-sim/viewer/view_server.h"
#include "runtime/log.h"
#include "wire/address.h"
#include "wire/cli/args.h"

int main(int argc, char** argv) {
  troupe::set_log_program("troupe-view");
  troupe::viewer::ViewOptions options;
  options.web_root = troupe::viewer::default_web_root();
  std::string node;
  auto app = troupe::cli::make_app(
      "troupe view",
      {"troupe view HOST[:PORT] [--http-port P] [--listen ADDR] [--identity FILE] [--node-key KEY] [options]",
       "Serves the browser viewer bridged to the node at HOST[:PORT] (default port 6665)\n"
       "and prints its URL. The page shows the node's devices: laser scans, odometry\n"
       "trails, the map of a map device; with troupe-sim, the whole world.\n"
       "To a node with keys the viewer connects through a secure session as\n"
       "--identity; the page then talks to the node through it.\n",
       {"troupe view localhost", "troupe view robot7.local:6670 --http-port 8080 --listen 0.0.0.0",
        "troupe view robot7.local --identity laptop --node-key robot7.pub"}});
  app->add_option("HOST", node, "HOST[:PORT]")->required();
  troupe::cli::add_port(*app, "--http-port", options.http_port, "HTTP port (default 6680; 0: any free port)");
  app->add_option("--listen", options.listen, "address to serve the page on (default 127.0.0.1)")
      ->type_name("ADDR");
  app->add_option("--root", options.web_root,
                  "folder with the page's files (default: ../share/troupe/viewer beside this program)")
      ->type_name("DIR");
  app->add_option("--allow-origin", options.allow_origins,
                  "also accept WebSockets from pages of origin O (http://host:port; repeatable); by\n"
                  "default only the page it served itself, under an address or this machine's name")
      ->type_name("O")
      ->allow_extra_args(false);
  troupe::cli::add_secure_session(*app, options.keys);
  if (int rc = troupe::cli::parse(*app, argc, argv); rc >= 0) return rc;
  troupe::wire::HostPort hp;
  std::string error;
  if (!troupe::wire::parse_host(node, hp, error)) return troupe::cli::usage_error(*app, error);
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
  std::printf("viewer at %s (node %s:%u%s)\n", server.url().c_str(), hp.host.c_str(), unsigned(hp.port),
              options.keys.secure() ? ", secure session" : "");
  std::fflush(stdout);
  server.start_thread();
  int sig = 0;
  sigwait(&set, &sig);
  troupe::log_info("stopping");
  return 0;
}
