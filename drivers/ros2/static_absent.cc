// The ros2 driver's entry in a statically linked program (one that sets the
// target property TROUPE_STATIC_LINK, such as the kernel-CAN test): Debian
// ships Cyclone DDS as a shared library only, so there the driver cannot be
// linked. The board's driver table still names it; a config that uses it is
// refused at setup with this reason instead of failing the link.
#include "runtime/driver.h"

namespace troupe::drivers::ros2 {
namespace {

class Absent final : public Driver {
 public:
  bool setup(Node&, const DriverSetup&, std::string& error) override {
    error = "the ros2 driver is not in this statically linked program (Cyclone DDS is a shared library)";
    return false;
  }
};

}  // namespace

extern const DriverEntry kEntry;
const DriverEntry kEntry{"ros2", []() -> Driver* { return new Absent; }};

}  // namespace troupe::drivers::ros2
