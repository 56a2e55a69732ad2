// Simulating many strands under a rigid head motion, frame by frame (`ringlet simulate`,
// ringlet.simulate; docs/dynamics.md, "Simulating a groom"): every strand a StrandDynamics with
// its root carried by the HeadMotion (and its body's head part with it), stepped in parallel,
// with a summary per frame; and the strands of a frame (a groom's wisps around the moving masters).
#pragma once

#include <atomic>
#include <string>
#include <vector>

#include "ringlet/dynamics.h"
#include "ringlet/hair_curves.h"
#include "ringlet/hairstyle.h"
#include "ringlet/motion.h"
#include "ringlet/strand_model.h"

namespace ringlet {

/// Most frames of one simulation (duration x fps + 1).
inline constexpr int kMaxSimulationFrames = 1000000;
/// Most point samples (points of a frame x frames) ringlet.simulate keeps: it returns every
/// frame's points as arrays (12 bytes per point sample). `ringlet simulate` streams its files
/// and has no such limit (docs/dynamics.md, "Writing").
inline constexpr long long kMaxPointFrames = 1LL << 26;
/// Most implicit steps per frame.
inline constexpr int kMaxSubsteps = 1000;

/// How long and how finely to simulate.
struct SimulationOptions {
  double duration = 1.0;  ///< simulated time T (s), > 0
  double fps = 24.0;      ///< frames per second F (1/s), > 0; frame k is at t = k / F
  int substeps = 1;       ///< implicit steps per frame, 1..kMaxSubsteps: h = 1 / (F substeps)
  /// Dissipation, integrator and Newton settings; time_step is replaced by 1 / (F substeps).
  DynamicsOptions dynamics;

  /// Frames written: frame 0 (t = 0, the start) to floor(T F + 1e-9), inclusive.
  int NumFrames() const;
  /// True when every field is in range (and NumFrames() <= kMaxSimulationFrames); otherwise *why
  /// names the field ("duration: expected a finite number > 0 (s), got -1").
  bool IsValid(std::string* why) const;
};

/// One frame's summary over all strands (frames.jsonl of `ringlet simulate`).
struct FrameSummary {
  int frame = 0;
  double time = 0.0;             ///< (s)
  double kinetic = 0.0;          ///< sum of StrandDynamics::Kinetic (J, world frame)
  double elastic = 0.0;          ///< sum of the elastic energies (J)
  double gravity = 0.0;          ///< sum of the gravity energies, each from its root (J)
  double contact = 0.0;          ///< sum of the contact penalties (J)
  double max_penetration = 0.0;  ///< deepest point below the (moving) body surface (m)
  long newton_iterations = 0;    ///< over all strands' steps into this frame
  int halved_steps = 0;          ///< strands whose step into this frame was halved
  int failed_steps = 0;          ///< strands whose step failed (state kept from the last frame)
  double residual = 0.0;         ///< largest StepReport::residual of the frame's steps (rad)
  /// The first halving or failure message of the frame ("strand 3: step of ... halved ...").
  std::string message;
};

/// Strands simulated together under one head motion, each independent of the others (no
/// hair-hair interaction). Deterministic: the same bits whatever the thread count.
class Simulation {
 public:
  /// Strand i starts at rest (zero rates) in curvatures start[i] (size 3n each) with its root
  /// carried by motion (HeadMotion::Clamp, the body moving with it: a Body with a torso part is
  /// split once, SplitBody, and shared by the strands on it, its torso only translating). Throws
  /// std::invalid_argument naming the strand for invalid models, options or sizes.
  Simulation(const std::vector<StrandModel>& models, const std::vector<VecX>& start,
             const HeadMotion& motion, const SimulationOptions& options);

  /// The summary of the current frame (frame 0 before any Advance).
  const FrameSummary& summary() const { return summary_; }
  int frame() const { return summary_.frame; }
  int NumFrames() const { return options_.NumFrames(); }
  bool Done() const { return summary_.frame + 1 >= NumFrames(); }
  /// Advances every strand by one frame (substeps implicit steps; threads workers, 0 = all;
  /// cancel, when set before a strand starts, leaves it and returns false: the simulation is
  /// then not usable). Returns true with the new frame's summary in summary().
  bool Advance(int threads, const std::atomic<bool>* cancel = nullptr);

  int NumStrands() const { return static_cast<int>(strands_.size()); }
  const StrandDynamics& strand(int i) const { return strands_[static_cast<size_t>(i)]; }
  const HeadMotion& motion() const { return motion_; }
  const SimulationOptions& options() const { return options_; }

 private:
  void Summarize(const std::vector<StepReport>* reports, const std::vector<double>* depths);

  std::vector<StrandDynamics> strands_;
  HeadMotion motion_;
  SimulationOptions options_;
  FrameSummary summary_;
};

/// How far below the head centre the presets' pivot lies (m): the neck (docs/dynamics.md,
/// "Presets").
inline constexpr double kNeckDrop = 0.1;

/// The head axes and pivot of a hairstyle's motion: up and left (= up x front) of its scalp's
/// HeadFrame (HeadAxes), pivot = centre - kNeckDrop up.
void HairstyleMotionAxes(const Hairstyle& style, Vec3* pivot, Vec3* up, Vec3* left);
/// The same for single strands (a scene): up = +z, left = -x (the face toward +y), pivot the
/// mean of the roots (the origin without strands).
void StrandsMotionAxes(const std::vector<StrandModel>& strands, Vec3* pivot, Vec3* up,
                       Vec3* left);

/// Carries strands of the head at rest rigidly to where the head is at time t (points and major
/// axes; GroomFrameStrands' last step), the points in parallel (each by the same double
/// products on any thread count).
void PoseStrands(const HeadMotion& motion, double t, HairCurves* strands);

/// A groom's strands at one frame: the wisps grown (GrowWisps) around the masters at rest with
/// the given curvatures, carried by the head pose at time t (points and major axes), so that the
/// children follow their masters and their push-out from the body is the groom's. One curvature
/// vector per master. False with a one-line reason on inconsistent input.
bool GroomFrameStrands(const Hairstyle& style, const HairstyleMasters& masters,
                       const std::vector<VecX>& curvatures, const HeadMotion& motion, double t,
                       HairCurves* strands, std::string* why);

/// The simulated strands themselves as curves: points_per_segment (>= 1) points per segment of
/// each strand's current model and curvatures, width the section's mean diameter, major axes n1.
HairCurves SimulationStrands(const Simulation& simulation, int points_per_segment);

}  // namespace ringlet
