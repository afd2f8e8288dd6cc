// libFuzzer: bytes as /etc/garmcapd/garmcapd.toml, read by the daemon at start and on reload.
// Only ConfigError (naming the file and key) may come out of loadConfig.

#include <unistd.h>

#include <cstdint>
#include <cstdio>
#include <fstream>
#include <string>

#include "garmcap/daemon/config.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static const std::string path =
      "/tmp/garmcap-fuzz-config-" + std::to_string(::getpid()) + ".toml";
  {
    std::ofstream out(path, std::ios::binary | std::ios::trunc);
    out.write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
  }
  try {
    (void)garmcap::daemon::loadConfig(path);
  } catch (const garmcap::daemon::ConfigError&) {
  }
  return 0;
}
