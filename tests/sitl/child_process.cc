#include "tests/sitl/child_process.h"

#include <fcntl.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <thread>

namespace troupe::sitl {
namespace {

constexpr int kPollMs = 20;

std::string read_file(const std::string& path) {
  std::string text;
  FILE* f = std::fopen(path.c_str(), "rb");
  if (f == nullptr) return text;
  char chunk[4096];
  for (size_t n; (n = std::fread(chunk, 1, sizeof chunk, f)) > 0;) text.append(chunk, n);
  std::fclose(f);
  return text;
}

}  // namespace

ChildProcess::~ChildProcess() {
  if (pid_ > 0 && running()) {
    kill(pid_, SIGKILL);
    waitpid(pid_, nullptr, 0);
  }
}

bool ChildProcess::start(const std::vector<std::string>& args, const std::string& dir, const std::string& tag,
                         std::string& error) {
  out_path_ = dir + "/" + tag + ".out";
  err_path_ = dir + "/" + tag + ".err";
  int out = open(out_path_.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  int err = open(err_path_.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  if (out < 0 || err < 0) {
    error = "cannot create " + out_path_ + ": " + strerror(errno);
    if (out >= 0) close(out);
    if (err >= 0) close(err);
    return false;
  }
  std::vector<std::string> copy = args;
  std::vector<char*> argv;
  for (std::string& a : copy) argv.push_back(a.data());
  argv.push_back(nullptr);
  pid_ = fork();
  if (pid_ == 0) {
    dup2(out, STDOUT_FILENO);
    dup2(err, STDERR_FILENO);
    int null_fd = open("/dev/null", O_RDONLY);
    dup2(null_fd, STDIN_FILENO);
    execvp(argv[0], argv.data());
    dprintf(STDERR_FILENO, "exec %s: %s\n", argv[0], strerror(errno));
    _exit(127);
  }
  close(out);
  close(err);
  if (pid_ < 0) {
    error = std::string("fork: ") + strerror(errno);
    return false;
  }
  return true;
}

std::string ChildProcess::out() const {
  return read_file(out_path_);
}

std::string ChildProcess::err() const {
  return read_file(err_path_);
}

bool ChildProcess::running() const {
  if (pid_ <= 0 || exited_) return false;
  int status = 0;
  if (waitpid(pid_, &status, WNOHANG) == pid_) {
    exited_ = true;
    status_ = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  }
  return !exited_;
}

bool ChildProcess::wait_for(const std::string& needle, bool in_err, int timeout_ms) const {
  for (int waited = 0;; waited += kPollMs) {
    // Read after checking the child: a line written just before it exited
    // still counts.
    const bool alive = running();
    if ((in_err ? err() : out()).find(needle) != std::string::npos) return true;
    if (!alive || waited >= timeout_ms) return false;
    std::this_thread::sleep_for(std::chrono::milliseconds(kPollMs));
  }
}

int ChildProcess::wait_exit(int timeout_ms) const {
  for (int waited = 0; running() && waited < timeout_ms; waited += kPollMs) {
    std::this_thread::sleep_for(std::chrono::milliseconds(kPollMs));
  }
  return running() ? -1 : status_;
}

int ChildProcess::stop() {
  if (pid_ <= 0) return -1;
  if (running()) {
    kill(pid_, SIGTERM);
    for (int waited = 0; running(); waited += kPollMs) {
      if (waited > 20000) {
        kill(pid_, SIGKILL);
        waitpid(pid_, nullptr, 0);
        exited_ = true;
        status_ = -1;
        break;
      }
      std::this_thread::sleep_for(std::chrono::milliseconds(kPollMs));
    }
  }
  return status_;
}

}  // namespace troupe::sitl
