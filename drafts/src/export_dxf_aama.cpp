#include "garmcap/daemon/export_pattern.h"

#include <Eigen/Dense>
#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <map>
#include <nlohmann/json.hpp>
#include <set>
#include <sstream>

#include "garmcap/drafts/xml_escape.h"

namespace garmcap::daemon {
namespace {

using drafts::Panel;
using drafts::Pattern;
using drafts::Point2;
using drafts::Polyline;
using drafts::xmlEscape;

constexpr double kPi = 3.14159265358979323846;
constexpr double kTurnAngleDeg = 20.0;  // a sharper bend than this is a corner, not a curve
constexpr double kOnVertexCm = 0.02;    // a dart leg or notch this close to a vertex is on it

std::string fmt(double v, int decimals = 4) {
  char buf[48];
  std::snprintf(buf, sizeof buf, "%.*f", decimals, v);
  std::string s = buf;
  if (s == "-0.0000" || s == "-0.000" || s == "-0.00" || s == "-0.0")
    s.erase(0, 1);
  return s;
}

// DXF R12 text and block names: printable ASCII only (CAD systems read them in a code page).
std::string dxfText(const std::string& s) {
  std::string out;
  for (unsigned char c : s)
    out += (c >= 32 && c < 127) ? static_cast<char>(c) : '_';
  return out;
}

std::string blockName(const std::string& piece, const std::string& size) {
  std::string out;
  for (unsigned char c : piece + "_" + size)
    out += (std::isalnum(c) || c == '_' || c == '-') ? static_cast<char>(c) : '-';
  return out;
}

struct Box {
  Point2 min{1e300, 1e300};
  Point2 max{-1e300, -1e300};
  void add(const Point2& p) {
    min = min.cwiseMin(p);
    max = max.cwiseMax(p);
  }
  double width() const { return max.x() - min.x(); }
  double height() const { return max.y() - min.y(); }
};

Box panelBox(const Panel& p) {
  Box b;
  for (const auto& q : p.outline)
    b.add(q);
  return b;
}

int nearestVertex(const Polyline& outline, const Point2& p) {
  int best = -1;
  double bestD = kOnVertexCm;
  for (size_t i = 0; i < outline.size(); ++i) {
    double d = (outline[i] - p).norm();
    if (d <= bestD) {
      bestD = d;
      best = static_cast<int>(i);
    }
  }
  return best;
}

// Unit normal pointing into the panel at outline point `p` (nearest edge), for notch slits.
Point2 inwardNormal(const Polyline& outline, const Point2& p) {
  double area = 0;
  for (size_t i = 0; i < outline.size(); ++i) {
    const auto& a = outline[i];
    const auto& b = outline[(i + 1) % outline.size()];
    area += a.x() * b.y() - b.x() * a.y();
  }
  size_t bestI = 0;
  double bestD = 1e300;
  for (size_t i = 0; i < outline.size(); ++i) {
    const auto& a = outline[i];
    const auto& b = outline[(i + 1) % outline.size()];
    Point2 ab = b - a;
    double t = ab.squaredNorm() > 0 ? std::clamp((p - a).dot(ab) / ab.squaredNorm(), 0.0, 1.0) : 0;
    double d = (a + t * ab - p).norm();
    if (d < bestD) {
      bestD = d;
      bestI = i;
    }
  }
  Point2 e = outline[(bestI + 1) % outline.size()] - outline[bestI];
  if (e.norm() == 0)
    return Point2(0, 0);
  e.normalize();
  // With positive shoelace area the interior lies to the left of each edge: (-ey, ex).
  Point2 left(-e.y(), e.x());
  return area >= 0 ? left : Point2(-left);
}

void checkPanel(const Panel& p) {
  if (p.outline.size() < 3)
    throw ExportError("panel '" + p.name + "': outline has " + std::to_string(p.outline.size()) +
                      " points; a piece needs at least 3");
  for (const auto& q : p.outline)
    if (!std::isfinite(q.x()) || !std::isfinite(q.y()))
      throw ExportError("panel '" + p.name + "': outline has a non-finite coordinate");
}

// ---------------------------------------------------------------------------------------------
// DXF writer (R12 group codes).
class Dxf {
 public:
  void code(int c, const std::string& v) {
    char buf[8];
    std::snprintf(buf, sizeof buf, "%3d", c);
    out_ += buf;
    out_ += "\r\n";
    out_ += v;
    out_ += "\r\n";
  }
  void xy(const Point2& pCm, int cx = 10) {
    code(cx, fmt(pCm.x() * 10.0));
    code(cx + 10, fmt(-pCm.y() * 10.0));
    code(cx + 20, "0.0");
  }
  void text(const std::string& layer, const Point2& at, double heightMm, const std::string& s) {
    code(0, "TEXT");
    code(8, layer);
    xy(at);
    code(40, fmt(heightMm, 2));
    code(1, dxfText(s));
  }
  void point(const std::string& layer, const Point2& at) {
    code(0, "POINT");
    code(8, layer);
    xy(at);
  }
  void line(const std::string& layer, const Point2& a, const Point2& b) {
    code(0, "LINE");
    code(8, layer);
    xy(a, 10);
    xy(b, 11);
  }
  void polyline(const std::string& layer, const Polyline& pts, bool closed) {
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
      xy(p);
    }
    code(0, "SEQEND");
    code(8, layer);
  }
  std::string& str() { return out_; }

 private:
  std::string out_;
};

void dxfHeader(Dxf& d) {
  d.code(0, "SECTION");
  d.code(2, "HEADER");
  d.code(9, "$ACADVER");
  d.code(1, "AC1009");
  d.code(9, "$INSUNITS");
  d.code(70, "4");  // millimetres
  d.code(9, "$MEASUREMENT");
  d.code(70, "1");  // metric
  d.code(0, "ENDSEC");
  d.code(0, "SECTION");
  d.code(2, "TABLES");
  d.code(0, "TABLE");
  d.code(2, "LAYER");
  const std::vector<std::string> layers = {"1", "2", "3", "4", "7", "8", "13", "15"};
  d.code(70, std::to_string(layers.size()));
  for (const auto& l : layers) {
    d.code(0, "LAYER");
    d.code(2, l);
    d.code(70, "0");
    d.code(62, "7");
    d.code(6, "CONTINUOUS");
  }
  d.code(0, "ENDTAB");
  d.code(0, "ENDSEC");
}

// One piece of one size as a BLOCK. `ruleNumbers` (same length as the turn-point list, may be
// empty) are written as "# N" texts beside layer-2 turn points.
void dxfPieceBlock(Dxf& d, const Pattern& pattern, const Panel& panel, const std::string& size,
                   const PieceText& text, const std::vector<int>& turns,
                   const std::vector<int>& ruleNumbers, bool sample) {
  checkPanel(panel);
  const std::string name = blockName(panel.name, size);
  d.code(0, "BLOCK");
  d.code(8, "0");
  d.code(2, name);
  d.code(70, "0");
  d.code(10, "0.0");
  d.code(20, "0.0");
  d.code(30, "0.0");
  d.code(3, name);

  d.polyline("1", panel.outline, true);

  std::set<int> turnSet(turns.begin(), turns.end());
  for (size_t k = 0; k < turns.size(); ++k) {
    const auto& p = panel.outline[static_cast<size_t>(turns[k])];
    d.point("2", p);
    if (!ruleNumbers.empty())
      d.text("2", p, 3.0, "# " + std::to_string(ruleNumbers[k]));
  }
  for (size_t i = 0; i < panel.outline.size(); ++i)
    if (!turnSet.count(static_cast<int>(i)))
      d.point("3", panel.outline[i]);

  for (const auto& n : panel.notches) {
    Point2 in = inwardNormal(panel.outline, n.position);
    d.line("4", n.position, n.position + 0.5 * in);  // 5 mm slit notch
  }
  d.line("7", panel.grainline.start, panel.grainline.end);
  for (const auto& dart : panel.darts) {
    d.polyline("8", {dart.leg1, dart.apex, dart.leg2}, false);
    d.point("13", dart.apex);
  }
  for (const auto& l : panel.internalLines)
    d.polyline("8", l.points, false);

  Box b = panelBox(panel);
  Point2 at(b.min.x() + 0.15 * b.width(), b.min.y() + 0.3 * b.height());
  std::vector<std::string> lines = {"Piece Name: " + panel.name,
                                    "Size: " + size,
                                    "Quantity: " + std::to_string(panel.cutCount),
                                    "Material: " + text.fabric,
                                    "Style Name: " + text.style,
                                    "Category: " + pattern.type};
  if (panel.cutOnFold)
    lines.push_back("Annotation: cut on fold");
  lines.push_back("Annotation: seam allowance " + fmt(panel.seamAllowanceCm * 10, 1) +
                  " mm not included");
  if (sample)
    lines.push_back("Sample Size: " + size);
  for (size_t i = 0; i < lines.size(); ++i)
    d.text("1", at + Point2(0, 0.8 * static_cast<double>(i)), 5.0, lines[i]);
  d.code(0, "ENDBLK");
  d.code(8, "0");
}

void dxfStyleText(Dxf& d, const std::vector<std::string>& lines) {
  for (size_t i = 0; i < lines.size(); ++i)
    d.text("1", Point2(0, -5.0 - 0.8 * static_cast<double>(lines.size() - i)), 5.0, lines[i]);
}

void dxfInsert(Dxf& d, const std::string& name) {
  d.code(0, "INSERT");
  d.code(8, "1");
  d.code(2, name);
  d.code(10, "0.0");
  d.code(20, "0.0");
  d.code(30, "0.0");
}

// ---------------------------------------------------------------------------------------------
// GarmentCode: cubic Bezier through the polyline between two breakpoints, least squares on
// the two inner control points with chord-length parameters. Returns the control points.
std::pair<Point2, Point2> fitCubic(const std::vector<Point2>& q) {
  const Point2 p0 = q.front();
  const Point2 p3 = q.back();
  std::vector<double> t(q.size(), 0.0);
  for (size_t k = 1; k < q.size(); ++k)
    t[k] = t[k - 1] + (q[k] - q[k - 1]).norm();
  for (auto& v : t)
    v /= t.back();
  Eigen::Matrix2d m = Eigen::Matrix2d::Zero();
  Eigen::Matrix<double, 2, 2> rhs = Eigen::Matrix2d::Zero();  // rows: C1, C2; cols: x, y
  for (size_t k = 0; k < q.size(); ++k) {
    double s = 1 - t[k];
    double a = 3 * s * s * t[k];
    double b = 3 * s * t[k] * t[k];
    Point2 r = q[k] - s * s * s * p0 - t[k] * t[k] * t[k] * p3;
    m(0, 0) += a * a;
    m(0, 1) += a * b;
    m(1, 1) += b * b;
    rhs.row(0) += a * r.transpose();
    rhs.row(1) += b * r.transpose();
  }
  m(1, 0) = m(0, 1);
  Eigen::Matrix2d c = m.ldlt().solve(rhs);
  return {c.row(0).transpose(), c.row(1).transpose()};
}

Eigen::Vector2d relative(const Point2& start, const Point2& end, const Point2& c) {
  Point2 d = end - start;
  Point2 perp(-d.y(), d.x());
  double l2 = d.squaredNorm();
  return {(c - start).dot(d) / l2, (c - start).dot(perp) / l2};
}

// ---------------------------------------------------------------------------------------------
// PDF helpers
std::string pdfString(const std::string& s) {
  std::string out = "(";
  for (unsigned char c : s) {
    if (c == '(' || c == ')' || c == '\\') {
      out += '\\';
      out += static_cast<char>(c);
    } else if (c >= 32 && c < 127) {
      out += static_cast<char>(c);
    } else {
      out += '?';  // base-14 fonts have no UTF-8; piece names are ASCII anyway
    }
  }
  return out + ")";
}

}  // namespace

// ---------------------------------------------------------------------------------------------
std::vector<int> turnPointIndices(const Panel& panel, const Pattern& pattern) {
  checkPanel(panel);
  const auto& o = panel.outline;
  const size_t n = o.size();
  std::set<int> turns;
  for (size_t i = 0; i < n; ++i) {
    Point2 a = o[i] - o[(i + n - 1) % n];
    Point2 b = o[(i + 1) % n] - o[i];
    if (a.norm() == 0 || b.norm() == 0)
      continue;
    double cosA = std::clamp(a.normalized().dot(b.normalized()), -1.0, 1.0);
    if (std::acos(cosA) * 180.0 / kPi > kTurnAngleDeg)
      turns.insert(static_cast<int>(i));
  }
  for (const auto& s : pattern.seams) {
    for (const auto* e : {&s.a, &s.b}) {
      if (e->panel != panel.name)
        continue;
      if (e->from >= 0 && static_cast<size_t>(e->from) < n)
        turns.insert(e->from);
      if (e->to >= 0 && static_cast<size_t>(e->to) < n)
        turns.insert(e->to);
    }
  }
  for (const auto& d : panel.darts)
    for (const auto& leg : {d.leg1, d.leg2}) {
      int v = nearestVertex(o, leg);
      if (v >= 0)
        turns.insert(v);
    }
  for (const auto& nt : panel.notches) {
    int v = nearestVertex(o, nt.position);
    if (v >= 0)
      turns.insert(v);
  }
  if (turns.empty())
    turns.insert(0);
  return {turns.begin(), turns.end()};
}

Layout layoutPanels(const Pattern& pattern, double gapCm, double maxRowWidthCm) {
  Layout lay;
  double x = gapCm, y = gapCm, rowH = 0;
  for (const auto& p : pattern.panels) {
    checkPanel(p);
    Box b = panelBox(p);
    if (x > gapCm && x + b.width() + gapCm > maxRowWidthCm) {
      x = gapCm;
      y += rowH + gapCm;
      rowH = 0;
    }
    lay.offsets.push_back(Point2(x, y) - b.min);
    x += b.width() + gapCm;
    rowH = std::max(rowH, b.height());
    lay.widthCm = std::max(lay.widthCm, x);
  }
  lay.heightCm = y + rowH + gapCm;
  return lay;
}

std::string patternSvg(const Pattern& pattern, const PieceText& text) {
  if (pattern.panels.empty())
    throw ExportError("pattern '" + pattern.type + "' has no panels");
  Layout lay = layoutPanels(pattern, 2.0, 160.0);
  const double extraCm = 2.0;  // title line
  std::ostringstream os;
  auto pt = [](const Point2& p) { return fmt(p.x() * 10, 2) + "," + fmt(p.y() * 10, 2); };
  os << "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n"
     << "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" << fmt(lay.widthCm * 10, 2)
     << "mm\" height=\"" << fmt((lay.heightCm + extraCm) * 10, 2) << "mm\" viewBox=\"0 0 "
     << fmt(lay.widthCm * 10, 2) << " " << fmt((lay.heightCm + extraCm) * 10, 2) << "\">\n"
     << "<title>" << xmlEscape(text.style + " " + pattern.type + " size " + text.size)
     << "</title>\n"
     << "<style>.cut{fill:#fdfcf8;stroke:#111;stroke-width:0.5}.dart{fill:none;stroke:#c33;"
        "stroke-width:0.4;stroke-dasharray:3 2}.int{fill:none;stroke:#36c;stroke-width:0.4;"
        "stroke-dasharray:4 2}.grain{stroke:#111;stroke-width:0.4}.notch{stroke:#111;"
        "stroke-width:0.6}text{font-family:sans-serif;fill:#111}</style>\n";
  os << "<text x=\"20\" y=\"" << fmt((lay.heightCm + 1.2) * 10, 2) << "\" font-size=\"5\">"
     << xmlEscape(text.style + " · " + pattern.type + " · size " + text.size +
                  " · 1:1, units mm · seam allowance not included")
     << "</text>\n";
  for (size_t i = 0; i < pattern.panels.size(); ++i) {
    const auto& p = pattern.panels[i];
    const Point2 off = lay.offsets[i];
    auto q = [&](const Point2& a) { return pt(a + off); };
    os << "<g id=\"" << xmlEscape(p.name) << "\">\n<polygon class=\"cut\" points=\"";
    for (size_t k = 0; k < p.outline.size(); ++k)
      os << (k ? " " : "") << q(p.outline[k]);
    os << "\"/>\n";
    for (const auto& d : p.darts)
      os << "<polyline class=\"dart\" points=\"" << q(d.leg1) << " " << q(d.apex) << " "
         << q(d.leg2) << "\"/>\n";
    for (const auto& l : p.internalLines) {
      os << "<polyline class=\"int\" points=\"";
      for (size_t k = 0; k < l.points.size(); ++k)
        os << (k ? " " : "") << q(l.points[k]);
      os << "\"/>\n";
    }
    for (const auto& n : p.notches) {
      Point2 in = inwardNormal(p.outline, n.position);
      os << "<line class=\"notch\" x1=\"" << fmt((n.position + off).x() * 10, 2) << "\" y1=\""
         << fmt((n.position + off).y() * 10, 2) << "\" x2=\""
         << fmt((n.position + 0.5 * in + off).x() * 10, 2) << "\" y2=\""
         << fmt((n.position + 0.5 * in + off).y() * 10, 2) << "\"/>\n";
    }
    // Grainline with an arrowhead at each end.
    Point2 a = p.grainline.start + off, b = p.grainline.end + off;
    os << "<line class=\"grain\" x1=\"" << fmt(a.x() * 10, 2) << "\" y1=\"" << fmt(a.y() * 10, 2)
       << "\" x2=\"" << fmt(b.x() * 10, 2) << "\" y2=\"" << fmt(b.y() * 10, 2) << "\"/>\n";
    if ((b - a).norm() > 0) {
      Point2 u = (b - a).normalized(), v(-u.y(), u.x());
      for (const auto& [tip, dir] : {std::pair{b, u}, std::pair{a, Point2(-u)}}) {
        Point2 l = tip - 0.8 * dir + 0.3 * v, r = tip - 0.8 * dir - 0.3 * v;
        os << "<polyline class=\"grain\" fill=\"none\" points=\"" << pt(l) << " " << pt(tip) << " "
           << pt(r) << "\"/>\n";
      }
    }
    Box bx = panelBox(p);
    Point2 c = (bx.min + bx.max) / 2 + off;
    std::string cut = "Cut " + std::to_string(p.cutCount) + (p.cutOnFold ? " on fold" : "");
    os << "<text x=\"" << fmt(c.x() * 10, 2) << "\" y=\"" << fmt(c.y() * 10 - 4, 2)
       << "\" font-size=\"7\" text-anchor=\"middle\">" << xmlEscape(p.name) << "</text>\n"
       << "<text x=\"" << fmt(c.x() * 10, 2) << "\" y=\"" << fmt(c.y() * 10 + 5, 2)
       << "\" font-size=\"5\" text-anchor=\"middle\">"
       << xmlEscape("size " + text.size + " · " + cut) << "</text>\n</g>\n";
  }
  os << "</svg>\n";
  return os.str();
}

std::string patternDxf(const Pattern& pattern, const PieceText& text) {
  if (pattern.panels.empty())
    throw ExportError("pattern '" + pattern.type + "' has no panels");
  Dxf d;
  dxfHeader(d);
  d.code(0, "SECTION");
  d.code(2, "BLOCKS");
  for (const auto& p : pattern.panels)
    dxfPieceBlock(d, pattern, p, text.size, text, turnPointIndices(p, pattern), {}, false);
  d.code(0, "ENDSEC");
  d.code(0, "SECTION");
  d.code(2, "ENTITIES");
  dxfStyleText(d, {"Style Name: " + text.style, "Units: METRIC", "Size: " + text.size,
                   "Author: GarmCap Station"});
  for (const auto& p : pattern.panels)
    dxfInsert(d, blockName(p.name, text.size));
  d.code(0, "ENDSEC");
  d.code(0, "EOF");
  return std::move(d.str());
}

void checkGradedRun(const GradedRun& run) {
  if (run.sizes.empty())
    throw ExportError("graded run '" + run.style + "': no sizes");
  if (run.sizes.size() != run.patterns.size())
    throw ExportError("graded run '" + run.style + "': " + std::to_string(run.sizes.size()) +
                      " sizes but " + std::to_string(run.patterns.size()) + " patterns");
  if (std::find(run.sizes.begin(), run.sizes.end(), run.sampleSize) == run.sizes.end())
    throw ExportError("graded run '" + run.style + "': sample size '" + run.sampleSize +
                      "' is not in the size list");
  const auto& base = run.patterns.front();
  for (size_t s = 0; s < run.patterns.size(); ++s) {
    const auto& p = run.patterns[s];
    if (p.panels.size() != base.panels.size())
      throw ExportError("graded run '" + run.style + "': size " + run.sizes[s] + " has " +
                        std::to_string(p.panels.size()) + " panels, size " + run.sizes[0] +
                        " has " + std::to_string(base.panels.size()));
    for (size_t i = 0; i < p.panels.size(); ++i) {
      checkPanel(p.panels[i]);
      if (p.panels[i].name != base.panels[i].name ||
          p.panels[i].outline.size() != base.panels[i].outline.size())
        throw ExportError("graded run '" + run.style + "': panel '" + p.panels[i].name +
                          "' of size " + run.sizes[s] +
                          " does not correspond vertex by vertex to size " + run.sizes[0]);
    }
  }
}

namespace {
size_t sampleIndex(const GradedRun& run) {
  return static_cast<size_t>(std::find(run.sizes.begin(), run.sizes.end(), run.sampleSize) -
                             run.sizes.begin());
}
}  // namespace

std::string gradedDxf(const GradedRun& run) {
  checkGradedRun(run);
  const size_t si = sampleIndex(run);
  const auto& sample = run.patterns[si];
  Dxf d;
  dxfHeader(d);
  d.code(0, "SECTION");
  d.code(2, "BLOCKS");
  int rule = 1;
  std::vector<std::vector<int>> turnsPerPanel;
  std::vector<std::vector<int>> rulesPerPanel;
  for (const auto& p : sample.panels) {
    auto turns = turnPointIndices(p, sample);
    std::vector<int> rules;
    for (size_t k = 0; k < turns.size(); ++k)
      rules.push_back(rule++);
    turnsPerPanel.push_back(std::move(turns));
    rulesPerPanel.push_back(std::move(rules));
  }
  for (size_t s = 0; s < run.sizes.size(); ++s) {
    const PieceText text{run.style, run.sizes[s]};
    for (size_t i = 0; i < run.patterns[s].panels.size(); ++i)
      dxfPieceBlock(d, run.patterns[s], run.patterns[s].panels[i], run.sizes[s], text,
                    turnsPerPanel[i], s == si ? rulesPerPanel[i] : std::vector<int>{}, s == si);
  }
  d.code(0, "ENDSEC");
  d.code(0, "SECTION");
  d.code(2, "ENTITIES");
  std::string list;
  for (const auto& s : run.sizes)
    list += (list.empty() ? "" : " ") + s;
  dxfStyleText(d, {"Style Name: " + run.style, "Units: METRIC", "Grade Rule Table: " + run.style,
                   "Number of Sizes: " + std::to_string(run.sizes.size()), "Size List: " + list,
                   "Sample Size: " + run.sampleSize, "Author: GarmCap Station"});
  for (size_t s = 0; s < run.sizes.size(); ++s)
    for (const auto& p : run.patterns[s].panels)
      dxfInsert(d, blockName(p.name, run.sizes[s]));
  d.code(0, "ENDSEC");
  d.code(0, "EOF");
  return std::move(d.str());
}

std::string gradeRuleTable(const GradedRun& run) {
  checkGradedRun(run);
  const size_t si = sampleIndex(run);
  const auto& sample = run.patterns[si];
  std::ostringstream os;
  os << "ASTM/D13Proposal 1 Version: D 6673-04\r\n"
     << "AUTHOR: GarmCap Station\r\nPRODUCT: GarmCap Station\r\nVERSION: 1\r\n"
     << "UNITS: METRIC\r\n"
     << "GRADE RULE TABLE: " << dxfText(run.style) << "\r\n"
     << "NUMBER OF SIZES: " << run.sizes.size() << "\r\n"
     << "SIZE LIST:";
  for (const auto& s : run.sizes)
    os << " " << dxfText(s);
  os << "\r\nSAMPLE SIZE: " << dxfText(run.sampleSize) << "\r\n";
  int rule = 1;
  for (size_t i = 0; i < sample.panels.size(); ++i) {
    for (int v : turnPointIndices(sample.panels[i], sample)) {
      os << "RULE: DELTA " << rule++ << "\r\n";
      const Point2 base = sample.panels[i].outline[static_cast<size_t>(v)];
      for (size_t s = 0; s < run.sizes.size(); ++s) {
        Point2 p = run.patterns[s].panels[i].outline[static_cast<size_t>(v)];
        double dx = (p.x() - base.x()) * 10.0, dy = -(p.y() - base.y()) * 10.0;
        os << (s % 5 == 0 ? "" : " ") << fmt(dx, 3) << "," << fmt(dy, 3);
        if (s % 5 == 4 || s + 1 == run.sizes.size())
          os << "\r\n";
      }
    }
  }
  os << "END\r\n";
  return os.str();
}

std::string garmentCodeJson(const Pattern& pattern, const PieceText& text) {
  using nlohmann::json;
  if (pattern.panels.empty())
    throw ExportError("pattern '" + pattern.type + "' has no panels");
  json panels = json::object();
  json order = json::array();
  // panel name -> (original vertex index -> GarmentCode vertex index, reversed?)
  std::map<std::string, std::pair<std::map<int, int>, bool>> maps;
  std::map<std::string, int> vertexCount;
  const bool lower = pattern.type == "skirt" || pattern.type == "pants";
  for (const auto& p : pattern.panels) {
    checkPanel(p);
    const auto& o = p.outline;
    const int n = static_cast<int>(o.size());
    // Breakpoints: seam ends always; turn points only outside seams, so that every seam side
    // is exactly one GarmentCode edge (its stitches are edge-to-edge).
    std::set<int> seamEnds;
    std::vector<std::pair<int, int>> seamRanges;
    for (const auto& s : pattern.seams)
      for (const auto* e : {&s.a, &s.b})
        if (e->panel == p.name) {
          if (e->from < 0 || e->from >= n || e->to < 0 || e->to >= n || e->from == e->to)
            throw ExportError("seam '" + s.name + "': edge of panel '" + p.name +
                              "' has bad vertex range " + std::to_string(e->from) + ".." +
                              std::to_string(e->to));
          seamEnds.insert(e->from);
          seamEnds.insert(e->to);
          seamRanges.emplace_back(e->from, e->to);
        }
    auto insideSeam = [&](int v) {
      for (auto [f, t] : seamRanges) {
        int len = (t - f + n) % n, pos = (v - f + n) % n;
        if (pos > 0 && pos < len)
          return true;
      }
      return false;
    };
    std::set<int> breaks = seamEnds;
    for (int v : turnPointIndices(p, pattern))
      if (!insideSeam(v))
        breaks.insert(v);
    if (breaks.size() < 3) {  // a loop needs at least 3 vertices: add evenly spaced ones
      for (int k = 0; k < 3; ++k)
        breaks.insert(k * n / 3);
    }
    // y up; make the loop counter-clockwise in y-up coordinates.
    std::vector<Point2> up(o.size());
    for (size_t i = 0; i < o.size(); ++i)
      up[i] = Point2(o[i].x(), -o[i].y());
    double area = 0;
    for (int i = 0; i < n; ++i) {
      const auto& a = up[static_cast<size_t>(i)];
      const auto& b = up[static_cast<size_t>((i + 1) % n)];
      area += a.x() * b.y() - b.x() * a.y();
    }
    const bool reversed = area < 0;
    std::vector<int> loop(breaks.begin(), breaks.end());
    if (reversed)
      std::reverse(loop.begin(), loop.end());
    Box bb;
    for (const auto& q : up)
      bb.add(q);
    // Start at the lowest-left vertex.
    auto startIt = std::min_element(loop.begin(), loop.end(), [&](int a, int b) {
      const auto& pa = up[static_cast<size_t>(a)];
      const auto& pb = up[static_cast<size_t>(b)];
      return std::make_pair(pa.y(), pa.x()) < std::make_pair(pb.y(), pb.x());
    });
    std::rotate(loop.begin(), startIt, loop.end());
    std::map<int, int> idx;
    json verts = json::array();
    for (size_t k = 0; k < loop.size(); ++k) {
      idx[loop[k]] = static_cast<int>(k);
      const auto& q = up[static_cast<size_t>(loop[k])];
      verts.push_back({q.x() - bb.min.x(), q.y() - bb.max.y()});
    }
    json edges = json::array();
    const int m = static_cast<int>(loop.size());
    for (int k = 0; k < m; ++k) {
      int a = loop[static_cast<size_t>(k)], b = loop[static_cast<size_t>((k + 1) % m)];
      std::vector<Point2> pts;
      int step = reversed ? -1 : 1;
      for (int v = a;; v = (v + step + n) % n) {
        pts.push_back(up[static_cast<size_t>(v)]);
        if (v == b)
          break;
      }
      json e = {{"endpoints", {k, (k + 1) % m}}};
      bool straight = true;
      const Point2 d = pts.back() - pts.front();
      for (const auto& q : pts) {
        Point2 r = q - pts.front();
        if (d.norm() > 0 && std::abs(d.x() * r.y() - d.y() * r.x()) / d.norm() > 0.01)
          straight = false;
      }
      if (!straight && pts.size() > 2 && d.norm() > 0) {
        auto [c1, c2] = fitCubic(pts);
        auto r1 = relative(pts.front(), pts.back(), c1);
        auto r2 = relative(pts.front(), pts.back(), c2);
        e["curvature"] = {{"type", "cubic"}, {"params", {{r1.x(), r1.y()}, {r2.x(), r2.y()}}}};
      }
      edges.push_back(e);
    }
    const bool back = p.name.find("back") != std::string::npos;
    const double z = back ? -20.0 : 20.0;
    const double top = lower ? 105.0 : 150.0;
    json panel = {{"translation", {-bb.width() / 2, top, z}},
                  {"rotation", {0.0, back ? 180.0 : 0.0, 0.0}},
                  {"vertices", verts},
                  {"edges", edges}};
    panels[p.name] = panel;
    order.push_back(p.name);
    maps[p.name] = {idx, reversed};
    vertexCount[p.name] = m;
  }
  auto edgeIndex = [&](const drafts::EdgeRef& e, const std::string& seam) {
    auto it = maps.find(e.panel);
    if (it == maps.end())
      throw ExportError("seam '" + seam + "' names unknown panel '" + e.panel + "'");
    const auto& [idx, reversed] = it->second;
    int gf = idx.at(e.from), gt = idx.at(e.to);
    int m = vertexCount[e.panel];
    int start = reversed ? gt : gf, end = reversed ? gf : gt;
    if ((start + 1) % m != end)
      throw ExportError("seam '" + seam + "': edge of panel '" + e.panel +
                        "' crosses another seam's end; GarmentCode stitches are edge to edge");
    return start;
  };
  json stitches = json::array();
  for (const auto& s : pattern.seams)
    stitches.push_back({{{"panel", s.a.panel}, {"edge", edgeIndex(s.a, s.name)}},
                        {{"panel", s.b.panel}, {"edge", edgeIndex(s.b, s.name)}},
                        "right_wrong"});
  json spec = {{"pattern", {{"panels", panels}, {"stitches", stitches}, {"panel_order", order}}},
               {"parameters", json::object()},
               {"parameter_order", json::array()},
               {"properties",
                {{"curvature_coords", "relative"},
                 {"normalize_panel_translation", false},
                 {"normalized_edge_loops", true},
                 {"units_in_meter", 100}}},
               {"garmcap", {{"style", text.style}, {"size", text.size}, {"type", pattern.type}}}};
  return spec.dump(2) + "\n";
}

std::string patternPdfA4(const Pattern& pattern, const PieceText& text) {
  if (pattern.panels.empty())
    throw ExportError("pattern '" + pattern.type + "' has no panels");
  constexpr double kPt = 72.0 / 2.54;  // points per cm
  constexpr double kPageW = 21.0, kPageH = 29.7, kMargin = 1.0;
  constexpr double kTileW = kPageW - 2 * kMargin, kTileH = kPageH - 2 * kMargin;
  Layout lay = layoutPanels(pattern, 2.0, 120.0);
  // Room for the 10 cm test square above the panels on the first tile.
  const double shiftY = 13.0;
  const int cols = std::max(1, static_cast<int>(std::ceil(lay.widthCm / kTileW)));
  const int rows = std::max(1, static_cast<int>(std::ceil((lay.heightCm + shiftY) / kTileH)));

  std::vector<std::string> objects;  // object bodies, numbered from 1
  auto add = [&](std::string body) {
    objects.push_back(std::move(body));
    return static_cast<int>(objects.size());
  };
  const int catalogId = add("");  // filled later
  const int pagesId = add("");
  const int fontId = add("<< /Type /Font /Subtype /Type1 /BaseFont /Helvetica >>");
  std::vector<int> pageIds;

  // Geometry in sheet cm (y down) drawn once per page; the page's transform maps the tile.
  std::ostringstream geo;
  auto P = [&](const Point2& p) { return fmt(p.x() * kPt, 3) + " " + fmt(-p.y() * kPt, 3); };
  geo << "0 0 0 RG 0.8 w 1 J 1 j\n";
  // Test square 10 x 10 cm at (2, 2) cm of the sheet.
  geo << P({2, 2}) << " m " << P({12, 2}) << " l " << P({12, 12}) << " l " << P({2, 12})
      << " l h S\n";
  geo << "BT /F1 12 Tf " << P({2.5, 7.2}) << " Td " << pdfString("10 cm test square") << " Tj ET\n";
  geo << "BT /F1 10 Tf " << P({2.5, 8.0}) << " Td " << pdfString("print at 100% / actual size")
      << " Tj ET\n";
  for (size_t i = 0; i < pattern.panels.size(); ++i) {
    const auto& p = pattern.panels[i];
    const Point2 off = lay.offsets[i] + Point2(0, shiftY);
    geo << "1.2 w\n";
    for (size_t k = 0; k < p.outline.size(); ++k)
      geo << P(p.outline[k] + off) << (k ? " l\n" : " m\n");
    geo << "h S\n0.6 w [3 2] 0 d\n";
    for (const auto& d : p.darts)
      geo << P(d.leg1 + off) << " m " << P(d.apex + off) << " l " << P(d.leg2 + off) << " l S\n";
    for (const auto& l : p.internalLines)
      for (size_t k = 0; k < l.points.size(); ++k)
        geo << P(l.points[k] + off) << (k ? " l" : " m")
            << (k + 1 == l.points.size() ? " S\n" : "\n");
    geo << "[] 0 d 0.8 w\n";
    for (const auto& n : p.notches) {
      Point2 in = inwardNormal(p.outline, n.position);
      geo << P(n.position + off) << " m " << P(n.position + 0.5 * in + off) << " l S\n";
    }
    geo << P(p.grainline.start + off) << " m " << P(p.grainline.end + off) << " l S\n";
    Box bx = panelBox(p);
    Point2 c = (bx.min + bx.max) / 2 + off;
    geo << "BT /F1 14 Tf " << P(c + Point2(-3, 0)) << " Td " << pdfString(p.name) << " Tj ET\n";
    geo << "BT /F1 10 Tf " << P(c + Point2(-3, 0.7)) << " Td "
        << pdfString(text.style + "  size " + text.size + "  cut " + std::to_string(p.cutCount) +
                     (p.cutOnFold ? " on fold" : ""))
        << " Tj ET\n";
  }
  const std::string geometry = geo.str();

  for (int r = 0; r < rows; ++r) {
    for (int c = 0; c < cols; ++c) {
      std::ostringstream cs;
      const double ox = kMargin * kPt, oyTop = (kPageH - kMargin) * kPt;
      // Tile frame and corner marks (outside the tile), page label.
      cs << "q 0.5 G 0.3 w " << fmt(ox, 3) << " " << fmt(kMargin * kPt, 3) << " "
         << fmt(kTileW * kPt, 3) << " " << fmt(kTileH * kPt, 3) << " re S Q\n";
      const double L = 0.6 * kPt;
      for (auto [cx, cy] :
           {std::pair{ox, kMargin * kPt}, std::pair{ox + kTileW * kPt, kMargin * kPt},
            std::pair{ox, oyTop}, std::pair{ox + kTileW * kPt, oyTop}}) {
        cs << "0 G 0.5 w " << fmt(cx - L, 3) << " " << fmt(cy, 3) << " m " << fmt(cx + L, 3) << " "
           << fmt(cy, 3) << " l S " << fmt(cx, 3) << " " << fmt(cy - L, 3) << " m " << fmt(cx, 3)
           << " " << fmt(cy + L, 3) << " l S\n";
      }
      char label[160];
      std::snprintf(
          label, sizeof label, "%s size %s - page row %d col %d of %dx%d - glue edges on frame",
          dxfText(text.style).c_str(), dxfText(text.size).c_str(), r + 1, c + 1, rows, cols);
      cs << "BT /F1 8 Tf " << fmt(ox, 3) << " " << fmt(0.35 * kPt, 3) << " Td " << pdfString(label)
         << " Tj ET\n";
      char big[32];
      std::snprintf(big, sizeof big, "%c%d", 'A' + (r % 26), c + 1);
      cs << "BT /F1 10 Tf " << fmt(ox, 3) << " " << fmt((kPageH - 0.7) * kPt, 3) << " Td "
         << pdfString(big) << " Tj ET\n";
      // Clip to the tile and draw the sheet shifted so that this tile's corner is at the
      // tile frame's top-left corner.
      cs << "q " << fmt(ox, 3) << " " << fmt(kMargin * kPt, 3) << " " << fmt(kTileW * kPt, 3) << " "
         << fmt(kTileH * kPt, 3) << " re W n\n"
         << "1 0 0 1 " << fmt(ox - c * kTileW * kPt, 3) << " " << fmt(oyTop + r * kTileH * kPt, 3)
         << " cm\n"
         << geometry << "Q\n";
      const std::string content = cs.str();
      int contentId = add("<< /Length " + std::to_string(content.size()) + " >>\nstream\n" +
                          content + "endstream");
      int pageId = add("<< /Type /Page /Parent " + std::to_string(pagesId) +
                       " 0 R /MediaBox [0 0 " + fmt(kPageW * kPt, 3) + " " + fmt(kPageH * kPt, 3) +
                       "] /Resources << /Font << /F1 " + std::to_string(fontId) +
                       " 0 R >> >> /Contents " + std::to_string(contentId) + " 0 R >>");
      pageIds.push_back(pageId);
    }
  }
  std::string kids;
  for (int id : pageIds)
    kids += std::to_string(id) + " 0 R ";
  objects[static_cast<size_t>(catalogId - 1)] =
      "<< /Type /Catalog /Pages " + std::to_string(pagesId) + " 0 R >>";
  objects[static_cast<size_t>(pagesId - 1)] =
      "<< /Type /Pages /Kids [" + kids + "] /Count " + std::to_string(pageIds.size()) + " >>";
  std::string out = "%PDF-1.4\n%\xE2\xE3\xCF\xD3\n";
  std::vector<size_t> offsets;
  for (size_t i = 0; i < objects.size(); ++i) {
    offsets.push_back(out.size());
    out += std::to_string(i + 1) + " 0 obj\n" + objects[i] + "\nendobj\n";
  }
  const size_t xref = out.size();
  out += "xref\n0 " + std::to_string(objects.size() + 1) + "\n0000000000 65535 f \n";
  for (size_t off : offsets) {
    char buf[24];
    std::snprintf(buf, sizeof buf, "%010zu 00000 n \n", off);
    out += buf;
  }
  out += "trailer\n<< /Size " + std::to_string(objects.size() + 1) + " /Root " +
         std::to_string(catalogId) + " 0 R /Info << /Title " +
         pdfString(text.style + " " + pattern.type + " size " + text.size) +
         " /Producer (GarmCap Station) >> >>\nstartxref\n" + std::to_string(xref) + "\n%%EOF\n";
  return out;
}

}  // namespace garmcap::daemon
