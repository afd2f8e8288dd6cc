#pragma once
// Private helpers of the pattern file writers (export_*.cpp): number and text formatting for
// ASCII formats, bounding boxes, notch directions, the checks every writer makes on a panel.

#include <optional>
#include <string>
#include <vector>

#include "garmcap/drafts/pattern.h"
#include "garmcap/drafts/pattern_export.h"

namespace garmcap::drafts::detail {

/// Fixed-point number with `decimals` digits, never "-0.000".
std::string fixed(double v, int decimals = 4);
/// Printable ASCII only ('_' for anything else): DXF R12 and base-14 PDF fonts read no UTF-8.
std::string asciiText(const std::string& s);
/// DXF block name "<piece>_<size>" with anything but [A-Za-z0-9_-] replaced by '-'.
std::string blockName(const std::string& piece, const std::string& size);

struct Box {
  Point2 min{1e300, 1e300};
  Point2 max{-1e300, -1e300};
  void add(const Point2& p) {
    min = min.cwiseMin(p);
    max = max.cwiseMax(p);
  }
  void add(const Polyline& pl) {
    for (const auto& p : pl)
      add(p);
  }
  bool empty() const { return min.x() > max.x(); }
  double width() const { return max.x() - min.x(); }
  double height() const { return max.y() - min.y(); }
};
Box panelBox(const Panel& p);

/// Unit normal pointing into the panel at outline point `p` (nearest edge), for notch slits.
Point2 inwardNormal(const Polyline& outline, const Point2& p);
/// Index of the outline vertex within 0.2 mm of `p`, or -1.
int nearestVertex(const Polyline& outline, const Point2& p);
/// Where to print a panel's name: its area centroid when that lies inside the outline, else
/// the middle of the widest inside span of the horizontal line through the centroid.
Point2 labelPoint(const Polyline& outline);

/// The panel's cut line (seam_allowance.h), a SeamAllowanceError rethrown as E.
template <class E>
Polyline cutLine(const Panel& p, const Pattern& pattern);
/// "seam allowance 10.0 mm included, hem 30.0 mm, none on fold": what the cut line holds.
std::string allowanceNote(const Panel& p);

/// Every panel's cut line and the side-by-side layout of those cut lines (layoutPanels).
struct CutSheet {
  std::vector<Polyline> cuts;  // one per panel
  Layout layout;
};
template <class E>
CutSheet cutSheet(const Pattern& pattern, double gapCm, double maxRowWidthCm);

/// A notch as the cutter cuts it: a 5 mm slit from the cut line inward, on the sew line's
/// normal through the notch (so that it points at the notch on the sew line).
struct NotchSlit {
  Point2 from;  // on the cut line
  Point2 to;    // 5 mm inside
};
NotchSlit notchSlit(const Polyline& outline, const Polyline& cut, const Point2& notch);

/// The "place on fold" bracket of a piece cut on the fold (foldEdge): a line 2 cm inside the
/// fold over its middle 70 %, legs back to the fold ending in arrowheads on it, and where to
/// write "PLACE ON FOLD" (reading along the fold).
struct FoldMark {
  Point2 foldStart, foldEnd;     // the mirror line
  Polyline bracket;              // open: fold, inside, inside, fold
  std::vector<Polyline> arrows;  // open V at each end of the bracket, tips on the fold
  Point2 label;                  // start of the text
  double labelAngleDeg = 0;      // text direction, degrees in y-down coordinates
};
std::optional<FoldMark> foldMark(const Panel& p, const Pattern& pattern);

/// Throws E (a PatternExportError) naming the panel when its outline has fewer than 3 points
/// or a non-finite coordinate.
template <class E>
void checkPanel(const Panel& p);
/// Throws E when the pattern has no panels or one fails checkPanel.
template <class E>
void checkPattern(const Pattern& p);

}  // namespace garmcap::drafts::detail
