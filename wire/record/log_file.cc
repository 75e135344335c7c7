#include "wire/record/log_file.h"

#include <array>
#include <cerrno>
#include <cstring>

namespace troupe::record {
namespace {

constexpr std::array<uint32_t, 256> make_crc_table() {
  std::array<uint32_t, 256> table{};
  for (uint32_t i = 0; i < 256; ++i) {
    uint32_t c = i;
    for (int k = 0; k < 8; ++k) c = (c & 1u) ? 0xEDB88320u ^ (c >> 1) : c >> 1;
    table[i] = c;
  }
  return table;
}

constexpr std::array<uint32_t, 256> kCrcTable = make_crc_table();

void put_u16(uint8_t* p, uint16_t v) {
  p[0] = uint8_t(v);
  p[1] = uint8_t(v >> 8);
}
void put_u32(uint8_t* p, uint32_t v) {
  for (int i = 0; i < 4; ++i) p[i] = uint8_t(v >> (8 * i));
}
void put_u64(uint8_t* p, uint64_t v) {
  for (int i = 0; i < 8; ++i) p[i] = uint8_t(v >> (8 * i));
}
uint16_t get_u16(const uint8_t* p) {
  return uint16_t(p[0] | (p[1] << 8));
}
uint32_t get_u32(const uint8_t* p) {
  return wire::read_prefix(p);
}
uint64_t get_u64(const uint8_t* p) {
  return uint64_t(get_u32(p)) | (uint64_t(get_u32(p + 4)) << 32);
}

std::string errno_text() {
  return strerror(errno);
}

}  // namespace

uint32_t crc32(std::span<const uint8_t> bytes, uint32_t crc) {
  crc = ~crc;
  for (uint8_t b : bytes) crc = kCrcTable[(crc ^ b) & 0xFFu] ^ (crc >> 8);
  return ~crc;
}

// ---- Writing ----------------------------------------------------------------

LogWriter::~LogWriter() {
  std::string ignored;
  close(ignored);
}

bool LogWriter::open(const std::string& path, uint64_t start_unix_us, std::string& error) {
  path_ = path;
  file_ = fopen(path.c_str(), "wb");
  if (file_ == nullptr) {
    error = path + ": cannot create: " + errno_text();
    return false;
  }
  uint8_t header[kLogHeaderBytes] = {};
  memcpy(header, kLogMagic, sizeof kLogMagic);
  put_u16(header + 8, kLogVersion);
  put_u16(header + 10, kLogHeaderBytes);
  put_u32(header + 12, 0);
  put_u64(header + 16, start_unix_us);
  if (fwrite(header, 1, sizeof header, file_) != sizeof header) {
    error = path + ": cannot write: " + errno_text();
    return false;
  }
  bytes_ = sizeof header;
  return true;
}

bool LogWriter::write(uint64_t time_us, std::span<const uint8_t> frame, std::string& error) {
  uint8_t head[kRecordHeaderBytes];
  put_u32(head, uint32_t(frame.size()));
  put_u64(head + 8, time_us);
  put_u32(head + 4, crc32(frame, crc32({head + 8, 8})));
  if (fwrite(head, 1, sizeof head, file_) != sizeof head ||
      fwrite(frame.data(), 1, frame.size(), file_) != frame.size()) {
    error = path_ + ": cannot write: " + errno_text();
    return false;
  }
  bytes_ += sizeof head + frame.size();
  return true;
}

bool LogWriter::flush(std::string& error) {
  if (file_ != nullptr && fflush(file_) != 0) {
    error = path_ + ": cannot write: " + errno_text();
    return false;
  }
  return true;
}

bool LogWriter::close(std::string& error) {
  if (file_ == nullptr) return true;
  bool ok = fclose(file_) == 0;
  file_ = nullptr;
  if (!ok) error = path_ + ": cannot write: " + errno_text();
  return ok;
}

// ---- Reading ----------------------------------------------------------------

LogReader::LogReader(wire::Limits limits) : limits_(limits) {}

LogReader::~LogReader() {
  if (file_ != nullptr) fclose(file_);
}

bool LogReader::fail(uint64_t at, const std::string& what) {
  problem_ = path_ + ": byte " + std::to_string(at) + ": " + what;
  return false;
}

bool LogReader::open(const std::string& path, std::string& error) {
  path_ = path;
  file_ = fopen(path.c_str(), "rb");
  if (file_ == nullptr) {
    error = path + ": cannot open: " + errno_text();
    return false;
  }
  if (fseek(file_, 0, SEEK_END) != 0 || ftell(file_) < 0) {
    error = path + ": cannot read: " + errno_text();
    return false;
  }
  file_bytes_ = uint64_t(ftell(file_));
  fseek(file_, 0, SEEK_SET);
  uint8_t header[kLogHeaderBytes];
  size_t got = fread(header, 1, sizeof header, file_);
  if (got < sizeof kLogMagic || memcmp(header, kLogMagic, sizeof kLogMagic) != 0) {
    error = path + ": byte 0: not a troupe log (no \\x89TROUPE magic)";
    return false;
  }
  if (got < sizeof header) {
    error = path + ": byte " + std::to_string(got) + ": file header cut short (" + std::to_string(got) +
            " of " + std::to_string(kLogHeaderBytes) + " bytes)";
    return false;
  }
  header_.version = get_u16(header + 8);
  header_bytes_ = get_u16(header + 10);
  header_.start_unix_us = get_u64(header + 16);
  if (header_.version != kLogVersion) {
    error = path + ": byte 8: format version " + std::to_string(header_.version) +
            ", this program reads version " + std::to_string(kLogVersion);
    return false;
  }
  if (header_bytes_ < kLogHeaderBytes || header_bytes_ > file_bytes_) {
    error = path + ": byte 10: bad header size " + std::to_string(header_bytes_);
    return false;
  }
  return this->rewind();
}

bool LogReader::rewind() {
  problem_.clear();
  offset_ = header_bytes_;
  return fseek(file_, long(offset_), SEEK_SET) == 0;
}

bool LogReader::next(LogRecord& out) {
  if (file_ == nullptr || !problem_.empty() || offset_ == file_bytes_) return false;
  uint64_t left = file_bytes_ - offset_;
  uint8_t head[kRecordHeaderBytes];
  if (left < sizeof head || fread(head, 1, sizeof head, file_) != sizeof head) {
    return fail(offset_, "record header cut short (" + std::to_string(left) + " of " +
                             std::to_string(kRecordHeaderBytes) + " bytes): the file is truncated");
  }
  uint32_t size = get_u32(head);
  if (size > limits_.max_frame_bytes) {
    return fail(offset_, "record of " + std::to_string(size) + " bytes is over the frame limit of " +
                             std::to_string(limits_.max_frame_bytes) + ": the file is corrupt");
  }
  if (size > left - sizeof head) {
    return fail(offset_, "record of " + std::to_string(size) + " bytes but only " +
                             std::to_string(left - sizeof head) + " left: the file is truncated");
  }
  frame_.resize(size);
  if (fread(frame_.data(), 1, size, file_) != size) return fail(offset_, "read error: " + errno_text());
  if (crc32(frame_, crc32({head + 8, 8})) != get_u32(head + 4)) {
    return fail(offset_, "checksum mismatch: the record is corrupt");
  }
  wire::VerifyError why{};
  const wire::Message* msg = wire::verify_frame(frame_, limits_, &why);
  if (msg == nullptr) {
    return fail(offset_, "the frame fails verification (" + std::string(wire::verify_error_text(why)) + ")");
  }
  out.offset = offset_;
  out.time_us = get_u64(head + 8);
  out.frame = frame_;
  out.message = msg;
  offset_ += sizeof head + size;
  return true;
}

uint64_t PlayClock::next(uint64_t record_us, bool& jumped) {
  jumped = false;
  if (!started_) {
    started_ = true;
    play_us_ = 0;
  } else if (record_us < last_record_us_ || record_us - last_record_us_ > max_gap_us_) {
    jumped = true;
  } else {
    play_us_ += record_us - last_record_us_;
  }
  last_record_us_ = record_us;
  return play_us_;
}

bool summarize_log(const std::string& path, LogSummary& out, std::string& error, uint64_t max_gap_us) {
  out = LogSummary{};
  LogReader reader;
  if (!reader.open(path, error)) return false;
  PlayClock clock(max_gap_us);
  LogRecord r;
  while (reader.next(r)) {
    ++out.records;
    const wire::Header& h = *r.message->header();
    if (h.kind() == wire::Kind::Data) {
      if (out.data_records++ == 0) out.first_data_us = r.time_us;
      bool jumped = false;
      out.play_us = clock.next(r.time_us, jumped);
      if (jumped && out.jump_count++ < LogSummary::kMaxJumpsListed) {
        out.jumps.push_back({r.offset, out.last_data_us, r.time_us});
      }
      out.last_data_us = r.time_us;
    } else if (h.kind() == wire::Kind::DeviceList && r.message->body_as_DeviceList() != nullptr) {
      out.device_list.assign(r.frame.begin(), r.frame.end());
    } else if (const wire::Hello* hello = r.message->body_as_Hello(); hello && hello->name()) {
      out.node_name = hello->name()->str();
    }
  }
  out.valid_bytes = reader.offset();
  out.problem = reader.problem();
  return true;
}

}  // namespace troupe::record
