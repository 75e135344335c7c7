// ODrive axes on a CAN bus, on any descriptor that carries `struct can_frame`
// bytes (a PF_CAN socket on vcan0, or a socketpair end shared with a driver
// in the same process). Runs in an EventLoop: every 10 ms it steps the
// wheels and sends each axis's encoder estimates, every 100 ms a heartbeat,
// and it answers frames as they come.
//
// Faults a test can inject, each as the hardware shows it:
//  - a silent node (cable off): the axis sends nothing and hears nothing, so
//    its watchdog expires;
//  - an axis error (motor or encoder failure), transient or persistent;
//  - dropped frames, in both directions, with a seeded probability;
//  - a burst of malformed frames from an axis's node id;
//  - a reboot (position count back to 0).
#pragma once

#include <cstdint>
#include <random>
#include <string>
#include <vector>

#include "host-sim/emulators/odrive/odrive_axis.h"
#include "runtime/event_loop.h"

namespace troupe::emulators::odrive {

struct EmulatorOptions {
  /// The axes on the bus; node ids must differ.
  std::vector<AxisConfig> axes;
  /// Period of the encoder estimates (and physics step), us.
  uint64_t estimates_period_us = 10000;
  /// Period of the heartbeats, us.
  uint64_t heartbeat_period_us = 100000;
  /// Seed of the generator deciding which frames are dropped.
  uint64_t seed = 1;
};

struct EmulatorCounters {
  uint64_t frames_in = 0;    // frames read from the descriptor
  uint64_t frames_out = 0;   // frames written
  uint64_t dropped_in = 0;   // lost to fault injection
  uint64_t dropped_out = 0;  // lost to fault injection or a full queue
  uint64_t short_reads = 0;  // reads that were not one can_frame
};

class OdriveEmulator final : public FdHandler, public TimerHandler {
 public:
  /// Does not take ownership of `fd`; call start() to begin.
  OdriveEmulator(EventLoop& loop, int fd, EmulatorOptions options);
  ~OdriveEmulator();
  OdriveEmulator(const OdriveEmulator&) = delete;
  OdriveEmulator& operator=(const OdriveEmulator&) = delete;

  /// Watches the descriptor and arms the timers. False with `error`.
  bool start(std::string& error);
  void stop();

  /// The axis with `node_id`, or nullptr.
  Axis* axis(uint8_t node_id);
  const EmulatorCounters& counters() const { return counters_; }
  const EmulatorOptions& options() const { return options_; }
  /// False once the descriptor failed (the other end closed).
  bool connected() const { return fd_ >= 0; }

  // ---- Faults -------------------------------------------------------------------

  /// A silent node neither sends nor receives (as if unplugged).
  void set_silent(uint8_t node_id, bool silent);
  /// Probability in [0, 1] that any one frame, in or out, is lost.
  void set_drop_probability(double p) { drop_p_ = p; }
  /// Sends `count` malformed frames with `node_id`'s id: short heartbeats and
  /// encoder estimates, DLC over 8, extended ids, error frames.
  void send_garbage(uint8_t node_id, int count);
  /// Sends any frame as if an axis had (for tests that craft one).
  void send_raw(const can_frame& f) { send(f); }

  void on_fd(int fd, uint32_t events) override;
  void on_timer(TimerId id) override;

 private:
  struct Slot {
    Axis axis;
    bool silent = false;
  };
  Slot* find(uint8_t node_id);
  void send(const can_frame& f);
  bool drop();
  void update_bus();

  EventLoop& loop_;
  int fd_;
  EmulatorOptions options_;
  std::vector<Slot> slots_;
  std::mt19937_64 rng_;
  double drop_p_ = 0;
  TimerId estimates_timer_ = 0, heartbeat_timer_ = 0;
  // Heartbeats ride on every n-th estimates tick (0: their own timer).
  uint32_t heartbeat_every_ = 0;
  uint64_t ticks_ = 0;  // estimates ticks since start
  EmulatorCounters counters_;
};

}  // namespace troupe::emulators::odrive
