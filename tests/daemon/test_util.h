#pragma once
// Helpers shared by the daemon's unit tests: temp folders.
#include <unistd.h>

#include <filesystem>
#include <random>
#include <string>

namespace garmcap::daemon::test {

/// A fresh folder under the system temp dir, removed with its contents at destruction.
class TempDir {
 public:
  TempDir() {
    std::random_device rd;
    path_ = std::filesystem::temp_directory_path() /
            ("garmcap-daemon-test-" + std::to_string(::getpid()) + "-" + std::to_string(rd()));
    std::filesystem::create_directories(path_);
  }
  ~TempDir() {
    std::error_code ec;
    std::filesystem::remove_all(path_, ec);
  }
  const std::filesystem::path& path() const { return path_; }

 private:
  std::filesystem::path path_;
};

}  // namespace garmcap::daemon::test
