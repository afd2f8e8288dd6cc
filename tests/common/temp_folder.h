#pragma once
// A fresh folder under the system's temp directory for one test, removed with everything in it
// when the test ends. The name carries the process id and a counter, so tests run side by side
// (ctest -j, several binaries) never share one.

#include <unistd.h>

#include <filesystem>
#include <string>
#include <system_error>

namespace garmcap::testing {

class TempFolder {
 public:
  explicit TempFolder(const std::string& prefix = "garmcap-test")
      : path_(std::filesystem::temp_directory_path() /
              (prefix + "-" + std::to_string(::getpid()) + "-" + std::to_string(counter_++))) {
    std::filesystem::create_directories(path_);
  }
  ~TempFolder() {
    std::error_code ec;
    std::filesystem::remove_all(path_, ec);
  }
  TempFolder(const TempFolder&) = delete;
  TempFolder& operator=(const TempFolder&) = delete;
  const std::filesystem::path& path() const { return path_; }

 private:
  static inline int counter_ = 0;
  std::filesystem::path path_;
};

}  // namespace garmcap::testing
