// A scratch folder for one test, removed when the test ends.
#pragma once

#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>

namespace troupe::test {

class TempDir {
 public:
  TempDir() {
    std::string pattern = (std::filesystem::temp_directory_path() / "troupe-sim-XXXXXX").string();
    root_ = mkdtemp(pattern.data()) ? pattern : std::string();
  }
  ~TempDir() {
    std::error_code ec;
    if (!root_.empty()) std::filesystem::remove_all(root_, ec);
  }
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;

  /// `name` inside the folder.
  std::string path(const std::string& name) const { return root_ + "/" + name; }

  /// Writes `text` to `name`, creating folders on the way; returns the path.
  std::string write(const std::string& name, const std::string& text) const {
    std::filesystem::path p(path(name));
    std::filesystem::create_directories(p.parent_path());
    std::ofstream(p, std::ios::binary) << text;
    return p.string();
  }

 private:
  std::string root_;
};

}  // namespace troupe::test
