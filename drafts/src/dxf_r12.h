#pragma once
// Private: a minimal DXF R12 (AC1009) writer in mm with y up for the drawings that are not
// DXF-AAMA pattern files (nested grading, markers): named coloured layers, closed or open
// POLYLINEs, LINEs and TEXTs in the ENTITIES section.

#include <string>
#include <vector>

#include "garmcap/drafts/pattern.h"

namespace garmcap::drafts::detail {

struct DxfLayer {
  std::string name;
  int colour = 7;                       // AutoCAD colour index
  std::string linetype = "CONTINUOUS";  // CONTINUOUS or DASHED (both defined in the file)
};

class DxfR12 {
 public:
  /// Points are given in pattern cm with y down and written as mm with y up.
  explicit DxfR12(const std::vector<DxfLayer>& layers);
  void polyline(const std::string& layer, const Polyline& ptsCm, bool closed);
  void line(const std::string& layer, const Point2& aCm, const Point2& bCm);
  void text(const std::string& layer, const Point2& atCm, double heightMm, const std::string& s);
  /// Closes the ENTITIES section and the file.
  std::string finish();

 private:
  void code(int c, const std::string& v);
  void xy(const Point2& pCm, int cx);
  std::string out_;
};

}  // namespace garmcap::drafts::detail
