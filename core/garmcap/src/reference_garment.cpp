#include "garmcap/pipeline/reference_garment.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <optional>
#include <stdexcept>
#include <utility>
#include <vector>

#include "garmcap/drafts/recipes.h"

namespace garmcap::pipeline {
namespace {

// No garment is shown tighter than this over the form (cm of girth): even a fitted one stands
// a little off it, and a negative ease would draw it inside the form's outline.
constexpr double kLeastEaseCm = 2.0;

double designDefault(const std::string& recipe, const std::string& name) {
  for (const auto& p : drafts::garmentType(recipe).design)
    if (p.name == name)
      return p.defaultValue;
  throw std::invalid_argument("recipe '" + recipe + "' has no design parameter '" + name + "'");
}

const std::string& attribute(const std::map<std::string, std::string>& attributes,
                             const std::string& type, const std::string& name) {
  const auto it = attributes.find(name);
  if (it == attributes.end())
    throw std::invalid_argument("reference " + type + " needs the attribute '" + name + "'");
  return it->second;
}

// Offset (px) of the outline of a garment `easeCm` looser than the form's section under it.
double standoffPx(double easeCm, const FormView& view) {
  return std::max(easeCm, kLeastEaseCm) / (2 * std::numbers::pi) * view.pose().pxPerCm;
}

double lerp(double a, double b, double t) {
  return a + (b - a) * std::clamp(t, 0.0, 1.0);
}

// Ease at form height h on the torso: linear between the heights the recipes give it at (bust,
// waist, hip), constant beyond the outer ones.
double torsoEase(const ReferenceGarment& g, const FormView& view, double h) {
  std::vector<std::pair<double, double>> knots;  // (height, ease), falling height
  if (g.type == "top" || g.type == "dress")
    knots.emplace_back(view.bustCm(), g.easeBustCm);
  knots.emplace_back(view.waistCm(), g.easeWaistCm);
  knots.emplace_back(view.hipCm(), g.easeHipCm);
  if (h >= knots.front().first)
    return knots.front().second;
  for (std::size_t i = 1; i < knots.size(); ++i)
    if (h >= knots[i].first)
      return lerp(knots[i].second, knots[i - 1].second,
                  (h - knots[i].first) / (knots[i - 1].first - knots[i].first));
  return knots.back().second;
}

struct Span {
  double left = 0, right = 0;
};

void fillSpan(cv::Mat1b& mask, int row, Span s) {
  if (row < 0 || row >= mask.rows)
    return;
  const int x0 = std::max(0, static_cast<int>(std::ceil(s.left)));
  const int x1 = std::min(mask.cols - 1, static_cast<int>(std::floor(s.right)));
  if (x1 >= x0)
    mask.row(row).colRange(x0, x1 + 1).setTo(255);
}

Span offsetSection(const calib::RowSection& sec, double offPx) {
  return {sec.leftPx - offPx, sec.rightPx + offPx};
}

// The body of the garment row by row, from the armpit (tops, dresses) or the waistband down to
// the hem (pants: to the crotch). Returns the first row drawn and its span (the armpit's, for
// the shoulders above it).
std::optional<std::pair<int, Span>> drawBody(const ReferenceGarment& g, const FormView& view,
                                             cv::Mat1b& mask) {
  const bool upper = g.type == "top" || g.type == "dress";
  const bool pants = g.type == "pants";
  const auto hipSec = view.torsoAtHeight(view.hipCm());
  if (!hipSec)
    throw std::invalid_argument("the form has no torso section at the hip");
  const double bottomCm = pants ? view.crotchCm().value() : g.hemCm;
  const int first =
      std::max(0, static_cast<int>(std::ceil(view.rowOfHeight(upper ? view.armpitCm() : g.topCm))));
  const int last =
      std::min(mask.rows - 1, static_cast<int>(std::floor(view.rowOfHeight(bottomCm))));
  std::optional<std::pair<int, Span>> top;
  for (int y = first; y <= last; ++y) {
    const double h = view.heightOfRow(y);
    const auto sec = view.torsoAtRow(y);
    Span s;
    if (h >= view.hipCm() || pants) {
      // On the body (pants follow the seat down to the crotch).
      if (!sec)
        continue;
      s = offsetSection(*sec, standoffPx(torsoEase(g, view, h), view));
    } else {
      // Below the hip the garment hangs from the hip's outline, widening to its hem's ease.
      const double ease =
          lerp(g.easeHipCm, g.easeHemCm, (view.hipCm() - h) / (view.hipCm() - g.hemCm));
      s = offsetSection(*hipSec, standoffPx(ease, view));
      // Whatever of the form it hangs over (thighs wider than the hip, legs) stays inside it.
      const double least = standoffPx(kLeastEaseCm, view);
      if (sec)
        s = {std::min(s.left, sec->leftPx - least), std::max(s.right, sec->rightPx + least)};
      for (int side = 0; side < 2; ++side)
        if (const auto leg = view.legAtRow(y, side))
          s = {std::min(s.left, leg->leftPx - least), std::max(s.right, leg->rightPx + least)};
    }
    fillSpan(mask, y, s);
    if (!top)
      top.emplace(y, s);
  }
  return top;
}

// Image x beyond which (away from the body) the form is the arm at this row: the armhole seam,
// a straight line from the shoulder tip down to the armpit.
double armholeX(const FormView& view, int side, int armpitRow, const Span& armpit, int row) {
  const double armpitX = side == 0 ? armpit.left : armpit.right;
  const auto& arm = view.arm(side);
  if (!arm || row >= armpitRow)
    return armpitX;
  const Eigen::Vector2d tip = arm->shoulderTipPx;
  if (row <= tip.y() || armpitRow <= tip.y())
    return tip.x();
  return lerp(tip.x(), armpitX, (row - tip.y()) / (armpitRow - tip.y()));
}

bool onArmSide(int side, double x, double armhole) {
  return side == 0 ? x < armhole : x > armhole;
}

// Shoulders: the form above the armpit, inside the armholes and below the neckline (a curve
// from the side necks down to the centre-front depth).
void drawShoulders(const ReferenceGarment& g, const FormView& view, int armpitRow,
                   const Span& armpit, cv::Mat1b& mask) {
  const double neckRow = view.rowOfHeight(view.neckSideCm());
  const double halfNeck = view.neckHalfWidthPx();
  const double depthPx = g.neckDepthCm * view.pose().pxPerCm;
  const double axis = view.axisXPx();
  for (int y = std::max(0, static_cast<int>(std::ceil(neckRow))); y < armpitRow && y < mask.rows;
       ++y) {
    const float* form = view.coverage().ptr<float>(y);
    std::uint8_t* out = mask.ptr<std::uint8_t>(y);
    const double left = armholeX(view, 0, armpitRow, armpit, y);
    const double right = armholeX(view, 1, armpitRow, armpit, y);
    for (int x = std::max(0, static_cast<int>(std::ceil(left)));
         x <= std::min(mask.cols - 1, static_cast<int>(std::floor(right))); ++x) {
      if (form[x] < 0.5f)
        continue;
      const double u = std::abs(x - axis) / halfNeck;
      if (u < 1 && y < neckRow + depthPx * (1 - u * u))
        continue;  // the neckline
      out[x] = 255;
    }
  }
}

// A sleeve: the arm from the armhole seam down to the sleeve's end, as wide as the arm plus its
// ease (the upper arm's, tapering to the wrist's on a long sleeve).
void drawSleeve(const ReferenceGarment& g, const FormView& view, int side, int armpitRow,
                const Span& armpit, cv::Mat1b& mask) {
  const auto& arm = view.arm(side);
  if (!arm || g.sleeveCm <= 0)
    return;
  const double endPx = g.sleeveCm * view.pose().pxPerCm;
  auto ease = [&](double t) {
    return lerp(g.easeSleeveTopCm, g.easeSleeveWristCm, t / std::max(1.0, arm->tWristPx));
  };
  const Eigen::Vector2d across(arm->dir.y(), -arm->dir.x());  // the direction d() measures
  double x0 = 1e18, x1 = -1e18, y0 = 1e18, y1 = -1e18;
  for (double t = 0; t <= endPx + 1; t += 2) {
    const Eigen::Vector2d c = arm->originPx + t * arm->dir + arm->centreAt(t) * across;
    const double r = arm->halfWidthAt(t) + standoffPx(ease(t), view) + 2;
    x0 = std::min(x0, c.x() - r);
    x1 = std::max(x1, c.x() + r);
    y0 = std::min(y0, c.y() - r);
    y1 = std::max(y1, c.y() + r);
  }
  for (int y = std::max(0, static_cast<int>(y0)); y <= std::min<double>(mask.rows - 1, y1); ++y) {
    std::uint8_t* out = mask.ptr<std::uint8_t>(y);
    const double armhole = armholeX(view, side, armpitRow, armpit, y);
    for (int x = std::max(0, static_cast<int>(x0)); x <= std::min<double>(mask.cols - 1, x1); ++x) {
      if (!onArmSide(side, x, armhole))
        continue;
      const Eigen::Vector2d p(x, y);
      const double t = arm->t(p);
      if (t < 0 || t > endPx)
        continue;
      const double d = arm->d(p) - arm->centreAt(t);
      if (std::abs(d) <= arm->halfWidthAt(t) + standoffPx(ease(t), view))
        out[x] = 255;
    }
  }
}

// Pants legs: each leg of the form from the crotch to the hem, the seat's ease at the crotch
// narrowing to the leg opening at the hem; a leg does not cross the body's centre line.
void drawLegs(const ReferenceGarment& g, const FormView& view, cv::Mat1b& mask) {
  const double crotch = view.crotchCm().value();
  const int first = std::max(0, static_cast<int>(std::ceil(view.rowOfHeight(crotch))));
  const int last = std::min(mask.rows - 1, static_cast<int>(std::floor(view.rowOfHeight(g.hemCm))));
  const double axis = view.axisXPx();
  for (int side = 0; side < 2; ++side) {
    // The leg's girth at the hem (the lowest section the view has, if the hem is below it).
    std::optional<calib::RowSection> hemSec;
    for (int y = first; y <= last; ++y)
      if (const auto s = view.legAtRow(y, side))
        hemSec = s;
    if (!hemSec)
      throw std::invalid_argument("the form has no leg below the crotch");
    const double hemEase = std::max(g.legOpeningCircCm - hemSec->circCm, kLeastEaseCm);
    std::optional<calib::RowSection> sec;
    for (int y = first; y <= last; ++y) {
      if (const auto s = view.legAtRow(y, side))
        sec = s;  // below the form's last section the leg hangs straight
      if (!sec)
        continue;
      const double h = view.heightOfRow(y);
      const double ease = lerp(g.easeHipCm, hemEase, (crotch - h) / (crotch - g.hemCm));
      Span s = offsetSection(*sec, standoffPx(ease, view));
      if (side == 0)
        s.right = std::min(s.right, axis);
      else
        s.left = std::max(s.left, axis);
      fillSpan(mask, y, s);
    }
  }
}

}  // namespace

ReferenceGarment referenceGarment(const std::string& type,
                                  const std::map<std::string, std::string>& attributes,
                                  double lengthFactor, const drafts::Measurements& body,
                                  const FormView& view) {
  if (type != "top" && type != "dress" && type != "skirt" && type != "pants")
    throw std::invalid_argument("no reference garment of type '" + type + "'");
  const std::string recipe =
      type == "top"     ? "blouse"
      : type == "pants" ? "pants"
      : type == "dress"
          ? "dress"
          : (attribute(attributes, type, "skirt") == "a_line" ? "skirt_a" : "skirt_h");
  ReferenceGarment g;
  g.type = type;
  g.attributes = attributes;
  const double floorCm = view.form().minYCm();
  if (type == "top" || type == "dress")
    g.easeBustCm = designDefault(recipe, "ease_bust");
  g.easeWaistCm = designDefault(recipe, "ease_waist");
  g.easeHipCm = designDefault(recipe, "ease_hip");
  g.easeHemCm = g.easeHipCm;
  g.topCm = type == "skirt" || type == "pants" ? view.waistCm() : view.neckSideCm();
  if (type == "skirt" || type == "dress") {
    const double length =
        std::clamp(designDefault(recipe, "skirt_length") * lengthFactor,
                   view.waistCm() - view.hipCm() + 8, view.waistCm() - floorCm - 10);
    g.hemCm = view.waistCm() - length;
    if (attribute(attributes, type, "skirt") == "a_line") {
      // An A-line's side seams leave the hip at a constant angle: the hem's extra girth (four
      // side-seam edges of hem_flare at the recipe's length) grows with the length below the
      // hip.
      const double depth =
          designDefault("skirt_a", "skirt_length") - (view.waistCm() - view.hipCm());
      g.easeHemCm = g.easeHipCm + 4 * designDefault("skirt_a", "hem_flare") *
                                      (view.hipCm() - g.hemCm) / std::max(1.0, depth);
    }
  }
  if (type == "top") {
    // A top ends above the crotch (below it, it is a dress).
    const double below = designDefault(recipe, "blouse_length") * lengthFactor;
    const double lowest = std::max(view.hipCm() - 12, view.crotchCm().value_or(-1e9) + 3);
    g.hemCm = std::clamp(view.waistCm() - below, lowest, view.waistCm() - 4);
  }
  if (type == "top" || type == "dress") {
    // The bodice block's front neck: about a sixth of the neck's girth deep (the neck's half
    // width as the view sees it, in cm) plus a little.
    g.neckDepthCm = view.neckHalfWidthPx() / view.pose().pxPerCm + 2;
    const std::string& sleeve = attribute(attributes, type, "sleeve");
    const double arm = body.get("arm_shoulder_tip_to_wrist");
    double length = sleeve == "none"    ? 0.0
                    : sleeve == "short" ? 0.3 * arm
                                        : std::min(1.0, 0.9 + 0.1 * lengthFactor) * arm;
    // No longer than the form's arm as this view sees it: the chart's arm can be longer than
    // the scanned form's.
    for (int side = 0; side < 2 && length > 0; ++side)
      if (const auto& a = view.arm(side))
        length = std::min(length, a->tWristPx / view.pose().pxPerCm + 5.0);
    g.sleeveCm = length;
    // A sleeve is as loose on the arm as the bodice on the bust, in proportion to the girths;
    // a full-length one closes to the recipe's wrist ease.
    // Girths as the view sees them: the upper arm's taken round, a fifth of the way to the
    // wrist.
    double armGirth = 0;
    for (int side = 0; side < 2 && armGirth == 0; ++side)
      if (const auto& a = view.arm(side))
        armGirth = std::numbers::pi * 2 * a->halfWidthAt(0.2 * a->tWristPx) / view.pose().pxPerCm;
    const auto bustSec = view.torsoAtHeight(view.bustCm());
    const double bustGirth = bustSec ? bustSec->circCm : body.get("bust_circ");
    g.easeSleeveTopCm = g.easeBustCm * armGirth / bustGirth;
    g.easeSleeveWristCm =
        sleeve == "long" ? designDefault(recipe, "ease_wrist") : g.easeSleeveTopCm;
  }
  if (type == "pants") {
    const double crotch = view.crotchCm().value_or(view.hipCm() - 10);
    const double outseam = designDefault(recipe, "pants_length") *
                           body.get("leg_waist_side_to_floor") * std::min(1.0, lengthFactor);
    g.hemCm = std::clamp(view.waistCm() - outseam, floorCm + 6, crotch - 20);
    // Front and back leg hem widths (the back's 2 cm wider) make the leg opening.
    g.legOpeningCircCm = 2 * designDefault(recipe, "hem_width") + 2;
  }
  return g;
}

cv::Mat1b drawReferenceGarment(const ReferenceGarment& g, const FormView& view) {
  if (g.type == "pants" && !view.crotchCm())
    throw std::invalid_argument("the form has no legs for pants");
  cv::Mat1b mask(view.size(), std::uint8_t{0});
  const auto body = drawBody(g, view, mask);
  if (g.type == "top" || g.type == "dress") {
    if (!body)
      throw std::invalid_argument("the form has no torso section below the armpit");
    const auto& [armpitRow, armpit] = *body;
    drawShoulders(g, view, armpitRow, armpit, mask);
    for (int side = 0; side < 2; ++side)
      drawSleeve(g, view, side, armpitRow, armpit, mask);
  }
  if (g.type == "pants")
    drawLegs(g, view, mask);
  if (cv::countNonZero(mask) == 0)
    throw std::invalid_argument("the garment covers nothing of this view");
  return mask;
}

}  // namespace garmcap::pipeline
