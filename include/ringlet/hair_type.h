// Hair types: measured fibre geometry by origin and curl, and per-strand random variation.
//
// Every preset number and its source is listed in docs/hair-types.md and next to the table in
// src/groom/hair_type.cpp. Origin sets the section (mean radius, ellipticity), curl sets the natural
// helix (curl radius and pitch); the material is the paper's for all (section 4, [Rob02]).
#pragma once

#include <cstdint>
#include <span>
#include <string>
#include <string_view>

#include "ringlet/cross_section.h"
#include "ringlet/material.h"
#include "ringlet/math.h"
#include "ringlet/strand_model.h"

namespace ringlet {

/// Curvature and torsion of a helix (1/m).
struct HelixCurvature {
  double curvature = 0.0;  ///< kappa >= 0 (1/m)
  double torsion = 0.0;    ///< tau (1/m); > 0 right-handed, < 0 left-handed
};

/// Radius and pitch of a helix (m).
struct HelixShape {
  double radius = 0.0;  ///< R >= 0 (m); +infinity for a straight line
  double pitch = 0.0;   ///< p (m), the rise per turn; > 0 right-handed, < 0 left-handed
};

/// kappa and tau of the helix of radius R >= 0 and pitch p (m): with c = p / (2 pi),
///   kappa = R / (R^2 + c^2),  tau = c / (R^2 + c^2)
/// (the helix r(t) = (R cos t, R sin t, c t); e.g. do Carmo, Differential Geometry of Curves and
/// Surfaces, section 1-5, exercise 1). R = +infinity gives the straight line (0, 0); R = 0 with
/// p != 0 is a straight twisted rod (0, 2 pi / p). R = p = 0 is not a helix: returns NaNs.
HelixCurvature CurvatureFromHelix(double radius, double pitch);

/// The inverse: R = kappa / (kappa^2 + tau^2), p = 2 pi tau / (kappa^2 + tau^2) for kappa >= 0.
/// kappa = tau = 0 (a straight, untwisted line) gives R = p = +infinity.
HelixShape HelixFromCurvature(double curvature, double torsion);

/// A hair type: population means and per-strand standard deviations, SI units.
///
/// Per-strand sampling (SampleStrand): the mean radius, the excess ellipticity a/b - 1, the curl
/// radius and the pitch factor are log-normal with the given means and standard deviations, so they
/// stay positive (a/b >= 1) and their means and standard deviations are exactly the listed ones.
struct HairType {
  std::string origin;  ///< "asian", "caucasian" or "african"
  std::string curl;    ///< "straight", "wavy", "curly" or "kinky"

  double mean_radius = 0.0;      ///< mean over strands of r = sqrt(a b) (m)
  double mean_radius_std = 0.0;  ///< strand-to-strand standard deviation of r (m)
  double ellipticity = 1.0;      ///< mean a/b of the section (major/minor diameter), >= 1
  double ellipticity_std = 0.0;  ///< standard deviation of a/b

  /// Mean helix radius R of the natural curl (m); +infinity for straight hair.
  double curl_radius = 0.0;
  double curl_radius_std = 0.0;  ///< standard deviation of R (m); unused when straight
  /// Mean pitch p of the natural helix (m); a strand's pitch is its R times curl_pitch/curl_radius
  /// times a log-normal factor of mean 1, keeping the helix angle about constant.
  double curl_pitch = 0.0;
  double curl_pitch_rel_std = 0.0;  ///< relative standard deviation of that factor
  /// Straight hair only: kappa1^0 ~ Normal(0, this) (1/m), no twist; "straight" fibres have large
  /// but finite curl radii (Nagase et al. 2008).
  double straight_curvature_std = 0.0;
  /// Helix handedness: +1 right, -1 left, 0 each strand picks one with probability 1/2.
  int handedness = 0;

  Material material;              ///< E, Poisson's ratio, density (the same for every strand)
  double length_factor_std = 0.0;  ///< standard deviation of the length factor (mean 1)

  /// True when curl_radius is +infinity.
  bool IsStraight() const;
  /// (kappa1^0, kappa2^0, tau^0) of the mean helix (1/m): the curl bends about n1 (kappa2^0 = 0).
  Vec3 MeanNaturalCurvature() const;
};

/// Checks every field (finite where needed, positive radii, ellipticity >= 1, valid material).
bool IsValid(const HairType& type, std::string* why);

/// The valid origin names, in table order: asian, caucasian, african.
std::span<const std::string_view> HairOrigins();
/// The valid curl names, straightest first: straight, wavy, curly, kinky.
std::span<const std::string_view> CurlTypes();
/// The usual curl of an origin (asian -> straight, caucasian -> wavy, african -> kinky), or an
/// empty view for an unknown origin.
std::string_view DefaultCurl(std::string_view origin);

/// The preset for (origin, curl); an empty curl picks DefaultCurl(origin). Names are lower case.
/// Unknown names return false with `why` listing the valid ones.
bool FindHairType(std::string_view origin, std::string_view curl, HairType* type,
                  std::string* why);

/// One strand's parameters drawn from a hair type.
struct StrandParameters {
  CrossSection section;                   ///< semi-axes a >= b (m), major axis along n1
  Vec3 natural_curvature = Vec3::Zero();  ///< (kappa1^0, kappa2^0, tau^0) (1/m)
  Material material;                      ///< the type's material
  double length_factor = 1.0;             ///< multiply the hairstyle's length by this (> 0)
  /// The natural helix (R, p) (m). A straight-type strand is a planar arc: R = 1/|kappa1^0|
  /// (+infinity when kappa1^0 = 0), p = 0.
  HelixShape helix;
};

/// Draws strand `strand_index` of a hairstyle with this seed. Each (seed, index) has its own
/// random stream (groom/random.h), so the result does not depend on which other strands are drawn,
/// in which order or on how many threads. `type` must be valid.
StrandParameters SampleStrand(const HairType& type, uint64_t seed, uint64_t strand_index);

/// The section, material and natural curvature that inverse statics gives target strand
/// `strand_index` (`ringlet invert --hair-type`, ringlet.invert): for spec "ORIGIN" or
/// "ORIGIN/CURL" the hair type's SampleStrand with seed 1; for an empty spec the paper's
/// defaults (a circular 50-um fibre, Material{}, straight). Sets model->section, ->material and
/// ->natural_curvature. An unknown name returns false with `why` naming the valid ones.
bool ApplyInverseHairType(std::string_view spec, uint64_t strand_index, StrandModel* model,
                          std::string* why);

}  // namespace ringlet
