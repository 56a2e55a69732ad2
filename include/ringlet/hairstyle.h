// A full hairstyle (paper, section 3): body, scalp, hair type, master strands solved physically,
// wisps of strands around them, and hull layers for volume.
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <variant>
#include <vector>

#include "ringlet/body.h"
#include "ringlet/hair_curves.h"
#include "ringlet/hair_type.h"
#include "ringlet/scalp.h"
#include "ringlet/solve_strands.h"
#include "ringlet/statics.h"
#include "ringlet/strand_model.h"
#include "ringlet/wisp.h"

namespace ringlet {

/// Self-collisions by multiple layer hulls (Lee & Ko, "Natural hairstyle modeling and
/// animation", Graphical Models 63(2), 2001; the paper's section 3.1): every wisp is assigned a
/// layer by the position of its root, and layer l collides with the body inflated by l times
/// thickness. Roots near the crown get the outer layers, since their hair falls over the hair
/// rooted lower down: with polar angle theta of a root from the head's up axis and theta_max
/// the largest over all roots,
///   l = min(count - 1, floor(count (1 - theta / theta_max))).
/// count = 1 (or thickness = 0) turns the layers off: every wisp touches the bare body.
struct HullLayers {
  int count = 4;            ///< number of layers, >= 1
  double thickness = 0.004; ///< offset between consecutive layers (m), >= 0
};

/// The hull layer of a root at polar angle theta (rad) when the largest polar angle of all roots
/// is theta_max (rad, > 0): HullLayers' rule above.
int HullLayerOf(const HullLayers& layers, double polar_angle, double max_polar_angle);

/// The default solver options of a hairstyle's masters: SolveOptions with tolerance 1e-6 (a
/// moment mismatch a millionth of the largest moment, far below what can be seen; 1e-9 is for
/// validation), the automatic method and the stability certificate on (the exact Hessian's O(n)
/// factorization, about a fifth of a solve: every master's summary says whether it is a stable
/// equilibrium; "check_stability": false in the file turns it off).
SolveOptions GroomSolveOptions();

/// Most points of the generated strands, masters.count x wisps.strands_per_wisp x
/// wisps.points_per_strand: 2^28 (268 million; 80 times the 100,000-strand example). The
/// strands take 28 bytes per point (position, width, major axis: 7.5 GB at the limit) and the
/// text exports ~40 more per point each; HairCurves' int counts would allow 2^31 - 1.
inline constexpr long long kMaxHairPoints = 1LL << 28;

/// One master strand given explicitly (a masters file, docs/hairstyle-format.md "Explicit
/// masters"; written by `ringlet invert`, docs/inverse.md) instead of sampled from the scalp and
/// the hair type. What is not given is taken as for a sampled master i (BuildMasters).
struct ExplicitMaster {
  /// Root position r(0) on (or near) the scalp (m).
  Vec3 root_position = Vec3::Zero();
  /// Material frame at the root, world_from_material: columns (n1, n2, t), a proper rotation.
  Mat3 root_frame = Mat3::Identity();
  /// Segment lengths, root to tip (m), each > 0; their count is the master's segment count n.
  std::vector<double> segment_lengths;
  /// Section and material; absent: the hair type's for master i (SampleStrand).
  std::optional<CrossSection> section;
  std::optional<Material> material;
  /// The hair type's natural curl (kappa1^0, kappa2^0, tau^0) (1/m): the curvature of hair that
  /// grows (Grow) and of the wisp thickness; absent: the hair type's for master i, with
  /// BuildMasters' sign (kappa1^0 <= 0).
  std::optional<Vec3> natural_curvature;
  /// The rest shape per segment, 3n (1/m), or empty: natural_curvature on every segment
  /// (StrandModel::rest_curvatures).
  VecX rest_curvatures;
  /// Where the master's solve starts, 3n curvatures (1/m), or empty: the natural (rest) shape
  /// as for sampled masters. `ringlet invert` gives the target, so that the groom finds the
  /// inverted equilibrium itself rather than another one.
  VecX start_curvatures;
  /// Hull layer (>= 0, < layers.count); absent: HullLayerOf from the root's polar angle.
  std::optional<int> layer;
  /// Wisp radius r_w (m, >= 0); absent: as for a sampled master (wisps.wisp_radius, or
  /// WispRadius from the curliness of natural_curvature).
  std::optional<double> wisp_radius;
  /// The contact clearance without the hull-layer offset (m, >= 0): absent, r_w max(1,
  /// tip_scale) as for sampled masters. `ringlet invert` gives its --clearance.
  std::optional<double> clearance;
  /// Per-contact-sample shifts of the clearance (m), one per sample (segments x the hairstyle's
  /// contact samples per segment), or empty: none (ContactModel::support_offsets). `ringlet
  /// invert` gives the offsets with which the penalty reproduces the support forces it chose.
  std::vector<double> support_offsets;
};

/// Masters given explicitly by a masters file (Hairstyle::explicit_masters).
struct ExplicitMasters {
  /// The file as the hairstyle names it ("masters": {"file": ...}), relative to the hairstyle.
  std::string file;
  std::vector<ExplicitMaster> masters;
};

/// Most masters of a hairstyle: the largest masters.count, and the most masters a masters file
/// may list.
inline constexpr int kMaxMasters = 1000000;

/// Everything that defines a hairstyle; immutable once built (ParseHairstyle, or by hand).
struct Hairstyle {
  /// The body the hair collides with (spheres and meshes). Required.
  std::shared_ptr<const Body> body;
  /// Where the roots grow: a region of the head sphere, or chosen triangles of a body mesh.
  std::variant<SphereScalp, MeshScalp> scalp;
  /// Master roots: roots.count masters, Poisson-disk placed with roots.seed.
  RootSamplingOptions roots;
  /// Root tangents: tilt from the scalp normal toward a comb direction, optional parting.
  CombOptions comb;
  /// Fibre section, natural curl and material, with per-strand variation.
  HairType hair_type;
  /// Mean strand length before the per-strand length factor (m), > 0.
  double length = 0.25;
  /// Regional length (a layered cut, a fringe, a longer nape): when `regional_length` is true the
  /// mean length at a root of azimuth phi from the face (HeadCoordinates) replaces `length`:
  ///   L(phi) = a0 + a1 cos(phi) + a2 cos(2 phi)
  /// through L(0) = length_front (the fringe), L(+-pi/2) = length_side (over the ears) and
  /// L(pi) = length_back (the nape), the curve of the scalp's hairline (scalp.h). Each > 0 (m);
  /// L(phi) stays between the smallest and largest of the three when the side value lies
  /// between the others, and is checked > 0 at every azimuth otherwise.
  bool regional_length = false;
  double length_front = 0.25;
  double length_side = 0.25;
  double length_back = 0.25;
  /// The crown's length (m; 0 = none, else in (0, 10], only with regional_length): a root at
  /// polar angle theta from the head's up axis takes
  ///   L(phi, theta) = length_crown + (L(phi) - length_crown) min(1, theta / crown_polar_angle),
  /// so the hair of the crown, which falls over the back of the head, is cut to its own length
  /// while the hairline keeps L(phi) (a fringe stays a fringe; without it the top of the head
  /// takes the fringe's length and short, light strands there stand up). crown_polar_angle
  /// (rad, in (0, pi)) is the scalp's hairline_front (the reader sets it).
  double length_crown = 0.0;
  double crown_polar_angle = 1.047;
  /// Segments per master strand, >= 1.
  int segments = 20;
  /// Last/first segment-length ratio (>= 1); 0 selects RecommendedGradingRatio per strand.
  double grading = 0.0;
  /// Contact with the body: penalty stiffness (N/m^2, 0 = DefaultContactStiffness) and
  /// samples per segment.
  double contact_stiffness = 0.0;
  int contact_samples = 4;
  /// Hull layers for volume.
  HullLayers layers;
  /// Child strands around each master (strands_per_wisp, radius profile, jitter, ...).
  WispOptions wisps;
  /// Spread the children's roots over the master's share of the scalp: the root scale of the
  /// wisp profile is raised to (Poisson-disk radius of the masters) / (mean r_w), so that a
  /// full head has no bald gaps between wisps at the scalp (wisps.root_scale is a lower bound).
  bool spread_roots = true;
  /// Every strand a solved rod (issue 11): when true, each child strand of the wisps is itself
  /// solved as a Kirchhoff rod (its own root on the scalp, the master's root frame, section,
  /// material, natural curl and segment count; length the master's times the child's length
  /// fraction, WispLengthFractions; body contact with the clearance of one fibre plus its hull
  /// layer's offset), warm-started from the nearest solved strand of its wisp and certified like
  /// the masters (SolveChildren). File key:
  /// "wisps": {"children": "solved"} (default "procedural").
  bool solve_children = false;
  /// Centreline samples per master segment handed to the wisp generator (>= 1).
  int master_points_per_segment = 4;
  /// The solver of every master: GroomSolveOptions() unless the file says otherwise.
  SolveOptions solver = GroomSolveOptions();
  /// Seed of the per-strand variation and of the wisps (roots use roots.seed).
  std::uint64_t seed = 1;
  /// Gravitational acceleration (m/s^2), the same for every strand.
  Vec3 gravity = Vec3(0.0, 0.0, -9.81);
  /// Explicit masters (a masters file) instead of sampled ones; null = sampled. With them the
  /// roots, comb, length, segments and grading above are not used (the file has them); the
  /// scalp still gives the head coordinates of the roots (selections, hull layers) and, with
  /// roots.packing, the spacing that spread_roots uses: r = sqrt(packing A / N).
  std::shared_ptr<const ExplicitMasters> explicit_masters;

  /// Checks every field (and the parts' own IsValid); says which field and what was expected.
  bool IsValid(std::string* why) const;
};

/// The mean length (m) at a root of azimuth phi and polar angle theta (rad; HeadCoordinates):
/// `length`, or L(phi) with regional_length, blended toward length_crown when it is set.
double RegionalLength(const Hairstyle& style, double azimuth, double polar_angle);

/// The master strands of a hairstyle, ready to solve: roots and one StrandModel per root.
struct HairstyleMasters {
  std::vector<Root> roots;
  std::vector<StrandModel> models;
  std::vector<int> layers;         ///< hull layer of each master
  std::vector<double> wisp_radii;  ///< r_w of each master (m): WispRadius from the natural curl
  /// The contact clearance of each master without its hull-layer offset (m): r_w max(1,
  /// tip_scale), or an explicit master's clearance. The contact model's clearance is this plus
  /// layer x layers.thickness (styling.h, MasterClearance). Empty (a HairstyleMasters made by
  /// hand) means r_w max(1, tip_scale) for every master.
  std::vector<double> contact_radii;
  /// Where each master's solve starts: empty (every master from its natural shape) or one
  /// vector per master, each empty (natural shape) or 3n curvatures (explicit masters).
  std::vector<VecX> start_curvatures;
  WispOptions wisp_options;        ///< the hairstyle's wisp options with spread_roots applied
  /// Per-master wisp parameters set by the clump and frizz brushes (styling.h, Clump, Frizz):
  /// master i's wisp takes tip_scale x clump_factors[i] and frizz_amplitude =
  /// frizz_amplitudes[i] (m). Empty (BuildMasters): every wisp takes wisp_options as they are.
  std::vector<double> clump_factors;
  std::vector<double> frizz_amplitudes;
  RootSamplingSummary root_summary;
};

/// The wisp options of master i: wisp_options with the per-master clump factor and frizz
/// amplitude applied (HairstyleMasters; the same options, bit for bit, when both are empty).
WispOptions MasterWispOptions(const HairstyleMasters& masters, size_t i);

/// Samples the roots and builds the master models: strand i takes SampleStrand(hair_type, seed,
/// i) (section, natural curvature, material, length factor), segments graded as asked, root
/// frame from the comb, and a contact model with the body whose clearance is the wisp radius
/// r_w = WispRadius(strands_per_wisp, fibre radius, Curliness of the natural shape) (the
/// paper's wisp thickness, so that the children stay outside the body) plus the layer offset.
/// Returns false (with why) for an invalid hairstyle or a scalp on which no root fits.
/// With explicit masters (Hairstyle::explicit_masters) no root is sampled: master i is the
/// file's i-th (ExplicitMaster: what it leaves out is taken as above), its Root has the file's
/// position and frame, the head coordinates of the position, the outward normal from the head
/// centre, and root_summary counts the file's masters with disk_radius sqrt(packing A / N).
bool BuildMasters(const Hairstyle& style, HairstyleMasters* masters, std::string* why);

/// What grooming did.
struct GroomSummary {
  int masters = 0;             ///< master strands solved
  int strands = 0;             ///< strands generated (wisps, masters included)
  int points = 0;              ///< points of all strands
  int converged = 0;           ///< masters whose solve converged
  int unconverged = 0;         ///< masters whose solve did not converge (reported, kept)
  int unstable = 0;            ///< converged masters found unstable
  long iterations = 0;         ///< minimizer iterations over all masters
  double max_penetration = 0.0;  ///< deepest master point below the body surface (m)
  double solve_seconds = 0.0;  ///< wall time of the master solve (s)
  double wisp_seconds = 0.0;   ///< wall time of the wisp generation (s)
  /// Solved children (Hairstyle::solve_children; zeros otherwise): strands solved, of those
  /// unconverged and unstable, minimizer iterations, deepest point below the body (m) and wall
  /// time (s).
  int children_solved = 0;
  int children_unconverged = 0;
  int children_unstable = 0;
  long children_iterations = 0;
  double children_max_penetration = 0.0;
  double children_seconds = 0.0;
};

/// A groomed head: the masters, their solutions and the generated strands.
struct Groom {
  HairstyleMasters masters;
  std::vector<StrandSolution> solutions;  ///< one per master
  HairCurves strands;                     ///< every strand, wisp by wisp in master order
  GroomSummary summary;
};

/// Builds, solves (in parallel, BatchOptions) and grows the wisps of a hairstyle. The result
/// does not depend on the thread count. Returns false (with why) only for invalid input, or
/// with why = "cancelled" when batch.cancel was set during a solve (*groom untouched);
/// numerical trouble (unconverged or unstable masters) is counted in the summary.
bool GroomHairstyle(const Hairstyle& style, const BatchOptions& batch, Groom* groom,
                    std::string* why);

/// With the solver's method "auto", a solved child (Hairstyle::solve_children) whose load
/// w L^3 / (E I1) is at least this is solved by Newton from a neighbour's equilibrium, a lighter
/// one by L-BFGS: the crossover measured on the example heads (docs/benchmarks.md, "Every strand
/// a solved rod"). Masters keep kAutoNewtonLoad (statics.h): they start from the natural shape.
inline constexpr double kChildNewtonLoad = 30.0;

/// Replaces every child strand of strands (GrowWisps' output: wisp i holds strands i N .. i N +
/// N - 1, the first being the master itself when include_master) by a solved rod: root at the
/// child's first point, the master's root frame, section, material and natural curvature, the
/// master's length times the child's length fraction (WispLengthFractions; not the drawn
/// polyline, which winds around curly masters) divided into the master's segment count (graded
/// as the master), body contact with clearance = fibre radius + the master's hull-layer offset,
/// solved with style.solver (the certificate included) and sampled exactly at the child's point
/// count, equally spaced in arc length (major axes from its own material frame). Warm starts:
/// within a wisp, children are solved in order of their root's distance to the master's root,
/// each from the equilibrium of the nearest strand of the wisp solved before it (the master
/// included; nearness |root - root'|^2 + (L - L')^2); wisps are solved in parallel, each as one
/// sequential chain. Counts go to summary's children_* fields. Deterministic on any thread
/// count. Returns false for inconsistent input, or with why = "cancelled" (batch.cancel). The
/// method per child: kChildNewtonLoad.
bool SolveChildren(const Hairstyle& style, const HairstyleMasters& masters,
                   const std::vector<StrandSolution>& solutions, const BatchOptions& batch,
                   HairCurves* strands, GroomSummary* summary, std::string* why);

/// Samples the solved masters (master_points_per_segment per segment) and generates the wisps
/// around them, children pushed out of the body. Used by GroomHairstyle and by styling
/// operations that re-solve masters.
bool GrowWisps(const Hairstyle& style, const HairstyleMasters& masters,
               const std::vector<StrandSolution>& solutions, HairCurves* strands,
               std::string* why);

/// GrowWisps for the masters `which` only: *strands holds GrowWisps' output for masters with the
/// same count and wisp options (every wisp has N strands of the same point count, so wisp i owns
/// a fixed slice); the wisps of `which` are regrown in place (WispSeed(style.seed, i), the same
/// sampling, radius and push-out as GrowWisps), the others are left as they are. The result is
/// bit-identical to GrowWisps when only the masters in `which` changed since *strands was grown.
/// Used by the studio after an edit that re-solved some masters. False (strands unchanged) when
/// the layout does not match or an index is out of range.
bool RegrowWisps(const Hairstyle& style, const HairstyleMasters& masters,
                 const std::vector<StrandSolution>& solutions, const std::vector<int>& which,
                 HairCurves* strands, std::string* why);

}  // namespace ringlet
