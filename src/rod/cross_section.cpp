// Elliptic cross-section (paper section 2.2: I1, I2, J depend on the eccentricity e).
#include "ringlet/cross_section.h"

#include <cmath>
#include <numbers>

namespace ringlet {

double CrossSection::Area() const { return std::numbers::pi * a * b; }
double CrossSection::I1() const { return std::numbers::pi * a * b * b * b / 4.0; }
double CrossSection::I2() const { return std::numbers::pi * a * a * a * b / 4.0; }
double CrossSection::J() const {
  // Saint-Venant torsion constant of an elliptic shaft (Timoshenko & Goodier, Theory of
  // Elasticity, section 105): J = pi a^3 b^3 / (a^2 + b^2); a = b = r gives the polar moment.
  return std::numbers::pi * a * a * a * b * b * b / (a * a + b * b);
}
double CrossSection::Eccentricity() const { return std::sqrt(1.0 - (b * b) / (a * a)); }
double CrossSection::Ellipticity() const { return a / b; }
double CrossSection::MeanRadius() const { return std::sqrt(a * b); }

CrossSection SectionFromEccentricity(double mean_radius, double eccentricity) {
  // b/a = sqrt(1 - e^2) and a b = r^2.
  const double ratio = std::sqrt(1.0 - eccentricity * eccentricity);
  return CrossSection{mean_radius / std::sqrt(ratio), mean_radius * std::sqrt(ratio)};
}

CrossSection SectionFromEllipticity(double mean_radius, double ellipticity) {
  // a/b = ellipticity and a b = r^2.
  return CrossSection{mean_radius * std::sqrt(ellipticity), mean_radius / std::sqrt(ellipticity)};
}

bool IsValid(const CrossSection& section, std::string* why) {
  if (!(std::isfinite(section.a) && std::isfinite(section.b) && section.b > 0.0 &&
        section.a >= section.b)) {
    if (why) *why = "cross-section semi-axes must be finite with a >= b > 0";
    return false;
  }
  return true;
}

}  // namespace ringlet
