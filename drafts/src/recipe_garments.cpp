// Garment recipes assembled from the blocks: bodice, dress, blouse, sleeve; and the common
// finishing step.
#include <algorithm>
#include <cmath>

#include "recipe_blocks.h"
#include "recipe_list.h"

namespace garmcap::drafts::detail {

void finishPattern(DraftBuilder& b) {
  Pattern& p = b.pattern();
  const double sa = b.design("seam_allowance");
  for (auto& panel : p.panels) {
    panel.seamAllowanceCm = sa;
    if (auto hit = findSelfIntersection(panel.outline)) {
      b.refuse("panel '" + panel.name + "' outline crosses itself (edges " +
               std::to_string(hit->first) + " and " + std::to_string(hit->second) +
               "): the measurements do not fit together");
    }
    if (polygonArea(panel.outline) < 1.0)
      b.refuse("panel '" + panel.name + "' is empty");
  }
  for (const auto& r : p.regions) {
    // A panel's own region (addPanelWithRegion) was just checked as its outline, more strictly.
    const bool checkedAsPanel = std::any_of(p.panels.begin(), p.panels.end(), [&](const Panel& q) {
      return q.name == r.name && q.outline == r.polygon;
    });
    if (!checkedAsPanel && !isSimplePolygon(r.polygon))
      b.refuse("draft region '" + r.name + "' crosses itself");
  }
}

void recipeBodice(DraftBuilder& b) {
  BodiceOptions o;
  o.easeBust = b.design("ease_bust");
  o.easeWaist = b.design("ease_waist");
  o.bustpointToBustpoint = b.measurement("bustpoint_to_bustpoint");
  o.bustpointToNeckSide = b.measurement("bustpoint_to_neck_side");
  const BodiceDraft d = draftBodiceBlock(b, b.measurement("bust_circ"), b.measurement("waist_circ"),
                                         b.measurement("neck_back_to_waist_b"), o);
  addBodicePanels(b, d);
}

}  // namespace garmcap::drafts::detail
