// consumer HOST PORT: drives position2d:0 of a node forward through the
// installed client library until its odometry shows it moved, then prints
// "devices=N moved_m=X" and stops the robot.
#include <cstdio>
#include <cstdlib>

#include "wire/client/proxies.h"

int main(int argc, char** argv) {
  if (argc != 3) {
    std::fprintf(stderr, "usage: consumer HOST PORT\n");
    return 2;
  }
  troupe::client::Client robot(argv[1], uint16_t(std::atoi(argv[2])));
  if (!robot.connect()) {
    std::fprintf(stderr, "consumer: %s\n", robot.error().c_str());
    return 1;
  }
  std::vector<troupe::client::DeviceEntry> devices;
  if (!robot.device_list(devices)) return 1;
  troupe::client::Position2dProxy base(robot);
  base.set_velocity(0.5, 0, 0);  // m/s, m/s, rad/s
  // At most 10 s (100 ms a spin): a bound against a hang, not a timing.
  for (int i = 0; i < 100 && base.x() < 0.1; ++i) robot.spin_once(100);
  base.set_velocity(0, 0, 0);
  robot.sync();
  std::printf("devices=%zu moved_m=%.3f\n", devices.size(), double(base.x()));
  return base.x() >= 0.1 ? 0 : 1;
}
