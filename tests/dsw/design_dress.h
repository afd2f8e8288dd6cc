#pragma once
// The source design of the grading experiments (seed §4.6): a one-piece dress designed on the
// size-55 draft and deliberately different from it — front neckline lowered 6 cm at the centre
// front (a scoop that leaves the shoulder seam alone), skirt flared 8 cm per side seam at the
// hem (the flare grows from nothing at the hip line), and the draft's set-in sleeve. The
// committed file tests/data/designs/dress_55.json is this function's output; the test
// DesignDress.CommittedFileIsTheGeneratorOutput regenerates it with GARMCAP_REGENERATE=1.

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>
#include <tuple>

#include "garmcap/drafts/panel_measure.h"
#include "garmcap/drafts/recipes.h"

namespace garmcap::dsw::testing {

inline constexpr double kNecklineDropCm = 6.0;
inline constexpr double kHemFlareCm = 8.0;

inline drafts::Panel& panelNamed(drafts::Pattern& p, const std::string& name) {
  for (auto& panel : p.panels) {
    if (panel.name == name)
      return panel;
  }
  throw std::runtime_error("design: no panel " + name);
}

inline drafts::Pattern designDress(const drafts::Measurements& body55) {
  drafts::Pattern p = drafts::draftGarment("dress", body55);
  // Lowered front neckline: walk the outline from the side neck point to the centre-front neck
  // point (the shorter way) and drop each vertex by drop·s², s the fraction of the way.
  drafts::Panel& front = panelNamed(p, "bodice_front");
  const int n = static_cast<int>(front.outline.size());
  const int snp = *drafts::nearestOutlineVertex(front, p.points.at("neck_side_front"), 0.01);
  const int cf = *drafts::nearestOutlineVertex(front, p.points.at("neck_front_cf"), 0.01);
  const int forward = (cf - snp + n) % n, backward = (snp - cf + n) % n;
  const int steps = std::min(forward, backward);
  const int dir = forward <= backward ? 1 : -1;
  for (int k = 1; k <= steps; ++k) {
    const double s = static_cast<double>(k) / steps;
    front.outline[static_cast<std::size_t>((snp + dir * k + n) % n)].y() += kNecklineDropCm * s * s;
  }
  // Flared skirt: below the hip line every point moves away from the centre line by
  // flare · (depth below hip / hip-to-hem) · (distance from centre / half width at hip).
  const double yHip = p.points.at("level_hip").y();
  for (const auto& [name, centre, side] :
       {std::tuple<std::string, std::string, std::string>{"skirt_back", "skirt_waist_cb",
                                                          "skirt_hip_side_back"},
        {"skirt_front", "skirt_waist_cf", "skirt_hip_side_front"}}) {
    drafts::Panel& skirt = panelNamed(p, name);
    const double xc = p.points.at(centre).x();
    const double xs = p.points.at(side).x();
    double yHem = yHip;
    for (const auto& v : skirt.outline)
      yHem = std::max(yHem, v.y());
    auto flare = [&](drafts::Point2& q) {
      if (q.y() <= yHip)
        return;
      const double depth = (q.y() - yHip) / (yHem - yHip);  // 0 at the hip line, 1 at the hem
      const double across = (q.x() - xc) / (xs - xc);       // 0 at the centre line, 1 at the side
      q.x() += kHemFlareCm * depth * across * (xs > xc ? 1.0 : -1.0);
    };
    for (auto& v : skirt.outline)
      flare(v);
    for (auto& d : skirt.darts) {
      flare(d.apex);
      flare(d.leg1);
      flare(d.leg2);
    }
    flare(skirt.grainline.start);
    flare(skirt.grainline.end);
    for (auto& nt : skirt.notches)
      flare(nt.position);
  }
  return p;
}

}  // namespace garmcap::dsw::testing
