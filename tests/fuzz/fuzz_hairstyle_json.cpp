// Fuzz harness: hairstyle files with their operations list (hairstyle_json.h,
// docs/hairstyle-format.md). The studio's saved sessions are hairstyle files (Session::Save
// writes the document and its operations; Session::Open reads them with LoadHairstyle), so this
// harness covers them too. Bodies given by file name are not read (kNoDirectory): body objects
// are fuzzed inline here and on their own by fuzz_body_json.
#include "fuzz_input.h"
#include "ringlet/hairstyle_json.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, size_t size) {
  ringlet::Hairstyle style;
  std::vector<ringlet::StyleOperation> operations;
  std::string error;
  const bool ok = ringlet::ParseHairstyleText(ringlet::fuzz::Text(data, size),
                                              ringlet::fuzz::kNoDirectory, &style, &operations,
                                              &error);
  ringlet::fuzz::CheckAnswer(ok, error);
  if (ok) ringlet::fuzz::Require(style.IsValid(&error), "hairstyle: " + error);
  return 0;
}
