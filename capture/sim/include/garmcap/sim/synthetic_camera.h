#pragma once
// The "synthetic" camera back end: a capture::ReplayCamera whose scenes the scene simulator
// renders on demand. It lives here, not in capture/, because it needs the simulator (and so
// calib and drafts), which capture must not know about (docs/architecture.md). Programs that
// offer the synthetic camera (garmcapd, the CLI, tests) call sim::makeCamera, which handles
// "synthetic" and forwards every other back end to capture::makeCamera.

#include <cstdint>
#include <filesystem>
#include <memory>
#include <opencv2/core.hpp>
#include <string>
#include <vector>

#include "garmcap/capture/camera.h"
#include "garmcap/capture/replay_camera.h"

namespace garmcap::sim {

/// SceneSource rendering scenes with the simulator (sim.h). It simulates one station: the
/// camera pose, the lights and the bare form are those of randomScene(seed) for the source's
/// whole life; case i brings the garment and fabric of randomScene(seed + i), its own sensor
/// noise and a small exposure drift (+-0.5 %), without camera shake. When `outDir` is given,
/// each case's truth.json and calibration.json are written to `outDir`/<case id>/
/// (FrameMetadata::truthPath names it). open() throws CameraError kNotFound when `formPath` is
/// empty or cannot be loaded; load() throws kBadData for a scene that cannot be drawn.
std::unique_ptr<capture::SceneSource> makeSyntheticSceneSource(
    const std::filesystem::path& formPath, std::uint64_t seed, cv::Size size,
    const std::filesystem::path& outDir = {});

/// capture::cameraBackends() followed by "synthetic", in a stable order.
std::vector<std::string> cameraBackends();

/// "synthetic": a ReplayCamera over makeSyntheticSceneSource(options.formPath, options.seed,
/// options.syntheticSize, options.device) named "synthetic". Any other back end:
/// capture::makeCamera(options); an unknown name throws std::invalid_argument listing
/// cameraBackends().
std::unique_ptr<capture::Camera> makeCamera(const capture::CameraOptions& options);

}  // namespace garmcap::sim
