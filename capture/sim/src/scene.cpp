#include "garmcap/sim/scene.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "garmcap/drafts/file_io.h"
#include "garmcap/drafts/panel_measure.h"
#include "garmcap/drafts/recipes.h"
#include "garmcap/drafts/size_charts.h"

namespace garmcap::sim {

using calib::FormView;

namespace {

nlohmann::json vecJson(const cv::Vec3f& v) {
  return {v[0], v[1], v[2]};
}

cv::Vec3f vecFrom(const nlohmann::json& j, const std::string& key, const std::string& what) {
  const auto& v = drafts::requireField(j, key, what);
  if (!v.is_array() || v.size() != 3 || !v[0].is_number() || !v[1].is_number() ||
      !v[2].is_number()) {
    throw drafts::ParseError(what + ": field '" + key + "' must be an array of 3 numbers");
  }
  return {v[0].get<float>(), v[1].get<float>(), v[2].get<float>()};
}

void onlyKeys(const nlohmann::json& j, std::initializer_list<const char*> keys,
              const std::string& what) {
  if (!j.is_object())
    throw drafts::ParseError(what + ": must be an object");
  // The key by name, not by structured binding: clang 14 (the sanitized build, tests/fuzz) cannot
  // capture a binding in a lambda.
  for (const auto& item : j.items()) {
    const std::string& k = item.key();
    if (std::find_if(keys.begin(), keys.end(), [&](const char* n) { return k == n; }) ==
        keys.end()) {
      throw drafts::ParseError(what + ": unknown field '" + k + "'");
    }
  }
}

double num(const nlohmann::json& j, const char* key, const std::string& what) {
  return drafts::requireNumber(j, key, what);
}

}  // namespace

nlohmann::json Lighting::toJson() const {
  return {{"screen_bgr", vecJson(screenBgr)},
          {"form_bgr", vecJson(formBgr)},
          {"light_dir", {lightDir.x(), lightDir.y(), lightDir.z()}},
          {"exposure", exposure},
          {"ambient", ambient},
          {"gradient", gradient},
          {"gradient_angle_deg", gradientAngleDeg},
          {"vignetting", vignetting},
          {"shadow_strength", shadowStrength},
          {"shadow_offset_cm", shadowOffsetCm},
          {"shadow_blur_cm", shadowBlurCm},
          {"spill_strength", spillStrength},
          {"spill_width_cm", spillWidthCm},
          {"noise_shot", noiseShot},
          {"noise_read", noiseRead},
          {"blur_px", blurPx}};
}

Lighting Lighting::fromJson(const nlohmann::json& j, const std::string& what) {
  onlyKeys(
      j,
      {"screen_bgr", "form_bgr", "light_dir", "exposure", "ambient", "gradient",
       "gradient_angle_deg", "vignetting", "shadow_strength", "shadow_offset_cm", "shadow_blur_cm",
       "spill_strength", "spill_width_cm", "noise_shot", "noise_read", "blur_px"},
      what);
  Lighting l;
  l.screenBgr = vecFrom(j, "screen_bgr", what);
  l.formBgr = vecFrom(j, "form_bgr", what);
  vecFrom(j, "light_dir", what);  // validates the shape; read again in double precision
  const auto& ld = j["light_dir"];
  l.lightDir = Eigen::Vector3d(ld[0].get<double>(), ld[1].get<double>(), ld[2].get<double>());
  if (l.lightDir.norm() < 1e-6)
    throw drafts::ParseError(what + ": field 'light_dir' must not be zero");
  l.exposure = num(j, "exposure", what);
  l.ambient = num(j, "ambient", what);
  l.gradient = num(j, "gradient", what);
  l.gradientAngleDeg = num(j, "gradient_angle_deg", what);
  l.vignetting = num(j, "vignetting", what);
  l.shadowStrength = num(j, "shadow_strength", what);
  l.shadowOffsetCm = num(j, "shadow_offset_cm", what);
  l.shadowBlurCm = num(j, "shadow_blur_cm", what);
  l.spillStrength = num(j, "spill_strength", what);
  l.spillWidthCm = num(j, "spill_width_cm", what);
  l.noiseShot = num(j, "noise_shot", what);
  l.noiseRead = num(j, "noise_read", what);
  l.blurPx = num(j, "blur_px", what);
  if (l.noiseShot < 0 || l.noiseRead < 0 || l.blurPx < 0 || l.exposure <= 0) {
    throw drafts::ParseError(what + ": noise, blur must be >= 0 and exposure > 0");
  }
  return l;
}

nlohmann::json Shake::toJson() const {
  return {{"dx_px", dxPx}, {"dy_px", dyPx}, {"roll_deg", rollDeg}};
}

Shake Shake::fromJson(const nlohmann::json& j, const std::string& what) {
  onlyKeys(j, {"dx_px", "dy_px", "roll_deg"}, what);
  return {num(j, "dx_px", what), num(j, "dy_px", what), num(j, "roll_deg", what)};
}

namespace {

nlohmann::json poseJson(const calib::FormPose& p) {
  nlohmann::json j = {{"model", p.perspective ? "perspective" : "orthographic"},
                      {"px_per_cm", p.pxPerCm},
                      {"offset_px", {p.offsetPx.x(), p.offsetPx.y()}},
                      {"roll_rad", p.rollRad}};
  if (p.perspective) {
    j["intrinsics"] = {{"fx", p.perspective->fx},
                       {"fy", p.perspective->fy},
                       {"cx", p.perspective->cx},
                       {"cy", p.perspective->cy}};
  }
  return j;
}

calib::FormPose poseFrom(const nlohmann::json& j, const std::string& what) {
  calib::FormPose p;
  const std::string model = drafts::requireString(j, "model", what);
  p.pxPerCm = num(j, "px_per_cm", what);
  const auto& o = drafts::requireField(j, "offset_px", what);
  if (!o.is_array() || o.size() != 2)
    throw drafts::ParseError(what + ": field 'offset_px' must be [x, y]");
  p.offsetPx = {o[0].get<double>(), o[1].get<double>()};
  p.rollRad = num(j, "roll_rad", what);
  if (model == "perspective") {
    const auto& i = drafts::requireField(j, "intrinsics", what);
    p.perspective = calib::Intrinsics{num(i, "fx", what), num(i, "fy", what), num(i, "cx", what),
                                      num(i, "cy", what)};
  } else if (model != "orthographic") {
    throw drafts::ParseError(what + ": field 'model' must be orthographic or perspective");
  }
  if (!(p.pxPerCm > 0))
    throw drafts::ParseError(what + ": field 'px_per_cm' must be > 0");
  return p;
}

}  // namespace

nlohmann::json Scene::toJson() const {
  nlohmann::json j = {{"form", formPath},
                      {"width", size.width},
                      {"height", size.height},
                      {"pose", poseJson(pose)},
                      {"lighting", lighting.toJson()},
                      {"garment", garment.toJson()},
                      {"fabric", fabric.toJson()},
                      {"shake", shake.toJson()},
                      {"seed", seed},
                      {"hard", hard}};
  if (!chart.empty())
    j["drafted_from"] = {{"chart", chart}, {"size", chartSize}};
  return j;
}

Scene Scene::fromJson(const nlohmann::json& j, const std::string& what) {
  onlyKeys(j,
           {"form", "width", "height", "pose", "lighting", "garment", "fabric", "shake", "seed",
            "hard", "drafted_from"},
           what);
  Scene s;
  s.formPath = drafts::requireString(j, "form", what);
  s.size =
      cv::Size(static_cast<int>(num(j, "width", what)), static_cast<int>(num(j, "height", what)));
  s.pose = poseFrom(drafts::requireField(j, "pose", what), what + " pose");
  s.lighting = Lighting::fromJson(drafts::requireField(j, "lighting", what), what + " lighting");
  s.garment = GarmentSpec::fromJson(drafts::requireField(j, "garment", what), what + " garment");
  s.fabric = Fabric::fromJson(drafts::requireField(j, "fabric", what), what + " fabric");
  s.shake = Shake::fromJson(drafts::requireField(j, "shake", what), what + " shake");
  const auto& seed = drafts::requireField(j, "seed", what);
  if (!seed.is_number_unsigned())
    throw drafts::ParseError(what + ": field 'seed' must be a non-negative integer");
  s.seed = seed.get<std::uint64_t>();
  const auto& h = drafts::requireField(j, "hard", what);
  if (!h.is_boolean())
    throw drafts::ParseError(what + ": field 'hard' must be true or false");
  s.hard = h.get<bool>();
  if (j.contains("drafted_from")) {
    const auto& d = j["drafted_from"];
    onlyKeys(d, {"chart", "size"}, what + " drafted_from");
    s.chart = drafts::requireString(d, "chart", what + " drafted_from");
    s.chartSize = drafts::requireString(d, "size", what + " drafted_from");
  }
  return s;
}

namespace {

// The garment of a scene drafted for a size of `chartName` instead of sampled ease. The size
// comes from a stream of its own, so the scene's lighting, fabric and pose stay those of the
// same seed without a chart.
void draftFromChart(Scene& s, const RandomSceneOptions& options, std::uint64_t seed,
                    const FormView& view) {
  const drafts::SizeChart& chart = drafts::sizeChart(options.chart);
  std::mt19937_64 rng(seed * 0xD1B54A32D192ED03ULL + 77);
  const std::size_t n = chart.sizes.size();
  std::size_t first = static_cast<std::size_t>(rng() % n), tries = n;
  if (!options.chartSize.empty()) {
    chart.body(options.chartSize);  // throws naming the chart and its sizes
    first = static_cast<std::size_t>(
        std::find(chart.sizes.begin(), chart.sizes.end(), options.chartSize) - chart.sizes.begin());
    tries = 1;
  }
  std::string refused;
  for (std::size_t k = 0; k < tries; ++k) {
    const std::size_t i = (first + k) % n;
    GarmentSpec g = s.garment;
    try {
      g.measurements = draftedGarment(g, chart.bodies[i], view);
      checkGarmentFits(g, view);
    } catch (const std::exception& e) {
      refused += "; size " + chart.sizes[i] + ": " + e.what();
      continue;
    }
    s.garment = std::move(g);
    s.chart = chart.name;
    s.chartSize = chart.sizes[i];
    return;
  }
  throw std::invalid_argument("no size of chart '" + chart.name + "' gives a " + s.garment.type +
                              " that fits the form" + refused);
}

}  // namespace

std::map<std::string, double> simDraftDesign(const std::string& recipe,
                                             const std::map<std::string, std::string>& attributes,
                                             const drafts::Measurements& body) {
  std::map<std::string, double> design;
  const auto sl = attributes.find("sleeve");
  auto clamped = [](double v, const drafts::DesignParameter& p) {
    return std::clamp(v, p.minValue, p.maxValue);
  };
  for (const auto& p : drafts::garmentType(recipe).design) {
    // sleeve_length is a fraction of the arm (docs/drafts.md): 0 sleeveless; short is 0.4, as
    // 0.3 leaves no sleeve below the high cap of the larger dress sizes.
    if (sl != attributes.end() && p.name == "sleeve_length") {
      design[p.name] = sl->second == "none"    ? p.minValue
                       : sl->second == "short" ? clamped(0.4, p)
                                               : p.defaultValue;
    }
    // The simulator wears a garment only with kMinEaseCm of ease at every measured height; a
    // skirt's or trousers' 1 cm waist ease is raised to that plus a margin for the form's
    // polygonal sections. Every other ease is the recipe's.
    if (p.name.rfind("ease_", 0) == 0 && p.defaultValue < kMinEaseCm + 0.5)
      design[p.name] = clamped(kMinEaseCm + 0.5, p);
    // Its tops end at least 3 cm above the crotch and its hems 3 cm above the floor: a blouse
    // ends 7 cm above the body's crotch at the most, trousers 6 cm above the floor.
    if (p.name == "blouse_length" && body.has("rise_length_side"))
      design[p.name] = clamped(std::min(p.defaultValue, body.get("rise_length_side") - 7), p);
    if (p.name == "pants_length" && body.has("leg_waist_side_to_floor")) {
      design[p.name] =
          clamped(std::min(p.defaultValue, 1 - 6 / body.get("leg_waist_side_to_floor")), p);
    }
  }
  return design;
}

std::map<std::string, double> draftedGarment(const GarmentSpec& garment,
                                             const drafts::Measurements& body, const FormView& view,
                                             std::string* recipeUsed) {
  const auto& names = garmentMeasurementNames(garment.type);
  const auto attr = [&](const char* key) {
    const auto it = garment.attributes.find(key);
    return it == garment.attributes.end() ? std::string() : it->second;
  };
  // The recipe of each type; a top is the blouse, which ends below the waist as tops do.
  const std::string recipe = garment.type == "skirt"
                                 ? (attr("skirt") == "a_line" ? "skirt_a" : "skirt_h")
                             : garment.type == "top" ? "blouse"
                                                     : garment.type;  // dress, pants
  const auto design = simDraftDesign(recipe, garment.attributes, body);
  const auto measured = drafts::measurePattern(drafts::draftGarment(recipe, body, design));
  // truth.json names that the pattern measurements (panel_measure.h) spell differently, and
  // what depends on the form the garment is worn on.
  static const std::map<std::string, std::string> kPantsNames = {
      {"outseam", "outseam_length"}, {"inseam", "inseam_length"}, {"leg_opening_circ", "hem_circ"}};
  const double neckToWaist = view.neckSideCm() - view.waistCm();
  std::map<std::string, double> m;
  for (const auto& n : names) {
    const auto alias = garment.type == "pants" ? kPantsNames.find(n) : kPantsNames.end();
    const auto it = measured.find(alias != kPantsNames.end() ? alias->second : n);
    if (it != measured.end()) {
      m[n] = it->second;
    } else if (n == "sleeve_length" && attr("sleeve") == "none") {
      m[n] = 0;
    } else if (n == "garment_length" && garment.type == "dress") {
      m[n] = neckToWaist + measured.at("skirt_length");
    } else if (n == "garment_length" && garment.type == "top") {
      m[n] = neckToWaist + design.at("blouse_length");
    } else {
      throw std::invalid_argument("the " + recipe + " draft does not give '" + n + "'");
    }
  }
  if (recipeUsed)
    *recipeUsed = recipe;
  return m;
}

calib::FormPose fitPose(const calib::FormModel& form, cv::Size size, double marginFrac) {
  const Eigen::Vector3d lo = form.mesh().minCorner(), hi = form.mesh().maxCorner();
  const double usableH = size.height * (1.0 - 2.0 * marginFrac);
  const double usableW = size.width * (1.0 - 2.0 * marginFrac);
  calib::FormPose p;
  p.pxPerCm = std::min(usableH / (hi.y() - lo.y()), usableW / (hi.x() - lo.x()));
  // World origin at the image position that centres the form.
  const double cx = 0.5 * (lo.x() + hi.x()), cy = 0.5 * (lo.y() + hi.y());
  p.offsetPx = {0.5 * size.width - p.pxPerCm * cx, 0.5 * size.height + p.pxPerCm * cy};
  return p;
}

Scene randomScene(const calib::FormModel& form, const std::string& formPath, std::uint64_t seed,
                  const RandomSceneOptions& options) {
  std::mt19937_64 rng(seed * 0x9E3779B97F4A7C15ULL + 12345);
  std::uniform_real_distribution<double> u01(0.0, 1.0);
  auto pick = [&](double lo, double hi) { return lo + (hi - lo) * u01(rng); };
  Scene s;
  s.formPath = formPath;
  s.size = options.size;
  s.seed = rng();
  s.hard = u01(rng) < options.hardFraction;

  // Pose: fitted, then the camera a little nearer or farther and off-centre.
  calib::FormPose pose = fitPose(form, options.size, 0.06);
  const double f = pick(0.93, 1.06);
  const Eigen::Vector2d centre(0.5 * options.size.width, 0.5 * options.size.height);
  pose.pxPerCm *= f;
  pose.offsetPx = centre + (pose.offsetPx - centre) * f +
                  Eigen::Vector2d(pick(-0.02, 0.02) * options.size.width,
                                  pick(-0.01, 0.01) * options.size.height);
  s.pose = pose;

  // Studio.
  Lighting& l = s.lighting;
  l.screenBgr =
      cv::Vec3f(static_cast<float>(pick(0.16, 0.32)), static_cast<float>(pick(0.50, 0.70)),
                static_cast<float>(pick(0.14, 0.28)));
  static const cv::Vec3f kForms[] = {
      {0.62f, 0.72f, 0.80f}, {0.78f, 0.82f, 0.85f}, {0.66f, 0.67f, 0.68f}, {0.55f, 0.63f, 0.74f}};
  l.formBgr = kForms[rng() % 4];
  l.lightDir = Eigen::Vector3d(pick(-0.6, 0.6), pick(0.2, 0.6), 0.8).normalized();
  l.exposure = pick(0.9, 1.12);
  l.ambient = pick(0.35, 0.6);
  l.gradient = pick(0.04, 0.2);
  l.gradientAngleDeg = pick(0, 360);
  l.vignetting = pick(0.1, 0.35);
  l.shadowStrength = s.hard ? pick(0.35, 0.5) : pick(0.15, 0.35);
  l.shadowOffsetCm = pick(3, 9);
  l.shadowBlurCm = pick(3, 8);
  l.spillStrength = s.hard ? pick(0.3, 0.45) : pick(0.1, 0.3);
  l.spillWidthCm = pick(0.6, 1.6);
  l.noiseShot = pick(0.0003, 0.0015);
  l.noiseRead = pick(0.00001, 0.00006);
  l.blurPx = pick(0.4, 0.9);

  // Garment: sampled in a view a few hundred pixels tall (the measurements do not depend on
  // the image size; the arms' length does, and is converted to cm).
  const cv::Size small(300, 400);
  const FormView view(form, fitPose(form, small, 0.05), small);
  const double sc = view.pose().pxPerCm;
  GarmentSpec& g = s.garment;
  g.type = options.type.empty() ? garmentTypeNames()[rng() % 4] : options.type;
  garmentMeasurementNames(g.type);  // validates the type
  const bool upper = g.type == "top" || g.type == "dress";
  const bool skirted = g.type == "skirt" || g.type == "dress";
  static const char* kSleeves[] = {"none", "short", "long"};
  if (upper) {
    // An armless form (a torso form) wears sleeveless tops and dresses only: this simulator
    // draws sleeves along the form's arms. The draw is made anyway, so that a seed gives the
    // same rest of the scene on either form.
    const char* sleeve = kSleeves[rng() % 3];
    g.attributes["sleeve"] = view.arm(0) || view.arm(1) ? sleeve : "none";
  }
  if (skirted)
    g.attributes["skirt"] = u01(rng) < 0.5 ? "a_line" : "h_line";
  g.neckline = u01(rng) < 0.7 ? "round" : "v";
  g.neckDepthCm = pick(4, 14);
  g.sleeveFlare = pick(1.1, 1.5);
  g.thighEase = pick(1.1, 1.35);
  g.hemWaveCm = pick(0.15, 0.45);
  g.foldSeed = rng();

  auto formCirc = [&](double h) {
    const auto sec = view.torsoAtHeight(std::max(h, view.hipCm()));
    if (!sec)
      throw std::invalid_argument("the form has no torso section at " + std::to_string(h) + " cm");
    return sec->circCm;
  };
  const double floorCm = form.minYCm();
  auto& m = g.measurements;
  const bool tight = s.hard && u01(rng) < 0.3;
  if (upper)
    m["bust_circ"] = formCirc(view.bustCm()) + (tight ? pick(2.5, 4) : pick(4, 16));
  m["waist_circ"] = formCirc(view.waistCm()) +
                    (g.type == "top" ? pick(5, 24) : (upper ? pick(3, 16) : pick(2.5, 6)));
  if (g.type != "top")
    m["hip_circ"] = formCirc(view.hipCm()) + pick(3, 12);
  if (g.type == "top") {
    const double lo = view.crotchCm() ? *view.crotchCm() + 6 : view.hipCm() - 10;
    const double hem = pick(lo, view.waistCm() - 5);
    m["garment_length"] = view.neckSideCm() - hem;
    m["hem_circ"] = std::max(formCirc(hem) + pick(3, 14), m["waist_circ"] + pick(-2, 6));
    m["hem_circ"] = std::max(m["hem_circ"], formCirc(hem) + kMinEaseCm + 0.5);
  }
  if (skirted) {
    const double maxLen = view.waistCm() - floorCm - 8;
    const double len =
        std::min(maxLen, pick(view.waistCm() - view.hipCm() + 15, view.waistCm() - floorCm - 20));
    m["skirt_length"] = len;
    if (g.type == "dress")
      m["garment_length"] = view.neckSideCm() - view.waistCm() + len;
    m["hem_circ"] =
        g.attributes["skirt"] == "a_line"
            ? m["hip_circ"] + pick(25, 90)
            : std::max(m["hip_circ"] + pick(-4, 4), formCirc(view.hipCm()) + kMinEaseCm + 0.5);
  }
  if (upper) {
    const std::string& sl = g.attributes["sleeve"];
    double armCm = 1e9;
    for (int side = 0; side < 2; ++side) {
      if (view.arm(side))
        armCm = std::min(armCm, view.arm(side)->tWristPx / sc);
    }
    if (sl != "none" && armCm > 1e8)
      throw std::invalid_argument("the form has no arms for sleeves");
    m["sleeve_length"] = sl == "none" ? 0.0 : (sl == "short" ? pick(8, 22) : armCm + pick(-4, 0));
  }
  if (g.type == "pants") {
    if (!view.crotchCm())
      throw std::invalid_argument("pants need a form with legs");
    const double crotch = *view.crotchCm() - pick(0.5, 4);
    const double hem = pick(floorCm + 6, floorCm + 0.45 * (crotch - floorCm));
    m["outseam"] = view.waistCm() - hem;
    m["inseam"] = crotch - hem;
    double legCirc = 0;
    const int row = static_cast<int>(std::lround(view.rowOfHeight(hem + 1.0)));
    for (int side = 0; side < 2; ++side) {
      if (const auto leg = view.legAtRow(row, side))
        legCirc = std::max(legCirc, leg->circCm);
    }
    m["leg_opening_circ"] = legCirc + pick(10, 28);
  }

  if (!options.chart.empty())
    draftFromChart(s, options, seed, view);

  // Fabric and shake.
  s.fabric = randomFabric(rng, s.hard, l.formBgr);
  if (s.hard && u01(rng) < 0.6) {
    s.shake = Shake{pick(-1.5, 1.5), pick(-1.5, 1.5), pick(-0.08, 0.08)};
  }
  return s;
}

}  // namespace garmcap::sim
