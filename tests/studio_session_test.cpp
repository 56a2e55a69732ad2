// The studio's editing model without GL (studio/session.h): edits, re-solves on the worker,
// undo / redo, cancellation, and the save -> `ringlet style` round trip, bit for bit.
#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <mutex>
#include <nlohmann/json.hpp>
#include <string>
#include <thread>

#include "ringlet/hairstyle_json.h"
#include "ringlet/masters_json.h"
#include "ringlet/strand_geometry.h"
#include "ringlet/styling.h"
#include "brush_tool.h"
#include "session.h"

namespace ringlet::studio {
namespace {

using ojson = nlohmann::ordered_json;

// A small head of wavy hair on the example mannequin: `count` masters, 4 strands per wisp.
ojson SmallDocument(int count = 60) {
  return ojson::parse(R"({
    "body": "bodies/mannequin.json",
    "masters": {"count": )" +
                      std::to_string(count) + R"(, "seed": 3, "segments": 12},
    "comb": {"tilt": 1.2, "direction": [0, 0, -1], "parting": {"normal": [1, 0, 0], "offset": 0.03}},
    "hair": {"origin": "caucasian", "curl": "wavy", "length": 0.2, "seed": 2},
    "wisps": {"strands_per_wisp": 4, "jitter": 0.001, "points_per_strand": 16},
    "layers": {"count": 3, "thickness": 0.003}
  })");
}

std::string TempPath(const std::string& name) {
  const std::filesystem::path dir =
      std::filesystem::temp_directory_path() / ("ringlet_studio_test_" + std::to_string(getpid()));
  std::filesystem::create_directories(dir);
  return (dir / name).string();
}

// The hair `ringlet style FILE -o OUT/` makes of a file (the code path of cli/style_command.cpp:
// LoadHairstyle, GroomHairstyle, MakeStyledHair, ApplyOperation in order, StyledStrands).
HairCurves StyleFile(const std::string& path) {
  Hairstyle style;
  std::vector<StyleOperation> operations;
  std::string error;
  EXPECT_TRUE(LoadHairstyle(path, &style, &operations, &error)) << error;
  Groom groom;
  EXPECT_TRUE(GroomHairstyle(style, {}, &groom, &error)) << error;
  StyledHair state;
  EXPECT_TRUE(MakeStyledHair(style, groom, &state, &error)) << error;
  for (const StyleOperation& op : operations) {
    EXPECT_TRUE(ApplyOperation(&state, op, {}, nullptr, nullptr, &error)) << error;
  }
  HairCurves strands;
  EXPECT_TRUE(StyledStrands(state, &strands, &error)) << error;
  return strands;
}

// Bit-exact comparison of two sets of strands.
void ExpectSameBits(const HairCurves& a, const HairCurves& b) {
  ASSERT_EQ(a.point_counts, b.point_counts);
  ASSERT_EQ(a.points.size(), b.points.size());
  ASSERT_GT(a.points.size(), 0u);
  EXPECT_EQ(0, std::memcmp(a.points.data(), b.points.data(), a.points.size() * sizeof(Vec3f)));
  ASSERT_EQ(a.widths.size(), b.widths.size());
  EXPECT_EQ(0, std::memcmp(a.widths.data(), b.widths.data(), a.widths.size() * sizeof(float)));
}

double MeanLength(const StyledHair& hair) {
  double sum = 0.0;
  for (const StrandModel& m : hair.masters.models) sum += m.Length();
  return sum / hair.masters.models.size();
}

class StudioSession : public ::testing::Test {
 protected:
  void Open(int count = 60) {
    std::string error;
    ASSERT_TRUE(
        session.OpenDocument(SmallDocument(count), RINGLET_EXAMPLES_DIR, "small.json", &error))
        << error;
    session.Wait();
    ASSERT_TRUE(session.Hair());
    ASSERT_TRUE(session.UpToDate());
  }
  Session session;
};

TEST_F(StudioSession, OpenGroomsTheHair) {
  Open();
  const HairState& hair = *session.Hair();
  EXPECT_EQ(hair.stats.what, "groom");
  EXPECT_EQ(hair.stats.masters, 60);
  EXPECT_EQ(hair.stats.resolved, 60);
  EXPECT_GT(hair.stats.iterations, 0);
  EXPECT_EQ(hair.strands->NumStrands(), 60 * 4);
  EXPECT_EQ(hair.status.size(), 60u);
}

// Issue 26: the masters of a freshly opened file are shown as they are solved. With previews
// after every block of 32 masters, the last one (before Poll takes the hair) holds every
// master, each the polyline of the groom's own solution (2 points per segment).
TEST_F(StudioSession, PreviewShowsTheMastersAsTheyAreSolved) {
  session.SetPreviewSeconds(0.0);
  std::string error;
  ASSERT_TRUE(session.OpenDocument(SmallDocument(70), RINGLET_EXAMPLES_DIR, "small.json", &error))
      << error;
  std::shared_ptr<const HairState> preview;
  const auto until = std::chrono::steady_clock::now() + std::chrono::seconds(120);
  std::vector<int> solved_counts;  // masters with more than a root point, per preview seen
  while (std::chrono::steady_clock::now() < until) {
    if (auto p = session.Preview(); p && p != preview) {
      preview = p;
      int solved = 0;
      for (std::uint32_t c : p->strands->point_counts) solved += c > 2 ? 1 : 0;
      solved_counts.push_back(solved);
      if (solved == 70) break;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(2));
  }
  ASSERT_TRUE(preview);
  ASSERT_EQ(solved_counts.back(), 70) << "no preview with every master solved";
  EXPECT_TRUE(std::is_sorted(solved_counts.begin(), solved_counts.end()));
  session.Wait();
  ASSERT_TRUE(session.Hair());
  EXPECT_FALSE(session.Preview());  // the hair is shown: no preview any more
  const HairState& hair = *session.Hair();
  ASSERT_EQ(preview->strands->NumStrands(), 70);
  size_t p = 0;
  for (int i = 0; i < 70; ++i) {
    const std::vector<Vec3> reference =
        SampleCentreline(hair.base->masters.models[i], hair.base->solutions[i].curvatures, 2);
    ASSERT_EQ(preview->strands->point_counts[i], reference.size()) << "master " << i;
    for (const Vec3& x : reference) {
      ASSERT_EQ(preview->strands->points[p++], x.cast<float>()) << "master " << i;
    }
  }
}

// The polyline of master i of a preview (its points from the preview's strands).
std::vector<Vec3f> PreviewMaster(const HairState& preview, int i) {
  const HairCurves& c = *preview.strands;
  size_t first = 0;
  for (int k = 0; k < i; ++k) first += c.point_counts[k];
  return {c.points.begin() + first, c.points.begin() + first + c.point_counts[i]};
}

// The polyline a preview must show for master i of a styled hair (2 points per segment).
std::vector<Vec3f> MasterLine(const StyledHair& hair, int i) {
  std::vector<Vec3f> out;
  for (const Vec3& x : SampleCentreline(hair.masters.models[i], hair.solutions[i].curvatures, 2)) {
    out.push_back(x.cast<float>());
  }
  return out;
}

// Issue 26: an edit streams its masters as they are re-solved, children after. A parameter edit
// (every master's length changes) publishes after each block of masters: the solved ones in
// their new shape, the others still in the shape shown before; then every master, before the
// wisps grow; the UI sees the last one (Preview) until it takes the hair. An operation
// publishes its styled masters the same way.
TEST_F(StudioSession, EditsStreamTheResolvedMasters) {
  Open(70);
  const std::shared_ptr<const HairState> before = session.Hair();
  std::mutex mutex;
  std::vector<std::shared_ptr<const HairState>> previews;
  session.SetPreviewSeconds(0.0);
  session.SetPreviewListener([&](const std::shared_ptr<const HairState>& p) {
    std::lock_guard<std::mutex> lock(mutex);
    previews.push_back(p);
  });
  const auto last_resolved = [&] {
    std::lock_guard<std::mutex> lock(mutex);
    return previews.empty() ? -1 : previews.back()->stats.resolved;
  };
  for (int edit = 0; edit < 2; ++edit) {
    {
      std::lock_guard<std::mutex> lock(mutex);
      previews.clear();
    }
    std::string error;
    if (edit == 0) {
      ASSERT_TRUE(session.SetParameter("hair.length", 0.26, &error)) << error;
    } else {
      StyleOperation curl;
      curl.kind = StyleOperation::Kind::kCurl;
      curl.curl_radius = 0.01;
      curl.curl_pitch = 0.02;
      ASSERT_TRUE(session.AddOperation(curl, &error)) << error;
    }
    // Every master published in its final shape: the UI's Preview shows it until Poll.
    const auto until = std::chrono::steady_clock::now() + std::chrono::seconds(120);
    while (last_resolved() < 70 && std::chrono::steady_clock::now() < until) {
      std::this_thread::sleep_for(std::chrono::milliseconds(1));
    }
    ASSERT_EQ(last_resolved(), 70) << "edit " << edit;
    ASSERT_TRUE(session.Preview()) << "edit " << edit;
    EXPECT_EQ(session.Preview()->stats.resolved, 70);
    const std::shared_ptr<const HairState> shown_before = session.Hair();
    session.Wait();
    EXPECT_FALSE(session.Preview()) << "edit " << edit;
    const std::shared_ptr<const HairState> after = session.Hair();
    ASSERT_TRUE(after && after != shown_before);
    std::lock_guard<std::mutex> lock(mutex);
    std::vector<int> resolved;
    for (const auto& p : previews) resolved.push_back(p->stats.resolved);
    EXPECT_TRUE(std::is_sorted(resolved.begin(), resolved.end()));
    if (edit == 0) {
      // Blocks of 32 masters: 32, 64, 70 solved, then all before the wisps.
      ASSERT_GE(previews.size(), 3u);
      EXPECT_EQ(resolved.front(), 32);
      const HairState& first = *previews.front();
      for (int i = 0; i < 70; ++i) {
        // The groom of the edit (no operations: the styled masters are the groom's).
        const std::vector<Vec3f> expected =
            i < 32 ? MasterLine(after->styled, i) : MasterLine(before->styled, i);
        ASSERT_EQ(PreviewMaster(first, i), expected) << "master " << i;
      }
    } else {
      ASSERT_GE(previews.size(), 1u);
    }
    // The last preview: every master as the hair has it.
    const HairState& last = *previews.back();
    ASSERT_EQ(last.strands->NumStrands(), 70);
    for (int i = 0; i < 70; ++i) {
      ASSERT_EQ(PreviewMaster(last, i), MasterLine(after->styled, i)) << "master " << i;
      if (edit == 0) {
        ASSERT_NE(MasterLine(after->styled, i), MasterLine(before->styled, i)) << "master " << i;
      }
    }
  }
}

// A quick edit (faster than the preview period) publishes nothing: the hair is shown directly.
TEST_F(StudioSession, QuickEditsPublishNoPreview) {
  Open(20);
  std::atomic<int> published{0};
  session.SetPreviewSeconds(1e9);
  session.SetPreviewListener([&](const std::shared_ptr<const HairState>&) { ++published; });
  std::string error;
  ASSERT_TRUE(session.SetParameter("hair.length", 0.22, &error)) << error;
  session.Wait();
  EXPECT_EQ(published.load(), 0);
  EXPECT_FALSE(session.Preview());
}

TEST_F(StudioSession, BadFileKeepsTheHair) {
  Open();
  const auto before = session.Hair();
  ojson bad = SmallDocument();
  bad["hair"]["origin"] = "martian";
  std::string error;
  EXPECT_FALSE(session.OpenDocument(bad, RINGLET_EXAMPLES_DIR, "bad.json", &error));
  // The CLI's message: the reader's, naming the field.
  EXPECT_NE(error.find("hair.origin"), std::string::npos) << error;
  EXPECT_NE(error.find("martian"), std::string::npos) << error;
  EXPECT_EQ(session.Hair(), before);
  EXPECT_FALSE(session.Open("/nonexistent/hairstyle.json", &error));
  EXPECT_NE(error.find("/nonexistent/hairstyle.json"), std::string::npos) << error;
  EXPECT_FALSE(session.SetParameter("hair.length", -1.0, &error));
  EXPECT_NE(error.find("hair.length"), std::string::npos) << error;
  EXPECT_EQ(session.Hair(), before);
  EXPECT_FALSE(session.CanUndo());
}

TEST_F(StudioSession, OperationChangesTheModelAndResolvesWarm) {
  Open();
  const auto before = session.Hair();
  StyleOperation cut;
  cut.kind = StyleOperation::Kind::kCut;
  cut.cut_region.offset = -0.12;  // keep z >= -0.12
  std::string error;
  ASSERT_TRUE(session.AddOperation(cut, &error)) << error;
  session.Wait();
  const auto after = session.Hair();
  ASSERT_NE(after, before);
  EXPECT_EQ(after->stats.what, "cut");
  EXPECT_GT(after->stats.resolved, 0);
  EXPECT_LT(MeanLength(after->styled), MeanLength(before->styled));
  // The groom was not redone: the unstyled masters are shared.
  EXPECT_EQ(after->base, before->base);
  // A cut is a warm-started re-solve: fewer iterations than the groom.
  EXPECT_LT(after->stats.iterations, before->stats.iterations);
}

TEST_F(StudioSession, BrushedCurlActsOnTheBrushedMastersOnly) {
  Open();
  const auto before = session.Hair();
  StyleOperation curl;
  curl.kind = StyleOperation::Kind::kCurl;
  curl.curl_radius = 0.008;
  curl.curl_pitch = 0.02;
  curl.selection.indices = {1, 5, 7};
  std::string error;
  ASSERT_TRUE(session.AddOperation(curl, &error)) << error;
  session.Wait();
  const auto after = session.Hair();
  EXPECT_EQ(after->stats.resolved, 3);
  for (int i = 0; i < 60; ++i) {
    const bool brushed = i == 1 || i == 5 || i == 7;
    EXPECT_EQ(after->styled.masters.models[i].natural_curvature !=
                  before->styled.masters.models[i].natural_curvature,
              brushed)
        << i;
  }
  curl.selection.indices = {60};
  EXPECT_FALSE(session.AddOperation(curl, &error));
  EXPECT_NE(error.find("60"), std::string::npos) << error;
}

TEST_F(StudioSession, UndoRedo) {
  Open();
  const auto groomed = session.Hair();
  StyleOperation wet;
  wet.kind = StyleOperation::Kind::kWet;
  std::string error;
  ASSERT_TRUE(session.AddOperation(wet, &error)) << error;
  session.Wait();
  const auto wetted = session.Hair();
  EXPECT_TRUE(wetted->styled.wet);
  StyleOperation wet_again = wet;
  EXPECT_FALSE(session.AddOperation(wet_again, &error));  // already wet
  ASSERT_TRUE(session.SetParameter("wisps.jitter", 0.002, &error)) << error;
  session.Wait();
  const auto jittered = session.Hair();
  // Only the wisps changed: every master kept its solution, the operations were replayed.
  EXPECT_EQ(jittered->stats.reused, 60);
  EXPECT_TRUE(jittered->styled.wet);

  ASSERT_TRUE(session.Undo());
  session.Wait();
  EXPECT_EQ(session.Hair(), wetted);  // shown at once, not re-solved
  ASSERT_TRUE(session.Undo());
  session.Wait();
  EXPECT_EQ(session.Hair(), groomed);
  EXPECT_FALSE(session.Undo());
  EXPECT_EQ(session.CurrentDocument().operations.size(), 0u);
  ASSERT_TRUE(session.Redo());
  ASSERT_TRUE(session.Redo());
  session.Wait();
  EXPECT_EQ(session.Hair(), jittered);
  EXPECT_FALSE(session.Redo());
  // A new edit after an undo drops the redo branch.
  ASSERT_TRUE(session.Undo());
  StyleOperation dry;
  dry.kind = StyleOperation::Kind::kDry;
  ASSERT_TRUE(session.AddOperation(dry, &error)) << error;
  session.Wait();
  EXPECT_FALSE(session.CanRedo());
  EXPECT_FALSE(session.Hair()->styled.wet);
  EXPECT_EQ(session.HistoryLabels().size(), 3u);
}

TEST_F(StudioSession, SaveReproducesTheHairBitForBit) {
  Open();
  std::string error;
  StyleOperation curl;
  curl.kind = StyleOperation::Kind::kCurl;
  curl.curl_radius = 0.01;
  curl.curl_pitch = 0.03;
  curl.selection.indices = {0, 2, 3, 10, 11, 12, 40};
  ASSERT_TRUE(session.AddOperation(curl, &error)) << error;
  ASSERT_TRUE(session.SetParameter("hair.length", 0.23, &error)) << error;
  StyleOperation wet;
  wet.kind = StyleOperation::Kind::kWet;
  ASSERT_TRUE(session.AddOperation(wet, &error)) << error;
  session.Wait();
  StyleOperation cut;
  cut.kind = StyleOperation::Kind::kCut;
  cut.cut_region.kind = CutRegion::Kind::kInsideSphere;
  cut.cut_region.centre = Vec3(0.0, 0.01, 0.02);
  cut.cut_region.radius = 0.2;
  ASSERT_TRUE(session.AddOperation(cut, &error)) << error;
  StyleOperation dry;
  dry.kind = StyleOperation::Kind::kDry;
  ASSERT_TRUE(session.AddOperation(dry, &error)) << error;
  StyleOperation grow;
  grow.kind = StyleOperation::Kind::kGrow;
  grow.grow_step = 0.005;
  grow.grow_steps = 2;
  ASSERT_TRUE(session.AddOperation(grow, &error)) << error;
  session.Wait();
  ASSERT_TRUE(session.UpToDate());
  EXPECT_TRUE(session.Modified());

  // Saved into another directory: the body path is rewritten relative to it.
  const std::string path = TempPath("saved/styled.json");
  std::filesystem::create_directories(std::filesystem::path(path).parent_path());
  ASSERT_TRUE(session.Save(path, &error)) << error;
  EXPECT_FALSE(session.Modified());
  ExpectSameBits(*session.Hair()->strands, StyleFile(path));

  // Opening the saved file gives the same document and, solved from scratch, the same hair.
  Session reopened;
  ASSERT_TRUE(reopened.Open(path, &error)) << error;
  reopened.Wait();
  EXPECT_EQ(reopened.CurrentDocument().operations.size(), 5u);
  ExpectSameBits(*session.Hair()->strands, *reopened.Hair()->strands);
}

// Every operation brushed (the brush's indices in each operation's "select"): the unbrushed
// masters keep their solution bit for bit, only their wisps are regrown (RegrowWisps), and the
// saved file gives the same hair through `ringlet style`'s code path, bit for bit.
TEST_F(StudioSession, BrushedOperationsRegrowTheirWispsAndSaveBitForBit) {
  Open();
  std::string error;
  const auto groomed = session.Hair();
  const std::vector<int> brush = {2, 3, 10, 11, 12, 40, 41};
  StyleOperation wet;
  wet.kind = StyleOperation::Kind::kWet;
  wet.selection.indices = brush;
  ASSERT_TRUE(session.AddOperation(wet, &error)) << error;
  session.Wait();
  const auto wetted = session.Hair();
  EXPECT_EQ(wetted->stats.resolved, 7);
  ASSERT_EQ(wetted->regrown_from, groomed->strands_id);  // only some wisps regrown
  EXPECT_LE(wetted->stats.regrown, 7);
  EXPECT_GT(wetted->stats.regrown, 0);
  for (int i = 0; i < 60; ++i) {
    const bool brushed = std::find(brush.begin(), brush.end(), i) != brush.end();
    EXPECT_EQ(IsWet(wetted->styled, i), brushed) << i;
    if (!brushed) {
      EXPECT_TRUE(wetted->styled.solutions[i].curvatures == groomed->styled.solutions[i].curvatures)
          << i;
    }
  }
  // The partly regrown strands equal growing every wisp (the independent reference).
  HairCurves full;
  ASSERT_TRUE(StyledStrands(wetted->styled, &full, &error)) << error;
  ExpectSameBits(full, *wetted->strands);

  StyleOperation cut;
  cut.kind = StyleOperation::Kind::kCut;
  cut.cut_region.offset = -0.1;
  cut.selection.indices = {2, 3, 10, 11};
  ASSERT_TRUE(session.AddOperation(cut, &error)) << error;
  StyleOperation grow;
  grow.kind = StyleOperation::Kind::kGrow;
  grow.grow_step = 0.01;
  grow.grow_steps = 1;
  grow.selection.indices = {40, 41, 50};
  ASSERT_TRUE(session.AddOperation(grow, &error)) << error;
  StyleOperation dry;
  dry.kind = StyleOperation::Kind::kDry;
  dry.selection.indices = {2, 40};
  ASSERT_TRUE(session.AddOperation(dry, &error)) << error;
  session.Wait();
  ASSERT_TRUE(session.UpToDate());
  const auto styled = session.Hair();
  // One job ran the cut, the grow (3 masters) and the dry (2): the counts add up.
  EXPECT_EQ(styled->stats.what, "dry");
  EXPECT_GE(styled->stats.resolved, 5);
  EXPECT_TRUE(IsWet(styled->styled, 3) && !IsWet(styled->styled, 2) && !IsWet(styled->styled, 40));
  EXPECT_NEAR(styled->styled.masters.models[50].Length(),
              groomed->styled.masters.models[50].Length() + 0.01, 1e-12);
  EXPECT_LT(styled->styled.masters.models[2].Length() + styled->styled.masters.models[3].Length() +
                styled->styled.masters.models[10].Length() +
                styled->styled.masters.models[11].Length(),
            groomed->styled.masters.models[2].Length() + groomed->styled.masters.models[3].Length() +
                groomed->styled.masters.models[10].Length() +
                groomed->styled.masters.models[11].Length());
  EXPECT_EQ(styled->styled.masters.models[20].Length(), groomed->styled.masters.models[20].Length());
  ASSERT_TRUE(StyledStrands(styled->styled, &full, &error)) << error;
  ExpectSameBits(full, *styled->strands);

  const std::string path = TempPath("brushed.json");
  ASSERT_TRUE(session.Save(path, &error)) << error;
  // The file holds the selections.
  std::ifstream file(path);
  const nlohmann::json saved = nlohmann::json::parse(file);
  ASSERT_EQ(saved["operations"].size(), 4u);
  EXPECT_EQ(saved["operations"][0]["wet"]["select"]["indices"], nlohmann::json(brush));
  EXPECT_EQ(saved["operations"][3]["dry"]["select"]["indices"], nlohmann::json({2, 40}));
  ExpectSameBits(*styled->strands, StyleFile(path));
  // Not replaced without overwrite.
  EXPECT_FALSE(session.Save(path, &error, false));
  EXPECT_NE(error.find("exists"), std::string::npos) << error;
}

// New drops the document and the hair (the UI asks first when Modified()).
TEST_F(StudioSession, NewEmptiesTheSession) {
  Open();
  std::string error;
  ASSERT_TRUE(session.SetParameter("hair.length", 0.21, &error)) << error;
  EXPECT_TRUE(session.Modified());
  session.New();
  session.Wait();
  EXPECT_FALSE(session.Modified());
  EXPECT_FALSE(session.Hair());
  EXPECT_FALSE(session.CanUndo());
  EXPECT_TRUE(session.CurrentDocument().operations.empty());
}

TEST_F(StudioSession, OperationJsonRoundTrips) {
  std::vector<StyleOperation> ops(5);
  ops[0].kind = StyleOperation::Kind::kCurl;
  ops[0].curl_radius = std::numeric_limits<double>::infinity();
  ops[0].curl_pitch = 0.1 / 3.0;
  ops[0].selection.min_polar_angle = 0.1;
  ops[0].selection.max_polar_angle = 0.7;
  ops[1].kind = StyleOperation::Kind::kWet;
  ops[1].wet.swelling = 1.1;
  ops[2].kind = StyleOperation::Kind::kCut;
  ops[2].cut_region.normal = Vec3(0.1, 0.2, 1.0);
  ops[2].cut_region.offset = -0.1 / 7.0;
  ops[2].cut.settle = true;
  ops[3].kind = StyleOperation::Kind::kCut;
  ops[3].cut_region.kind = CutRegion::Kind::kMaxLength;
  ops[3].cut_region.length = 0.17;
  ops[4].kind = StyleOperation::Kind::kGrow;
  ops[4].grow_step = 0.003;
  ops[4].grow_steps = 3;
  // The brushes (styling.h, Brush): a mirrored sculpt stroke and a linear puff.
  ops.resize(7);
  ops[5].kind = StyleOperation::Kind::kSculpt;
  ops[5].sculpt.brush.centre = Vec3(0.01, 0.1 / 3.0, -0.02);
  ops[5].sculpt.to = Vec3(0.02, 0.05, -0.1 / 7.0);
  ops[5].sculpt.brush.radius = 0.03;
  ops[5].sculpt.brush.mirror = true;
  ops[6].kind = StyleOperation::Kind::kPuff;
  ops[6].puff_angle = 0.1 / 3.0;
  ops[6].puff_brush.centre = Vec3(0.0, 0.02, 0.1);
  ops[6].puff_brush.radius = 0.04;
  ops[6].puff_brush.strength = 0.7;
  ops[6].puff_brush.falloff = Brush::Falloff::kLinear;
  nlohmann::json document = {{"operations", nlohmann::json::array()}};
  for (const StyleOperation& op : ops) {
    document["operations"].push_back(nlohmann::json::parse(OperationToJson(op).dump()));
  }
  std::vector<StyleOperation> back;
  std::string error;
  ASSERT_TRUE(ParseStyleOperations(document, &back, &error)) << error;
  ASSERT_EQ(back.size(), ops.size());
  for (size_t k = 0; k < ops.size(); ++k) {
    EXPECT_EQ(OperationToJson(back[k]), OperationToJson(ops[k])) << k;
  }
  EXPECT_EQ(back[0].curl_pitch, ops[0].curl_pitch);
  EXPECT_EQ(back[2].cut_region.offset, ops[2].cut_region.offset);
  EXPECT_EQ(back[2].cut_region.normal, ops[2].cut_region.normal);
  EXPECT_EQ(back[5].sculpt.brush.centre, ops[5].sculpt.brush.centre);
  EXPECT_EQ(back[5].sculpt.to, ops[5].sculpt.to);
  EXPECT_TRUE(back[5].sculpt.brush.mirror);
  EXPECT_EQ(back[6].puff_angle, ops[6].puff_angle);
  EXPECT_EQ(back[6].puff_brush.strength, 0.7);
  EXPECT_EQ(back[6].puff_brush.falloff, Brush::Falloff::kLinear);
}

// The library's hook: a set cancel flag stops an operation between blocks of masters.
TEST(StudioCancel, OperationStopsWhenCancelled) {
  Hairstyle style;
  std::string error;
  ASSERT_TRUE(
      ParseHairstyle(nlohmann::json(SmallDocument(200)), RINGLET_EXAMPLES_DIR, &style, &error))
      << error;
  Groom groom;
  ASSERT_TRUE(GroomHairstyle(style, {}, &groom, &error)) << error;
  StyledHair state;
  ASSERT_TRUE(MakeStyledHair(style, groom, &state, &error)) << error;
  StyleOperation wet;
  wet.kind = StyleOperation::Kind::kWet;

  // Cancelled after the first masters: the operation stops early and says so.
  std::atomic<bool> cancel{false};
  int solved = 0;
  BatchOptions batch;
  batch.threads = 1;
  batch.cancel = &cancel;
  batch.progress = [&](int done, int) {
    solved = done;
    if (done >= 5) cancel = true;
  };
  StyledHair copy = state;
  EXPECT_FALSE(ApplyOperation(&copy, wet, batch, nullptr, nullptr, &error));
  EXPECT_EQ(error, "cancelled");
  EXPECT_LT(solved, 200);

  // Not cancelled: the same result as without a flag (blocks do not change the solves).
  cancel = false;
  batch.progress = nullptr;
  StyledHair with_flag = state, without = state;
  ASSERT_TRUE(ApplyOperation(&with_flag, wet, batch, nullptr, nullptr, &error)) << error;
  ASSERT_TRUE(ApplyOperation(&without, wet, {}, nullptr, nullptr, &error)) << error;
  for (int i = 0; i < 200; ++i) {
    ASSERT_EQ(with_flag.solutions[i].curvatures, without.solutions[i].curvatures) << i;
  }
}

// A newer edit cancels the stale solve: the hair shown is the newest edit's.
TEST_F(StudioSession, NewerEditCancelsStaleSolve) {
  Open(200);
  std::string error;
  ASSERT_TRUE(session.SetParameter("hair.length", 0.21, &error)) << error;  // 200 re-solves
  StyleOperation wet;
  wet.kind = StyleOperation::Kind::kWet;
  ASSERT_TRUE(session.AddOperation(wet, &error)) << error;
  ASSERT_TRUE(session.SetParameter("hair.length", 0.22, &error)) << error;
  session.Wait();
  ASSERT_TRUE(session.UpToDate());
  EXPECT_GE(session.CancelledSolves(), 1);
  const std::string path = TempPath("cancel.json");
  ASSERT_TRUE(session.Save(path, &error)) << error;
  ExpectSameBits(*session.Hair()->strands, StyleFile(path));
}

// A hairstyle with explicit masters (a masters file: the groom's own masters with a rest shape
// bent by 5 1/m, ExplicitMastersOf): the studio opens it, refuses the parameters that would
// sample the masters (one line naming the field), applies operations, and the file it saves
// in another directory (masters file path rewritten) gives the same hair through `ringlet
// style`'s code path, bit for bit.
// A regional length (front / side / back) gets one length field per region, and setting one
// keeps the others (one "hair.length" slider showed 0.25 for such hairstyles and, moved, would
// have replaced all three with one number).
TEST(StudioLength, RegionalLengthsAreEditedOneByOne) {
  ojson document = SmallDocument(12);
  EXPECT_EQ(LengthFields(document), std::vector<std::string>{"hair.length"});
  document["hair"].erase("length");
  EXPECT_EQ(LengthFields(document), std::vector<std::string>{"hair.length"});
  document["hair"]["length"] = {{"front", 0.12}, {"side", 0.25}, {"back", 0.3}};
  EXPECT_EQ(LengthFields(document),
            (std::vector<std::string>{"hair.length.front", "hair.length.side", "hair.length.back"}));

  Session session;
  std::string error;
  ASSERT_TRUE(session.OpenDocument(document, RINGLET_EXAMPLES_DIR, "regional.json", &error))
      << error;
  session.Wait();
  ASSERT_TRUE(session.SetParameter("hair.length.front", 0.15, &error)) << error;
  session.Wait();
  EXPECT_EQ(session.Parameter("hair.length"),
            (ojson{{"front", 0.15}, {"side", 0.25}, {"back", 0.3}}));
  EXPECT_EQ(LengthFields(session.CurrentDocument().parameters).size(), 3u);
}

// The comb panel's "waves laid into the head" box sets comb.curl_inward: the re-solved masters
// start their curl into the head (kappa1^0 > 0); a non-boolean is refused with the CLI's message.
// The panel's section, curl, wisp-size and comb controls are fields of the file: each edit
// re-solves and reaches the model, and a bad value keeps the hair with the reader's message.
TEST(StudioFields, SectionCurlWispSizeAndCombAreFields) {
  Session session;
  std::string error;
  ASSERT_TRUE(session.OpenDocument(SmallDocument(16), RINGLET_EXAMPLES_DIR, "s.json", &error))
      << error;
  session.Wait();
  const double radius_before = session.Hair()->styled.style.hair_type.curl_radius;
  ASSERT_TRUE(session.SetParameter("hair.ellipticity", 1.6, &error)) << error;
  ASSERT_TRUE(session.SetParameter("hair.curl_radius", 2.0 * radius_before, &error)) << error;
  ASSERT_TRUE(session.SetParameter("hair.curl_spread", 0.2, &error)) << error;
  ASSERT_TRUE(session.SetParameter("wisps.radius", 0.004, &error)) << error;
  ASSERT_TRUE(session.SetParameter("comb.face_sweep", 1.0, &error)) << error;
  ASSERT_TRUE(session.SetParameter("comb.direction", ojson::array({0.0, -0.3, -1.0}), &error))
      << error;
  session.Wait();
  const StyledHair& hair = session.Hair()->styled;
  EXPECT_EQ(hair.style.hair_type.ellipticity, 1.6);
  EXPECT_EQ(hair.style.hair_type.curl_radius, 2.0 * radius_before);
  EXPECT_NEAR(hair.style.hair_type.curl_radius_std, 0.2 * 2.0 * radius_before, 1e-15);
  EXPECT_EQ(hair.style.wisps.wisp_radius, 0.004);
  for (const double r : hair.masters.wisp_radii) EXPECT_EQ(r, 0.004);
  EXPECT_FALSE(session.SetParameter("hair.ellipticity", 0.5, &error));
  EXPECT_EQ(error.rfind("hair.ellipticity: expected a finite a/b in [1, 10]", 0), 0u) << error;
  EXPECT_EQ(session.Hair()->styled.style.hair_type.ellipticity, 1.6);  // kept
}

TEST(StudioComb, CurlInwardIsAField) {
  Session session;
  std::string error;
  ASSERT_TRUE(session.OpenDocument(SmallDocument(12), RINGLET_EXAMPLES_DIR, "small.json", &error))
      << error;
  session.Wait();
  ASSERT_TRUE(session.Hair());
  EXPECT_LT(session.Hair()->styled.masters.models[0].natural_curvature.x(), 0.0);
  ASSERT_TRUE(session.SetParameter("comb.curl_inward", true, &error)) << error;
  session.Wait();
  ASSERT_TRUE(session.Hair());
  for (const StrandModel& m : session.Hair()->styled.masters.models) {
    EXPECT_GT(m.natural_curvature.x(), 0.0);
  }
  EXPECT_FALSE(session.SetParameter("comb.curl_inward", 1, &error));
  EXPECT_NE(error.find("comb.curl_inward: expected true or false"), std::string::npos) << error;
}

TEST(StudioExplicitMasters, OpenStyleSaveRoundTrip) {
  std::string error;
  Hairstyle sampled;
  ASSERT_TRUE(ParseHairstyle(nlohmann::json(SmallDocument(16)), RINGLET_EXAMPLES_DIR, &sampled,
                             &error))
      << error;
  HairstyleMasters built;
  ASSERT_TRUE(BuildMasters(sampled, &built, &error)) << error;
  std::vector<ExplicitMaster> masters = ExplicitMastersOf(built);
  for (ExplicitMaster& m : masters) {
    const int n = static_cast<int>(m.segment_lengths.size());
    m.rest_curvatures.resize(3 * n);
    for (int i = 0; i < n; ++i) {
      m.rest_curvatures.segment<3>(3 * i) = *m.natural_curvature + Vec3(-5.0 * i / n, 0.0, 0.0);
    }
  }
  const std::string masters_path = TempPath("explicit/masters.json");
  std::filesystem::create_directories(std::filesystem::path(masters_path).parent_path());
  std::ofstream(masters_path) << MastersToString(masters);
  ojson document = SmallDocument(16);
  document["body"] = std::string(RINGLET_EXAMPLES_DIR) + "/bodies/mannequin.json";
  document["masters"] = {{"file", "masters.json"}};
  document.erase("comb");
  document["hair"].erase("length");

  Session session;
  ASSERT_TRUE(session.OpenDocument(document, std::filesystem::path(masters_path).parent_path(),
                                   "explicit.json", &error))
      << error;
  session.Wait();
  ASSERT_TRUE(session.Hair());
  EXPECT_EQ(session.Hair()->stats.masters, 16);
  EXPECT_EQ(session.Hair()->styled.masters.models[3].rest_curvatures.size(),
            3 * session.Hair()->styled.masters.models[3].NumSegments());
  // The message names the hairstyle key that is refused (the comb object as a whole).
  for (const auto& [field, named] : std::vector<std::pair<std::string, std::string>>{
           {"masters.count", "masters.count"}, {"hair.length", "hair.length"},
           {"comb.tilt", "comb"}}) {
    EXPECT_FALSE(session.SetParameter(field, 0.3, &error)) << field;
    EXPECT_EQ(error.rfind(named + ": not with masters.file", 0), 0u) << error;
    EXPECT_EQ(error.find('\n'), std::string::npos) << error;
  }
  EXPECT_FALSE(session.CanUndo());
  StyleOperation wet;
  wet.kind = StyleOperation::Kind::kWet;
  ASSERT_TRUE(session.AddOperation(wet, &error)) << error;
  StyleOperation cut;
  cut.kind = StyleOperation::Kind::kCut;
  cut.cut_region.kind = CutRegion::Kind::kMaxLength;
  cut.cut_region.length = 0.15;
  ASSERT_TRUE(session.AddOperation(cut, &error)) << error;
  ASSERT_TRUE(session.SetParameter("wisps.jitter", 0.002, &error)) << error;
  session.Wait();
  ASSERT_TRUE(session.UpToDate());

  const std::string path = TempPath("saved_explicit/styled.json");
  std::filesystem::create_directories(std::filesystem::path(path).parent_path());
  ASSERT_TRUE(session.Save(path, &error)) << error;
  std::ifstream saved(path);
  const ojson written = ojson::parse(saved);
  EXPECT_EQ(written["masters"]["file"], "../explicit/masters.json");
  ExpectSameBits(*session.Hair()->strands, StyleFile(path));
}

// Every example hairstyle opens in the studio, takes every operation (a brushed curl, wet, a
// cut by a plane, dry, grow) after its own operations, saves, and `ringlet style`'s code path
// gives the same hair from the saved file, bit for bit. The examples are opened with fewer
// masters and strands (24 masters, 4 strands per wisp, when the file samples its masters) so
// that the test stays short under the sanitizers; every other field is the file's.
TEST(StudioExamples, EveryExampleOpensStylesAndSavesBitForBit) {
  const std::filesystem::path dir = std::filesystem::path(RINGLET_EXAMPLES_DIR) / "hairstyles";
  std::vector<std::filesystem::path> files;
  for (const auto& entry : std::filesystem::directory_iterator(dir)) {
    if (entry.path().extension() == ".json") files.push_back(entry.path());
  }
  std::sort(files.begin(), files.end());
  ASSERT_GE(files.size(), 15u);
  int examples_cut = 0;  // examples where the cut removed hair (anti-vacuity)
  for (const std::filesystem::path& file : files) {
    SCOPED_TRACE(file.filename().string());
    std::ifstream in(file);
    ojson document = ojson::parse(in);
    if (document["masters"].contains("count")) document["masters"]["count"] = 24;
    document["wisps"]["strands_per_wisp"] = 4;
    const size_t own_operations =
        document.contains("operations") ? document["operations"].size() : 0;
    Session session;
    std::string error;
    ASSERT_TRUE(session.OpenDocument(document, dir.string(), file.filename().string(), &error))
        << error;
    session.Wait();
    ASSERT_TRUE(session.Hair());
    ASSERT_EQ(session.CurrentDocument().operations.size(), own_operations);
    const int masters = session.Hair()->stats.masters;
    ASSERT_GT(masters, 0);

    StyleOperation curl;
    curl.kind = StyleOperation::Kind::kCurl;
    curl.curl_radius = 0.01;
    curl.curl_pitch = 0.03;
    curl.selection.indices = {0, masters / 2, masters - 1};
    std::sort(curl.selection.indices.begin(), curl.selection.indices.end());
    curl.selection.indices.erase(
        std::unique(curl.selection.indices.begin(), curl.selection.indices.end()),
        curl.selection.indices.end());
    StyleOperation wet, cut, dry, grow;
    wet.kind = StyleOperation::Kind::kWet;
    cut.kind = StyleOperation::Kind::kCut;
    cut.cut_region.kind = CutRegion::Kind::kAbovePlane;
    cut.cut_region.offset = -0.15;  // keep z >= -15 cm
    dry.kind = StyleOperation::Kind::kDry;
    grow.kind = StyleOperation::Kind::kGrow;
    grow.grow_step = 0.01;
    grow.grow_steps = 1;
    // A hairstyle whose own operations leave it wet is dried first.
    if (session.Hair()->styled.wet) {
      ASSERT_TRUE(session.AddOperation(dry, &error)) << error;
    }
    for (const StyleOperation* op : {&curl, &wet, &cut, &dry, &grow}) {
      // Points of strands rooted above the plane that reach below it.
      auto below_plane = [](const HairCurves& strands) {
        size_t first = 0;
        int below = 0;
        for (const auto count : strands.point_counts) {
          if (strands.points[first].z() >= -0.15f) {
            for (size_t k = first; k < first + count; ++k) below += strands.points[k].z() < -0.15f;
          }
          first += count;
        }
        return below;
      };
      const int below_before = below_plane(*session.Hair()->strands);
      ASSERT_TRUE(session.AddOperation(*op, &error)) << error;
      session.Wait();
      ASSERT_TRUE(session.UpToDate());
      EXPECT_EQ(session.LastError(), "");
      if (op != &cut) continue;
      // Right after the cut, no strand rooted above the plane reaches below it (the grow at the
      // end lengthens the hair again).
      EXPECT_EQ(below_plane(*session.Hair()->strands), 0);
      examples_cut += below_before > 0;
    }
    EXPECT_GE(session.CurrentDocument().operations.size(), own_operations + 5);
    const std::string path = TempPath("examples/" + file.filename().string());
    std::filesystem::create_directories(std::filesystem::path(path).parent_path());
    ASSERT_TRUE(session.Save(path, &error)) << error;
    ExpectSameBits(*session.Hair()->strands, StyleFile(path));
  }
  EXPECT_GE(examples_cut, 10);
}



// A comb stroke as the window makes it (a ray picks a hair point; the stroke ends in the view
// plane) and a puff at the crown, applied through the session with mirror symmetry: the stroke
// moves the hair it touched, leaves the masters it did not bit for bit, is saved in the file
// as data and `ringlet style`'s code path replays the saved file bit for bit.
TEST_F(StudioSession, CombStrokeAndPuffReplayFromTheSavedFile) {
  Open();
  const auto groomed = session.Hair();
  // A tip of the hair seen from the front (+y, the face side): the ray from 1 m away, toward it.
  const StyledHair& before = groomed->styled;
  const Vec3 tip = ComputeGeometry(before.masters.models[5], before.solutions[5].curvatures)
                       .points.back();
  const Ray press{tip - Vec3(0, -1, 0), Vec3(0, -1, 0)};
  const std::optional<Vec3> from = PickMasterPoint(before, press, 0.004);
  ASSERT_TRUE(from.has_value());
  // The mouse moves 3 cm to the right and 1 cm up in the view plane (the camera looks along -y).
  const Ray release{*from + Vec3(0.03, 1, 0.01), Vec3(0, -1, 0)};
  const Vec3 to = StrokeEnd(*from, release, press.direction);
  EXPECT_LT((to - (*from + Vec3(0.03, 0, 0.01))).norm(), 1e-15);
  BrushSettings brush;
  brush.radius = 0.04;
  brush.strength = 1.0;
  brush.mirror = true;
  std::string error;
  ASSERT_TRUE(session.AddOperation(SculptOperation(brush, *from, to), &error)) << error;
  ASSERT_TRUE(session.AddOperation(PuffOperation(brush, Vec3(0, 0, 0.1), false), &error)) << error;
  session.Wait();
  ASSERT_TRUE(session.UpToDate());
  const auto styled = session.Hair();
  EXPECT_EQ(styled->stats.what, "puff");
  const Vec3 moved = ComputeGeometry(styled->styled.masters.models[5],
                                     styled->styled.solutions[5].curvatures)
                         .points.back() -
                     tip;
  EXPECT_GT(moved.x(), 0.01) << moved.transpose();
  int untouched = 0;
  for (size_t i = 0; i < before.masters.models.size(); ++i) {
    if (styled->styled.solutions[i].curvatures == before.solutions[i].curvatures) ++untouched;
  }
  EXPECT_GT(untouched, 20);  // 60 masters: the stroke and the crown's puff touch some only
  EXPECT_LT(untouched, 58);

  const std::string path = TempPath("combed.json");
  ASSERT_TRUE(session.Save(path, &error)) << error;
  std::ifstream file(path);
  const nlohmann::json saved = nlohmann::json::parse(file);
  ASSERT_EQ(saved["operations"].size(), 2u);
  EXPECT_TRUE(saved["operations"][0].contains("sculpt"));
  EXPECT_EQ(saved["operations"][0]["sculpt"]["mirror"], true);
  EXPECT_TRUE(saved["operations"][1].contains("puff"));
  ExpectSameBits(*styled->strands, StyleFile(path));
}

// ---------------------------------------------------------------------------------------------
// The brush tools' geometry (brush_tool.h), against hand-computed points.

// Two straight vertical strands of 0.2 m hanging from (0, 0, 0) and (-0.05, 0, 0): curvatures 0,
// 10 segments, so the samples lie every 5 mm down the z axis.
StyledHair TwoStraightStrands() {
  StyledHair hair;
  Mat3 frame;
  frame << 1, 0, 0, 0, -1, 0, 0, 0, -1;  // n1 = x, n2 = -y, t = -z
  for (double x : {0.0, -0.05}) {
    StrandModel m;
    m.segment_lengths = UniformSegments(0.2, 10);
    m.root_position = Vec3(x, 0, 0);
    m.root_frame = frame;
    hair.masters.models.push_back(m);
    StrandSolution s;
    s.curvatures = VecX::Zero(30);
    hair.solutions.push_back(s);
  }
  return hair;
}

TEST(StudioBrushTool, PicksTheNearestHairPointOnTheRay) {
  const StyledHair hair = TwoStraightStrands();
  // From +x toward -x at z = -0.1: both strands lie on the ray; the nearer (x = 0) wins, at its
  // sample z = -0.1 (20 samples of 5 mm down).
  const std::optional<Vec3> p = PickMasterPoint(hair, {Vec3(1, 0, -0.1), Vec3(-1, 0, 0)}, 0.003);
  ASSERT_TRUE(p.has_value());
  EXPECT_LT((*p - Vec3(0, 0, -0.1)).norm(), 1e-12) << p->transpose();
  // From -x: the other strand is nearer.
  const std::optional<Vec3> q = PickMasterPoint(hair, {Vec3(-1, 0, -0.1), Vec3(1, 0, 0)}, 0.003);
  ASSERT_TRUE(q.has_value());
  EXPECT_LT((*q - Vec3(-0.05, 0, -0.1)).norm(), 1e-12) << q->transpose();
  // 1 cm beside both strands, with a reach of 3 mm: nothing; behind the eye: nothing.
  EXPECT_FALSE(PickMasterPoint(hair, {Vec3(1, 0.01, -0.1), Vec3(-1, 0, 0)}, 0.003).has_value());
  EXPECT_FALSE(PickMasterPoint(hair, {Vec3(-1, 0, -0.1), Vec3(-1, 0, 0)}, 0.003).has_value());
}

TEST(StudioBrushTool, PicksTheBodySurfaceAndEndsStrokesInTheViewPlane) {
  Body body;
  std::string error;
  ASSERT_TRUE(Body::Create({Sphere{Vec3::Zero(), 0.1, "head"}}, {}, &body, &error)) << error;
  // A ray along +y at height 0.05 enters the sphere at y = -sqrt(0.1^2 - 0.05^2).
  const std::optional<Vec3> hit = PickBodyPoint(body, {Vec3(0, -1, 0.05), Vec3(0, 2, 0)}, 5.0);
  ASSERT_TRUE(hit.has_value());
  EXPECT_LT((*hit - Vec3(0, -std::sqrt(0.0075), 0.05)).norm(), 2e-6) << hit->transpose();
  EXPECT_FALSE(PickBodyPoint(body, {Vec3(0, -1, 0.2), Vec3(0, 1, 0)}, 5.0).has_value());
  EXPECT_FALSE(PickBodyPoint(body, {Vec3(0, -1, 0.05), Vec3(0, 1, 0)}, 0.5).has_value());

  // The plane through `from` facing a camera looking along +y is y = from.y.
  const Vec3 from(0.01, 0.02, 0.03);
  EXPECT_LT((StrokeEnd(from, {Vec3(0.3, -1, 0.2), Vec3(0, 1, 0)}, Vec3(0, 1, 0)) -
             Vec3(0.3, 0.02, 0.2))
                .norm(),
            1e-15);
  const Vec3 slanted = StrokeEnd(from, {Vec3(0, -1, 0), Vec3(0.1, 1, 0.2)}, Vec3(0, 1, 0));
  EXPECT_NEAR(slanted.y(), 0.02, 1e-15);
  EXPECT_NEAR(slanted.x(), 0.1 * 1.02, 1e-15);
  EXPECT_NEAR(slanted.z(), 0.2 * 1.02, 1e-15);
  // Parallel to the plane, or meeting it behind the eye: the stroke stays at from.
  EXPECT_EQ(StrokeEnd(from, {Vec3(0, -1, 0), Vec3(1, 0, 0)}, Vec3(0, 1, 0)), from);
  EXPECT_EQ(StrokeEnd(from, {Vec3(0, 1, 0), Vec3(0, 1, 0)}, Vec3(0, 1, 0)), from);
}

TEST(StudioBrushTool, StrokesBecomeValidOperations) {
  BrushSettings brush;
  brush.radius = 0.04;
  brush.strength = 0.8;
  brush.falloff = Brush::Falloff::kLinear;
  brush.mirror = false;
  brush.puff_angle = 0.25;
  const StyleOperation sculpt = SculptOperation(brush, Vec3(0, -0.1, 0), Vec3(0.01, -0.1, 0.02));
  std::string why;
  EXPECT_TRUE(sculpt.IsValid(&why)) << why;
  EXPECT_EQ(sculpt.kind, StyleOperation::Kind::kSculpt);
  EXPECT_EQ(sculpt.sculpt.brush.centre, Vec3(0, -0.1, 0));
  EXPECT_EQ(sculpt.sculpt.to, Vec3(0.01, -0.1, 0.02));
  EXPECT_EQ(sculpt.sculpt.brush.radius, 0.04);
  EXPECT_EQ(sculpt.sculpt.brush.strength, 0.8);
  EXPECT_EQ(sculpt.sculpt.brush.falloff, Brush::Falloff::kLinear);
  EXPECT_FALSE(sculpt.sculpt.brush.mirror);
  const StyleOperation lift = PuffOperation(brush, Vec3(0, 0, 0.1), false);
  const StyleOperation flat = PuffOperation(brush, Vec3(0, 0, 0.1), true);
  EXPECT_TRUE(lift.IsValid(&why)) << why;
  EXPECT_EQ(lift.puff_angle, 0.25);
  EXPECT_EQ(flat.puff_angle, -0.25);
  EXPECT_EQ(flat.puff_brush.centre, Vec3(0, 0, 0.1));
}

}  // namespace
}  // namespace ringlet::studio
