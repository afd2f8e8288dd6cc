// libFuzzer: bytes as the dress form's 3D scan (OBJ when the first byte is even, PLY when odd), the
// file a station is calibrated from (`garmcap calibrate --form`). The readers take a path, so the
// input goes through a file in /dev/shm. Only drafts::ParseError and drafts::FileError may come out.

#include <unistd.h>

#include <cstdint>
#include <fstream>
#include <string>

#include "garmcap/calib/mesh.h"
#include "garmcap/drafts/file_io.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size == 0)
    return 0;
  static const std::string stem = "/dev/shm/garmcap-fuzz-mesh-" + std::to_string(::getpid());
  const std::string path = stem + ((data[0] & 1) == 0 ? ".obj" : ".ply");
  {
    std::ofstream out(path, std::ios::binary | std::ios::trunc);
    out.write(reinterpret_cast<const char*>(data + 1), static_cast<std::streamsize>(size - 1));
  }
  try {
    (void)garmcap::calib::readMesh(path);
  } catch (const garmcap::drafts::ParseError&) {
  } catch (const garmcap::drafts::FileError&) {
  }
  return 0;
}
