// Fuzz harness: masters files (masters_json.h, docs/hairstyle-format.md "Explicit masters").
#include "fuzz_input.h"
#include "ringlet/masters_json.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, size_t size) {
  std::vector<ringlet::ExplicitMaster> masters;
  std::string error;
  const bool ok = ringlet::ParseMastersText(ringlet::fuzz::Text(data, size), &masters, &error);
  ringlet::fuzz::CheckAnswer(ok, error);
  for (const ringlet::ExplicitMaster& m : masters) {
    const size_t n = m.segment_lengths.size();
    ringlet::fuzz::Require(n >= 1, "master without segments");
    ringlet::fuzz::Require(m.rest_curvatures.size() == 0 ||
                               static_cast<size_t>(m.rest_curvatures.size()) == 3 * n,
                           "rest_curvatures not one triple per segment");
    ringlet::fuzz::Require(m.start_curvatures.size() == 0 ||
                               static_cast<size_t>(m.start_curvatures.size()) == 3 * n,
                           "curvatures not one triple per segment");
  }
  return 0;
}
