#pragma once
// A marker: every piece to cut for one size or a size run laid on a fabric width, grain along
// the fabric's length, nested by libnest2d (Debian's libnest2d-dev). Files out: SVG (mm), PDF
// (one page the size of the marker, for a plotter), DXF R12 (one layer per size).

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "garmcap/drafts/pattern_export.h"

namespace garmcap::drafts {

class MarkerError : public PatternExportError {
 public:
  using PatternExportError::PatternExportError;
};

/// A marker asked to lay more pieces than MarkerOptions::maxPieces; the message names the count
/// and the limit.
class MarkerLimitError : public MarkerError {
 public:
  using MarkerError::MarkerError;
};

/// Pieces one marker lays at most unless told otherwise (MarkerOptions::maxPieces, `garmcap
/// marker --max-pieces`, the station's `[marker] max_pieces`). libnest2d's time grows faster
/// than the piece count (a dress in five sizes, 40 pieces: about 4 s on the station); 60 holds
/// seven sizes of a dress (8 pieces each) or fifteen of trousers (4 each).
inline constexpr int kDefaultMarkerMaxPieces = 60;

struct MarkerOptions {
  double fabricWidthCm = 150.0;             // usable width between the selvedges
  double gapCm = 0.2;                       // least distance between two pieces
  int maxPieces = kDefaultMarkerMaxPieces;  // pieces laid at most (cut counts and sizes included)
};

/// One piece as laid: its cut line in marker cm (x along the fabric's length from the marker's
/// start, y across the width from one selvedge, y down as on paper).
struct MarkerPiece {
  std::string panel;
  std::string size;
  bool mirrored = false;  // the second of a "cut 2" pair (the pair's other half)
  bool unfolded = false;  // a cut-on-fold piece opened out about its fold
  bool turned = false;    // turned 180 degrees by the nester (grain kept, direction reversed)
  Polyline cutLine;
  Point2 grainStart, grainEnd;
  double areaCm2 = 0;
};

struct Marker {
  double widthCm = 0;
  double lengthCm = 0;      // from x = 0 to the far end of the last piece
  double pieceAreaCm2 = 0;  // sum of the pieces' cut-line areas
  double efficiency = 0;    // pieceAreaCm2 / (lengthCm * widthCm)
  std::vector<MarkerPiece> pieces;
};

/// A pattern of one size with its size label.
struct SizedPattern {
  std::string size;
  Pattern pattern;
};

/// The pieces to cut: per panel its cut line (seam_allowance.h) turned so that its grain line
/// runs along the fabric's length; a cut-on-fold panel opened out about its fold; `cutCount`
/// copies, every second one mirrored (a "cut 2" is a left and a right). Laid by libnest2d
/// turning pieces only by 0 or 180 degrees. Throws MarkerError naming the panel when a piece
/// cannot be prepared (no grain line, a fold that is not a straight run of the cut line), or
/// is wider than the fabric; MarkerLimitError, before any nesting, when there are more pieces
/// than options.maxPieces.
Marker layMarker(const std::vector<SizedPattern>& sizes, const MarkerOptions& options);

/// SVG in mm (1 user unit = 1 mm, 1:1): the fabric (selvedges), each piece with its grain arrow
/// and label, one colour per size with a legend, length and efficiency in the title.
std::string markerSvg(const Marker& marker, const std::string& title);
/// PDF: one page of the marker's size plus a 2 cm border, 1:1.
std::string markerPdf(const Marker& marker, const std::string& title);
/// The marker as numbers (what `garmcap marker` prints and the API's marker.json answers):
/// title, fabric_width_cm, length_cm, piece_area_cm2, efficiency (0..1), sizes (the size
/// labels in the order first laid), piece_count, and pieces (panel, size, mirrored, unfolded,
/// turned, area_cm2 each).
nlohmann::json markerSummaryJson(const Marker& marker, const std::string& title);
/// DXF R12 in mm (y up): layer "FABRIC" (selvedges and ends), one layer "SIZE_<size>" per size
/// holding that size's closed cut lines, grain lines on "GRAIN".
std::string markerDxf(const Marker& marker);

}  // namespace garmcap::drafts
