// Many strands under a rigid head motion, frame by frame (simulate.h; docs/dynamics.md,
// "Simulating a groom").
#include "ringlet/simulate.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <memory>
#include <sstream>
#include <stdexcept>

#include "ringlet/body.h"
#include "ringlet/contact.h"
#include "ringlet/split_body.h"
#include "ringlet/strand_geometry.h"

namespace ringlet {

int SimulationOptions::NumFrames() const {
  const double frames = std::floor(duration * fps + 1e-9);
  if (!(frames >= 0.0) || frames >= kMaxSimulationFrames) return kMaxSimulationFrames + 1;
  return static_cast<int>(frames) + 1;
}

bool SimulationOptions::IsValid(std::string* why) const {
  auto fail = [&](const std::string& message) {
    if (why) *why = message;
    return false;
  };
  if (!(std::isfinite(duration) && duration > 0.0)) {
    return fail("duration: expected a finite number > 0 (s)");
  }
  if (!(std::isfinite(fps) && fps > 0.0)) {
    return fail("fps: expected a finite number > 0 (frames per second)");
  }
  if (substeps < 1 || substeps > kMaxSubsteps) {
    return fail("substeps: expected an integer between 1 and " + std::to_string(kMaxSubsteps));
  }
  if (NumFrames() > kMaxSimulationFrames) {
    return fail("duration x fps: expected at most " + std::to_string(kMaxSimulationFrames - 1) +
                " frames");
  }
  DynamicsOptions dynamic = dynamics;
  dynamic.time_step = 1.0 / (fps * substeps);
  std::string reason;
  if (!dynamic.IsValid(&reason)) return fail(reason);
  return true;
}

Simulation::Simulation(const std::vector<StrandModel>& models, const std::vector<VecX>& start,
                       const HeadMotion& motion, const SimulationOptions& options)
    : motion_(motion), options_(options) {
  std::string why;
  if (!options_.IsValid(&why)) throw std::invalid_argument(why);
  if (start.size() != models.size()) {
    throw std::invalid_argument("start: expected one curvature vector per strand (" +
                                std::to_string(models.size()) + "), got " +
                                std::to_string(start.size()));
  }
  options_.dynamics.time_step = 1.0 / (options_.fps * options_.substeps);
  strands_.reserve(models.size());
  // A body with a torso part is split once (its parts' grids built once) and shared by every
  // strand on it: its head part turns with the head, its torso part only translates. A motion
  // that never turns (walk, none, keyframes without angles: R = I exactly) moves both parts
  // alike, so the body stays one rigid obstacle there.
  bool turns = motion_.preset() == MotionPreset::kNod || motion_.preset() == MotionPreset::kShake ||
               motion_.preset() == MotionPreset::kTurn;
  for (const MotionKeyframe& key : motion_.keyframes()) turns = turns || key.angle != 0.0;
  std::map<const Obstacle*, std::shared_ptr<const SplitBody>> splits;
  auto split_of = [&splits, turns](const std::shared_ptr<const Obstacle>& obstacle) {
    const auto body = std::dynamic_pointer_cast<const Body>(obstacle);
    if (!body || !turns) return std::shared_ptr<const SplitBody>();
    const auto found = splits.find(body.get());
    if (found != splits.end()) return found->second;
    return splits[body.get()] = SplitBody::Create(body);
  };
  for (size_t i = 0; i < models.size(); ++i) {
    try {
      StrandState state;
      state.curvatures = start[i];
      state.rates = VecX::Zero(start[i].size());
      strands_.emplace_back(models[i], options_.dynamics, state);
      strands_.back().SetClampMotion(motion_.Clamp(models[i].root_position, models[i].root_frame,
                                                   split_of(models[i].contact.obstacle)));
    } catch (const std::invalid_argument& e) {
      throw std::invalid_argument("strand " + std::to_string(i) + ": " + e.what());
    }
  }
  Summarize(nullptr, nullptr);
}

bool Simulation::Advance(int threads, const std::atomic<bool>* cancel) {
  const size_t count = strands_.size();
  std::vector<StepReport> reports(count);
  std::vector<double> depths(count, 0.0);  // deepest penetration of each strand at the frame
  std::atomic<bool> cancelled{false};
  // The frame's end time is k / F (not a sum of steps): the last sub-step takes what is left
  // when the steps have drifted, so that frames stay on their time codes however long the run.
  const int next = summary_.frame + 1;
  const double end = next / options_.fps;
  auto step_one = [&](size_t i) {
    if (cancel && cancel->load()) {
      cancelled = true;
      return;
    }
    StrandDynamics& strand = strands_[i];
    StepReport total;
    total.converged = true;
    for (int s = 0; s < options_.substeps; ++s) {
      // The last sub-step ends at k / F: its length is the nominal h unless the sum of the
      // steps has drifted from the frame's time by more than 1e-9 h (rounding over many
      // frames); the nominal length keeps BDF2's equal-step history (it compares lengths).
      const double nominal = options_.dynamics.time_step;
      double h = nominal;
      if (s + 1 == options_.substeps) {
        const double left = end - strand.state().time;
        if (std::abs(left - nominal) > 1e-9 * nominal) h = left;
      }
      const StepReport report = strand.Step(h);
      total.newton_iterations += report.newton_iterations;
      total.halvings = std::max(total.halvings, report.halvings);
      total.residual = std::max(total.residual, report.residual);
      if (!report.message.empty() && total.message.empty()) total.message = report.message;
      if (!report.converged) total.converged = false;
      // The energies of the state at the frame: the last sub-step's (Step's own evaluation).
      total.potential = report.potential;
      total.kinetic = report.kinetic;
    }
    reports[i] = std::move(total);
    if (strand.model().contact.obstacle) {
      depths[i] = MeasureContact(strand.model(), strand.state().curvatures).max_penetration;
    }
  };
  // One strand per task: step costs vary with contact and curl.
  tbb::task_arena arena(threads > 0 ? threads : tbb::task_arena::automatic);
  arena.execute([&] {
    tbb::parallel_for(tbb::blocked_range<size_t>(0, count, 1),
                      [&](const tbb::blocked_range<size_t>& r) {
                        for (size_t i = r.begin(); i != r.end(); ++i) step_one(i);
                      });
  });
  if (cancelled) return false;
  summary_.frame = next;
  Summarize(&reports, &depths);
  return true;
}

// With the frame's reports the per-strand energies and depths come from the parallel steps (the
// same numbers: Step reports the potential and kinetic energy of the state it leaves, and each
// strand's depth is measured on its own thread); at frame 0 they are computed here.
void Simulation::Summarize(const std::vector<StepReport>* reports,
                           const std::vector<double>* depths) {
  FrameSummary s;
  s.frame = summary_.frame;
  s.time = s.frame / options_.fps;
  // In strand order, one after another: the sums do not depend on the threads.
  for (size_t i = 0; i < strands_.size(); ++i) {
    const StrandDynamics& strand = strands_[i];
    const EnergyTerms potential = reports ? (*reports)[i].potential : strand.Potential();
    s.kinetic += reports ? (*reports)[i].kinetic : strand.Kinetic();
    s.elastic += potential.elastic;
    s.gravity += potential.gravity;
    s.contact += potential.contact;
    if (depths) {
      s.max_penetration = std::max(s.max_penetration, (*depths)[i]);
    } else if (strand.model().contact.obstacle) {
      s.max_penetration = std::max(
          s.max_penetration, MeasureContact(strand.model(), strand.state().curvatures).max_penetration);
    }
    if (!reports) continue;
    const StepReport& report = (*reports)[i];
    s.newton_iterations += report.newton_iterations;
    if (report.halvings > 0) ++s.halved_steps;
    if (!report.converged) ++s.failed_steps;
    s.residual = std::max(s.residual, report.residual);
    if (!report.message.empty() && s.message.empty()) {
      s.message = "strand " + std::to_string(i) + ": " + report.message;
    }
  }
  summary_ = std::move(s);
}

void HairstyleMotionAxes(const Hairstyle& style, Vec3* pivot, Vec3* up, Vec3* left) {
  const HeadFrame& head = std::holds_alternative<SphereScalp>(style.scalp)
                              ? std::get<SphereScalp>(style.scalp).head
                              : std::get<MeshScalp>(style.scalp).head;
  const Mat3 axes = HeadAxes(head);  // columns (up, front, left)
  *up = axes.col(0);
  *left = axes.col(2);
  *pivot = head.centre - kNeckDrop * *up;
}

void StrandsMotionAxes(const std::vector<StrandModel>& strands, Vec3* pivot, Vec3* up,
                       Vec3* left) {
  *up = Vec3::UnitZ();
  *left = -Vec3::UnitX();
  *pivot = Vec3::Zero();
  for (const StrandModel& m : strands) *pivot += m.root_position;
  if (!strands.empty()) *pivot /= static_cast<double>(strands.size());
}

bool GroomFrameStrands(const Hairstyle& style, const HairstyleMasters& masters,
                       const std::vector<VecX>& curvatures, const HeadMotion& motion, double t,
                       HairCurves* strands, std::string* why) {
  if (curvatures.size() != masters.models.size()) {
    if (why) *why = "curvatures: expected one vector per master";
    return false;
  }
  std::vector<StrandSolution> solutions(curvatures.size());
  for (size_t i = 0; i < curvatures.size(); ++i) solutions[i].curvatures = curvatures[i];
  HairCurves curves;
  if (!GrowWisps(style, masters, solutions, &curves, why)) return false;
  // The wisps of the head at rest, carried rigidly to where the head is at t.
  PoseStrands(motion, t, &curves);
  *strands = std::move(curves);
  return true;
}

void PoseStrands(const HeadMotion& motion, double t, HairCurves* strands) {
  const RigidPose pose = motion.Pose(t);
  const Eigen::Matrix3f rotation = pose.rotation.cast<float>();
  const Vec3 shift = motion.pivot() + pose.translation - pose.rotation * motion.pivot();
  tbb::parallel_for(tbb::blocked_range<size_t>(0, strands->points.size(), 4096),
                    [&](const tbb::blocked_range<size_t>& range) {
                      for (size_t j = range.begin(); j != range.end(); ++j) {
                        Vec3f& x = strands->points[j];
                        x = (pose.rotation * x.cast<double>() + shift).cast<float>();
                      }
                    });
  for (Vec3f& a : strands->major_axes) a = rotation * a;
}

HairCurves SimulationStrands(const Simulation& simulation, int points_per_segment) {
  HairCurves curves;
  for (int i = 0; i < simulation.NumStrands(); ++i) {
    const StrandDynamics& strand = simulation.strand(i);
    const FramedCentreline line = SampleFramedCentreline(
        strand.model(), strand.state().curvatures, std::max(1, points_per_segment));
    curves.point_counts.push_back(static_cast<std::uint32_t>(line.points.size()));
    const float width = static_cast<float>(2.0 * strand.model().section.MeanRadius());
    for (size_t j = 0; j < line.points.size(); ++j) {
      curves.points.push_back(line.points[j].cast<float>());
      curves.widths.push_back(width);
      curves.major_axes.push_back(line.frames[j].col(0).cast<float>());
    }
  }
  return curves;
}

}  // namespace ringlet
