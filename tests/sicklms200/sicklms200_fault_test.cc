// Faults on the line and in the scanner, each with the sicklms200 driver in
// a real node beside a kinematic driver: only scans the scanner really sent
// are published (the fixture checks every one), the driver resyncs or
// configures the scanner again, and the kinematic base is served all along.
#include "tests/sicklms200/sick_fixture.h"

namespace troupe::testing {
namespace {

class SickFaults : public SickNode {
 protected:
  // Runs for `seconds` with whatever faults are set; both devices must go
  // on publishing, and nothing but the scanner's own scans.
  void run_through_faults(double seconds) {
    uint32_t other = client_.count(kKinematic), scans = client_.count(kLaser);
    loop_.run_for(seconds);
    EXPECT_GT(client_.count(kKinematic), other + 5) << "the kinematic base stopped being served";
    EXPECT_GT(client_.count(kLaser), scans + 3) << "the scanner stopped publishing";
    EXPECT_EQ(mismatched_, 0u) << "a corrupted scan was published";
  }
  // After the faults: the stream is whole again.
  void recovers() {
    scanner_->faults().rates = {};
    scanner_->inbound_faults().rates = {};
    uint32_t n = client_.count(kLaser);
    EXPECT_TRUE(loop_.run_until([&] { return client_.count(kLaser) > n + 5; }, 15));
    EXPECT_EQ(mismatched_, 0u);
  }
};

TEST_F(SickFaults, FlippedBits) {
  start();
  ASSERT_TRUE(streaming());
  scanner_->faults().rates.bit_flip = 0.001;  // about one scan in three hit
  run_through_faults(3.0);
  EXPECT_GE(scanner_->faults().counts().flipped, 3u);
  recovers();
}

TEST_F(SickFaults, DroppedBytes) {
  start();
  ASSERT_TRUE(streaming());
  scanner_->faults().rates.byte_drop = 0.001;
  run_through_faults(3.0);
  EXPECT_GE(scanner_->faults().counts().dropped, 3u);
  recovers();
}

TEST_F(SickFaults, TornTelegrams) {
  start();
  ASSERT_TRUE(streaming());
  scanner_->faults().rates.tear = 0.3;
  run_through_faults(3.0);
  EXPECT_GT(scanner_->faults().counts().torn, 3u);
  recovers();
}

TEST_F(SickFaults, BurstsOfGarbage) {
  start();
  ASSERT_TRUE(streaming());
  uint32_t other = client_.count(kKinematic);
  for (int i = 0; i < 5; ++i) {
    scanner_->inject_noise(1000);
    loop_.run_for(0.4);
  }
  EXPECT_GT(client_.count(kKinematic), other + 5);
  recovers();
}

TEST_F(SickFaults, RequestsLostWhileConfiguringAreSentAgain) {
  start({}, R"("reply_timeout_ms": 300, "reply_attempts": 3)");
  // Nothing reaches the scanner for a while, then a noisy line.
  scanner_->inbound_faults().rates.byte_drop = 1.0;
  loop_.run_for(0.5);
  scanner_->inbound_faults().rates.byte_drop = 0.01;
  scanner_->inbound_faults().rates.bit_flip = 0.01;
  EXPECT_TRUE(streaming());
  EXPECT_GT(scanner_->inbound_faults().counts().dropped, 0u);
  EXPECT_EQ(scanner_->units(), drivers::sicklms200::Units::Millimetres);
  EXPECT_EQ(mismatched_, 0u);
}

TEST_F(SickFaults, ThePortVanishesAndReturns) {
  start();
  ASSERT_TRUE(streaming());
  ::testing::internal::CaptureStderr();
  scanner_->vanish();
  uint32_t other = client_.count(kKinematic);
  loop_.run_for(1.5);
  EXPECT_GT(client_.count(kKinematic), other + 10) << "the kinematic base stopped being served";
  std::string error;
  ASSERT_TRUE(scanner_->reappear(error)) << error;
  uint32_t scans = client_.count(kLaser);
  ASSERT_TRUE(loop_.run_until([&] { return client_.count(kLaser) > scans + 3; }, 15)) << "no reconnect";
  std::string log = ::testing::internal::GetCapturedStderr();
  EXPECT_NE(log.find(dir_.file("laser") + ": the device hung up"), std::string::npos) << log;
  EXPECT_EQ(mismatched_, 0u);
}

TEST_F(SickFaults, TheScannerRestartsAtItsPowerUpSpeed) {
  start({}, R"("reply_timeout_ms": 300)");
  ASSERT_TRUE(streaming());
  scanner_->power_cycle();  // back to 9600, silent
  EXPECT_EQ(scanner_->baud(), 9600u);
  uint32_t scans = client_.count(kLaser);
  ASSERT_TRUE(loop_.run_until([&] { return client_.count(kLaser) > scans + 3; }, 20));
  EXPECT_EQ(scanner_->baud(), 38400u);
  EXPECT_EQ(mismatched_, 0u);
}

TEST_F(SickFaults, TheScannerFallsSilent) {
  start({}, R"("reply_timeout_ms": 300)");
  ASSERT_TRUE(streaming());
  uint32_t other = client_.count(kKinematic);
  scanner_->set_mute(true);
  loop_.run_for(2.5);  // past the scan timeout: the driver starts over
  scanner_->set_mute(false);
  uint32_t scans = client_.count(kLaser);
  ASSERT_TRUE(loop_.run_until([&] { return client_.count(kLaser) > scans + 3; }, 20));
  EXPECT_GT(client_.count(kKinematic), other + 10);
}

}  // namespace
}  // namespace troupe::testing
