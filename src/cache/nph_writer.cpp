// NphWriter: temp file + rename, one zstd frame per timestep (layout in nph_cache.h).
#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>
#include <zstd.h>

#include <cmath>
#include <cstdlib>
#include <cstring>
#include <nlohmann/json.hpp>
#include <system_error>

#include "cache/checksum.h"
#include "cache/nph_cache.h"
#include "cache/nph_format.h"
#include "cache/nph_index.h"
#include "cache/quantize.h"
#include "core/error.h"
#include "core/log.h"
#include "core/temp_files.h"

namespace nph::cache {

namespace {

std::string errnoText() { return std::generic_category().message(errno); }

}  // namespace

struct NphWriter::State {
  std::filesystem::path path;
  std::filesystem::path temp_path;
  NphMetadata metadata;
  WriterOptions options;
  int fd = -1;
  std::uint64_t offset = 0;  ///< bytes written so far = offset of the next block
  std::vector<TimestepInfo> timesteps;
  ChunkRef geolocation;
  ChunkRef terrain;
  bool committed = false;
  int cleanup_slot = -1;  ///< temp_files::registerForCleanup (unlinked on SIGINT/SIGTERM)
  ZSTD_CCtx* cctx = nullptr;

  void writeAll(const void* data, std::size_t bytes) {
    const auto* p = static_cast<const char*>(data);
    std::size_t left = bytes;
    while (left > 0) {
      const ssize_t n = ::write(fd, p, left);
      if (n < 0) {
        if (errno == EINTR) continue;
        throw IoError(fmt::format("{}: cannot write: {}", temp_path.string(), errnoText()));
      }
      p += n;
      left -= static_cast<std::size_t>(n);
    }
    offset += bytes;
  }

  /// Compresses `raw` into one zstd frame (with zstd's own content checksum) and writes it.
  ChunkRef writeChunk(const void* raw, std::size_t raw_bytes) {
    std::vector<std::byte> packed(ZSTD_compressBound(raw_bytes));
    const std::size_t n = ZSTD_compress2(cctx, packed.data(), packed.size(), raw, raw_bytes);
    if (ZSTD_isError(n)) {
      throw IoError(fmt::format("{}: zstd compression failed: {}", temp_path.string(), ZSTD_getErrorName(n)));
    }
    ChunkRef ref;
    ref.offset = offset;
    ref.bytes = n;
    ref.raw_bytes = raw_bytes;
    ref.xxh64 = xxh64(std::span<const std::byte>(packed.data(), n));
    writeAll(packed.data(), n);
    return ref;
  }

  ~State() {
    temp_files::unregisterForCleanup(cleanup_slot);
    if (cctx != nullptr) ZSTD_freeCCtx(cctx);
    if (fd >= 0) ::close(fd);
    if (!committed && !temp_path.empty()) {
      std::error_code ec;
      std::filesystem::remove(temp_path, ec);
    }
  }
};

NphWriter::NphWriter(std::filesystem::path path, NphMetadata metadata, WriterOptions options)
    : state_(std::make_unique<State>()) {
  State& s = *state_;
  s.path = std::move(path);
  s.metadata = std::move(metadata);
  s.options = options;
  if (s.metadata.nx <= 0 || s.metadata.ny <= 0 || !(s.metadata.dz_m > 0.0)) {
    throw UsageError(
        fmt::format("{}: invalid grid {}x{}, dz {} m", s.path.string(), s.metadata.nx, s.metadata.ny, s.metadata.dz_m));
  }
  // Exclusive, unpredictable temporary in the target's directory, so that rename() stays on one
  // file system (atomic); named with our pid, so that a later run removes it if we are killed.
  const std::filesystem::path dir = s.path.has_parent_path() ? s.path.parent_path() : std::filesystem::path(".");
  temp_files::removeStale(dir, ".tmp-");
  const temp_files::Created temp = temp_files::createExclusive(s.path, s.path.filename().string(), ".tmp-", "");
  s.fd = temp.fd;
  s.temp_path = temp.path;
  s.cleanup_slot = temp_files::registerForCleanup(s.temp_path);
  s.cctx = ZSTD_createCCtx();
  if (s.cctx == nullptr) throw IoError("zstd: cannot create a compression context");
  ZSTD_CCtx_setParameter(s.cctx, ZSTD_c_compressionLevel, s.options.zstd_level);
  ZSTD_CCtx_setParameter(s.cctx, ZSTD_c_checksumFlag, 1);
  if (s.options.zstd_workers > 0) {
    // Ignored (returns an error) by a libzstd built without multithreading: fine.
    ZSTD_CCtx_setParameter(s.cctx, ZSTD_c_nbWorkers, s.options.zstd_workers);
  }
  const std::array<std::byte, kHeaderBytes> placeholder{};
  s.writeAll(placeholder.data(), placeholder.size());

  const geo::GridGeoreference& g = s.metadata.georef;
  const std::size_t columns = std::size_t(s.metadata.nx) * std::size_t(s.metadata.ny);
  if (!g.lat_deg.empty() || !g.lon_deg.empty()) {
    if (g.lat_deg.size() != columns || g.lon_deg.size() != columns) {
      throw UsageError(fmt::format("{}: geolocation has {}/{} lat/lon values, expected {} ({}x{})", s.path.string(),
                                   g.lat_deg.size(), g.lon_deg.size(), columns, s.metadata.nx, s.metadata.ny));
    }
    std::vector<float> latlon(g.lat_deg);
    latlon.insert(latlon.end(), g.lon_deg.begin(), g.lon_deg.end());
    s.geolocation = s.writeChunk(latlon.data(), latlon.size() * sizeof(float));
  }
  const std::vector<float>& terrain = s.metadata.terrain_height_m;
  if (!terrain.empty()) {
    if (terrain.size() != columns) {
      throw UsageError(fmt::format("{}: terrain has {} values, expected {} ({}x{})", s.path.string(), terrain.size(),
                                   columns, s.metadata.nx, s.metadata.ny));
    }
    for (std::size_t q = 0; q < columns; ++q) {
      if (!std::isfinite(terrain[q])) {
        throw InputError(fmt::format("{}: terrain height at column {} is {}; expected a finite height [m]",
                                     s.path.string(), q, terrain[q]));
      }
    }
    s.terrain = s.writeChunk(terrain.data(), terrain.size() * sizeof(float));
  }
}

NphWriter::~NphWriter() = default;

void NphWriter::append(const ExtinctionVolumes& v) {
  State& s = *state_;
  if (s.committed) throw UsageError(fmt::format("{}: append() after commit()", s.path.string()));
  const NphMetadata& m = s.metadata;
  if (v.nx != m.nx || v.ny != m.ny || v.dz_m != m.dz_m || v.z_bottom_m != m.z_bottom_m) {
    throw UsageError(fmt::format("{}: timestep {} has grid {}x{} (dz {} m, bottom {} m), the file has {}x{} (dz {} m, "
                                 "bottom {} m)",
                                 s.path.string(), geo::isoOrEmpty(v.time_utc), v.nx, v.ny, v.dz_m, v.z_bottom_m, m.nx,
                                 m.ny, m.dz_m, m.z_bottom_m));
  }
  const std::size_t n = v.voxelCount();
  if (v.nz < 0 || v.ice_per_m.size() != n || v.water_per_m.size() != n) {
    throw UsageError(fmt::format("{}: timestep {}: {} ice / {} water values for {}x{}x{} voxels", s.path.string(),
                                 geo::isoOrEmpty(v.time_utc), v.ice_per_m.size(), v.water_per_m.size(), v.nx, v.ny,
                                 v.nz));
  }
  float max_ice = 0.0f, max_water = 0.0f;
  for (std::size_t q = 0; q < n; ++q) {
    const float a = v.ice_per_m[q], b = v.water_per_m[q];
    if (!std::isfinite(a) || !std::isfinite(b) || a < 0.0f || b < 0.0f) {
      throw InputError(fmt::format("{}: timestep {}: extinction at voxel {} is {} (ice) / {} (water); expected finite, "
                                   ">= 0",
                                   s.path.string(), geo::isoOrEmpty(v.time_utc), q, a, b));
    }
    max_ice = std::max(max_ice, a);
    max_water = std::max(max_water, b);
  }
  std::vector<std::uint16_t> codes(2 * n);
  quantise(v.ice_per_m, max_ice, std::span(codes).first(n));
  quantise(v.water_per_m, max_water, std::span(codes).subspan(n));
  const ChunkRef ref = s.writeChunk(codes.data(), codes.size() * sizeof(std::uint16_t));
  std::vector<std::uint16_t>().swap(codes);

  // U, V for the motion blend (engine::blendVolumes; docs/animation.md "Between two timesteps"):
  // its own chunk after the timestep's, so that the reader checks and decodes it like the
  // extinction and a file without it reads as before (nph_cache.h).
  const std::size_t nu = v.wind_u_m_per_s.size(), nv = v.wind_v_m_per_s.size();
  if ((nu != 0 && nu != n) || (nv != 0 && nv != n)) {
    throw UsageError(fmt::format("{}: timestep {}: {} U / {} V values for {}x{}x{} voxels", s.path.string(),
                                 geo::isoOrEmpty(v.time_utc), nu, nv, v.nx, v.ny, v.nz));
  }
  ChunkRef wind;
  if (nu == n && nv == n) {
    std::vector<std::int16_t> uv(2 * n);
    const std::size_t calm = quantiseWind(v.wind_u_m_per_s, std::span(uv).first(n)) +
                             quantiseWind(v.wind_v_m_per_s, std::span(uv).subspan(n));
    if (calm > 0) {
      log::warn("{}: timestep {}: {} non-finite U/V values stored as calm (0 m/s)", s.path.string(),
                geo::isoOrEmpty(v.time_utc), calm);
    }
    std::vector<std::byte> packed(uv.size() * sizeof(std::int16_t));
    packWindCodes(uv, std::size_t(v.nx), packed);
    wind = s.writeChunk(packed.data(), packed.size());
  }

  TimestepInfo info;
  info.time_utc = v.time_utc;
  info.source_file = v.source_file;
  info.source_time_index = v.source_time_index;
  info.nz = v.nz;
  info.max_ice_per_m = max_ice;
  info.max_water_per_m = max_water;
  info.chunk_offset = ref.offset;
  info.chunk_bytes = ref.bytes;
  info.raw_bytes = ref.raw_bytes;
  info.chunk_xxh64 = ref.xxh64;
  info.wind_chunk_offset = wind.offset;
  info.wind_chunk_bytes = wind.bytes;
  info.wind_raw_bytes = wind.raw_bytes;
  info.wind_chunk_xxh64 = wind.xxh64;
  s.timesteps.push_back(std::move(info));
}

void NphWriter::commit() {
  State& s = *state_;
  if (s.committed) return;
  // Provenance strings (input paths) need not be UTF-8 on Linux; dump() threw an error naming no
  // file at the very end of a conversion. Such bytes are stored as U+FFFD instead.
  const std::string index = encodeIndex(s.metadata, s.timesteps, s.geolocation, s.terrain)
                                .dump(1, ' ', false, nlohmann::json::error_handler_t::replace);
  detail::Header h;
  h.version = kFormatVersion;
  h.header_bytes = kHeaderBytes;
  h.index_offset = s.offset;
  h.index_bytes = index.size();
  h.index_xxh64 = xxh64(std::as_bytes(std::span(index.data(), index.size())));
  s.writeAll(index.data(), index.size());
  h.file_bytes = s.offset;

  std::array<std::byte, kHeaderBytes> raw{};
  std::memcpy(raw.data(), detail::kMagic.data(), detail::kMagic.size());
  detail::put(raw.data() + 8, h.version);
  detail::put(raw.data() + 12, h.header_bytes);
  detail::put(raw.data() + 16, h.index_offset);
  detail::put(raw.data() + 24, h.index_bytes);
  detail::put(raw.data() + 32, h.index_xxh64);
  detail::put(raw.data() + 40, h.file_bytes);
  detail::put(raw.data() + 48, std::uint64_t{0});
  detail::put(raw.data() + detail::kHeaderChecksumOffset, xxh64(std::span(raw.data(), detail::kHeaderChecksumOffset)));
  if (::pwrite(s.fd, raw.data(), raw.size(), 0) != static_cast<ssize_t>(raw.size())) {
    throw IoError(fmt::format("{}: cannot write the header: {}", s.temp_path.string(), errnoText()));
  }
  if (::fsync(s.fd) != 0) {
    throw IoError(fmt::format("{}: fsync failed: {}", s.temp_path.string(), errnoText()));
  }
  ::close(s.fd);
  s.fd = -1;
  std::error_code ec;
  std::filesystem::rename(s.temp_path, s.path, ec);
  if (ec) {
    throw IoError(fmt::format("{}: cannot rename {} to it: {}", s.path.string(), s.temp_path.string(), ec.message()));
  }
  s.committed = true;
  temp_files::unregisterForCleanup(s.cleanup_slot);
  s.cleanup_slot = -1;
  log::debug("{}: wrote {} timesteps, {} bytes", s.path.string(), s.timesteps.size(), s.offset);
}

std::size_t NphWriter::timestepCount() const { return state_->timesteps.size(); }
std::uint64_t NphWriter::bytesWritten() const { return state_->offset; }
const std::filesystem::path& NphWriter::temporaryPath() const { return state_->temp_path; }

}  // namespace nph::cache
