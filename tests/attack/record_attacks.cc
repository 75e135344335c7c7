// Attacks on troupe play through its input: damaged recordings (it must say
// where and play what comes before) and recordings whose times jump (it must
// not wait for days). Each file is given to its own troupe play.
#include <algorithm>
#include <fstream>
#include <iterator>
#include <random>
#include <thread>

#include "tests/attack/attacks.h"
#include "tests/attack/recordings.h"
#include "tests/attack/wire_peer.h"
#include "wire/record/log_file.h"

namespace troupe::attack {
namespace {

constexpr int kRunMs = 30000;  // bounds a hung program, not a requirement
constexpr uint64_t kSeed = 40;

Bytes read_file(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return Bytes(std::istreambuf_iterator<char>(in), {});
}

void write_file(const std::string& path, const Bytes& bytes) {
  std::ofstream(path, std::ios::binary | std::ios::trunc)
      .write(reinterpret_cast<const char*>(bytes.data()), std::streamsize(bytes.size()));
}

// `troupe play FILE --info`: its exit status (-1: crashed or hung) and output.
testing::ProgramResult info(const std::string& file) {
  return testing::run_to_end({program("troupe-play"), file, "--info"}, kRunMs);
}

// Plays `file` to its end while a client reads position2d:0: the exit
// status (-1: crashed or hung) and the Data frames the client received.
struct Played {
  int status = -1;
  int frames = 0;
  std::string log;
};
Played play(const std::string& file, const std::string& dir) {
  Played p;
  testing::ChildProcess proc;
  const uint16_t port = testing::free_port();
  std::string error;
  // --wait: nothing plays before the client has opened the device.
  if (!proc.start({program("troupe-play"), file, "--port", std::to_string(port), "--wait"}, dir, "play",
                  error))
    return p;
  // Listening soon, unless it refused the file and exited.
  const Deadline deadline = deadline_in(10000);
  while (!testing::wait_for_listener(port, 0) && proc.running() && ms_left(deadline) > 0) {
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  WirePeer client;
  Frames f;
  if (proc.running() && client.connect(port) && client.send(f.hello(0)) &&
      client.ask(f.open(kPosition0, 1), 1, 10000)) {
    while (auto frame = client.read_frame(kRunMs)) {
      const wire::Message* m = message(*frame);
      p.frames += m && m->header()->kind() == wire::Kind::Data;
    }
  }
  p.status = proc.wait_exit(kRunMs);
  proc.kill_hard();
  p.log = proc.err();
  return p;
}

// Byte offsets where each record starts, for damage that must be found.
std::vector<uint64_t> record_offsets(const Bytes& file) {
  std::vector<uint64_t> at;
  for (uint64_t o = record::kLogHeaderBytes; o + record::kRecordHeaderBytes <= file.size();) {
    at.push_back(o);
    o += record::kRecordHeaderBytes + wire::read_prefix(&file[o]);
  }
  return at;
}

}  // namespace

void corrupt_recordings(Target& t, int scale, Outcome& out) {
  out.unit = "files";
  const std::string good = t.dir() + "/good.trl";
  std::string error;
  if (!write_recording(good, steady_times(30, 10000), error)) {
    out.got_through("cannot write the recording: " + error);
    return;
  }
  const Bytes original = read_file(good);
  const std::vector<uint64_t> starts = record_offsets(original);
  std::mt19937_64 rng(kSeed);
  for (int i = 0; i < 40 * scale; ++i) {
    Bytes bad = original;
    std::string damage;
    bool must_be_found = true;  // a cut at a record boundary leaves a good, shorter file
    switch (i % 4) {
      case 0: {  // flipped bits in the records
        for (int b = 0; b < 1 + int(rng() % 4); ++b) {
          const size_t at = record::kLogHeaderBytes + rng() % (bad.size() - record::kLogHeaderBytes);
          bad[at] ^= uint8_t(1u << (rng() % 8));
        }
        damage = "flipped bits";
        break;
      }
      case 1: {  // cut short
        const size_t keep = 1 + rng() % (bad.size() - 1);
        bad.resize(keep);
        must_be_found =
            keep > record::kLogHeaderBytes && std::find(starts.begin(), starts.end(), keep) == starts.end();
        damage = "cut at byte " + std::to_string(keep);
        break;
      }
      case 2: {  // a record length forged huge
        const uint64_t at = starts[rng() % starts.size()];
        bad[at + 3] = 0x7F;
        damage = "a forged length at byte " + std::to_string(at);
        break;
      }
      case 3: {  // a checksum zeroed
        const uint64_t at = starts[rng() % starts.size()];
        bad[at + 4] = bad[at + 5] = bad[at + 6] = bad[at + 7] = 0;
        damage = "a zeroed checksum at byte " + std::to_string(at);
        break;
      }
    }
    const std::string file = t.dir() + "/bad" + std::to_string(i) + ".trl";
    write_file(file, bad);
    ++out.volume;
    const testing::ProgramResult r = info(file);
    if (r.status != 0 && r.status != 1) {
      out.survived = false;
      out.got_through("troupe play --info crashed or hung on " + damage);
      continue;
    }
    if (must_be_found && r.out.find("status    complete") != std::string::npos)
      out.got_through("--info called a file complete with " + damage);
    // Every eighth file is played too, to a client: it must end by itself.
    if (i % 8 == 0 && r.status == 0) {
      const Played p = play(file, t.dir());
      if (p.status != 0 && p.status != 1) {
        out.survived = false;
        out.got_through("troupe play crashed or hung on " + damage + ": " + p.log);
      }
    }
  }
}

void time_jump_recordings(Target& t, int scale, Outcome& out) {
  out.unit = "files";
  const uint64_t far = uint64_t(1) << 40;
  std::vector<std::vector<uint64_t>> files;
  // A jump forward in the middle, the times going on from there.
  std::vector<uint64_t> a = steady_times(20, 10000);
  for (int i = 0; i < 10; ++i) a.push_back(far + uint64_t(i) * 10000);
  files.push_back(a);
  // Forward, then back to where it was.
  std::vector<uint64_t> b = steady_times(10, 10000);
  b.push_back(far);
  for (int i = 0; i < 10; ++i) b.push_back(100000 + uint64_t(i) * 10000);
  files.push_back(b);
  // The very first Data record far away, the rest near zero.
  std::vector<uint64_t> c = {far};
  for (uint64_t x : steady_times(10, 10000)) c.push_back(x);
  files.push_back(c);
  // Every other record jumps; and the largest time there is.
  std::vector<uint64_t> d;
  for (int i = 0; i < 20; ++i) d.push_back(i % 2 ? far * uint64_t(i) : uint64_t(i) * 10000);
  d.push_back(UINT64_MAX);
  d.push_back(0);
  files.push_back(d);
  for (int round = 0; round < scale; ++round) {
    for (size_t i = 0; i < files.size(); ++i) {
      const std::string file = t.dir() + "/jump" + std::to_string(i) + ".trl";
      std::string error;
      if (!write_recording(file, files[i], error)) {
        out.got_through("cannot write the recording: " + error);
        return;
      }
      ++out.volume;
      const testing::ProgramResult r = info(file);
      if (r.status != 0) {
        out.survived = r.status == 1;
        out.got_through("troupe play --info failed on jump file " + std::to_string(i) + ": " + r.err);
        continue;
      }
      if (r.out.find("jump      byte ") == std::string::npos)
        out.got_through("--info did not report the jumps of file " + std::to_string(i) + ":\n" + r.out);
      const Played p = play(file, t.dir());
      if (p.status != 0) {
        out.survived = p.status == 1;
        out.got_through("troupe play did not play jump file " + std::to_string(i) + " to its end: " + p.log);
      } else if (p.frames != int(files[i].size())) {
        out.got_through("jump file " + std::to_string(i) + ": the client got " + std::to_string(p.frames) +
                        " of " + std::to_string(files[i].size()) + " frames");
      }
    }
  }
}

}  // namespace troupe::attack
