// Fuzz harness: .obj strands read as inverse-statics targets (ReadStrandTargets,
// strand_targets.h), through a file on tmpfs (the reader takes a path).
#include "fuzz_input.h"
#include "ringlet/strand_targets.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, size_t size) {
  const std::string path = ringlet::fuzz::InputFile(data, size, ".obj");
  ringlet::HairCurves curves;
  std::string error;
  const bool ok =
      ringlet::ReadStrandTargets(path, ringlet::StrandTargetOptions{}, &curves, &error);
  ringlet::fuzz::CheckAnswer(ok, error);
  if (ok) ringlet::fuzz::Require(ringlet::CheckHairCurves(curves, "curves", &error), error);
  return 0;
}
