#include "host-sim/emulators/serial_line/emulator_main.h"

#include <poll.h>
#include <signal.h>
#include <time.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <cstring>

#include "runtime/clock.h"

namespace troupe::emulators {
namespace {

volatile sig_atomic_t g_stop = 0;

void on_signal(int) {
  g_stop = 1;
}

bool number(const char* text, double& out) {
  char* end = nullptr;
  out = strtod(text, &end);
  return end != text && *end == '\0' && out >= 0;
}

std::string list(const std::vector<uint32_t>& bauds) {
  std::string text;
  for (size_t i = 0; i < bauds.size(); ++i) {
    text += (i == 0 ? "" : i + 1 == bauds.size() ? " or " : ", ") + std::to_string(bauds[i]);
  }
  return text;
}

}  // namespace

std::string emulator_usage(const EmulatorProgram& p) {
  return std::string("usage: ") + p.name + " [--link PATH] [--baud N] " + p.synopsis +
         "\n       [--flip P] [--drop P] [--tear P] [--seed N] [--no-baud-check]\n\n" + p.about +
         "\n\n  --link PATH      also make PATH a symbolic link to the port\n"
         "  --baud N         the device's line speed at power-up, bit/s: " +
         list(p.bauds) + " (default " + std::to_string(p.bauds.front()) + ")\n" + p.flags_help +
         "  --flip P         per byte sent: probability a bit flips\n"
         "  --drop P         per byte sent: probability it is lost\n"
         "  --tear P         per packet sent: probability it is cut short\n"
         "  --seed N         seed of the fault generator (default 1)\n"
         "  --no-baud-check  talk whatever speed the driver's end is set to\n"
         "\nexamples:\n" +
         p.examples;
}

int emulator_main(int argc, char** argv, const EmulatorProgram& program) {
  EmulatorOptions options;
  options.baud = program.bauds.front();
  const std::string usage = emulator_usage(program);
  auto fail = [&](const std::string& why) {
    fprintf(stderr, "%s: %s\n%s", program.name, why.c_str(), usage.c_str());
    return 2;
  };
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--help" || a == "-h") {
      fputs(usage.c_str(), stdout);
      return 0;
    }
    if (a == "--no-baud-check") {
      options.check_baud = false;
      continue;
    }
    if (i + 1 >= argc) return fail(a + " needs a value");
    const char* value = argv[++i];
    double n = 0;
    auto need_number = [&](double& out) { return number(value, out); };
    if (a == "--link") {
      options.link = value;
    } else if (a == "--baud" || a == "--flip" || a == "--drop" || a == "--tear" || a == "--seed") {
      if (!need_number(n)) return fail(a + " needs a number >= 0, not '" + value + "'");
      if (a == "--baud") options.baud = uint32_t(n);
      if (a == "--flip") options.rates.bit_flip = n;
      if (a == "--drop") options.rates.byte_drop = n;
      if (a == "--tear") options.rates.tear = n;
      if (a == "--seed") options.seed = uint64_t(n);
    } else {
      auto flag = std::find_if(program.flags.begin(), program.flags.end(),
                               [&](const EmulatorProgram::Flag& f) { return a == f.name; });
      if (flag == program.flags.end()) return fail("unexpected argument '" + a + "'");
      std::string error = flag->set(value);
      if (!error.empty()) return fail(error);
    }
  }
  if (std::find(program.bauds.begin(), program.bauds.end(), options.baud) == program.bauds.end()) {
    return fail("--baud must be " + list(program.bauds));
  }

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
