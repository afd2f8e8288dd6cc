#pragma once
// A simulated capture scene: the form and its pose in the picture, the studio (green screen,
// lights, lens, sensor), the garment and its fabric, and camera shake between the two shots.
// Everything that makes the two frames is here, so a scene saved as JSON re-renders the same
// images bit for bit.

#include <Eigen/Core>
#include <cstdint>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <opencv2/core.hpp>
#include <random>
#include <string>

#include "garmcap/calib/form_model.h"
#include "garmcap/calib/garment_model.h"
#include "garmcap/calib/projection.h"
#include "garmcap/capture/fabric.h"

namespace garmcap::capture {

/// The studio: colours are BGR reflectances in [0, 1]; the light model is ambient + Lambert.
struct Lighting {
  cv::Vec3f screenBgr{0.25f, 0.62f, 0.22f};     // green screen
  cv::Vec3f formBgr{0.62f, 0.72f, 0.80f};       // the form's cover (beige)
  Eigen::Vector3d lightDir{-0.35, 0.45, 0.82};  // towards the key light (x right, y up, z camera)
  double exposure = 1.0;                        // overall gain
  double ambient = 0.45;                        // fraction of light that is ambient
  double gradient = 0.12;                       // relative brightness change across the screen
  double gradientAngleDeg = 30;  // direction of the gradient (0 = brighter to the right)
  double vignetting = 0.25;      // relative darkening in the corners
  double shadowStrength = 0.35;  // darkening of the screen in the form's soft shadow
  double shadowOffsetCm = 6;     // shadow shift on the screen (down-right of the form)
  double shadowBlurCm = 5;       // shadow softness (Gaussian sigma)
  double spillStrength = 0.25;   // green spill on foreground edges (blend weight at the edge)
  double spillWidthCm = 1.2;     // spill falls off over this distance inside the edge
  double noiseShot = 0.0008;     // sensor noise variance per unit intensity (shot noise)
  double noiseRead = 0.00002;    // constant variance (read noise)
  double blurPx = 0.6;           // lens point-spread sigma in px

  nlohmann::json toJson() const;
  static Lighting fromJson(const nlohmann::json& j, const std::string& what);
};

/// Camera motion between the bare-form and the dressed shot (applied to the dressed frame).
struct Shake {
  double dxPx = 0, dyPx = 0, rollDeg = 0;
  nlohmann::json toJson() const;
  static Shake fromJson(const nlohmann::json& j, const std::string& what);
};

struct Scene {
  std::string formPath;  // the --form argument the scene was made with
  cv::Size size{0, 0};   // image size, px
  calib::FormPose pose;  // orthographic or perspective; roll applied to both frames
  Lighting lighting;
  calib::GarmentSpec garment;
  Fabric fabric;
  Shake shake;
  std::uint64_t seed = 1;  // sensor noise (each frame its own stream)
  bool hard = false;       // drawn as a hard case (for rig statistics)

  nlohmann::json toJson() const;
  static Scene fromJson(const nlohmann::json& j, const std::string& what);
};

/// Largest frame the simulator renders (12 MP, the station's biggest sensor).
inline constexpr long kMaxPixels = 12'000'000;

/// The pose that fits the whole form into `size` with `marginFrac` of the image height free
/// above and below, centred horizontally, feet towards the bottom. Orthographic.
calib::FormPose fitPose(const calib::FormModel& form, cv::Size size, double marginFrac = 0.05);

/// Options for drawing random scenes.
struct RandomSceneOptions {
  cv::Size size{960, 1280};
  double hardFraction = 0.3;  // share of hard cases (form-coloured or dark green fabric,
                              // camera shake, stronger spill and shadow)
  std::string type;           // empty = any of top, dress, skirt, pants
  std::string chart = "";     // size chart for drafted garments (empty = sampled ease)
};

/// Draws a scene: garment type and attributes, ease and lengths (or a chart size drafted by the
/// project's recipes when `options.chart` is set and the drafted garment fits the form), fabric,
/// lighting, pose jitter (camera distance +-8%) and, for hard cases, shake. Deterministic in
/// `seed`. Throws std::invalid_argument if no garment of the asked type fits the form.
Scene randomScene(const calib::FormModel& form, const std::string& formPath, std::uint64_t seed,
                  const RandomSceneOptions& options);

}  // namespace garmcap::capture
