#pragma once
// Runs a shell command for the tests that hand a file to an independent reader (Python's zipfile,
// csv and xml, ezdxf, pdfinfo, unzip) and compare its answer with ours.

#include <cstdio>
#include <stdexcept>
#include <string>

namespace garmcap::testing {

/// Runs `cmd` with /bin/sh and returns its standard output; `status` gets pclose's status.
/// Throws when the shell cannot be started (a missing reader is then named by the shell's
/// own output and a non-zero status).
inline std::string runCommand(const std::string& cmd, int& status) {
  FILE* p = ::popen(cmd.c_str(), "r");
  if (!p)
    throw std::runtime_error("cannot run " + cmd);
  std::string out;
  char buf[4096];
  while (const std::size_t n = std::fread(buf, 1, sizeof buf, p))
    out.append(buf, n);
  status = ::pclose(p);
  return out;
}

}  // namespace garmcap::testing
