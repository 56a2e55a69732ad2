// Batch specs and items (batch.h, docs/batch.md): items are pure functions of (spec, index); the
// distributions draw what they say (moments against their closed forms); a bad spec is one line
// naming the field; shards cover the items once; manifest lines survive concurrent appends;
// resampling spaces points equally; the label maps of a known scene.
#include "ringlet/batch.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <numbers>
#include <string>
#include <thread>
#include <vector>

#include "ringlet/hair_bsdf.h"
#include "ringlet/hairstyle_json.h"
#include "ringlet/render.h"

namespace ringlet {
namespace {

using nlohmann::json;

// A spec over an inline hairstyle on one sphere (no file is read).
json SpecDocument() {
  return json::parse(R"({
    "seed": 5, "count": 400,
    "bases": [
      {"body": {"spheres": [{"name": "head", "center": [0, 0, 0], "radius": 0.1}]},
       "masters": {"count": 4, "segments": 4}, "wisps": {"strands_per_wisp": 1},
       "hair": {"curl": "wavy"}},
      {"body": {"spheres": [{"name": "head", "center": [0, 0, 0], "radius": 0.1}]},
       "masters": {"count": 5, "segments": 4}, "hair": {"curl": "curly"}}
    ],
    "parameters": {
      "hair.length": {"uniform": [0.1, 0.3]},
      "masters.count": {"uniform": [3, 6]},
      "hair.curl_spread": {"normal": {"mean": 0.2, "sd": 0.1, "min": 0.1, "max": 0.4}},
      "hair.origin": {"choice": ["asian", "caucasian", "african", "caucasian"]}
    },
    "operations": [{"probability": 0.25, "cut": {"length": {"uniform": [0.05, 0.08]}}}]
  })");
}

BatchSpec ParseOrDie(const json& document) {
  BatchSpec spec;
  std::string error;
  EXPECT_TRUE(ParseBatchSpec(document, ".", &spec, &error)) << error;
  return spec;
}

TEST(BatchSpec, ItemsArePureFunctionsOfSpecAndIndex) {
  const BatchSpec spec = ParseOrDie(SpecDocument());
  // Resolved in different orders and from a separately parsed spec: the same documents.
  const BatchSpec again = ParseOrDie(SpecDocument());
  std::vector<std::string> forward, backward;
  for (int k = 0; k < 20; ++k) forward.push_back(ResolveBatchItem(spec, k).hairstyle.dump());
  for (int k = 19; k >= 0; --k) backward.push_back(ResolveBatchItem(again, k).hairstyle.dump());
  for (int k = 0; k < 20; ++k) EXPECT_EQ(forward[k], backward[19 - k]) << "item " << k;
  // Different items differ (their own seeds at least).
  EXPECT_NE(forward[0], forward[1]);
  const BatchItem item = ResolveBatchItem(spec, 7);
  EXPECT_EQ(item.name, "item-000000007");
  EXPECT_EQ(item.index, 7);
  // The values recorded are the hairstyle's.
  for (const auto& [path, value] : item.parameters["values"].items()) {
    json node = item.hairstyle;
    size_t begin = 0;
    while (true) {
      const size_t dot = path.find('.', begin);
      node = node[path.substr(begin, dot == std::string::npos ? dot : dot - begin)];
      if (dot == std::string::npos) break;
      begin = dot + 1;
    }
    EXPECT_EQ(node, value) << path;
  }
}

TEST(BatchSpec, EachBaseBodyIsReadOnceAndSharedByItsItems) {
  const BatchSpec spec = ParseOrDie(SpecDocument());
  ASSERT_EQ(spec.bodies.size(), 2u);
  for (const auto& body : spec.bodies) {
    ASSERT_NE(body, nullptr);
    ASSERT_EQ(body->spheres().size(), 1u);
    EXPECT_EQ(body->spheres()[0].radius, 0.1);
  }
  // ParseHairstyle with a body takes it as it is, and still requires the member.
  const BatchItem item = ResolveBatchItem(spec, 3);
  Hairstyle style;
  std::string error;
  ASSERT_TRUE(ParseHairstyle(item.hairstyle, ".", spec.bodies[item.base], &style, &error)) << error;
  EXPECT_EQ(style.body.get(), spec.bodies[item.base].get());
  json no_body = item.hairstyle;
  no_body.erase("body");
  EXPECT_FALSE(ParseHairstyle(no_body, ".", spec.bodies[0], &style, &error));
  EXPECT_NE(error.find("body: missing required field"), std::string::npos) << error;
}

TEST(BatchSpec, ItemSeedsDifferPerItemUnlessTurnedOff) {
  const BatchSpec spec = ParseOrDie(SpecDocument());
  std::map<std::uint64_t, int> seeds;
  for (int k = 0; k < 50; ++k) {
    const json style = ResolveBatchItem(spec, k).hairstyle;
    const std::uint64_t seed = style["masters"]["seed"].get<std::uint64_t>();
    EXPECT_LE(seed, std::uint64_t{1} << 53);
    ++seeds[seed];
    EXPECT_NE(style["hair"]["seed"], style["masters"]["seed"]);
  }
  EXPECT_EQ(seeds.size(), 50u);
  json document = SpecDocument();
  document["item_seeds"] = false;
  const BatchSpec fixed = ParseOrDie(document);
  for (int k = 0; k < 5; ++k) {
    EXPECT_FALSE(ResolveBatchItem(fixed, k).hairstyle["masters"].contains("seed"));
  }
}

// Moments of the draws over many items against the distributions' closed forms, within 4.5
// standard errors (a false failure about once in 150,000 runs per check; the draws are
// deterministic, so a pass is a pass for good).
TEST(BatchSpec, DistributionsDrawWhatTheySay) {
  const BatchSpec spec = ParseOrDie(SpecDocument());
  const int n = 400;
  std::vector<double> length, spread;
  std::map<int, int> count, base;
  std::map<std::string, int> origin;
  int cuts = 0;
  for (int k = 0; k < n; ++k) {
    const BatchItem item = ResolveBatchItem(spec, k);
    const json& v = item.parameters["values"];
    length.push_back(v["hair.length"].get<double>());
    spread.push_back(v["hair.curl_spread"].get<double>());
    ++count[v["masters.count"].get<int>()];
    ++origin[v["hair.origin"].get<std::string>()];
    ++base[item.base];
    const json& ops = item.parameters["operations"];
    if (!ops.empty()) {
      ++cuts;
      const double l = ops[0]["cut"]["length"].get<double>();
      EXPECT_GE(l, 0.05);
      EXPECT_LT(l, 0.08);
    }
  }
  const auto mean = [](const std::vector<double>& x) {
    double s = 0;
    for (double v : x) s += v;
    return s / static_cast<double>(x.size());
  };
  // Uniform [0.1, 0.3): mean 0.2, SD 0.2 / sqrt(12).
  for (double x : length) {
    EXPECT_GE(x, 0.1);
    EXPECT_LT(x, 0.3);
  }
  const double sd_uniform = 0.2 / std::sqrt(12.0);
  EXPECT_NEAR(mean(length), 0.2, 4.5 * sd_uniform / std::sqrt(n));
  // Integers 3..6 inclusive: each with probability 1/4 (binomial SD sqrt(n p (1 - p))).
  ASSERT_EQ(count.size(), 4u);
  for (const auto& [value, c] : count) {
    EXPECT_GE(value, 3);
    EXPECT_LE(value, 6);
    EXPECT_NEAR(c, n / 4.0, 4.5 * std::sqrt(n * 0.25 * 0.75)) << value;
  }
  // Choice of 4 with "caucasian" twice: probabilities 1/4, 1/2, 1/4.
  EXPECT_NEAR(origin["caucasian"], n / 2.0, 4.5 * std::sqrt(n * 0.25));
  EXPECT_NEAR(origin["asian"], n / 4.0, 4.5 * std::sqrt(n * 0.25 * 0.75));
  // Two bases, 1/2 each; the cut with probability 1/4.
  EXPECT_NEAR(base[0], n / 2.0, 4.5 * std::sqrt(n * 0.25));
  EXPECT_NEAR(cuts, n / 4.0, 4.5 * std::sqrt(n * 0.25 * 0.75));
  // Normal(0.2, 0.1) truncated to [0.1, 0.4]: mean mu + sigma (phi(a) - phi(b)) / (Phi(b) -
  // Phi(a)), a = -1, b = 2 (Johnson, Kotz & Balakrishnan, Continuous Univariate Distributions
  // 1, eq. 13.134); the SD bounded by the untruncated 0.1.
  const auto phi = [](double x) {
    return std::exp(-0.5 * x * x) / std::sqrt(2 * std::numbers::pi);
  };
  const auto Phi = [](double x) { return 0.5 * std::erfc(-x / std::sqrt(2.0)); };
  const double truncated_mean = 0.2 + 0.1 * (phi(-1) - phi(2)) / (Phi(2) - Phi(-1));
  for (double x : spread) {
    EXPECT_GE(x, 0.1);
    EXPECT_LE(x, 0.4);
  }
  EXPECT_NEAR(mean(spread), truncated_mean, 4.5 * 0.1 / std::sqrt(n));
}

TEST(BatchSpec, IntegerFieldsOfOperationsDrawIntegers) {
  json document = SpecDocument();
  document["operations"] = json::parse(R"([
    {"grow": {"step": 0.01, "steps": {"uniform": [1, 3]}}},
    {"cut": {"plane": {"normal": [0, 0, 1], "offset": {"uniform": [-0.2, -0.1]}}}}
  ])");
  const BatchSpec spec = ParseOrDie(document);
  std::map<std::int64_t, int> steps;
  for (int k = 0; k < 60; ++k) {
    const json ops = ResolveBatchItem(spec, k).parameters["operations"];
    ASSERT_EQ(ops.size(), 2u);
    ASSERT_TRUE(ops[0]["grow"]["steps"].is_number_integer()) << ops[0];
    ++steps[ops[0]["grow"]["steps"].get<std::int64_t>()];
    EXPECT_EQ(ops[1]["cut"]["plane"]["normal"], json::parse("[0, 0, 1]"));
    const double offset = ops[1]["cut"]["plane"]["offset"].get<double>();
    EXPECT_GE(offset, -0.2);
    EXPECT_LT(offset, -0.1);
  }
  EXPECT_EQ(steps.size(), 3u);
  EXPECT_EQ(steps.begin()->first, 1);
  EXPECT_EQ(steps.rbegin()->first, 3);
}

TEST(BatchSpec, BadSpecsNameTheField) {
  struct Case {
    const char* patch;  // merged into the good spec (null values remove members)
    const char* message;
  };
  const Case cases[] = {
      {R"({"count": 0})", "count: expected an integer between 1 and 1000000000, got 0"},
      {R"({"count": null})", "count: missing required field"},
      {R"({"seed": -1})", "seed: expected an integer between 0 and 2^53"},
      {R"({"bases": []})", "bases: expected an array of 1 to 1000"},
      {R"({"bases": [3]})", "bases[0]: expected a hairstyle file name or a hairstyle object"},
      {R"({"parameters": {"hair.lenght": {"uniform": [0.1, 0.2]}}})",
       "parameters[\"hair.lenght\"]: not a hairstyle field a batch can vary"},
      {R"({"parameters": {"hair.length": {"uniform": [0.3, 0.1]}}})",
       "parameters[\"hair.length\"].uniform: expected [low, high]: finite numbers, low < high"},
      {R"({"parameters": {"hair.length": {"uniform": [-0.1, 0.1]}}})",
       "with the parameters at their lowest bounds and choice[0] of each choice (its last when "
       "shorter): hair.length: expected"},
      {R"({"parameters": {"hair.length": {"gamma": [1, 2]}}})",
       "parameters[\"hair.length\"]: expected a distribution"},
      {R"({"parameters": {"hair.curl": {"uniform": [1, 2]}}})",
       "parameters[\"hair.curl\"].uniform: only \"choice\" can give a string"},
      {R"({"parameters": {"masters.segments": {"choice": [2.5]}}})",
       "parameters[\"masters.segments\"].choice[0]: expected an integer, got 2.5"},
      {R"({"parameters": {"hair.curl_radius": {"normal": {"mean": 0.2, "sd": 0.1, "min": 0.3, "max": 0.2}}}})",
       "parameters[\"hair.curl_radius\"].normal.max: expected a number > min"},
      {R"({"operations": [{"cut": {"z": 0}, "probability": 2}]})",
       "operations[0].probability: expected a number in [0, 1], got 2"},
      {R"({"operations": [{"cut": {"z": 0}, "wet": {}}]})", "one operation per entry"},
      {R"({"operations": [{"cut": {"z": {"choice": ["low"]}}}]})", "operations[0].cut.z"},
      {R"({"views": {"orbit": {"count": 0}}})",
       "views.orbit.count: expected an integer between 1 and 1000, got 0"},
      {R"({"views": [{"position": [0, 1, 0]}]})", "views[0].camera"},
      {R"({"outputs": {"points_per_strand": 1}})",
       "outputs.points_per_strand: expected an integer between 2 and 65536, got 1"},
      {R"({"outputs": {"formats": ["hair", "hair"]}})",
       "outputs.formats[1]: expected each format once"},
      {R"({"outputs": {"images": {"width": 0}}})", "outputs.images.width"},
      {R"({"outptus": {}})", "outptus: unknown field (did you mean \"outputs\"?)"},
  };
  for (const Case& c : cases) {
    json document = SpecDocument();
    document.merge_patch(json::parse(c.patch));
    BatchSpec spec;
    spec.count = 77;
    std::string error;
    EXPECT_FALSE(ParseBatchSpec(document, ".", &spec, &error)) << c.patch;
    EXPECT_NE(error.find(c.message), std::string::npos) << c.patch << "\n  got: " << error;
    EXPECT_EQ(error.find('\n'), std::string::npos) << error;
    EXPECT_EQ(spec.count, 77) << "the spec was changed by a failed parse: " << c.patch;
  }
}

TEST(BatchSpec, OrbitViewsCircleTheHeadAtTheElevation) {
  json document = SpecDocument();
  document["views"] = json::parse(R"({"orbit": {"count": 4, "elevation_degrees": 30}})");
  const BatchSpec spec = ParseOrDie(document);
  ASSERT_EQ(spec.views.size(), 4u);
  // View 0 from the face (+y) looking toward -y and down; views a quarter turn apart.
  const double c = std::cos(std::numbers::pi / 6), s = std::sin(std::numbers::pi / 6);
  const double expected[4][3] = {{0, -c, -s}, {-c, 0, -s}, {0, c, -s}, {c, 0, -s}};
  for (int v = 0; v < 4; ++v) {
    for (int i = 0; i < 3; ++i) {
      EXPECT_NEAR(spec.views[v]["view_direction"][i].get<double>(), expected[v][i], 1e-15);
    }
  }
}

TEST(BatchItems, RunWritesTheDocumentedFilesWithExplicitViews) {
  const json document = json::parse(R"({
    "count": 2,
    "bases": [{"body": {"spheres": [{"name": "head", "center": [0, 0, 0], "radius": 0.1}]},
               "masters": {"count": 3, "segments": 4},
               "hair": {"length": 0.12},
               "wisps": {"strands_per_wisp": 2, "points_per_strand": 6}}],
    "views": [{"position": [0, 0.6, 0.1], "look_at": [0, 0, 0], "fov_degrees": 40},
              {"view_direction": [0, 1, 0]}],
    "outputs": {"formats": ["hair", "data"], "points_per_strand": 5,
                "images": {"width": 16, "height": 12, "samples_per_pixel": 1}}
  })");
  const BatchSpec spec = ParseOrDie(document);
  const BatchItem item = ResolveBatchItem(spec, 1);
  const BatchItemResult result = RunBatchItem(spec, item, 1, nullptr);
  ASSERT_EQ(result.status, BatchItemResult::Status::kDone) << result.error;
  std::vector<std::string> names;
  for (const auto& file : result.files) names.push_back(file.first);
  const std::vector<std::string> expected = {
      "hairstyle.json", "strands.hair",       "strands.data", "rgb_00.png",
      "mask_00.png",    "orientation_00.png", "depth_00.npy", "rgb_01.png",
      "mask_01.png",    "orientation_01.png", "depth_01.npy", "metadata.json"};
  EXPECT_EQ(names, expected);
  const json metadata = json::parse(result.files.back().second);
  EXPECT_EQ(metadata["status"], "done");
  EXPECT_EQ(metadata["strands"]["strands"], 6);
  EXPECT_EQ(metadata["strands"]["points"], 30);
  EXPECT_EQ(metadata["views"][0]["camera"]["position"], json::parse("[0, 0.6, 0.1]"));
  EXPECT_EQ(metadata["views"][0]["width"], 16);
  EXPECT_EQ(metadata["views"][0]["height"], 12);
  // The framed view looks along +y: the camera lies on the -y side of the head.
  EXPECT_LT(metadata["views"][1]["camera"]["position"][1].get<double>(), -0.1);
  // depth_00.npy: the 128-byte header, then 16 x 12 float32.
  EXPECT_EQ(result.files[6].second.size(), 128u + 16u * 12u * 4u);
  EXPECT_EQ(result.files[6].second.substr(0, 6), "\x93NUMPY");
  // The same bytes on two threads.
  const BatchItemResult again = RunBatchItem(spec, item, 2, nullptr);
  ASSERT_EQ(again.files.size(), result.files.size());
  for (size_t i = 0; i < result.files.size(); ++i) {
    EXPECT_EQ(again.files[i].second, result.files[i].second) << result.files[i].first;
  }
}

TEST(BatchRange, ShardsCoverTheItemsOnceInBlocks) {
  for (const std::int64_t length : {1, 7, 12, 1000}) {
    for (const int n : {1, 2, 3, 5, 12, 13}) {
      const BatchRange range{10, 10 + length};
      std::int64_t next = range.begin;
      for (int k = 0; k < n; ++k) {
        const BatchRange shard = ShardRange(range, k, n);
        EXPECT_EQ(shard.begin, next);
        const std::int64_t size = shard.end - shard.begin;
        EXPECT_TRUE(size == length / n || size == length / n + 1) << length << " " << n;
        next = shard.end;
      }
      EXPECT_EQ(next, range.end);
    }
  }
  BatchRange r;
  std::string error;
  EXPECT_TRUE(ParseItemRange("3:5", 12, &r, &error));
  EXPECT_EQ(r.begin, 3);
  EXPECT_EQ(r.end, 5);
  for (const char* bad : {"5:3", "3:3", "-1:2", "a:b", "3", "0:13", " 1:2"}) {
    EXPECT_FALSE(ParseItemRange(bad, 12, &r, &error)) << bad;
    EXPECT_NE(error.find("--items"), std::string::npos);
  }
  int k = 0, n = 0;
  EXPECT_TRUE(ParseShard("2/3", &k, &n, &error));
  EXPECT_EQ(k, 2);
  EXPECT_EQ(n, 3);
  for (const char* bad : {"3/3", "1/0", "1", "-1/2", "1/2/3"}) {
    EXPECT_FALSE(ParseShard(bad, &k, &n, &error)) << bad;
  }
}

TEST(BatchStore, ConcurrentManifestAppendsStayWholeLines) {
  const std::string path = (std::filesystem::temp_directory_path() /
                            ("ringlet_manifest_" + std::to_string(::getpid()) + ".jsonl"))
                               .string();
  std::filesystem::remove(path);
  const int threads = 4, lines = 50;
  // Long lines (> PIPE_BUF) so that an unlocked, split write would show.
  const std::string padding(5000, 'x');
  std::vector<std::thread> workers;
  for (int t = 0; t < threads; ++t) {
    workers.emplace_back([&, t] {
      for (int i = 0; i < lines; ++i) {
        std::string error;
        const json line = {{"thread", t}, {"i", i}, {"padding", padding}};
        EXPECT_TRUE(AppendManifestLine(path, line.dump(), &error)) << error;
      }
    });
  }
  for (std::thread& w : workers) w.join();
  std::ifstream in(path);
  std::string text;
  int count = 0;
  std::map<int, int> per_thread;
  while (std::getline(in, text)) {
    const json line = json::parse(text);  // throws (fails) on an interleaved line
    EXPECT_EQ(line["padding"], padding);
    ++per_thread[line["thread"].get<int>()];
    ++count;
  }
  EXPECT_EQ(count, threads * lines);
  for (int t = 0; t < threads; ++t) EXPECT_EQ(per_thread[t], lines);
  std::filesystem::remove(path);
}

TEST(BatchItems, ResampleSpacesPointsEquallyInArcLength) {
  // An L-shaped strand with uneven points: 0.3 m along x (points at 0, 0.05, 0.3), then 0.1 m
  // along z; 5 points 0.1 m apart along the path.
  HairCurves curves;
  curves.point_counts = {4, 2};
  curves.points = {Vec3f(0, 0, 0),       Vec3f(0.05f, 0, 0), Vec3f(0.3f, 0, 0),
                   Vec3f(0.3f, 0, 0.1f), Vec3f(1, 1, 1),     Vec3f(1, 1, 2)};
  curves.widths = {1e-4f, 1e-4f, 1e-4f, 5e-5f, 2e-4f, 0.0f};
  curves.colors = {Vec3f(1, 0, 0), Vec3f(0, 1, 0)};
  const HairCurves out = ResampleStrands(curves, 5);
  ASSERT_EQ(out.point_counts, (std::vector<std::uint32_t>{5, 5}));
  const Vec3f expected[5] = {Vec3f(0, 0, 0), Vec3f(0.1f, 0, 0), Vec3f(0.2f, 0, 0),
                             Vec3f(0.3f, 0, 0), Vec3f(0.3f, 0, 0.1f)};
  for (int j = 0; j < 5; ++j) {
    EXPECT_NEAR((out.points[j] - expected[j]).norm(), 0.0, 1e-7) << j;
  }
  EXPECT_NEAR(out.widths[4], 5e-5f, 1e-12);
  EXPECT_NEAR(out.widths[3], 1e-4f, 1e-12);
  // The second strand: a straight line, widths from 2e-4 to 0 linearly.
  for (int j = 0; j < 5; ++j) {
    EXPECT_NEAR(out.points[5 + j].z(), 1.0 + 0.25 * j, 1e-7);
    EXPECT_NEAR(out.widths[5 + j], 2e-4 * (1.0 - 0.25 * j), 1e-11);
  }
  EXPECT_EQ(out.colors, curves.colors);
}

// One straight strand across the view of an explicit camera: the labels of the centre row.
TEST(RenderLabels, StrandAcrossTheViewGivesMaskDirectionAndDepth) {
  HairCurves hair;
  hair.point_counts = {2};
  // Root to tip along +x, a quarter of a pixel (1.5 mm, pixels are 2 tan(0.1) / 33 = 6.08 mm
  // wide at 1 m) above the rays of the centre row.
  const float z0 = 1.5e-3f;
  hair.points = {Vec3f(-0.05f, 0, z0), Vec3f(0.05f, 0, z0)};
  hair.widths = {1e-4f, 1e-4f};
  RenderScene scene;
  scene.hair = &hair;
  scene.fibre = std::make_shared<HairBsdf>(HairOptics{});
  scene.camera.position = Vec3(0, -1, 0);  // looking along +y at the strand, 1 m away
  scene.camera.look_at = Vec3::Zero();
  scene.camera.vertical_fov = 0.2;
  RenderOptions options;
  options.width = 33;
  options.height = 33;
  RenderLabels labels;
  std::string error;
  ASSERT_TRUE(RenderLabelMaps(scene, options, 1.0, &labels, &error)) << error;
  ASSERT_EQ(labels.hair.size(), 33u * 33u);
  // Half the image is tan(0.1) m wide at 1 m: the strand (0.05 m each side) covers columns
  // whose centre lies within 0.05 / tan(0.1) * 16.5 = 8.2 pixels of the centre (16.5).
  const double half_columns = 0.05 / std::tan(0.1) * 16.5;
  for (int y = 0; y < 33; ++y) {
    for (int x = 0; x < 33; ++x) {
      const size_t i = static_cast<size_t>(y) * 33 + x;
      const bool on = y == 16 && std::abs(x + 0.5 - 16.5) < half_columns - 0.5;
      // (+ half a pixel more for the round end caps)
      const bool off = y != 16 || std::abs(x + 0.5 - 16.5) > half_columns + 1.0;
      if (on) {
        EXPECT_EQ(labels.hair[i], 1) << x << ", " << y;
        EXPECT_NEAR(labels.direction[i].x(), 1.0, 1e-6);
        EXPECT_NEAR(labels.direction[i].y(), 0.0, 1e-6);
        // z-depth: the axis lies 1 m ahead; the hit is on the surface of the widened tube
        // (radius r = half a pixel, 3.04 mm), sqrt(r^2 - z0^2) = 2.64 mm closer.
        const double r = std::tan(0.1) / 33.0;
        EXPECT_NEAR(labels.depth[i], 1.0 - std::sqrt(r * r - z0 * z0), 1e-5);
      }
      if (off) {
        EXPECT_EQ(labels.hair[i], 0) << x << ", " << y;
        EXPECT_EQ(labels.depth[i], 0.0f);
      }
    }
  }
  // With the true 0.1-mm width, every centre ray passes 1.5 mm from the axis and misses.
  ASSERT_TRUE(RenderLabelMaps(scene, options, 0.0, &labels, &error)) << error;
  int hits = 0;
  for (const std::uint8_t h : labels.hair) hits += h;
  EXPECT_EQ(hits, 0);
}

}  // namespace
}  // namespace ringlet
