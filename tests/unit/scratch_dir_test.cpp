// The tests' scratch directory (tests/support/scratch_dir.h): fresh, distinct, named after the
// test, removed with its contents.
#include "support/scratch_dir.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

namespace nph::test {
namespace {

namespace fs = std::filesystem;

TEST(ScratchDir, IsFreshNamedAfterTheTestAndRemovedWithItsContents) {
  fs::path kept;
  {
    ScratchDir a("unit"), b("unit");
    ASSERT_TRUE(fs::is_directory(a.path()));
    EXPECT_TRUE(fs::is_empty(a.path()));
    EXPECT_NE(a.path(), b.path());
    EXPECT_EQ(a.path().parent_path(), fs::temp_directory_path());
    const std::string name = a.path().filename().string();
    EXPECT_EQ(name.rfind("nephele-unit-ScratchDir-IsFreshNamedAfterTheTestAndRemovedWithItsContents-", 0), 0u) << name;
    EXPECT_EQ(fs::path(a.file("x.nc")), a.path() / "x.nc");
    fs::create_directories(a.path() / "sub");
    std::ofstream(a.file("sub/f.txt")) << "data";
    kept = a.path();
  }
  EXPECT_FALSE(fs::exists(kept));
}

TEST(ScratchDir, ForProcessHasNoTestName) {
  const ScratchDir p = ScratchDir::forProcess("unit");
  EXPECT_EQ(p.path().filename().string().find("ScratchDir"), std::string::npos) << p.path();
  EXPECT_TRUE(fs::is_directory(p.path()));
}

class ScratchDirParam : public ::testing::TestWithParam<int> {};
TEST_P(ScratchDirParam, SlashOfParameterisedNamesIsReplaced) {
  ScratchDir d("unit");
  EXPECT_EQ(d.path().parent_path(), fs::temp_directory_path()) << d.path();
  EXPECT_NE(d.path().filename().string().find("Case_ScratchDirParam-SlashOfParameterisedNamesIsReplaced_0"),
            std::string::npos)
      << d.path();
}
INSTANTIATE_TEST_SUITE_P(Case, ScratchDirParam, ::testing::Values(7));

}  // namespace
}  // namespace nph::test
