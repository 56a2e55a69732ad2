// Wisps: child strands generated procedurally around a physically solved master strand (the
// paper's section 3, after Choe & Ko 2005). Model, formulas and sources: docs/wisps.md.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "ringlet/cross_section.h"
#include "ringlet/hair_curves.h"
#include "ringlet/obstacle.h"
#include "ringlet/strand_geometry.h"

namespace ringlet {

/// Packing fraction of a random close packing of equal disks in the plane, 0.82 (Berryman,
/// "Random close packing of hard spheres and disks", Phys. Rev. A 27, 1053 (1983), table I:
/// 0.82 +- 0.02). The cross-section of a bundle of parallel fibres is such a disk packing.
inline constexpr double kRandomPackingFraction2D = 0.82;

/// Largest curliness that Curliness and HelixCurliness return (a strand whose end-to-end distance
/// is below L / sqrt(1 + 100^2) ~ L/100, or a planar curl, counts as this curly).
inline constexpr double kMaxCurliness = 100.0;

/// Curliness of a natural helix of curvature vector Omega0 = (kappa1, kappa2, tau) (1/m):
/// tan(alpha) = kappa / |tau|, kappa = sqrt(kappa1^2 + kappa2^2), alpha the angle between the fibre
/// and the helix axis. Equivalently the ratio of the helix circumference 2 pi R to its pitch P
/// (R = kappa / |Omega|^2, P = 2 pi |tau| / |Omega|^2). 0 for a straight or purely twisted fibre,
/// capped at kMaxCurliness (a planar curl, tau = 0, is infinitely curly). Dimensionless.
double HelixCurliness(const Vec3& natural_curvature);

/// Curliness of a sampled strand from its shape: sqrt((L / d)^2 - 1), L its arc length and d its
/// end-to-end distance (m). For a helix of whole turns d is the axial advance L cos(alpha), so this
/// is tan(alpha) again, the same number as HelixCurliness; 0 for a straight strand; capped at
/// kMaxCurliness. Needs >= 2 points.
double Curliness(const FramedCentreline& strand);

/// Radius of a wisp of N fibres of radius r (m) and curliness c (dimensionless, as above), packed
/// with area fraction phi in (0, 1]:
///   r_w = r (1 + sqrt((N - 1) sqrt(1 + c^2) / phi))      (m).
/// Derivation (docs/wisps.md): the N - 1 fibres around a central one put their centres in a disk
/// of radius r_w - r, each taking an area pi r^2 / phi of the section; a fibre inclined at alpha
/// to the wisp axis cuts the section in an ellipse of area pi r^2 / cos(alpha) = pi r^2
/// sqrt(1 + c^2) (the ideal helical yarn of Hearle, Grosberg & Backer, "Structural Mechanics of
/// Fibers, Yarns, and Fabrics", 1969, ch. 4), so curly wisps are thicker. Limits: N = 1 gives r;
/// large N gives r sqrt(N sqrt(1 + c^2) / phi). For N <= 7 it is never below the optimal
/// (densest) enclosing radius of N disks, as a random packing must not be.
double WispRadius(int strands, double fibre_radius, double curliness,
                  double packing_fraction = kRandomPackingFraction2D);

/// How child strands are drawn around a master. Defaults give a slightly clumped wisp of 100
/// strands with small variations.
struct WispOptions {
  /// Strands generated per master, N >= 1 (counting the master itself if include_master).
  int strands_per_wisp = 100;
  /// Wisp radius r_w at the root (m); 0 means automatic: WispRadius(N, mean fibre radius,
  /// Curliness(master), packing_fraction).
  double wisp_radius = 0.0;
  /// Area packing fraction phi in (0, 1] used by the automatic radius (dimensionless).
  double packing_fraction = kRandomPackingFraction2D;
  /// Radius profile r_w(s) = r_w (root_scale + (tip_scale - root_scale) (s/L)^profile_exponent),
  /// s the arc length along the master, L its length. root_scale > 1 spreads the roots over a
  /// wider disk, tip_scale < 1 clumps the strands toward the tip (the cone-shaped wisps of Choe &
  /// Ko). Both > 0, dimensionless.
  double root_scale = 1.0;
  double tip_scale = 0.5;
  /// Exponent of the profile, > 0 (1 = linear in s).
  double profile_exponent = 1.0;
  /// Distance distribution in the section: rho = r_w(s) u^(gamma/2), theta = 2 pi v with u, v
  /// uniform in [0, 1). gamma = 1 is uniform in the disk (E[rho^2] = r_w^2 / 2); gamma > 1
  /// concentrates strands near the master (E[rho^2] = r_w^2 / (gamma + 1)). > 0.
  double distance_exponent = 1.0;
  /// Amplitude (m) of a smooth random displacement of each child, expressed in the master's
  /// (n1, n2) plane: a sum of three sinusoids of wavelengths L, L/2, L/3 with random phases and
  /// weights; its norm never exceeds jitter. >= 0.
  double jitter = 0.0;
  /// Child length L_c = L (1 - length_variation u), u uniform in [0, 1): never longer than the
  /// master. In [0, 1).
  double length_variation = 0.1;
  /// Frizz: a circular wobble of the child in the master's (n1, n2) plane, radius growing
  /// linearly from 0 at the root to frizz_amplitude at the tip (m, >= 0), at frizz_frequency
  /// turns per metre of arc length (1/m, >= 0; each child draws its own in [0.75, 1.25] times it
  /// and a random phase).
  double frizz_amplitude = 0.0;
  double frizz_frequency = 50.0;
  /// Points per child strand, equally spaced in arc length, root and tip included (>= 2).
  int points_per_strand = 32;
  /// Width taper toward the tip over the last tip_taper_length of each child (WidthTaperFactor):
  /// the diameter is 2 r up to arc length L_c - l_t and falls linearly to 2 r (1 - tip_taper) at
  /// the tip, with l_t = min(tip_taper_length, L_c) and r the mean fibre radius. tip_taper in
  /// [0, 1) (0: no taper), tip_taper_length > 0 (m; >= the strand length: the whole strand).
  /// Defaults: an uncut hair's distal end narrows over its last 6-8 cm (Hutchinson & Thompson,
  /// "The cross-sectional size and shape of human terminal scalp hair", Br. J. Dermatol. 136,
  /// 1997: from the tip toward the scalp the size increases over ~6-8 cm); we take 6 cm and a tip
  /// at 1/5 of the diameter (a pointed end at the strands' sampling; cut hair has blunter ends:
  /// lower tip_taper).
  double tip_taper = 0.8;
  double tip_taper_length = 0.06;
  /// If true the first strand of each wisp is the master itself (full length, no offset).
  bool include_master = true;

  /// True when every field is in range; otherwise says which field and what was expected.
  bool IsValid(std::string* why) const;
};

/// The width factor of WispOptions' tip taper at arc length s of a child of length L_c (m):
/// 1 for s <= L_c - l_t, 1 - tip_taper (s - (L_c - l_t)) / l_t beyond, l_t =
/// min(tip_taper_length, L_c). A child's width at s is 2 r times this.
double WidthTaperFactor(const WispOptions& options, double s, double child_length);

/// The radius profile factor root_scale + (tip_scale - root_scale) (s/L)^profile_exponent for
/// arc length fraction s/L in [0, 1] (dimensionless).
double WispRadiusScale(const WispOptions& options, double fraction);

/// Checks that a master is usable: >= 2 samples, arrays of equal size, finite points, proper
/// rotation frames, arc lengths starting at 0 and strictly increasing. Says what is wrong.
bool IsValidMaster(const FramedCentreline& master, std::string* why);

/// Appends one wisp (options.strands_per_wisp strands of options.points_per_strand points each)
/// around master to curves. Child k, of length L_k, at arc length s in [0, L_k]:
///   x(s) = r(s) + Q(s) [ r_w scale(s/L) (o1 e1 + o2 e2) + j(s) + f(s) ]
/// with r(s), Q(s) the master's point and frame (linearly interpolated between its samples), e1,
/// e2 the first two material axes (so the offset is o1 n1 + o2 n2 in world coordinates),
/// scale = WispRadiusScale, (o1, o2) drawn once per child in the unit disk with the distance
/// distribution of the options, j the jitter and f the frizz (material (n1, n2) plane). Because
/// the offset is constant in the material frame the children turn with the master's curls.
/// wisp_radius is r_w (m, >= 0; 0 collapses the wisp onto the master; pass ResolveWispRadius).
/// The random stream is SplitMix64 seeded with seed. If obstacle is not null, points whose signed
/// distance is below the fibre radius r are pushed out along the distance gradient (up to four
/// projections x += (r - d) grad d; one is exact for a sphere). Master and options must be valid.
void AppendWisp(const FramedCentreline& master, const CrossSection& section, double wisp_radius,
                const WispOptions& options, std::uint64_t seed, const Obstacle* obstacle,
                HairCurves* curves);

/// The wisp radius AppendWisp uses for master with these options: options.wisp_radius if > 0,
/// else WispRadius(N, section.MeanRadius(), Curliness(master), options.packing_fraction) (m).
double ResolveWispRadius(const FramedCentreline& master, const CrossSection& section,
                         const WispOptions& options);

/// The length of each strand of a wisp relative to its master's, L_k / L in (0, 1] (1 for the
/// master itself when include_master): the fractions AppendWisp draws from the stream seeded
/// with seed, replayed without building the strands. Options must be valid.
std::vector<double> WispLengthFractions(const WispOptions& options, std::uint64_t seed);

/// The random-stream seed of wisp `index` for a head seeded with `seed`: a SplitMix64 hash of
/// both, so each wisp's strands depend only on (seed, index).
std::uint64_t WispSeed(std::uint64_t seed, std::uint64_t index);

/// Generates the wisps of a whole head in parallel (TBB, across masters) and returns them in
/// master order: wisp i (strands i N .. i N + N - 1) uses WispSeed(seed, i), so the output is
/// bit-identical whatever the thread count. sections has one entry per master or a single one
/// shared by all. wisp_radii, when not null, gives each wisp's radius r_w (m, one per master),
/// overriding options.wisp_radius and the automatic radius. per_master_options, when not null,
/// gives each wisp its own options (one per master, each with options' strands_per_wisp and
/// points_per_strand; the brushes' clump and frizz, HairstyleMasters). On bad input (invalid
/// options, master, section or radius, size mismatch) returns empty curves and, if why is not
/// null, a one-line message naming the field.
HairCurves GenerateWisps(const std::vector<FramedCentreline>& masters,
                         const std::vector<CrossSection>& sections, const WispOptions& options,
                         std::uint64_t seed, const Obstacle* obstacle = nullptr,
                         std::string* why = nullptr,
                         const std::vector<double>* wisp_radii = nullptr,
                         const std::vector<WispOptions>* per_master_options = nullptr);

}  // namespace ringlet
