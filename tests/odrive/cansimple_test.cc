// The CAN Simple codec against the worked frame in protocols.md and against
// ODrive's own machine-readable description (odrive-cansimple.dbc): every
// frame the driver or emulator builds is decoded with the DBC's signal
// layout, and frames laid out by the DBC are read back with the codec.
#include "drivers/odrive_can/cansimple.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

namespace troupe::cansimple {
namespace {

TEST(CanSimple, WorkedFrameFromTheProtocolNotes) {
  // Node 1, Set_Input_Vel 2.0 turns/s -> id 0x02D, data 00 00 00 40 00 00 00 00.
  can_frame f = set_input_vel_frame(1, {2.0f, 0.0f});
  EXPECT_EQ(f.can_id, 0x02Du);
  ASSERT_EQ(f.len, 8);
  const uint8_t expected[8] = {0x00, 0x00, 0x00, 0x40, 0x00, 0x00, 0x00, 0x00};
  EXPECT_EQ(std::memcmp(f.data, expected, 8), 0);
}

TEST(CanSimple, NonFiniteVelocitiesGoOutAsAStop) {
  for (float bad : {std::nanf(""), INFINITY, -INFINITY}) {
    can_frame f = set_input_vel_frame(1, {bad, bad});
    EXPECT_EQ(get_f32(f.data), 0.0f);
    EXPECT_EQ(get_f32(f.data + 4), 0.0f);
  }
}

TEST(CanSimple, IdsCarryNodeAndCommand) {
  EXPECT_EQ(make_id(0x3F, Cmd::ClearErrors), 0x7F8u);
  EXPECT_EQ(node_of(0x7F8), 0x3F);
  EXPECT_EQ(cmd_of(0x7F8), uint8_t(Cmd::ClearErrors));
  // Node ids are six bits: higher bits never spill into the id.
  EXPECT_EQ(make_id(0x41, Cmd::Heartbeat), make_id(0x01, Cmd::Heartbeat));
}

TEST(CanSimple, GetRequestsAreRemoteFramesWithoutPayload) {
  can_frame f = get_request_frame(5, Cmd::GetBusVoltageCurrent);
  EXPECT_EQ(f.can_id, CAN_RTR_FLAG | (5u << 5 | 0x17u));
  EXPECT_EQ(f.len, 0);
  EXPECT_TRUE(is_get_request(f));
  EXPECT_FALSE(is_plain_data(f));
  can_frame dlc0 = empty_frame(5, Cmd::GetEncoderEstimates);  // ODrive answers these too
  EXPECT_TRUE(is_get_request(dlc0));
  can_frame ext = f;
  ext.can_id |= CAN_EFF_FLAG;
  EXPECT_FALSE(is_get_request(ext));
}

TEST(CanSimple, RoundTripsAndShortFrames) {
  Heartbeat hb{0x4000, AxisState::ClosedLoopControl, true, false, true, true};
  Heartbeat back;
  ASSERT_TRUE(parse(heartbeat_frame(3, hb), back));
  EXPECT_EQ(back.axis_error, 0x4000u);
  EXPECT_EQ(back.state, AxisState::ClosedLoopControl);
  EXPECT_TRUE(back.motor_error);
  EXPECT_FALSE(back.encoder_error);
  EXPECT_TRUE(back.controller_error);
  EXPECT_TRUE(back.trajectory_done);

  can_frame est = encoder_estimates_frame(3, {-1234.5f, 7.25f});
  EncoderEstimates e;
  ASSERT_TRUE(parse(est, e));
  EXPECT_EQ(e.pos_turns, -1234.5f);
  EXPECT_EQ(e.vel_turns_s, 7.25f);
  est.len = 7;  // one byte short: refused, output untouched
  EncoderEstimates untouched{1, 2};
  EXPECT_FALSE(parse(est, untouched));
  EXPECT_EQ(untouched.pos_turns, 1.0f);

  can_frame hb_short = heartbeat_frame(3, hb);
  hb_short.len = 4;
  EXPECT_FALSE(parse(hb_short, back));
}

TEST(CanSimple, ErrorNames) {
  EXPECT_STREQ(axis_error_name(0), "NONE");
  EXPECT_STREQ(axis_error_name(axis_error::kWatchdogTimerExpired), "WATCHDOG_TIMER_EXPIRED");
  // Several bits: the lowest names the message.
  EXPECT_STREQ(axis_error_name(axis_error::kEstopRequested | axis_error::kMotorFailed), "MOTOR_FAILED");
  EXPECT_STREQ(axis_error_name(0x80000000u), "UNKNOWN");
}

// ---- The DBC -------------------------------------------------------------------

struct DbcSignal {
  int start = 0, length = 0;
  bool little_endian = true, is_signed = false, is_float = false;
};
struct DbcMessage {
  std::string name;
  int dlc = 0;
  std::map<std::string, DbcSignal> signals;
};

// Reads the parts of a DBC the codec must agree with: messages (BO_), their
// signals (SG_) and which signals are IEEE floats (SIG_VALTYPE_ ... : 1).
std::map<uint32_t, DbcMessage> read_dbc(const std::string& path) {
  std::map<uint32_t, DbcMessage> out;
  std::ifstream in(path);
  std::string line;
  DbcMessage* current = nullptr;
  while (std::getline(in, line)) {
    if (!line.empty() && line.back() == '\r') line.pop_back();
    std::istringstream s(line);
    std::string tag;
    s >> tag;
    if (tag == "BO_") {
      uint32_t id;
      std::string name;
      int dlc;
      s >> id >> name >> dlc;
      name.pop_back();  // the ':'
      current = &out[id];
      current->name = name;
      current->dlc = dlc;
    } else if (tag == "SG_" && current) {
      std::string name, colon, layout;
      s >> name >> colon >> layout;  // 32|8@1+
      DbcSignal sig;
      sig.start = std::stoi(layout.substr(0, layout.find('|')));
      sig.length = std::stoi(layout.substr(layout.find('|') + 1, layout.find('@')));
      sig.little_endian = layout[layout.find('@') + 1] == '1';
      sig.is_signed = layout.back() == '-';
      current->signals[name] = sig;
    } else if (tag == "SIG_VALTYPE_") {
      uint32_t id;
      std::string name, colon;
      int type;
      s >> id >> name >> colon >> type;
      if (out.count(id) && out[id].signals.count(name)) out[id].signals[name].is_float = type == 1;
    } else if (tag.empty()) {
      current = nullptr;
    }
  }
  return out;
}

uint64_t raw_bits(const can_frame& f, const DbcSignal& sig) {
  uint64_t payload = 0;
  for (int i = 0; i < 8; ++i) payload |= uint64_t(f.data[i]) << (8 * i);
  uint64_t mask = sig.length == 64 ? ~0ull : ((1ull << sig.length) - 1);
  return (payload >> sig.start) & mask;
}

double decode(const can_frame& f, const DbcSignal& sig) {
  uint64_t raw = raw_bits(f, sig);
  if (sig.is_float) {
    uint32_t bits = uint32_t(raw);
    float v;
    std::memcpy(&v, &bits, 4);
    return v;
  }
  if (sig.is_signed && sig.length < 64 && (raw >> (sig.length - 1)) & 1)
    return double(int64_t(raw - (1ull << sig.length)));
  return double(raw);
}

void encode(can_frame& f, const DbcSignal& sig, double value) {
  uint64_t raw;
  if (sig.is_float) {
    float v = float(value);
    uint32_t bits;
    std::memcpy(&bits, &v, 4);
    raw = bits;
  } else {
    raw = uint64_t(int64_t(value));
  }
  for (int b = 0; b < sig.length; ++b) {
    int bit = sig.start + b;
    if ((raw >> b) & 1) f.data[bit / 8] |= uint8_t(1u << (bit % 8));
  }
}

class CanSimpleDbc : public ::testing::Test {
 protected:
  void SetUp() override {
    const std::string path = std::string(TROUPE_SHARED_DATA) + "/odrive/odrive-cansimple.dbc";
    if (!std::ifstream(path).good())
      GTEST_SKIP() << "ODrive DBC not found at " << path << " (third-party data)";
    dbc_ = read_dbc(path);
    ASSERT_GT(dbc_.size(), 100u) << "could not read " << path;
  }

  // The DBC entry for a frame, checked to be `name` on the frame's node.
  const DbcMessage& entry(const can_frame& f, const std::string& name) {
    uint32_t id = f.can_id & CAN_SFF_MASK;
    auto it = dbc_.find(id);
    EXPECT_NE(it, dbc_.end()) << "id 0x" << std::hex << id << " is not in the DBC";
    if (it == dbc_.end()) return empty_;
    EXPECT_EQ(it->second.name, "Axis" + std::to_string(node_of(id)) + "_" + name);
    return it->second;
  }

  // Decodes every signal of `f` with the DBC and compares with `expected`.
  void expect_signals(const can_frame& f, const std::string& name,
                      const std::map<std::string, double>& expected) {
    const DbcMessage& m = entry(f, name);
    EXPECT_EQ(int(f.len), m.dlc) << name;
    EXPECT_EQ(m.signals.size(), expected.size()) << name << ": the DBC has other signals";
    for (const auto& [signal, value] : expected) {
      auto s = m.signals.find(signal);
      ASSERT_NE(s, m.signals.end()) << name << " has no signal " << signal;
      EXPECT_TRUE(s->second.little_endian) << signal;
      EXPECT_DOUBLE_EQ(decode(f, s->second), value) << name << "." << signal;
    }
  }

  std::map<uint32_t, DbcMessage> dbc_;
  DbcMessage empty_;
};

TEST_F(CanSimpleDbc, FramesTheDriverSendsMatchTheDbc) {
  for (uint8_t node : {0, 3, 7}) {
    SCOPED_TRACE("node " + std::to_string(node));
    expect_signals(set_input_vel_frame(node, {2.0f, -0.5f}), "Set_Input_Vel",
                   {{"Input_Vel", 2.0}, {"Input_Torque_FF", -0.5}});
    expect_signals(set_axis_state_frame(node, AxisState::ClosedLoopControl), "Set_Axis_State",
                   {{"Axis_Requested_State", 8}});
    expect_signals(set_controller_modes_frame(node, {ControlMode::Velocity, InputMode::VelRamp}),
                   "Set_Controller_Mode", {{"Control_Mode", 2}, {"Input_Mode", 2}});
    expect_signals(set_limits_frame(node, {12.5f, 20.0f}), "Set_Limits",
                   {{"Velocity_Limit", 12.5}, {"Current_Limit", 20.0}});
    expect_signals(empty_frame(node, Cmd::ClearErrors), "Clear_Errors", {});
    expect_signals(empty_frame(node, Cmd::Reboot), "Reboot", {});
    // Get requests carry no data; the DBC lists the reply on the same id.
    EXPECT_EQ(entry(get_request_frame(node, Cmd::GetEncoderEstimates), "Get_Encoder_Estimates").dlc, 8);
    EXPECT_EQ(entry(get_request_frame(node, Cmd::GetBusVoltageCurrent), "Get_Bus_Voltage_Current").dlc, 8);
  }
}

TEST_F(CanSimpleDbc, FramesTheEmulatorSendsMatchTheDbc) {
  Heartbeat hb{0x800, AxisState::ClosedLoopControl, true, false, true, true};
  expect_signals(heartbeat_frame(2, hb), "Heartbeat",
                 {{"Axis_Error", 0x800},
                  {"Axis_State", 8},
                  {"Motor_Error_Flag", 1},
                  {"Encoder_Error_Flag", 0},
                  {"Controller_Error_Flag", 1},
                  {"Trajectory_Done_Flag", 1}});
  expect_signals(encoder_estimates_frame(2, {123.25f, -4.5f}), "Get_Encoder_Estimates",
                 {{"Pos_Estimate", 123.25}, {"Vel_Estimate", -4.5}});
  expect_signals(bus_voltage_current_frame(2, {24.5f, -1.25f}), "Get_Bus_Voltage_Current",
                 {{"Bus_Voltage", 24.5}, {"Bus_Current", -1.25}});
}

TEST_F(CanSimpleDbc, FramesLaidOutByTheDbcParse) {
  const uint8_t node = 6;
  auto build = [&](Cmd cmd, const std::map<std::string, double>& values) {
    can_frame f;
    std::memset(&f, 0, sizeof f);
    f.can_id = make_id(node, cmd);
    const DbcMessage& m = dbc_.at(f.can_id);
    f.len = uint8_t(m.dlc);
    for (const auto& [signal, value] : values) encode(f, m.signals.at(signal), value);
    return f;
  };
  Heartbeat hb;
  ASSERT_TRUE(
      parse(build(Cmd::Heartbeat, {{"Axis_Error", 0x40}, {"Axis_State", 1}, {"Encoder_Error_Flag", 1}}), hb));
  EXPECT_EQ(hb.axis_error, 0x40u);
  EXPECT_EQ(hb.state, AxisState::Idle);
  EXPECT_TRUE(hb.encoder_error);
  EXPECT_FALSE(hb.motor_error);
  EncoderEstimates est;
  ASSERT_TRUE(parse(build(Cmd::GetEncoderEstimates, {{"Pos_Estimate", -0.125}, {"Vel_Estimate", 9.5}}), est));
  EXPECT_EQ(est.pos_turns, -0.125f);
  EXPECT_EQ(est.vel_turns_s, 9.5f);
  BusVoltageCurrent bus;
  ASSERT_TRUE(parse(build(Cmd::GetBusVoltageCurrent, {{"Bus_Voltage", 48.0}, {"Bus_Current", 3.5}}), bus));
  EXPECT_EQ(bus.volts, 48.0f);
  EXPECT_EQ(bus.amps, 3.5f);
  InputVel in;
  ASSERT_TRUE(parse(build(Cmd::SetInputVel, {{"Input_Vel", -7.0}, {"Input_Torque_FF", 0.25}}), in));
  EXPECT_EQ(in.vel_turns_s, -7.0f);
  EXPECT_EQ(in.torque_ff, 0.25f);
}

}  // namespace
}  // namespace troupe::cansimple
