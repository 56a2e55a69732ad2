// Fuzz harness: body files (body_json.h, docs/body.md). OBJ meshes named by the file are not
// read (kNoDirectory); fuzz_obj_mesh fuzzes the OBJ reader.
#include "fuzz_input.h"
#include "ringlet/body_json.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, size_t size) {
  ringlet::Body body;
  std::string error;
  const bool ok = ringlet::ParseBodyText(ringlet::fuzz::Text(data, size),
                                         ringlet::fuzz::kNoDirectory, &body, &error);
  ringlet::fuzz::CheckAnswer(ok, error);
  return 0;
}
