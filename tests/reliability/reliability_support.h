#pragma once
// Helpers of the reliability tests: a scratch folder per test, NetCDF-C edits of generated
// files, and the expectation "throws E whose message mentions all of these".
#include <gtest/gtest.h>
#include <netcdf.h>

#include <fcntl.h>
#include <pthread.h>
#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <functional>
#include <initializer_list>
#include <mutex>
#include <string>

#include "cache/nph_cache.h"
#include "support/scratch_dir.h"
#include "wrf_hurricane.h"

namespace nph::reliability {

/// A small valid wrfout (12 x 10 x 8 mass points, hourly timesteps) written by the generator.
inline void writeSmallWrf(const std::string& path, int timesteps = 1) {
  datagen::WrfHurricaneSpec s;
  s.nx = 12;
  s.ny = 10;
  s.nz = 8;
  s.ntimes = timesteps;
  datagen::writeWrfHurricane(s, path);
}

/// The .nph metadata describing `v`'s grid (what a conversion writes).
inline cache::NphMetadata nphMetadataOf(const ExtinctionVolumes& v) {
  cache::NphMetadata m;
  m.nx = v.nx;
  m.ny = v.ny;
  m.dz_m = v.dz_m;
  m.z_bottom_m = v.z_bottom_m;
  m.georef = v.georef;
  m.created_by = "nephele reliability test";
  return m;
}

/// A fresh folder for the running test, removed at its end (tests/support/scratch_dir.h).
using Scratch = nph::test::ScratchDir;

/// Opens a NetCDF file for writing, runs `fn(ncid)` in define mode when `define` is set, closes.
inline void ncEdit(const std::string& path, bool define, const std::function<void(int)>& fn) {
  int ncid = -1;
  ASSERT_EQ(nc_open(path.c_str(), NC_WRITE, &ncid), NC_NOERR) << path;
  if (define) {
    ASSERT_EQ(nc_redef(ncid), NC_NOERR);
  }
  fn(ncid);
  ASSERT_EQ(nc_close(ncid), NC_NOERR) << path;
}

inline int ncVar(int ncid, const char* name) {
  int id = -1;
  EXPECT_EQ(nc_inq_varid(ncid, name, &id), NC_NOERR) << name;
  return id;
}

/// With NEPHELE_FUZZ_CORPUS=DIR set, copies a hostile input into DIR/<target>/<Suite>.<Test>[-n]
/// (a regression case for the fuzz targets, tests/fuzz: `target` is model, nph or scene). To
/// refresh the committed corpus: NEPHELE_FUZZ_CORPUS=tests/fuzz/corpus
/// build/tests/reliability/nephele_reliability_tests --gtest_filter='Hostile*'.
inline void saveFuzzInput(const std::string& path, const char* target) {
  const char* dir = std::getenv("NEPHELE_FUZZ_CORPUS");
  if (dir == nullptr || *dir == '\0') return;
  const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
  const std::filesystem::path folder = std::filesystem::path(dir) / target;
  std::filesystem::create_directories(folder);
  const std::string stem = std::string(info->test_suite_name()) + "." + info->name();
  std::filesystem::path out = folder / stem;
  for (int n = 2; std::filesystem::exists(out); ++n) out = folder / (stem + "-" + std::to_string(n));
  std::filesystem::copy_file(path, out);
}

/// saveFuzzInput for an input held in memory (scene text).
inline void saveFuzzText(const std::string& text, const char* target) {
  if (std::getenv("NEPHELE_FUZZ_CORPUS") == nullptr) return;
  const std::filesystem::path tmp =
      std::filesystem::temp_directory_path() / ("nephele-corpus-" + std::to_string(::getpid()));
  {
    std::FILE* f = std::fopen(tmp.c_str(), "wb");
    ASSERT_NE(f, nullptr) << tmp;
    std::fwrite(text.data(), 1, text.size(), f);
    std::fclose(f);
  }
  saveFuzzInput(tmp.string(), target);
  std::filesystem::remove(tmp);
}

/// Runs `fn`, expects an exception of type E whose what() contains every one of `mentions`.
template <class E>
void expectError(const std::function<void()>& fn, std::initializer_list<std::string> mentions) {
  try {
    fn();
    ADD_FAILURE() << "no exception; expected one mentioning " << *mentions.begin();
  } catch (const E& e) {
    const std::string what = e.what();
    for (const std::string& m : mentions)
      EXPECT_NE(what.find(m), std::string::npos) << "\"" << m << "\" not in: " << what;
  } catch (const std::exception& e) {
    ADD_FAILURE() << "wrong exception type: " << e.what();
  }
}

/// Sees whether this process forks while it lives: a pthread_atfork child handler — it runs in
/// every child fork() makes and in no process posix_spawn starts — creates a marker file (open(2)
/// is async-signal-safe). nephele must not fork (core/process.h: a forked copy of a multithreaded
/// process deadlocked under ASan), so its tests assert !forked() around process starts.
class ForkWatch {
 public:
  explicit ForkWatch(const Scratch& dir) : marker_(dir.file("forked")) {
    static std::once_flag registered;
    std::call_once(registered, [] { pthread_atfork(nullptr, nullptr, &ForkWatch::inChild); });
    std::snprintf(markerPath(), kMarkerBytes, "%s", marker_.c_str());
  }
  ~ForkWatch() { markerPath()[0] = '\0'; }
  ForkWatch(const ForkWatch&) = delete;
  ForkWatch& operator=(const ForkWatch&) = delete;
  bool forked() const { return std::filesystem::exists(marker_); }

 private:
  static constexpr std::size_t kMarkerBytes = 4096;
  static char* markerPath() {
    static char path[kMarkerBytes] = {};
    return path;
  }
  static void inChild() {
    if (markerPath()[0] == '\0') return;
    const int fd = ::open(markerPath(), O_CREAT | O_WRONLY, 0600);
    if (fd >= 0) ::close(fd);
  }
  std::string marker_;
};

}  // namespace nph::reliability
