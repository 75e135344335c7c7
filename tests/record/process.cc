#include "tests/record/process.h"

#include <chrono>
#include <cstdio>
#include <thread>
#include <utility>

namespace troupe::testing {

std::string bin(const std::string& relative) {
  return std::string(TROUPE_BINARY_DIR) + "/" + relative;
}

Process::Process(std::vector<std::string> argv) : dir_(make_temp_dir("troupe-record-")) {
  std::string error;
  // A program that cannot start shows as one that exited at once, and the
  // test's next expectation fails.
  if (!child_.start(argv, dir_, "proc", error)) std::fprintf(stderr, "%s\n", error.c_str());
}

Process::~Process() {
  child_.kill_hard();
  remove_tree(dir_);
}

bool Process::wait_listening(uint16_t port) {
  for (int i = 0; i < 1000; ++i) {
    if (wait_for_listener(port, 0)) return true;
    if (!running()) return false;
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  return false;
}

Outcome run_program(std::vector<std::string> argv, int timeout_ms) {
  ProgramResult r = run_to_end(argv, timeout_ms);
  return {r.status, std::move(r.out), std::move(r.err)};
}

}  // namespace troupe::testing
