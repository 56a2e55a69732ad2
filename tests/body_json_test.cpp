// Body descriptions in JSON (src/io/body_json.cpp): the shipped mannequins, paths in messages,
// every rejected field.
#include "ringlet/body_json.h"

#include <gtest/gtest.h>
#include <stdlib.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>

#include "ringlet/atomic_file.h"

namespace ringlet {
namespace {

using nlohmann::json;

std::string Examples() { return RINGLET_EXAMPLES_DIR; }

// A fresh empty directory for file tests, removed by the destructor.
class TempDirectory {
 public:
  TempDirectory() {
    std::string pattern = ::testing::TempDir() + "ringlet_body_json_XXXXXX";
    path_ = ::mkdtemp(pattern.data()) ? pattern : std::string();
  }
  ~TempDirectory() {
    std::error_code ec;
    if (!path_.empty()) std::filesystem::remove_all(path_, ec);
  }
  std::string Write(const std::string& name, const std::string& contents) const {
    const std::string file = path_ + "/" + name;
    std::ofstream(file) << contents;
    return file;
  }
  const std::string& path() const { return path_; }

 private:
  std::string path_;
};

// The box [-1, 1]^3 as an OBJ file of 6 quads.
const char* kBoxObj =
    "o box\nv -1 -1 -1\nv 1 -1 -1\nv -1 1 -1\nv 1 1 -1\nv -1 -1 1\nv 1 -1 1\nv -1 1 1\n"
    "v 1 1 1\nf 1 3 4 2\nf 5 6 8 7\nf 1 2 6 5\nf 3 7 8 4\nf 1 5 7 3\nf 2 4 8 6\n";

// The error of ParseBody on document under the prefix "body", expecting failure.
std::string Error(const json& document, const std::string& base = "") {
  Body body;
  std::string error;
  EXPECT_FALSE(ParseBody(document, "body", base, &body, &error)) << document.dump();
  EXPECT_TRUE(body.spheres().empty());  // untouched
  return error;
}

TEST(BodyJson, ParsesSpheres) {
  const json document = json::parse(R"({
    "description": "two spheres",
    "spheres": [{"name": "head", "center": [0, 0, 0], "radius": 0.1},
                {"center": [0, 0, -0.15], "radius": 0.05}]
  })");
  Body body;
  std::string error;
  ASSERT_TRUE(ParseBody(document, "body", "", &body, &error)) << error;
  ASSERT_EQ(body.spheres().size(), 2u);
  const Sphere* head = body.FindSphere("head");
  ASSERT_NE(head, nullptr);
  EXPECT_EQ(head->center, Vec3::Zero());
  EXPECT_EQ(head->radius, 0.1);
  EXPECT_EQ(body.spheres()[1].name, "");
  // Closed forms: 0.2 above the head's centre is 0.1 outside; the union's box.
  EXPECT_NEAR(body.SignedDistance(Vec3(0, 0, 0.2), nullptr), 0.1, 1e-16);
  EXPECT_TRUE(body.Bounds().isApprox(Box3(Vec3(-0.1, -0.1, -0.2), Vec3(0.1, 0.1, 0.1)), 1e-15));
}

TEST(BodyJson, MessagesNameTheFieldUnderThePrefix) {
  json spheres = json::parse(R"({"spheres": [
    {"center": [0, 0, 0], "radius": 0.1}, {"center": [0, 0, 0], "radius": 0.1},
    {"center": [0, 0, 0], "radius": -0.1}]})");
  EXPECT_EQ(Error(spheres), "body.spheres[2].radius: expected a positive number (m), got -0.1");

  EXPECT_EQ(Error(json::parse(R"({"spheres": [], "colour": "red"})")),
            "body.colour: unknown field (known fields: spheres, meshes, blend, description, "
            "mesh_distance, grid_spacing, grid_band)");
  EXPECT_EQ(Error(json::parse(R"({"spheres": [{"center": [0, 0, 0], "radius": 1, "r": 2}]})")),
            "body.spheres[0].r: unknown field (known fields: name, center, radius, moves_with)");
  EXPECT_EQ(Error(json::parse(R"({"spheres": [{"radius": 1}]})")),
            "body.spheres[0].center: missing required field (expected an array of 3 finite "
            "numbers (m))");
  EXPECT_EQ(Error(json::parse(R"({"spheres": [{"center": [0, 0], "radius": 1}]})")),
            "body.spheres[0].center: expected an array of 3 finite numbers (m), got [0,0]");
  EXPECT_EQ(Error(json::parse(R"({"spheres": [{"center": [0, "a", 0], "radius": 1}]})")),
            "body.spheres[0].center: expected an array of 3 finite numbers (m), got [0,\"a\",0]");
  EXPECT_EQ(Error(json::parse(R"({"spheres": [{"center": [0, 0, 0]}]})")),
            "body.spheres[0].radius: missing required field (expected a positive number (m))");
  EXPECT_EQ(Error(json::parse(R"({"spheres": [{"center": [0, 0, 0], "radius": "big"}]})")),
            "body.spheres[0].radius: expected a positive number (m), got \"big\"");
  EXPECT_EQ(Error(json::parse(R"({"spheres": [{"center": [0, 0, 0], "radius": 0}]})")),
            "body.spheres[0].radius: expected a positive number (m), got 0");
  EXPECT_EQ(Error(json::parse(R"({"spheres": [{"name": 3, "center": [0, 0, 0], "radius": 1}]})")),
            "body.spheres[0].name: expected a string, got 3");
  EXPECT_EQ(Error(json::parse(R"({"spheres": [{"name": "a", "center": [0, 0, 0], "radius": 1},
                                              {"name": "a", "center": [1, 0, 0], "radius": 1}]})")),
            "body.spheres[1].name: \"a\" is already the name of body.spheres[0] (names must be "
            "unique)");
  EXPECT_EQ(Error(json::parse(R"({"spheres": [1]})")),
            "body.spheres[0]: expected an object {\"center\": [x, y, z], \"radius\": r}, got 1");
  EXPECT_EQ(Error(json::parse(R"({"spheres": {"center": [0, 0, 0]}})")),
            "body.spheres: expected an array of sphere objects, got {\"center\":[0,0,0]}");
  EXPECT_EQ(Error(json::parse(R"({"meshes": "a.obj"})")),
            "body.meshes: expected an array of mesh objects, got \"a.obj\"");
  EXPECT_EQ(Error(json::parse(R"({"meshes": [{}]})")),
            "body.meshes[0].obj: missing required field (expected the path of an OBJ file "
            "(relative to the body file's directory))");
  EXPECT_EQ(Error(json::parse(R"({"meshes": [{"obj": "a.obj", "scale": 2}]})")),
            "body.meshes[0].scale: unknown field (known fields: obj, moves_with)");
  EXPECT_EQ(Error(json::parse(R"({"description": 1, "spheres": []})")),
            "body.description: expected a string, got 1");
  EXPECT_EQ(Error(json::parse(R"({})")),
            "body: a body needs at least one sphere or mesh (\"spheres\", \"meshes\")");
  EXPECT_EQ(Error(json::parse(R"([1, 2])")),
            "body: expected an object {\"spheres\": [...], \"meshes\": [...]}, got [1,2]");
}

// "moves_with": the part a sphere or an OBJ object moves with (docs/body.md, "Head and torso"),
// by name when absent; every wrong value named with its field.
TEST(BodyJson, MovesWithSetsThePartOfEachComponent) {
  TempDirectory dir;
  dir.Write("two.obj", std::string(kBoxObj) +
                           "o torso\nv 2 -1 -1\nv 4 -1 -1\nv 2 1 -1\nv 4 1 -1\nv 2 -1 1\n"
                           "v 4 -1 1\nv 2 1 1\nv 4 1 1\nf 9 11 12 10\nf 13 14 16 15\n"
                           "f 9 10 14 13\nf 11 15 16 12\nf 9 13 15 11\nf 10 12 16 14\n");
  Body body;
  std::string error;
  ASSERT_TRUE(ParseBody(json::parse(R"({"spheres": [
      {"name": "head", "center": [0, 0, 0], "radius": 0.1},
      {"name": "neck", "center": [0, 0, -1], "radius": 0.1},
      {"name": "hat", "center": [0, 0, 1], "radius": 0.1, "moves_with": "head"},
      {"name": "jaw", "center": [0, 1, 0], "radius": 0.1, "moves_with": "torso"}],
      "meshes": [{"obj": "two.obj"}, {"obj": "two.obj", "moves_with": "torso"},
                 {"obj": "two.obj", "moves_with": {"torso": "head"}}],
      "mesh_distance": "exact"})"),
                        "body", dir.path(), &body, &error)) << error;
  EXPECT_EQ(body.sphere_part(0), BodyPart::kHead);
  EXPECT_EQ(body.sphere_part(1), BodyPart::kTorso);
  EXPECT_EQ(body.sphere_part(2), BodyPart::kHead);
  EXPECT_EQ(body.sphere_part(3), BodyPart::kTorso);
  ASSERT_EQ(body.meshes().size(), 6u);  // box and torso, three times
  const BodyPart parts[6] = {BodyPart::kTorso, BodyPart::kTorso, BodyPart::kTorso,
                             BodyPart::kTorso, BodyPart::kTorso, BodyPart::kHead};
  for (size_t i = 0; i < 6; ++i) EXPECT_EQ(body.mesh_part(i), parts[i]) << i;  // "box": torso

  EXPECT_EQ(Error(json::parse(R"({"spheres": [{"center": [0, 0, 0], "radius": 1,
                                               "moves_with": "neck"}]})")),
            "body.spheres[0].moves_with: expected \"head\" or \"torso\" (the part it moves "
            "with), got \"neck\"");
  EXPECT_EQ(Error(json::parse(R"({"spheres": [{"center": [0, 0, 0], "radius": 1,
                                               "moves_with": 1}]})")),
            "body.spheres[0].moves_with: expected \"head\" or \"torso\" (the part it moves "
            "with), got 1");
  EXPECT_EQ(Error(json::parse(R"({"meshes": [{"obj": "two.obj", "moves_with": ["head"]}]})"),
                  dir.path()),
            "body.meshes[0].moves_with: expected \"head\", \"torso\" or an object {\"OBJ "
            "object or group name\": \"head\" or \"torso\"}, got [\"head\"]");
  EXPECT_EQ(Error(json::parse(R"({"meshes": [{"obj": "two.obj", "moves_with": "arm"}]})"),
                  dir.path()),
            "body.meshes[0].moves_with: expected \"head\" or \"torso\" (the part it moves "
            "with), got \"arm\"");
  EXPECT_EQ(Error(json::parse(R"({"meshes": [{"obj": "two.obj",
                                              "moves_with": {"torso": "feet"}}]})"),
                  dir.path()),
            "body.meshes[0].moves_with.torso: expected \"head\" or \"torso\" (the part it "
            "moves with), got \"feet\"");
  EXPECT_EQ(Error(json::parse(R"({"meshes": [{"obj": "two.obj",
                                              "moves_with": {"tors": "torso"}}]})"),
                  dir.path()),
            "body.meshes[0].moves_with.tors: expected the name of an object or group of two.obj "
            "(\"box\", \"torso\")");
}

TEST(BodyJson, MeshPathsAreRelativeToTheBaseDirectory) {
  TempDirectory dir;
  std::filesystem::create_directory(dir.path() + "/meshes");
  dir.Write("meshes/box.obj", kBoxObj);
  const json document = json::parse(R"({"meshes": [{"obj": "meshes/box.obj"}],
    "mesh_distance": "exact", "spheres": [{"name": "head", "center": [3, 0, 0], "radius": 0.5}]})");
  Body body;
  std::string error;
  ASSERT_TRUE(ParseBody(document, "body", dir.path(), &body, &error)) << error;
  ASSERT_EQ(body.meshes().size(), 1u);
  // Box [-1, 1]^3 and a sphere at x = 3: at (2, 0, 0) both are 0.5 (box face x = 1 at 1,
  // sphere surface at 2.5); at the origin the box's depth 1.
  EXPECT_NEAR(body.SignedDistance(Vec3(2, 0, 0), nullptr), 0.5, 1e-15);
  EXPECT_NEAR(body.SignedDistance(Vec3(0, 0, 0), nullptr), -1.0, 1e-15);

  // The same through a standalone file, loaded from another working directory.
  const std::string file = dir.Write("body.json", document.dump());
  Body loaded;
  ASSERT_TRUE(LoadBody(file, &loaded, &error)) << error;
  EXPECT_EQ(loaded.meshes().size(), 1u);

  // A missing OBJ names the field and the resolved path; a broken one the problem.
  EXPECT_EQ(
      Error(json::parse(R"({"meshes": [{"obj": "nowhere.obj"}]})"), dir.path()),
      "body.meshes[0].obj: " + dir.path() + "/nowhere.obj: cannot open: No such file or directory");
  dir.Write("open.obj", std::string(kBoxObj).substr(0, std::string(kBoxObj).rfind("f ")));
  EXPECT_EQ(Error(json::parse(R"({"meshes": [{"obj": "open.obj"}]})"), dir.path()),
            "body.meshes[0].obj: " + dir.path() +
                "/open.obj: box: edge (2, 4) belongs to 1 triangle (3, 4, 2): the mesh is not "
                "closed, so its inside is undefined");
}

// A mesh file name with control characters and thousands of bytes (found by the body_json
// fuzzer's long run: the name was quoted raw, newlines and all) is shown escaped and cut, on
// one bounded line.
TEST(BodyJson, OddMeshFileNamesStayOnOneBoundedLine) {
  TempDirectory dir;
  const std::string odd = "a\nb\tc\x01" + std::string(5000, 'x') + "\nend.obj";
  const std::string error =
      Error(json{{"meshes", json::array({json{{"obj", odd}}})}}, dir.path());
  EXPECT_EQ(error.find_first_of("\n\r\t"), std::string::npos) << error;
  EXPECT_LT(error.size(), 500u) << error;
  EXPECT_NE(error.find("/a\\nb\\tc\\x01xxx"), std::string::npos) << error;
  EXPECT_NE(error.find("...xxx"), std::string::npos) << error;
  EXPECT_NE(error.find("x\\nend.obj: cannot open: "), std::string::npos) << error;
  // Ordinary names are unchanged.
  const std::string ordinary = "/tmp/dir with spaces/b\u00e9b\u00e9.obj";
  EXPECT_EQ(DisplayPath(ordinary), ordinary);
  EXPECT_EQ(DisplayPath("tab\there\x7f"), "tab\\there\\x7f");
}

// Issue 16: tinyobjloader reads a bad coordinate as 0 and "8x" as 8; the lines are checked
// first, and refused with their number.
TEST(BodyJson, ObjLinesAreValidatedWithTheLineNumber) {
  TempDirectory dir;
  const std::string box(kBoxObj);
  struct Case {
    std::string from, to, message;
  };
  const Case cases[] = {
      {"v 1 -1 -1", "v nan -1 -1", "line 3: vertex: expected finite numbers, got \"nan\""},
      {"v 1 -1 -1", "v abc -1 -1", "line 3: vertex: expected finite numbers, got \"abc\""},
      {"v 1 -1 -1", "v 1 -1", "line 3: vertex: expected 3 coordinates x y z (m), got 2 values"},
      {"v 1 -1 -1", "v 1e999 -1 -1", "line 3: vertex: expected finite numbers, got \"1e999\""},
      {"v 1 -1 -1", "v 1.5x -1 -1", "got \"1.5x\""},
      {"f 2 4 8 6", "f 2 4 8x 6",
       "line 15: face: expected vertex references v, v/vt, v//vn or "
       "v/vt/vn (non-zero integers), got \"8x\""},
      {"f 2 4 8 6", "f 2 4 0 6", "line 15: face: expected vertex references"},
      {"f 2 4 8 6", "f 2 4/ 8 6", "got \"4/\""},
      {"f 2 4 8 6", "f 2 4", "line 15: face: expected at least 3 vertices, got 2"},
  };
  for (const Case& c : cases) {
    std::string text = box;
    text.replace(text.find(c.from), c.from.size(), c.to);
    dir.Write("bad.obj", text);
    const std::string error = Error(json::parse(R"({"meshes": [{"obj": "bad.obj"}]})"), dir.path());
    EXPECT_EQ(error.rfind("body.meshes[0].obj: " + dir.path() + "/bad.obj: line ", 0), 0u) << error;
    EXPECT_NE(error.find(c.message), std::string::npos) << c.to << ": " << error;
  }
  // What tinyobjloader also accepts stays accepted: comment lines, CRLF, v/vt/vn references,
  // negative (relative) indices, a vertex weight.
  std::string fancy = "# a box\r\nvn 0 0 1\r\nvt 0 0\r\n" + box;
  fancy.replace(fancy.find("v -1 -1 -1"), 10, "v -1 -1 -1 1.0");
  fancy.replace(fancy.find("f 1 3 4 2"), 9, "f -8//1 -6//1 -5//1 -7//1");
  dir.Write("fancy.obj", fancy);
  Body body;
  std::string error;
  // (a 2-m box: exact queries, the default 5-mm grid would need 74 million nodes)
  EXPECT_TRUE(ParseBody(json::parse(R"({"meshes": [{"obj": "fancy.obj"}],
                                        "mesh_distance": "exact"})"),
                        "body", dir.path(), &body, &error))
      << error;
}

TEST(BodyJson, LoadBodyReportsFileAndSyntaxErrors) {
  TempDirectory dir;
  Body body;
  std::string error;
  const std::string missing = dir.path() + "/missing.json";
  EXPECT_FALSE(LoadBody(missing, &body, &error));
  EXPECT_EQ(error, missing + ": cannot open: No such file or directory");

  const std::string broken = dir.Write("broken.json", "{\n  \"spheres\": [,]\n}\n");
  EXPECT_FALSE(LoadBody(broken, &body, &error));
  EXPECT_EQ(error.rfind(broken + ": line 2, column 15: invalid JSON: ", 0), 0u) << error;

  const std::string bad = dir.Write("bad.json", R"({"spheres": [{"center": [0, 0, 0]}]})");
  EXPECT_FALSE(LoadBody(bad, &body, &error));
  EXPECT_EQ(error, bad +
                       ": spheres[0].radius: missing required field (expected a positive "
                       "number (m))");
}

TEST(BodyJson, ShippedMannequinsLoad) {
  // Spheres only (the paper's approach): the head is the sphere of radius 0.1 m at the origin,
  // so the top of the head (0, 0, 0.1) is exactly on the surface.
  Body spheres;
  std::string error;
  ASSERT_TRUE(LoadBody(Examples() + "/bodies/mannequin.json", &spheres, &error)) << error;
  EXPECT_GE(spheres.spheres().size(), 6u);
  EXPECT_LE(spheres.spheres().size(), 10u);
  const Sphere* head = spheres.FindSphere("head");
  ASSERT_NE(head, nullptr);
  EXPECT_EQ(head->center, Vec3::Zero());
  EXPECT_EQ(head->radius, 0.1);
  EXPECT_EQ(spheres.SignedDistance(Vec3(0, 0, 0.1), nullptr), 0.0);
  // The neck and shoulders are there: inside at the neck, near the surface at the shoulders.
  EXPECT_LT(spheres.SignedDistance(Vec3(0, -0.01, -0.15), nullptr), -0.03);
  EXPECT_NEAR(spheres.SignedDistance(Vec3(0.13, -0.01, -0.22), nullptr), 0.0, 0.01);
  EXPECT_NEAR(spheres.SignedDistance(Vec3(-0.13, -0.01, -0.22), nullptr), 0.0, 0.01);

  // Meshes: three closed components; the head's top within 0.2 mm of the surface
  // (body_test.cpp checks the geometry in detail).
  Body meshes;
  ASSERT_TRUE(LoadBody(Examples() + "/bodies/mannequin_mesh.json", &meshes, &error)) << error;
  EXPECT_EQ(meshes.meshes().size(), 3u);
  EXPECT_NEAR(meshes.SignedDistance(Vec3(0, 0, 0.1), nullptr), 0.0, 2e-4);
}

}  // namespace
}  // namespace ringlet
