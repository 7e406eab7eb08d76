// Fuzz target: the scene-file parser (issue 18 item 7), the JSON a user or a render farm hands
// to `nephele render` / `animate`: every key, range and cross-check of scene/scene_file.cpp,
// without touching the data file it names (parseSceneText does not open it).
#include <string_view>

#include "fuzz_support.h"
#include "scene/scene_file.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string name = "fuzz-scene.json";
  nph::fuzz::expectCleanOutcome(name, [&] {
    (void)nph::scene::parseSceneText(std::string_view(reinterpret_cast<const char*>(data), size), name, "/nonexistent");
  });
  return 0;
}
