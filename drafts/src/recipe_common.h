#pragma once
// Private helpers shared by the recipes: a builder that records named points and lines into the
// Pattern as the draft is drawn, fixed-count curve sampling (DSW needs body-independent vertex
// counts), dart insertion along seam lines, and panel assembly with seam references.

#include <map>
#include <optional>
#include <string>
#include <vector>

#include "garmcap/drafts/geometry.h"
#include "garmcap/drafts/pattern.h"
#include "garmcap/drafts/recipes.h"

namespace garmcap::drafts::detail {

// Fixed vertex counts of flattened curves (never adaptive: see DraftRegion).
inline constexpr int kNeckCount = 13;
inline constexpr int kArmholeCount = 25;
inline constexpr int kCapCount = 25;
inline constexpr int kSideCurveCount = 13;
inline constexpr int kWaistPieceCount = 7;
inline constexpr int kHemCount = 13;
inline constexpr int kCrotchCount = 17;
// Fine sampling of the waist and hip curves that darts are later opened in (skirt, pants).
inline constexpr int kFineCurveCount = 400;

/// Smooth curve through nodes, sampled at exactly `count` points equally spaced by arc length.
Polyline curve(const std::vector<CurveNode>& nodes, int count);

/// Records the draft into a Pattern: named points, contour and construction lines; `refuse`
/// throws DraftError prefixed with the recipe name.
class DraftBuilder {
 public:
  DraftBuilder(Pattern& pattern, std::string recipe) : p_(pattern), recipe_(std::move(recipe)) {}
  const Point2& point(const std::string& name, const Point2& p);
  const Point2& at(const std::string& name) const;
  void contour(const std::string& name, const Polyline& pl);
  void construction(const std::string& name, const Polyline& pl);
  void construction(const std::string& name, const Point2& a, const Point2& b) {
    construction(name, Polyline{a, b});
  }
  [[noreturn]] void refuse(const std::string& message) const;
  void require(bool ok, const std::string& message) const {
    if (!ok)
      refuse(message);
  }
  /// Design parameter value (already merged with defaults by draftGarment).
  double design(const std::string& name) const;
  double measurement(const std::string& name) const;
  Pattern& pattern() { return p_; }
  const std::string& recipe() const { return recipe_; }

 private:
  Pattern& p_;
  std::string recipe_;
};

/// A dart to open in a seam line: centre at arc length `centreS` from the line's start, width
/// measured along the line, apex at height `apexY` (vertical darts) on the perpendicular
/// bisector of the legs (so that both legs are equal: the dart is trued).
struct DartSpec {
  std::string name;
  double centreS = 0;
  double width = 0;
  double apexY = 0;
};

struct LineWithDarts {
  Polyline points;          // start ... leg1 apex leg2 ... end (each piece at a fixed count)
  std::vector<Dart> darts;  // in order along the line
  double sewnLength = 0;    // length without the dart openings
};

/// Opens the darts (sorted by centreS, non-overlapping) in the polyline `line` (finely
/// sampled). Each piece between darts is resampled at `pieceCount` points. Returns nullopt
/// when the darts overlap each other or the ends.
std::optional<LineWithDarts> openDarts(const Polyline& line, std::vector<DartSpec> darts,
                                       int pieceCount = kWaistPieceCount);

/// Appends points skipping a point equal to the last one.
void append(Polyline& out, const Polyline& pts);
void append(Polyline& out, const Point2& p);

/// Makes a panel from an outline in any orientation: orders it counter-clockwise as seen on
/// paper (signedArea < 0 in y-down coordinates), keeping vertex 0.
Panel makePanel(const std::string& name, Polyline outline);

/// Index of the outline vertex equal to `p` (within 1e-6 cm); throws std::logic_error (a bug
/// in a recipe) when absent.
int vertexIndex(const Panel& panel, const Point2& p);
/// Edge of the panel between the vertices at `p1` and `p2`: the forward walk (p1 -> p2 or
/// p2 -> p1) with the shorter arc length.
EdgeRef shortEdge(const Panel& panel, const Point2& p1, const Point2& p2);
/// Adds a seam pair between the edge a1-a2 of panel `a` and b1-b2 of panel `b`, where a1 sews
/// to b1 and a2 to b2. The stored edges follow the file convention: a.from meets b.to and a.to
/// meets b.from (both outlines counter-clockwise, right sides together). `ease` = intended
/// length of b minus length of a. `sameDirection`: the two outlines run the same way along the
/// seam (a set-in sleeve cap against its armhole: the sleeve is a tube turned into the
/// armhole), so a.from meets b.from instead.
void addSeam(Pattern& pattern, const std::string& name, const std::string& a, const Point2& a1,
             const Point2& a2, const std::string& b, const Point2& b1, const Point2& b2,
             double ease = 0, bool sameDirection = false);
/// The outline points of an edge (forward walk, inclusive).
Polyline edgePoints(const Panel& panel, const EdgeRef& e);

/// Adds the panel's own outline as a draft region of the same name and links them.
void addPanelWithRegion(Pattern& pattern, Panel panel);

/// Grainline from a to b, shortened to the middle 80 %.
Grainline grainline(const Point2& a, const Point2& b);

/// Point on the outline edge at arc length s from its start (for notches).
Point2 pointAlong(const Polyline& pl, double s);

/// Gap between the two notches of a double notch (pattern makers use 0.6 to 1.3 cm).
constexpr double kDoubleNotchGapCm = 1.0;
/// A double notch: the back of an armhole and of its sleeve cap carry two notches, the front
/// one, so that a sleeve cannot be set in back to front. `name` at arc length `s` of `pl` and
/// `name`_2 kDoubleNotchGapCm nearer the line's start.
void addDoubleNotch(Panel& panel, const std::string& name, const Polyline& pl, double s);

/// Matching notches `name` on both pieces of the seam pair `seamName` (already added): at the
/// same sewn distance (dart openings left out: their legs are sewn together) from the end
/// where the two edges meet, `fraction` of the shorter of the two sewn lengths.
void addSeamNotches(Pattern& pattern, const std::string& seamName, const std::string& name,
                    double fraction);

}  // namespace garmcap::drafts::detail
