#include "host-sim/emulators/serial_line/emulator_main.h"

#include <poll.h>
#include <signal.h>
#include <time.h>

#include <cstdio>

#include "runtime/clock.h"
#include "wire/cli/args.h"

namespace troupe::emulators {
namespace {

volatile sig_atomic_t g_stop = 0;

void on_signal(int) {
  g_stop = 1;
}

std::string list(const std::vector<uint32_t>& bauds) {
  std::string text;
  for (size_t i = 0; i < bauds.size(); ++i) {
    text += (i == 0 ? "" : i + 1 == bauds.size() ? " or " : ", ") + std::to_string(bauds[i]);
  }
  return text;
}

// --baud: one of the device's speeds.
CLI::Validator one_of(const std::vector<uint32_t>& bauds) {
  return CLI::Validator(
      [bauds](std::string& text) -> std::string {
        for (uint32_t baud : bauds) {
          if (text == std::to_string(baud)) return "";
        }
        return "must be " + list(bauds) + ", not '" + text + "'";
      },
      "", "baud");
}

}  // namespace

int emulator_main(int argc, char** argv, const EmulatorProgram& program) {
  EmulatorOptions options;
  options.baud = program.bauds.front();
  auto app = cli::make_app(program.name,
                           {std::string(program.name) + " [--link PATH] [--baud N] " + program.synopsis +
                                "\n       [--flip P] [--drop P] [--tear P] [--seed N] [--no-baud-check]",
                            program.about, program.examples});
  app->add_option("--link", options.link, "also make PATH a symbolic link to the port")->type_name("PATH");
  app->add_option("--baud", options.baud,
                  "the device's line speed at power-up, bit/s: " + list(program.bauds) + " (default " +
                      std::to_string(program.bauds.front()) + ")")
      ->type_name("N")
      ->check(one_of(program.bauds));
  if (program.add_flags) program.add_flags(*app);
  app->add_option("--flip", options.rates.bit_flip, "per byte sent: probability a bit flips")
      ->type_name("P")
      ->check(cli::between(0, 1));
  app->add_option("--drop", options.rates.byte_drop, "per byte sent: probability it is lost")
      ->type_name("P")
      ->check(cli::between(0, 1));
  app->add_option("--tear", options.rates.tear, "per packet sent: probability it is cut short")
      ->type_name("P")
      ->check(cli::between(0, 1));
  app->add_option("--seed", options.seed, "seed of the fault generator (default 1)")
      ->type_name("N")
      ->check(cli::at_least(0));
  bool no_baud_check = false;
  app->add_flag("--no-baud-check", no_baud_check, "talk whatever speed the driver's end is set to");
  if (int rc = cli::parse(*app, argc, argv); rc >= 0) return rc;
  options.check_baud = !no_baud_check;

  std::unique_ptr<SerialEmulator> device = program.make(options);
  device->faults().rates = options.rates;
  std::string error;
  if (!device->open(options.link, error)) {
    fprintf(stderr, "%s: %s\n", program.name, error.c_str());
    return 1;
  }
  signal(SIGINT, on_signal);
  signal(SIGTERM, on_signal);
  printf("%s\n", device->path().c_str());
  fflush(stdout);
  fprintf(stderr, "%s: %s on %s\n", program.name, program.describe(options).c_str(),
          device->port().slave_path().c_str());
  while (!g_stop) {
    pollfd pfd{device->port().fd(), POLLIN, 0};
    int n = poll(&pfd, 1, program.poll_ms);
    // With no driver on the other end the master reports a hang-up at once;
    // wait out the poll time instead of spinning.
    if (n > 0 && (pfd.revents & POLLHUP)) {
      timespec pause{0, long(program.poll_ms) * 1'000'000};
      nanosleep(&pause, nullptr);
    }
    device->step(monotonic_us());
  }
  device->vanish();
  return 0;
}

}  // namespace troupe::emulators
