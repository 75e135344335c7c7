// What the serial drivers' codecs cost per byte: finding P2OS packets and
// parsing SIPs, finding SICK telegrams (CRC) and parsing scans, in 512-byte
// reads as the serial link hands them over, clean and with one bit in a
// thousand bytes flipped. The baseline is a copy of the same bytes in the same run;
// times are medians over repeats. The last column is the share of one core
// the codec needs at the line's full speed.
//
//   build/host-release/tests/bench/serial/bench_serial_codecs [REPEATS]
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <random>
#include <vector>

#include "drivers/p2os/p2os_protocol.h"
#include "drivers/sicklms200/sick_protocol.h"

using namespace troupe::drivers;

namespace {

using Bytes = std::vector<uint8_t>;
constexpr size_t kChunk = 512;

double seconds_now() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

// A SIP stream: 16 sonar readings a packet, counters moving.
Bytes sip_stream(size_t packets) {
  Bytes out;
  p2os::Sip sip;
  sip.type = 0x33;
  sip.battery = 125;
  sip.sonar_count = 16;
  for (size_t i = 0; i < packets; ++i) {
    sip.x = uint16_t(i * 7);
    sip.heading = int16_t(i % 4096);
    for (uint8_t k = 0; k < 16; ++k) sip.sonar[k] = {k, uint16_t(500 + i % 3000)};
    uint8_t payload[p2os::kMaxPayloadBytes];
    p2os::Packet p;
    p2os::make_packet({payload, p2os::write_sip(sip, payload)}, p);
    out.insert(out.end(), p.view().begin(), p.view().end());
  }
  return out;
}

// A stream of 361-value scans, as continuous output sends them.
Bytes scan_stream(size_t telegrams) {
  Bytes out;
  uint16_t ranges[361];
  for (size_t i = 0; i < telegrams; ++i) {
    for (size_t k = 0; k < 361; ++k) ranges[k] = uint16_t((k * 13 + i) % 8192);
    uint8_t data[2 + 2 * 361];
    size_t n = sicklms200::write_scan(ranges, sicklms200::Units::Millimetres, data);
    sicklms200::Telegram t;
    out.push_back(sicklms200::kAck);
    sicklms200::make_reply(sicklms200::kScanReply, {data, n}, 0, t);
    out.insert(out.end(), t.view().begin(), t.view().end());
  }
  return out;
}

Bytes noisy(Bytes b, uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_int_distribution<size_t> where(0, b.size() - 1);
  for (size_t i = 0; i < b.size() / 1000; ++i) b[where(rng)] ^= uint8_t(1u << (i % 8));
  return b;
}

// One pass of each kind over `stream`; returns the number of items found.
size_t copy_pass(const Bytes& stream, Bytes& sink) {
  for (size_t i = 0; i < stream.size(); i += kChunk) {
    size_t n = std::min(kChunk, stream.size() - i);
    memcpy(sink.data() + i, stream.data() + i, n);
  }
  return sink[stream.size() / 2];
}

size_t p2os_pass(const Bytes& stream) {
  p2os::PacketScanner scanner;
  size_t sips = 0;
  for (size_t i = 0; i < stream.size(); i += kChunk) {
    std::span<const uint8_t> in(stream.data() + i, std::min(kChunk, stream.size() - i));
    p2os::scan_packets(scanner, in, [&](std::span<const uint8_t> p) {
      p2os::Sip sip;
      sips += p2os::parse_sip(p, sip, nullptr);
    });
  }
  return sips;
}

size_t sick_pass(const Bytes& stream) {
  sicklms200::TelegramScanner scanner(sicklms200::kReplyAddress);
  static sicklms200::Scan scan;
  size_t scans = 0;
  for (size_t i = 0; i < stream.size(); i += kChunk) {
    std::span<const uint8_t> in(stream.data() + i, std::min(kChunk, stream.size() - i));
    sicklms200::scan_telegrams(scanner, in, [&](std::span<const uint8_t> body) {
      sicklms200::Reply r;
      scans += sicklms200::split_reply(body, r) && sicklms200::parse_scan(r.data, scan, nullptr);
    });
  }
  return scans;
}

template <typename Pass>
double time_pass(int repeats, Pass&& pass, size_t& found) {
  std::vector<double> t;
  for (int r = 0; r < repeats; ++r) {
    double t0 = seconds_now();
    found = pass();
    t.push_back(seconds_now() - t0);
  }
  return median(t);
}

}  // namespace

int main(int argc, char** argv) {
  int repeats = argc > 1 ? std::max(1, atoi(argv[1])) : 21;
  const Bytes sips = sip_stream(20000), scans = scan_stream(2000);
  const Bytes noisy_sips = noisy(sips, 1), noisy_scans = noisy(scans, 2);
  Bytes sink(std::max(sips.size(), scans.size()));

  struct Row {
    const char* name;
    const Bytes* stream;
    size_t (*pass)(const Bytes&);
    double line_bytes_per_s;  // the line's full speed: baud / 10
  } rows[] = {
      {"p2os SIPs, clean", &sips, p2os_pass, 38400 / 10.0},
      {"p2os SIPs, 1 flip / 1000 B", &noisy_sips, p2os_pass, 38400 / 10.0},
      {"sick scans, clean", &scans, sick_pass, 500000 / 10.0},
      {"sick scans, 1 flip / 1000 B", &noisy_scans, sick_pass, 500000 / 10.0},
  };
  printf("serial codecs: %d repeats, medians; baseline is a copy of the same bytes in %zu-byte reads\n\n",
         repeats, kChunk);
  printf("%-30s %10s %9s %10s %12s %14s\n", "stream", "bytes", "found", "ns/byte", "x copy", "core @ line");
  for (const Row& row : rows) {
    size_t found = 0, unused = 0;
    double base = time_pass(
        repeats, [&] { return copy_pass(*row.stream, sink); }, unused);
    double t = time_pass(
        repeats, [&] { return row.pass(*row.stream); }, found);
    double per_byte = t / double(row.stream->size());
    printf("%-30s %10zu %9zu %10.2f %12.1f %13.4f%%\n", row.name, row.stream->size(), found, per_byte * 1e9,
           t / base, 100.0 * per_byte * row.line_bytes_per_s);
  }
  printf(
      "\ncore @ line: the share of one core the codec needs at 38400 baud (p2os) or 500000 baud (sick).\n");
  return 0;
}
