// Validation of material constants.
#include "ringlet/material.h"

#include <cmath>

namespace ringlet {

bool IsValid(const Material& material, std::string* why) {
  if (!(std::isfinite(material.young_modulus) && material.young_modulus > 0.0)) {
    if (why) *why = "young_modulus must be a finite number > 0 (Pa)";
    return false;
  }
  if (!(std::isfinite(material.poisson_ratio) && material.poisson_ratio > -1.0 &&
        material.poisson_ratio <= 0.5)) {
    if (why) *why = "poisson_ratio must be a finite number in (-1, 0.5]";
    return false;
  }
  if (!(std::isfinite(material.density) && material.density >= 0.0)) {
    if (why) *why = "density must be a finite number >= 0 (kg/m^3)";
    return false;
  }
  return true;
}

}  // namespace ringlet
