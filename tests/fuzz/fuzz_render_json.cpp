// Fuzz harness: render settings, the "render" member of a hairstyle or settings file
// (render_json.h, docs/hairstyle-format.md#render).
#include "fuzz_input.h"
#include "ringlet/render_json.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, size_t size) {
  ringlet::RenderSettings settings;
  std::string error;
  // As `render --settings` reads it: the member is required.
  const bool ok = ringlet::ParseRenderSettingsText(ringlet::fuzz::Text(data, size), &settings,
                                                   &error, /*required=*/true);
  ringlet::fuzz::CheckAnswer(ok, error);
  return 0;
}
