// The "synthetic" camera: a ReplayCamera whose scenes are rendered on demand by the scene
// simulator (sim.h) instead of read from a rig folder.
//
// It simulates one station, not a rig of many: the camera pose, the studio's lights and the
// bare form are those of randomScene(seed) for the camera's whole life, as a fixed camera on a
// fixed form would be. Case i only brings the garment and fabric of randomScene(seed + i), its
// own sensor noise and a small drift of the exposure (+-0.5 %). Camera shake is left out: a
// moved camera is a real fault the station refuses (capture the bare form again), not
// something that happens on every press. (Hard cases keep their strong spill and shadow only as
// far as the fixed studio has them; a fabric drawn form-coloured is so for the case's own form
// cover colour, which the station's fixed cover only approaches.)

#include <algorithm>
#include <map>
#include <mutex>
#include <optional>
#include <stdexcept>

#include "garmcap/calib/form_model.h"
#include "garmcap/drafts/file_io.h"
#include "garmcap/sim/scene.h"
#include "garmcap/sim/sim.h"
#include "garmcap/sim/synthetic_camera.h"

namespace garmcap::sim {
namespace fs = std::filesystem;
using capture::CameraError;
using capture::CameraErrorKind;
using capture::SceneImage;
using capture::SceneSource;
using capture::Shot;

namespace {

/// Loading the form mesh takes about half a second: cameras on the same form share it, and it
/// stays loaded for the process (a station uses one form; reconnects must not reload it).
std::shared_ptr<const calib::FormModel> sharedForm(const fs::path& formPath) {
  static std::mutex mutex;
  static std::map<fs::path, std::shared_ptr<const calib::FormModel>> cache;
  std::lock_guard lock(mutex);
  if (auto it = cache.find(formPath); it != cache.end()) {
    return it->second;
  }
  std::shared_ptr<const calib::FormModel> form;
  try {
    form = std::make_shared<const calib::FormModel>(calib::FormModel::load(formPath));
  } catch (const std::exception& e) {
    throw CameraError(CameraErrorKind::kNotFound,
                      "synthetic camera: cannot load the dress form: " + std::string(e.what()));
  }
  cache[formPath] = form;
  return form;
}

class SyntheticSceneSource final : public SceneSource {
 public:
  SyntheticSceneSource(fs::path formPath, std::uint64_t seed, cv::Size size, fs::path outDir)
      : formPath_(std::move(formPath)), seed_(seed), size_(size), outDir_(std::move(outDir)) {}

  std::string describe() const override {
    return "synthetic seed " + std::to_string(seed_) + " (form " + formPath_.string() + ")";
  }

  void open() override {
    if (formPath_.empty()) {
      throw CameraError(CameraErrorKind::kNotFound,
                        "synthetic camera: no dress form given (formPath)");
    }
    if (form_) {
      return;
    }
    form_ = sharedForm(formPath_);
  }

  // Scenes are drawn from the seed forever; a large count keeps the replay sequencing as is.
  std::size_t caseCount() const override { return kCases; }
  std::string caseId(std::size_t index) const override {
    return "synthetic_" + std::to_string(seed_ + index);
  }

  SceneImage load(std::size_t index, Shot shot) override {
    if (!renderer_ || index != rendered_) {
      try {
        renderer_ = std::make_unique<SceneRenderer>(*form_, stationScene(index));
      } catch (const std::invalid_argument& e) {
        throw CameraError(CameraErrorKind::kBadData,
                          "synthetic camera: scene " + caseId(index) + ": " + e.what());
      }
      rendered_ = index;
      truthPath_.clear();
      if (!outDir_.empty()) {
        truthPath_ = outDir_ / caseId(index) / "truth.json";
        drafts::writeJsonFile(truthPath_, renderer_->truth());
        drafts::writeJsonFile(outDir_ / caseId(index) / "calibration.json",
                              renderer_->calibration());
      }
    }
    SceneImage out;
    out.caseId = caseId(index);
    out.bgr = shot == Shot::kDressed ? renderer_->renderDressed() : renderer_->renderEmpty();
    out.source = describe() + " case " + out.caseId;
    out.truthPath = truthPath_;
    return out;
  }

 private:
  // The studio of the station (pose, lights, form cover) with the garment of case `index`.
  Scene stationScene(std::size_t index) {
    RandomSceneOptions options;
    options.size = size_;
    if (!studio_) {
      RandomSceneOptions calm = options;
      calm.hardFraction = 0;  // an ordinary studio: moderate spill and shadow
      studio_ = randomScene(*form_, formPath_.string(), seed_, calm);
    }
    Scene s = randomScene(*form_, formPath_.string(), seed_ + index, options);
    s.size = studio_->size;
    s.pose = studio_->pose;
    const double exposure = s.lighting.exposure;
    s.lighting = studio_->lighting;
    // The case's own exposure draw, 0.9-1.12, mapped to +-0.5 % around the studio's.
    s.lighting.exposure *= 1.0 + 0.005 * ((exposure - 0.9) / 0.11 - 1.0);
    s.shake = Shake{};
    return s;
  }

  static constexpr std::size_t kCases = 1'000'000;
  fs::path formPath_;
  std::uint64_t seed_;
  cv::Size size_;
  fs::path outDir_;
  std::shared_ptr<const calib::FormModel> form_;
  std::optional<Scene> studio_;
  std::unique_ptr<SceneRenderer> renderer_;
  std::size_t rendered_ = 0;
  fs::path truthPath_;
};

}  // namespace

std::unique_ptr<SceneSource> makeSyntheticSceneSource(const fs::path& formPath, std::uint64_t seed,
                                                      cv::Size size, const fs::path& outDir) {
  return std::make_unique<SyntheticSceneSource>(formPath, seed, size, outDir);
}

std::vector<std::string> cameraBackends() {
  std::vector<std::string> names = capture::cameraBackends();
  names.push_back("synthetic");
  return names;
}

std::unique_ptr<capture::Camera> makeCamera(const capture::CameraOptions& options) {
  if (options.backend == "synthetic") {
    return std::make_unique<capture::ReplayCamera>(
        makeSyntheticSceneSource(options.formPath, options.seed, options.syntheticSize,
                                 options.device),
        "synthetic", options.loop);
  }
  // capture::makeCamera lists only its own back ends when it refuses a name; here the
  // synthetic one is also on offer, so the message names the full list.
  const auto known = capture::cameraBackends();
  if (std::find(known.begin(), known.end(), options.backend) == known.end()) {
    std::string list;
    for (const auto& b : cameraBackends()) {
      list += (list.empty() ? "" : ", ") + b;
    }
    throw std::invalid_argument("unknown camera back end '" + options.backend +
                                "' (known: " + list + ")");
  }
  return capture::makeCamera(options);
}

}  // namespace garmcap::sim
