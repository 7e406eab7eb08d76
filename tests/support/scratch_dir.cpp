#include "support/scratch_dir.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <random>
#include <system_error>

namespace nph::test {

ScratchDir::ScratchDir(std::string_view tag) : ScratchDir(tag, true) {}

ScratchDir ScratchDir::forProcess(std::string_view tag) { return ScratchDir(tag, false); }

ScratchDir::ScratchDir(std::string_view tag, bool with_test_name) {
  std::string name = "nephele-" + std::string(tag);
  const auto* info = with_test_name ? ::testing::UnitTest::GetInstance()->current_test_info() : nullptr;
  if (info != nullptr) {
    name += "-" + std::string(info->test_suite_name()) + "-" + info->name();
  }
  for (char& c : name) {
    if (c == '/') c = '_';
  }
  name += "-" + std::to_string(::getpid()) + "-" + std::to_string(std::random_device{}());
  path_ = std::filesystem::temp_directory_path() / name;
  std::filesystem::create_directories(path_);
}

ScratchDir::~ScratchDir() {
  std::error_code ec;  // never throw from a destructor; a leftover folder in /tmp is harmless
  std::filesystem::remove_all(path_, ec);
}

std::string ScratchDir::file(std::string_view name) const { return (path_ / name).string(); }

}  // namespace nph::test
