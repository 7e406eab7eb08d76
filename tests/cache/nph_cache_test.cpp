#include "cache/nph_cache.h"

#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <fstream>
#include <limits>
#include <memory>
#include <random>

#include "cache/quantize.h"
#include "core/error.h"
#include "support/scratch_dir.h"

namespace nph::cache {
namespace {

namespace fs = std::filesystem;

/// A fresh scratch directory per test.
class NphCacheTest : public ::testing::Test {
 protected:
  void SetUp() override {
    scratch_ = std::make_unique<test::ScratchDir>("cache");
    dir_ = scratch_->path();
  }
  void TearDown() override { scratch_.reset(); }

  std::vector<fs::path> filesInDir() const {
    std::vector<fs::path> out;
    for (const auto& e : fs::directory_iterator(dir_)) out.push_back(e.path());
    return out;
  }

  std::unique_ptr<test::ScratchDir> scratch_;
  fs::path dir_;
};

NphMetadata smallMetadata() {
  NphMetadata m;
  m.nx = 7;
  m.ny = 5;
  m.dz_m = 250.0;
  m.z_bottom_m = -250.0;
  m.georef.proj_definition = "+proj=lcc +lat_1=30 +lat_2=60 +lat_0=25 +lon_0=-80 +R=6370000";
  m.georef.dx_m = 3000.0;
  m.georef.dy_m = 3000.0;
  m.georef.x0 = -9000.0;
  m.georef.y0 = -6000.0;
  for (int n = 0; n < m.nx * m.ny; ++n) {
    m.georef.lat_deg.push_back(25.0f + 0.01f * float(n));
    m.georef.lon_deg.push_back(-80.0f - 0.02f * float(n));
  }
  m.optics_json = R"({"preset":"test","cloud":{"r_eff_m":1e-5}})";
  m.inputs = {"wrfout_d01_a.nc"};
  m.created_by = "nephele test";
  return m;
}

ExtinctionVolumes randomVolumes(const NphMetadata& m, int nz, unsigned seed, float scale) {
  ExtinctionVolumes v;
  v.nx = m.nx;
  v.ny = m.ny;
  v.nz = nz;
  v.dz_m = m.dz_m;
  v.z_bottom_m = m.z_bottom_m;
  v.georef = m.georef;
  v.time_utc = nph::geo::UtcTime::parse("2026-09-01T0" + std::to_string(seed % 10) + ":00:00Z");
  v.source_file = "wrfout_d01_a.nc";
  v.source_time_index = seed;
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  v.ice_per_m.resize(v.voxelCount());
  v.water_per_m.resize(v.voxelCount());
  for (std::size_t n = 0; n < v.voxelCount(); ++n) {
    // a mix of exact zeros (empty space), tiny values and large values
    const float r = u(rng);
    v.ice_per_m[n] = r < 0.3f ? 0.0f : scale * r * r * r;
    v.water_per_m[n] = r > 0.8f ? 0.0f : 3.0f * scale * u(rng);
  }
  v.updateMaxima();
  return v;
}

fs::path writeFile(const fs::path& path, const NphMetadata& m, const std::vector<ExtinctionVolumes>& steps) {
  NphWriter w(path, m);
  for (const auto& s : steps) w.append(s);
  w.commit();
  return path;
}

TEST_F(NphCacheTest, RoundTripWithinDocumentedBoundAndPadsToCommonNz) {
  const NphMetadata m = smallMetadata();
  const std::vector<ExtinctionVolumes> steps = {randomVolumes(m, 4, 1, 0.01f), randomVolumes(m, 9, 2, 2e-5f),
                                                randomVolumes(m, 0, 3, 1.0f)};
  const fs::path file = writeFile(dir_ / "storm.nph", m, steps);
  EXPECT_EQ(filesInDir(), std::vector<fs::path>{file});  // no temporary left over
  ASSERT_TRUE(NphReader::sniff(file));

  NphReader r(file);
  EXPECT_EQ(r.formatVersion(), kFormatVersion);
  EXPECT_EQ(r.timestepCount(), 3u);
  EXPECT_EQ(r.nz(), 9);
  EXPECT_EQ(r.metadata().georef, m.georef);
  EXPECT_EQ(r.metadata().inputs, m.inputs);
  EXPECT_EQ(r.metadata().created_by, m.created_by);
  EXPECT_NE(r.metadata().optics_json.find("\"preset\":\"test\""), std::string::npos);
  EXPECT_EQ(r.metadata().dz_m, 250.0);
  EXPECT_EQ(r.metadata().z_bottom_m, -250.0);

  // read in a different order: lazily, one chunk at a time
  for (std::size_t t : {2u, 0u, 1u}) {
    const ExtinctionVolumes& in = steps[t];
    const ExtinctionVolumes out = r.read(t);
    EXPECT_EQ(out.time_utc, in.time_utc);
    EXPECT_EQ(out.source_time_index, in.source_time_index);
    EXPECT_EQ(out.nz, 9);
    EXPECT_EQ(out.max_ice_per_m, in.max_ice_per_m);
    EXPECT_EQ(out.max_water_per_m, in.max_water_per_m);
    const double bound_ice = quantisationErrorBound(in.max_ice_per_m);
    const double bound_water = quantisationErrorBound(in.max_water_per_m);
    for (int k = 0; k < out.nz; ++k) {
      for (int j = 0; j < out.ny; ++j) {
        for (int i = 0; i < out.nx; ++i) {
          const std::size_t q = out.index(i, j, k);
          if (k >= in.nz) {  // padding above the cropped top
            ASSERT_EQ(out.ice_per_m[q], 0.0f);
            ASSERT_EQ(out.water_per_m[q], 0.0f);
            continue;
          }
          const std::size_t p = in.index(i, j, k);
          ASSERT_LE(std::abs(double(out.ice_per_m[q]) - double(in.ice_per_m[p])), bound_ice);
          ASSERT_LE(std::abs(double(out.water_per_m[q]) - double(in.water_per_m[p])), bound_water);
          if (in.ice_per_m[p] == 0.0f) {
            ASSERT_EQ(out.ice_per_m[q], 0.0f);  // zero stays zero
          }
        }
      }
    }
  }
  EXPECT_THROW((void)r.read(3), UsageError);

  // the quantised form decodes to exactly what read() returns
  const QuantisedVolumes q = r.readQuantised(1);
  const ExtinctionVolumes f = r.read(1);
  ASSERT_EQ(q.ice_codes.size(), f.voxelCount());
  EXPECT_EQ(q.nz, 9);
  EXPECT_EQ(q.max_water_per_m, f.max_water_per_m);
  for (std::size_t n = 0; n < f.voxelCount(); n += 13) {
    EXPECT_EQ(f.water_per_m[n], static_cast<float>(double(q.water_codes[n]) * double(q.max_water_per_m) / 65535.0));
  }
}

// Issue 19 (memory, docs/benchmarks.md "Memory"): readSlices decodes a timestep a layer at a time
// straight from its chunk (a zstd stream over the file) and decodes every layer, the padding above
// a cropped timestep included, to read()'s floats bit for bit, in any order (upwards is one
// decode; downwards rewinds); readHeader is read() without the volumes, and materialise() is read().
TEST_F(NphCacheTest, LayersDecodeAsReadBitForBitInAnyOrder) {
  const NphMetadata m = smallMetadata();
  const std::vector<ExtinctionVolumes> steps = {randomVolumes(m, 4, 1, 0.01f), randomVolumes(m, 9, 2, 2e-5f),
                                                randomVolumes(m, 0, 3, 1.0f)};
  const NphReader r(writeFile(dir_ / "storm.nph", m, steps));
  for (std::size_t t = 0; t < steps.size(); ++t) {
    const ExtinctionVolumes full = r.read(t);
    const std::unique_ptr<ExtinctionSlices> slices = r.readSlices(t);
    const ExtinctionVolumes& header = slices->volumes();
    EXPECT_EQ(slices->whole(), nullptr) << "the floats are never held whole";
    EXPECT_EQ(VolumeSlices(full).heldBytes(), 8 * full.voxelCount());
    EXPECT_TRUE(header.ice_per_m.empty() && header.water_per_m.empty());
    const ExtinctionVolumes read_header = r.readHeader(t);
    for (const ExtinctionVolumes* h : {&header, &read_header}) {
      EXPECT_EQ(h->nx, full.nx);
      EXPECT_EQ(h->ny, full.ny);
      EXPECT_EQ(h->nz, full.nz);
      EXPECT_EQ(h->dz_m, full.dz_m);
      EXPECT_EQ(h->z_bottom_m, full.z_bottom_m);
      EXPECT_EQ(h->georef, full.georef);
      EXPECT_EQ(h->terrain_height_m, full.terrain_height_m);
      EXPECT_EQ(h->time_utc, full.time_utc);
      EXPECT_EQ(h->source_file, full.source_file);
      EXPECT_EQ(h->source_time_index, full.source_time_index);
      EXPECT_EQ(h->max_ice_per_m, full.max_ice_per_m);
      EXPECT_EQ(h->max_water_per_m, full.max_water_per_m);
    }
    const std::size_t layer = std::size_t(full.nx) * std::size_t(full.ny);
    std::vector<float> scratch;
    std::vector<int> order;  // upwards, downwards (each step rewinds), then skipping about
    for (int k = 0; k < full.nz; ++k) order.push_back(k);
    for (int k = full.nz - 1; k >= 0; --k) order.push_back(k);
    for (int k : {2, 2, 0, 5, 3, 8, 1}) order.push_back(std::min(k, full.nz - 1));
    for (int k : order) {
      const ExtinctionSlices::Slice s = slices->slice(k, scratch);
      for (std::size_t c = 0; c < layer; ++c) {
        ASSERT_EQ(std::bit_cast<std::uint32_t>(s.ice[c]),
                  std::bit_cast<std::uint32_t>(full.ice_per_m[std::size_t(k) * layer + c]))
            << "layer " << k;
        ASSERT_EQ(std::bit_cast<std::uint32_t>(s.water[c]),
                  std::bit_cast<std::uint32_t>(full.water_per_m[std::size_t(k) * layer + c]))
            << "layer " << k;
      }
    }
    EXPECT_THROW((void)slices->slice(full.nz, scratch), UsageError);
    const ExtinctionVolumes again = slices->materialise();
    EXPECT_EQ(again.ice_per_m, full.ice_per_m);
    EXPECT_EQ(again.water_per_m, full.water_per_m);
  }
}

TEST_F(NphCacheTest, FileWithoutGeolocation) {
  NphMetadata m = smallMetadata();
  m.georef.lat_deg.clear();
  m.georef.lon_deg.clear();
  m.georef.proj_definition.clear();
  const fs::path file = writeFile(dir_ / "ideal.nph", m, {randomVolumes(m, 3, 4, 0.1f)});
  NphReader r(file);
  EXPECT_TRUE(r.metadata().georef.lat_deg.empty());
  EXPECT_EQ(r.read(0).nz, 3);
}

// Terrain (issue 14): stored once, read back bit-exact with every timestep; a file without it
// (all files before issue 14) reads as sea level, an empty field.
TEST_F(NphCacheTest, TerrainIsStoredOnceAndReadExactlyWithEveryTimestep) {
  NphMetadata m = smallMetadata();
  for (int n = 0; n < m.nx * m.ny; ++n) m.terrain_height_m.push_back(-12.5f + 317.25f * float(n % 11));
  const fs::path file = writeFile(dir_ / "hills.nph", m, {randomVolumes(m, 3, 5, 0.1f), randomVolumes(m, 2, 6, 0.1f)});
  NphReader r(file);
  EXPECT_EQ(r.metadata().terrain_height_m, m.terrain_height_m);
  EXPECT_EQ(r.read(0).terrain_height_m, m.terrain_height_m);
  EXPECT_EQ(r.read(1).terrain_height_m, m.terrain_height_m);

  const fs::path flat = writeFile(dir_ / "sea.nph", smallMetadata(), {randomVolumes(m, 3, 5, 0.1f)});
  EXPECT_TRUE(NphReader(flat).read(0).terrain_height_m.empty());

  m.terrain_height_m.pop_back();
  EXPECT_THROW(NphWriter(dir_ / "short.nph", m), UsageError);
  m.terrain_height_m.push_back(std::numeric_limits<float>::quiet_NaN());
  EXPECT_THROW(NphWriter(dir_ / "nan.nph", m), InputError);
}

// --- corrupt and truncated files: InputError naming the file (and the chunk) ---------------

std::string readAll(const fs::path& p) {
  std::ifstream f(p, std::ios::binary);
  return {std::istreambuf_iterator<char>(f), std::istreambuf_iterator<char>()};
}
void writeAll(const fs::path& p, const std::string& bytes) {
  std::ofstream f(p, std::ios::binary | std::ios::trunc);
  f.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
}

/// The file offset of the middle of timestep t's chunk.
std::uint64_t middleOfChunk(const fs::path& file, std::size_t t) {
  const NphReader r(file);
  return r.timestep(t).chunk_offset + r.timestep(t).chunk_bytes / 2;
}

/// The InputError message of `fn`, or a test failure.
template <class F>
std::string inputErrorOf(F&& fn) {
  try {
    fn();
  } catch (const InputError& e) {
    return e.what();
  } catch (const std::exception& e) {
    ADD_FAILURE() << "expected InputError, got: " << e.what();
    return {};
  }
  ADD_FAILURE() << "expected InputError, nothing thrown";
  return {};
}

/// `v` with a horizontal wind (U, V) per voxel: a jet-like profile in ±80 m/s with 4 decimals, so
/// that values fall between the 0.01 m/s codes.
ExtinctionVolumes withWind(ExtinctionVolumes v, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> u(-80.0f, 80.0f);
  v.wind_u_m_per_s.resize(v.voxelCount());
  v.wind_v_m_per_s.resize(v.voxelCount());
  for (std::size_t n = 0; n < v.voxelCount(); ++n) {
    v.wind_u_m_per_s[n] = u(rng);
    v.wind_v_m_per_s[n] = u(rng);
  }
  return v;
}

// Issue 13 follow-up: U, V stored per timestep (int16 codes at 0.01 m/s, quantize.h) for the
// motion blend; read back within the stated bound, padded calm above each timestep's nz_t like β;
// out-of-range values clamped, non-finite ones calm. A timestep without wind reads without it.
TEST_F(NphCacheTest, WindRoundTripsWithinItsStepAndPadsCalm) {
  const NphMetadata m = smallMetadata();
  ExtinctionVolumes low = withWind(randomVolumes(m, 4, 1, 0.01f), 11);
  low.wind_u_m_per_s[0] = 400.0f;                                   // beyond the int16 range: clamped
  low.wind_v_m_per_s[0] = -1.0e6f;                                  // ditto, negative
  low.wind_u_m_per_s[1] = std::numeric_limits<float>::quiet_NaN();  // broken: calm
  low.wind_v_m_per_s[1] = std::numeric_limits<float>::infinity();
  low.wind_u_m_per_s[2] = 0.005f;  // float 0.005 is just below half a step: 0
  const ExtinctionVolumes high = withWind(randomVolumes(m, 9, 2, 2e-5f), 12);
  const ExtinctionVolumes calm = randomVolumes(m, 6, 3, 1.0f);                 // no wind
  const ExtinctionVolumes empty = withWind(randomVolumes(m, 0, 4, 1.0f), 14);  // cropped to nothing
  const fs::path file = writeFile(dir_ / "windy.nph", m, {low, high, calm, empty});
  NphReader r(file);
  ASSERT_EQ(r.timestepCount(), 4u);
  EXPECT_TRUE(r.timestep(0).hasWind());
  EXPECT_TRUE(r.timestep(1).hasWind());
  EXPECT_FALSE(r.timestep(2).hasWind());
  EXPECT_TRUE(r.timestep(3).hasWind());
  EXPECT_EQ(r.nz(), 9);
  for (std::size_t t : {0u, 1u, 3u}) {
    const ExtinctionVolumes& in = t == 0 ? low : t == 1 ? high : empty;
    const ExtinctionVolumes out = r.read(t);
    ASSERT_EQ(out.wind_u_m_per_s.size(), out.voxelCount());
    ASSERT_EQ(out.wind_v_m_per_s.size(), out.voxelCount());
    for (int k = 0; k < out.nz; ++k) {
      for (int j = 0; j < out.ny; ++j) {
        for (int i = 0; i < out.nx; ++i) {
          const std::size_t q = out.index(i, j, k);
          if (k >= in.nz) {  // padding above the cropped top: calm
            ASSERT_EQ(out.wind_u_m_per_s[q], 0.0f);
            ASSERT_EQ(out.wind_v_m_per_s[q], 0.0f);
            continue;
          }
          const std::size_t p = in.index(i, j, k);
          if (t == 0 && p < 3) continue;  // the special values, below
          ASSERT_LE(std::abs(double(out.wind_u_m_per_s[q]) - double(in.wind_u_m_per_s[p])), kWindErrorBound_m_per_s);
          ASSERT_LE(std::abs(double(out.wind_v_m_per_s[q]) - double(in.wind_v_m_per_s[p])), kWindErrorBound_m_per_s);
        }
      }
    }
    // β is unchanged by the wind beside it
    EXPECT_EQ(out.ice_per_m, r.readSlices(t)->materialise().ice_per_m);
  }
  const ExtinctionVolumes first = r.read(0);
  EXPECT_EQ(first.wind_u_m_per_s[0], 327.67f);
  EXPECT_EQ(first.wind_v_m_per_s[0], -327.67f);
  EXPECT_EQ(first.wind_u_m_per_s[1], 0.0f);
  EXPECT_EQ(first.wind_v_m_per_s[1], 0.0f);
  EXPECT_EQ(first.wind_u_m_per_s[2], 0.0f);
  // the timestep written without wind reads without it, as does readHeader (no chunk read)
  EXPECT_TRUE(r.read(2).wind_u_m_per_s.empty());
  EXPECT_TRUE(r.read(2).wind_v_m_per_s.empty());
  EXPECT_TRUE(r.readHeader(0).wind_u_m_per_s.empty());
  // the model route's noise clock, from the time
  EXPECT_GT(r.readHeader(0).detail_clock_s, 0.0);

  // a wrong count is the caller's error; U without V is no wind the blend could use: not stored
  ExtinctionVolumes odd = low;
  odd.wind_v_m_per_s.pop_back();
  NphWriter w(dir_ / "odd.nph", m);
  EXPECT_THROW(w.append(odd), UsageError);
  odd.wind_v_m_per_s.clear();
  w.append(odd);
  w.commit();
  NphReader u_only(dir_ / "odd.nph");
  EXPECT_FALSE(u_only.timestep(0).hasWind());
  EXPECT_TRUE(u_only.read(0).wind_u_m_per_s.empty());
}

// A file written without wind (every file before the wind chunk) has no "wind" key at all and reads
// without U, V: the linear blend, as before.
TEST_F(NphCacheTest, FileWithoutWindHasNoWindKeyAndReadsWithoutWind) {
  const NphMetadata m = smallMetadata();
  const fs::path file = writeFile(dir_ / "still.nph", m, {randomVolumes(m, 3, 5, 0.1f), randomVolumes(m, 2, 6, 0.1f)});
  EXPECT_EQ(readAll(file).find("\"wind\""), std::string::npos);
  NphReader r(file);
  for (std::size_t t = 0; t < r.timestepCount(); ++t) {
    EXPECT_FALSE(r.timestep(t).hasWind());
    EXPECT_TRUE(r.read(t).wind_u_m_per_s.empty());
    EXPECT_TRUE(r.read(t).wind_v_m_per_s.empty());
  }
}

TEST_F(NphCacheTest, FlippedByteInAChunkNamesFileAndChunk) {
  const NphMetadata m = smallMetadata();
  const fs::path file = writeFile(dir_ / "s.nph", m, {randomVolumes(m, 4, 1, 0.01f), randomVolumes(m, 4, 2, 0.01f)});
  const std::uint64_t offset = middleOfChunk(file, 1);
  std::string bytes = readAll(file);
  bytes[offset] = static_cast<char>(bytes[offset] ^ 0x20);
  writeAll(file, bytes);
  NphReader r(file);  // header and index are intact: opening works
  EXPECT_NO_THROW((void)r.read(0));
  const std::string msg = inputErrorOf([&] { (void)r.read(1); });
  EXPECT_NE(msg.find(file.string()), std::string::npos) << msg;
  EXPECT_NE(msg.find("chunk 1"), std::string::npos) << msg;
}

// readSlices holds no code of the timestep beyond one layer (issue 19, memory): zstd's window and
// one input piece per stream, well under the 4 bytes per voxel the codes would take; and a second
// source of the same timestep reads the same while the reader is gone (it owns its descriptor).
TEST_F(NphCacheTest, LayeredReadHoldsLessThanTheCodes) {
  NphMetadata m = smallMetadata();
  m.nx = 256;
  m.ny = 256;
  m.georef.lat_deg.assign(std::size_t(m.nx) * std::size_t(m.ny), 30.0f);
  m.georef.lon_deg.assign(std::size_t(m.nx) * std::size_t(m.ny), -80.0f);
  const ExtinctionVolumes in = randomVolumes(m, 64, 7, 0.01f);
  const fs::path file = writeFile(dir_ / "big.nph", m, {in});
  std::unique_ptr<ExtinctionSlices> slices;
  ExtinctionVolumes full;
  {
    NphReader r(file);
    full = r.read(0);
    slices = r.readSlices(0);
  }
  const std::size_t codes = 4 * full.voxelCount();  // 16.8 MB
  EXPECT_LT(slices->heldBytes(), codes / 2) << "held " << slices->heldBytes() << " bytes";
  const ExtinctionVolumes again = slices->materialise();
  EXPECT_EQ(again.ice_per_m, full.ice_per_m);
  EXPECT_EQ(again.water_per_m, full.water_per_m);
}

// The layered read checks the chunk as read() does, before any layer is decoded: a flipped byte
// (XXH64) or a file cut inside the chunk is an InputError naming the file and the chunk.
TEST_F(NphCacheTest, LayeredReadOfACorruptOrTruncatedChunkNamesFileAndChunk) {
  const NphMetadata m = smallMetadata();
  const fs::path file = writeFile(dir_ / "s.nph", m, {randomVolumes(m, 4, 1, 0.01f), randomVolumes(m, 4, 2, 0.01f)});
  const std::uint64_t offset = middleOfChunk(file, 1);
  const std::string original = readAll(file);
  std::string bytes = original;
  bytes[offset] = static_cast<char>(bytes[offset] ^ 0x20);
  writeAll(file, bytes);
  {
    NphReader r(file);
    EXPECT_NO_THROW((void)r.readSlices(0)->materialise());
    const std::string msg = inputErrorOf([&] { (void)r.readSlices(1); });
    EXPECT_NE(msg.find(file.string()), std::string::npos) << msg;
    EXPECT_NE(msg.find("chunk 1"), std::string::npos) << msg;
    EXPECT_NE(msg.find("corrupt"), std::string::npos) << msg;
  }
  // The file changed under an open source: the pass that reads the last layer finds it.
  writeAll(file, original);
  {
    NphReader r(file);
    const std::unique_ptr<ExtinctionSlices> slices = r.readSlices(1);
    writeAll(file, bytes);
    const std::string msg = inputErrorOf([&] { (void)slices->materialise(); });
    EXPECT_NE(msg.find("chunk 1"), std::string::npos) << msg;
  }
  // Cut inside the chunk after the reader opened it.
  writeAll(file, original);
  {
    NphReader r(file);
    fs::resize_file(file, offset);
    const std::string msg = inputErrorOf([&] { (void)r.readSlices(1); });
    EXPECT_NE(msg.find(file.string()), std::string::npos) << msg;
    EXPECT_NE(msg.find("chunk 1"), std::string::npos) << msg;
    EXPECT_NE(msg.find("truncated"), std::string::npos) << msg;
  }
}

// A corrupt wind chunk is the reader's usual error, naming the file and the wind chunk; the other
// timestep, and the extinction of this one (readSlices), still read.
TEST_F(NphCacheTest, FlippedByteInAWindChunkNamesFileAndChunk) {
  const NphMetadata m = smallMetadata();
  const fs::path file = writeFile(
      dir_ / "w.nph", m, {withWind(randomVolumes(m, 4, 1, 0.01f), 1), withWind(randomVolumes(m, 4, 2, 0.01f), 2)});
  std::uint64_t offset = 0;
  {
    NphReader r(file);
    ASSERT_TRUE(r.timestep(1).hasWind());
    offset = r.timestep(1).wind_chunk_offset + r.timestep(1).wind_chunk_bytes / 2;
  }
  std::string bytes = readAll(file);
  bytes[offset] = static_cast<char>(bytes[offset] ^ 0x20);
  writeAll(file, bytes);
  NphReader r(file);
  EXPECT_NO_THROW((void)r.read(0));
  EXPECT_NO_THROW((void)r.readSlices(1));
  const std::string msg = inputErrorOf([&] { (void)r.read(1); });
  EXPECT_NE(msg.find(file.string()), std::string::npos) << msg;
  EXPECT_NE(msg.find("wind chunk 1"), std::string::npos) << msg;
  EXPECT_NE(msg.find("corrupt"), std::string::npos) << msg;
}

TEST_F(NphCacheTest, TruncatedAndForeignFilesAreInputErrors) {
  const NphMetadata m = smallMetadata();
  const fs::path good = writeFile(dir_ / "good.nph", m, {randomVolumes(m, 4, 1, 0.01f)});
  const std::string bytes = readAll(good);
  for (std::size_t keep : {std::size_t{0}, std::size_t{10}, std::size_t{64}, bytes.size() / 2, bytes.size() - 1}) {
    const fs::path cut = dir_ / ("cut" + std::to_string(keep) + ".nph");
    writeAll(cut, bytes.substr(0, keep));
    const std::string msg = inputErrorOf([&] { NphReader r(cut); });
    EXPECT_NE(msg.find(cut.string()), std::string::npos) << msg;
  }
  const fs::path text = dir_ / "notes.txt";
  writeAll(text, std::string(200, 'x'));
  EXPECT_FALSE(NphReader::sniff(text));
  EXPECT_NE(inputErrorOf([&] { NphReader r(text); }).find("not a nephele"), std::string::npos);
  EXPECT_NE(inputErrorOf([&] { NphReader r(dir_ / "missing.nph"); }).find("missing.nph"), std::string::npos);

  // a corrupt index (flip a byte in the JSON at the end of the file)
  std::string bad = bytes;
  bad[bad.size() - 3] = static_cast<char>(bad[bad.size() - 3] ^ 0x01);
  const fs::path idx = dir_ / "index.nph";
  writeAll(idx, bad);
  EXPECT_NE(inputErrorOf([&] { NphReader r(idx); }).find("index"), std::string::npos);

  // a future format version (with a recomputed header checksum it would still be refused)
  std::string future = bytes;
  future[8] = 2;
  const fs::path fut = dir_ / "future.nph";
  writeAll(fut, future);
  EXPECT_FALSE(inputErrorOf([&] { NphReader r(fut); }).empty());
}

TEST_F(NphCacheTest, EveryFlippedByteAndEveryTruncationIsDetected) {
  // Every byte of a .nph file is covered by a checksum (header, chunks, wind, geolocation, index) or
  // by the size check, so any single corrupted byte or any truncation must be an InputError
  // (never a crash, never silently wrong data).
  NphMetadata m = smallMetadata();
  m.nx = 3;
  m.ny = 2;
  m.georef.lat_deg.resize(6);
  m.georef.lon_deg.resize(6);
  const fs::path good =
      writeFile(dir_ / "small.nph", m, {randomVolumes(m, 2, 1, 0.01f), withWind(randomVolumes(m, 3, 2, 0.02f), 2)});
  const std::string bytes = readAll(good);
  const fs::path bad = dir_ / "bad.nph";
  auto openAndReadAll = [&] {
    NphReader r(bad);
    for (std::size_t t = 0; t < r.timestepCount(); ++t) (void)r.read(t);
  };
  std::size_t detected = 0;
  for (std::size_t at = 0; at < bytes.size(); ++at) {
    std::string flipped = bytes;
    flipped[at] = static_cast<char>(flipped[at] ^ 0x5a);
    writeAll(bad, flipped);
    try {
      openAndReadAll();
      ADD_FAILURE() << "flipped byte " << at << " of " << bytes.size() << " went unnoticed";
    } catch (const InputError& e) {
      ++detected;
      EXPECT_NE(std::string(e.what()).find("bad.nph"), std::string::npos) << e.what();
    }
  }
  EXPECT_EQ(detected, bytes.size());
  for (std::size_t keep = 0; keep < bytes.size(); keep += 7) {
    writeAll(bad, bytes.substr(0, keep));
    EXPECT_THROW(openAndReadAll(), InputError) << "truncated to " << keep;
  }
}

// --- no partial file after a failed write ---------------------------------------------------

TEST_F(NphCacheTest, FailedWriteLeavesNoFile) {
  const NphMetadata m = smallMetadata();
  const fs::path target = dir_ / "storm.nph";
  {
    NphWriter w(target, m);
    w.append(randomVolumes(m, 4, 1, 0.01f));
    EXPECT_TRUE(fs::exists(w.temporaryPath()));
    ExtinctionVolumes wrong = randomVolumes(m, 4, 2, 0.01f);
    wrong.nx = 6;  // grid mismatch: the conversion fails half way
    EXPECT_THROW(w.append(wrong), UsageError);
    ExtinctionVolumes nan = randomVolumes(m, 2, 3, 0.01f);
    nan.water_per_m[5] = std::nanf("");
    EXPECT_THROW(w.append(nan), InputError);
  }  // destroyed without commit()
  EXPECT_FALSE(fs::exists(target));
  EXPECT_TRUE(filesInDir().empty());
}

TEST_F(NphCacheTest, FailedRewriteKeepsThePreviousFile) {
  const NphMetadata m = smallMetadata();
  const fs::path target = writeFile(dir_ / "storm.nph", m, {randomVolumes(m, 4, 1, 0.01f)});
  const std::string before = readAll(target);
  {
    NphWriter w(target, m);
    w.append(randomVolumes(m, 5, 2, 0.01f));
  }  // not committed
  EXPECT_EQ(readAll(target), before);
  EXPECT_EQ(filesInDir().size(), 1u);
}

TEST_F(NphCacheTest, UnwritableDirectoryIsIoError) {
  EXPECT_THROW(NphWriter(dir_ / "no" / "such" / "dir" / "x.nph", smallMetadata()), IoError);
}

}  // namespace
}  // namespace nph::cache
