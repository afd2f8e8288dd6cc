// libFuzzer: bytes as /etc/garmcapd/garmcapd.toml, read by the daemon at start and on reload.
// Only ConfigError (naming the file and key) may come out of the reader. The text goes to
// parseConfigText, the part of loadConfig after the file is read: writing a file per input
// cost a sixth of the run in system calls.

#include <cstdint>
#include <string>

#include "garmcap/daemon/config.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  try {
    (void)garmcap::daemon::parseConfigText(text, "fuzz.toml");
  } catch (const garmcap::daemon::ConfigError&) {
  }
  return 0;
}
