// Hostile NetCDF inputs (issue #18), each built with NetCDF-C from a generated wrfout / ICON file:
// the loaders must refuse them with an InputError naming the file, the variable or attribute and
// what was expected, before any undefined behaviour, huge allocation or hang.
#include <netcdf.h>
#include <sys/stat.h>

#include <cmath>
#include <filesystem>
#include <limits>
#include <vector>

#include "core/error.h"
#include "core/terminal_text.h"
#include "engine/dataset.h"
#include "icon_scene.h"
#include "io/classic_header.h"
#include "io/icon_loader.h"
#include "io/model_file.h"
#include "io/wrf_loader.h"
#include "physics/extinction.h"
#include "physics/vertical_resampling.h"
#include "reliability_support.h"
#include "wrf_hurricane.h"

namespace nph::reliability {
namespace {

std::string smallWrf(const Scratch& dir) {
  const std::string path = dir.file("wrfout.nc");
  writeSmallWrf(path);
  return path;
}

void putGlobalDouble(const std::string& path, const char* name, double value) {
  ncEdit(path, true,
         [&](int nc) { ASSERT_EQ(nc_put_att_double(nc, NC_GLOBAL, name, NC_DOUBLE, 1, &value), NC_NOERR); });
}

void putElement(const std::string& path, const char* var, std::size_t element, float value) {
  ncEdit(path, false, [&](int nc) {
    const int id = ncVar(nc, var);
    int ndims = 0;
    nc_inq_varndims(nc, id, &ndims);
    std::vector<int> dims(static_cast<std::size_t>(ndims));
    nc_inq_vardimid(nc, id, dims.data());
    std::vector<std::size_t> index(static_cast<std::size_t>(ndims));
    for (int d = ndims - 1; d >= 0; --d) {  // unravel, last dimension fastest
      std::size_t len = 0;
      nc_inq_dimlen(nc, dims[std::size_t(d)], &len);
      index[std::size_t(d)] = element % len;
      element /= len;
    }
    ASSERT_EQ(nc_put_var1_float(nc, id, index.data(), &value), NC_NOERR) << var;
  });
}

/// A netCDF-4 file with nothing in it (the HDF5 probe opens it; the loaders refuse it).
std::string emptyNetcdf4(const Scratch& dir) {
  const std::string path = dir.file("netcdf4.nc");
  int nc = -1;
  EXPECT_EQ(nc_create(path.c_str(), NC_CLOBBER | NC_NETCDF4, &nc), NC_NOERR);
  EXPECT_EQ(nc_close(nc), NC_NOERR);
  return path;
}

void expectLoadError(const std::string& path, std::initializer_list<std::string> mentions) {
  saveFuzzInput(path, "model");
  expectError<InputError>([&] { (void)io::loadWrfTimestep(path, 0); }, mentions);
}

// --- float -> int conversions of attributes (UBSan reported them) -------------------------------

TEST(HostileNetcdf, MapProjAndMicrophysicsCodesAreRangeCheckedBeforeTheCast) {
  const Scratch dir;
  for (const char* name : {"MAP_PROJ", "MP_PHYSICS"}) {
    for (const double bad : {1e20, std::numeric_limits<double>::quiet_NaN(), 2.5}) {
      SCOPED_TRACE(std::string(name) + " = " + std::to_string(bad));
      const std::string path = smallWrf(dir);
      putGlobalDouble(path, name, bad);
      expectLoadError(path, {path, name, "expected", "an integer"});
    }
  }
}

// --- plausibility gates -------------------------------------------------------------------------

TEST(HostileNetcdf, TinyGridSpacingIsRefused) {
  const Scratch dir;
  const std::string path = smallWrf(dir);
  putGlobalDouble(path, "DX", 1e-30);
  expectLoadError(path, {path, "DX", "a grid spacing in [0.1, 1e7) m"});
}

TEST(HostileNetcdf, AbsurdMixingRatioIsRefused) {
  const Scratch dir;
  const std::string path = smallWrf(dir);
  putElement(path, "QCLOUD", 7, 1e30f);
  expectLoadError(path, {path, "QCLOUD", "element 7", "a mixing ratio [kg/kg] of at most 0.1"});
}

TEST(HostileNetcdf, HeightsOf1e26AreRefused) {
  const Scratch dir;
  const std::string path = smallWrf(dir);
  putElement(path, "PHB", 200, 1e27f);  // geopotential [m^2/s^2]: 1e26 m
  expectLoadError(path, {path, "(PH+PHB)/g", "element 200", "a height [m] in [-1000, 200000]"});
}

TEST(HostileNetcdf, TerrainOfMinus1e7IsRefused) {
  const Scratch dir;
  const std::string path = smallWrf(dir);
  putElement(path, "HGT", 3, -1e7f);
  expectLoadError(path, {path, "HGT", "element 3", "a terrain height [m] in [-1000, 9000]"});
}

TEST(HostileNetcdf, CharScaleFactorIsRefusedNotIgnored) {
  const Scratch dir;
  const std::string path = smallWrf(dir);
  ncEdit(path, true,
         [](int nc) { ASSERT_EQ(nc_put_att_text(nc, ncVar(nc, "QCLOUD"), "scale_factor", 3, "100"), NC_NOERR); });
  expectLoadError(path, {path, "QCLOUD:scale_factor is text", "expected one number"});
}

TEST(HostileNetcdf, IntegerMixingRatioWithoutPackingIsRefused) {
  const Scratch dir;
  const std::string path = smallWrf(dir);
  ncEdit(path, true, [](int nc) {
    const int old_id = ncVar(nc, "QRAIN");
    int dims[4] = {};
    ASSERT_EQ(nc_inq_vardimid(nc, old_id, dims), NC_NOERR);
    ASSERT_EQ(nc_rename_var(nc, old_id, "QRAIN_float"), NC_NOERR);
    int id = -1;
    ASSERT_EQ(nc_def_var(nc, "QRAIN", NC_INT, 4, dims, &id), NC_NOERR);
  });
  expectLoadError(path, {path, "QRAIN is an integer variable without scale_factor", "expected float or double"});
}

// --- truncation and declared sizes ----------------------------------------------------------------

TEST(HostileNetcdf, ClassicHeaderWalkGivesTheExactFileSize) {
  // A complete file ends exactly where its header says the last record ends (closed form: the
  // walk of the header reproduces NetCDF-C's layout byte for byte).
  const Scratch dir;
  const std::string path = smallWrf(dir);
  const auto end = io::classicDataEnd_bytes(path);
  ASSERT_TRUE(end.has_value());
  EXPECT_EQ(*end, std::filesystem::file_size(path));
}

TEST(HostileNetcdf, ClassicFileMissingItsLastBytesIsRefused) {
  // The old check assumed a 32-byte header, so a file missing less than its real header size
  // (several KB for a wrfout) converted, with zeros for the missing data.
  const Scratch dir;
  for (const std::uintmax_t missing : {std::uintmax_t(1), std::uintmax_t(6 * 1024)}) {
    SCOPED_TRACE(missing);
    const std::string path = smallWrf(dir);
    const auto size = std::filesystem::file_size(path);
    std::filesystem::resize_file(path, size - missing);
    saveFuzzInput(path, "model");
    expectError<InputError>([&] { (void)io::openModelFile(path); },
                            {path, "truncated NetCDF file", std::to_string(missing) + " bytes missing"});
  }
}

TEST(HostileNetcdf, Netcdf4DeclaringGigabytesWithoutDataIsRefusedBeforeReading) {
  // 2000 x 2000 x 55 floats in six variables declared in a small file, within the memory budget:
  // HDF5 would invent fill values for 2.7 GB over minutes. Refused before the first read.
  const Scratch dir;
  const std::string path = dir.file("hollow.nc");
  int nc = -1;
  ASSERT_EQ(nc_create(path.c_str(), NC_CLOBBER | NC_NETCDF4, &nc), NC_NOERR);
  int t = -1, z = -1, zs = -1, y = -1, x = -1;
  nc_def_dim(nc, "Time", NC_UNLIMITED, &t);
  nc_def_dim(nc, "bottom_top", 55, &z);
  nc_def_dim(nc, "bottom_top_stag", 56, &zs);
  nc_def_dim(nc, "south_north", 2000, &y);
  nc_def_dim(nc, "west_east", 2000, &x);
  const int mass[4] = {t, z, y, x}, stag[4] = {t, zs, y, x};
  int p_id = -1;
  const std::size_t chunk[4] = {1, 1, 64, 64};  // small chunks: one written value stores 16 KB
  for (const char* v : {"QCLOUD", "P", "PB", "T", "PH", "PHB"}) {
    int id = -1;
    const bool staggered = v[0] == 'P' && v[1] == 'H';
    ASSERT_EQ(nc_def_var(nc, v, NC_FLOAT, 4, staggered ? stag : mass, &id), NC_NOERR);
    ASSERT_EQ(nc_def_var_chunking(nc, id, NC_CHUNKED, chunk), NC_NOERR);
    ASSERT_EQ(nc_def_var_deflate(nc, id, 1, 1, 1), NC_NOERR);
    if (std::string(v) == "P") p_id = id;
  }
  const float dx = 3000.0f;
  nc_put_att_float(nc, NC_GLOBAL, "DX", NC_FLOAT, 1, &dx);
  nc_put_att_float(nc, NC_GLOBAL, "DY", NC_FLOAT, 1, &dx);
  ASSERT_EQ(nc_enddef(nc), NC_NOERR);
  const std::size_t index[4] = {0, 0, 0, 0};
  const float zero = 0.0f;
  ASSERT_EQ(nc_put_var1_float(nc, p_id, index, &zero), NC_NOERR);  // one record, one chunk
  ASSERT_EQ(nc_close(nc), NC_NOERR);
  ASSERT_LT(std::filesystem::file_size(path), 1u << 20);
  expectLoadError(path, {path, "QCLOUD declares 880000000 bytes in a NetCDF-4 file", "never written"});
}

TEST(HostileNetcdf, Hdf5CrashingInItsOwnParserIsContainedInAChildProcess) {
  // libhdf5 frees an invalid pointer while opening some damaged netCDF-4 files (found by the fuzz
  // campaign; tests/fuzz/corpus/model/hdf5-invalid-free-on-open). netCDF-4 files are opened in a
  // separate process first (nephele-nc-probe): a probe killed by a signal is an InputError here, this process survives.
  // The child is made to crash on purpose (NEPHELE_TEST_HDF5_PROBE_CRASH): whether the real input
  // crashes depends on the allocator (it does under ASan, not with glibc's malloc).
  const Scratch dir;
  const std::string path = emptyNetcdf4(dir);
  ::setenv("NEPHELE_TEST_HDF5_PROBE_CRASH", "1", 1);
  // The message names the signal, not necessarily SIGSEGV: under ASan (make test-sanitize,
  // abort_on_error=1) the sanitizer's SEGV handler turns the crash into SIGABRT (signal 6).
  expectError<InputError>([&] { (void)io::openModelFile(path); },
                          {path, "the HDF5 library crashed", "(signal ", "the file is damaged"});
  ::unsetenv("NEPHELE_TEST_HDF5_PROBE_CRASH");
  // Without the fault, the same file opens (and is refused for what it lacks, not for a crash).
  try {
    (void)io::openModelFile(path);
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()).find("crashed"), std::string::npos) << e.what();
  }
  // The fuzz finding itself: a clean InputError naming the file, whichever process sees it fail.
  const std::string found = std::string(NEPHELE_SOURCE_DIR) + "/tests/fuzz/corpus/model/hdf5-invalid-free-on-open";
  expectError<InputError>([&] { (void)io::openModelFile(found); }, {found});
}

TEST(HostileNetcdf, Hdf5ProbeIsASpawnedProcessNotAFork) {
  // The probe was a fork() of this process until session 11; forked from a multithreaded process it
  // deadlocked under ASan (an llvmpipe thread held the allocator's lock; PROJ's atfork handler freed
  // memory in the child). Now it is nephele-nc-probe started with posix_spawn: no atfork handler
  // runs (ForkWatch), and the file opens as before.
  const Scratch dir;
  const std::string path = emptyNetcdf4(dir);
  {
    const ForkWatch watch(dir);
    try {
      (void)io::openModelFile(path);
    } catch (const InputError& e) {  // refused for what it lacks, not by the probe
      EXPECT_EQ(std::string(e.what()).find("separate process"), std::string::npos) << e.what();
    }
    EXPECT_FALSE(watch.forked());
  }
  // The probe proves it ran: made to crash, it is reported (and this process is not the one that
  // crashed).
  ::setenv("NEPHELE_TEST_HDF5_PROBE_CRASH", "1", 1);
  expectError<InputError>([&] { (void)io::openModelFile(path); }, {path, "crashed", "separate process"});
  ::unsetenv("NEPHELE_TEST_HDF5_PROBE_CRASH");
  // A pinned probe must be an absolute path to an executable.
  ::setenv("NEPHELE_NC_PROBE", "nephele-nc-probe", 1);
  expectError<UsageError>([&] { (void)io::openModelFile(path); },
                          {"NEPHELE_NC_PROBE", "expected the absolute path of an executable"});
  ::unsetenv("NEPHELE_NC_PROBE");
}

TEST(HostileNetcdf, Hdf5ParserThatNeverReturnsIsKilledAfterTheOpenTimeout) {
  // A damaged netCDF-4 file can make libhdf5 loop forever while parsing its metadata. The child
  // that opens it first is killed after NEPHELE_HDF5_OPEN_TIMEOUT_S and the file refused. The
  // child is made to hang on purpose (NEPHELE_TEST_HDF5_PROBE_HANG: it never returns, so the
  // outcome does not depend on the machine's speed; the limit is 1 s to keep the test short).
  const Scratch dir;
  const std::string path = emptyNetcdf4(dir);
  ::setenv("NEPHELE_TEST_HDF5_PROBE_HANG", "1", 1);
  ::setenv("NEPHELE_HDF5_OPEN_TIMEOUT_S", "1", 1);
  expectError<InputError>([&] { (void)io::openModelFile(path); },
                          {path, "did not finish reading", "in 1 s", "NEPHELE_HDF5_OPEN_TIMEOUT_S"});
  ::unsetenv("NEPHELE_TEST_HDF5_PROBE_HANG");
  // A limit that is not a whole number of seconds in [1, 86400] is a usage error naming it.
  ::setenv("NEPHELE_HDF5_OPEN_TIMEOUT_S", "0", 1);
  expectError<UsageError>([&] { (void)io::openModelFile(path); }, {"NEPHELE_HDF5_OPEN_TIMEOUT_S", "86400"});
  ::unsetenv("NEPHELE_HDF5_OPEN_TIMEOUT_S");
}

// --- special files --------------------------------------------------------------------------------

TEST(HostileNetcdf, FifoAndDirectoryAreRefusedByFileTypeWithoutBlocking) {
  // A FIFO without a writer blocks open(2) forever: the refusal must come from stat, not a timeout.
  const Scratch dir;
  const std::string fifo = dir.file("pipe.nc");
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  expectError<InputError>([&] { (void)io::openModelFile(fifo); },
                          {fifo, "is a FIFO (named pipe)", "expected a NetCDF file"});
  expectError<InputError>([&] { (void)engine::Dataset::open(fifo); }, {fifo, "is a FIFO (named pipe)"});
  expectError<InputError>([&] { (void)engine::Dataset::openSeries({fifo, fifo}); }, {fifo, "is a FIFO"});
  const std::string folder = dir.file("folder.nc");
  std::filesystem::create_directory(folder);
  expectError<InputError>([&] { (void)io::openModelFile(folder); }, {folder, "is a directory"});
  expectError<InputError>([&] { (void)engine::Dataset::open("/dev/zero"); }, {"/dev/zero", "a character device"});
}

// --- strings from files on a terminal -----------------------------------------------------------

TEST(HostileNetcdf, EscapeSequencesInTimesAreShownNotSent) {
  // `nephele info` printed WRF Times as they were: ESC ] 0 ; ... BEL retitles the terminal.
  const Scratch dir;
  const std::string path = smallWrf(dir);
  ncEdit(path, false, [](int nc) {
    const std::string evil = "\x1b]0;pwned\x07\x1b[2J\xc2\x9b"
                             "1m";  // OSC, CSI, C1 CSI
    std::size_t len = 0;
    int dims[2] = {};
    nc_inq_vardimid(nc, ncVar(nc, "Times"), dims);
    nc_inq_dimlen(nc, dims[1], &len);
    std::string row = evil;
    row.resize(len, ' ');
    const std::size_t start[2] = {0, 0}, count[2] = {1, len};
    ASSERT_EQ(nc_put_vara_text(nc, ncVar(nc, "Times"), start, count, row.data()), NC_NOERR);
  });
  // The loader parses Times (issue 17): the row is not a time, so the timestep has none (the
  // warning quotes it through terminalSafe), and nothing downstream ever prints the raw bytes.
  EXPECT_FALSE(io::listWrfTimes(path).at(0).has_value());
  const std::string shown = terminalSafe("\x1b]0;pwned\x07\x1b[2J\xc2\x9b"
                                         "1m");
  EXPECT_EQ(shown.find('\x1b'), std::string::npos);
  EXPECT_EQ(shown.find('\x07'), std::string::npos);
  EXPECT_EQ(shown.find("\xc2\x9b"), std::string::npos);
  EXPECT_EQ(shown.rfind("\\x1b]0;pwned\\x07\\x1b[2J\\x9b1m", 0), 0u) << shown;
  EXPECT_EQ(terminalSafe("grüße\n2026-09-01"), "grüße\n2026-09-01");  // UTF-8 and newlines kept
  EXPECT_EQ(terminalSafe("a\nb", false), "a\\x0ab");
}

// --- derived grids --------------------------------------------------------------------------------

TEST(HostileNetcdf, DerivedVerticalGridIsBoundedBeforeTheCast) {
  const Scratch dir;
  const io::ModelTimestep ts = io::loadWrfTimestep(smallWrf(dir), 0);
  const physics::ModelLevelExtinction beta = physics::modelLevelExtinction(ts, physics::defaultOptics());
  for (const auto& [bottom, top] : {std::pair{-1e7, 1e4}, std::pair{0.0, 1e26}}) {
    SCOPED_TRACE(top);
    physics::VerticalGridOptions o;
    o.z_bottom_m = bottom;
    o.z_top_m = top;
    expectError<InputError>([&] { (void)physics::planVerticalGrid(ts, beta, o); },
                            {ts.source_file, "levels of 250 m", "limits::kMaxDerivedLevels"});
  }
}

TEST(HostileNetcdf, IconNativeCellsOnOneLineGiveASmallGridQuickly) {
  // Cells along one parallel have a bounding box without area: the automatic spacing became
  // ~1e-5 deg and CellLocator::nearest scanned empty buckets for hours (a 2-cell grid hung).
  const Scratch dir;
  const std::string path = dir.file("icon_native.nc");
  datagen::IconSceneSpec spec;
  spec.native_divisions = 3 * 128;  // R3B7, ~20 km cells over a 1 x 1 deg region
  spec.nlon = spec.nlat = 10;
  spec.nz = 6;
  spec.ntimes = 1;
  const datagen::IconTruth truth = datagen::writeIconScene(spec, path);
  ncEdit(path, false, [&](int nc) {
    std::vector<double> lat(std::size_t(truth.ncells), 0.8), lon(std::size_t(truth.ncells));
    for (std::size_t c = 0; c < lon.size(); ++c) lon[c] = 0.1 + 0.5 * double(c) / double(lon.size());
    ASSERT_EQ(nc_put_var_double(nc, ncVar(nc, "clat"), lat.data()), NC_NOERR);
    ASSERT_EQ(nc_put_var_double(nc, ncVar(nc, "clon"), lon.data()), NC_NOERR);
  });
  const io::ModelTimestep ts = io::loadIconTimestep(path, 0);
  EXPECT_LE(std::int64_t(ts.nx) * ts.ny, 3 * truth.ncells + 1);
  EXPECT_GE(ts.nx, 2);
}

}  // namespace
}  // namespace nph::reliability
