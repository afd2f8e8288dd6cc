#include "garmcap/sim/fabric.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
#include <stdexcept>

#include "garmcap/drafts/file_io.h"

namespace garmcap::sim {

namespace {

// Anti-aliased step: the fraction of a pixel of width `w` (same units as x) centred at x that
// lies above `edge`.
double coverage(double x, double edge, double w) {
  const double t = (x - edge) / std::max(w, 1e-6) + 0.5;
  return std::clamp(t, 0.0, 1.0);
}

// Fraction of a band [0, duty*period) within one period covered by a pixel at phase x.
double bandCoverage(double x, double period, double duty, double w) {
  const double p = x / period - std::floor(x / period);  // 0..1
  const double wp = w / period;
  // The band is [0, duty); with its repeats at -1 and +1 the pixel sees at most two edges.
  const double in = coverage(p, 0.0, wp) - coverage(p, duty, wp) + coverage(p, 1.0, wp) -
                    coverage(p, 1.0 + duty, wp) + coverage(p, -1.0, wp) -
                    coverage(p, duty - 1.0, wp);
  return std::clamp(in, 0.0, 1.0);
}

std::uint64_t mix(std::uint64_t x) {  // splitmix64 finaliser: a cheap deterministic hash
  x += 0x9e3779b97f4a7c15ULL;
  x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ULL;
  x = (x ^ (x >> 27)) * 0x94d049bb133111ebULL;
  return x ^ (x >> 31);
}

double unit(std::uint64_t h) {
  return static_cast<double>(h >> 11) * (1.0 / 9007199254740992.0);
}

cv::Vec3f lerp(const cv::Vec3f& a, const cv::Vec3f& b, double t) {
  return a * static_cast<float>(1.0 - t) + b * static_cast<float>(t);
}

cv::Vec3f vec3(const nlohmann::json& j, const std::string& key, const std::string& what) {
  const auto& v = drafts::requireField(j, key, what);
  if (!v.is_array() || v.size() != 3) {
    throw drafts::ParseError(what + ": field '" + key + "' must be an array of 3 numbers (BGR)");
  }
  cv::Vec3f out;
  for (int i = 0; i < 3; ++i) {
    if (!v[static_cast<std::size_t>(i)].is_number()) {
      throw drafts::ParseError(what + ": field '" + key + "' must hold numbers");
    }
    out[i] = v[static_cast<std::size_t>(i)].get<float>();
    if (out[i] < 0.f || out[i] > 1.f) {
      throw drafts::ParseError(what + ": field '" + key + "' values must be in [0, 1]");
    }
  }
  return out;
}

}  // namespace

nlohmann::json Fabric::toJson() const {
  return {{"kind", fabricKindName(kind)},
          {"base_bgr", {base[0], base[1], base[2]}},
          {"accent_bgr", {accent[0], accent[1], accent[2]}},
          {"period_cm", periodCm},
          {"duty_cycle", dutyCycle},
          {"angle_deg", angleDeg},
          {"weave_contrast", weaveContrast},
          {"fold_depth", foldDepth},
          {"seed", seed}};
}

Fabric Fabric::fromJson(const nlohmann::json& j, const std::string& what) {
  Fabric f;
  try {
    f.kind = fabricKindFromName(drafts::requireString(j, "kind", what));
  } catch (const std::invalid_argument& e) {
    throw drafts::ParseError(what + ": field 'kind': " + e.what());
  }
  f.base = vec3(j, "base_bgr", what);
  f.accent = vec3(j, "accent_bgr", what);
  f.periodCm = drafts::requireNumber(j, "period_cm", what);
  f.dutyCycle = drafts::requireNumber(j, "duty_cycle", what);
  f.angleDeg = drafts::requireNumber(j, "angle_deg", what);
  f.weaveContrast = drafts::requireNumber(j, "weave_contrast", what);
  f.foldDepth = drafts::requireNumber(j, "fold_depth", what);
  const auto& s = drafts::requireField(j, "seed", what);
  if (!s.is_number_unsigned()) {
    throw drafts::ParseError(what + ": field 'seed' must be a non-negative integer");
  }
  f.seed = s.get<std::uint64_t>();
  if (!(f.periodCm > 0.1 && f.periodCm < 100)) {
    throw drafts::ParseError(what + ": field 'period_cm' must be in (0.1, 100) cm");
  }
  if (!(f.dutyCycle > 0 && f.dutyCycle < 1)) {
    throw drafts::ParseError(what + ": field 'duty_cycle' must be in (0, 1)");
  }
  return f;
}

cv::Vec3f fabricColour(const Fabric& fabric, double uCm, double vCm, double footprintCm) {
  const double a = fabric.angleDeg * std::numbers::pi / 180.0;
  const double along = uCm * std::cos(a) + vCm * std::sin(a);    // across the stripes
  const double across = -uCm * std::sin(a) + vCm * std::cos(a);  // along the stripes
  cv::Vec3f c = fabric.base;
  switch (fabric.kind) {
    case FabricKind::kSolid:
      break;
    case FabricKind::kStripes: {
      const double t = bandCoverage(along, fabric.periodCm, fabric.dutyCycle, footprintCm);
      c = lerp(fabric.base, fabric.accent, t);
      break;
    }
    case FabricKind::kChecks: {
      // Gingham: where one set of bands crosses the other the accent is doubled.
      const double t1 = bandCoverage(along, fabric.periodCm, fabric.dutyCycle, footprintCm);
      const double t2 = bandCoverage(across, fabric.periodCm, fabric.dutyCycle, footprintCm);
      c = lerp(fabric.base, fabric.accent, 0.5 * (t1 + t2));
      break;
    }
    case FabricKind::kPrint: {
      // One round motif per cell, jittered, with a size and a shade of the accent per cell.
      const double cu = uCm / fabric.periodCm;
      const double cv = vCm / fabric.periodCm;
      const auto iu = static_cast<std::int64_t>(std::floor(cu));
      const auto iv = static_cast<std::int64_t>(std::floor(cv));
      double best = 0;
      cv::Vec3f motif = fabric.accent;
      for (std::int64_t du = -1; du <= 1; ++du) {
        for (std::int64_t dv = -1; dv <= 1; ++dv) {
          const std::uint64_t h =
              mix(fabric.seed ^ mix(static_cast<std::uint64_t>(iu + du) * 73856093ULL ^
                                    static_cast<std::uint64_t>(iv + dv) * 19349663ULL));
          const double ox = static_cast<double>(iu + du) + 0.2 + 0.6 * unit(h);
          const double oy = static_cast<double>(iv + dv) + 0.2 + 0.6 * unit(mix(h));
          const double r = 0.12 + 0.18 * unit(mix(mix(h)));
          const double d = std::hypot(cu - ox, cv - oy) * fabric.periodCm;
          const double t = coverage(r * fabric.periodCm, d, footprintCm);
          if (t > best) {
            best = t;
            const double shade = 0.75 + 0.5 * unit(mix(h ^ 0x5bd1e995ULL));
            motif = fabric.accent * static_cast<float>(std::min(
                                        shade, 1.0 / std::max({fabric.accent[0], fabric.accent[1],
                                                               fabric.accent[2], 1e-3f})));
          }
        }
      }
      c = lerp(fabric.base, motif, best);
      break;
    }
  }
  // Weave: a fine twill-like ripple, below the pixel size at low resolutions (then it averages).
  if (fabric.weaveContrast > 0 && footprintCm < 0.15) {
    const double w = std::sin((uCm + vCm) * 2 * std::numbers::pi / 0.12) *
                     std::sin((uCm - vCm) * 2 * std::numbers::pi / 0.17);
    c *= static_cast<float>(1.0 + fabric.weaveContrast * w * (1.0 - footprintCm / 0.15));
  }
  return c;
}

Fabric randomFabric(std::mt19937_64& rng, bool hard, const cv::Vec3f& formColour) {
  std::uniform_real_distribution<double> u01(0.0, 1.0);
  auto pick = [&](double lo, double hi) { return lo + (hi - lo) * u01(rng); };
  Fabric f;
  f.seed = rng();
  // Everyday garment colours (BGR reflectance): navy, red, black, white, denim, mustard, ...
  static const std::array<cv::Vec3f, 10> kPalette = {
      cv::Vec3f{0.35f, 0.12f, 0.08f}, cv::Vec3f{0.12f, 0.10f, 0.62f},
      cv::Vec3f{0.07f, 0.07f, 0.08f}, cv::Vec3f{0.85f, 0.86f, 0.86f},
      cv::Vec3f{0.55f, 0.38f, 0.25f}, cv::Vec3f{0.15f, 0.55f, 0.75f},
      cv::Vec3f{0.45f, 0.20f, 0.45f}, cv::Vec3f{0.50f, 0.50f, 0.52f},
      cv::Vec3f{0.20f, 0.30f, 0.70f}, cv::Vec3f{0.60f, 0.45f, 0.15f}};
  const double hardPick = u01(rng);
  if (hard && hardPick < 0.5) {
    // Close to the form: the base mask cannot separate it by colour.
    const float d = static_cast<float>(pick(-0.06, 0.06));
    f.base = formColour + cv::Vec3f{d, d * 0.5f, -d};
  } else if (hard) {
    // Dark olive / bottle green: close to a shadowed green screen.
    f.base = cv::Vec3f{static_cast<float>(pick(0.05, 0.15)), static_cast<float>(pick(0.22, 0.35)),
                       static_cast<float>(pick(0.08, 0.2))};
  } else {
    f.base = kPalette[static_cast<std::size_t>(rng() % kPalette.size())];
  }
  for (int i = 0; i < 3; ++i)
    f.base[i] = std::clamp(f.base[i], 0.02f, 0.95f);
  f.accent = kPalette[static_cast<std::size_t>(rng() % kPalette.size())];
  if (cv::norm(f.accent - f.base) < 0.3)
    f.accent = cv::Vec3f{0.9f, 0.9f, 0.88f};
  const double k = u01(rng);
  f.kind = k < 0.4 ? FabricKind::kSolid
                   : (k < 0.65 ? FabricKind::kStripes
                               : (k < 0.85 ? FabricKind::kChecks : FabricKind::kPrint));
  f.periodCm = f.kind == FabricKind::kPrint ? pick(2.0, 5.0) : pick(1.0, 4.0);
  f.dutyCycle = pick(0.25, 0.5);
  f.angleDeg = f.kind == FabricKind::kStripes ? (u01(rng) < 0.5 ? 0.0 : 90.0) : 0.0;
  f.weaveContrast = pick(0.02, 0.06);
  f.foldDepth = pick(0.06, 0.16);
  return f;
}

}  // namespace garmcap::sim
