// troupe-emulate-p2os: a Pioneer robot on a pseudo-terminal, for trying the
// p2os driver (or any P2OS client, ARIA's included) without a robot. Prints
// the port's path on stdout, then runs until interrupted.
#include <cstdio>
#include <memory>

#include "host-sim/emulators/p2os/pioneer_emulator.h"
#include "host-sim/emulators/serial_line/emulator_main.h"
#include "wire/cli/args.h"

int main(int argc, char** argv) {
  namespace emu = troupe::emulators;
  emu::PioneerEmulator::Config robot;
  emu::EmulatorProgram p;
  p.name = "troupe-emulate-p2os";
  p.synopsis = "[--model NAME] [--name TEXT]";
  p.about =
      "Emulates a Pioneer robot (P2OS firmware) on a new pseudo-terminal and\n"
      "prints its path. A p2os driver (or ARIA) opens that path (or PATH, a\n"
      "symbolic link made to it) as its serial port.\n";
  p.examples = {"troupe-emulate-p2os --link pioneer-port --baud 38400",
                "troupe emulate-p2os --link pioneer-port --drop 0.01 --seed 7   # a noisy cable"};
  p.bauds = {9600, 19200, 38400, 57600, 115200};
  p.add_flags = [&](CLI::App& app) {
    app.add_option("--model", robot.model, "robot subclass: p3dx-sh (default) or p3dx")->type_name("NAME");
    app.add_option("--name", robot.name, "robot name reported in the handshake")->type_name("TEXT");
  };
  p.make = [&](const emu::EmulatorOptions& o) {
    if (troupe::drivers::p2os::find_robot(robot.model) == nullptr) {
      fprintf(stderr, "troupe-emulate-p2os: note: '%s' is no known model; reporting it with p3dx-sh units\n",
              robot.model.c_str());
    }
    robot.baud = o.baud;
    robot.seed = o.seed;
    robot.check_baud = o.check_baud;
    return std::make_unique<emu::PioneerEmulator>(robot);
  };
  p.describe = [&](const emu::EmulatorOptions& o) {
    return robot.model + " robot '" + robot.name + "' at " + std::to_string(o.baud) + " baud";
  };
  return emu::emulator_main(argc, argv, p);
}
