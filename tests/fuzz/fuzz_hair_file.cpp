// Fuzz harness: Cem Yuksel's .hair files (DecodeHairFile, hair_file.h).
#include "fuzz_input.h"
#include "ringlet/hair_file.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, size_t size) {
  ringlet::HairCurves curves;
  std::string error;
  const bool ok = ringlet::DecodeHairFile(
      std::string_view(reinterpret_cast<const char*>(data), size), &curves, &error);
  ringlet::fuzz::CheckAnswer(ok, error);
  if (ok) ringlet::fuzz::Require(ringlet::CheckHairCurves(curves, "curves", &error), error);
  return 0;
}
