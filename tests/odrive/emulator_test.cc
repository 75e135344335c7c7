// The ODrive emulator on its own: the axis state machine, the wheel, the
// watchdog and errors (Axis, with explicit time), and the bus cadence and Get
// replies over a socketpair in a real EventLoop.
#include <gtest/gtest.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cmath>
#include <cstring>
#include <map>
#include <memory>

#include "drivers/odrive_can/can_io.h"
#include "host-sim/emulators/odrive/fault_console.h"
#include "host-sim/emulators/odrive/odrive_emulator.h"

namespace troupe::emulators::odrive {
namespace {

namespace cs = troupe::cansimple;
using cs::AxisState;

constexpr uint64_t kMs = 1000;

AxisConfig node(uint8_t id) {
  AxisConfig c;
  c.node_id = id;
  return c;
}

struct AxisBench {
  explicit AxisBench(AxisConfig c = {}) : axis(c) { axis.step(now); }
  can_frame reply{};
  uint64_t now = 1000000;
  Axis axis;
  bool send(const can_frame& f) { return axis.handle(f, now, reply); }
  void run(uint64_t ms, bool feed = false) {
    for (uint64_t i = 0; i < ms; ++i) {
      now += kMs;
      if (feed && i % 20 == 0) send(cs::set_input_vel_frame(axis.node_id(), {axis.input_vel(), 0}));
      axis.step(now);
    }
  }
  void arm() { send(cs::set_axis_state_frame(axis.node_id(), AxisState::ClosedLoopControl)); }
};

TEST(OdriveAxis, ClosedLoopVelocityWithRamp) {
  AxisBench b;
  b.send(cs::set_controller_modes_frame(0, {cs::ControlMode::Velocity, cs::InputMode::VelRamp}));
  b.arm();
  ASSERT_EQ(b.axis.state(), AxisState::ClosedLoopControl);
  b.send(cs::set_input_vel_frame(0, {4.0f, 0}));
  b.run(100);  // 20 turns/s^2: the ramp is at 2 turns/s after 100 ms
  EXPECT_GT(b.axis.velocity(), 1.5f);
  EXPECT_LT(b.axis.velocity(), 2.0f);
  b.run(400);
  EXPECT_NEAR(b.axis.velocity(), 4.0f, 1e-3f);
  // Position is the integral of velocity: about 4 turns/s for the last 0.3 s.
  double p = b.axis.position_turns();
  b.run(500);
  EXPECT_NEAR(b.axis.position_turns() - p, 2.0, 1e-3);
}

TEST(OdriveAxis, VelocityLimitClampsTheSetpoint) {
  AxisBench b;
  b.send(cs::set_limits_frame(0, {1.5f, 10}));
  b.arm();
  b.send(cs::set_input_vel_frame(0, {5.0f, 0}));
  b.run(500);
  EXPECT_NEAR(b.axis.velocity(), 1.5f, 1e-3f);
}

TEST(OdriveAxis, IdleWheelCoastsToAStop) {
  AxisBench b;
  b.arm();
  b.send(cs::set_input_vel_frame(0, {3.0f, 0}));
  b.run(300);
  b.send(cs::set_axis_state_frame(0, AxisState::Idle));
  b.run(20);
  EXPECT_GT(b.axis.velocity(), 1.0f);  // no brake: it runs down, not stops dead
  b.run(3000);
  EXPECT_LT(std::fabs(b.axis.velocity()), 1e-3f);
}

TEST(OdriveAxis, WatchdogDisarmsAnUnfedAxis) {
  AxisConfig c;
  c.watchdog_timeout_ms = 200;
  AxisBench b(c);
  b.arm();
  b.run(1000, /*feed=*/true);  // a frame every 20 ms keeps it armed
  EXPECT_EQ(b.axis.state(), AxisState::ClosedLoopControl);
  b.run(250);
  EXPECT_EQ(b.axis.state(), AxisState::Idle);
  EXPECT_EQ(b.axis.error(), cs::axis_error::kWatchdogTimerExpired);
  EXPECT_EQ(b.axis.watchdog_expiries(), 1u);
  b.arm();  // refused while the error is set
  EXPECT_EQ(b.axis.state(), AxisState::Idle);
  b.send(cs::empty_frame(0, cs::Cmd::ClearErrors));
  b.arm();
  EXPECT_EQ(b.axis.state(), AxisState::ClosedLoopControl);
}

TEST(OdriveAxis, ErrorsEstopAndReboot) {
  AxisBench b;
  b.arm();
  b.axis.inject_error(cs::axis_error::kMotorFailed, /*persistent=*/true);
  EXPECT_EQ(b.axis.state(), AxisState::Idle);
  cs::Heartbeat hb;
  ASSERT_TRUE(cs::parse(b.axis.heartbeat(), hb));
  EXPECT_EQ(hb.axis_error, cs::axis_error::kMotorFailed);
  EXPECT_TRUE(hb.motor_error);
  b.send(cs::empty_frame(0, cs::Cmd::ClearErrors));
  EXPECT_EQ(b.axis.error(), cs::axis_error::kMotorFailed);  // the cause is still there
  b.axis.clear_fault();
  b.send(cs::empty_frame(0, cs::Cmd::ClearErrors));
  EXPECT_EQ(b.axis.error(), 0u);

  b.arm();
  b.send(cs::empty_frame(0, cs::Cmd::Estop));
  EXPECT_EQ(b.axis.state(), AxisState::Idle);
  EXPECT_EQ(b.axis.error(), cs::axis_error::kEstopRequested);

  b.send(cs::set_input_vel_frame(0, {1.0f, 0}));
  b.send(cs::empty_frame(0, cs::Cmd::Reboot));
  EXPECT_EQ(b.axis.error(), 0u);
  EXPECT_EQ(b.axis.input_vel(), 0.0f);
  EXPECT_EQ(b.axis.position_turns(), 0.0);
}

TEST(OdriveAxis, AnswersGetRequestsAsRemoteFramesOrEmptyFrames) {
  AxisBench b(node(9));
  b.axis.set_bus(23.5f, 1.25f);
  ASSERT_TRUE(b.send(cs::get_request_frame(9, cs::Cmd::GetBusVoltageCurrent)));
  EXPECT_EQ(b.reply.can_id, cs::make_id(9, cs::Cmd::GetBusVoltageCurrent));  // same id, no RTR
  cs::BusVoltageCurrent bus;
  ASSERT_TRUE(cs::parse(b.reply, bus));
  EXPECT_EQ(bus.volts, 23.5f);
  EXPECT_EQ(bus.amps, 1.25f);
  ASSERT_TRUE(b.send(cs::empty_frame(9, cs::Cmd::GetEncoderEstimates)));
  EXPECT_EQ(b.reply.len, 8);
  // A set command is no request, and a malformed one changes nothing.
  can_frame bad = cs::set_input_vel_frame(9, {7.0f, 0});
  bad.len = 2;
  EXPECT_FALSE(b.send(bad));
  EXPECT_EQ(b.axis.input_vel(), 0.0f);
  EXPECT_EQ(b.axis.malformed_frames(), 1u);
}

TEST(OdriveAxis, ExternalWheelReportsWhatTheSimulatorSets) {
  AxisConfig c;
  c.external_wheel = true;
  AxisBench b(c);
  b.send(cs::set_controller_modes_frame(0, {cs::ControlMode::Velocity, cs::InputMode::VelRamp}));
  b.arm();
  b.send(cs::set_input_vel_frame(0, {3.0f, 0}));
  b.run(50);  // the ramp runs: 20 turns/s^2 for 50 ms
  EXPECT_NEAR(b.axis.velocity_demand(), 1.0f, 1e-3f);
  EXPECT_EQ(b.axis.velocity(), 0.0f);  // nothing moves the wheel but the simulator
  b.axis.set_wheel(12.5, 0.9f);
  b.run(10);
  cs::EncoderEstimates est;
  ASSERT_TRUE(cs::parse(b.axis.encoder_estimates(), est));
  EXPECT_EQ(est.pos_turns, 12.5f);
  EXPECT_EQ(est.vel_turns_s, 0.9f);
  b.send(cs::set_axis_state_frame(0, AxisState::Idle));
  EXPECT_EQ(b.axis.velocity_demand(), 0.0f);
}

TEST(OdriveAxis, WrappedPositionReport) {
  AxisConfig c;
  c.wrap_turns = 1.0f;
  AxisBench b(c);
  b.arm();
  b.send(cs::set_input_vel_frame(0, {-2.0f, 0}));
  b.run(1000);
  cs::EncoderEstimates est;
  ASSERT_TRUE(cs::parse(b.axis.encoder_estimates(), est));
  EXPECT_GE(est.pos_turns, 0.0f);
  EXPECT_LT(est.pos_turns, 1.0f);
  EXPECT_LT(b.axis.position_turns(), -1.0);
  EXPECT_NEAR(est.pos_turns, b.axis.position_turns() - std::floor(b.axis.position_turns()), 1e-5);
}

// ---- The bus over a socketpair ---------------------------------------------------

class EmulatorBus : public ::testing::Test {
 protected:
  void SetUp() override {
    ASSERT_EQ(socketpair(AF_UNIX, SOCK_SEQPACKET | SOCK_CLOEXEC, 0, fds_), 0);
    EmulatorOptions o;
    o.axes = {node(4), node(5)};
    emu_ = std::make_unique<OdriveEmulator>(loop_, fds_[1], o);
    std::string error;
    ASSERT_TRUE(emu_->start(error)) << error;
    ASSERT_TRUE(cs::make_nonblocking(fds_[0], error));
  }
  void TearDown() override {
    emu_.reset();
    close(fds_[0]);
    close(fds_[1]);
  }
  // Runs the loop for `ms` and counts the frames by id the host side saw.
  std::map<uint32_t, int> listen(uint64_t ms) {
    std::map<uint32_t, int> seen;
    uint64_t end = loop_.now_us() + ms * kMs;
    while (loop_.now_us() < end) {
      loop_.run_once(2000);
      can_frame f;
      int err = 0;
      while (cs::read_frame(fds_[0], f, err) == cs::IoResult::Frame) {
        seen[f.can_id]++;
        last_ = f;
      }
    }
    return seen;
  }
  void send(const can_frame& f) {
    int err = 0;
    ASSERT_EQ(cs::write_frame(fds_[0], f, err), cs::IoResult::Frame);
  }

  int fds_[2] = {-1, -1};
  EventLoop loop_;
  std::unique_ptr<OdriveEmulator> emu_;
  can_frame last_{};
};

TEST_F(EmulatorBus, HeartbeatsAndEstimatesAtTheirRates) {
  auto seen = listen(1000);
  for (uint8_t node : {4, 5}) {
    // 10 heartbeats and 100 estimates a second. A busy machine may delay the
    // loop's timers, never run them early: bound from above. The heartbeat
    // rides on every tenth estimates tick, so however late the ticks come,
    // each heartbeat follows exactly ten estimates.
    int heartbeats = seen[cs::make_id(node, cs::Cmd::Heartbeat)];
    int estimates = seen[cs::make_id(node, cs::Cmd::GetEncoderEstimates)];
    EXPECT_GE(heartbeats, 1);
    EXPECT_LE(heartbeats, 10);
    EXPECT_LE(estimates, 100);
    EXPECT_GE(estimates, 10 * heartbeats);
    EXPECT_LT(estimates, 10 * (heartbeats + 1));
  }
}

TEST_F(EmulatorBus, SilentNodeSendsNothingAndHearsNothing) {
  emu_->set_silent(5, true);
  send(cs::set_axis_state_frame(5, AxisState::ClosedLoopControl));
  auto seen = listen(300);
  EXPECT_EQ(seen[cs::make_id(5, cs::Cmd::Heartbeat)], 0);
  EXPECT_EQ(seen[cs::make_id(5, cs::Cmd::GetEncoderEstimates)], 0);
  EXPECT_GT(seen[cs::make_id(4, cs::Cmd::Heartbeat)], 0);
  EXPECT_EQ(emu_->axis(5)->state(), AxisState::Idle);
}

TEST_F(EmulatorBus, RepliesToRemoteRequests) {
  listen(20);
  send(cs::get_request_frame(4, cs::Cmd::GetBusVoltageCurrent));
  auto seen = listen(30);
  ASSERT_EQ(seen[cs::make_id(4, cs::Cmd::GetBusVoltageCurrent)], 1);
  EXPECT_EQ(seen.count(cs::make_id(5, cs::Cmd::GetBusVoltageCurrent)), 0u);
}

TEST_F(EmulatorBus, SameSeedDropsTheSameFrames) {
  // The drop decisions come from the seeded generator: two emulators with
  // the same seed lose the same frames of the same sequence.
  auto pattern = [](uint64_t seed) {
    int fds[2];
    socketpair(AF_UNIX, SOCK_SEQPACKET | SOCK_CLOEXEC, 0, fds);
    EventLoop loop;
    EmulatorOptions o;
    o.axes = {node(1)};
    o.seed = seed;
    OdriveEmulator emu(loop, fds[1], o);
    emu.set_drop_probability(0.5);
    std::string out;
    for (int i = 0; i < 64; ++i) {
      uint64_t before = emu.counters().dropped_out;
      emu.send_raw(cs::heartbeat_frame(1, {}));
      out += emu.counters().dropped_out > before ? 'x' : '.';
    }
    close(fds[0]);
    close(fds[1]);
    return out;
  };
  EXPECT_EQ(pattern(42), pattern(42));
  EXPECT_NE(pattern(42), pattern(43));
  EXPECT_NE(pattern(42).find('x'), std::string::npos);
  EXPECT_NE(pattern(42).find('.'), std::string::npos);
}

TEST_F(EmulatorBus, FaultCommandsAndTheirErrors) {
  EXPECT_EQ(apply_fault_command(*emu_, "silent 5 on", 0), "node 5 silent");
  auto seen = listen(250);
  EXPECT_EQ(seen[cs::make_id(5, cs::Cmd::Heartbeat)], 0);
  apply_fault_command(*emu_, "silent 5 off", 0);
  EXPECT_NE(apply_fault_command(*emu_, "error 4 0x100 keep", 0).find("ENCODER_FAILED"), std::string::npos);
  EXPECT_EQ(emu_->axis(4)->error(), cs::axis_error::kEncoderFailed);
  send(cs::empty_frame(4, cs::Cmd::ClearErrors));
  listen(20);
  EXPECT_EQ(emu_->axis(4)->error(), cs::axis_error::kEncoderFailed);  // kept
  apply_fault_command(*emu_, "clear 4", 0);
  send(cs::empty_frame(4, cs::Cmd::ClearErrors));
  listen(20);
  EXPECT_EQ(emu_->axis(4)->error(), 0u);
  // Bad lines say what is wrong and change nothing.
  EXPECT_NE(apply_fault_command(*emu_, "silent 9 on", 0).find("'9' is not a node id"), std::string::npos);
  EXPECT_NE(apply_fault_command(*emu_, "drop 1.5", 0).find("[0, 1]"), std::string::npos);
  EXPECT_NE(apply_fault_command(*emu_, "error 4 zero", 0).find("error NODE BITS"), std::string::npos);
  EXPECT_NE(apply_fault_command(*emu_, "explode 4", 0).find("unknown command 'explode'"), std::string::npos);
  EXPECT_EQ(apply_fault_command(*emu_, "   ", 0), "");
  EXPECT_EQ(emu_->axis(4)->error(), 0u);
}

}  // namespace
}  // namespace troupe::emulators::odrive
