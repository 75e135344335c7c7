#include "tests/support/child_process.h"

#include <arpa/inet.h>
#include <fcntl.h>
#include <netinet/in.h>
#include <signal.h>
#include <sys/socket.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <thread>

namespace troupe::testing {
namespace {

constexpr int kPollMs = 20;
constexpr int kTermGraceMs = 20000;

sockaddr_in loopback(uint16_t port) {
  sockaddr_in a{};
  a.sin_family = AF_INET;
  a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  a.sin_port = htons(port);
  return a;
}

}  // namespace

ChildProcess::~ChildProcess() {
  if (running()) kill_hard();
}

bool ChildProcess::start(const std::vector<std::string>& argv, const std::string& dir, const std::string& tag,
                         std::string& error) {
  out_path_ = dir + "/" + tag + ".out";
  err_path_ = dir + "/" + tag + ".err";
  int out = open(out_path_.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  int err = open(err_path_.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  const bool ok = out >= 0 && err >= 0 && spawn(argv, out, err, error);
  if (out < 0 || err < 0) error = "cannot create " + out_path_ + ": " + strerror(errno);
  if (out >= 0) close(out);
  if (err >= 0) close(err);
  return ok;
}

bool ChildProcess::start_logged(const std::vector<std::string>& argv, const std::string& log_path,
                                std::string& error) {
  out_path_ = err_path_ = log_path;
  int fd = open(log_path.c_str(), O_WRONLY | O_CREAT | O_APPEND | O_CLOEXEC, 0644);
  if (fd < 0) {
    error = "cannot open " + log_path + ": " + strerror(errno);
    return false;
  }
  const bool ok = spawn(argv, fd, fd, error);
  close(fd);
  return ok;
}

bool ChildProcess::spawn(const std::vector<std::string>& argv, int out_fd, int err_fd, std::string& error) {
  stop();
  std::vector<std::string> copy = argv;
  std::vector<char*> args;
  for (std::string& a : copy) args.push_back(a.data());
  args.push_back(nullptr);
  exited_ = false;
  status_ = -1;
  pid_ = fork();
  if (pid_ == 0) {
    dup2(out_fd, STDOUT_FILENO);
    dup2(err_fd, STDERR_FILENO);
    // No terminal input: a program waiting on stdin would hang the test.
    int null_fd = open("/dev/null", O_RDONLY);
    dup2(null_fd, STDIN_FILENO);
    execvp(args[0], args.data());
    dprintf(STDERR_FILENO, "exec %s: %s\n", args[0], strerror(errno));
    _exit(127);
  }
  if (pid_ < 0) {
    error = std::string("fork: ") + strerror(errno);
    return false;
  }
  return true;
}

std::string ChildProcess::out() const {
  return read_text(out_path_);
}

std::string ChildProcess::err() const {
  return read_text(err_path_);
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

void ChildProcess::reap_now() {
  waitpid(pid_, nullptr, 0);
  exited_ = true;
  status_ = -1;
}

int ChildProcess::stop() {
  if (pid_ <= 0) return -1;
  if (running()) {
    kill(pid_, SIGTERM);
    for (int waited = 0; running(); waited += kPollMs) {
      if (waited > kTermGraceMs) {
        kill(pid_, SIGKILL);
        reap_now();
        break;
      }
      std::this_thread::sleep_for(std::chrono::milliseconds(kPollMs));
    }
  }
  return status_;
}

void ChildProcess::kill_hard() {
  if (!running()) return;
  kill(pid_, SIGKILL);
  reap_now();
}

ProgramResult run_to_end(const std::vector<std::string>& argv, int timeout_ms) {
  ProgramResult r;
  const std::string dir = make_temp_dir("troupe-run-");
  ChildProcess child;
  std::string error;
  if (dir.empty() || !child.start(argv, dir, "run", error)) {
    r.err = dir.empty() ? "cannot make a scratch folder" : error;
    remove_tree(dir);
    return r;
  }
  r.status = child.wait_exit(timeout_ms);
  child.kill_hard();
  r.out = child.out();
  r.err = child.err();
  remove_tree(dir);
  return r;
}

uint16_t free_port() {
  int fd = socket(AF_INET, SOCK_STREAM | SOCK_CLOEXEC, 0);
  sockaddr_in a = loopback(0);
  socklen_t len = sizeof a;
  uint16_t port = 0;
  if (bind(fd, reinterpret_cast<sockaddr*>(&a), sizeof a) == 0 &&
      getsockname(fd, reinterpret_cast<sockaddr*>(&a), &len) == 0) {
    port = ntohs(a.sin_port);
  }
  close(fd);
  return port;
}

bool wait_for_listener(uint16_t port, double timeout_s) {
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::duration<double>(timeout_s);
  // At least one try, so a timeout of 0 asks once.
  for (;;) {
    int fd = socket(AF_INET, SOCK_STREAM | SOCK_CLOEXEC, 0);
    sockaddr_in a = loopback(port);
    const bool ok = connect(fd, reinterpret_cast<sockaddr*>(&a), sizeof a) == 0;
    close(fd);
    if (ok) return true;
    if (std::chrono::steady_clock::now() >= deadline) return false;
    std::this_thread::sleep_for(std::chrono::milliseconds(kPollMs));
  }
}

std::string make_temp_dir(const std::string& prefix) {
  std::error_code ec;
  std::string pattern = (std::filesystem::temp_directory_path(ec) / (prefix + "XXXXXX")).string();
  return mkdtemp(pattern.data()) != nullptr ? pattern : std::string();
}

void remove_tree(const std::string& path) {
  std::error_code ec;
  if (!path.empty()) std::filesystem::remove_all(path, ec);
}

std::string read_text(const std::string& path) {
  std::string text;
  FILE* f = std::fopen(path.c_str(), "rb");
  if (f == nullptr) return text;
  char chunk[4096];
  for (size_t n; (n = std::fread(chunk, 1, sizeof chunk, f)) > 0;) text.append(chunk, n);
  std::fclose(f);
  return text;
}

}  // namespace troupe::testing
