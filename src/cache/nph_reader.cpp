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

  void checkInside(const ChunkRef& c, const std::string& what) const {
    if (c.offset < kHeaderBytes || c.offset + c.bytes > file_bytes || c.bytes > file_bytes) {
      throw InputError(fmt::format("{}: {} lies outside the file (offset {}, {} bytes, file {} bytes)", name(), what,
                                   c.offset, c.bytes, file_bytes));
    }
  }
  void checkSum(std::uint64_t sum, const ChunkRef& c, const std::string& what) const {
    if (sum != c.xxh64) {
      throw InputError(
          fmt::format("{}: {} is corrupt: XXH64 {} , expected {}", name(), what, toHex(sum), toHex(c.xxh64)));
    }
  }
  /// The zstd frame states its decompressed size (in its header, at the block's start): compared
  /// before allocating raw_bytes, so a small file cannot make the reader allocate what its index claims.
  void checkFrameSize(std::span<const std::byte> start, const ChunkRef& c, const std::string& what) const {
    const unsigned long long frame_bytes = ZSTD_getFrameContentSize(start.data(), start.size());
    if (frame_bytes != c.raw_bytes) {
      throw InputError(fmt::format("{}: {} decompresses to {} bytes, the index says {}", name(), what,
                                   frame_bytes == ZSTD_CONTENTSIZE_UNKNOWN || frame_bytes == ZSTD_CONTENTSIZE_ERROR
                                       ? std::string("an unknown number of")
                                       : std::to_string(frame_bytes),
                                   c.raw_bytes));
    }
  }

  /// Checks that block `c` lies inside the file, that its compressed bytes, read a piece at a
  /// time, have the index's XXH64 and that its zstd frame states the index's decompressed size:
  /// readBlock's checks without holding the block (readSlices decodes it as a stream).
  void verifyBlock(const ChunkRef& c, const std::string& what) const {
    checkInside(c, what);
    std::vector<std::byte> piece(std::size_t(std::min<std::uint64_t>(c.bytes, 1u << 20)));
    Xxh64Stream hash;
    for (std::uint64_t at = 0; at < c.bytes;) {
      const std::size_t n = std::size_t(std::min<std::uint64_t>(piece.size(), c.bytes - at));
      if (!readAt(fd, piece.data(), n, c.offset + at)) {
        throw InputError(
            fmt::format("{}: {} is truncated (expected {} bytes at offset {})", name(), what, c.bytes, c.offset));
      }
      if (at == 0) checkFrameSize(std::span<const std::byte>(piece.data(), n), c, what);
      hash.update(std::span<const std::byte>(piece.data(), n));
      at += n;
    }
    checkSum(hash.digest(), c, what);
  }

  /// Reads, checksums and decompresses one block. `what` names it in errors.
  std::vector<std::byte> readBlock(const ChunkRef& c, const std::string& what) const {
    checkInside(c, what);
    std::vector<std::byte> packed = hugePageVector<std::byte>(c.bytes);
    if (!readAt(fd, packed.data(), packed.size(), c.offset)) {
      throw InputError(
          fmt::format("{}: {} is truncated (expected {} bytes at offset {})", name(), what, c.bytes, c.offset));
    }
    checkSum(xxh64(packed), c, what);
    checkFrameSize(packed, c, what);
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
/// One chunk's zstd frame decoded front to back while its compressed bytes are read from the file
/// a piece at a time (issue 19, memory): it holds zstd's window (2 MiB at the writer's level 3)
/// and one input piece (ZSTD_DStreamInSize, 128 KiB), never the chunk. readBlock's checks, spread
/// over the read: decompression errors as they come; the content's length, zstd's own content
/// checksum and the chunk's XXH64 when the frame ends (finish()). Not thread-safe.
class ChunkStream {
 public:
  ChunkStream(int fd, std::string file, const ChunkRef& chunk, std::string what)
      : fd_(fd), file_(std::move(file)), c_(chunk), what_(std::move(what)), in_(ZSTD_DStreamInSize()) {
    if (!ds_) throw std::bad_alloc();
    rewind();
  }
  /// Back to the frame's first byte.
  void rewind() {
    ZSTD_DCtx_reset(ds_.get(), ZSTD_reset_session_only);
    read_ = produced_ = 0;
    ended_ = false;
    in_buf_ = {in_.data(), 0, 0};
    hash_.reset();
  }
  /// The frame's next `bytes` of content into `into`, or decoded and dropped where `into` is null.
  void read(std::byte* into, std::size_t bytes) {
    std::size_t done = 0;
    while (done < bytes) {
      if (in_buf_.pos == in_buf_.size) fill();
      std::byte* dst = into ? into + done : discard_.data();
      ZSTD_outBuffer out{dst, into ? bytes - done : std::min(bytes - done, discard_.size()), 0};
      const std::size_t r = ZSTD_decompressStream(ds_.get(), &out, &in_buf_);
      if (ZSTD_isError(r)) fail(fmt::format("does not decompress: {}", ZSTD_getErrorName(r)));
      done += out.pos;
      produced_ += out.pos;
      ended_ = r == 0;  // the frame decoded, its checksum checked, all flushed
      const bool stuck = out.pos == 0 && in_buf_.pos == in_buf_.size && read_ == c_.bytes;
      if ((r == 0 && done < bytes) || stuck)
        fail(fmt::format("does not decompress to {} bytes: it ends after {}", c_.raw_bytes, produced_));
    }
  }
  /// Reads the frame to its end and verifies it: its content ends at raw_bytes, zstd's content
  /// checksum holds (ZSTD_decompressStream checks it as the frame ends), no byte follows the frame
  /// in the chunk, and the compressed bytes' XXH64 is the index's.
  void finish() {
    if (produced_ != c_.raw_bytes) read(nullptr, c_.raw_bytes - produced_);
    while (!ended_) {
      std::byte extra{};
      ZSTD_outBuffer out{&extra, 1, 0};
      if (in_buf_.pos == in_buf_.size && read_ < c_.bytes) fill();
      const std::size_t r = ZSTD_decompressStream(ds_.get(), &out, &in_buf_);
      if (ZSTD_isError(r)) fail(fmt::format("does not decompress: {}", ZSTD_getErrorName(r)));
      if (out.pos > 0) fail(fmt::format("decompresses to more than {} bytes", c_.raw_bytes));
      ended_ = r == 0;
      if (ended_) break;
      if (in_buf_.pos == in_buf_.size && read_ == c_.bytes)
        fail(fmt::format("is truncated: its zstd frame does not end within its {} bytes", c_.bytes));
    }
    if (in_buf_.pos != in_buf_.size || read_ != c_.bytes)
      fail(fmt::format("holds bytes after its zstd frame (the index says {} bytes)", c_.bytes));
    const std::uint64_t sum = hash_.digest();
    if (sum != c_.xxh64) fail(fmt::format("is corrupt: XXH64 {} , expected {}", toHex(sum), toHex(c_.xxh64)));
  }
  std::size_t heldBytes() const { return ZSTD_sizeof_DStream(ds_.get()) + in_.size() + discard_.size(); }

 private:
  void fill() {
    const std::size_t n = std::size_t(std::min<std::uint64_t>(in_.size(), c_.bytes - read_));
    if (n == 0) return;
    if (!readAt(fd_, in_.data(), n, c_.offset + read_))
      fail(fmt::format("is truncated (expected {} bytes at offset {})", c_.bytes, c_.offset));
    hash_.update(std::span<const std::byte>(in_.data(), n));
    read_ += n;
    in_buf_ = {in_.data(), n, 0};
  }
  [[noreturn]] void fail(const std::string& why) const {
    throw InputError(fmt::format("{}: {} {}", file_, what_, why));
  }

  int fd_;
  std::string file_;
  ChunkRef c_;
  std::string what_;
  std::unique_ptr<ZSTD_DStream, decltype(&ZSTD_freeDStream)> ds_{ZSTD_createDStream(), ZSTD_freeDStream};
  std::vector<std::byte> in_;
  std::vector<std::byte> discard_ = std::vector<std::byte>(64 * 1024);
  ZSTD_inBuffer in_buf_{};
  std::uint64_t read_ = 0;      // compressed bytes read from the file
  std::uint64_t produced_ = 0;  // content bytes decoded
  bool ended_ = false;          // ZSTD_decompressStream returned 0: the frame is complete
  Xxh64Stream hash_;
};

/// A timestep decoded a layer at a time straight from its chunk in the file (issue 19, memory):
/// two streams over the one zstd frame, one at the ice codes' layer k and one at the water codes'
/// (which starts by decoding and dropping the ice codes), so no code of the timestep is held
/// beyond the layer being read, and every layer decodes with read()'s rule (dequantise) to
/// read()'s floats bit for bit. Layers read in increasing k cost one decode of the frame (1.5 with
/// the skip); a lower k than the last one rewinds both streams. The chunk is verified when its
/// last stored layer is read (ChunkStream::finish) and, by its XXH64, when the source is made.
/// Owns a duplicate of the reader's descriptor, so it outlives the reader.
class NphSlices final : public ExtinctionSlices {
 public:
  NphSlices(ExtinctionVolumes header, int fd, const std::string& file, const ChunkRef& chunk, const std::string& what,
            int stored_nz, float max_ice_per_m, float max_water_per_m)
      : header_(std::move(header)),
        fd_(fd),
        layer_(std::size_t(header_.nx) * std::size_t(header_.ny)),
        stored_nz_(stored_nz),
        max_ice_(max_ice_per_m),
        max_water_(max_water_per_m),
        ice_(fd, file, chunk, what),
        water_(fd, file, chunk, what),
        codes_(2 * layer_) {}
  ~NphSlices() override { ::close(fd_); }
  NphSlices(const NphSlices&) = delete;
  NphSlices& operator=(const NphSlices&) = delete;

  const ExtinctionVolumes& volumes() const override { return header_; }
  Slice slice(int k, std::vector<float>& scratch) const override {
    if (k < 0 || k >= header_.nz)
      throw UsageError(fmt::format("NphSlices::slice: layer {} asked for, the grid has {}", k, header_.nz));
    scratch.resize(2 * layer_);
    const std::span<float> ice(scratch.data(), layer_), water(scratch.data() + layer_, layer_);
    if (k >= stored_nz_) {  // padding above the timestep's cropped top: code 0, β 0 (read() pads so)
      std::fill(scratch.begin(), scratch.end(), 0.0f);
      return {ice.data(), water.data()};
    }
    const std::size_t layerBytes = layer_ * sizeof(std::uint16_t);
    if (k < next_ || next_ < 0) {  // from the frame's start; the water stream past the ice codes
      ice_.rewind();
      water_.rewind();
      water_.read(nullptr, std::size_t(stored_nz_) * layerBytes);
      next_ = 0;
    }
    for (; next_ < k; ++next_) {
      ice_.read(nullptr, layerBytes);
      water_.read(nullptr, layerBytes);
    }
    const std::span<std::uint16_t> iceCodes(codes_.data(), layer_), waterCodes(codes_.data() + layer_, layer_);
    ice_.read(reinterpret_cast<std::byte*>(iceCodes.data()), layerBytes);
    water_.read(reinterpret_cast<std::byte*>(waterCodes.data()), layerBytes);
    if (++next_ == stored_nz_) water_.finish();  // the whole frame read: verified
    dequantise(iceCodes, max_ice_, ice);
    dequantise(waterCodes, max_water_, water);
    return {ice.data(), water.data()};
  }
  std::size_t heldBytes() const override {
    return ice_.heldBytes() + water_.heldBytes() + codes_.size() * sizeof(std::uint16_t);
  }

 private:
  ExtinctionVolumes header_;
  int fd_;
  std::size_t layer_;
  int stored_nz_;
  float max_ice_, max_water_;
  mutable ChunkStream ice_, water_;
  mutable std::vector<std::uint16_t> codes_;
  mutable int next_ = -1;  // the next layer the streams stand at; −1: not positioned
};
}  // namespace

std::unique_ptr<ExtinctionSlices> NphReader::readSlices(std::size_t t) const {
  const State& s = *state_;
  const TimestepInfo& info = timestep(t);
  ExtinctionVolumes header = readHeader(t);
  const ChunkRef chunk{info.chunk_offset, info.chunk_bytes, info.raw_bytes, info.chunk_xxh64};
  const std::string what = fmt::format("chunk {} (timestep {})", t, geo::isoOrEmpty(info.time_utc));
  s.verifyBlock(chunk, what);
  const std::size_t stored = std::size_t(header.nx) * std::size_t(header.ny) * std::size_t(info.nz);
  if (info.raw_bytes != 2 * stored * sizeof(std::uint16_t) || info.nz > header.nz) {  // as readQuantised
    throw InputError(fmt::format("{}: chunk {} holds {} bytes, expected {} for {}x{}x{} voxels", s.name(), t,
                                 info.raw_bytes, 2 * stored * sizeof(std::uint16_t), header.nx, header.ny, info.nz));
  }
  const int fd = ::fcntl(s.fd, F_DUPFD_CLOEXEC, 0);
  if (fd < 0) throw IoError(fmt::format("{}: cannot duplicate its descriptor: {}", s.name(), errnoText()));
  try {
    return std::make_unique<NphSlices>(std::move(header), fd, s.name(), chunk, what, info.nz, info.max_ice_per_m,
                                       info.max_water_per_m);
  } catch (...) {
    ::close(fd);
    throw;
  }
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
