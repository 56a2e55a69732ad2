// A rest shape per segment (StrandModel::rest_curvatures, issue 13): the constant case is bit for
// bit the old one, the elastic term and its gradient against closed forms and finite
// differences, the gravity-free equilibrium is the rest shape, the Kirchhoff certificate holds at
// solved equilibria, and the validation, scene reader, result writer and styling edits.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <memory>
#include <nlohmann/json.hpp>

#include "ringlet/energy.h"
#include "ringlet/kirchhoff.h"
#include "ringlet/obstacle.h"
#include "ringlet/result_json.h"
#include "ringlet/scene_json.h"
#include "ringlet/statics.h"
#include "ringlet/strand_hessian.h"
#include "ringlet/styling.h"
#include "test_util.h"

namespace ringlet {
namespace {

using testing::MakeStrand;
using testing::RandomCurvatures;

// A sphere with its exact signed distance (independent of src/body).
class SphereObstacle final : public Obstacle {
 public:
  SphereObstacle(const Vec3& c, double r) : c_(c), r_(r) {}
  double SignedDistance(const Vec3& x, Vec3* gradient) const override {
    const Vec3 d = x - c_;
    const double n = d.norm();
    if (gradient) *gradient = n > 0.0 ? Vec3(d / n) : Vec3(0, 0, 1);
    return n - r_;
  }

 private:
  Vec3 c_;
  double r_;
};

// A curly 20-cm strand rooted on top of a 10-cm sphere, tangent horizontal, so that gravity and
// contact both act.
StrandModel CurlyOnSphere(int segments, unsigned seed) {
  StrandModel m = MakeStrand(0.2, segments, 0.5, Vec3(-40.0, 5.0, 12.0) * (1.0 + 0.1 * seed),
                            testing::HorizontalFrame());
  m.root_position = Vec3(0, 0, 0.1);
  m.contact.obstacle = std::make_shared<SphereObstacle>(Vec3::Zero(), 0.1);
  m.contact.clearance = 0.002;
  return m;
}

StrandModel WithConstantRest(const StrandModel& m) {
  StrandModel out = m;
  out.rest_curvatures = m.NaturalCurvatures();  // natural_curvature repeated
  EXPECT_TRUE(out.HasRestShape());
  return out;
}

bool BitEqual(const VecX& a, const VecX& b) {
  if (a.size() != b.size()) return false;
  for (Eigen::Index i = 0; i < a.size(); ++i) {
    if (std::memcmp(&a(i), &b(i), sizeof(double)) != 0) return false;
  }
  return true;
}

// The constant case stays bit-identical: a rest shape filled with natural_curvature gives the
// same bits as the empty one in the energy terms, the gradient, the Kirchhoff certificate and a
// whole solve (with gravity and contact).
TEST(RestShape, ConstantRestShapeIsBitIdentical) {
  for (unsigned seed : {1u, 2u, 3u}) {
    const StrandModel plain = CurlyOnSphere(12, seed);
    const StrandModel filled = WithConstantRest(plain);
    const VecX q = plain.NaturalCurvatures() + RandomCurvatures(12, 10.0, seed);
    StrandEnergy e_plain(plain), e_filled(filled);
    VecX g_plain, g_filled;
    EnergyTerms t_plain, t_filled;
    const double a = e_plain.Evaluate(q, &g_plain, &t_plain);
    const double b = e_filled.Evaluate(q, &g_filled, &t_filled);
    EXPECT_EQ(std::memcmp(&a, &b, sizeof a), 0);
    EXPECT_EQ(t_plain.elastic, t_filled.elastic);
    EXPECT_GT(t_plain.elastic, 0.0);  // anti-vacuity: the elastic term is in play
    EXPECT_TRUE(BitEqual(g_plain, g_filled));
    EXPECT_TRUE(BitEqual(KirchhoffImbalance(plain, q), KirchhoffImbalance(filled, q)));

    const StrandSolution s_plain = SolveStrand(plain);
    const StrandSolution s_filled = SolveStrand(filled);
    ASSERT_TRUE(s_plain.summary.Converged()) << s_plain.summary.message;
    EXPECT_GT(s_plain.summary.iterations, 0);
    EXPECT_TRUE(BitEqual(s_plain.curvatures, s_filled.curvatures));
    EXPECT_EQ(s_plain.summary.iterations, s_filled.summary.iterations);
    EXPECT_EQ(s_plain.summary.min_eigenvalue, s_filled.summary.min_eigenvalue);
    EXPECT_GT(s_plain.summary.contact.samples_in_contact, 0);  // contact is in play too
  }
}

// The elastic energy with a rest shape per segment against its definition written out here
// (eq. 3 with Omega^0_i), and its gradient l_i K (Omega_i - Omega^0_i) against central
// differences of the energy.
TEST(RestShape, ElasticTermAgainstClosedFormAndFiniteDifferences) {
  StrandModel m = MakeStrand(0.3, 7, 0.6);
  m.segment_lengths = GradedSegments(0.3, 7, 3.0);
  m.rest_curvatures = RandomCurvatures(7, 50.0, 11);
  const VecX q = RandomCurvatures(7, 50.0, 12);
  const Vec3 k = m.Stiffness();
  double expected = 0.0;
  for (int i = 0; i < 7; ++i) {
    for (int j = 0; j < 3; ++j) {
      const double d = q(3 * i + j) - m.rest_curvatures(3 * i + j);
      expected += 0.5 * m.segment_lengths[i] * k(j) * d * d;
    }
  }
  VecX gradient;
  const double energy = ElasticEnergy(m, q, &gradient);
  EXPECT_NEAR(energy, expected, 1e-14 * expected);
  const auto f = [&](const VecX& x) { return ElasticEnergy(m, x, nullptr); };
  for (int i = 0; i < q.size(); ++i) {
    const double fd = testing::CentralDifference(f, q, i, 1e-3);  // exact for a quadratic
    EXPECT_NEAR(gradient(i), fd, 1e-9 * gradient.cwiseAbs().maxCoeff()) << i;
  }
  // Anti-vacuity: the rest shape matters (the constant-natural energy differs).
  StrandModel constant = m;
  constant.rest_curvatures.resize(0);
  EXPECT_GT(std::abs(ElasticEnergy(constant, q, nullptr) - energy), 0.1 * energy);
}

// Without gravity or contact the equilibrium is the rest shape itself (zero elastic energy), and
// the total gradient there is zero: the physics invariant "zero gravity gives the natural helix"
// for a non-uniform rest shape.
TEST(RestShape, ZeroGravityEquilibriumIsTheRestShape) {
  StrandModel m = MakeStrand(0.25, 10, 0.3);
  m.gravity = Vec3::Zero();
  m.rest_curvatures = RandomCurvatures(10, 60.0, 5);
  const StrandSolution s = SolveStrand(m);
  ASSERT_TRUE(s.summary.Converged()) << s.summary.message;
  EXPECT_TRUE(BitEqual(s.curvatures, m.rest_curvatures));  // the solver's natural start
  VecX g;
  StrandEnergy(m).Evaluate(m.rest_curvatures, &g);
  EXPECT_EQ(g.norm(), 0.0);
}

// At equilibria solved with a non-uniform rest shape (gravity and contact), Kirchhoff's balance
// by quadrature (independent of the gradient code) holds, and the Hessian does not depend on the
// rest shape (its elastic part is l_i K, whatever Omega^0).
TEST(RestShape, KirchhoffCertificateAndRestIndependentHessian) {
  for (unsigned seed : {7u, 8u}) {
    StrandModel m = CurlyOnSphere(10, seed);
    m.rest_curvatures = m.NaturalCurvatures() + RandomCurvatures(10, 20.0, seed);
    SolveOptions options;
    options.tolerance = 1e-11;
    const StrandSolution s = SolveStrand(m, options);
    ASSERT_TRUE(s.summary.Converged()) << s.summary.message;
    EXPECT_LT(KirchhoffResidual(m, s.curvatures), 1e-9);
    // The same configuration is far from equilibrium for the constant rest shape.
    StrandModel constant = m;
    constant.rest_curvatures.resize(0);
    EXPECT_GT(KirchhoffResidual(constant, s.curvatures), 1e-3);

    StrandHessian h_rest, h_constant;
    ComputeStrandHessian(m, s.curvatures, &h_rest);
    ComputeStrandHessian(constant, s.curvatures, &h_constant);
    EXPECT_EQ((h_rest.Dense() - h_constant.Dense()).norm(), 0.0);
  }
}

TEST(RestShape, ValidationRejectsWrongSizeAndNonFinite) {
  StrandModel m = MakeStrand(0.2, 4);
  std::string why;
  m.rest_curvatures = VecX::Zero(12);
  EXPECT_TRUE(IsValid(m, &why)) << why;
  m.rest_curvatures = VecX::Zero(9);
  EXPECT_FALSE(IsValid(m, &why));
  EXPECT_NE(why.find("3 per segment (12 numbers), got 9"), std::string::npos) << why;
  m.rest_curvatures = VecX::Zero(12);
  m.rest_curvatures(7) = std::nan("");
  EXPECT_FALSE(IsValid(m, &why));
  EXPECT_NE(why.find("segment 2"), std::string::npos) << why;
}

// The scene reader: one triple per segment, errors naming the field.
TEST(RestShape, SceneReaderReadsAndChecksRestCurvatures) {
  const std::string good = R"({"strands": [{"length": 0.2, "segments": 2,
      "rest_curvatures": [[1, 2, 3], [4, 5, -6]],
      "root": {"position": [0,0,0], "tangent": [1,0,0], "normal": [0,0,1]}}]})";
  Scene scene;
  std::string error;
  ASSERT_TRUE(ParseSceneText(good, &scene, &error)) << error;
  ASSERT_EQ(scene.strands[0].rest_curvatures.size(), 6);
  EXPECT_EQ(scene.strands[0].rest_curvatures(5), -6.0);
  EXPECT_EQ(scene.strands[0].NaturalCurvature(1), Vec3(4, 5, -6));

  const auto fails = [&](const std::string& rest, const std::string& message) {
    const std::string text = R"({"strands": [{"length": 0.2, "segments": 2, "rest_curvatures": )" +
                             rest +
                             R"(, "root": {"position": [0,0,0], "tangent": [1,0,0],
                             "normal": [0,0,1]}}]})";
    Scene s;
    std::string e;
    EXPECT_FALSE(ParseSceneText(text, &s, &e)) << rest;
    EXPECT_NE(e.find(message), std::string::npos) << e;
    EXPECT_EQ(e.find('\n'), std::string::npos) << e;
  };
  fails("[[1, 2, 3]]", "strands[0].rest_curvatures: has 1 entries, expected 2");
  fails("[[1, 2, 3], [1, 2]]", "strands[0].rest_curvatures[1]: expected an array of 3 finite");
  fails("[[1, 2, 3], [1, \"x\", 2]]", "strands[0].rest_curvatures[1]: expected");
  fails("7", "strands[0].rest_curvatures: expected an array of 2 triples");
}

// The result writer: "rest_curvatures" only for strands that have one, the same value from the
// tree writer and the text writer.
TEST(RestShape, ResultFilesCarryRestCurvatures) {
  StrandModel m = MakeStrand(0.2, 3);
  m.rest_curvatures = RandomCurvatures(3, 10.0, 3);
  const StrandSolution s = SolveStrand(m);
  const StrandResult with = MakeStrandResult(m, s, 1);
  StrandModel plain = m;
  plain.rest_curvatures.resize(0);
  const StrandResult without = MakeStrandResult(plain, SolveStrand(plain), 1);
  const nlohmann::ordered_json tree = ResultToJson({with, without}, 1.0);
  const nlohmann::json text = nlohmann::json::parse(ResultToString({with, without}, 1.0));
  EXPECT_EQ(nlohmann::json(tree), text);
  ASSERT_TRUE(text["strands"][0].contains("rest_curvatures"));
  EXPECT_FALSE(text["strands"][1].contains("rest_curvatures"));
  EXPECT_EQ(text["strands"][0]["rest_curvatures"][2][1].get<double>(), m.rest_curvatures(7));
}

// Cutting keeps the rest curvatures of the kept segments, the shortened one's included.
TEST(RestShape, TruncateKeepsTheKeptSegmentsRestShape) {
  StrandModel m = MakeStrand(0.4, 4);
  m.rest_curvatures = RandomCurvatures(4, 10.0, 9);
  VecX q = RandomCurvatures(4, 10.0, 10);
  const StrandModel cut = TruncateModel(m, 0.25, &q);  // segments of 0.1: keeps 0.1, 0.1, 0.05
  ASSERT_EQ(cut.NumSegments(), 3);
  EXPECT_NEAR(cut.segment_lengths[2], 0.05, 1e-15);
  std::string why;
  EXPECT_TRUE(IsValid(cut, &why)) << why;
  EXPECT_TRUE(BitEqual(cut.rest_curvatures, m.rest_curvatures.head(9)));
}

}  // namespace
}  // namespace ringlet
