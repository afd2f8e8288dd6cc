// libFuzzer: bytes as a station's calibration.json or camera.json (docs/formats.md), read at every
// daemon start, by `garmcap capture --calibration` and by rig eval. The first byte chooses the
// reader. Only drafts::ParseError (a JSON syntax error, naming line and column) and
// calib::CalibError (a field out of range, naming it) may come out.

#include <cstdint>
#include <string>

#include "garmcap/calib/camera.h"
#include "garmcap/calib/errors.h"
#include "garmcap/calib/registration.h"
#include "garmcap/drafts/file_io.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size == 0)
    return 0;
  const bool camera = (data[0] & 1) == 1;
  const std::string text(reinterpret_cast<const char*>(data + 1), size - 1);
  try {
    const auto j = garmcap::drafts::parseJson(text, "fuzz.json");
    if (camera)
      (void)garmcap::calib::cameraFromJson(j, "camera.json");
    else
      (void)garmcap::calib::calibrationFromJson(j, "calibration.json");
  } catch (const garmcap::drafts::ParseError&) {
  } catch (const garmcap::calib::CalibError&) {
  }
  return 0;
}
