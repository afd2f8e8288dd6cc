// Nested grading drawings (SVG, PDF, DXF); see export_nested_grading.h.
#include "garmcap/drafts/export_nested_grading.h"

#include <sstream>

#include "dxf_r12.h"
#include "export_util.h"
#include "garmcap/drafts/panel_edges.h"
#include "garmcap/drafts/xml_escape.h"
#include "pdf_document.h"
#include "size_styles.h"

namespace garmcap::drafts {
namespace {

using detail::Box;
using detail::fixed;

// The reference point a size of a piece is aligned at: the top of its outline (smallest y),
// at the x of its fold (the centre front/back of a piece cut on the fold) or else the middle of
// its width (a sleeve's cap, a skirt panel's waist).
Point2 referencePoint(const Panel& p, const Pattern& pattern) {
  const Box b = detail::panelBox(p);
  double x = (b.min.x() + b.max.x()) / 2;
  if (p.cutOnFold)
    if (const auto fold = foldEdge(p, pattern))
      x = p.outline[static_cast<size_t>(fold->from)].x();
  return Point2(x, b.min.y());
}

// The outline of size k of panel i, moved so that its reference point lies on the sample's.
Polyline aligned(const GradedRun& run, size_t k, size_t i) {
  const size_t s = sampleIndex(run);
  const Point2 shift = referencePoint(run.patterns[s].panels[i], run.patterns[s]) -
                       referencePoint(run.patterns[k].panels[i], run.patterns[k]);
  Polyline out;
  for (const auto& q : run.patterns[k].panels[i].outline)
    out.push_back(q + shift);
  return out;
}

// Where each piece's nest goes on the sheet: pieces side by side (rows no wider than 200 cm),
// each nest's box (all sizes) moved to its slot, below a header of `headerCm` for the legend.
struct NestSheet {
  std::vector<Point2> offsets;  // per panel, added to every size's points
  double widthCm = 0, heightCm = 0;
};

NestSheet nestSheet(const GradedRun& run, double headerCm) {
  constexpr double kGap = 3.0, kMaxRow = 200.0;
  NestSheet s;
  double x = kGap, y = headerCm, rowH = 0;
  const auto& panels = run.patterns.front().panels;
  for (size_t i = 0; i < panels.size(); ++i) {
    Box b;
    for (size_t k = 0; k < run.patterns.size(); ++k)
      b.add(aligned(run, k, i));
    if (x > kGap && x + b.width() + kGap > kMaxRow) {
      x = kGap;
      y += rowH + kGap;
      rowH = 0;
    }
    s.offsets.push_back(Point2(x, y + 1.0) - b.min);  // 1 cm above for the piece name
    x += b.width() + kGap;
    rowH = std::max(rowH, b.height() + 1.0);
    s.widthCm = std::max(s.widthCm, x);
  }
  s.heightCm = y + rowH + kGap;
  return s;
}

void checkRun(const GradedRun& run) {
  try {
    checkGradedRun(run);
  } catch (const PatternExportError& e) {
    throw NestedGradingError(e.what());
  }
  if (run.patterns.empty() || run.patterns.front().panels.empty())
    throw NestedGradingError("nested grading: the run has no pieces");
}

std::string sampleNote(const GradedRun& run) {
  return run.style + " nested grading, sizes " + run.sizes.front() + " to " + run.sizes.back() +
         ", sample size " + run.sampleSize + " (thick), sew lines, 1:1";
}

Point2 nameAt(const GradedRun& run, size_t panel, const NestSheet& s) {
  Box b;
  for (size_t k = 0; k < run.patterns.size(); ++k)
    b.add(aligned(run, k, panel));
  return Point2(b.min.x(), b.min.y() - 0.4) + s.offsets[panel];
}

}  // namespace

std::string nestedGradingSvg(const GradedRun& run) {
  checkRun(run);
  const size_t sample = sampleIndex(run);
  const double header = 2.0 + 0.7 * static_cast<double>(run.sizes.size());
  const NestSheet sh = nestSheet(run, header);
  auto pt = [](const Point2& p) { return fixed(p.x() * 10, 2) + "," + fixed(p.y() * 10, 2); };
  std::ostringstream os;
  os << "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n<svg xmlns=\"http://www.w3.org/2000/svg\" "
     << "width=\"" << fixed(sh.widthCm * 10, 2) << "mm\" height=\"" << fixed(sh.heightCm * 10, 2)
     << "mm\" viewBox=\"0 0 " << fixed(sh.widthCm * 10, 2) << " " << fixed(sh.heightCm * 10, 2)
     << "\">\n<title>" << xmlEscape(sampleNote(run)) << "</title>\n"
     << "<style>text{font-family:sans-serif;fill:#111}polygon{fill:none}</style>\n"
     << "<text x=\"30\" y=\"10\" font-size=\"6\">" << xmlEscape(sampleNote(run)) << "</text>\n";
  for (size_t k = 0; k < run.sizes.size(); ++k) {
    const auto st = detail::sizeStyle(k);
    const double y = 17 + 7 * static_cast<double>(k);
    os << "<g class=\"legend\" data-size=\"" << xmlEscape(run.sizes[k])
       << "\"><line x1=\"30\" y1=\"" << fixed(y - 1.5, 2) << "\" x2=\"45\" y2=\""
       << fixed(y - 1.5, 2) << "\" stroke=\"" << st.svgColour << "\" stroke-width=\""
       << (k == sample ? "1.2" : "0.4") << "\"" << (st.dashed ? " stroke-dasharray=\"4 2\"" : "")
       << "/><text x=\"48\" y=\"" << fixed(y, 2) << "\" font-size=\"5\">size "
       << xmlEscape(run.sizes[k]) << (k == sample ? " (sample)" : "") << "</text></g>\n";
  }
  const auto& panels = run.patterns.front().panels;
  for (size_t i = 0; i < panels.size(); ++i) {
    const Point2 off = sh.offsets[i];
    os << "<g class=\"piece\" id=\"" << xmlEscape(panels[i].name) << "\">\n";
    // Sample last, so that it lies on top.
    std::vector<size_t> order;
    for (size_t k = 0; k < run.sizes.size(); ++k)
      if (k != sample)
        order.push_back(k);
    order.push_back(sample);
    for (size_t k : order) {
      const auto st = detail::sizeStyle(k);
      const Polyline o = aligned(run, k, i);
      os << "<polygon data-size=\"" << xmlEscape(run.sizes[k]) << "\""
         << (k == sample ? " data-sample=\"1\"" : "") << " stroke=\"" << st.svgColour
         << "\" stroke-width=\"" << (k == sample ? "1.2" : "0.4") << "\""
         << (st.dashed ? " stroke-dasharray=\"4 2\"" : "") << " points=\"";
      for (size_t j = 0; j < o.size(); ++j)
        os << (j ? " " : "") << pt(o[j] + off);
      os << "\"/>\n";
    }
    const auto& g = run.patterns[sample].panels[i].grainline;
    os << "<line class=\"grain\" stroke=\"#111\" stroke-width=\"0.4\" x1=\""
       << fixed((g.start + off).x() * 10, 2) << "\" y1=\"" << fixed((g.start + off).y() * 10, 2)
       << "\" x2=\"" << fixed((g.end + off).x() * 10, 2) << "\" y2=\""
       << fixed((g.end + off).y() * 10, 2) << "\"/>\n";
    const Point2 at = nameAt(run, i, sh);
    os << "<text x=\"" << fixed(at.x() * 10, 2) << "\" y=\"" << fixed(at.y() * 10, 2)
       << "\" font-size=\"6\">" << xmlEscape(pieceTitle(panels[i].name)) << "</text>\n</g>\n";
  }
  os << "</svg>\n";
  return os.str();
}

std::string nestedGradingPdf(const GradedRun& run) {
  checkRun(run);
  const size_t sample = sampleIndex(run);
  const double header = 2.0 + 0.7 * static_cast<double>(run.sizes.size());
  const NestSheet sh = nestSheet(run, header);
  std::ostringstream cs;
  cs << "1 0 0 1 0 " << fixed(sh.heightCm * detail::kPtPerCm, 3) << " cm 1 J 1 j 0 g\n";
  cs << detail::pdfText({3.0, 1.0}, 10, sampleNote(run));
  auto style = [&](size_t k) {
    const auto st = detail::sizeStyle(k);
    return fixed(st.r, 3) + " " + fixed(st.g, 3) + " " + fixed(st.b, 3) + " RG " +
           (k == sample ? "2.5 w " : "0.7 w ") + (st.dashed ? "[6 3] 0 d\n" : "[] 0 d\n");
  };
  for (size_t k = 0; k < run.sizes.size(); ++k) {
    const double y = 1.7 + 0.7 * static_cast<double>(k);
    cs << style(k) << detail::pdfPath({{3.0, y - 0.15}, {4.5, y - 0.15}}, false) << "0 g "
       << detail::pdfText({4.8, y}, 9, "size " + run.sizes[k] + (k == sample ? " (sample)" : ""));
  }
  const auto& panels = run.patterns.front().panels;
  for (size_t i = 0; i < panels.size(); ++i) {
    const Point2 off = sh.offsets[i];
    auto moved = [&](const Polyline& pl) {
      Polyline out;
      for (const auto& q : pl)
        out.push_back(q + off);
      return out;
    };
    for (size_t k = 0; k < run.sizes.size(); ++k)
      if (k != sample)
        cs << style(k) << detail::pdfPath(moved(aligned(run, k, i)), true);
    cs << style(sample) << detail::pdfPath(moved(aligned(run, sample, i)), true);
    const auto& g = run.patterns[sample].panels[i].grainline;
    cs << "[] 0 d 0 G 0.6 w " << detail::pdfPath(moved({g.start, g.end}), false) << "0 g "
       << detail::pdfText(nameAt(run, i, sh), 10, pieceTitle(panels[i].name));
  }
  detail::PdfDocument doc;
  doc.addPage(sh.widthCm, sh.heightCm, cs.str());
  return doc.bytes(sampleNote(run));
}

std::string nestedGradingDxf(const GradedRun& run) {
  checkRun(run);
  const size_t sample = sampleIndex(run);
  const NestSheet sh = nestSheet(run, 2.0 + 0.7 * static_cast<double>(run.sizes.size()));
  std::vector<detail::DxfLayer> layers = {{"GRAIN", 7, "CONTINUOUS"}, {"TEXT", 7, "CONTINUOUS"}};
  for (size_t k = 0; k < run.sizes.size(); ++k) {
    const auto st = detail::sizeStyle(k);
    layers.push_back({"SIZE_" + detail::blockName("", run.sizes[k]).substr(1), st.aci,
                      st.dashed ? "DASHED" : "CONTINUOUS"});
  }
  detail::DxfR12 d(layers);
  d.text("TEXT", {3.0, 1.0}, 5.0, sampleNote(run));
  for (size_t k = 0; k < run.sizes.size(); ++k)
    d.text("TEXT", {3.0, 1.7 + 0.7 * static_cast<double>(k)}, 4.0,
           layers[2 + k].name + ": size " + run.sizes[k] + (k == sample ? " (sample)" : ""));
  const auto& panels = run.patterns.front().panels;
  for (size_t i = 0; i < panels.size(); ++i) {
    const Point2 off = sh.offsets[i];
    for (size_t k = 0; k < run.sizes.size(); ++k) {
      Polyline o;
      for (const auto& q : aligned(run, k, i))
        o.push_back(q + off);
      d.polyline(layers[2 + k].name, o, true);
    }
    const auto& g = run.patterns[sample].panels[i].grainline;
    d.line("GRAIN", g.start + off, g.end + off);
    d.text("TEXT", nameAt(run, i, sh), 5.0, pieceTitle(panels[i].name));
  }
  return d.finish();
}

}  // namespace garmcap::drafts
