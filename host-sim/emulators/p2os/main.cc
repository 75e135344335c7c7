// troupe-emulate-p2os: a Pioneer robot on a pseudo-terminal, for trying the
// p2os driver (or any P2OS client) without a robot. Prints the port's path
// on stdout, then runs until interrupted.
#include <poll.h>
#include <signal.h>
#include <time.h>

#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>

#include "host-sim/emulators/p2os/pioneer_emulator.h"
#include "runtime/clock.h"

namespace {

const char kUsage[] =
    "usage: troupe-emulate-p2os [--link PATH] [--model NAME] [--baud N] [--name TEXT]\n"
    "                           [--flip P] [--drop P] [--tear P] [--seed N] [--no-baud-check]\n"
    "\n"
    "Emulates a Pioneer robot (P2OS firmware) on a new pseudo-terminal and\n"
    "prints its path. A p2os driver opens that path (or PATH, a symbolic link\n"
    "made to it) as its serial port.\n"
    "\n"
    "  --link PATH      also make PATH a symbolic link to the port\n"
    "  --model NAME     robot subclass: p3dx-sh (default) or p3dx\n"
    "  --baud N         the robot's line speed, bit/s (default 9600)\n"
    "  --name TEXT      robot name reported in the handshake\n"
    "  --flip P         per byte sent: probability a bit flips\n"
    "  --drop P         per byte sent: probability it is lost\n"
    "  --tear P         per packet sent: probability it is cut short\n"
    "  --seed N         seed of the fault generator (default 1)\n"
    "  --no-baud-check  talk whatever speed the driver's end is set to\n"
    "\n"
    "examples:\n"
    "  troupe-emulate-p2os --link pioneer-port --baud 38400\n"
    "  troupe emulate-p2os --link pioneer-port --drop 0.01 --seed 7   # a noisy cable\n";

volatile sig_atomic_t g_stop = 0;

void on_signal(int) {
  g_stop = 1;
}

double number(const char* flag, const char* text) {
  char* end = nullptr;
  double v = strtod(text, &end);
  if (end == text || *end != '\0' || v < 0) {
    fprintf(stderr, "troupe-emulate-p2os: %s needs a number >= 0, not '%s'\n", flag, text);
    exit(2);
  }
  return v;
}

}  // namespace

int main(int argc, char** argv) {
  troupe::emulators::PioneerEmulator::Config config;
  troupe::emulators::FaultRates rates;
  std::string link;
  for (int i = 1; i < argc; ++i) {
    auto value = [&](const char* flag) -> const char* {
      if (i + 1 >= argc) {
        fprintf(stderr, "troupe-emulate-p2os: %s needs a value\n%s", flag, kUsage);
        exit(2);
      }
      return argv[++i];
    };
    const char* a = argv[i];
    if (!strcmp(a, "--help") || !strcmp(a, "-h")) {
      fputs(kUsage, stdout);
      return 0;
    } else if (!strcmp(a, "--link")) {
      link = value(a);
    } else if (!strcmp(a, "--model")) {
      config.model = value(a);
    } else if (!strcmp(a, "--baud")) {
      config.baud = uint32_t(number(a, value(a)));
    } else if (!strcmp(a, "--name")) {
      config.name = value(a);
    } else if (!strcmp(a, "--flip")) {
      rates.bit_flip = number(a, value(a));
    } else if (!strcmp(a, "--drop")) {
      rates.byte_drop = number(a, value(a));
    } else if (!strcmp(a, "--tear")) {
      rates.tear = number(a, value(a));
    } else if (!strcmp(a, "--seed")) {
      config.seed = uint64_t(number(a, value(a)));
    } else if (!strcmp(a, "--no-baud-check")) {
      config.check_baud = false;
    } else {
      fprintf(stderr, "troupe-emulate-p2os: unexpected argument '%s'\n%s", a, kUsage);
      return 2;
    }
  }
  if (config.baud != 9600 && config.baud != 19200 && config.baud != 38400 && config.baud != 57600 &&
      config.baud != 115200) {
    fprintf(stderr, "troupe-emulate-p2os: --baud must be 9600, 19200, 38400, 57600 or 115200\n");
    return 2;
  }
  if (troupe::drivers::p2os::find_robot(config.model) == nullptr) {
    fprintf(stderr, "troupe-emulate-p2os: note: '%s' is no known model; reporting it with p3dx-sh units\n",
            config.model.c_str());
  }

  troupe::emulators::PioneerEmulator robot(config);
  robot.faults().rates = rates;
  std::string error;
  if (!robot.open(link, error)) {
    fprintf(stderr, "troupe-emulate-p2os: %s\n", error.c_str());
    return 1;
  }
  signal(SIGINT, on_signal);
  signal(SIGTERM, on_signal);
  printf("%s\n", robot.path().c_str());
  fflush(stdout);
  fprintf(stderr, "troupe-emulate-p2os: %s robot '%s' at %u baud on %s\n", config.model.c_str(),
          config.name.c_str(), unsigned(config.baud), robot.port().slave_path().c_str());

  while (!g_stop) {
    pollfd pfd{robot.port().fd(), POLLIN, 0};
    int n = poll(&pfd, 1, 5);
    // With no driver on the other end the master reports a hang-up at once;
    // wait out the 5 ms instead of spinning.
    if (n > 0 && (pfd.revents & POLLHUP)) {
      timespec pause{0, 5'000'000};
      nanosleep(&pause, nullptr);
    }
    robot.step(troupe::monotonic_us());
  }
  robot.vanish();
  return 0;
}
