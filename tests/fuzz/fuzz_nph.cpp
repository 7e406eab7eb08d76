// Fuzz target: the .nph cache reader on its own (issue 18 item 7): header, JSON index, every
// timestep's chunks read, verified and decoded. Checksums reject almost every blind mutation,
// so the corpus also holds files whose checksums were recomputed over hostile headers (see
// tests/reliability/hostile_nph_test.cpp for how such files are built).
#include "cache/nph_cache.h"
#include "fuzz_support.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const nph::fuzz::ScratchInput input(data, size, "nephele-fuzz", ".nph");
  const std::string name = input.path().filename().string();
  nph::fuzz::expectCleanOutcome(name, [&] {
    const nph::cache::NphReader reader(input.path());
    for (std::size_t t = 0; t < reader.timestepCount() && t < 4; ++t) (void)reader.read(t);
  });
  return 0;
}
