// The troupe log format: records read back as written; every truncation and
// every corrupted byte is found at the right offset, and everything before
// it still reads.
#include "wire/record/log_file.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdio>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "wire/writer.h"

namespace troupe::record {
namespace {

using Bytes = std::vector<uint8_t>;

Bytes data_frame(uint32_t seq, float x) {
  wire::MessageWriter w;
  auto& b = w.start();
  wire::Pose2d pose(x, 2 * x, 0.5f);
  auto body = wire::CreatePosition2dState(b, &pose, nullptr, false, nullptr, b.CreateString("fine"));
  auto f = w.finish(wire::make_header(wire::Address(0, uint16_t(wire::Interface::Position2d), 0),
                                      wire::Kind::Data, 1, seq, 1000000u + seq),
                    wire::Body::Position2dState, body.Union());
  return Bytes(f.begin(), f.end());
}

class LogFile : public ::testing::Test {
 protected:
  void SetUp() override {
    path_ = std::string(P_tmpdir) + "/troupe-log-test-XXXXXX";
    int fd = mkstemp(path_.data());
    ASSERT_GE(fd, 0);
    close(fd);
  }
  void TearDown() override { unlink(path_.c_str()); }

  // Writes `n` records; returns each record's byte offset.
  std::vector<uint64_t> write(int n) {
    LogWriter w;
    std::string error;
    EXPECT_TRUE(w.open(path_, 1700000000000000ull, error)) << error;
    std::vector<uint64_t> offsets;
    for (int i = 0; i < n; ++i) {
      offsets.push_back(w.bytes());
      Bytes f = data_frame(uint32_t(i + 1), float(i));
      frames_.push_back(f);
      EXPECT_TRUE(w.write(uint64_t(i) * 100000u, f, error)) << error;
    }
    EXPECT_TRUE(w.close(error)) << error;
    return offsets;
  }
  Bytes file() {
    std::ifstream in(path_, std::ios::binary);
    return Bytes(std::istreambuf_iterator<char>(in), {});
  }
  void put(const Bytes& bytes) {
    std::ofstream out(path_, std::ios::binary | std::ios::trunc);
    out.write(reinterpret_cast<const char*>(bytes.data()), std::streamsize(bytes.size()));
  }
  // Reads every good record; `problem` gets the reader's verdict.
  std::vector<Bytes> read_all(std::string& problem) {
    LogReader r;
    std::string error;
    EXPECT_TRUE(r.open(path_, error)) << error;
    std::vector<Bytes> out;
    LogRecord rec;
    while (r.next(rec)) out.emplace_back(rec.frame.begin(), rec.frame.end());
    problem = r.problem();
    return out;
  }

  std::string path_;
  std::vector<Bytes> frames_;
};

TEST(Crc32, MatchesTheStandardCheckValue) {
  const char* text = "123456789";
  EXPECT_EQ(crc32({reinterpret_cast<const uint8_t*>(text), 9}), 0xCBF43926u);
  // Continuing a CRC over two pieces gives the CRC of the whole.
  EXPECT_EQ(crc32({reinterpret_cast<const uint8_t*>(text) + 4, 5},
                  crc32({reinterpret_cast<const uint8_t*>(text), 4})),
            0xCBF43926u);
}

TEST_F(LogFile, RecordsReadBackWithTheirTimesAndOffsets) {
  std::vector<uint64_t> offsets = write(5);
  LogReader r;
  std::string error;
  ASSERT_TRUE(r.open(path_, error)) << error;
  EXPECT_EQ(r.header().version, kLogVersion);
  EXPECT_EQ(r.header().start_unix_us, 1700000000000000ull);
  LogRecord rec;
  for (int i = 0; i < 5; ++i) {
    ASSERT_TRUE(r.next(rec)) << r.problem();
    EXPECT_EQ(rec.offset, offsets[size_t(i)]);
    EXPECT_EQ(rec.time_us, uint64_t(i) * 100000u);
    EXPECT_EQ(Bytes(rec.frame.begin(), rec.frame.end()), frames_[size_t(i)]);
    EXPECT_EQ(rec.message->header()->seq(), uint32_t(i + 1));
  }
  EXPECT_FALSE(r.next(rec));
  EXPECT_EQ(r.problem(), "");
  ASSERT_TRUE(r.rewind());
  ASSERT_TRUE(r.next(rec));
  EXPECT_EQ(rec.offset, kLogHeaderBytes);
}

TEST_F(LogFile, EveryTruncationKeepsTheRecordsBeforeItAndNamesTheCut) {
  std::vector<uint64_t> offsets = write(4);
  Bytes whole = file();
  offsets.push_back(whole.size());
  for (size_t cut = kLogHeaderBytes; cut < whole.size(); ++cut) {
    put(Bytes(whole.begin(), whole.begin() + long(cut)));
    std::string problem;
    std::vector<Bytes> got = read_all(problem);
    size_t complete = 0;
    while (offsets[complete + 1] <= cut) ++complete;
    ASSERT_EQ(got.size(), complete) << "cut at " << cut;
    for (size_t i = 0; i < complete; ++i) EXPECT_EQ(got[i], frames_[i]);
    if (cut == offsets[complete]) {
      EXPECT_EQ(problem, "") << "a cut between records leaves a shorter, good file";
    } else {
      EXPECT_NE(problem.find("byte " + std::to_string(offsets[complete]) + ": "), std::string::npos)
          << problem;
      EXPECT_NE(problem.find("truncated"), std::string::npos) << problem;
    }
  }
}

TEST_F(LogFile, EveryFlippedByteIsFoundAtItsRecord) {
  std::vector<uint64_t> offsets = write(3);
  Bytes whole = file();
  offsets.push_back(whole.size());
  for (size_t at = kLogHeaderBytes; at < whole.size(); ++at) {
    Bytes bad = whole;
    bad[at] ^= 0x10;
    put(bad);
    std::string problem;
    std::vector<Bytes> got = read_all(problem);
    size_t record = 0;
    while (offsets[record + 1] <= at) ++record;
    ASSERT_EQ(got.size(), record) << "flip at " << at;
    EXPECT_NE(problem.find("byte " + std::to_string(offsets[record]) + ": "), std::string::npos)
        << "flip at " << at << ": " << problem;
  }
}

TEST_F(LogFile, ACheckedRecordWhoseFrameDoesNotVerifyIsRefused) {
  LogWriter w;
  std::string error;
  ASSERT_TRUE(w.open(path_, 0, error));
  Bytes good = data_frame(1, 1.0f);
  Bytes garbage = {8, 0, 0, 0, 0xFF, 0xFF, 0xFF, 0x7F, 1, 2, 3, 4};
  ASSERT_TRUE(w.write(0, good, error));
  uint64_t bad_at = w.bytes();
  ASSERT_TRUE(w.write(10, garbage, error));
  ASSERT_TRUE(w.close(error));
  std::string problem;
  EXPECT_EQ(read_all(problem).size(), 1u);
  EXPECT_NE(problem.find("byte " + std::to_string(bad_at) + ": the frame fails verification"),
            std::string::npos)
      << problem;
}

TEST_F(LogFile, BadHeadersAreRefusedWithTheirOffset) {
  write(1);
  Bytes whole = file();
  LogReader r;
  std::string error;
  Bytes magic = whole;
  magic[1] = 'X';
  put(magic);
  EXPECT_FALSE(r.open(path_, error));
  EXPECT_NE(error.find(": byte 0: not a troupe log"), std::string::npos) << error;
  Bytes version = whole;
  version[8] = 2;
  put(version);
  LogReader r2;
  EXPECT_FALSE(r2.open(path_, error));
  EXPECT_NE(error.find(": byte 8: format version 2, this program reads version 1"), std::string::npos)
      << error;
  put(Bytes(whole.begin(), whole.begin() + 12));
  LogReader r3;
  EXPECT_FALSE(r3.open(path_, error));
  EXPECT_NE(error.find(": byte 12: file header cut short (12 of 24 bytes)"), std::string::npos) << error;
  LogReader r4;
  EXPECT_FALSE(r4.open(path_ + "-missing", error));
  EXPECT_NE(error.find("cannot open: No such file or directory"), std::string::npos) << error;
}

TEST_F(LogFile, ALengthOverTheLimitIsCorruptNotAnAllocation) {
  std::vector<uint64_t> offsets = write(2);
  Bytes bad = file();
  bad[offsets[1] + 3] = 0x7F;  // the second record claims about 2 GB
  put(bad);
  std::string problem;
  EXPECT_EQ(read_all(problem).size(), 1u);
  EXPECT_NE(problem.find("byte " + std::to_string(offsets[1]) + ": record of"), std::string::npos) << problem;
  EXPECT_NE(problem.find("over the frame limit"), std::string::npos) << problem;
}

TEST_F(LogFile, SummaryCountsTheValidPart) {
  std::vector<uint64_t> offsets = write(6);
  Bytes whole = file();
  put(Bytes(whole.begin(), whole.begin() + long(offsets[4] + 5)));
  LogSummary s;
  std::string error;
  ASSERT_TRUE(summarize_log(path_, s, error)) << error;
  EXPECT_EQ(s.records, 4u);
  EXPECT_EQ(s.data_records, 4u);
  EXPECT_EQ(s.first_data_us, 0u);
  EXPECT_EQ(s.last_data_us, 300000u);
  EXPECT_EQ(s.valid_bytes, offsets[4]);
  EXPECT_NE(s.problem.find("byte " + std::to_string(offsets[4])), std::string::npos) << s.problem;
}

TEST(PlayClock, KeepsPausesAndDropsJumps) {
  PlayClock clock(60'000'000);
  bool jumped = true;
  EXPECT_EQ(clock.next(5'000'000, jumped), 0u);  // the first record plays at once
  EXPECT_FALSE(jumped);
  EXPECT_EQ(clock.next(5'100'000, jumped), 100'000u);
  EXPECT_FALSE(jumped);
  EXPECT_EQ(clock.next(65'100'000, jumped), 60'100'000u);  // a pause of exactly the limit is kept
  EXPECT_FALSE(jumped);
  EXPECT_EQ(clock.next(uint64_t(1) << 40, jumped), 60'100'000u);  // forward past the limit: not kept
  EXPECT_TRUE(jumped);
  EXPECT_EQ(clock.next((uint64_t(1) << 40) + 10'000, jumped), 60'110'000u);  // the pace goes on from there
  EXPECT_FALSE(jumped);
  EXPECT_EQ(clock.next(1'000, jumped), 60'110'000u);  // back: not kept either
  EXPECT_TRUE(jumped);
  EXPECT_EQ(clock.next(UINT64_MAX, jumped), 60'110'000u);
  EXPECT_TRUE(jumped);
  clock.restart();
  EXPECT_EQ(clock.next(7, jumped), 0u);
  EXPECT_FALSE(jumped);
}

TEST_F(LogFile, SummaryReportsTimeJumpsWithTheirOffsets) {
  LogWriter w;
  std::string error;
  ASSERT_TRUE(w.open(path_, 1700000000000000ull, error)) << error;
  const uint64_t far = uint64_t(1) << 40;
  const std::vector<uint64_t> times = {0, 100000, far, far + 100000, 300000, 400000};
  std::vector<uint64_t> offsets;
  for (size_t i = 0; i < times.size(); ++i) {
    offsets.push_back(w.bytes());
    ASSERT_TRUE(w.write(times[i], data_frame(uint32_t(i + 1), float(i)), error)) << error;
  }
  ASSERT_TRUE(w.close(error)) << error;
  LogSummary s;
  ASSERT_TRUE(summarize_log(path_, s, error)) << error;
  EXPECT_EQ(s.problem, "");  // nothing is corrupt: the times are just not kept
  ASSERT_EQ(s.jump_count, 2u);
  ASSERT_EQ(s.jumps.size(), 2u);
  EXPECT_EQ(s.jumps[0].offset, offsets[2]);
  EXPECT_EQ(s.jumps[0].from_us, 100000u);
  EXPECT_EQ(s.jumps[0].to_us, far);
  EXPECT_EQ(s.jumps[1].offset, offsets[4]);
  EXPECT_EQ(s.jumps[1].to_us, 300000u);
  // Played: 0.1 s, the jump, 0.1 s, the jump back, 0.1 s.
  EXPECT_EQ(s.play_us, 300000u);
  // With a limit above the gap, the forward jump is a pause to keep.
  ASSERT_TRUE(summarize_log(path_, s, error, far)) << error;
  EXPECT_EQ(s.jump_count, 1u);
}

}  // namespace
}  // namespace troupe::record
