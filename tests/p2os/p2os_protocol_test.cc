// The P2OS codec against the worked packets of protocols.md, and the packet
// scanner against the ways a serial line mangles a byte stream.
#include "drivers/p2os/p2os_protocol.h"

#include <gtest/gtest.h>

#include <string>
#include <vector>

namespace troupe::drivers::p2os {
namespace {

using Bytes = std::vector<uint8_t>;

Bytes bytes(const Packet& p) {
  return Bytes(p.view().begin(), p.view().end());
}

TEST(P2osPacket, MatchesTheWorkedPackets) {
  EXPECT_EQ(bytes(command(Command::Sync0)), (Bytes{0xfa, 0xfb, 0x03, 0x00, 0x00, 0x00}));
  EXPECT_EQ(bytes(command(Command::Sync1)), (Bytes{0xfa, 0xfb, 0x03, 0x01, 0x00, 0x01}));
  EXPECT_EQ(bytes(command_int(Command::Enable, 1)),
            (Bytes{0xfa, 0xfb, 0x06, 0x04, 0x3b, 0x01, 0x00, 0x05, 0x3b}));
  EXPECT_EQ(bytes(command_int(Command::Vel, 300)),
            (Bytes{0xfa, 0xfb, 0x06, 0x0b, 0x3b, 0x2c, 0x01, 0x37, 0x3c}));
  EXPECT_EQ(bytes(command_int(Command::RVel, -20)),
            (Bytes{0xfa, 0xfb, 0x06, 0x15, 0x1b, 0x14, 0x00, 0x29, 0x1b}));
  EXPECT_EQ(bytes(vel2(10, 10)), (Bytes{0xfa, 0xfb, 0x06, 0x20, 0x3b, 0x0a, 0x0a, 0x2a, 0x45}));
}

TEST(P2osPacket, ChecksumXorsAnOddLastByte) {
  // Pairs 0x0102 + 0x0304 = 0x0406, then 0x05 XORed into the low byte.
  const uint8_t payload[] = {1, 2, 3, 4, 5};
  EXPECT_EQ(checksum(payload), 0x0403);
  // The sum wraps at 16 bits.
  const uint8_t big[] = {0xff, 0xff, 0x00, 0x02};
  EXPECT_EQ(checksum(big), 0x0001);
}

TEST(P2osPacket, ArgumentsClampAndReadBack) {
  Packet p = command_int(Command::Vel, 100000);
  CommandArg arg = parse_arg(p.payload());
  ASSERT_TRUE(arg.present);
  EXPECT_EQ(arg.value, 32767);
  arg = parse_arg(command_int(Command::RVel, -45).payload());
  EXPECT_EQ(arg.type, ArgType::NegativeInt);
  EXPECT_EQ(arg.value, -45);
  // VEL2 wheel speeds are signed bytes, right low, left high, clamped.
  arg = parse_arg(vel2(-3, 200).payload());
  EXPECT_EQ(int8_t(arg.lo), -3);
  EXPECT_EQ(int8_t(arg.hi), 126);
  EXPECT_FALSE(parse_arg(command(Command::Pulse).payload()).present);
}

TEST(P2osPacket, RefusesPayloadsThatDoNotFit) {
  Packet p;
  EXPECT_FALSE(make_packet({}, p));
  Bytes big(kMaxPayloadBytes + 1, 7);
  EXPECT_FALSE(make_packet(big, p));
  Bytes fits(kMaxPayloadBytes, 7);
  EXPECT_TRUE(make_packet(fits, p));
  EXPECT_EQ(p.size, kMaxPacketBytes);
}

// Feeds `stream` to a scanner in chunks of `chunk` bytes; returns payloads.
std::vector<Bytes> scan_all(PacketScanner& s, const Bytes& stream, size_t chunk) {
  std::vector<Bytes> out;
  for (size_t i = 0; i < stream.size(); i += chunk) {
    std::span<const uint8_t> in(stream.data() + i, std::min(chunk, stream.size() - i));
    scan_packets(s, in, [&](std::span<const uint8_t> p) { out.emplace_back(p.begin(), p.end()); });
  }
  return out;
}

Bytes join(std::initializer_list<Bytes> parts) {
  Bytes all;
  for (const Bytes& p : parts) all.insert(all.end(), p.begin(), p.end());
  return all;
}

TEST(P2osScanner, FindsPacketsWhateverTheChunking) {
  Bytes stream =
      join({bytes(command(Command::Sync0)), bytes(command_int(Command::Vel, 300)), bytes(vel2(1, 2))});
  for (size_t chunk : {size_t(1), size_t(2), size_t(5), size_t(7), stream.size()}) {
    PacketScanner s;
    auto found = scan_all(s, stream, chunk);
    ASSERT_EQ(found.size(), 3u) << "chunk " << chunk;
    EXPECT_EQ(found[0], (Bytes{0}));
    EXPECT_EQ(found[1], (Bytes{0x0b, 0x3b, 0x2c, 0x01}));
    EXPECT_EQ(found[2][0], 32);
  }
}

TEST(P2osScanner, SkipsNoiseAndAModemWakeUp) {
  Bytes wake = {'W', 'M', 'S', '2', '\r'};
  Bytes noise = {0x00, 0xfa, 0x12, 0xfb, 0xfa, 0xfa};  // stray header bytes included
  Bytes stream = join({wake, noise, bytes(command(Command::Sync1)), noise});
  PacketScanner s;
  auto found = scan_all(s, stream, 3);
  ASSERT_EQ(found.size(), 1u);
  EXPECT_EQ(found[0], (Bytes{1}));
  EXPECT_GT(s.skipped_bytes(), 0u);
}

TEST(P2osScanner, DropsABadChecksumAndFindsThePacketInsideIt) {
  Bytes good = bytes(command_int(Command::Vel, 300));
  Bytes bad = good;
  bad[6] ^= 0x10;  // flipped bit in the argument
  PacketScanner s;
  auto found = scan_all(s, join({bad, good}), 4);
  ASSERT_EQ(found.size(), 1u);
  EXPECT_EQ(found[0], Bytes(good.begin() + 3, good.end() - 2));
  EXPECT_EQ(s.bad_checksums(), 1u);

  // A torn packet whose count swallows the start of the next one: the
  // checksum fails, and the hunt resumes inside it.
  Bytes torn(good.begin(), good.begin() + 4);
  PacketScanner t;
  found = scan_all(t, join({torn, good, good}), 1);
  EXPECT_EQ(found.size(), 2u);
}

TEST(P2osScanner, RejectsImpossibleCounts) {
  Bytes stream = {0xfa, 0xfb, 0x02, 0xfa, 0xfb, 0xff};
  Bytes all = join({stream, bytes(command(Command::Sync0))});
  PacketScanner s;
  auto found = scan_all(s, all, 2);
  ASSERT_EQ(found.size(), 1u);
  EXPECT_EQ(found[0], (Bytes{0}));
}

TEST(P2osScanner, ExpiringAStalledPacketFreesThoseBehindIt) {
  // A corrupted count (0xc8: 200 bytes) makes the first packet look long;
  // two good packets sit behind it, and nothing more comes.
  Bytes bogus = {0xfa, 0xfb, 0xc5, 0x04};
  Bytes stream = join({bogus, bytes(command(Command::Pulse)), bytes(command_int(Command::Vel, 300))});
  PacketScanner s;
  EXPECT_TRUE(scan_all(s, stream, 64).empty());
  EXPECT_TRUE(s.partial());
  std::vector<Bytes> found;
  expire_packets(s, [&](std::span<const uint8_t> p) { found.emplace_back(p.begin(), p.end()); });
  ASSERT_EQ(found.size(), 2u);
  EXPECT_EQ(found[0], (Bytes{0}));
  EXPECT_EQ(found[1], (Bytes{0x0b, 0x3b, 0x2c, 0x01}));
  EXPECT_FALSE(s.partial());
}

TEST(P2osSip, ParsesFieldsAtTheirOffsets) {
  // A SIP written out by hand, byte by byte, from the table in protocols.md.
  Bytes p = {0x33,  // moving
             0x10,
             0x80,  // x: bit 15 is not part of the counter
             0xff,
             0x7f,  // y: 32767
             0x00,
             0x04,  // heading 1024
             0x2c,
             0x01,  // left 300
             0xd4,
             0xfe,                // right -300
             125,                 // 12.5 V
             0x01 | (0x05 << 1),  // left stall, rear bumpers 0 and 2
             0x00 | (0x40 << 1),  // front bumper 6
             0x34,
             0x12,
             0x01,
             0x00,  // control, flags
             0x00,  // compass: none
             2,     // two sonar readings
             3,
             0xe8,
             0x03,  // sonar 3: 1000
             15,
             0x88,
             0x13,  // sonar 15: 5000
             0x01,
             0x02,
             9,
             8,
             7};  // timer, analog, digital in, digital out
  Sip sip;
  const char* why = nullptr;
  ASSERT_TRUE(parse_sip(p, sip, &why)) << why;
  EXPECT_EQ(sip.type, 0x33);
  EXPECT_EQ(sip.x, 0x0010);
  EXPECT_EQ(sip.y, 32767);
  EXPECT_EQ(sip.heading, 1024);
  EXPECT_EQ(sip.left_vel, 300);
  EXPECT_EQ(sip.right_vel, -300);
  EXPECT_EQ(sip.battery, 125);
  EXPECT_TRUE(sip.left_stall);
  EXPECT_FALSE(sip.right_stall);
  EXPECT_EQ(sip.rear_bumpers, 0x05);
  EXPECT_EQ(sip.front_bumpers, 0x40);
  EXPECT_EQ(sip.control, 0x1234);
  EXPECT_EQ(sip.flags, 1);
  ASSERT_EQ(sip.sonar_count, 2);
  EXPECT_EQ(sip.sonar[0].index, 3);
  EXPECT_EQ(sip.sonar[0].range, 1000);
  EXPECT_EQ(sip.sonar[1].index, 15);
  EXPECT_EQ(sip.sonar[1].range, 5000);
  ASSERT_TRUE(sip.has_io);
  EXPECT_EQ(sip.timer, 0x0201);
  EXPECT_EQ(sip.digital_out, 7);

  // What write_sip makes of it is the same bytes (bit 15 of x aside).
  uint8_t out[kMaxPayloadBytes];
  ASSERT_EQ(write_sip(sip, out), p.size());
  p[2] &= 0x7f;
  EXPECT_EQ(Bytes(out, out + p.size()), p);
}

TEST(P2osSip, RefusesShortOrOverrunningSips) {
  Sip sip;
  const char* why = nullptr;
  Bytes short_sip(10, 0);
  short_sip[0] = 0x32;
  EXPECT_FALSE(parse_sip(short_sip, sip, &why));
  EXPECT_STREQ(why, "SIP shorter than its fixed fields");
  Bytes overrun(19, 0);
  overrun[0] = 0x32;
  overrun.push_back(4);  // four readings announced, none carried
  EXPECT_FALSE(parse_sip(overrun, sip, &why));
  EXPECT_STREQ(why, "SIP names more sonar readings than it carries");
  Bytes config(30, 0);
  config[0] = 0x20;  // a config packet, not a SIP
  EXPECT_FALSE(parse_sip(config, sip, &why));
}

TEST(P2osSync2, ReadsNameClassAndSubclass) {
  Bytes p = {2};
  for (const char* s : {"Pioneer-7", "Pioneer", "p3dx-sh"}) p.insert(p.end(), s, s + strlen(s) + 1);
  RobotIdentity id;
  ASSERT_TRUE(parse_sync2(p, id));
  EXPECT_STREQ(id.name, "Pioneer-7");
  EXPECT_STREQ(id.robot_class, "Pioneer");
  EXPECT_STREQ(id.subclass, "p3dx-sh");
  EXPECT_FALSE(parse_sync2(Bytes{2, 'a', 0}, id));
  EXPECT_FALSE(parse_sync2(Bytes{1}, id));
}

}  // namespace
}  // namespace troupe::drivers::p2os
