#pragma once
// Private: the DXF R12 (AC1009) group-code writer in mm with y up that every DXF of drafts/
// shares. Drawings that are not pattern files (nested grading, markers) take the whole file from
// it: header, line types and named coloured layers, then POLYLINEs, LINEs and TEXTs in the
// ENTITIES section. DXF-AAMA pattern files (export_dxf_aama.cpp) use its header, layer table,
// entities and group codes, and write their BLOCKS section themselves.

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
  /// A drawing: the header and tables (with the CONTINUOUS and DASHED line types), then the
  /// ENTITIES section opened.
  explicit DxfR12(const std::vector<DxfLayer>& layers);
  /// Nothing written yet: the caller writes the sections (headerAndTables, then its own).
  DxfR12() = default;

  /// The HEADER section (AC1009, millimetres, metric) and the TABLES section: the LTYPE table
  /// defining CONTINUOUS and DASHED when `withLinetypes`, then the LAYER table of `layers`.
  void headerAndTables(const std::vector<DxfLayer>& layers, bool withLinetypes);
  /// "0 SECTION 2 <name>" and "0 ENDSEC".
  void beginSection(const std::string& name);
  void endSection();

  void polyline(const std::string& layer, const Polyline& ptsCm, bool closed);
  void line(const std::string& layer, const Point2& aCm, const Point2& bCm);
  void point(const std::string& layer, const Point2& atCm);
  void text(const std::string& layer, const Point2& atCm, double heightMm, const std::string& s);

  /// One group: the code right-aligned in 3 columns, CR LF, the value, CR LF.
  void code(int c, const std::string& v);
  /// A point as the groups cx, cx + 10, cx + 20 (x, y, z = 0) in mm with y up.
  void xy(const Point2& pCm, int cx = 10);

  /// Closes the open (ENTITIES) section and the file.
  std::string finish();

 private:
  std::string out_;
};

}  // namespace garmcap::drafts::detail
