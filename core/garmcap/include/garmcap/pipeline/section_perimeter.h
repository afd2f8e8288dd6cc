#pragma once
// Perimeters of the garment sections the measurer models (docs/measurement_model.md, "The
// measurement model"): an ellipse as wide and deep as the section, and the convex hull of that
// ellipse with a fin of cloth standing out at one end of its width (a loose bodice's side seam).

namespace garmcap::pipeline {

/// Perimeter of an ellipse of full width w and depth d (Ramanujan's first approximation, within
/// 0.01 % for the ratios of a body's sections).
double ellipsePerimeter(double w, double d);

/// What a fin of length f standing out from one end of an ellipse's width (full width w, depth
/// d) adds to the perimeter of their convex hull: the two tangents from the fin's tip to the
/// ellipse less the arc between their feet. 0 for f <= 0 or a degenerate ellipse.
double finHullGain(double w, double d, double f);

}  // namespace garmcap::pipeline
