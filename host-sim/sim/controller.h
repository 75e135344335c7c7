// In-process controllers (Stage's `ctrl "wander"`): C++ classes built as
// plugins of the one plugin ABI (host-sim/plugin/plugin_abi.h), one
// instance per robot, run before every step. A controller sees its own
// robot only: its sensors, its state, its command.
//
// A controller library wander.so names a factory,
//   troupe::sim::Controller* make_wander(const char* args);
//   TROUPE_CONTROLLER("wander", make_wander)
// `args` is the rest of the ctrl string ("wander speed=0.3" gives
// "speed=0.3"); the factory returns nullptr when the arguments are bad.
//
// What a controller remembers from one step to the next lives in memory the
// World owns (memory_size(), RobotHandle::memory()), not in the controller
// object: the World can then hand a robot, with its memory, to a fresh
// controller instance (another process of a distributed run, a reloaded
// controller) and the robot carries on as if nothing happened. The object
// keeps only what init() derives from its arguments and the robot's
// description, which a fresh instance derives again.
#pragma once

#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <span>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <vector>

#include "host-sim/plugin/plugin_abi.h"
#include "host-sim/sim/world.h"

namespace troupe::sim {

/// A controller's view of its robot. Every call is virtual, so a controller
/// library needs nothing from the simulator but this header: no symbols to
/// resolve when it is loaded.
class RobotHandle {
 public:
  virtual ~RobotHandle() = default;

  virtual RobotId id() const = 0;
  virtual const std::string& name() const = 0;
  /// Pose, velocity, odometry, stall.
  virtual const RobotState& state() const = 0;
  /// Simulated time, s.
  virtual double time() const = 0;
  /// Simulated time per step, s.
  virtual double interval() const = 0;

  /// How many sensors of a kind the robot carries.
  virtual uint32_t count(SensorKind kind) const = 0;
  virtual const RangerDesc& ranger_desc(uint32_t k) const = 0;
  virtual RangerView ranger(uint32_t k) const = 0;
  virtual FiducialView fiducial(uint32_t k) const = 0;
  virtual BlobView blobfinder(uint32_t k) const = 0;
  virtual BumperView bumper(uint32_t k) const = 0;
  /// Asks for a sensor to be computed every step (sensors nobody wants are
  /// skipped). Data appears after the next step.
  virtual void want(SensorKind kind, uint32_t k, bool wanted) = 0;

  virtual void command(const Command& cmd) = 0;

  /// Seeded random numbers for this robot: uniform in [0, 1), a pure
  /// function of the run's seed, the robot, the step and `k`.
  virtual double uniform(uint64_t k) const = 0;

  /// The robot's grippers: paddles and what they hold; closing catches the
  /// puck between them at the next step, opening drops it.
  virtual uint32_t gripper_count() const = 0;
  virtual GripperView gripper(uint32_t k) const = 0;
  virtual void set_gripper(uint32_t k, bool closed) = 0;

  /// The robot's controller memory: Controller::memory_size() bytes, all
  /// zero at the start and after a reset, aligned for any scalar type
  /// (alignof(std::max_align_t)).
  virtual std::span<std::byte> memory() = 0;

  /// That memory as the controller's state struct, which must be trivially
  /// copyable (the World moves it as bytes) and have all-zero bytes as its
  /// initial state.
  template <class T>
  T& memory_as() {
    static_assert(std::is_trivially_copyable_v<T>, "controller memory is moved as bytes");
    static_assert(alignof(T) <= alignof(std::max_align_t));
    const std::span<std::byte> m = memory();
    if (m.size() < sizeof(T)) throw std::logic_error("controller memory is smaller than its state");
    return *reinterpret_cast<T*>(m.data());
  }
};

class Controller {
 public:
  virtual ~Controller() = default;
  /// Bytes of memory the World keeps for this controller's robot
  /// (RobotHandle::memory()); asked once, before init().
  virtual size_t memory_size() const { return 0; }
  /// Once per instance, before its first update: say which sensors to
  /// compute. False with `error` refuses the robot (e.g. it lacks the
  /// sensor the controller needs). It must not write the robot's memory:
  /// a robot handed to a fresh instance keeps what it remembered.
  virtual bool init(RobotHandle& robot, std::string& error) = 0;
  /// Every step, before the world steps: read sensors, send a command.
  virtual void update(RobotHandle& robot) = 0;
};

/// The version of the Controller and RobotHandle interfaces
/// (TroupePluginInfo::interface_version).
/// 2: RobotHandle's grippers.
/// 3: the robot's controller memory (memory_size, RobotHandle::memory).
inline constexpr uint32_t kControllerInterfaceVersion = 3;

/// The plugin description of a controller made by `Create`.
template <Controller* (*Create)(const char* args)>
const TroupePluginInfo* controller_info(const char* name) {
  static const TroupePluginInfo info{TROUPE_PLUGIN_ABI_VERSION,
                                     TROUPE_PLUGIN_CONTROLLER,
                                     kControllerInterfaceVersion,
                                     name,
                                     [](const char* args) -> void* { return Create(args); },
                                     [](void* p) { delete static_cast<Controller*>(p); }};
  return &info;
}

/// Exports controller NAME (the library is NAME.so) made by CREATE.
#define TROUPE_CONTROLLER(NAME, CREATE)                             \
  TROUPE_PLUGIN_EXPORT const TroupePluginInfo* troupe_plugin_v1() { \
    return troupe::sim::controller_info<CREATE>(NAME);              \
  }

/// Controller arguments: "speed=0.3 turn=1 aggregate" as numbers by key and
/// bare words as flags. Header-only, so controller libraries link nothing.
class ControllerArgs {
 public:
  explicit ControllerArgs(const char* text) {
    std::string s = text ? text : "";
    size_t i = 0;
    while (i < s.size()) {
      while (i < s.size() && s[i] == ' ') ++i;
      size_t j = s.find(' ', i);
      if (j == std::string::npos) j = s.size();
      if (j > i) words_.push_back({s.substr(i, j - i), false});
      i = j;
    }
  }
  /// The value of key=value, or `fallback`; a malformed number is an error.
  double number(const std::string& key, double fallback) {
    for (Word& w : words_) {
      if (w.text.compare(0, key.size() + 1, key + "=") != 0) continue;
      w.used = true;
      const std::string v = w.text.substr(key.size() + 1);
      char* end = nullptr;
      double d = std::strtod(v.c_str(), &end);
      if (v.empty() || *end != '\0') {
        bad_ = true;
        return fallback;
      }
      return d;
    }
    return fallback;
  }
  /// True when the bare word is present.
  bool flag(const std::string& word) {
    for (Word& w : words_) {
      if (w.text == word) return w.used = true;
    }
    return false;
  }
  /// False when a value was malformed or a word was not asked for.
  bool ok() const {
    for (const Word& w : words_) {
      if (!w.used) return false;
    }
    return !bad_;
  }

 private:
  struct Word {
    std::string text;
    bool used;
  };
  std::vector<Word> words_;
  bool bad_ = false;
};

}  // namespace troupe::sim
