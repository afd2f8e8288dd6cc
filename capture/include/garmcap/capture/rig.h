#pragma once
// Rigs of replayed images (ARCHITECTURE.md "Rig case"): a folder with rig.json and one folder
// per case holding empty.png, dressed.png and truth.json (plus calibration.json and scene.json
// when the simulator made it). The reader is shared by the replay camera, the rig tests and
// `garmcap rig eval`; the writer is `garmcap rig make`.
//
// rig.json:
//   {"format": "garmcap-rig", "version": 1, "generator": "...", "form": "...",
//    "width": 960, "height": 1280, "seed": 7,
//    "cases": [{"id": "case_000", "dir": "case_000", "type": "dress",
//               "attributes": {"sleeve": "short", "skirt": "a_line"}, "hard": false}, ...]}
// A rig made with a size chart (`rig make --chart C`) also has "chart": C, and each case the
// "size" of C its garment was drafted for.
//
// Errors: RigError naming the file and the reason (missing or corrupt image, unknown field,
// frames of different sizes).

#include <cstdint>
#include <filesystem>
#include <functional>
#include <map>
#include <nlohmann/json.hpp>
#include <opencv2/core.hpp>
#include <stdexcept>
#include <string>
#include <vector>

#include "garmcap/calib/form_model.h"

namespace garmcap::capture {

class RigError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

struct RigCaseInfo {
  std::string id;
  std::filesystem::path dir;  // absolute (resolved against the rig folder)
  std::string type;
  std::map<std::string, std::string> attributes;
  bool hard = false;
  std::string size;  // the size of rig.json's "chart" the garment was drafted for, else empty
};

struct Rig {
  std::filesystem::path dir;
  nlohmann::json index;  // rig.json as read
  std::vector<RigCaseInfo> cases;
  /// Case by id; throws RigError naming the rig and the id.
  const RigCaseInfo& find(const std::string& id) const;
};

/// Reads `dir`/rig.json strictly and checks that every case folder holds empty.png,
/// dressed.png and truth.json. Images are not decoded here (see loadRigCase).
Rig readRig(const std::filesystem::path& dir);

/// One case with its frames decoded (8-bit BGR).
struct RigCase {
  std::string id;
  std::filesystem::path dir;
  cv::Mat empty;
  cv::Mat dressed;
  nlohmann::json truth;
  nlohmann::json calibration;  // calibration.json, or truth["calibration"]; null if neither
};

/// Loads a case folder. Throws RigError "<file>: missing", "<file>: not a readable image
/// (corrupt or truncated)", or "<dressed>: 960x1280 differs from <empty>: 1000x1280".
RigCase loadRigCase(const std::filesystem::path& caseDir);

/// Decodes one frame of a case folder ("empty" or "dressed"), with the same errors.
cv::Mat loadRigImage(const std::filesystem::path& file);

struct RigMakeOptions {
  int count = 12;
  std::uint64_t seed = 1;
  cv::Size size{960, 1280};
  double hardFraction = 0.3;
  std::string
      chart;  // size chart the garments are drafted from (randomScene); empty = sampled ease
  /// Called after each case with (index, count, case id).
  std::function<void(int, int, const std::string&)> progress;
};

/// Renders a rig: `count` scenes with a balanced mix of types (cycling top, dress, skirt,
/// pants), the rest drawn from the seed; writes the case folders and rig.json. Returns the rig
/// as readRig would. With `options.chart`, each case is a size of the chart drawn from its
/// seed: it is rendered on the parametric form of that size's body (calib::ParametricForm,
/// written once per size to `outDir`/forms/<chart>_<size>/form.{obj,json}; `form` is not used)
/// wearing the garment drafted for the same body (randomScene with chartSize).
Rig makeRig(const calib::FormModel& form, const std::string& formPath,
            const std::filesystem::path& outDir, const RigMakeOptions& options);

}  // namespace garmcap::capture
