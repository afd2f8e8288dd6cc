// libFuzzer: bytes as a body-measurement file, the readers behind `garmcap draft --measurements`,
// the daemon's tape and draft inputs: a Valentina individual measurement file (.vit, XML) when the
// first byte is even, measurements JSON when it is odd. Only ParseError (naming the place) may
// come out; anything else (std::out_of_range from a substr, a crash) is a finding.

#include <cstdint>
#include <string>

#include "garmcap/drafts/file_io.h"
#include "garmcap/drafts/measurements.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size == 0)
    return 0;
  const bool vit = (data[0] & 1) == 0;
  const std::string text(reinterpret_cast<const char*>(data + 1), size - 1);
  try {
    if (vit)
      (void)garmcap::drafts::measurementsFromVit(text, "fuzz.vit");
    else
      (void)garmcap::drafts::measurementsFromJson(text, "fuzz.json");
  } catch (const garmcap::drafts::ParseError&) {
  }
  return 0;
}
