// troupe-emulate-sick: a SICK LMS200 on a pseudo-terminal, for trying
// the sicklms200 driver without a scanner. Prints the port's path on
// stdout, then runs until interrupted.
#include <poll.h>
#include <signal.h>
#include <time.h>

#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>

#include "host-sim/emulators/sicklms200/sick_emulator.h"
#include "runtime/clock.h"

namespace {

const char kUsage[] =
    "usage: troupe-emulate-sick [--link PATH] [--baud N] [--flip P] [--drop P] [--tear P]\n"
    "                                 [--seed N] [--no-baud-check]\n"
    "\n"
    "Emulates a SICK LMS200 laser scanner on a new pseudo-terminal and prints\n"
    "its path. It stands in a 20 x 6 m corridor, powers up at 9600 baud and\n"
    "waits for a driver to configure it.\n"
    "\n"
    "  --link PATH      also make PATH a symbolic link to the port\n"
    "  --baud N         the speed it powers up at, bit/s (default 9600)\n"
    "  --flip P         per byte sent: probability a bit flips\n"
    "  --drop P         per byte sent: probability it is lost\n"
    "  --tear P         per telegram sent: probability it is cut short\n"
    "  --seed N         seed of the fault generator (default 1)\n"
    "  --no-baud-check  talk whatever speed the driver's end is set to\n"
    "\n"
    "examples:\n"
    "  troupe-emulate-sick --link laser-port\n"
    "  troupe emulate-sick --link laser-port --tear 0.05 --seed 3   # torn telegrams\n";

volatile sig_atomic_t g_stop = 0;

void on_signal(int) {
  g_stop = 1;
}

double number(const char* flag, const char* text) {
  char* end = nullptr;
  double v = strtod(text, &end);
  if (end == text || *end != '\0' || v < 0) {
    fprintf(stderr, "troupe-emulate-sick: %s needs a number >= 0, not '%s'\n", flag, text);
    exit(2);
  }
  return v;
}

}  // namespace

int main(int argc, char** argv) {
  troupe::emulators::SickEmulator::Config config;
  troupe::emulators::FaultRates rates;
  std::string link;
  for (int i = 1; i < argc; ++i) {
    auto value = [&](const char* flag) -> const char* {
      if (i + 1 >= argc) {
        fprintf(stderr, "troupe-emulate-sick: %s needs a value\n%s", flag, kUsage);
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
    } else if (!strcmp(a, "--baud")) {
      config.power_up_baud = uint32_t(number(a, value(a)));
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
      fprintf(stderr, "troupe-emulate-sick: unexpected argument '%s'\n%s", a, kUsage);
      return 2;
    }
  }
  troupe::drivers::sicklms200::Mode unused{};
  if (!troupe::drivers::sicklms200::mode_for_baud(config.power_up_baud, unused)) {
    fprintf(stderr, "troupe-emulate-sick: --baud must be 9600, 38400 or 500000\n");
    return 2;
  }

  troupe::emulators::SickEmulator scanner(config);
  scanner.faults().rates = rates;
  std::string error;
  if (!scanner.open(link, error)) {
    fprintf(stderr, "troupe-emulate-sick: %s\n", error.c_str());
    return 1;
  }
  signal(SIGINT, on_signal);
  signal(SIGTERM, on_signal);
  printf("%s\n", scanner.path().c_str());
  fflush(stdout);
  fprintf(stderr, "troupe-emulate-sick: LMS200 at %u baud on %s\n", unsigned(config.power_up_baud),
          scanner.port().slave_path().c_str());

  while (!g_stop) {
    pollfd pfd{scanner.port().fd(), POLLIN, 0};
    // 2 ms: the line is paced in small steps (38400 baud is 4 bytes a ms).
    int n = poll(&pfd, 1, 2);
    if (n > 0 && (pfd.revents & POLLHUP)) {
      timespec pause{0, 2'000'000};
      nanosleep(&pause, nullptr);
    }
    scanner.step(troupe::monotonic_us());
  }
  scanner.vanish();
  return 0;
}
