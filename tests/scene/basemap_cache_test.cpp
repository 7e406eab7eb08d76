// The reprojected-basemap cache (src/scene/basemap_cache.h): a hit returns the warp's bytes; any
// change of what the warp depends on (the file, the rectangle, the pixels, the projection) misses;
// damaged entries are misses that get rewritten; images in memory are never cached; the folder is
// trimmed to NEPHELE_CACHE_MAX_MB. Real GeoTIFFs written with GDAL, real files on disk.
#include <gtest/gtest.h>
#include <stdlib.h>

#include <chrono>
#include <cstring>
#include <filesystem>
#include <fstream>

#include "gdal_raster_writer.h"
#include "scene/basemap.h"
#include "scene/basemap_cache.h"
#include "scene_test_support.h"

namespace nph::scene {
namespace {

namespace fs = std::filesystem;

/// Sets an environment variable for the scope of a test and restores the previous value.
class ScopedEnv {
 public:
  ScopedEnv(const char* name, const std::string& value) : name_(name) {
    if (const char* old = std::getenv(name)) old_ = old;
    ::setenv(name, value.c_str(), 1);
  }
  ~ScopedEnv() {
    if (old_) {
      ::setenv(name_, old_->c_str(), 1);
    } else {
      ::unsetenv(name_);
    }
  }

 private:
  const char* name_;
  std::optional<std::string> old_;
};

/// A whole-Earth 2:1 float GeoTIFF (no georeference: the 2:1 rule) with a pattern in all bands.
void writeWorld(const std::string& path, int w, double phase) {
  const int h = w / 2;
  std::vector<double> px(std::size_t(w) * std::size_t(h) * 3);
  for (std::size_t i = 0; i < px.size(); ++i) px[i] = 0.5 + 0.5 * std::sin(0.37 * double(i) + phase);
  test::writeGeoTiff(path, {w, h, 3, GDT_Float32, std::nullopt, ""}, px);
}

std::size_t entries(const fs::path& dir) {
  std::size_t n = 0;
  if (!fs::exists(dir / "basemaps")) return 0;
  for (const auto& e : fs::directory_iterator(dir / "basemaps")) n += e.path().extension() == ".nbm" ? 1 : 0;
  return n;
}

struct Fixture {
  ExtinctionVolumes v = test::lambertVolumes(8, 8, 2);
  volume::VolumeFrame frame = volume::frameOf(v);
  SceneGeoreference geo{v, frame};
  WorldRect rect = basemapRectangle(frame, 0.25);
};

void expectSameImage(const LinearRgbImage& a, const LinearRgbImage& b) {
  ASSERT_EQ(a.width, b.width);
  ASSERT_EQ(a.height, b.height);
  EXPECT_EQ(a.integer_source, b.integer_source);
  ASSERT_EQ(a.rgb.size(), b.rgb.size());
  EXPECT_EQ(0, std::memcmp(a.rgb.data(), b.rgb.data(), a.rgb.size() * sizeof(float))) << "not bit for bit";
}

TEST(BasemapCache, AHitIsTheWarpBitForBitAndChangesMiss) {
  nph::test::ScratchDir dir("scene");
  const ScopedEnv env("NEPHELE_CACHE_DIR", dir.file("cache"));
  const std::string path = dir.file("world.tif");
  writeWorld(path, 720, 0.0);
  const Fixture f;
  const std::vector<BasemapRaster> layers{BasemapRaster::open(path)};
  const LinearRgbImage direct = reprojectBasemap(layers, f.geo, f.rect, 64, 48);

  const BasemapCacheStats s0 = basemapCacheStats();
  const LinearRgbImage first = reprojectBasemapCached(layers, f.geo, f.rect, 64, 48);
  const LinearRgbImage second = reprojectBasemapCached(layers, f.geo, f.rect, 64, 48);
  const BasemapCacheStats s1 = basemapCacheStats();
  EXPECT_EQ(s1.misses - s0.misses, 1);
  EXPECT_EQ(s1.hits - s0.hits, 1);
  expectSameImage(direct, first);
  expectSameImage(direct, second);
  EXPECT_EQ(entries(dir.file("cache")), 1u);

  // Other pixels, another rectangle, another projection's offset: other keys.
  const auto key = basemapCacheKey(layers, f.geo, f.rect, 64, 48);
  ASSERT_TRUE(key);
  EXPECT_NE(*key, *basemapCacheKey(layers, f.geo, f.rect, 64, 47));
  WorldRect wider = f.rect;
  wider.max_m.x += 1.0;
  EXPECT_NE(*key, *basemapCacheKey(layers, f.geo, wider, 64, 48));
  const SceneGeoreference shifted(f.v, f.frame, LonLatOffset{1.0, 0.0});
  EXPECT_NE(*key, *basemapCacheKey(layers, shifted, f.rect, 64, 48));
  const volume::VolumeFrame moved = volume::frameOf(f.v, 1.0);
  EXPECT_EQ(*key, *basemapCacheKey(layers, SceneGeoreference(f.v, moved), f.rect, 64, 48))
      << "the same mapping gives the same key";

  // The file rewritten with other pixels (a new time and here another size): a miss, the new warp.
  writeWorld(path, 720, 1.0);
  fs::last_write_time(path, fs::last_write_time(path) + std::chrono::seconds(5));
  const std::vector<BasemapRaster> reopened{BasemapRaster::open(path)};
  const LinearRgbImage changed = reprojectBasemapCached(reopened, f.geo, f.rect, 64, 48);
  EXPECT_EQ(basemapCacheStats().misses - s1.misses, 1);
  expectSameImage(reprojectBasemap(reopened, f.geo, f.rect, 64, 48), changed);
  EXPECT_NE(0, std::memcmp(changed.rgb.data(), direct.rgb.data(), direct.rgb.size() * sizeof(float)));
}

TEST(BasemapCache, DamagedEntriesAreMissesAndAreRewritten) {
  nph::test::ScratchDir dir("scene");
  const ScopedEnv env("NEPHELE_CACHE_DIR", dir.file("cache"));
  const std::string path = dir.file("world.tif");
  writeWorld(path, 360, 0.5);
  const std::vector<BasemapRaster> layers{BasemapRaster::open(path)};
  const LinearRgbImage direct = reprojectEquirectangular(layers, 128, 64);
  (void)reprojectEquirectangularCached(layers, 128, 64);
  ASSERT_EQ(entries(dir.file("cache")), 1u);
  const fs::path entry = fs::directory_iterator(fs::path(dir.file("cache")) / "basemaps")->path();
  const auto size = fs::file_size(entry);

  // A flipped byte in the compressed floats (zstd's content checksum), then a truncated entry.
  for (int damage = 0; damage < 2; ++damage) {
    if (damage == 0) {
      std::fstream e(entry, std::ios::in | std::ios::out | std::ios::binary);
      e.seekp(std::streamoff(size - 20));
      e.put('\x5a');
    } else {
      fs::resize_file(entry, size / 2);
    }
    const BasemapCacheStats before = basemapCacheStats();
    const LinearRgbImage again = reprojectEquirectangularCached(layers, 128, 64);
    EXPECT_EQ(basemapCacheStats().misses - before.misses, 1) << "damage " << damage;
    expectSameImage(direct, again);
    EXPECT_EQ(fs::file_size(entry), size) << "rewritten";
    const BasemapCacheStats rewritten = basemapCacheStats();
    expectSameImage(direct, reprojectEquirectangularCached(layers, 128, 64));
    EXPECT_EQ(basemapCacheStats().hits - rewritten.hits, 1);
  }
}

TEST(BasemapCache, ImagesInMemoryAndOffAreNotCachedAndTheFolderIsTrimmed) {
  nph::test::ScratchDir dir("scene");
  const std::string path = dir.file("world.tif");
  writeWorld(path, 360, 0.25);
  const Fixture f;
  LinearRgbImage memory{8, 4, std::vector<float>(8 * 4 * 3, 0.5f), false};
  EXPECT_FALSE(basemapCacheKey({BasemapRaster::fromEquirectangular(memory)}, f.geo, f.rect, 16, 16));
  EXPECT_FALSE(equirectangularCacheKey({BasemapRaster::fromEquirectangular(memory)}, 16, 8));
  {
    const ScopedEnv env("NEPHELE_CACHE_DIR", "off");
    EXPECT_FALSE(basemapCacheDir());
  }
  const ScopedEnv env("NEPHELE_CACHE_DIR", dir.file("cache"));
  const std::vector<BasemapRaster> layers{BasemapRaster::open(path)};
  (void)reprojectBasemapCached(layers, f.geo, f.rect, 32, 32);
  (void)reprojectBasemapCached(layers, f.geo, f.rect, 32, 31);
  EXPECT_EQ(entries(dir.file("cache")), 2u);
  const ScopedEnv cap("NEPHELE_CACHE_MAX_MB", "0");
  (void)reprojectBasemapCached(layers, f.geo, f.rect, 32, 30);
  EXPECT_EQ(entries(dir.file("cache")), 0u) << "trimmed to 0 MB, the least recently used first";
}

}  // namespace
}  // namespace nph::scene
