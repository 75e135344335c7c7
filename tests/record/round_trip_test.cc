// Record and replay end to end, as a user runs them: troupe-node (or
// room_node) serving, `troupe record` writing a log, `troupe play` serving
// it again, and a client comparing what it sees with what was recorded.
// Also: truncated and corrupted logs play their valid part, and a recording
// survives the node restarting.
#include <gtest/gtest.h>
#include <signal.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <fstream>
#include <iterator>
#include <map>
#include <string>
#include <thread>
#include <vector>

#include "tests/record/process.h"
#include "wire/client/client.h"
#include "wire/record/log_file.h"

namespace troupe::testing {
namespace {

using Bytes = std::vector<uint8_t>;

const std::string kExample = std::string(TROUPE_SOURCE_DIR) + "/examples/nodes/kinematic.json";
const std::string kRoomWorld = std::string(TROUPE_SOURCE_DIR) + "/examples/worlds/room.world";

/// What a client saw of one Data message, and what the log holds: the
/// device, the sender's timestamp and the body's values.
struct Sample {
  uint64_t key = 0;  // wire::address_key
  uint64_t time_us = 0;
  std::vector<float> values;
  bool operator==(const Sample&) const = default;
};

Sample sample_of(const wire::Message& msg) {
  Sample s{wire::address_key(msg.header()->addr()), wire::time_us(*msg.header()), {}};
  if (const wire::Position2dState* p = msg.body_as_Position2dState()) {
    if (p->pose()) s.values.insert(s.values.end(), {p->pose()->x(), p->pose()->y(), p->pose()->a()});
    if (p->vel()) s.values.insert(s.values.end(), {p->vel()->x(), p->vel()->y(), p->vel()->a()});
  } else if (const wire::RangerScan* r = msg.body_as_RangerScan()) {
    s.values.insert(s.values.end(), {r->scale(), r->min_angle(), r->angular_res(), r->max_range()});
    if (r->ranges()) {
      for (uint16_t v : *r->ranges()) s.values.push_back(float(v));
    }
  }
  return s;
}

std::vector<Sample> samples_in(const std::string& path, std::string* problem = nullptr) {
  record::LogReader reader;
  std::string error;
  EXPECT_TRUE(reader.open(path, error)) << error;
  std::vector<Sample> out;
  record::LogRecord r;
  while (reader.next(r)) {
    if (r.message->header()->kind() == wire::Kind::Data) out.push_back(sample_of(*r.message));
  }
  if (problem != nullptr) *problem = reader.problem();
  return out;
}

/// Data records in a log being written (0 before the file exists).
size_t data_count(const std::string& path) {
  record::LogReader reader;
  std::string error;
  if (!reader.open(path, error)) return 0;
  size_t n = 0;
  record::LogRecord r;
  while (reader.next(r)) n += r.message->header()->kind() == wire::Kind::Data;
  return n;
}

std::vector<uint64_t> data_offsets(const std::string& path) {
  record::LogReader reader;
  std::string error;
  EXPECT_TRUE(reader.open(path, error)) << error;
  std::vector<uint64_t> out;
  record::LogRecord r;
  while (reader.next(r)) {
    if (r.message->header()->kind() == wire::Kind::Data) out.push_back(r.offset);
  }
  return out;
}

/// Each device's frames arrive in order; across devices, frames due at the
/// same moment may interleave differently, so logs and replays are compared
/// per device.
std::map<uint64_t, std::vector<Sample>> by_device(const std::vector<Sample>& samples) {
  std::map<uint64_t, std::vector<Sample>> m;
  for (const Sample& s : samples) m[s.key].push_back(s);
  return m;
}

Bytes read_file(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return Bytes(std::istreambuf_iterator<char>(in), {});
}

void write_file(const std::string& path, const Bytes& bytes) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out.write(reinterpret_cast<const char*>(bytes.data()), std::streamsize(bytes.size()));
}

class RecordReplay : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = std::string(P_tmpdir) + "/troupe-record-test-XXXXXX";
    ASSERT_NE(mkdtemp(dir_.data()), nullptr);
  }
  void TearDown() override {
    for (const std::string& f : files_) unlink(f.c_str());
    rmdir(dir_.c_str());
  }
  std::string file(const std::string& name) {
    files_.push_back(dir_ + "/" + name);
    return files_.back();
  }
  static Outcome troupe(std::vector<std::string> args) {
    args.insert(args.begin(), bin("bin/troupe"));
    return run_program(std::move(args));
  }
  static std::string host(uint16_t port) { return "127.0.0.1:" + std::to_string(port); }

  /// Records `count` samples of the kinematic example's position2d:0 into
  /// the file `name`; its path.
  std::string record_kinematic(const std::string& name, int count) {
    uint16_t port = free_port();
    Process node({bin("bin/troupe-node"), kExample, "--port", std::to_string(port)});
    EXPECT_TRUE(node.wait_listening(port)) << node.err();
    std::string log = file(name);
    EXPECT_EQ(troupe({"record", host(port), "position2d:0", "-o", log, "--count", std::to_string(count)}).rc,
              0);
    EXPECT_EQ(node.stop(), 0);
    return log;
  }

  /// Plays `log` with `troupe play --wait` and collects what a client sees
  /// of `devices`, until the player exits.
  std::vector<Sample> play(const std::string& log, const std::vector<std::string>& devices,
                           std::vector<std::string> extra = {}, std::string* player_err = nullptr) {
    uint16_t port = free_port();
    std::vector<std::string> args = {bin("bin/troupe"), "play",  log, "--port",
                                     std::to_string(port),   "--wait"};
    args.insert(args.end(), extra.begin(), extra.end());
    Process player(args);
    EXPECT_TRUE(player.wait_listening(port)) << player.err();
    client::Client c("127.0.0.1", port);
    EXPECT_TRUE(c.connect()) << c.error();
    std::vector<Sample> seen;
    c.add_data_handler([&](const wire::Message& msg) { seen.push_back(sample_of(msg)); });
    for (const std::string& d : devices) {
      wire::Address a;
      EXPECT_TRUE(c.resolve(d, a)) << c.error();
      EXPECT_TRUE(c.open(a, wire::Access::Read)) << c.error();
    }
    auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(60);
    while (player.running() && std::chrono::steady_clock::now() < deadline) c.spin_once(50);
    c.spin_for(100);
    EXPECT_EQ(player.wait(), 0) << player.err();
    if (player_err != nullptr) *player_err = player.err();
    return seen;
  }

  std::string dir_;
  std::vector<std::string> files_;
};

TEST_F(RecordReplay, AClientSeesTheRecordedDataWithItsTimestamps) {
  uint16_t port = free_port();
  Process node({bin("bin/troupe-node"), kExample, "--port", std::to_string(port)});
  ASSERT_TRUE(node.wait_listening(port)) << node.err();
  ASSERT_EQ(troupe({"cmd", host(port), "position2d:0", "vel", "0.4", "0", "0.3"}).rc, 0);
  std::string log = file("base.trl");
  Outcome rec = troupe({"record", host(port), "position2d:0", "-o", log, "--count", "20"});
  ASSERT_EQ(rec.rc, 0) << rec.err;
  EXPECT_NE(rec.err.find("recorded 20 frames"), std::string::npos) << rec.err;
  EXPECT_EQ(node.stop(), 0);

  std::vector<Sample> recorded = samples_in(log);
  ASSERT_EQ(recorded.size(), 20u);
  // The base was moving: the recorded poses differ from one another.
  EXPECT_NE(recorded.front().values, recorded.back().values);

  Outcome info = troupe({"play", log, "--info"});
  ASSERT_EQ(info.rc, 0) << info.err;
  EXPECT_NE(info.out.find("records   22 (20 data)"), std::string::npos) << info.out;
  EXPECT_NE(info.out.find("device    position2d:0\tkinematic"), std::string::npos) << info.out;
  EXPECT_NE(info.out.find("status    complete"), std::string::npos) << info.out;

  EXPECT_EQ(play(log, {"position2d:0"}), recorded);
  // Faster, the same data.
  EXPECT_EQ(play(log, {"position2d:0"}, {"--speed", "4"}), recorded);
}

TEST_F(RecordReplay, TwoDevicesOfRoomNodeIncludingLaserScans) {
  uint16_t port = free_port();
  Process node({bin("tests/python/room_node"), "--port", std::to_string(port)});
  ASSERT_TRUE(node.wait_listening(port)) << node.err();
  ASSERT_EQ(troupe({"cmd", host(port), "position2d:0", "vel", "0.3", "0", "0.5"}).rc, 0);
  std::string log = file("room.trl");
  Outcome rec = troupe({"record", host(port), "position2d:0", "ranger:0", "-o", log, "--count", "30"});
  ASSERT_EQ(rec.rc, 0) << rec.err;
  EXPECT_EQ(node.stop(), 0);
  std::vector<Sample> recorded = samples_in(log);
  ASSERT_EQ(recorded.size(), 30u);
  std::map<uint64_t, int> per_device;
  for (const Sample& s : recorded) ++per_device[s.key];
  ASSERT_EQ(per_device.size(), 2u);

  Outcome ls_info = troupe({"play", log, "--info"});
  EXPECT_NE(ls_info.out.find("device    ranger:0\troom-laser"), std::string::npos) << ls_info.out;
  std::vector<Sample> seen = play(log, {"position2d:0", "ranger:0"}, {"--speed", "2"});
  EXPECT_EQ(by_device(seen), by_device(recorded));
}

TEST_F(RecordReplay, ARobotOfTroupeSimPlaysBackUnderItsRobotName) {
  uint16_t port = free_port();
  Process sim({bin("bin/troupe-sim"), kRoomWorld, "--port", std::to_string(port), "--seed", "3"});
  ASSERT_TRUE(sim.wait_listening(port)) << sim.err();
  ASSERT_EQ(troupe({"cmd", host(port), "r0/position2d:0", "vel", "0.3", "0", "0.4"}).rc, 0);
  std::string log = file("sim.trl");
  Outcome rec = troupe({"record", host(port), "r0/position2d:0", "r0/ranger:0", "-o", log, "--count", "30"});
  ASSERT_EQ(rec.rc, 0) << rec.err;
  EXPECT_EQ(sim.stop(), 0);
  std::vector<Sample> recorded = samples_in(log);
  ASSERT_EQ(recorded.size(), 30u);
  std::map<uint64_t, std::vector<Sample>> per_device = by_device(recorded);
  ASSERT_EQ(per_device.size(), 2u);
  // The robot was turning: its pose and what its laser sees changed.
  for (const auto& [key, samples] : per_device)
    EXPECT_NE(samples.front().values, samples.back().values) << key;

  Outcome info = troupe({"play", log, "--info"});
  EXPECT_NE(info.out.find("node      troupe-sim\n"), std::string::npos) << info.out;
  EXPECT_NE(info.out.find("device    r0/ranger:0\ttroupe-sim"), std::string::npos) << info.out;
  // The replay serves the devices under the robot's name, so a client
  // written against the simulator finds them there.
  EXPECT_EQ(by_device(play(log, {"r0/position2d:0", "r0/ranger:0"})), per_device);
}

TEST_F(RecordReplay, TruncatedAndCorruptLogsPlayTheirValidPart) {
  std::string log = record_kinematic("whole.trl", 12);
  std::vector<Sample> recorded = samples_in(log);
  std::vector<uint64_t> offsets = data_offsets(log);
  ASSERT_EQ(offsets.size(), 12u);
  Bytes whole = read_file(log);

  // Cut in the middle of the 8th data record.
  std::string cut = file("cut.trl");
  write_file(cut, Bytes(whole.begin(), whole.begin() + long(offsets[7] + 30)));
  std::string at = "byte " + std::to_string(offsets[7]) + ": ";
  Outcome info = troupe({"play", cut, "--info"});
  EXPECT_NE(info.out.find("(7 data)"), std::string::npos) << info.out;
  EXPECT_NE(info.out.find(at), std::string::npos) << info.out;
  EXPECT_NE(info.out.find("truncated"), std::string::npos) << info.out;
  std::string err;
  std::vector<Sample> seen = play(cut, {"position2d:0"}, {}, &err);
  EXPECT_EQ(seen, std::vector<Sample>(recorded.begin(), recorded.begin() + 7));
  EXPECT_NE(err.find(at), std::string::npos) << err;

  // One flipped bit inside the 5th data record's frame.
  std::string flipped = file("flipped.trl");
  Bytes bad = whole;
  bad[offsets[4] + 40] ^= 0x01;
  write_file(flipped, bad);
  seen = play(flipped, {"position2d:0"}, {}, &err);
  EXPECT_EQ(seen, std::vector<Sample>(recorded.begin(), recorded.begin() + 4));
  EXPECT_NE(err.find("byte " + std::to_string(offsets[4]) + ": checksum mismatch"), std::string::npos) << err;

  // Garbage is not a log at all: refused, nothing served.
  std::string garbage = file("garbage.trl");
  write_file(garbage, Bytes(100, 0x42));
  Outcome refused = troupe({"play", garbage});
  EXPECT_EQ(refused.rc, 1);
  EXPECT_NE(refused.err.find("byte 0: not a troupe log"), std::string::npos) << refused.err;
}

// A recording whose record time jumps (a recorder clock that stepped, or a
// time damaged with its checksum redone) must not make play wait for days.
TEST_F(RecordReplay, ATimeJumpIsReportedAndNotWaitedFor) {
  std::string log = record_kinematic("jump.trl", 10);
  std::vector<Sample> recorded = samples_in(log);
  std::vector<uint64_t> offsets = data_offsets(log);
  ASSERT_EQ(offsets.size(), 10u);
  // The 6th data record's time to 2^40 us (twelve days), its CRC redone.
  Bytes bytes = read_file(log);
  uint8_t* rec = &bytes[offsets[5]];
  const uint64_t far = uint64_t(1) << 40;
  for (int i = 0; i < 8; ++i) rec[8 + i] = uint8_t(far >> (8 * i));
  const uint32_t size = wire::read_prefix(rec);
  const uint32_t crc = record::crc32({rec + 16, size}, record::crc32({rec + 8, 8}));
  for (int i = 0; i < 4; ++i) rec[4 + i] = uint8_t(crc >> (8 * i));
  write_file(log, bytes);

  Outcome info = troupe({"play", log, "--info"});
  EXPECT_EQ(info.rc, 0);
  EXPECT_NE(info.out.find("jumps     2"), std::string::npos) << info.out;  // there and back
  EXPECT_NE(info.out.find("jump      byte " + std::to_string(offsets[5]) + ": "), std::string::npos)
      << info.out;
  EXPECT_NE(info.out.find("status    complete"), std::string::npos) << info.out;
  EXPECT_EQ(info.out.find("duration  1099511"), std::string::npos) << info.out;
  // Played to its end, every frame, without waiting for the jump.
  std::string err;
  EXPECT_EQ(play(log, {"position2d:0"}, {}, &err), recorded);
  EXPECT_NE(err.find("byte " + std::to_string(offsets[5]) + ": the record time jumps"), std::string::npos)
      << err;
}

TEST_F(RecordReplay, RecordingGoesOnAcrossANodeRestart) {
  uint16_t port = free_port();
  auto node = std::make_unique<Process>(
      std::vector<std::string>{bin("bin/troupe-node"), kExample, "--port", std::to_string(port)});
  ASSERT_TRUE(node->wait_listening(port)) << node->err();
  std::string log = file("restart.trl");
  Process rec({bin("bin/troupe-record"), host(port), "position2d:0", "-o", log, "--count", "25"});
  // Once some frames are in the file, restart the node (its sample counter
  // starts again at 1).
  for (int i = 0; i < 1000 && rec.running() && data_count(log) < 5; ++i) {
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  ASSERT_GE(data_count(log), 5u) << rec.err();
  EXPECT_EQ(node->stop(), 0);
  node = std::make_unique<Process>(
      std::vector<std::string>{bin("bin/troupe-node"), kExample, "--port", std::to_string(port)});
  ASSERT_TRUE(node->wait_listening(port)) << node->err();
  ASSERT_EQ(rec.wait(), 0) << rec.err();
  EXPECT_NE(rec.err().find("reconnected"), std::string::npos) << rec.err();
  record::LogReader reader;
  std::string error;
  ASSERT_TRUE(reader.open(log, error)) << error;
  record::LogRecord r;
  std::vector<uint32_t> seqs;
  while (reader.next(r)) {
    if (r.message->header()->kind() == wire::Kind::Data) seqs.push_back(r.message->header()->seq());
  }
  EXPECT_EQ(reader.problem(), "");
  ASSERT_EQ(seqs.size(), 25u);
  int restarts = 0;
  for (size_t i = 1; i < seqs.size(); ++i) restarts += seqs[i] < seqs[i - 1];
  EXPECT_EQ(restarts, 1) << "frames of both node sessions are in the log";
}

TEST_F(RecordReplay, RecordErrorsAreOneLineAndCreateNoFile) {
  uint16_t port = free_port();
  Process node({bin("bin/troupe-node"), kExample, "--port", std::to_string(port)});
  ASSERT_TRUE(node.wait_listening(port)) << node.err();
  std::string log = file("never.trl");
  Outcome missing = troupe({"record", host(port), "ranger:0", "-o", log});
  EXPECT_EQ(missing.rc, 1);
  EXPECT_NE(missing.err.find("no such device ranger:0 on 127.0.0.1 (it has: position2d:0)"),
            std::string::npos)
      << missing.err;
  EXPECT_NE(access(log.c_str(), F_OK), 0) << "no file for a recording that never started";
  Outcome refused = troupe({"record", host(free_port()), "position2d:0", "-o", log});
  EXPECT_EQ(refused.rc, 1);
  EXPECT_NE(refused.err.find("Connection refused"), std::string::npos) << refused.err;
  Outcome no_output = troupe({"record", host(port), "position2d:0"});
  EXPECT_EQ(no_output.rc, 2);
  EXPECT_NE(no_output.err.find("missing -o FILE"), std::string::npos) << no_output.err;
  Outcome bad_addr = troupe({"record", host(port), "laser:0", "-o", log});
  EXPECT_EQ(bad_addr.rc, 2);
  EXPECT_NE(bad_addr.err.find("unknown interface 'laser'"), std::string::npos) << bad_addr.err;
  for (const Outcome* r : {&missing, &refused, &no_output, &bad_addr}) {
    EXPECT_EQ(std::count(r->err.begin(), r->err.end(), '\n'), 1) << r->err;
  }
  EXPECT_EQ(node.stop(), 0);
}

TEST(RecordReplayHelp, EverySubcommandHasHelpWithExamples) {
  for (const char* sub : {"record", "play"}) {
    for (std::vector<std::string> args : {std::vector<std::string>{sub, "--help"}, {"help", sub}}) {
      args.insert(args.begin(), bin("bin/troupe"));
      Outcome r = run_program(args);
      EXPECT_EQ(r.rc, 0) << sub;
      EXPECT_EQ(r.out.rfind(std::string("usage: troupe ") + sub, 0), 0u) << r.out;
      EXPECT_NE(r.out.find("examples:\n  troupe " + std::string(sub)), std::string::npos) << r.out;
    }
  }
}

}  // namespace
}  // namespace troupe::testing
