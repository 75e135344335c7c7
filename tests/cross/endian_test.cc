// The wire format across byte orders: a big-endian powerpc build and the
// little-endian host write the same frames, byte for byte, and each decodes
// what the other wrote.
#include <gtest/gtest.h>

#include <cstdio>

#include "tests/cross/frame_samples.h"
#include "tests/cross/qemu_node.h"
#include "wire/frame.h"

namespace troupe::cross {
namespace {

class Endianness : public ::testing::Test {
 protected:
  void SetUp() override {
    std::string why;
    if (!load_cross_build("ppc-node-powerpc", build_, why)) {
      GTEST_SKIP() << why;
    }
    tool_ = build_.path("bin/troupe-frame-tool");
    dir_ = make_temp_dir("endian");
    ASSERT_FALSE(dir_.empty());
  }
  void TearDown() override {
    std::string ignored;
    if (!dir_.empty()) run("rm -rf " + quote(dir_), ignored);
  }
  // Runs the powerpc frame tool; its exit status, output in `out`.
  int tool(const std::string& verb, const std::string& file, std::string& out) {
    return run(qemu_command(build_, tool_, {verb, file}) + " 2>&1", out);
  }
  void write_file(const std::string& path, const std::vector<uint8_t>& bytes) {
    FILE* f = fopen(path.c_str(), "wb");
    ASSERT_NE(f, nullptr);
    ASSERT_EQ(fwrite(bytes.data(), 1, bytes.size(), f), bytes.size());
    fclose(f);
  }

  CrossBuild build_;
  std::string tool_;
  std::string dir_;
};

TEST_F(Endianness, PowerpcWritesTheHostsBytes) {
  std::string file = dir_ + "/from-powerpc.bin";
  std::string out;
  ASSERT_EQ(tool("write", file, out), 0) << out;
  std::string text = read_text(file);
  std::vector<uint8_t> from_powerpc(text.begin(), text.end());
  std::vector<uint8_t> from_host;
  write_samples(from_host);
  ASSERT_FALSE(from_host.empty());
  EXPECT_EQ(from_powerpc, from_host);
  EXPECT_EQ(check_samples(from_powerpc), "");
}

TEST_F(Endianness, PowerpcDecodesWhatTheHostWrote) {
  std::vector<uint8_t> bytes;
  write_samples(bytes);
  std::string file = dir_ + "/from-host.bin";
  write_file(file, bytes);
  std::string out;
  EXPECT_EQ(tool("check", file, out), 0) << out;
  EXPECT_NE(out.find("ok: " + std::to_string(sample_count()) + " frames"), std::string::npos) << out;
}

TEST_F(Endianness, PowerpcRefusesACorruptFrameAndSaysWhere) {
  std::vector<uint8_t> bytes;
  write_samples(bytes);
  // Point the second frame's root table far outside the buffer.
  size_t second = wire::kPrefixBytes + wire::read_prefix(bytes.data());
  bytes[second + 4 + 3] = 0x7F;
  std::string file = dir_ + "/corrupt.bin";
  write_file(file, bytes);
  std::string out;
  EXPECT_EQ(tool("check", file, out), 1) << out;
  std::string where = "frame 1 (byte " + std::to_string(second) + "): refused";
  EXPECT_NE(out.find(where), std::string::npos) << out;
  // The host says the same of the same bytes.
  EXPECT_NE(check_samples(bytes).find(where), std::string::npos);
}

TEST_F(Endianness, PowerpcNoticesAChangedValue) {
  std::vector<uint8_t> bytes;
  write_samples(bytes);
  // Find the Error sample's code field (u16, VersionMismatch = 8), the last
  // frame's, and change its low byte: a valid frame with a wrong value.
  size_t frame = 0;
  for (int i = 0; i + 1 < sample_count(); ++i)
    frame += wire::kPrefixBytes + wire::read_prefix(bytes.data() + frame);
  const wire::Message* msg = wire::trusted_message({bytes.data() + frame, bytes.size() - frame});
  ASSERT_NE(msg->body_as_Error(), nullptr);
  auto* table = reinterpret_cast<const flatbuffers::Table*>(msg->body_as_Error());
  size_t at = size_t(table->GetAddressOf(wire::Error::VT_CODE) - bytes.data());
  ASSERT_EQ(bytes[at], 8);
  bytes[at] = 7;
  std::string file = dir_ + "/changed.bin";
  write_file(file, bytes);
  std::string out;
  EXPECT_EQ(tool("check", file, out), 1) << out;
  EXPECT_NE(out.find("code is 0x7, expected 0x8"), std::string::npos) << out;
}

}  // namespace
}  // namespace troupe::cross
