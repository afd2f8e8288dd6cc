// A minimal PDF 1.4 writer; see pdf_document.h.
#include "pdf_document.h"

#include <cstdio>

#include "export_util.h"

namespace garmcap::drafts::detail {

std::string pdfString(const std::string& s) {
  std::string out = "(";
  for (unsigned char c : s) {
    if (c == '(' || c == ')' || c == '\\') {
      out += '\\';
      out += static_cast<char>(c);
    } else if (c >= 32 && c < 127) {
      out += static_cast<char>(c);
    } else {
      out += '?';
    }
  }
  return out + ")";
}

std::string pdfPoint(const Point2& p) {
  return fixed(p.x() * kPtPerCm, 3) + " " + fixed(-p.y() * kPtPerCm, 3);
}

std::string pdfPath(const Polyline& pl, bool closed) {
  std::string s;
  for (size_t k = 0; k < pl.size(); ++k)
    s += pdfPoint(pl[k]) + (k ? " l\n" : " m\n");
  return s + (closed ? "h S\n" : "S\n");
}

std::string pdfText(const Point2& at, double sizePt, const std::string& s) {
  return "BT /F1 " + fixed(sizePt, 1) + " Tf " + pdfPoint(at) + " Td " + pdfString(s) + " Tj ET\n";
}

void PdfDocument::addPage(double widthCm, double heightCm, const std::string& content) {
  pages_.push_back({widthCm, heightCm, content});
}

std::string PdfDocument::bytes(const std::string& title) const {
  // Objects: 1 catalog, 2 pages, 3 font, then (content, page) per page.
  std::vector<std::string> objects = {"", "",
                                      "<< /Type /Font /Subtype /Type1 /BaseFont /Helvetica >>"};
  std::string kids;
  for (const auto& p : pages_) {
    objects.push_back("<< /Length " + std::to_string(p.content.size()) + " >>\nstream\n" +
                      p.content + "endstream");
    const int contentId = static_cast<int>(objects.size());
    objects.push_back("<< /Type /Page /Parent 2 0 R /MediaBox [0 0 " +
                      fixed(p.widthCm * kPtPerCm, 3) + " " + fixed(p.heightCm * kPtPerCm, 3) +
                      "] /Resources << /Font << /F1 3 0 R >> >> /Contents " +
                      std::to_string(contentId) + " 0 R >>");
    kids += std::to_string(objects.size()) + " 0 R ";
  }
  objects[0] = "<< /Type /Catalog /Pages 2 0 R >>";
  objects[1] =
      "<< /Type /Pages /Kids [" + kids + "] /Count " + std::to_string(pages_.size()) + " >>";
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
  out += "trailer\n<< /Size " + std::to_string(objects.size() + 1) +
         " /Root 1 0 R /Info << /Title " + pdfString(title) +
         " /Producer (GarmCap Station) >> >>\nstartxref\n" + std::to_string(xref) + "\n%%EOF\n";
  return out;
}

}  // namespace garmcap::drafts::detail
