// The SICK telegram codec against the check values of protocols.md, and the
// telegram scanner against the ways a serial line mangles a byte stream.
#include "drivers/sicklms200/sick_protocol.h"

#include <gtest/gtest.h>

#include <vector>

namespace troupe::drivers::sicklms200 {
namespace {

using Bytes = std::vector<uint8_t>;

Bytes bytes(const Telegram& t) {
  return Bytes(t.view().begin(), t.view().end());
}

TEST(SickCrc, MatchesTheCheckValues) {
  const uint8_t start[] = {0x02, 0x00, 0x02, 0x00, 0x20, 0x24};
  const uint8_t stop[] = {0x02, 0x00, 0x02, 0x00, 0x20, 0x25};
  EXPECT_EQ(crc16(start), 0x0834);
  EXPECT_EQ(crc16(stop), 0x0835);
}

TEST(SickTelegram, RequestsAreFramedWithTheCrcLowByteFirst) {
  EXPECT_EQ(bytes(mode_change(Mode::Continuous)), (Bytes{0x02, 0x00, 0x02, 0x00, 0x20, 0x24, 0x34, 0x08}));
  EXPECT_EQ(bytes(mode_change(Mode::StopContinuous)),
            (Bytes{0x02, 0x00, 0x02, 0x00, 0x20, 0x25, 0x35, 0x08}));
  Bytes config = bytes(enter_config());
  ASSERT_EQ(config.size(), 16u);
  EXPECT_EQ(Bytes(config.begin(), config.begin() + 6), (Bytes{0x02, 0x00, 0x0a, 0x00, 0x20, 0x00}));
  EXPECT_EQ(std::string(config.begin() + 6, config.begin() + 14), "SICK_LMS");
  Bytes v = bytes(variant(180, 50));
  EXPECT_EQ(Bytes(v.begin(), v.begin() + 9), (Bytes{0x02, 0x00, 0x05, 0x00, 0x3b, 0xb4, 0x00, 0x32, 0x00}));
  Telegram t;
  ASSERT_TRUE(baud_change(38400, t));
  EXPECT_EQ(t.bytes[5], 0x40);
  ASSERT_TRUE(baud_change(9600, t));
  EXPECT_EQ(t.bytes[5], 0x42);
  ASSERT_TRUE(baud_change(500000, t));
  EXPECT_EQ(t.bytes[5], 0x48);
  ASSERT_TRUE(baud_change(19200, t));
  EXPECT_EQ(t.bytes[5], 0x41);
  EXPECT_FALSE(baud_change(57600, t));
}

TEST(SickTelegram, RepliesCountCodeDataAndStatus) {
  Telegram t;
  const uint8_t data[] = {0x00};
  ASSERT_TRUE(make_reply(0xA0, data, 0x10, t));
  // 02 80, length 3 (code, one data byte, status), then the CRC.
  EXPECT_EQ(Bytes(t.bytes.begin(), t.bytes.begin() + 7), (Bytes{0x02, 0x80, 0x03, 0x00, 0xa0, 0x00, 0x10}));
  EXPECT_EQ(t.size, 9u);
  Reply r;
  ASSERT_TRUE(split_reply({t.bytes.data() + 4, 3}, r));
  EXPECT_EQ(r.code, 0xA0);
  ASSERT_EQ(r.data.size(), 1u);
  EXPECT_EQ(r.status, 0x10);
}

std::vector<Bytes> scan_all(TelegramScanner& s, const Bytes& stream, size_t chunk) {
  std::vector<Bytes> out;
  for (size_t i = 0; i < stream.size(); i += chunk) {
    std::span<const uint8_t> in(stream.data() + i, std::min(chunk, stream.size() - i));
    scan_telegrams(s, in, [&](std::span<const uint8_t> b) { out.emplace_back(b.begin(), b.end()); });
  }
  return out;
}

Bytes reply_bytes(uint8_t code, Bytes data) {
  Telegram t;
  make_reply(code, data, 0, t);
  return bytes(t);
}

Bytes join(std::initializer_list<Bytes> parts) {
  Bytes all;
  for (const Bytes& p : parts) all.insert(all.end(), p.begin(), p.end());
  return all;
}

TEST(SickScanner, FindsRepliesAmongAcksNoiseAndRequests) {
  Bytes stream = join({Bytes{kAck}, reply_bytes(0xA0, {0}), Bytes{0x02, 0x02, 0x77, kNack},
                       bytes(mode_change(Mode::Continuous)),  // a request: not for a driver
                       reply_bytes(0xBB, {1, 0xb4, 0, 100, 0})});
  for (size_t chunk : {size_t(1), size_t(3), size_t(8), stream.size()}) {
    TelegramScanner s(kReplyAddress);
    auto found = scan_all(s, stream, chunk);
    ASSERT_EQ(found.size(), 2u) << "chunk " << chunk;
    EXPECT_EQ(found[0], (Bytes{0xA0, 0, 0}));
    EXPECT_EQ(found[1][0], 0xBB);
    EXPECT_EQ(s.nacks(), 1u);
  }
}

TEST(SickScanner, DropsABadCrcAndFindsTheTelegramInsideIt) {
  Bytes good = reply_bytes(0xA0, {0});
  Bytes bad = good;
  bad[5] ^= 0x01;
  TelegramScanner s(kReplyAddress);
  auto found = scan_all(s, join({bad, good}), 5);
  ASSERT_EQ(found.size(), 1u);
  EXPECT_EQ(s.bad_crcs(), 1u);
}

TEST(SickScanner, ExpiringAStalledTelegramFreesThoseBehindIt) {
  // A corrupted length (0x0300) makes the first telegram look long.
  Bytes bogus = {0x02, 0x80, 0x00, 0x03, 0xa0};
  Bytes stream = join({bogus, reply_bytes(0xA0, {0}), reply_bytes(0xF7, {1})});
  TelegramScanner s(kReplyAddress);
  EXPECT_TRUE(scan_all(s, stream, 64).empty());
  std::vector<Bytes> found;
  expire_telegrams(s, [&](std::span<const uint8_t> b) { found.emplace_back(b.begin(), b.end()); });
  ASSERT_EQ(found.size(), 2u);
  EXPECT_EQ(found[0][0], 0xA0);
  EXPECT_EQ(found[1][0], 0xF7);
  EXPECT_FALSE(s.partial());
}

TEST(SickScan, ReadsCountUnitsAndMasksFlags) {
  // Three values in mm: units 01 in the count's top bits; flag bits 13-15
  // set on the second value.
  Bytes data = {0x03, 0x40, 0xe8, 0x03, 0xff, 0xff, 0x10, 0x00};
  Scan scan;
  const char* why = nullptr;
  ASSERT_TRUE(parse_scan(data, scan, &why)) << why;
  EXPECT_EQ(scan.count, 3);
  EXPECT_EQ(scan.units, Units::Millimetres);
  EXPECT_EQ(scan.ranges[0], 1000);
  EXPECT_EQ(scan.ranges[1], kNoReturn);
  EXPECT_EQ(scan.ranges[2], 16);

  const uint16_t ranges[] = {1000, 9000, 16};
  uint8_t out[16];
  ASSERT_EQ(write_scan(ranges, Units::Millimetres, out), 8u);
  data[5] = 0x1f;  // written values are clamped, never flagged
  EXPECT_EQ(Bytes(out, out + 8), data);
}

TEST(SickScan, RefusesImpossibleCounts) {
  Scan scan;
  const char* why = nullptr;
  Bytes overrun = {0x05, 0x40, 0x01, 0x00};
  EXPECT_FALSE(parse_scan(overrun, scan, &why));
  EXPECT_STREQ(why, "scan count overruns the telegram");
  Bytes too_many = {0xff, 0x3f};
  EXPECT_FALSE(parse_scan(too_many, scan, &why));
  EXPECT_STREQ(why, "scan count over 401 values");
}

}  // namespace
}  // namespace troupe::drivers::sicklms200
