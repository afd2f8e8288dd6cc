#pragma once
// A pattern: the draft (named points, lines, closed regions) a recipe draws for one body, and
// the panels derived from it. All coordinates in cm, x to the right, y DOWN (as on paper and in
// SVG: the neck is above the hem, so it has a smaller y).

#include <Eigen/Core>
#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include "garmcap/drafts/measurements.h"

namespace garmcap::drafts {

using Point2 = Eigen::Vector2d;
using Polyline = std::vector<Point2>;

/// A named construction line or curve of the draft (already flattened to a polyline).
struct DraftLine {
  std::string name;
  Polyline points;
  bool construction = false;  // auxiliary line (drawn grey) vs. a contour of the draft
};

/// A closed polygon of the draft, used by DSW as the cage that encodes panels. Its vertex
/// count and order depend only on the garment type and design parameters, never on the
/// measurements (curves are sampled at a fixed number of points), so that the same region of
/// two drafts of the same type corresponds vertex by vertex.
struct DraftRegion {
  std::string name;  // e.g. "bodice_front"
  Polyline polygon;  // counter-clockwise in y-down coordinates as drawn, first point not repeated
};

struct Dart {
  std::string name;
  Point2 apex;
  Point2 leg1;  // both legs lie on the panel outline
  Point2 leg2;
};

struct Notch {
  std::string name;
  Point2 position;  // on the outline
};

struct Grainline {
  Point2 start;
  Point2 end;
};

struct Panel {
  std::string name;              // e.g. "bodice_front"
  Polyline outline;              // closed (first point not repeated), simple, cm
  std::vector<Dart> darts;
  Grainline grainline;
  std::vector<Notch> notches;
  std::vector<DraftLine> internalLines;
  int cutCount = 1;              // pieces to cut
  bool cutOnFold = false;        // centre line on the fold
  double seamAllowanceCm = 1.0;
  std::vector<std::string> draftRegions;  // which DraftRegion(s) encode this panel in DSW
};

/// An edge of a panel outline: the outline vertices from index `from` to index `to`, walking
/// forward (wrapping around).
struct EdgeRef {
  std::string panel;
  int from = 0;
  int to = 0;
};

/// Two panel edges sewn together.
struct SeamPair {
  std::string name;   // e.g. "side_seam"
  EdgeRef a;
  EdgeRef b;
  double easeCm = 0;  // intended length difference (b longer than a), e.g. sleeve cap ease
};

struct Pattern {
  std::string type;                         // recipe name, e.g. "dress"
  Measurements measurements;                // the body the draft was made for
  std::map<std::string, double> design;     // ease and design parameters actually used
  std::map<std::string, Point2> points;     // named draft points (`bust_side_front`, ...)
  std::vector<DraftLine> lines;
  std::vector<DraftRegion> regions;
  std::vector<Panel> panels;
  std::vector<SeamPair> seams;

  const Panel& panel(const std::string& name) const;  // throws naming the panel
  const DraftRegion& region(const std::string& name) const;
};

}  // namespace garmcap::drafts
