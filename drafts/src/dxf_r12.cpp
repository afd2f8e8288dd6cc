// Minimal DXF R12 writer; see dxf_r12.h.
#include "dxf_r12.h"

#include <cstdio>

#include "export_util.h"

namespace garmcap::drafts::detail {

void DxfR12::code(int c, const std::string& v) {
  char buf[8];
  std::snprintf(buf, sizeof buf, "%3d", c);
  out_ += buf;
  out_ += "\r\n";
  out_ += v;
  out_ += "\r\n";
}

void DxfR12::xy(const Point2& pCm, int cx) {
  code(cx, fixed(pCm.x() * 10.0));
  code(cx + 10, fixed(-pCm.y() * 10.0));
  code(cx + 20, "0.0");
}

DxfR12::DxfR12(const std::vector<DxfLayer>& layers) {
  headerAndTables(layers, true);
  beginSection("ENTITIES");
}

void DxfR12::headerAndTables(const std::vector<DxfLayer>& layers, bool withLinetypes) {
  beginSection("HEADER");
  code(9, "$ACADVER");
  code(1, "AC1009");
  code(9, "$INSUNITS");
  code(70, "4");  // millimetres
  code(9, "$MEASUREMENT");
  code(70, "1");  // metric
  endSection();
  beginSection("TABLES");
  if (withLinetypes) {
    code(0, "TABLE");
    code(2, "LTYPE");
    code(70, "2");
    code(0, "LTYPE");
    code(2, "CONTINUOUS");
    code(70, "0");
    code(3, "Solid line");
    code(72, "65");
    code(73, "0");
    code(40, "0.0");
    code(0, "LTYPE");
    code(2, "DASHED");
    code(70, "0");
    code(3, "__ __ __");
    code(72, "65");
    code(73, "2");
    code(40, "7.5");
    code(49, "5.0");
    code(49, "-2.5");
    code(0, "ENDTAB");
  }
  code(0, "TABLE");
  code(2, "LAYER");
  code(70, std::to_string(layers.size()));
  for (const auto& l : layers) {
    code(0, "LAYER");
    code(2, l.name);
    code(70, "0");
    code(62, std::to_string(l.colour));
    code(6, l.linetype);
  }
  code(0, "ENDTAB");
  endSection();
}

void DxfR12::beginSection(const std::string& name) {
  code(0, "SECTION");
  code(2, name);
}

void DxfR12::endSection() {
  code(0, "ENDSEC");
}

void DxfR12::polyline(const std::string& layer, const Polyline& pts, bool closed) {
  code(0, "POLYLINE");
  code(8, layer);
  code(66, "1");
  code(10, "0.0");
  code(20, "0.0");
  code(30, "0.0");
  code(70, closed ? "1" : "0");
  for (const auto& p : pts) {
    code(0, "VERTEX");
    code(8, layer);
    xy(p, 10);
  }
  code(0, "SEQEND");
  code(8, layer);
}

void DxfR12::point(const std::string& layer, const Point2& at) {
  code(0, "POINT");
  code(8, layer);
  xy(at, 10);
}

void DxfR12::line(const std::string& layer, const Point2& a, const Point2& b) {
  code(0, "LINE");
  code(8, layer);
  xy(a, 10);
  xy(b, 11);
}

void DxfR12::text(const std::string& layer, const Point2& at, double heightMm,
                  const std::string& s) {
  code(0, "TEXT");
  code(8, layer);
  xy(at, 10);
  code(40, fixed(heightMm, 2));
  code(1, asciiText(s));
}

std::string DxfR12::finish() {
  endSection();
  code(0, "EOF");
  return std::move(out_);
}

}  // namespace garmcap::drafts::detail
