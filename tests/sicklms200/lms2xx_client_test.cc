// Independent LMS2xx clients' start-up sequences, played byte for byte
// against the scanner emulator on a real pseudo-terminal (learnt from the
// public source of sicktoolbox's SickLMS2xx and ARIA's ArLMS2xx):
//  - ARIA: reset (0x10) at 9600 baud, then wait for the power-on message;
//  - sicktoolbox: ask for the session baud; when that times out, find the
//    scanner's baud by asking for its errors (0x32) at 9600, 19200, 38400
//    and 500000 in turn; then monitor mode, type, status, configuration,
//    the configuration round trip in installation mode, the variant and
//    mean values.
// The emulator runs on its own clock (step()); its line is paced at its
// baud, so replies take the time the bytes take.
#include <gtest/gtest.h>

#include <vector>

#include "drivers/sicklms200/sick_protocol.h"
#include "host-sim/emulators/sicklms200/sick_emulator.h"
#include "tests/device_harness/device_harness.h"
#include "tests/device_harness/raw_port.h"

namespace troupe::emulators {
namespace {

namespace sick = drivers::sicklms200;
using Bytes = std::vector<uint8_t>;

constexpr uint64_t kMs = 1000;

struct Reply {
  uint8_t code = 0;
  Bytes data;
};

class Lms2xxClient : public ::testing::Test {
 protected:
  void start(SickEmulator::Config config) {
    config.startup_us = 500 * kMs;
    scanner_ = std::make_unique<SickEmulator>(config);
    std::string error;
    ASSERT_TRUE(scanner_->open(dir_.file("laser"), error)) << error;
    port_ = std::make_unique<testing::RawPort>(scanner_->path(), B9600);
    ASSERT_TRUE(port_->ok());
    scanner_->step(0);
  }
  void run(uint64_t dt_us) {
    uint64_t end = now_ + dt_us;
    while (now_ < end) {
      now_ = std::min(end, now_ + 5 * kMs);
      scanner_->step(now_);
      Bytes in = port_->read_all();
      sick::scan_telegrams(replies_scanner_, in, [&](std::span<const uint8_t> body) {
        sick::Reply r;
        if (sick::split_reply(body, r)) heard_.push_back({r.code, Bytes(r.data.begin(), r.data.end())});
      });
    }
  }
  // Sends a request and waits up to `timeout_us` (the client's timeout) for
  // the reply `code`; empty code 0 when none came.
  Reply ask(const Bytes& body, uint8_t code, uint64_t timeout_us = 300 * kMs) {
    sick::Telegram t;
    EXPECT_TRUE(sick::make_request(body, t));
    EXPECT_TRUE(port_->write(t.view()));
    return wait_for(code, timeout_us);
  }
  Reply wait_for(uint8_t code, uint64_t timeout_us) {
    for (uint64_t waited = 0; waited < timeout_us; waited += 5 * kMs) {
      run(5 * kMs);
      for (size_t i = 0; i < heard_.size(); ++i) {
        if (heard_[i].code != code) continue;
        Reply r = heard_[i];
        heard_.erase(heard_.begin(), heard_.begin() + long(i) + 1);
        return r;
      }
    }
    return {};
  }
  // sicktoolbox's baud test: the error list at `speed`.
  bool answers_at(speed_t speed) {
    port_->set_speed(speed);
    heard_.clear();
    return ask({0x32}, 0xB2).code == 0xB2;
  }
  static uint16_t le16(const Bytes& b, size_t at) { return uint16_t(b[at] | (b[at + 1] << 8)); }

  testing::TempDir dir_;
  std::unique_ptr<SickEmulator> scanner_;
  std::unique_ptr<testing::RawPort> port_;
  sick::TelegramScanner replies_scanner_{sick::kReplyAddress};
  std::vector<Reply> heard_;
  uint64_t now_ = 0;
};

TEST_F(Lms2xxClient, ResetIsAcknowledgedThenThePowerOnMessageFollows) {
  start({});
  // ARIA's reset telegram, byte for byte.
  const Bytes reset = {0x02, 0x00, 0x01, 0x00, 0x10};
  uint16_t crc = sick::crc16(reset);
  Bytes telegram = reset;
  telegram.push_back(uint8_t(crc & 0xFF));
  telegram.push_back(uint8_t(crc >> 8));
  ASSERT_TRUE(port_->write(telegram));
  run(100 * kMs);
  ASSERT_FALSE(heard_.empty());
  EXPECT_EQ(heard_.front().code, sick::kResetReply);
  // Restarting, it hears nothing: a status request goes unanswered.
  EXPECT_EQ(ask({0x31}, 0xB1, 200 * kMs).code, 0);
  run(600 * kMs);
  bool powered_on = false;
  for (const Reply& r : heard_) {
    if (r.code != sick::kPowerOnReply) continue;
    powered_on = true;
    EXPECT_EQ(std::string(r.data.begin(), r.data.end()), "LMS200;30106");
  }
  EXPECT_TRUE(powered_on) << "no power-on message (0x90) after the start-up time";
  EXPECT_EQ(scanner_->baud(), 9600u);
  EXPECT_EQ(ask({0x31}, 0xB1).code, 0xB1) << "deaf after starting up";
}

TEST_F(Lms2xxClient, SicktoolboxFindsTheBaudAndReadsTheWholeStatus) {
  SickEmulator::Config config;
  config.power_up_baud = 500000;  // left at 500000 baud by an earlier run
  start(config);
  // It asks for 38400 at the default 9600: no answer at a wrong baud.
  EXPECT_EQ(ask({0x20, 0x40}, 0xA0).code, 0);
  // Baud detection, in sicktoolbox's order.
  EXPECT_FALSE(answers_at(B9600));
  EXPECT_FALSE(answers_at(B19200));
  EXPECT_FALSE(answers_at(B38400));
  ASSERT_TRUE(answers_at(B500000));
  // Then the session baud it wanted.
  Reply r = ask({0x20, 0x40}, 0xA0);
  ASSERT_EQ(r.code, 0xA0);
  EXPECT_EQ(r.data, Bytes{0});
  run(50 * kMs);
  port_->set_speed(B38400);
  EXPECT_EQ(ask({0x20, 0x25}, 0xA0).data, Bytes{0}) << "monitor mode, values on request";
  r = ask({0x3A}, 0xBA);
  EXPECT_EQ(std::string(r.data.begin(), r.data.end()), "LMS200;30106");
  r = ask({0x31}, 0xB1);
  ASSERT_EQ(r.data.size(), sick::kStatusBytes);
  EXPECT_EQ(std::string(r.data.begin(), r.data.begin() + 7), "V02.10 ");
  EXPECT_EQ(r.data[7], 0x25) << "operating mode";
  EXPECT_EQ(le16(r.data, 106), 180) << "scan angle, degrees";
  EXPECT_EQ(le16(r.data, 108), 100) << "resolution, 1/100 degree: sicktoolbox divides by it";
  EXPECT_EQ(r.data[121], uint8_t(sick::Units::Centimetres));
  EXPECT_EQ(le16(r.data, 115), 0x8019) << "the line's baud, 38400, as the listing codes it";
  EXPECT_EQ(r.data[118], 1) << "a baud kept over power cycles";
  r = ask({0x74}, 0xF4);
  ASSERT_EQ(r.data.size(), sick::kConfigBytes);
  EXPECT_EQ(r.data[sick::kConfigUnits], uint8_t(sick::Units::Centimetres));
}

TEST_F(Lms2xxClient, ConfigurationRoundTripVariantAndMeanValues) {
  start({});
  Bytes config = ask({0x74}, 0xF4).data;
  ASSERT_EQ(config.size(), sick::kConfigBytes);
  // Written only in installation mode.
  Bytes write = {0x77};
  config[sick::kConfigUnits] = uint8_t(sick::Units::Millimetres);
  write.insert(write.end(), config.begin(), config.end());
  EXPECT_EQ(ask(write, 0xF7).code, 0) << "written outside installation mode";
  Bytes login = {0x20, 0x00, 'S', 'I', 'C', 'K', '_', 'L', 'M', 'S'};
  ASSERT_EQ(ask(login, 0xA0).data, Bytes{0});
  Reply r = ask(write, 0xF7);
  ASSERT_FALSE(r.data.empty());
  EXPECT_EQ(r.data[0], 1);
  EXPECT_EQ(ask({0x74}, 0xF4).data[sick::kConfigUnits], uint8_t(sick::Units::Millimetres));
  EXPECT_EQ(ask({0x31}, 0xB1).data[121], uint8_t(sick::Units::Millimetres));
  // The variant: 180 degrees at 0.5.
  r = ask({0x3B, 180, 0, 50, 0}, 0xBB);
  EXPECT_EQ(r.data, (Bytes{1, 180, 0, 50, 0}));
  // Mean values over 5 scans: 0xB6 telegrams with the sample count.
  ASSERT_EQ(ask({0x20, 0x26, 5}, 0xA0).data, Bytes{0});
  EXPECT_EQ(scanner_->mode(), SickEmulator::Mode::MeanValues);
  Reply mean = wait_for(0xB6, 2000 * kMs);
  ASSERT_EQ(mean.code, 0xB6);
  EXPECT_EQ(mean.data[0], 5);
  EXPECT_EQ(le16(mean.data, 1) & 0x3FFF, 361);
  // At 9600 baud a 361-value telegram takes 0.75 s: replies queue behind it.
  EXPECT_EQ(ask({0x20, 0x26, 1}, 0xA0, 2000 * kMs).data, Bytes{2}) << "a mean of one scan is refused";
  EXPECT_EQ(ask({0x20, 0x25}, 0xA0, 2000 * kMs).data, Bytes{0});
  EXPECT_EQ(scanner_->mode(), SickEmulator::Mode::Monitor);
}

}  // namespace
}  // namespace troupe::emulators
