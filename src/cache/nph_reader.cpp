// NphReader: header + index at open, one verified chunk per read() (layout in nph_cache.h).
#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>
#include <zstd.h>

#include <cstring>
#include <system_error>

#include <fmt/format.h>
#include "cache/checksum.h"
#include "cache/nph_cache.h"
#include "cache/nph_format.h"
#include "cache/nph_index.h"
#include "cache/quantize.h"

#include "core/error.h"
#include "core/input_file.h"
#include "core/large_buffer.h"
#include "core/limits.h"
#include "volume/detail.h"

namespace nph::cache {

namespace {

std::string errnoText() { return std::generic_category().message(errno); }

/// Reads exactly `bytes` at `offset`; false when the file ends first.
bool readAt(int fd, void* into, std::size_t bytes, std::uint64_t offset) {
  auto* p = static_cast<char*>(into);
  while (bytes > 0) {
    const ssize_t n = ::pread(fd, p, bytes, static_cast<off_t>(offset));
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) return false;
    p += n;
    bytes -= static_cast<std::size_t>(n);
    offset += static_cast<std::uint64_t>(n);
  }
  return true;
}

}  // namespace

struct NphReader::State {
  std::filesystem::path path;
  int fd = -1;
  std::uint32_t version = 0;
  std::uint64_t file_bytes = 0;
  DecodedIndex index;

  ~State() {
    if (fd >= 0) ::close(fd);
  }

  std::string name() const { return path.string(); }

  /// Reads, checksums and decompresses one block. `what` names it in errors.
  std::vector<std::byte> readBlock(const ChunkRef& c, const std::string& what) const {
    if (c.offset < kHeaderBytes || c.offset + c.bytes > file_bytes || c.bytes > file_bytes) {
      throw InputError(fmt::format("{}: {} lies outside the file (offset {}, {} bytes, file {} bytes)", name(), what,
                                   c.offset, c.bytes, file_bytes));
    }
    std::vector<std::byte> packed = hugePageVector<std::byte>(c.bytes);
    if (!readAt(fd, packed.data(), packed.size(), c.offset)) {
      throw InputError(
          fmt::format("{}: {} is truncated (expected {} bytes at offset {})", name(), what, c.bytes, c.offset));
    }
    const std::uint64_t sum = xxh64(packed);
    if (sum != c.xxh64) {
      throw InputError(
          fmt::format("{}: {} is corrupt: XXH64 {} , expected {}", name(), what, toHex(sum), toHex(c.xxh64)));
    }
    // The zstd frame states its decompressed size: compare before allocating raw_bytes, so a
    // small file cannot make the reader allocate what its index claims.
    const unsigned long long frame_bytes = ZSTD_getFrameContentSize(packed.data(), packed.size());
    if (frame_bytes != c.raw_bytes) {
      throw InputError(fmt::format("{}: {} decompresses to {} bytes, the index says {}", name(), what,
                                   frame_bytes == ZSTD_CONTENTSIZE_UNKNOWN || frame_bytes == ZSTD_CONTENTSIZE_ERROR
                                       ? std::string("an unknown number of")
                                       : std::to_string(frame_bytes),
                                   c.raw_bytes));
    }
    std::vector<std::byte> raw = hugePageVector<std::byte>(c.raw_bytes);
    const std::size_t n = ZSTD_decompress(raw.data(), raw.size(), packed.data(), packed.size());
    if (ZSTD_isError(n) || n != raw.size()) {
      throw InputError(fmt::format("{}: {} does not decompress to {} bytes: {}", name(), what, raw.size(),
                                   ZSTD_isError(n) ? ZSTD_getErrorName(n) : "size mismatch"));
    }
    return raw;
  }
};

bool NphReader::sniff(const std::filesystem::path& path) {
  // O_NONBLOCK: opening a FIFO for reading must not wait for a writer; only regular files count.
  const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC | O_NONBLOCK);
  if (fd < 0) return false;
  struct stat st {};
  std::array<char, 8> magic{};
  const bool ok = ::fstat(fd, &st) == 0 && S_ISREG(st.st_mode) && readAt(fd, magic.data(), magic.size(), 0) &&
                  magic == detail::kMagic;
  ::close(fd);
  return ok;
}

NphReader::NphReader(std::filesystem::path path) : state_(std::make_unique<State>()) {
  State& s = *state_;
  s.path = std::move(path);
  requireRegularFile(s.name(), "a .nph cache file");
  // O_NONBLOCK as well, in case the path was swapped for a FIFO after the check above.
  s.fd = ::open(s.path.c_str(), O_RDONLY | O_CLOEXEC | O_NONBLOCK);
  if (s.fd < 0) throw InputError(fmt::format("{}: cannot open: {}", s.name(), errnoText()));
  struct stat st {};
  if (::fstat(s.fd, &st) != 0 || !S_ISREG(st.st_mode)) {
    throw InputError(fmt::format("{}: not a regular file, expected a .nph cache file", s.name()));
  }
  const auto actual_bytes = static_cast<std::uint64_t>(st.st_size);
  std::array<std::byte, kHeaderBytes> raw{};
  if (actual_bytes < kHeaderBytes || !readAt(s.fd, raw.data(), raw.size(), 0)) {
    throw InputError(fmt::format("{}: truncated: {} bytes, a .nph file starts with a {}-byte header", s.name(),
                                 actual_bytes, kHeaderBytes));
  }
  if (std::memcmp(raw.data(), detail::kMagic.data(), detail::kMagic.size()) != 0) {
    throw InputError(fmt::format("{}: not a nephele .nph cache file (no NPHCACHE magic)", s.name()));
  }
  const auto stored_sum = detail::get<std::uint64_t>(raw.data() + detail::kHeaderChecksumOffset);
  if (xxh64(std::span(raw.data(), detail::kHeaderChecksumOffset)) != stored_sum) {
    throw InputError(fmt::format("{}: the header is corrupt (checksum mismatch)", s.name()));
  }
  s.version = detail::get<std::uint32_t>(raw.data() + 8);
  if (s.version != kFormatVersion) {
    throw InputError(
        fmt::format("{}: .nph format version {}, this nephele reads version {}", s.name(), s.version, kFormatVersion));
  }
  const auto index_offset = detail::get<std::uint64_t>(raw.data() + 16);
  const auto index_bytes = detail::get<std::uint64_t>(raw.data() + 24);
  const auto index_sum = detail::get<std::uint64_t>(raw.data() + 32);
  s.file_bytes = detail::get<std::uint64_t>(raw.data() + 40);
  if (actual_bytes != s.file_bytes) {
    throw InputError(fmt::format("{}: {} ({} bytes, the header says {})", s.name(),
                                 actual_bytes < s.file_bytes ? "truncated" : "trailing data", actual_bytes,
                                 s.file_bytes));
  }
  if (index_offset < kHeaderBytes || index_offset + index_bytes != s.file_bytes) {
    throw InputError(
        fmt::format("{}: index at {} (+{} bytes) does not end the file", s.name(), index_offset, index_bytes));
  }
  std::string text(index_bytes, '\0');
  if (!readAt(s.fd, text.data(), text.size(), index_offset)) {
    throw InputError(fmt::format("{}: the index is truncated", s.name()));
  }
  if (xxh64(std::as_bytes(std::span(text.data(), text.size()))) != index_sum) {
    throw InputError(fmt::format("{}: the index is corrupt (checksum mismatch)", s.name()));
  }
  s.index = decodeIndex(s.name(), text);
  {
    // read() holds two uint16 code volumes and two float volumes of the padded grid at once; with
    // a wind chunk, two more float volumes (U, V) and, while decoding them, their int16 codes.
    const NphMetadata& m = s.index.metadata;
    bool wind = false;
    for (const TimestepInfo& t : s.index.timesteps) wind = wind || t.hasWind();
    const std::uint64_t per_voxel_bytes =
        2 * sizeof(std::uint16_t) + 2 * sizeof(float) + (wind ? 2 * sizeof(std::int16_t) + 2 * sizeof(float) : 0);
    const std::uint64_t budget = limits::memoryBudgetBytesFromEnv();
    limits::requireProductWithin(s.name(),
                                 wind ? "bytes to read one timestep with its wind (nx x ny x nz x 24)"
                                      : "bytes to read one timestep (nx x ny x nz x 12)",
                                 {std::uint64_t(m.nx), std::uint64_t(m.ny), std::uint64_t(s.index.nz), per_voxel_bytes},
                                 budget, "raise NEPHELE_IO_MEMORY_BUDGET_MB");
  }
  if (s.index.geolocation.present()) {
    const std::size_t columns = std::size_t(s.index.metadata.nx) * std::size_t(s.index.metadata.ny);
    if (s.index.geolocation.raw_bytes != 2 * columns * sizeof(float)) {
      throw InputError(fmt::format("{}: geolocation chunk has {} bytes, expected {}", s.name(),
                                   s.index.geolocation.raw_bytes, 2 * columns * sizeof(float)));
    }
    const std::vector<std::byte> latlon = s.readBlock(s.index.geolocation, "geolocation chunk");
    geo::GridGeoreference& g = s.index.metadata.georef;
    g.lat_deg.resize(columns);
    g.lon_deg.resize(columns);
    std::memcpy(g.lat_deg.data(), latlon.data(), columns * sizeof(float));
    std::memcpy(g.lon_deg.data(), latlon.data() + columns * sizeof(float), columns * sizeof(float));
  }
  if (s.index.terrain.present()) {
    const std::size_t columns = std::size_t(s.index.metadata.nx) * std::size_t(s.index.metadata.ny);
    if (s.index.terrain.raw_bytes != columns * sizeof(float)) {
      throw InputError(fmt::format("{}: terrain chunk has {} bytes, expected {} ({} columns of float32)", s.name(),
                                   s.index.terrain.raw_bytes, columns * sizeof(float), columns));
    }
    const std::vector<std::byte> heights = s.readBlock(s.index.terrain, "terrain chunk");
    std::vector<float>& terrain = s.index.metadata.terrain_height_m;
    terrain.resize(columns);
    std::memcpy(terrain.data(), heights.data(), columns * sizeof(float));
  }
}

NphReader::~NphReader() = default;
NphReader::NphReader(NphReader&&) noexcept = default;
NphReader& NphReader::operator=(NphReader&&) noexcept = default;

const std::filesystem::path& NphReader::path() const { return state_->path; }
std::uint32_t NphReader::formatVersion() const { return state_->version; }
const NphMetadata& NphReader::metadata() const { return state_->index.metadata; }
int NphReader::nz() const { return state_->index.nz; }
std::size_t NphReader::timestepCount() const { return state_->index.timesteps.size(); }
std::uint64_t NphReader::fileBytes() const { return state_->file_bytes; }

const TimestepInfo& NphReader::timestep(std::size_t t) const {
  if (t >= timestepCount()) {
    throw UsageError(fmt::format("{}: timestep {} requested, the file has {}", state_->name(), t, timestepCount()));
  }
  return state_->index.timesteps[t];
}

QuantisedVolumes NphReader::readQuantised(std::size_t t) const {
  const State& s = *state_;
  const TimestepInfo& info = timestep(t);
  const NphMetadata& m = s.index.metadata;
  const std::vector<std::byte> raw =
      s.readBlock({info.chunk_offset, info.chunk_bytes, info.raw_bytes, info.chunk_xxh64},
                  fmt::format("chunk {} (timestep {})", t, geo::isoOrEmpty(info.time_utc)));
  QuantisedVolumes q;
  q.nx = m.nx;
  q.ny = m.ny;
  q.nz = s.index.nz;
  q.time_utc = info.time_utc;
  q.max_ice_per_m = info.max_ice_per_m;
  q.max_water_per_m = info.max_water_per_m;
  const std::size_t stored = std::size_t(m.nx) * std::size_t(m.ny) * std::size_t(info.nz);
  const std::size_t padded = std::size_t(m.nx) * std::size_t(m.ny) * std::size_t(q.nz);
  // decodeIndex bounded nx*ny*nz and matched raw_bytes to it; re-checked here at the copy so
  // that no index can make the memcpy below read past the decompressed block.
  if (raw.size() != 2 * stored * sizeof(std::uint16_t) || info.nz > q.nz) {
    throw InputError(fmt::format("{}: chunk {} holds {} bytes, expected {} for {}x{}x{} voxels", s.name(), t,
                                 raw.size(), 2 * stored * sizeof(std::uint16_t), m.nx, m.ny, info.nz));
  }
  q.ice_codes = hugePageVector<std::uint16_t>(padded);  // layers above nz_t stay 0 (cropped, empty)
  q.water_codes = hugePageVector<std::uint16_t>(padded);
  // A timestep cropped to nothing (nz_t = 0) stores no voxels: raw is empty and its data() may be
  // null, which memcpy must not get even for 0 bytes (UBSan, make test-sanitize).
  if (stored > 0) {
    std::memcpy(q.ice_codes.data(), raw.data(), stored * sizeof(std::uint16_t));
    std::memcpy(q.water_codes.data(), raw.data() + stored * sizeof(std::uint16_t), stored * sizeof(std::uint16_t));
  }
  return q;
}

ExtinctionVolumes NphReader::readHeader(std::size_t t) const {
  const State& s = *state_;
  const TimestepInfo& info = timestep(t);
  const NphMetadata& m = s.index.metadata;
  ExtinctionVolumes v;
  v.nx = m.nx;
  v.ny = m.ny;
  v.nz = s.index.nz;
  v.dz_m = m.dz_m;
  v.z_bottom_m = m.z_bottom_m;
  v.georef = m.georef;
  v.terrain_height_m = m.terrain_height_m;
  v.time_utc = info.time_utc;
  v.source_file = info.source_file;
  v.source_time_index = info.source_time_index;
  v.max_ice_per_m = info.max_ice_per_m;
  v.max_water_per_m = info.max_water_per_m;
  // The clock the detail noise is advected by (volume/detail.h), set as the model route's builder
  // sets it; it moves the noise only with a wind (read()), so windless files render as before.
  v.detail_clock_s = volume::detailClock_s(v.time_utc);
  return v;
}

namespace {
/// A timestep held as its codes (QuantisedVolumes), decoded a layer at a time with read()'s rule.
class NphSlices final : public ExtinctionSlices {
 public:
  NphSlices(ExtinctionVolumes header, QuantisedVolumes codes) : header_(std::move(header)), q_(std::move(codes)) {}
  const ExtinctionVolumes& volumes() const override { return header_; }
  Slice slice(int k, std::vector<float>& scratch) const override {
    const std::size_t layer = std::size_t(q_.nx) * std::size_t(q_.ny), base = std::size_t(k) * layer;
    scratch.resize(2 * layer);
    const std::span<float> ice(scratch.data(), layer), water(scratch.data() + layer, layer);
    dequantise(std::span(q_.ice_codes).subspan(base, layer), q_.max_ice_per_m, ice);
    dequantise(std::span(q_.water_codes).subspan(base, layer), q_.max_water_per_m, water);
    return {ice.data(), water.data()};
  }
  std::size_t heldBytes() const override {
    return (q_.ice_codes.size() + q_.water_codes.size()) * sizeof(std::uint16_t);
  }

 private:
  ExtinctionVolumes header_;
  QuantisedVolumes q_;
};
}  // namespace

std::unique_ptr<ExtinctionSlices> NphReader::readSlices(std::size_t t) const {
  ExtinctionVolumes header = readHeader(t);
  return std::make_unique<NphSlices>(std::move(header), readQuantised(t));
}

ExtinctionVolumes NphReader::read(std::size_t t) const {
  QuantisedVolumes q = readQuantised(t);
  ExtinctionVolumes v = readHeader(t);
  // Each phase's codes are freed once decoded: codes and floats of both phases never coexist.
  v.ice_per_m.resize(v.voxelCount());
  dequantise(q.ice_codes, q.max_ice_per_m, v.ice_per_m);
  std::vector<std::uint16_t>().swap(q.ice_codes);
  v.water_per_m.resize(v.voxelCount());
  dequantise(q.water_codes, q.max_water_per_m, v.water_per_m);
  std::vector<std::uint16_t>().swap(q.water_codes);
  const TimestepInfo& info = timestep(t);
  if (info.hasWind()) {
    const State& s = *state_;
    const std::vector<std::byte> raw =
        s.readBlock({info.wind_chunk_offset, info.wind_chunk_bytes, info.wind_raw_bytes, info.wind_chunk_xxh64},
                    fmt::format("wind chunk {} (timestep {})", t, geo::isoOrEmpty(info.time_utc)));
    const std::size_t layer = std::size_t(v.nx) * std::size_t(v.ny);
    const std::size_t stored = layer * std::size_t(info.nz);
    // decodeIndex matched wind_raw_bytes to nz_t; re-checked at the copy as readQuantised does.
    if (raw.size() != 2 * stored * sizeof(std::int16_t) || info.nz > v.nz) {
      throw InputError(fmt::format("{}: wind chunk {} holds {} bytes, expected {} for {}x{}x{} voxels", s.name(), t,
                                   raw.size(), 2 * stored * sizeof(std::int16_t), v.nx, v.ny, info.nz));
    }
    std::vector<std::int16_t> codes(2 * stored);
    unpackWindCodes(raw, std::size_t(v.nx), codes);
    // Padded like β: calm above nz_t (nph_cache.h).
    v.wind_u_m_per_s.assign(v.voxelCount(), 0.0f);
    v.wind_v_m_per_s.assign(v.voxelCount(), 0.0f);
    dequantiseWind(std::span(codes).first(stored), std::span(v.wind_u_m_per_s).first(stored));
    dequantiseWind(std::span(codes).subspan(stored), std::span(v.wind_v_m_per_s).first(stored));
  }
  return v;
}

}  // namespace nph::cache
