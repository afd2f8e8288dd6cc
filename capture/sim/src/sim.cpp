#include "garmcap/sim/sim.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <opencv2/imgproc.hpp>
#include <stdexcept>

#include "garmcap/calib/registration.h"
#include "garmcap/drafts/file_io.h"

namespace garmcap::sim {

namespace {

calib::FormPose withoutRoll(calib::FormPose p) {
  p.rollRad = 0;
  return p;
}

Scene checked(Scene s) {
  if (s.size.width < 64 || s.size.height < 64) {
    throw std::invalid_argument("image size " + std::to_string(s.size.width) + "x" +
                                std::to_string(s.size.height) + " is too small (at least 64x64)");
  }
  if (static_cast<long>(s.size.width) * s.size.height > kMaxPixels) {
    throw std::invalid_argument("image size " + std::to_string(s.size.width) + "x" +
                                std::to_string(s.size.height) + " exceeds 12 MP");
  }
  return s;
}

// Smooth random field with values around 1 +- amplitude: a few control points upsampled, so
// it is the same at every resolution for a given seed.
cv::Mat1f smoothField(cv::Size size, std::uint64_t seed, int cells, double amplitude) {
  cv::RNG rng(seed);
  cv::Mat1f small(cells + 1, cells + 1);
  rng.fill(small, cv::RNG::UNIFORM, -amplitude, amplitude);
  cv::Mat1f big;
  cv::resize(small, big, size, 0, 0, cv::INTER_CUBIC);
  return big + 1.0f;
}

// Gaussian blur with a large sigma done at reduced resolution (a 100 px sigma at 12 MP would
// otherwise cost a second per frame).
cv::Mat1f wideBlur(const cv::Mat1f& src, double sigmaPx) {
  const double factor = std::max(1.0, sigmaPx / 6.0);
  cv::Mat1f small, blurred, out;
  cv::resize(src, small, cv::Size(), 1.0 / factor, 1.0 / factor, cv::INTER_AREA);
  cv::GaussianBlur(small, blurred, cv::Size(), sigmaPx / factor);
  cv::resize(blurred, out, src.size(), 0, 0, cv::INTER_LINEAR);
  return out;
}

float lambert(const cv::Vec3f& n, const Eigen::Vector3d& l, double ambient) {
  const double d = std::max(0.0, n[0] * l.x() + n[1] * l.y() + n[2] * l.z());
  // Normalised so that a surface facing the camera is lit at 1.
  return static_cast<float>(ambient + (1.0 - ambient) * std::min(1.35, d / std::max(0.3, l.z())));
}

double round2(double v) {
  return std::round(v * 100.0) / 100.0;
}

}  // namespace

SceneRenderer::SceneRenderer(const calib::FormModel& form, Scene scene)
    : form_(&form),
      scene_(checked(std::move(scene))),
      view_(form, withoutRoll(scene_.pose), scene_.size) {
  checkGarmentFits(scene_.garment, view_);
}

cv::Mat SceneRenderer::renderEmpty() const {
  return render(false);
}
cv::Mat SceneRenderer::renderDressed() const {
  return render(true);
}

cv::Mat1f SceneRenderer::garmentCoverage() const {
  return layGarment(scene_.garment, view_).coverage;
}

cv::Mat SceneRenderer::render(bool dressed) const {
  const cv::Size size = scene_.size;
  const Lighting& L = scene_.lighting;
  const double s = scene_.pose.pxPerCm;
  const Eigen::Vector3d light = L.lightDir.normalized();
  const float exposure = static_cast<float>(L.exposure);

  // Illumination of the screen: gradient, cloth unevenness (static between the two shots).
  cv::Mat1f illum(size);
  const double ga = L.gradientAngleDeg * std::numbers::pi / 180.0;
  const double half = 0.5 * std::hypot(size.width, size.height);
  const cv::Mat1f uneven = smoothField(size, scene_.seed ^ 0xA5A5A5A5ULL, 6, 0.03);
  for (int y = 0; y < size.height; ++y) {
    float* row = illum.ptr<float>(y);
    const float* un = uneven.ptr<float>(y);
    for (int x = 0; x < size.width; ++x) {
      const double g =
          ((x - 0.5 * size.width) * std::cos(ga) + (y - 0.5 * size.height) * std::sin(ga)) / half;
      row[x] = exposure * static_cast<float>(1.0 + L.gradient * g) * un[x];
    }
  }

  const cv::Mat1f& formA = view_.coverage();
  GarmentLayer garment;
  cv::Mat1f garmentA(size, 0.f);
  if (dressed) {
    garment = layGarment(scene_.garment, view_);
    garmentA = garment.coverage;
  }
  cv::Mat1f fgA = 1.0f - (1.0f - formA).mul(1.0f - garmentA);

  // Soft shadow on the screen, cast down-and-away from the key light.
  cv::Mat1f shadow;
  {
    const Eigen::Vector2d dir = Eigen::Vector2d(-light.x(), light.y()).normalized();
    const cv::Matx23f shift(1, 0, static_cast<float>(dir.x() * L.shadowOffsetCm * s), 0, 1,
                            static_cast<float>(dir.y() * L.shadowOffsetCm * s));
    cv::Mat1f moved;
    cv::warpAffine(fgA, moved, shift, size, cv::INTER_LINEAR, cv::BORDER_CONSTANT, 0);
    shadow = wideBlur(moved, L.shadowBlurCm * s);
  }

  // Static fine texture of the form's cover (a jersey weave), the same in both shots.
  const cv::Mat1f coverTex =
      smoothField(size, scene_.seed ^ 0x5EED5EEDULL, std::max(8, size.width / 24), 0.015);

  // Distance inside the foreground, for spill.
  cv::Mat1f dist;
  {
    cv::Mat1b fg = fgA > 0.5f;
    cv::distanceTransform(fg, dist, cv::DIST_L2, 3);
  }
  const double spillW = std::max(0.5, L.spillWidthCm * s);

  cv::Mat3f img(size);
  const Fabric& fabric = scene_.fabric;
  const double footprint = 1.0 / s;
  for (int y = 0; y < size.height; ++y) {
    const float* il = illum.ptr<float>(y);
    const float* sh = shadow.ptr<float>(y);
    const float* fa = formA.ptr<float>(y);
    const float* ga2 = garmentA.ptr<float>(y);
    const float* ds = dist.ptr<float>(y);
    const float* ct = coverTex.ptr<float>(y);
    const cv::Vec3f* fn = view_.normals().ptr<cv::Vec3f>(y);
    cv::Vec3f* out = img.ptr<cv::Vec3f>(y);
    for (int x = 0; x < size.width; ++x) {
      const cv::Vec3f screen = L.screenBgr * il[x];
      const cv::Vec3f bg = screen * static_cast<float>(1.0 - L.shadowStrength * sh[x]);
      cv::Vec3f c = bg;
      const float a = fa[x], g = ga2[x];
      if (a > 0.f) {
        const cv::Vec3f form = L.formBgr * (exposure * lambert(fn[x], light, L.ambient) * ct[x]);
        c = c * (1.f - a) + form * a;
      }
      if (g > 0.f) {
        const cv::Vec2f uv = garment.uvCm(y, x);
        const cv::Vec3f refl = fabricColour(fabric, uv[0], uv[1], footprint);
        const float fold = static_cast<float>(1.0 + fabric.foldDepth * garment.foldShade(y, x));
        const cv::Vec3f cloth =
            refl * (exposure * lambert(garment.normals(y, x), light, L.ambient) * fold);
        c = c * (1.f - g) + cloth * g;
      }
      const float fg = 1.f - (1.f - a) * (1.f - g);
      if (fg > 0.f && L.spillStrength > 0) {
        const float w = static_cast<float>(L.spillStrength * std::exp(-ds[x] / spillW)) * fg;
        // Spill tints towards the screen's colour without brightening the surface much.
        const float lum = (c[0] + c[1] + c[2]) / 3.f;
        const float slum = std::max(1e-3f, (screen[0] + screen[1] + screen[2]) / 3.f);
        c = c * (1.f - w) + screen * (w * lum / slum);
      }
      out[x] = c;
    }
  }

  // Vignetting (cos^4-like falloff approximated by a quadratic in the radius).
  {
    const double cx = 0.5 * (size.width - 1), cy = 0.5 * (size.height - 1);
    const double r2max = cx * cx + cy * cy;
    for (int y = 0; y < size.height; ++y) {
      cv::Vec3f* out = img.ptr<cv::Vec3f>(y);
      for (int x = 0; x < size.width; ++x) {
        const double r2 = ((x - cx) * (x - cx) + (y - cy) * (y - cy)) / r2max;
        out[x] *= static_cast<float>(1.0 - L.vignetting * r2);
      }
    }
  }

  // Roll of the camera (both shots) and shake (dressed only), as one affine warp.
  {
    const double roll = scene_.pose.rollRad;
    const Shake& sk = scene_.shake;
    const bool shake = dressed && (sk.dxPx != 0 || sk.dyPx != 0 || sk.rollDeg != 0);
    if (roll != 0 || shake) {
      // Roll is counter-clockwise on screen about the world origin's image position.
      cv::Mat r1 =
          cv::getRotationMatrix2D(cv::Point2f(static_cast<float>(scene_.pose.offsetPx.x()),
                                              static_cast<float>(scene_.pose.offsetPx.y())),
                                  roll * 180.0 / std::numbers::pi, 1.0);
      cv::Mat m = cv::Mat::eye(3, 3, CV_64F);
      r1.copyTo(m.rowRange(0, 2));
      if (shake) {
        cv::Mat r2 = cv::getRotationMatrix2D(cv::Point2f(0.5f * size.width, 0.5f * size.height),
                                             sk.rollDeg, 1.0);
        r2.at<double>(0, 2) += sk.dxPx;
        r2.at<double>(1, 2) += sk.dyPx;
        cv::Mat m2 = cv::Mat::eye(3, 3, CV_64F);
        r2.copyTo(m2.rowRange(0, 2));
        m = m2 * m;
      }
      cv::Mat3f warped;
      cv::warpAffine(img, warped, m.rowRange(0, 2), size, cv::INTER_LINEAR, cv::BORDER_REFLECT);
      img = warped;
    }
  }

  if (L.blurPx > 0.05)
    cv::GaussianBlur(img, img, cv::Size(), L.blurPx);

  // Sensor noise: Poisson-Gaussian, a different stream per shot.
  cv::Mat3f noise(size);
  cv::RNG rng(scene_.seed * 2 + (dressed ? 1 : 0));
  rng.fill(noise, cv::RNG::NORMAL, 0.0, 1.0);
  cv::Mat out(size, CV_8UC3);
  for (int y = 0; y < size.height; ++y) {
    const cv::Vec3f* in = img.ptr<cv::Vec3f>(y);
    const cv::Vec3f* nz = noise.ptr<cv::Vec3f>(y);
    cv::Vec3b* o = out.ptr<cv::Vec3b>(y);
    for (int x = 0; x < size.width; ++x) {
      for (int k = 0; k < 3; ++k) {
        const double v = std::max(0.0f, in[x][k]);
        const double sigma = std::sqrt(L.noiseShot * v + L.noiseRead);
        o[x][k] = cv::saturate_cast<uchar>(255.0 * (v + sigma * nz[x][k]));
      }
    }
  }
  return out;
}

nlohmann::json SceneRenderer::calibration() const {
  // The calibration contract of calib/ (docs/formats.md), with the scene's true pose: the
  // pipeline reads a simulated case exactly as it reads a station's calibration.
  calib::Calibration c;
  c.formSidecar = scene_.formPath;
  c.emptyFrame = "empty.png";
  c.imageSize = scene_.size;
  c.pose = scene_.pose;
  c.iou = 1.0;
  c.landmarks = calib::landmarkPoints(*form_, scene_.pose);
  c.landmarkHeightsCm = form_->landmarks().toMap();
  return nlohmann::json::parse(calib::calibrationToJson(c));
}

nlohmann::json SceneRenderer::truth() const {
  const GarmentSpec& g = scene_.garment;
  nlohmann::json m = nlohmann::json::object();
  for (const auto& n : garmentMeasurementNames(g.type))
    m[n] = round2(g.measurements.at(n));
  std::string subtype;
  for (const auto& [k, v] : g.attributes)
    subtype += (subtype.empty() ? "" : ",") + k + ":" + v;
  const GarmentHeights gh = garmentHeights(g, view_);
  nlohmann::json heights = {{"top", round2(gh.topCm)}, {"hem", round2(gh.hemCm)}};
  if (g.type == "pants")
    heights["crotch"] = round2(gh.crotchCm);
  nlohmann::json formLandmarks = form_->landmarks().toMap();
  formLandmarks["neck_side"] = round2(view_.neckSideCm());
  nlohmann::json arms = nlohmann::json::array();
  for (int side = 0; side < 2; ++side) {
    const auto& a = view_.arm(side);
    if (!a)
      continue;
    arms.push_back(
        {{"side", side == 0 ? "image_left" : "image_right"},
         {"shoulder_tip_px", {round2(a->shoulderTipPx.x()), round2(a->shoulderTipPx.y())}},
         {"axis_origin_px", {round2(a->originPx.x()), round2(a->originPx.y())}},
         {"axis_dir", {a->dir.x(), a->dir.y()}}});
  }
  return {
      {"type", g.type},
      {"subtype", subtype},
      {"attributes", g.attributes},
      {"units", "cm"},
      {"measurements", m},
      {"form",
       {{"path", scene_.formPath},
        {"name", form_->sidecar().name},
        {"landmark_heights_cm", formLandmarks},
        {"measurements", form_->measurements().values()}}},
      {"calibration", calibration()},
      {"garment_heights_cm", heights},
      {"arms", arms},
      {"details", g.toJson()["details"]},
      {"fabric", scene_.fabric.toJson()},
      {"lighting", scene_.lighting.toJson()},
      {"shake", scene_.shake.toJson()},
      {"hard", scene_.hard},
      {"seed", scene_.seed},
      {"model",
       "garment width = reference form width x garment/form circumference (docs/simulator.md)"}};
}

void writeCase(const SceneRenderer& renderer, const std::filesystem::path& caseDir,
               const capture::RigImageOptions& images) {
  images.validate();
  std::filesystem::create_directories(caseDir);
  const auto emptyPath = capture::writeRigFrame(caseDir, "empty", renderer.renderEmpty(), images);
  capture::writeRigFrame(caseDir, "dressed", renderer.renderDressed(), images);
  // The calibration names the bare-form frame it was made from: the file actually written.
  nlohmann::json calibration = renderer.calibration();
  calibration["empty_frame"] = emptyPath.filename().string();
  nlohmann::json truth = renderer.truth();
  truth["calibration"] = calibration;
  drafts::writeJsonFile(caseDir / "truth.json", truth);
  drafts::writeJsonFile(caseDir / "calibration.json", calibration);
  drafts::writeJsonFile(caseDir / "scene.json", renderer.scene().toJson());
}

}  // namespace garmcap::sim
