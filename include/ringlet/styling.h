// Virtual hairdressing (paper, section 3.2): curling, wetting, drying, cutting and growing a
// groomed hairstyle. Every operation edits the master models and re-solves them warm-started from
// the previous equilibrium (DESIGN.md, "styling operations = model edits followed by a
// warm-started re-solve"); the models, formulas and sources are in docs/styling.md.
#pragma once

#include <limits>
#include <numbers>
#include <string>
#include <vector>

#include "ringlet/cross_section.h"
#include "ringlet/hairstyle.h"
#include "ringlet/material.h"
#include "ringlet/math.h"
#include "ringlet/solve_strands.h"

namespace ringlet {

/// Robbins, "Chemical and Physical Behavior of Human Hair" (4th ed., 2002), as quoted by the
/// paper (section 3.2): wetting divides the stiffness by about 10 ...
inline constexpr double kWetStiffnessFactor = 0.1;
/// ... and swells the fibre radius by about 13%.
inline constexpr double kWetSwelling = 1.13;
/// Density of water (kg/m^3) at 20 C (CRC Handbook of Chemistry and Physics: 998.2).
inline constexpr double kWaterDensity = 998.2;

/// The wetting model (docs/styling.md). With the dry area A = pi a b and the wet one
/// A' = s^2 A (s = swelling), the fibre carries the absorbed water's mass
/// rho_water (A' - A) per unit length, so its density becomes
///   rho' = (rho A + rho_water (A' - A)) / A'
/// and its weight per length rho' A' g grows by the water's weight. E' = stiffness_factor E.
/// Wet hair clumps (water bridges between fibres), so the hull-layer offset shrinks:
/// thickness' = layer_factor thickness (the paper: "the hair volume is procedurally reduced
/// through the hull layers"; the factor is our choice, no measured value is known to us).
struct WetOptions {
  double stiffness_factor = kWetStiffnessFactor;  ///< E'/E, in (0, 1]
  double swelling = kWetSwelling;                 ///< a'/a = b'/b, in [1, 2]
  double water_density = kWaterDensity;           ///< rho_water (kg/m^3), in [0, 2000]
  double layer_factor = 0.5;                      ///< thickness'/thickness, in [0, 1]

  /// Checks every field; says which field and what was expected.
  bool IsValid(std::string* why) const;
};

/// The dry parameters remembered by Wet so that Dry restores them bit for bit.
struct DryParameters {
  std::vector<CrossSection> sections;  ///< dry section of each master (m)
  std::vector<Material> materials;     ///< dry material of each master
};

/// Where a cut ended one generated strand (a wisp's master or child, GrowWisps' output): the
/// strand keeps its points 0 .. segment and ends at the point lerp(p[segment], p[segment + 1],
/// t), rounded to float, with t in [0, 1). segment = -1: the strand is not cut. Because the wisps
/// are regenerated deterministically from the masters (WispSeed), the same record reproduces
/// the same clipped strand bit for bit (docs/styling.md, "Cut").
struct StrandCut {
  int segment = -1;  ///< last kept point index, -1 = uncut
  double t = 0.0;    ///< fraction of the segment (segment, segment + 1) kept, in [0, 1)
};

/// A styled head: the hairstyle, its masters and their current equilibria. Operations change
/// masters.models (and wisp radii, clearances) and solutions; the Hairstyle stays as parsed.
struct StyledHair {
  Hairstyle style;
  HairstyleMasters masters;
  std::vector<StrandSolution> solutions;  ///< one per master, the current equilibrium
  bool wet = false;                       ///< some master is wet (between Wet and Dry)
  /// Which masters are wet (one per master while wet; a brushed Wet wets some only).
  std::vector<bool> wet_masters;
  WetOptions wet_options;                 ///< the options of the Wets (valid while wet)
  DryParameters dry;                      ///< what Dry restores (entries of wet masters)
  /// Where each generated strand was clipped by the cuts since the last grow (one per strand of
  /// GrowWisps' output, wisp by wisp; empty = none). Cut fills it, StyledStrands applies it,
  /// Grow clears it (the hair regrows: docs/styling.md, "Cut").
  std::vector<StrandCut> strand_cuts;
};

/// Whether master i is wet.
bool IsWet(const StyledHair& state, int master);

/// The styled state of a groom made from `style` (GroomHairstyle): copies of its masters and
/// solutions. Returns false (with why) when the groom does not match (one solution per master).
bool MakeStyledHair(const Hairstyle& style, const Groom& groom, StyledHair* state,
                    std::string* why);

/// The clearance of master i's contact model (m): r_w max(1, tip_scale) + layer l thickness f,
/// with f = layer_factor while master i is wet and 1 when dry (the same expression as BuildMasters).
double MasterClearance(const StyledHair& state, int master);

/// What one operation did.
struct OperationReport {
  std::string name;         ///< "curl", "wet", "dry", "cut", "grow"
  int strands = 0;          ///< masters the operation changed
  long iterations = 0;      ///< minimizer iterations of all re-solves
  double seconds = 0.0;     ///< wall time of the operation (s)
  int unconverged = 0;      ///< masters whose last re-solve did not converge (kept, reported)
  int rounds = 1;           ///< re-solve rounds (cut with settle, grow steps)
  std::string message;      ///< one human line
};

/// Which masters an operation acts on. A master is selected when its index is listed in
/// `indices`, or, with `indices` empty, when its root's polar angle from the head's up axis and
/// height above the head centre (HeadCoordinates) lie in the closed ranges below. The default
/// selects every master.
struct StrandSelection {
  std::vector<int> indices;             ///< explicit master indices (none = use the ranges)
  double min_polar_angle = 0.0;         ///< (rad), in [0, pi]
  double max_polar_angle = std::numbers::pi;        ///< (rad), in [min_polar_angle, pi]
  double min_height = -std::numeric_limits<double>::infinity();  ///< (m)
  double max_height = std::numeric_limits<double>::infinity();   ///< (m), >= min_height

  /// Checks the ranges and that the indices lie in [0, masters); says which field.
  bool IsValid(int masters, std::string* why) const;
  /// Whether master i with this root is selected.
  bool Selects(int index, const Root& root) const;
};

/// Largest natural curvature and torsion a curl may give (1/m): a radius of curvature of 10 um,
/// a fifth of a fibre's radius. A helix of radius R and pitch p has curvature
/// R / (R^2 + c^2) and torsion c / (R^2 + c^2) (c = p / (2 pi)): both stay below the limit
/// when R or |c| is at least 5 um (docs/robustness.md).
inline constexpr double kMaxCurlCurvature = 1e5;
/// Largest length one grow step adds (m).
inline constexpr double kMaxGrowStep = 1.0;
/// Most grow steps of one grow operation (each writes one step_NNN.hair).
inline constexpr int kMaxGrowSteps = 1000;
/// Most length one grow operation adds, step x steps (m): hair grows about 15 cm a year.
inline constexpr double kMaxGrowLength = 10.0;

/// Checks the helix of a curl: R >= 0 (or +infinity), p finite, not R = p = 0, and curvature
/// and torsion (CurvatureFromHelix) finite and at most kMaxCurlCurvature. On failure *field is
/// "radius" or "pitch", the value to blame, and *why says what was expected.
bool CheckCurlHelix(double radius, double pitch, std::string* field, std::string* why);

/// Curl: sets the natural curvature of the selected masters to the helix of radius R (m) and
/// pitch p (m) (CurvatureFromHelix: kappa = R / (R^2 + c^2), tau = c / (R^2 + c^2),
/// c = p / (2 pi)), as (-kappa, 0, tau) in the comb frame (BuildMasters' sign: the curl starts
/// away from the head), updates their wisp radius (WispRadius with the new curliness, unless the
/// hairstyle fixes it) and clearance, and re-solves them warm-started. R = +infinity straightens.
/// A per-segment rest shape (StrandModel::rest_curvatures, inverse statics) is replaced: the
/// curl sets every segment's rest curvature to the new helix.
/// Rejects what CheckCurlHelix rejects and a bad selection.
bool Curl(StyledHair* state, double radius, double pitch, const StrandSelection& selection,
          const BatchOptions& batch, OperationReport* report, std::string* why);

/// Wet: every selected dry master's E times stiffness_factor, semi-axes times swelling, density
/// from the absorbed water (WetOptions), clearance with the layer offset times layer_factor;
/// remembers the dry parameters and re-solves them (the other masters keep their solution bit
/// for bit). Rejects invalid options, a bad selection, a selection whose masters are all wet
/// already, and options that differ from those of the masters already wet.
bool Wet(StyledHair* state, const WetOptions& options, const BatchOptions& batch,
         OperationReport* report, std::string* why,
         const StrandSelection& selection = StrandSelection());

/// Dry: the exact inverse of Wet on the selected wet masters. Restores their remembered sections
/// and materials bit for bit, the dry clearance, and re-solves them warm-started from the wet
/// equilibrium. Rejects a bad selection and one without a wet master.
bool Dry(StyledHair* state, const BatchOptions& batch, OperationReport* report,
         std::string* why, const StrandSelection& selection = StrandSelection());

/// The region that a cut keeps; everything of a strand beyond the first point where its
/// centreline leaves the region is removed (the paper: "removing the hair part located under a
/// given z position", l_new = l_prev - l_cut).
struct CutRegion {
  enum class Kind {
    kAbovePlane,   ///< keep n . r >= offset (n = normal, unit or not); CutBelow uses n = +z
    kInsideSphere, ///< keep |r - centre| <= radius (bobs, rounded layered cuts)
    kMaxLength,    ///< keep arc lengths s <= length
  };
  Kind kind = Kind::kAbovePlane;
  Vec3 normal = Vec3::UnitZ();  ///< plane normal, kAbovePlane (non-zero, world)
  double offset = 0.0;          ///< plane offset n . r (m, with n normalized), kAbovePlane
  Vec3 centre = Vec3::Zero();   ///< sphere centre (m), kInsideSphere
  double radius = 0.0;          ///< sphere radius (m, > 0), kInsideSphere
  double length = 0.0;          ///< maximal length (m, > 0), kMaxLength

  /// Signed distance-like value of a point: > 0 inside the kept region, 0 on its boundary (m):
  /// n . r - offset (n normalized) or radius - |r - centre|. Not used by kMaxLength.
  double Inside(const Vec3& point) const;
  /// Checks the fields of the kind; says which and what was expected.
  bool IsValid(std::string* why) const;
};

/// Clips generated strands to a cut region: every strand whose root lies in the region (for
/// kMaxLength: every strand) is ended where its polyline first leaves it, at a point found by
/// bisection on the segment parameter with the float-rounded point tested (so the stored point
/// is inside, Inside >= 0, or for kMaxLength its polyline arc length, summed in double from the
/// float points, is <= length). `cuts` has one entry per strand (resized, uncut, when it does
/// not match) and holds the previous clips: a strand is searched only up to its previous end and
/// its record is replaced by the new, shorter one. Strands rooted outside stay as they are.
/// Returns the number of strands newly clipped.
int ClipStrands(const CutRegion& region, const HairCurves& strands, std::vector<StrandCut>* cuts);

/// Ends each strand as its record says (ClipStrands); the widths and major axes follow (the
/// width interpolated, the axis of the last kept point). `cuts` must be empty (nothing done) or
/// hold one entry per strand, each within its strand.
void ApplyStrandCuts(const std::vector<StrandCut>& cuts, HairCurves* strands);

/// Options of Cut.
struct CutOptions {
  /// Iterate until the tips settle on the boundary: after the first cut the lighter hair rises
  /// and its tips end inside the region (the paper's point); with settle each cut master's length
  /// is adjusted (bracketed secant, Illinois rule, between the cut length and the previous
  /// length) and re-solved until |Inside(tip)| <= tolerance. Planes and spheres only.
  bool settle = false;
  double tolerance = 5e-4;  ///< settle tolerance on |Inside(tip)| (m), > 0
  int max_rounds = 40;      ///< settle rounds, >= 1
  /// Sub-intervals per segment searched for the first exit (each then bisected on the exact
  /// helix), >= 1: catches a curl that dips out of the region and back within one segment.
  int samples_per_segment = 8;

  bool IsValid(std::string* why) const;
};

/// Where a strand first leaves a cut region at its equilibrium: the arc length (m) from the
/// root, exact to rounding on the helix (bisection on HelixChord within the segment), or the
/// strand length when it never leaves. For kMaxLength, min(length, L). A root outside the region
/// returns 0.
double CutArcLength(const StrandModel& model, const VecX& curvatures, const CutRegion& region,
                    int samples_per_segment = 8);

/// The model truncated at arc length s in (0, L]: the segments beyond are dropped and the
/// crossing segment is shortened (to s minus the kept segments' sum). A per-segment rest shape
/// keeps the rest curvatures of the kept segments, the shortened one's included. `curvatures`,
/// when not null, is truncated to the kept segments (the warm start).
StrandModel TruncateModel(const StrandModel& model, double arc_length, VecX* curvatures = nullptr);

/// Cut: each master whose equilibrium leaves the region is truncated where it first leaves it
/// (CutArcLength) and all cut masters are re-solved warm-started; with settle, iterated (CutOptions).
/// Masters rooted outside the region are left uncut and counted in the message. Only the
/// selected masters are cut; the others keep their model and solution bit for bit.
bool Cut(StyledHair* state, const CutRegion& region, const CutOptions& options,
         const BatchOptions& batch, OperationReport* report, std::string* why,
         const StrandSelection& selection = StrandSelection());

/// Cut below the height z (m): Cut with the plane n = +z, offset z.
bool CutBelow(StyledHair* state, double z, const CutOptions& options, const BatchOptions& batch,
              OperationReport* report, std::string* why);

/// Grow: `steps` times, every selected master grows by `step` (m) at its tip and is re-solved from the
/// previous step's equilibrium. The length is added to the last segment; when that segment
/// would exceed the model's longest segment at the start, a new segment of the remainder is
/// appended, starting from the last segment's curvatures (the helix continued) so the grid stays
/// as fine as the groom's. Where hair grows does not change the equilibrium (the natural
/// curvature is uniform, so a strand of length L has the same energy however it came to be);
/// the tip is where the warm start stays closest. With a per-segment rest shape
/// (StrandModel::rest_curvatures) the lengthened last segment keeps its rest curvatures and the
/// appended segments get the strand's natural_curvature (the hair type's curl): the new hair
/// has not been shaped. `sequence`, when not null, receives the state
/// after each step (steps entries). Rejects a step outside (0, kMaxGrowStep], steps outside
/// [1, kMaxGrowSteps], step x steps above kMaxGrowLength, and growth that would give a master
/// more than kMaxSegments segments, and a bad selection. The unselected masters keep their model
/// and solution bit for bit.
bool Grow(StyledHair* state, double step, int steps, const BatchOptions& batch,
          std::vector<StyledHair>* sequence, OperationReport* report, std::string* why,
          const StrandSelection& selection = StrandSelection());

/// A brush (docs/styling.md, "Brushes"): the studio's brush circle on the head, as data. Its
/// influence at a point at distance d from the centre is
///   w(d) = strength f(d / radius),   f(x) = 0 for x >= 1, and for 0 <= x < 1
///   kSmooth: 1 - 3 x^2 + 2 x^3  (smoothstep reversed: f(0) = 1, f(1) = 0, f'(0) = f'(1) = 0),
///   kLinear: 1 - x,   kConstant: 1
/// (the falloff curves of sculpting tools, e.g. Blender's "Smooth" / "Linear" / "Constant").
/// With mirror the brush also acts at its image across the head's mid-plane (MirrorAcrossHead),
/// so a stroke on one side styles both.
struct Brush {
  enum class Falloff { kSmooth, kLinear, kConstant };
  Vec3 centre = Vec3::Zero();  ///< (m, world)
  double radius = 0.03;        ///< (m), > 0
  double strength = 1.0;       ///< in (0, 1]
  Falloff falloff = Falloff::kSmooth;
  bool mirror = false;

  /// Checks a finite centre, radius in (0, kMaxBrushRadius] and strength in (0, 1]; says which
  /// field ("centre", "radius", "strength") and what was expected.
  bool IsValid(std::string* why) const;
  /// w(d) above for a distance d >= 0 (m).
  double Weight(double distance) const;
};

/// Largest brush radius (m): a brush of 10 m covers any head.
inline constexpr double kMaxBrushRadius = 10.0;

/// The name of a falloff as the files write it: "smooth", "linear", "constant".
const char* FalloffName(Brush::Falloff falloff);

/// The head's mid-plane is the plane through HeadFrame::centre spanned by up and front (normal
/// to the left axis, HeadAxes' third column). The reflection of a point p across it:
///   p' = p - 2 ((p - c) . e) e,   e the unit left axis, c the head centre;
/// of a vector (a displacement) v: v' = v - 2 (v . e) e.
Vec3 MirrorAcrossHead(const HeadFrame& head, const Vec3& p);
Vec3 MirrorVectorAcrossHead(const HeadFrame& head, const Vec3& v);

/// The head frame of a hairstyle's scalp (sphere or mesh).
const HeadFrame& HairstyleHead(const Hairstyle& style);

/// Sculpt (comb): drag the hair near `brush.centre` by `to - brush.centre`, and make the dragged
/// shape a stable equilibrium with ringlet's inverse statics (inverse.h). For each selected
/// master, with its equilibrium centreline x_j sampled at 4 points per segment (arc lengths
/// s_j > 0), the target points are
///   p_j = x_j + w(|x_j - c|) d  [+ w(|x_j - c'|) d'  with mirror],   d = to - c,
/// c' and d' the mirror images of c and d (MirrorAcrossHead). The target curvatures q* of the
/// master's own segments (the strand keeps its length: hair does not stretch; the root keeps its
/// clamp) minimize sum_j |x_j(q) - p_j|^2 by Levenberg-Marquardt on the exact Jacobian
/// (PointForceGradients); InvertStrand gives the rest shape (and contact support offsets) that
/// holds q* under gravity and contact, certifies it and solves forward from it: that
/// equilibrium becomes the master's. A target that no rest shape holds stably settles in the
/// nearest stable equilibrium (reported as `unstable` in the message). Masters with every
/// w = 0 keep their model and solution bit for bit. The hair keeps its sculpted rest shape
/// through later operations except curl (which replaces the rest shape).
struct SculptStroke {
  Brush brush;                ///< centre = where the stroke starts (m)
  Vec3 to = Vec3::Zero();     ///< where it ends (m); |to - centre| <= kMaxBrushRadius

  /// Brush::IsValid and a finite `to` within kMaxBrushRadius of the centre.
  bool IsValid(std::string* why) const;
};

bool Sculpt(StyledHair* state, const SculptStroke& stroke, const StrandSelection& selection,
            const BatchOptions& batch, OperationReport* report, std::string* why);

/// Puff: lift the roots under the brush. Each selected master's root frame turns about the
/// axis t x N (t its root tangent, N the outward scalp normal at its root) by
///   a = w(|r - c|) angle  [the larger of w(|r - c|), w(|r - c'|) with mirror],
/// r the root, clamped so that the tilt from N stays in [0, kMaxPuffTilt]: angle > 0 raises the
/// hair toward the normal (volume at the roots), < 0 flattens it. Then the masters whose frame
/// turned are re-solved warm-started. |angle| <= pi / 2 (rad).
bool Puff(StyledHair* state, double angle, const Brush& brush, const StrandSelection& selection,
          const BatchOptions& batch, OperationReport* report, std::string* why);

/// Largest tilt of a root tangent from the scalp normal a puff leaves (rad): 85 degrees.
inline constexpr double kMaxPuffTilt = 85.0 * std::numbers::pi / 180.0;

/// The weight of a brush on master i (docs/styling.md, "Brushes"): w = Brush::Weight of the
/// distance from the brush centre to the nearest of the master's equilibrium centreline samples
/// (its root and 4 points per segment, u = l k / 4; w is decreasing in the distance, so this is
/// the largest weight over the samples), and with mirror the larger of that and the weight at the
/// mirrored centre (MirrorAcrossHead). So a brush on the hair or on the head near the roots both
/// reach the master.
double MasterBrushWeight(const StyledHair& state, int master, const Brush& brush);

/// Curl brush: Curl by the brush. Each selected master with weight w = MasterBrushWeight > 0
/// moves its natural curvature toward the helix (R, p) of Curl (Omega*, with Curl's sign):
///   Omega' = Omega + w (Omega* - Omega)   (Omega* itself when w = 1),
/// a per-segment rest shape likewise segment by segment (so a sculpted shape is curled, not
/// dropped; support offsets are dropped), its wisp radius and clearance follow the new
/// curliness as in Curl, and the changed masters are re-solved warm-started (the old
/// equilibrium shifted by the change of rest curvature). R = +infinity straightens. A constant
/// brush at strength 1 on masters without a rest shape is Curl on the masters it reaches, bit
/// for bit. Rejects what Curl rejects and a bad brush ("curl.brush.<field>").
bool CurlBrush(StyledHair* state, double radius, double pitch, const Brush& brush,
               const StrandSelection& selection, const BatchOptions& batch,
               OperationReport* report, std::string* why);

/// Largest factor of a length or clump brush (dimensionless): the factor is in (0, 10].
inline constexpr double kMaxBrushFactor = 10.0;
/// The per-master clump factor (HairstyleMasters::clump_factors) stays in [1/100, 100].
inline constexpr double kMaxClumpFactor = 100.0;
/// Largest frizz amplitude a frizz brush sets (m): 5 cm.
inline constexpr double kMaxFrizzAmplitude = 0.05;

/// Length brush: each selected master with weight w = MasterBrushWeight > 0 gets the length
///   L' = L (1 + w (factor - 1)),   factor in (0, kMaxBrushFactor]
/// (factor < 1 shortens, > 1 lengthens; a constant falloff at strength 1 scales the masters it
/// reaches by exactly the factor). Shortening truncates the master at L' (TruncateModel, as a
/// cut: the rest shape of the kept segments is kept); lengthening adds L' - L at the tip as Grow
/// does (the last segment lengthened, segments of the longest one's length appended, the helix
/// continued, appended rest curvatures the hair type's curl). The changed masters are re-solved
/// warm-started. The children follow (a child is a fixed fraction of its master's length); a
/// child clipped by an earlier cut (StyledHair::strand_cuts) keeps its clip scaled alike: its
/// drawn arc length c becomes c (1 + w (factor - 1)) on the new strand (ClipStrands with a
/// kMaxLength region; uncut when the new strand is not longer), so shortening never lengthens a
/// strand. Refuses a bad factor or brush ("length.<field>: ..."), a bad selection and growth
/// beyond kMaxSegments; the other masters keep their model and solution bit for bit.
bool LengthBrush(StyledHair* state, double factor, const Brush& brush,
                 const StrandSelection& selection, const BatchOptions& batch,
                 OperationReport* report, std::string* why);

/// Clump brush: each selected master with weight w > 0 multiplies its wisp's clump factor k
/// (HairstyleMasters::clump_factors, the multiplier of WispOptions::tip_scale, 1 by default) by
///   1 + w (factor - 1),   factor in (0, kMaxBrushFactor],
/// kept in [1 / kMaxClumpFactor, kMaxClumpFactor]: factor < 1 draws the children toward the
/// master at the tip (tighter wisps), > 1 spreads them. Only the wisps change: the masters keep
/// their model and solution (the contact clearance stays that of the hairstyle's tip_scale; the
/// children are pushed out of the body as always). Clip records of earlier cuts stay on the same
/// points of the strands.
bool ClumpBrush(StyledHair* state, double factor, const Brush& brush,
                const StrandSelection& selection, OperationReport* report, std::string* why);

/// Frizz brush: each selected master with weight w > 0 moves its wisp's frizz amplitude a
/// (HairstyleMasters::frizz_amplitudes, WispOptions::frizz_amplitude by default) toward
/// `amplitude` (m, in [0, kMaxFrizzAmplitude]):
///   a' = a + w (amplitude - a)
/// (amplitude 0 smooths the frizz away). Only the wisps change, as for ClumpBrush.
bool FrizzBrush(StyledHair* state, double amplitude, const Brush& brush,
                const StrandSelection& selection, OperationReport* report, std::string* why);

/// One styling operation with its parameters: an entry of a hairstyle file's "operations" list
/// (ParseStyleOperations, docs/hairstyle-format.md) or one option of `ringlet style`. Only the
/// fields of `kind` are used. ApplyOperation runs it, so the file and the command line share one
/// code path.
struct StyleOperation {
  enum class Kind { kCurl, kWet, kDry, kCut, kGrow, kSculpt, kPuff, kLength, kClump, kFrizz };
  Kind kind = Kind::kWet;
  /// Curl: helix radius R (m, >= 0, +infinity = straight) and pitch p (m, finite, < 0 =
  /// left-handed), on the selected masters (Curl).
  double curl_radius = 0.0;
  double curl_pitch = 0.0;
  /// Curl by a brush (CurlBrush, the file's "brush" object) instead of on the whole selection.
  bool curl_brushed = false;
  Brush curl_brush;
  /// The masters every kind acts on (the file's "select"; default: all).
  StrandSelection selection;
  /// Wet: the wetting model's parameters (WetOptions).
  WetOptions wet;
  /// Cut: the region kept and the options (Cut; CutBelow is a kAbovePlane region, n = +z).
  CutRegion cut_region;
  CutOptions cut;
  /// Grow: `grow_steps` steps (1 to kMaxGrowSteps) of `grow_step` (m, in (0, kMaxGrowStep])
  /// each, at most kMaxGrowLength in all (Grow).
  double grow_step = 0.0;
  int grow_steps = 10;
  /// Sculpt: the stroke (Sculpt).
  SculptStroke sculpt;
  /// Puff: the angle (rad, |angle| <= pi / 2) and the brush (Puff).
  double puff_angle = 0.0;
  Brush puff_brush;
  /// Length, clump and frizz: the brush (LengthBrush, ClumpBrush, FrizzBrush) with the length or
  /// clump factor (in (0, kMaxBrushFactor]) or the frizz amplitude (m, in [0,
  /// kMaxFrizzAmplitude]).
  Brush brush;
  double factor = 1.0;
  double frizz_amplitude = 0.0;

  /// Checks the parameters that do not depend on the hair (the checks of Curl, Wet, Cut and
  /// Grow, with their messages; selection indices only for >= 0, the upper bound is checked
  /// by ApplyOperation, for every kind). Says which field and what was expected.
  bool IsValid(std::string* why) const;
};

/// The operation's name, as in OperationReport::name: "curl", "wet", "dry", "cut", "grow",
/// "sculpt", "puff", "length", "clump", "frizz".
const char* OperationName(StyleOperation::Kind kind);

/// Runs one operation on the styled state (Curl, Wet, Dry, Cut or Grow with the operation's
/// parameters). For grow, `grow_sequence`, when not null, receives the state after each step.
/// On failure returns false with why and leaves the state unchanged, except when cancelled
/// (BatchOptions::cancel set during the re-solve: why = "cancelled", the state partly edited;
/// run a cancellable operation on a copy). Every operation above honours the cancel flag alike.
bool ApplyOperation(StyledHair* state, const StyleOperation& operation, const BatchOptions& batch,
                    std::vector<StyledHair>* grow_sequence, OperationReport* report,
                    std::string* why);

/// Samples the masters of a styled state and grows their wisps (GrowWisps), applies the cuts,
/// and sets HairCurves::wetness (1 for the strands of wet masters, 0 for the others; empty when
/// no master is wet) for the renderer's optics.
bool StyledStrands(const StyledHair& state, HairCurves* strands, std::string* why);

}  // namespace ringlet
