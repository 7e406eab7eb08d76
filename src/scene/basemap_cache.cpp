// The reprojected-basemap cache (basemap_cache.h).
#include "scene/basemap_cache.h"

#include <dlfcn.h>
#include <unistd.h>
#include <zstd.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstring>
#include <fstream>
#include <system_error>

#include <fmt/format.h>

#include "core/env.h"
#include "core/error.h"
#include "core/large_buffer.h"
#include "core/log.h"
#include "core/temp_files.h"

namespace nph::scene {
namespace {

namespace fs = std::filesystem;

constexpr char kMagic[8] = {'N', 'P', 'H', 'B', 'M', 'A', 'P', '\x01'};
constexpr const char* kEntrySuffix = ".nbm";
constexpr std::uint64_t kDefaultMaxMb = 2048;

std::atomic<int> g_hits{0}, g_misses{0};

/// FNV-1a, 64 bits: a stable name for a key (the key itself is compared on reading).
std::uint64_t fnv1a(const std::string& s) {
  std::uint64_t h = 14695981039346656037ull;
  for (const unsigned char c : s) {
    h ^= c;
    h *= 1099511628211ull;
  }
  return h;
}

/// "path size mtime" of a regular file, or nullopt.
std::optional<std::string> fileIdentity(const fs::path& p) {
  std::error_code ec;
  const fs::path canonical = fs::canonical(p, ec);
  if (ec || !fs::is_regular_file(canonical, ec)) return std::nullopt;
  const auto size = fs::file_size(canonical, ec);
  if (ec) return std::nullopt;
  const auto mtime = fs::last_write_time(canonical, ec);
  if (ec) return std::nullopt;
  return fmt::format("{} {} {}", canonical.string(), size, mtime.time_since_epoch().count());
}

/// The binary object holding this module (the shared library, or the executable it is linked
/// into): a rebuild of the warp changes its size or time, so every entry of an older build misses.
const std::string& codeIdentity() {
  static const std::string id = [] {
    Dl_info info{};
    if (dladdr(reinterpret_cast<void*>(&fnv1a), &info) != 0 && info.dli_fname != nullptr) {
      if (auto f = fileIdentity(info.dli_fname)) return *f;
    }
    return std::string("unknown ") + std::to_string(::getpid());  // never matches another process
  }();
  return id;
}

std::optional<std::string> layersIdentity(const std::vector<BasemapRaster>& layers) {
  std::string s;
  for (const BasemapRaster& l : layers) {
    const std::optional<std::string> f = fileIdentity(l.name());
    if (!f) return std::nullopt;  // an image in memory, or a name that is not a file
    s += fmt::format("layer {} overview {}\n", *f, l.overviewLevel());
  }
  return s;
}

template <class T>
void put(std::string& out, const T& v) {
  out.append(reinterpret_cast<const char*>(&v), sizeof(T));
}

template <class T>
bool get(const std::vector<char>& in, std::size_t& at, T& v) {
  if (at > in.size() || in.size() - at < sizeof(T)) return false;
  std::memcpy(&v, in.data() + at, sizeof(T));
  at += sizeof(T);
  return true;
}

std::uint64_t maxCacheBytes() {
  std::uint64_t mb = kDefaultMaxMb;
  if (const auto v = env::get("NEPHELE_CACHE_MAX_MB")) {
    try {
      std::size_t used = 0;
      const unsigned long long parsed = std::stoull(*v, &used);
      if (used == v->size() && parsed <= (std::uint64_t(1) << 30)) mb = parsed;
    } catch (const std::exception&) {
    }
  }
  return mb * 1024 * 1024;
}

/// Drops the least recently used entries until the folder holds at most maxCacheBytes().
void trim(const fs::path& dir) {
  struct Entry {
    fs::path path;
    fs::file_time_type used;
    std::uintmax_t bytes;
  };
  std::vector<Entry> entries;
  std::uintmax_t total = 0;
  std::error_code ec;
  for (const fs::directory_entry& e : fs::directory_iterator(dir, ec)) {
    if (e.path().extension() != kEntrySuffix || !e.is_regular_file(ec)) continue;
    const std::uintmax_t bytes = e.file_size(ec);
    if (ec) continue;
    entries.push_back({e.path(), e.last_write_time(ec), bytes});
    total += bytes;
  }
  const std::uint64_t max = maxCacheBytes();
  if (total <= max) return;
  std::sort(entries.begin(), entries.end(), [](const Entry& a, const Entry& b) { return a.used < b.used; });
  for (const Entry& e : entries) {
    if (total <= max) break;
    if (fs::remove(e.path, ec)) total -= e.bytes;
  }
}

std::optional<LinearRgbImage> readEntry(const fs::path& path, const std::string& key) {
  std::ifstream f(path, std::ios::binary);
  if (!f) return std::nullopt;
  std::error_code ec;
  const std::uintmax_t size = fs::file_size(path, ec);
  if (ec || size > (std::uintmax_t(1) << 34)) return std::nullopt;
  std::vector<char> in = hugePageVector<char>(size);
  if (!f.read(in.data(), std::streamsize(size))) return std::nullopt;
  std::size_t at = 0;
  char magic[8];
  std::uint32_t key_bytes = 0;
  if (!get(in, at, magic) || std::memcmp(magic, kMagic, 8) != 0 || !get(in, at, key_bytes) ||
      in.size() - at < key_bytes || std::string(in.data() + at, key_bytes) != key) {
    return std::nullopt;  // another format or, on a hash collision, another key
  }
  at += key_bytes;
  std::int32_t width = 0, height = 0;
  std::uint32_t flags = 0;
  std::uint64_t raw_bytes = 0, packed_bytes = 0;
  if (!get(in, at, width) || !get(in, at, height) || !get(in, at, flags) || !get(in, at, raw_bytes) ||
      !get(in, at, packed_bytes) || width <= 0 || height <= 0 ||
      raw_bytes != std::uint64_t(width) * std::uint64_t(height) * 3 * sizeof(float) || in.size() - at != packed_bytes ||
      ZSTD_getFrameContentSize(in.data() + at, packed_bytes) != raw_bytes) {
    return std::nullopt;
  }
  LinearRgbImage image{width, height, hugePageFloats(raw_bytes / sizeof(float)), (flags & 1u) != 0};
  // The frame carries its content checksum: ZSTD_decompress verifies it.
  const std::size_t n = ZSTD_decompress(image.rgb.data(), raw_bytes, in.data() + at, packed_bytes);
  if (ZSTD_isError(n) || n != raw_bytes) return std::nullopt;
  return image;
}

void writeEntry(const fs::path& path, const std::string& key, const LinearRgbImage& image) {
  const std::size_t raw_bytes = image.rgb.size() * sizeof(float);
  std::string packed(ZSTD_compressBound(raw_bytes), '\0');
  ZSTD_CCtx* cctx = ZSTD_createCCtx();
  if (cctx == nullptr) throw IoError("zstd: cannot create a compression context");
  ZSTD_CCtx_setParameter(cctx, ZSTD_c_compressionLevel, 1);
  ZSTD_CCtx_setParameter(cctx, ZSTD_c_checksumFlag, 1);
  const std::size_t n = ZSTD_compress2(cctx, packed.data(), packed.size(), image.rgb.data(), raw_bytes);
  ZSTD_freeCCtx(cctx);
  if (ZSTD_isError(n)) throw IoError(fmt::format("{}: zstd: {}", path.string(), ZSTD_getErrorName(n)));
  packed.resize(n);
  std::string header(kMagic, 8);
  put(header, std::uint32_t(key.size()));
  header += key;
  put(header, std::int32_t(image.width));
  put(header, std::int32_t(image.height));
  put(header, std::uint32_t(image.integer_source ? 1 : 0));
  put(header, std::uint64_t(raw_bytes));
  put(header, std::uint64_t(n));

  const fs::path dir = path.parent_path();
  temp_files::removeStale(dir, ".tmp-");
  const temp_files::Created temp = temp_files::createExclusive(path, path.filename().string(), ".tmp-", "");
  temp_files::CleanupRegistration cleanup(temp.path);
  bool ok = true;
  for (const std::string* part : {&header, &packed}) {
    const char* p = part->data();
    std::size_t left = part->size();
    while (ok && left > 0) {
      const ssize_t w = ::write(temp.fd, p, left);
      if (w < 0 && errno == EINTR) continue;
      ok = w > 0;
      if (ok) {
        p += w;
        left -= std::size_t(w);
      }
    }
  }
  ok = ::close(temp.fd) == 0 && ok;
  std::error_code ec;
  if (ok) fs::rename(temp.path, path, ec);
  if (!ok || ec) {
    fs::remove(temp.path, ec);
    throw IoError(fmt::format("{}: cannot write the basemap cache entry", path.string()));
  }
}

}  // namespace

std::optional<fs::path> basemapCacheDir() {
  if (const auto d = env::get("NEPHELE_CACHE_DIR")) {
    if (*d == "off") return std::nullopt;
    return fs::path(*d);
  }
  if (const auto x = env::get("XDG_CACHE_HOME")) return fs::path(*x) / "nephele";
  if (const auto h = env::get("HOME")) return fs::path(*h) / ".cache" / "nephele";
  return std::nullopt;
}

std::optional<std::string> basemapCacheKey(const std::vector<BasemapRaster>& layers, const SceneGeoreference& geo,
                                           const WorldRect& rect, int width, int height) {
  const std::optional<std::string> l = layersIdentity(layers);
  if (!l) return std::nullopt;
  std::string key = fmt::format("nephele basemap 1\ncode {}\nmap {}x{}\n{}", codeIdentity(), width, height, *l);
  key += fmt::format("projection {}\noffset {:a} {:a}\n", geo.projection().definition(), geo.offset().lon_deg,
                     geo.offset().lat_deg);
  for (const glm::dvec2 w : {glm::dvec2(0.0), glm::dvec2(1e5, 0.0), glm::dvec2(0.0, 1e5)}) {
    const LonLat ll = geo.lonLatFromWorld(w);
    key += fmt::format("point {:a} {:a}\n", ll.lon_deg, ll.lat_deg);
  }
  key += fmt::format("rect {:a} {:a} {:a} {:a}\n", rect.min_m.x, rect.min_m.y, rect.max_m.x, rect.max_m.y);
  return key;
}

std::optional<std::string> equirectangularCacheKey(const std::vector<BasemapRaster>& layers, int width, int height) {
  const std::optional<std::string> l = layersIdentity(layers);
  if (!l) return std::nullopt;
  return fmt::format("nephele basemap 1\ncode {}\nequirectangular {}x{}\n{}", codeIdentity(), width, height, *l);
}

BasemapCacheStats basemapCacheStats() { return {g_hits.load(), g_misses.load()}; }

LinearRgbImage cachedBasemap(const std::optional<std::string>& key, const std::function<LinearRgbImage()>& compute) {
  const std::optional<fs::path> root = key ? basemapCacheDir() : std::nullopt;
  if (!root) {
    ++g_misses;
    return compute();
  }
  const fs::path dir = *root / "basemaps";
  const fs::path path = dir / fmt::format("{:016x}{}", fnv1a(*key), kEntrySuffix);
  if (std::optional<LinearRgbImage> hit = readEntry(path, *key)) {
    std::error_code ec;
    fs::last_write_time(path, fs::file_time_type::clock::now(), ec);  // recently used
    ++g_hits;
    log::debug("basemap cache: {} ({}x{}) read", path.string(), hit->width, hit->height);
    return std::move(*hit);
  }
  ++g_misses;
  LinearRgbImage image = compute();
  try {
    std::error_code ec;
    fs::create_directories(dir, ec);
    if (ec) throw IoError(fmt::format("{}: cannot create the folder: {}", dir.string(), ec.message()));
    writeEntry(path, *key, image);
    trim(dir);
    log::debug("basemap cache: {} written", path.string());
  } catch (const std::exception& e) {
    log::warn("basemap cache: not stored ({}); NEPHELE_CACHE_DIR names another folder, or 'off'", e.what());
  }
  return image;
}

LinearRgbImage reprojectBasemapCached(const std::vector<BasemapRaster>& layers, const SceneGeoreference& geo,
                                      const WorldRect& rect, int width, int height) {
  return cachedBasemap(basemapCacheKey(layers, geo, rect, width, height),
                       [&] { return reprojectBasemap(layers, geo, rect, width, height); });
}

LinearRgbImage reprojectEquirectangularCached(const std::vector<BasemapRaster>& layers, int width, int height) {
  return cachedBasemap(equirectangularCacheKey(layers, width, height),
                       [&] { return reprojectEquirectangular(layers, width, height); });
}

}  // namespace nph::scene
