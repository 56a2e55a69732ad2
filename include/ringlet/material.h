// Isotropic linear-elastic material of a hair fibre, with the paper's defaults (section 4, [Rob02]).
#pragma once

#include <string>

namespace ringlet {

/// Material constants of a fibre, SI units. Defaults are the paper's: E = 10 GPa, sigma = 0.3,
/// rho = 1300 kg/m^3 (Robbins 2002, quoted in section 4 of Bertails et al. 2005).
struct Material {
  double young_modulus = 10e9;  ///< Young's modulus E (Pa)
  double poisson_ratio = 0.3;   ///< Poisson's ratio sigma (dimensionless), in (-1, 0.5]
  double density = 1300.0;      ///< volumic mass rho (kg/m^3)

  /// Shear modulus mu = E / (2 (1 + sigma)) (Pa), the paper's footnote 2.
  double ShearModulus() const { return young_modulus / (2.0 * (1.0 + poisson_ratio)); }
};

/// True when E > 0, rho >= 0, -1 < sigma <= 0.5 and all are finite; otherwise says why.
bool IsValid(const Material& material, std::string* why);

}  // namespace ringlet
