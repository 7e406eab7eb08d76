#pragma once
// The saved inputs a driver without libFuzzer feeds to a fuzz target (replay_main.cpp,
// mutate_main.cpp): files named on the command line, or found recursively in folders named there,
// in sorted order (so a run does the same on every machine), and their bytes.
#include <algorithm>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <vector>

namespace nph::fuzz {

/// Adds `p` (a regular file) or the regular files below it (a folder); false when it is neither.
inline bool addInputs(const std::filesystem::path& p, std::vector<std::filesystem::path>& out) {
  if (std::filesystem::is_directory(p)) {
    for (const auto& e : std::filesystem::recursive_directory_iterator(p))
      if (e.is_regular_file()) out.push_back(e.path());
    return true;
  }
  if (!std::filesystem::is_regular_file(p)) return false;
  out.push_back(p);
  return true;
}

inline std::vector<std::uint8_t> readInput(const std::filesystem::path& p) {
  std::ifstream in(p, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

}  // namespace nph::fuzz
