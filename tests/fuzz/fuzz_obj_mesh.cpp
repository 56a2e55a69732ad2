// Fuzz harness: OBJ body meshes (LoadObjMeshes / ParseObjMeshes, body.h; docs/body.md).
#include "fuzz_input.h"
#include "ringlet/body.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, size_t size) {
  std::vector<ringlet::TriangleMesh> meshes;
  std::string error;
  const bool ok = ringlet::ParseObjMeshes(
      std::string_view(reinterpret_cast<const char*>(data), size), &meshes, &error);
  ringlet::fuzz::CheckAnswer(ok, error);
  if (ok) ringlet::fuzz::Require(!meshes.empty(), "no meshes returned");
  return 0;
}
