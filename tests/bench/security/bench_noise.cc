// bench_noise: what a secure session costs, in memory (no sockets): the IK
// handshake (both sides), and frames of several sizes sealed by one side and
// opened into the other's frame reader, next to the same frames copied into
// a frame reader in plain, in the same run. Medians of 9 repeats, in the
// thread's CPU time (a shared machine's other load does not count).
//
//   build/host-release/tests/bench/security/bench_noise
#include <time.h>

#include <algorithm>
#include <cstdio>
#include <vector>

#include "wire/noise/noise_transport.h"

namespace {

using namespace troupe::wire;
using namespace troupe::wire::noise;
double cpu_us() {
  timespec t{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
  return t.tv_sec * 1e6 + t.tv_nsec / 1e3;
}

constexpr int kRepeats = 9;

template <typename F>
double median_us(int iterations, F&& run) {
  std::vector<double> per;
  for (int r = 0; r < kRepeats; ++r) {
    const double t0 = cpu_us();
    for (int i = 0; i < iterations; ++i) run();
    per.push_back((cpu_us() - t0) / iterations);
  }
  std::nth_element(per.begin(), per.begin() + kRepeats / 2, per.end());
  return per[kRepeats / 2];
}

std::vector<uint8_t> frame_of(size_t body) {
  std::vector<uint8_t> f(kPrefixBytes + body, 0x5a);
  for (size_t i = 0; i < kPrefixBytes; ++i) f[i] = static_cast<uint8_t>(body >> (8 * i));
  return f;
}

}  // namespace

int main() {
  const KeyPair node = generate_keypair(), client = generate_keypair();
  std::vector<uint8_t> c_out, n_out;
  std::string error;
  FrameReader sink(1u << 21);
  auto handshake = [&](NoiseTransport& c, NoiseTransport& n) {
    c_out.clear();
    n_out.clear();
    c.begin(c_out);
    n.begin(n_out);
    n.inbound(c_out, sink, n_out, error);
    c.inbound(n_out, sink, c_out, error);
  };
  NoiseTransport c(SecureOptions{Role::Initiator, client, node.public_key, nullptr});
  NoiseTransport n(SecureOptions{Role::Responder, node, {}, nullptr});
  const double hs = median_us(50, [&] { handshake(c, n); });
  if (!c.ready() || !n.ready()) {
    std::fprintf(stderr, "bench_noise: the handshake failed: %s\n", error.c_str());
    return 1;
  }
  std::printf("IK handshake, both sides: %.1f us CPU (median of %d x 50)\n\n", hs, kRepeats);

  std::printf("| frame bytes | plain us CPU | secure us CPU | secure / plain | secure MB/s |\n");
  std::printf("|---:|---:|---:|---:|---:|\n");
  for (size_t body : {size_t{100}, size_t{1000}, size_t{16'000}, size_t{200'000}}) {
    const auto frame = frame_of(body);
    const int iterations = static_cast<int>(std::max<size_t>(20, 2'000'000 / frame.size()));
    FrameReader plain_reader(1u << 21), secure_reader(1u << 21);
    const double plain = median_us(iterations, [&] {
      auto space = plain_reader.write_space(frame.size());
      std::copy(frame.begin(), frame.end(), space.begin());
      plain_reader.commit(frame.size());
      plain_reader.next();
    });
    std::vector<uint8_t> sealed;
    const double secure = median_us(iterations, [&] {
      sealed.clear();
      c.outbound(frame, sealed);
      n.inbound(sealed, secure_reader, n_out, error);
      secure_reader.next();
    });
    std::printf("| %zu | %.2f | %.2f | %.1f | %.0f |\n", frame.size(), plain, secure, secure / plain,
                frame.size() / secure);
  }
  if (!error.empty()) {
    std::fprintf(stderr, "bench_noise: %s\n", error.c_str());
    return 1;
  }
  return 0;
}
