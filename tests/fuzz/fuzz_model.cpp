// Fuzz target: a model file as `nephele render FILE` opens it (issue 18 item 7). The bytes are
// written to a scratch file and opened through engine::Dataset::open, which sniffs the format
// (.nph cache, WRF/ICON NetCDF classic or netCDF-4, ICON GRIB2) and runs the real loader; the
// first and last timesteps are then converted to extinction volumes (vertical resampling,
// optics, quantisation checks), which is where sizes and values taken from the file are used.
// Seeds: the generated tiny files (nephele-gen all, a .nph); see tests/fuzz/CMakeLists.txt.
#include "engine/dataset.h"
#include "fuzz_support.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const nph::fuzz::ScratchInput input(data, size, "nephele-fuzz-model", ".nc");
  const std::string name = input.path().filename().string();
  nph::fuzz::expectCleanOutcome(name, [&] {
    const auto dataset = nph::engine::Dataset::open(input.path().string());
    const std::size_t count = dataset->timestepCount();
    if (count == 0) return;
    (void)dataset->load(0);
    if (count > 1) (void)dataset->load(count - 1);
  });
  return 0;
}
