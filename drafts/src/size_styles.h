#pragma once
// Private: one colour and line style per size for drawings that superimpose or mix sizes
// (nested grading, markers): the same size gets the same look in SVG, PDF and DXF.

#include <array>
#include <cstddef>
#include <string>

namespace garmcap::drafts::detail {

struct SizeStyle {
  const char* svgColour;  // "#rrggbb"
  double r, g, b;         // PDF DeviceRGB, 0..1
  int aci;                // DXF AutoCAD colour index
  bool dashed;            // second round of colours: dashed, so that no two sizes look alike
};

inline SizeStyle sizeStyle(std::size_t i) {
  // Eight colours distinguishable in print and on screen (no yellow on white).
  static constexpr std::array<SizeStyle, 8> kColours{{
      {"#1f77b4", 0.122, 0.467, 0.706, 5, false},
      {"#d62728", 0.839, 0.153, 0.157, 1, false},
      {"#2ca02c", 0.173, 0.627, 0.173, 3, false},
      {"#9467bd", 0.580, 0.404, 0.741, 6, false},
      {"#ff7f0e", 1.000, 0.498, 0.055, 30, false},
      {"#17becf", 0.090, 0.745, 0.812, 4, false},
      {"#8c564b", 0.549, 0.337, 0.294, 34, false},
      {"#7f7f7f", 0.498, 0.498, 0.498, 8, false},
  }};
  SizeStyle s = kColours[i % kColours.size()];
  s.dashed = (i / kColours.size()) % 2 == 1;
  return s;
}

}  // namespace garmcap::drafts::detail
