#include "wire/noise/key_file.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <sodium.h>

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string_view>

namespace troupe::wire::noise {
namespace {

constexpr std::string_view kSecretTag = "troupe-x25519-secret";
constexpr std::string_view kPublicTag = "troupe-x25519";

// Creates `path` with `mode`, failing if it exists, and writes `text`.
bool create_new(const std::string& path, const std::string& text, mode_t mode, std::string& error) {
  int fd = ::open(path.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, mode);
  if (fd < 0) {
    error = path + ": " + (errno == EEXIST ? std::string("exists; not overwritten") : std::strerror(errno));
    return false;
  }
  // The mode the file was created with passes through the umask: set it.
  bool ok = ::fchmod(fd, mode) == 0 && ::write(fd, text.data(), text.size()) == static_cast<ssize_t>(text.size());
  ok = (::close(fd) == 0) && ok;
  if (!ok) error = path + ": cannot write: " + std::strerror(errno);
  return ok;
}

// Key files are one line and a known-nodes file a few; larger is not one.
constexpr size_t kMaxFileBytes = 1 << 20;

// The whole of `path` into `text`. POSIX reads, not <fstream>: iostreams
// bring libstdc++'s locale machinery, about 250 KB of a statically linked
// board node (boards/README.md, "Secure sessions on the boards").
bool read_file(const std::string& path, std::string& text, std::string& error) {
  int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd < 0) {
    error = path + ": cannot open: " + std::strerror(errno);
    return false;
  }
  char block[512];
  ssize_t n = 0;
  while ((n = ::read(fd, block, sizeof block)) > 0 && text.size() <= kMaxFileBytes) {
    text.append(block, static_cast<size_t>(n));
  }
  const int read_errno = errno;
  sodium_memzero(block, sizeof block);
  ::close(fd);
  if (n < 0) {
    error = path + ": cannot read: " + std::strerror(read_errno);
    return false;
  }
  if (text.size() > kMaxFileBytes) {
    error = path + ": larger than " + std::to_string(kMaxFileBytes) + " bytes: not a key file";
    return false;
  }
  return true;
}

// The line of `text` from `at` (without its newline); `at` moves past it.
std::string_view next_line(std::string_view text, size_t& at) {
  const size_t end = std::min(text.find('\n', at), text.size());
  std::string_view line = text.substr(at, end - at);
  at = end + 1;
  return line;
}

// The first two words of `line` (separated by blanks), as `>>` reads them.
void first_words(std::string_view line, std::string_view& first, std::string_view& second) {
  constexpr std::string_view kBlanks = " \t\r\v\f";
  std::string_view* words[] = {&first, &second};
  size_t at = 0;
  for (std::string_view* word : words) {
    const size_t start = std::min(line.find_first_not_of(kBlanks, at), line.size());
    at = std::min(line.find_first_of(kBlanks, start), line.size());
    *word = line.substr(start, at - start);
  }
}

// The first two words of the first line of `path`.
bool read_first_words(const std::string& path, std::string& text, std::string_view& first,
                      std::string_view& second, std::string& error) {
  if (!read_file(path, text, error)) return false;
  size_t at = 0;
  first_words(next_line(text, at), first, second);
  return true;
}

}  // namespace

std::string key_hex(const Key& key) {
  std::string out(2 * key.size() + 1, '\0');
  sodium_bin2hex(out.data(), out.size(), key.data(), key.size());
  out.pop_back();
  return out;
}

bool parse_key_hex(std::string_view text, Key& out) {
  if (text.size() != 2 * out.size()) return false;
  size_t n = 0;
  return sodium_hex2bin(out.data(), out.size(), text.data(), text.size(), nullptr, &n, nullptr) == 0 &&
         n == out.size();
}

bool write_key_pair(const std::string& path, const std::string& name, std::string& error) {
  for (const std::string& p : {path, path + ".pub"}) {
    struct stat st;
    if (::stat(p.c_str(), &st) == 0) {
      error = p + ": exists; not overwritten";
      return false;
    }
  }
  KeyPair pair = generate_keypair();
  std::string secret = std::string(kSecretTag) + " " + key_hex(pair.secret) + "\n";
  bool ok = create_new(path, secret, 0600, error) &&
            create_new(path + ".pub", std::string(kPublicTag) + " " + key_hex(pair.public_key) + " " + name + "\n",
                       0644, error);
  sodium_memzero(secret.data(), secret.size());
  sodium_memzero(pair.secret.data(), pair.secret.size());
  return ok;
}

bool read_secret_key(const std::string& path, KeyPair& out, std::string& error) {
  struct stat st;
  if (::stat(path.c_str(), &st) != 0) {
    error = path + ": cannot open: " + std::strerror(errno);
    return false;
  }
  if ((st.st_mode & 077) != 0) {
    char mode[8];
    std::snprintf(mode, sizeof mode, "%04o", static_cast<unsigned>(st.st_mode & 07777));
    error = path + ": permissions " + mode + " let others read this secret key; chmod 600 " + path;
    return false;
  }
  std::string text;
  std::string_view tag, hex;
  if (!read_first_words(path, text, tag, hex, error)) return false;
  Key secret;
  const bool ok = tag == kSecretTag && parse_key_hex(hex, secret);
  if (ok) out = keypair_from_secret(secret);
  sodium_memzero(secret.data(), secret.size());
  sodium_memzero(text.data(), text.size());
  if (!ok) error = path + ": not a secret key file (expected \"" + std::string(kSecretTag) + " <64 hex digits>\")";
  return ok;
}

bool read_public_key(const std::string& path_or_hex, Key& out, std::string& error) {
  if (parse_key_hex(path_or_hex, out)) return true;
  std::string text;
  std::string_view tag, hex;
  if (!read_first_words(path_or_hex, text, tag, hex, error)) return false;
  if (tag != kPublicTag || !parse_key_hex(hex, out)) {
    error = path_or_hex + ": not a public key file (expected \"" + std::string(kPublicTag) + " <64 hex digits> NAME\")";
    return false;
  }
  return true;
}

std::string known_nodes_path() {
  if (const char* xdg = std::getenv("XDG_CONFIG_HOME"); xdg != nullptr && *xdg != '\0') {
    return std::string(xdg) + "/troupe/known_nodes";
  }
  if (const char* home = std::getenv("HOME"); home != nullptr && *home != '\0') {
    return std::string(home) + "/.config/troupe/known_nodes";
  }
  return {};
}

bool find_known_node(const std::string& path, const std::string& host_port, Key& out, std::string& error) {
  const std::string how = "add the line \"" + host_port + " <the node's key: 64 hex digits>\" to " + path +
                          ", or name the key with --node-key";
  std::string text, ignored;
  if (!read_file(path, text, ignored)) {
    error = "no key known for " + host_port + " (no " + path + "): " + how;
    return false;
  }
  size_t at = 0;
  for (int number = 1; at < text.size(); ++number) {
    std::string_view node, hex;
    first_words(next_line(text, at), node, hex);
    if (node.empty() || node.front() == '#' || node != host_port) continue;
    if (!parse_key_hex(hex, out)) {
      error = path + ":" + std::to_string(number) + ": the key of " + host_port + " is not 64 hex digits";
      return false;
    }
    return true;
  }
  error = "no key known for " + host_port + " in " + path + ": " + how;
  return false;
}

}  // namespace troupe::wire::noise
