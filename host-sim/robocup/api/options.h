// Options of a plugin (or of any statement of a world or robot file): the
// `key=value` pairs written after the plugin's name. Typed getters record
// the first problem; finish() reports it, or any key nobody asked for, with
// the file and line the options came from. Header-only: plugins use it
// without linking the simulator.
#pragma once

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <utility>
#include <vector>

namespace troupe::robocup {

class Options {
 public:
  Options() = default;
  /// `where`: "file:line" for messages; `base_dir`: what relative paths in
  /// the options are relative to (the file's folder).
  Options(std::string where, std::string base_dir)
      : where_(std::move(where)), base_dir_(std::move(base_dir)) {}

  void set(std::string key, std::string value) {
    for (Entry& e : entries_) {
      if (e.key == key) {
        e.value = std::move(value);
        return;
      }
    }
    entries_.push_back({std::move(key), std::move(value), false});
  }
  bool has(const std::string& key) const { return find(key) != nullptr; }
  const std::string& where() const { return where_; }
  const std::string& base_dir() const { return base_dir_; }
  std::vector<std::pair<std::string, std::string>> entries() const {
    std::vector<std::pair<std::string, std::string>> out;
    for (const Entry& e : entries_) out.emplace_back(e.key, e.value);
    return out;
  }

  /// A number in [lo, hi], or `fallback` when the key is absent.
  double number(const std::string& key, double fallback, double lo = -1e300, double hi = 1e300) {
    Entry* e = use(key);
    if (!e) return fallback;
    double v;
    if (!parse_number(e->value, v)) {
      fail(key, "expected a number, got '" + e->value + "'");
      return fallback;
    }
    if (!(v >= lo && v <= hi)) {
      char buf[128];
      snprintf(buf, sizeof buf, "must be in [%g, %g], got %g", lo, hi, v);
      fail(key, buf);
      return fallback;
    }
    return v;
  }
  /// A whole number in [lo, hi].
  long integer(const std::string& key, long fallback, long lo, long hi) {
    double v = number(key, double(fallback), double(lo), double(hi));
    if (v != double(long(v))) {
      fail(key, "expected a whole number");
      return fallback;
    }
    return long(v);
  }
  /// 0/1, true/false, yes/no.
  bool flag(const std::string& key, bool fallback) {
    Entry* e = use(key);
    if (!e) return fallback;
    if (e->value == "1" || e->value == "true" || e->value == "yes") return true;
    if (e->value == "0" || e->value == "false" || e->value == "no") return false;
    fail(key, "expected 0/1, true/false or yes/no, got '" + e->value + "'");
    return fallback;
  }
  std::string text(const std::string& key, std::string fallback) {
    Entry* e = use(key);
    return e ? e->value : fallback;
  }
  /// One of `choices`; anything else is an error listing them.
  std::string choice(const std::string& key, std::string fallback, const std::vector<std::string>& choices) {
    Entry* e = use(key);
    if (!e) return fallback;
    if (std::find(choices.begin(), choices.end(), e->value) != choices.end()) return e->value;
    std::string list;
    for (const std::string& c : choices) list += (list.empty() ? "" : ", ") + c;
    fail(key, "expected one of " + list + ", got '" + e->value + "'");
    return fallback;
  }
  /// A file name, relative to the folder of the file the options came from.
  std::string path(const std::string& key, std::string fallback) {
    Entry* e = use(key);
    if (!e) return fallback;
    if (e->value.empty() || e->value[0] == '/' || base_dir_.empty()) return e->value;
    return base_dir_ + "/" + e->value;
  }
  /// Comma-separated numbers; exactly `count` of them unless count is 0.
  std::vector<double> numbers(const std::string& key, size_t count = 0) {
    std::vector<double> out;
    Entry* e = use(key);
    if (!e) return out;
    size_t start = 0;
    while (start <= e->value.size()) {
      size_t comma = e->value.find(',', start);
      if (comma == std::string::npos) comma = e->value.size();
      double v;
      if (!parse_number(e->value.substr(start, comma - start), v)) {
        fail(key, "expected comma-separated numbers, got '" + e->value + "'");
        return {};
      }
      out.push_back(v);
      start = comma + 1;
    }
    if (count && out.size() != count) {
      fail(key, "expected " + std::to_string(count) + " numbers, got " + std::to_string(out.size()));
      return {};
    }
    return out;
  }

  /// Records a problem found by the caller (a value out of its own rules).
  void fail(const std::string& key, const std::string& why) {
    if (error_.empty()) error_ = "option '" + key + "': " + why;
  }
  bool ok() const { return error_.empty(); }
  /// False with `error` on the first bad value or the first unknown key.
  bool finish(std::string& error) const {
    if (!error_.empty()) {
      error = error_;
      return false;
    }
    for (const Entry& e : entries_) {
      if (!e.used) {
        error = "unknown option '" + e.key + "'";
        return false;
      }
    }
    return true;
  }

  static bool parse_number(const std::string& text, double& out) {
    if (text.empty()) return false;
    char* end = nullptr;
    errno = 0;
    out = std::strtod(text.c_str(), &end);
    return errno == 0 && end == text.c_str() + text.size();
  }

 private:
  struct Entry {
    std::string key, value;
    bool used = false;
  };
  const Entry* find(const std::string& key) const {
    for (const Entry& e : entries_) {
      if (e.key == key) return &e;
    }
    return nullptr;
  }
  Entry* use(const std::string& key) {
    Entry* e = const_cast<Entry*>(find(key));
    if (e) e->used = true;
    return e;
  }

  std::string where_, base_dir_;
  std::vector<Entry> entries_;
  std::string error_;
};

}  // namespace troupe::robocup
