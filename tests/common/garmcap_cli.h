#pragma once
// Runs the built `garmcap` CLI the way a user does, for the end-to-end tests of its commands:
// stdout and stderr kept apart (a command's JSON goes to stdout, "garmcap: error: ..." to
// stderr) and the exit status decoded.

#include <sys/wait.h>
#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

namespace garmcap::testing {

struct CliResult {
  int status = -1;  // exit status, or 128 + signal
  std::string out;  // stdout
  std::string err;  // stderr
};

/// Runs `garmcap <args>` (args as a shell would split them; quote paths with spaces).
inline CliResult runGarmcap(const std::string& args) {
  const auto errFile = std::filesystem::temp_directory_path() /
                       ("garmcap_cli_stderr_" + std::to_string(::getpid()) + ".txt");
  const std::string cmd =
      std::string(GARMCAP_BIN_DIR) + "/garmcap " + args + " 2>'" + errFile.string() + "'";
  CliResult r;
  FILE* pipe = popen(cmd.c_str(), "r");
  if (pipe == nullptr)
    return r;
  char buf[4096];
  std::size_t n = 0;
  while ((n = std::fread(buf, 1, sizeof buf, pipe)) > 0)
    r.out.append(buf, n);
  const int st = pclose(pipe);
  r.status = WIFEXITED(st) ? WEXITSTATUS(st) : 128 + (WIFSIGNALED(st) ? WTERMSIG(st) : 0);
  std::ostringstream e;
  e << std::ifstream(errFile).rdbuf();
  r.err = e.str();
  std::filesystem::remove(errFile);
  return r;
}

/// A fresh temporary folder for one test, removed when it goes out of scope.
struct TempDir {
  std::filesystem::path path;
  explicit TempDir(const std::string& name)
      : path(std::filesystem::temp_directory_path() /
             ("garmcap_" + name + "_" + std::to_string(::getpid()))) {
    std::filesystem::remove_all(path);
    std::filesystem::create_directories(path);
  }
  ~TempDir() {
    std::error_code ec;
    std::filesystem::remove_all(path, ec);
  }
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;
  std::string operator/(const std::string& name) const { return (path / name).string(); }
};

inline void writeText(const std::string& path, const std::string& text) {
  std::ofstream(path, std::ios::binary) << text;
}

inline std::string readText(const std::string& path) {
  std::ostringstream s;
  s << std::ifstream(path, std::ios::binary).rdbuf();
  return s.str();
}

}  // namespace garmcap::testing
