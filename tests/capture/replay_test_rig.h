#pragma once
// A small rig folder written to a temporary directory for the replay tests: cases with a green
// backdrop, a grey form and (dressed) a coloured garment, a truth.json, and rig.json.

#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <iomanip>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <sstream>
#include <string>

#include "garmcap/capture/camera.h"

namespace garmcap::capture {

/// The options a station's config gives for a camera back end (`device`: a node or a rig folder).
inline CameraOptions cameraOptions(const std::string& backend, const std::string& device = {}) {
  CameraOptions o;
  o.backend = backend;
  o.device = device;
  return o;
}

struct TempRig {
  std::filesystem::path dir;

  explicit TempRig(const std::string& name)
      : dir(std::filesystem::temp_directory_path() /
            ("garmcap_capture_" + name + "_" + std::to_string(::getpid()))) {
    std::filesystem::remove_all(dir);
  }
  ~TempRig() {
    std::error_code ec;
    std::filesystem::remove_all(dir, ec);
  }
  TempRig(const TempRig&) = delete;
  TempRig& operator=(const TempRig&) = delete;

  static std::string caseName(int i) {
    std::ostringstream s;
    s << "case_" << std::setw(3) << std::setfill('0') << i;
    return s.str();
  }

  /// Writes `count` cases of `size` and the index (rig.json as capture::readRig reads it), the
  /// frames as empty.<ext> and dressed.<ext> (`ext` "png" or "jpg").
  void make(int count, cv::Size size, const std::string& ext = "png") {
    std::string index = "{\"format\": \"garmcap-rig\", \"version\": 1, \"cases\": [";
    for (int i = 0; i < count; ++i) {
      const std::filesystem::path c = dir / caseName(i);
      std::filesystem::create_directories(c);
      cv::Mat empty(size, CV_8UC3, cv::Scalar(40, 170, 50));
      const cv::Point centre(size.width / 2, size.height / 2);
      cv::ellipse(empty, centre, {size.width / 6, size.height / 3}, 0, 0, 360,
                  cv::Scalar(190, 190, 195), cv::FILLED);
      cv::Mat dressed = empty.clone();
      cv::rectangle(dressed,
                    cv::Rect(size.width / 3, size.height / 4, size.width / 3, size.height / 3),
                    cv::Scalar(30 + 40 * i, 40, 160), cv::FILLED);
      cv::imwrite((c / ("empty." + ext)).string(), empty);
      cv::imwrite((c / ("dressed." + ext)).string(), dressed);
      std::ofstream(c / "truth.json") << "{\"type\": \"skirt\"}\n";
      index += std::string(i ? ", " : "") + "{\"id\": \"" + caseName(i) + "\", \"dir\": \"" +
               caseName(i) + "\", \"type\": \"skirt\", \"attributes\": {}, \"hard\": false}";
    }
    index += "]}\n";
    std::ofstream(dir / "rig.json") << index;
  }
};

}  // namespace garmcap::capture
