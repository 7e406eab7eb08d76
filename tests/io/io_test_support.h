#pragma once
// Helpers for the io tests: a per-test temporary directory and small NetCDF-C edits used to
// break generated files in controlled ways.
#include <gtest/gtest.h>
#include <netcdf.h>

#include <filesystem>
#include <random>
#include <string>

namespace nph::io::test {

/// A fresh directory under the system temp dir, removed when the test ends.
class TempDir {
 public:
  TempDir() {
    std::random_device rd;
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    std::string name = info ? std::string(info->test_suite_name()) + "-" + info->name() : "io";
    for (char& c : name) {
      if (c == '/') c = '_';
    }
    path_ = std::filesystem::temp_directory_path() / ("nephele-io-" + name + "-" + std::to_string(rd()));
    std::filesystem::create_directories(path_);
  }
  ~TempDir() {
    std::error_code ec;
    std::filesystem::remove_all(path_, ec);
  }
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;
  std::string file(const std::string& name) const { return (path_ / name).string(); }

 private:
  std::filesystem::path path_;
};

/// Asserts a NetCDF-C status inside a test helper.
inline void ncCheck(int status, const char* what) {
  ASSERT_EQ(status, NC_NOERR) << what << ": " << nc_strerror(status);
}

}  // namespace nph::io::test
