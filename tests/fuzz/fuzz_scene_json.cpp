// Fuzz harness: scene files (scene_json.h, docs/scene-format.md).
#include "fuzz_input.h"
#include "ringlet/scene_json.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, size_t size) {
  ringlet::Scene scene;
  std::string error;
  const bool ok = ringlet::ParseSceneText(ringlet::fuzz::Text(data, size), &scene, &error);
  ringlet::fuzz::CheckAnswer(ok, error);
  for (const ringlet::StrandModel& strand : scene.strands) {
    ringlet::fuzz::Require(ringlet::IsValid(strand, &error), "strand: " + error);
  }
  return 0;
}
