#pragma once
// Cameras that serve scenes instead of photographing them: "replay" serves the cases of a rig
// folder (ARCHITECTURE.md: case folders with empty.png, dressed.png, truth.json, indexed by
// rig.json; the frames may be empty.jpg and dressed.jpg instead, see rig.h); "synthetic" serves
// scenes rendered on demand by the scene simulator (its SceneSource is in the simulator's
// target: sim::makeSyntheticSceneSource, capture/sim/.../synthetic_camera.h). Both are one
// ReplayCamera over a SceneSource, so they behave identically towards the station, and faults
// (latency, corrupt frame, disconnect) can be injected to exercise the daemon's error paths.
//
// Sequencing: a still with Shot::kEmpty serves the current case's empty frame; kDressed serves
// its dressed frame and then moves to the next case; kAny alternates empty, dressed, next case.
// StillRequest::caseId selects a case first. The preview shows the last shot served (the empty
// frame before any), scaled to the preview size.

#include <chrono>
#include <cstddef>
#include <filesystem>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include "garmcap/capture/camera.h"

namespace garmcap::capture {

/// One scene: an image and where it came from (for messages and metadata).
struct SceneImage {
  cv::Mat bgr;
  std::string caseId;
  std::filesystem::path source;     ///< the image file, or a description of the render
  std::filesystem::path truthPath;  ///< the case's truth.json (may be empty)
  /// The file's bytes when `bgr` is their decoding (Frame::encoded), with their media type;
  /// empty for rendered scenes.
  std::string encoded;
  std::string encodedMediaType;
};

/// Where a ReplayCamera gets its scenes.
class SceneSource {
 public:
  virtual ~SceneSource() = default;
  /// "rig <folder>" or "synthetic seed N".
  virtual std::string describe() const = 0;
  /// Checks the source is usable (rig folder and index present). Throws CameraError kNotFound
  /// naming the folder, kBadData naming the index file.
  virtual void open() = 0;
  /// Number of cases; valid after open().
  virtual std::size_t caseCount() const = 0;
  virtual std::string caseId(std::size_t index) const = 0;
  /// Loads one image of a case (kEmpty or kDressed). Throws CameraError kBadData naming the
  /// file when it is missing, present in both formats, corrupt or truncated, and when the empty
  /// and dressed images of the case differ in size.
  virtual SceneImage load(std::size_t index, Shot shot) = 0;
};

/// SceneSource over a rig folder, read with readRig (rig.h): a rig whose rig.json is missing
/// is not found (CameraError kNotFound); one readRig refuses is kBadData with its message.
std::unique_ptr<SceneSource> makeRigSceneSource(const std::filesystem::path& rigDir);

class ReplayCamera final : public Camera {
 public:
  /// `backend` is the name reported ("replay" or "synthetic").
  ReplayCamera(std::unique_ptr<SceneSource> source, std::string backend = "replay",
               bool loop = true);
  ~ReplayCamera() override;

  std::string backend() const override { return backend_; }
  std::string device() const override;
  void open() override;
  void close() noexcept override;
  bool isOpen() const override;
  void configure(const CameraConfig& config) override;
  CameraConfig config() const override;
  cv::Size stillSize() const override;
  cv::Size previewSize() const override;
  void lockSettings(const CaptureSettings& settings) override;
  CaptureSettings settings() const override;
  std::vector<std::string> unsupportedSettings() const override { return {}; }
  Frame captureStill(const StillRequest& request = {}) override;
  void startPreview() override;
  std::optional<Frame> nextPreviewFrame(std::chrono::milliseconds timeout) override;
  void stopPreview() noexcept override;
  bool previewRunning() const override;
  bool reconnect() override;

  // --- fault injection (thread-safe; the daemon's HTTP API may call these) ---
  /// Delay before each frame. A latency above the configured timeout makes stills time out
  /// (after waiting the timeout) and preview calls return nullopt.
  void setLatency(std::chrono::milliseconds latency);
  /// The next `count` frames arrive corrupt: a still throws CameraError(kBadData), a preview
  /// frame is dropped.
  void injectCorruptFrames(int count);
  /// Unplugs the camera: calls on the open camera throw kDisconnected, and open()/reconnect()
  /// fail as not found, until replug().
  void unplug();
  void replug();

  /// Case the next still comes from, and the shot kAny would serve next.
  std::size_t currentCase() const;
  std::size_t caseCount() const;
  /// Selects a case by id; throws CameraError(kNotFound) listing a few known ids.
  void selectCase(const std::string& caseId);
  std::uint64_t framesDropped() const;

 private:
  void requireUsable(const char* what) const;  // called with mutex_ held
  void waitLatency(std::chrono::milliseconds limit, bool& timedOut);
  cv::Mat scaled(const cv::Mat& bgr, cv::Size target) const;
  Frame makeFrame(const SceneImage& image, bool preview, Shot shot);

  std::unique_ptr<SceneSource> source_;
  std::string backend_;
  bool loop_;
  mutable std::mutex mutex_;
  bool open_ = false;
  bool present_ = true;
  bool disconnected_ = false;
  CameraConfig config_;
  CaptureSettings settings_;
  bool previewRunning_ = false;
  bool resumePreview_ = false;  // the preview ran when the camera was unplugged
  std::chrono::milliseconds latency_{0};
  int corruptLeft_ = 0;
  std::size_t case_ = 0;
  Shot nextShot_ = Shot::kEmpty;
  bool exhausted_ = false;
  std::optional<SceneImage> lastShown_;
  cv::Size lastStillSize_;
  std::uint64_t sequence_ = 0;
  std::uint64_t dropped_ = 0;
};

}  // namespace garmcap::capture
