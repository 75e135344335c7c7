// The LMS200 emulator as a client sees it, through its pty, on the
// emulator's own clock: replies, baud changes, variants, configuration and
// continuous output paced by the line's speed.
#include "host-sim/emulators/sicklms200/sick_emulator.h"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "tests/device_harness/device_harness.h"
#include "tests/device_harness/raw_port.h"

namespace troupe::emulators {
namespace {

namespace sick = drivers::sicklms200;
using Bytes = std::vector<uint8_t>;

constexpr uint64_t kMs = 1000;

// The client's end of the pty, speaking SICK telegrams.
class Client : public testing::RawPort {
 public:
  using testing::RawPort::RawPort;
  void send(const sick::Telegram& t) { ASSERT_TRUE(write(t.view())); }
  // Reply bodies that have arrived; ACK and NACK bytes are counted.
  std::vector<Bytes> replies() {
    std::vector<Bytes> out;
    Bytes bytes = read_all();
    acks += uint32_t(std::count(bytes.begin(), bytes.end(), sick::kAck));
    sick::scan_telegrams(scanner_, bytes,
                         [&](std::span<const uint8_t> b) { out.emplace_back(b.begin(), b.end()); });
    return out;
  }
  uint32_t nacks() const { return scanner_.nacks(); }
  uint32_t acks = 0;

 private:
  sick::TelegramScanner scanner_{sick::kReplyAddress};
};

class SickEmulatorTest : public ::testing::Test {
 protected:
  void start(SickEmulator::Config config = {}) {
    scanner_ = std::make_unique<SickEmulator>(config);
    std::string error;
    ASSERT_TRUE(scanner_->open(dir_.file("laser"), error)) << error;
    client_ = std::make_unique<Client>(scanner_->path(), B9600);
    ASSERT_TRUE(client_->ok());
    scanner_->step(now_);
  }
  void step(uint64_t dt_us) {
    uint64_t end = now_ + dt_us;
    do {
      now_ = std::min(end, now_ + kMs);
      scanner_->step(now_);
    } while (now_ < end);
  }
  // Sends `t` and returns the replies that came within `wait_us`.
  std::vector<Bytes> ask(const sick::Telegram& t, uint64_t wait_us = 100 * kMs) {
    client_->send(t);
    step(wait_us);
    return client_->replies();
  }

  testing::TempDir dir_;
  std::unique_ptr<SickEmulator> scanner_;
  std::unique_ptr<Client> client_;
  uint64_t now_ = 1'000'000;
};

TEST_F(SickEmulatorTest, PowersUpSilentAndAnswersWithAckThenReply) {
  start();
  step(500 * kMs);
  EXPECT_TRUE(client_->replies().empty());
  auto r = ask(sick::simple(sick::Request::Type));
  ASSERT_EQ(r.size(), 1u);
  EXPECT_EQ(r[0][0], 0xBA);
  EXPECT_EQ(std::string(r[0].begin() + 1, r[0].end() - 1), "LMS200;30106");
  EXPECT_EQ(client_->acks, 1u);
}

TEST_F(SickEmulatorTest, ConfigurationModeNeedsThePassword) {
  start();
  const uint8_t wrong[] = {0x20, 0x00, 'S', 'I', 'C', 'K', '_', 'X', 'X', 'X'};
  sick::Telegram t;
  sick::make_request(wrong, t);
  auto r = ask(t);
  ASSERT_EQ(r.size(), 1u);
  EXPECT_EQ(r[0], (Bytes{0xA0, 0x01, 0x00}));  // refused
  EXPECT_EQ(scanner_->mode(), SickEmulator::Mode::Monitor);
  r = ask(sick::enter_config());
  ASSERT_EQ(r.size(), 1u);
  EXPECT_EQ(r[0], (Bytes{0xA0, 0x00, 0x00}));
  EXPECT_EQ(scanner_->mode(), SickEmulator::Mode::Installation);
}

TEST_F(SickEmulatorTest, WritingTheConfigurationNeedsConfigurationMode) {
  start();
  auto r = ask(sick::simple(sick::Request::ReadConfig));
  ASSERT_EQ(r.size(), 1u);
  ASSERT_EQ(r[0].size(), 2 + sick::kConfigBytes);
  Bytes config(r[0].begin() + 1, r[0].end() - 1);
  EXPECT_EQ(config[sick::kConfigUnits], 0);  // centimetres from the factory
  config[sick::kConfigUnits] = 1;
  EXPECT_TRUE(ask(sick::write_config(config)).empty());
  EXPECT_EQ(client_->nacks(), 1u);
  EXPECT_EQ(scanner_->units(), sick::Units::Centimetres);
  ask(sick::enter_config());
  r = ask(sick::write_config(config));
  ASSERT_EQ(r.size(), 1u);
  EXPECT_EQ(r[0][0], 0xF7);
  EXPECT_EQ(r[0][1], 1);
  EXPECT_EQ(scanner_->units(), sick::Units::Millimetres);
}

TEST_F(SickEmulatorTest, ABadCrcIsAnsweredNack) {
  start();
  sick::Telegram t = sick::simple(sick::Request::Type);
  t.bytes[t.size - 1] ^= 0xFF;
  EXPECT_TRUE(ask(t).empty());
  EXPECT_EQ(client_->nacks(), 1u);
  EXPECT_EQ(scanner_->nacks_sent(), 1u);
}

TEST_F(SickEmulatorTest, SwitchesBaudOnceItsReplyHasLeft) {
  start();
  sick::Telegram t;
  ASSERT_TRUE(sick::baud_change(38400, t));
  auto r = ask(t);
  ASSERT_EQ(r.size(), 1u);  // the reply came at 9600
  EXPECT_EQ(scanner_->baud(), 38400u);
  // Still at 9600 on our end, we hear garbage and are heard as garbage.
  EXPECT_TRUE(ask(sick::simple(sick::Request::Type)).empty());
  client_->set_speed(B38400);
  client_->replies();
  EXPECT_EQ(ask(sick::simple(sick::Request::Type)).size(), 1u);
}

TEST_F(SickEmulatorTest, AcceptsTheVariantsTheScannerHas) {
  start();
  auto r = ask(sick::variant(180, 50));
  ASSERT_EQ(r.size(), 1u);
  EXPECT_EQ(r[0], (Bytes{0xBB, 1, 180, 0, 50, 0, 0}));
  r = ask(sick::variant(180, 25));  // not offered at 180 degrees
  ASSERT_EQ(r.size(), 1u);
  EXPECT_EQ(r[0], (Bytes{0xBB, 0, 180, 0, 50, 0, 0}));
  EXPECT_EQ(scanner_->resolution_cdeg(), 50);
  r = ask(sick::variant(100, 25));
  EXPECT_EQ(r[0][1], 1);
  EXPECT_EQ(scanner_->width_deg(), 100);
}

TEST_F(SickEmulatorTest, ContinuousOutputIsPacedByTheLine) {
  start();
  ask(sick::mode_change(sick::Mode::Continuous));
  uint32_t before = scanner_->scans_sent();
  step(2000 * kMs);
  // 181 values: a 372-byte telegram, 0.3875 s at 9600 baud.
  uint32_t sent = scanner_->scans_sent() - before;
  EXPECT_GE(sent, 4u);
  EXPECT_LE(sent, 6u);
  Bytes stream = client_->read_all();
  sick::TelegramScanner s(sick::kReplyAddress);
  uint32_t scans = 0;
  sick::scan_telegrams(s, stream, [&](std::span<const uint8_t> b) {
    sick::Reply r;
    sick::Scan scan;
    ASSERT_TRUE(sick::split_reply(b, r));
    ASSERT_EQ(r.code, sick::kScanReply);
    ASSERT_TRUE(sick::parse_scan(r.data, scan, nullptr));
    EXPECT_EQ(scan.count, 181);
    EXPECT_EQ(scan.units, sick::Units::Centimetres);
    ++scans;
  });
  EXPECT_GE(scans, sent - 1);  // the last may still be on the line
}

TEST_F(SickEmulatorTest, AtHighSpeedTheScanRateIsTheScanners) {
  SickEmulator::Config config;
  config.power_up_baud = 500000;
  start(config);
  client_->set_speed(B500000);
  ask(sick::mode_change(sick::Mode::Continuous));
  uint32_t before = scanner_->scans_sent();
  step(1000 * kMs);
  uint32_t sent = scanner_->scans_sent() - before;
  EXPECT_GE(sent, 74u);
  EXPECT_LE(sent, 76u);
}

TEST_F(SickEmulatorTest, ScansMeasureTheCorridor) {
  start();
  ask(sick::enter_config());
  ask(sick::mode_change(sick::Mode::Continuous));
  step(1000 * kMs);
  std::span<const uint16_t> scan = scanner_->last_scan();
  ASSERT_EQ(scan.size(), 181u);
  // Centimetres, as from the factory. Beam 0 looks right (-90 degrees) at
  // the wall 3 m away, beam 90 down the corridor to its end 10 m away.
  EXPECT_EQ(scan[0], 300);
  EXPECT_EQ(scan[180], 300);
  EXPECT_EQ(scan[90], 1000);
  EXPECT_EQ(scan[45], uint16_t(std::lround(300 / std::cos(45 * 3.14159265358979 / 180))));
}

TEST_F(SickEmulatorTest, APowerCycleKeepsTheStoredSettings) {
  start();
  sick::Telegram t;
  sick::baud_change(38400, t);
  ask(t);
  client_->set_speed(B38400);
  ask(sick::variant(180, 50));
  scanner_->power_cycle();
  EXPECT_EQ(scanner_->baud(), 9600u);
  EXPECT_EQ(scanner_->mode(), SickEmulator::Mode::Monitor);
  EXPECT_EQ(scanner_->resolution_cdeg(), 50);
}

}  // namespace
}  // namespace troupe::emulators
