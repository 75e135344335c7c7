#include "tests/cross/qemu_node.h"

#include <fcntl.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <cstring>
#include <thread>

namespace troupe::cross {
namespace {

constexpr int kPollMs = 20;

int count_lines_with(const std::string& text, const std::string& needle) {
  int n = 0;
  for (size_t at = text.find(needle); at != std::string::npos; at = text.find(needle, at + needle.size()))
    ++n;
  return n;
}

}  // namespace

std::vector<std::string> qemu_argv(const CrossBuild& build, const std::string& program,
                                   const std::string& preload) {
  std::vector<std::string> argv = {build.qemu, "-L", build.loader_prefix};
  if (!build.sysroot_lib.empty()) argv.insert(argv.end(), {"-E", "LD_LIBRARY_PATH=" + build.sysroot_lib});
  if (!preload.empty()) argv.insert(argv.end(), {"-E", "LD_PRELOAD=" + preload});
  argv.push_back(program);
  return argv;
}

std::string qemu_command(const CrossBuild& build, const std::string& program,
                         const std::vector<std::string>& args) {
  std::string command;
  for (const std::string& a : qemu_argv(build, program)) command += quote(a) + " ";
  for (const std::string& a : args) command += quote(a) + " ";
  return command;
}

QemuNode::~QemuNode() {
  if (pid_ > 0) {
    kill(pid_, SIGKILL);
    waitpid(pid_, nullptr, 0);
  }
  if (!dir_.empty()) {
    std::string ignored;
    run("rm -rf " + quote(dir_), ignored);
  }
}

bool QemuNode::start(const CrossBuild& build, const std::string& binary, const std::string& config,
                     std::string& error, const Extras& extras) {
  dir_ = make_temp_dir("node-" + build.name);
  log_path_ = dir_ + "/stderr.log";
  std::vector<std::string> args = extras.wrapper;
  for (const std::string& a : qemu_argv(build, binary, extras.preload)) args.push_back(a);
  args.insert(args.end(), {config, "--port", "0", "--listen", "127.0.0.1"});
  std::vector<char*> argv;
  for (std::string& a : args) argv.push_back(a.data());
  argv.push_back(nullptr);

  int log_fd = open(log_path_.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  if (log_fd < 0) {
    error = "cannot create " + log_path_ + ": " + strerror(errno);
    return false;
  }
  pid_ = fork();
  if (pid_ == 0) {
    dup2(log_fd, STDERR_FILENO);
    int null_fd = open("/dev/null", O_RDWR);
    dup2(null_fd, STDIN_FILENO);
    dup2(null_fd, STDOUT_FILENO);
    execvp(argv[0], argv.data());
    dprintf(STDERR_FILENO, "exec %s: %s\n", argv[0], strerror(errno));
    _exit(127);
  }
  close(log_fd);
  if (pid_ < 0) {
    error = std::string("fork: ") + strerror(errno);
    return false;
  }
  // "... serving N devices on 127.0.0.1:PORT"
  const std::string needle = " on 127.0.0.1:";
  for (int waited = 0; waited < 60000; waited += kPollMs) {
    std::string text = log();
    size_t at = text.find(needle);
    size_t serving = text.find("serving ");
    if (serving != std::string::npos && at != std::string::npos) {
      port_ = uint16_t(atoi(text.c_str() + at + needle.size()));
      return port_ != 0;
    }
    int status = 0;
    if (waitpid(pid_, &status, WNOHANG) == pid_) {
      pid_ = -1;
      exit_status_ = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
      error = "the node exited before serving; its log:\n" + text;
      return false;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(kPollMs));
  }
  error = "the node did not report serving within 60 s; its log:\n" + log();
  return false;
}

std::string QemuNode::log() const {
  return read_text(log_path_);
}

bool QemuNode::wait_for_log(const std::string& needle, int count, int timeout_ms) const {
  for (int waited = 0; waited <= timeout_ms; waited += kPollMs) {
    if (count_lines_with(log(), needle) >= count) return true;
    std::this_thread::sleep_for(std::chrono::milliseconds(kPollMs));
  }
  return false;
}

void QemuNode::signal(int sig) const {
  if (pid_ > 0) kill(pid_, sig);
}

int QemuNode::stop() {
  if (pid_ <= 0) return -1;
  kill(pid_, SIGTERM);
  int status = 0;
  for (int waited = 0; waitpid(pid_, &status, WNOHANG) != pid_; waited += kPollMs) {
    if (waited > 20000) {  // a node that ignores SIGTERM is a failure
      kill(pid_, SIGKILL);
      waitpid(pid_, &status, 0);
      break;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(kPollMs));
  }
  pid_ = -1;
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

}  // namespace troupe::cross
