#pragma once
// Private: a minimal PDF 1.4 document (uncompressed vector content streams, base-14 Helvetica
// as /F1) shared by the pattern PDF writers (tiled pattern, nested grading, marker).

#include <string>
#include <vector>

#include "garmcap/drafts/pattern.h"

namespace garmcap::drafts::detail {

inline constexpr double kPtPerCm = 72.0 / 2.54;

/// PDF literal string: ( ) and \ escaped, anything outside printable ASCII as '?' (base-14
/// fonts read no UTF-8).
std::string pdfString(const std::string& s);

/// Content-stream coordinates of a sheet point: sheet cm with y DOWN, origin at the top-left of
/// the sheet, to points with y UP, origin at the same corner (the page's transform places it).
std::string pdfPoint(const Point2& sheetCm);

/// "x y m x y l ... S" (or "h S" when closed) for a polyline in sheet cm.
std::string pdfPath(const Polyline& sheetCm, bool closed);

/// Text at a sheet point (baseline start), size in points.
std::string pdfText(const Point2& sheetCm, double sizePt, const std::string& s);

class PdfDocument {
 public:
  /// Adds a page of the given size in cm with its content stream.
  void addPage(double widthCm, double heightCm, const std::string& content);
  size_t pageCount() const { return pages_.size(); }
  /// The whole file; `title` goes into the document information.
  std::string bytes(const std::string& title) const;

 private:
  struct Page {
    double widthCm, heightCm;
    std::string content;
  };
  std::vector<Page> pages_;
};

}  // namespace garmcap::drafts::detail
