#pragma once
// A simulated capture scene: the form and its pose in the picture, the studio (green screen,
// lights, lens, sensor), the garment and its fabric, and camera shake between the two shots.
// Everything that makes the two frames is here, so a scene saved as JSON re-renders the same
// images bit for bit.

#include <Eigen/Core>
#include <cstdint>
#include <filesystem>
#include <map>
#include <nlohmann/json.hpp>
#include <opencv2/core.hpp>
#include <random>
#include <string>

#include "garmcap/calib/form_model.h"
#include "garmcap/calib/projection.h"
#include "garmcap/drafts/measurements.h"
#include "garmcap/sim/fabric.h"
#include "garmcap/sim/garment_model.h"

namespace garmcap::sim {

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
  GarmentSpec garment;
  Fabric fabric;
  Shake shake;
  std::uint64_t seed = 1;  // sensor noise (each frame its own stream)
  bool hard = false;       // drawn as a hard case (for rig statistics)
  // The size chart and size the garment was drafted for (randomScene with options.chart);
  // both empty when its ease was sampled. scene.json: "drafted_from": {"chart", "size"}.
  std::string chart, chartSize;

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
  double hardFraction = 0.3;   // share of hard cases (form-coloured or dark green fabric,
                               // camera shake, stronger spill and shadow)
  std::string type;            // empty = any of top, dress, skirt, pants
  std::string chart = "";      // size chart for drafted garments (empty = sampled ease)
  std::string chartSize = "";  // with chart: this size only (empty = drawn from the seed)
};

/// Draws a scene: garment type and attributes, ease and lengths, fabric, lighting, pose jitter
/// (camera distance +-8%) and, for hard cases, shake. Deterministic in `seed`.
/// With `options.chart`, the garment's measurements are those of the project's draft for a size
/// of that chart (draftedGarment), the size drawn from the seed; sizes whose garment does not fit
/// the form (checkGarmentFits) are passed over in turn, and everything else in the scene is the
/// same as without the chart. Throws std::invalid_argument for an unknown chart (listing the
/// known ones) and when no size gives a garment that fits the form (with each size's reason).
Scene randomScene(const calib::FormModel& form, const std::string& formPath, std::uint64_t seed,
                  const RandomSceneOptions& options);

/// Design parameters the simulator drafts `recipe` with (draftedGarment): the sleeve length
/// fraction from the sleeve attribute (none 0, short 0.4, long the default), every ease at least
/// kMinEaseCm + 0.5 cm (a skirt's 1 cm waist ease would not be worn), a blouse ending 7 cm above
/// the body's crotch at the most and trousers 6 cm above the floor, so that the garment passes
/// checkGarmentFits on the form of the same body. Other parameters keep the recipe's defaults.
std::map<std::string, double> simDraftDesign(const std::string& recipe,
                                             const std::map<std::string, std::string>& attributes,
                                             const drafts::Measurements& body);

/// Garment measurements (truth.json names) of the project's draft for `body`, measured on its
/// panels (drafts::measurePattern): the recipe of the type (skirt: skirt_h or skirt_a by the
/// skirt attribute; dress; top: blouse; pants) drafted with simDraftDesign, the trousers'
/// outseam_length, inseam_length and hem_circ as outseam, inseam, leg_opening_circ, and what
/// depends on the form it is worn on: garment_length = side neck to waist on the form +
/// skirt_length (dress) or + the blouse's length below the waist (top); sleeve_length 0 for a
/// sleeveless garment. Throws drafts::DraftError (the recipe refuses the body) or
/// std::invalid_argument for an unknown type.
std::map<std::string, double> draftedGarment(const GarmentSpec& garment,
                                             const drafts::Measurements& body,
                                             const calib::FormView& view,
                                             std::string* recipeUsed = nullptr);

}  // namespace garmcap::sim
