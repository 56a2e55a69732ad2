// Elliptic cross-section of a hair fibre (the paper's section 2.1 and footnote 1).
#pragma once

#include <string>

namespace ringlet {

/// An elliptic cross-section with semi-axes a >= b (metres).
///
/// Convention: the major semi-axis a lies along the material axis n1, the minor semi-axis b along n2.
/// Bending about n1 (curvature kappa1) is bending about the major axis, like a ruler bent about its
/// width: the soft direction, I1 = pi a b^3 / 4 <= I2 = pi a^3 b / 4 (I_X = integral of y^2 dA over
/// the ellipse x^2/a^2 + y^2/b^2 <= 1).
/// The mean radius r = sqrt(a b) keeps the area pi r^2 of the circle of the same radius.
struct CrossSection {
  double a = 0.0;  ///< major semi-axis, along n1 (m)
  double b = 0.0;  ///< minor semi-axis, along n2 (m)

  /// Area pi a b (m^2).
  double Area() const;
  /// Second moment of area about n1, pi a b^3 / 4 (m^4): the soft bending direction.
  double I1() const;
  /// Second moment of area about n2, pi a^3 b / 4 (m^4): the stiff bending direction.
  double I2() const;
  /// Saint-Venant torsion constant of the ellipse, pi a^3 b^3 / (a^2 + b^2) (m^4).
  double J() const;
  /// Eccentricity sqrt(1 - b^2/a^2) in [0, 1) (the paper's "mathematical definition").
  double Eccentricity() const;
  /// Ellipticity a/b >= 1 (the ratio of diameters dermatologists measure).
  double Ellipticity() const;
  /// Mean radius sqrt(a b) (m).
  double MeanRadius() const;
};

/// Section of mean radius r (m) and eccentricity e in [0, 1): b/a = sqrt(1 - e^2), a b = r^2.
CrossSection SectionFromEccentricity(double mean_radius, double eccentricity);

/// Section of mean radius r (m) and ellipticity a/b >= 1, a b = r^2.
CrossSection SectionFromEllipticity(double mean_radius, double ellipticity);

/// True when a >= b > 0 and both are finite; otherwise says why.
bool IsValid(const CrossSection& section, std::string* why);

}  // namespace ringlet
