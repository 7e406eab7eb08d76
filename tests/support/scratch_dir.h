#pragma once
// The tests' one scratch directory (issue 17: it replaces four temp-directory helpers in io, scene,
// physics and the renderer tests, and the hand-made folders of the cache, engine and viewer tests).
#include <filesystem>
#include <string>
#include <string_view>

namespace nph::test {

/// A fresh, empty directory under the system temp dir, removed with everything in it when the object
/// is destroyed. Its name holds `tag`, the running gtest's suite and test names ('/' of parameterised
/// names becomes '_'), the process id and a random number, so tests running in parallel under
/// ctest -j never share one, and a folder left behind by a crash says whose it was.
class ScratchDir {
 public:
  /// A folder for the running test (outside a test: for the process).
  explicit ScratchDir(std::string_view tag = "test");
  /// A folder shared by the tests of this process, without a test name: hold it in a function-local
  /// static, so it is removed at exit.
  static ScratchDir forProcess(std::string_view tag);
  ~ScratchDir();
  ScratchDir(const ScratchDir&) = delete;
  ScratchDir& operator=(const ScratchDir&) = delete;

  const std::filesystem::path& path() const { return path_; }
  /// `name` inside the directory (nothing is created).
  std::string file(std::string_view name) const;

 private:
  ScratchDir(std::string_view tag, bool with_test_name);
  std::filesystem::path path_;
};

}  // namespace nph::test
