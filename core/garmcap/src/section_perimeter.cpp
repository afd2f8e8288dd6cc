#include "garmcap/pipeline/section_perimeter.h"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace garmcap::pipeline {

double ellipsePerimeter(double w, double d) {
  const double a = 0.5 * w, b = 0.5 * d;
  return std::numbers::pi * (3.0 * (a + b) - std::sqrt((3.0 * a + b) * (a + 3.0 * b)));
}

double finHullGain(double w, double d, double f) {
  if (f <= 0 || w <= 0 || d <= 0)
    return 0.0;
  const double a = 0.5 * w, b = 0.5 * d;
  // The tangent points from (a + f, 0) lie on the tip's polar line x = a^2 / (a + f).
  const double xt = a * a / (a + f);
  const double yt = b * std::sqrt(std::max(0.0, 1.0 - (xt * xt) / (a * a)));
  const double tangent = std::hypot(a + f - xt, yt);
  // Arc of x = a cos t, y = b sin t over |t| <= acos(a / (a + f)), by the midpoint rule.
  const double tEnd = std::acos(a / (a + f));
  constexpr int kSteps = 64;
  double arc = 0;
  for (int i = 0; i < kSteps; ++i) {
    const double t = (i + 0.5) * tEnd / kSteps;
    arc += std::hypot(a * std::sin(t), b * std::cos(t));
  }
  arc *= 2.0 * tEnd / kSteps;
  return 2.0 * tangent - arc;
}

}  // namespace garmcap::pipeline
