// libFuzzer: bytes as a stored pattern (pattern.json, docs/formats.md), the reader the daemon runs
// on every pattern route and the CLI on --pattern files. Only its documented errors may come out.

#include <cstdint>
#include <string>

#include "garmcap/drafts/file_io.h"
#include "garmcap/drafts/pattern_io.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  try {
    (void)garmcap::drafts::patternFromJson(text, "fuzz input");
  } catch (const garmcap::drafts::ParseError&) {
  } catch (const std::invalid_argument&) {
  } catch (const std::out_of_range&) {
  }
  return 0;
}
