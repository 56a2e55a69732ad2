// Fuzz harness: USC-HairSalon .data files (DecodeUscData, usc_data.h), y up as the database.
#include "fuzz_input.h"
#include "ringlet/strand_targets.h"
#include "ringlet/usc_data.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, size_t size) {
  ringlet::StrandTargetOptions options;
  options.up_axis = ringlet::StrandTargetOptions::UpAxis::kY;
  ringlet::HairCurves curves;
  std::string error;
  const bool ok = ringlet::DecodeUscData(
      std::string_view(reinterpret_cast<const char*>(data), size), options, &curves, nullptr,
      &error);
  ringlet::fuzz::CheckAnswer(ok, error);
  if (ok) ringlet::fuzz::Require(ringlet::CheckHairCurves(curves, "curves", &error), error);
  return 0;
}
