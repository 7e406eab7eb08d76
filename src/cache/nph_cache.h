#pragma once
// The `.nph` extinction cache: all timesteps of one conversion (Nes 2008 §5.6 "pre-calculated
// extinction volumes", stored as scaled 16-bit values, Nes §5.1.2) in one versioned,
// checksummed file that is read lazily, one timestep at a time.
//
// File layout, version 1 (all integers little-endian):
//   [0, 64)   header
//               0  char[8]  magic "NPHCACHE"
//               8  u32      format version (1)
//              12  u32      header size in bytes (64)
//              16  u64      index offset        24  u64  index size in bytes
//              32  u64      XXH64 of the index  40  u64  total file size in bytes
//              48  u64      reserved (0)        56  u64  XXH64 of header bytes [0, 56)
//   chunks    one zstd frame per timestep: uint16 ice codes (nx*ny*nz_t), then uint16 water
//             codes, x fastest (quantize.h); optionally one zstd frame of float32 lat then lon
//             (the geolocation of mass points); optionally one zstd frame of float32 terrain
//             height above MSL [m] at the mass points (x fastest; issue 14), static in time;
//             optionally, after a timestep's chunk, its wind chunk: one zstd frame of int16 U
//             codes (nx*ny*nz_t), then int16 V codes, x fastest, 0.01 m/s per code (quantize.h
//             quantiseWind), differenced along x, zigzag coded and split in byte planes
//             (quantize.h packWindCodes): the horizontal wind the motion blend moves the timestep
//             along (engine::blendVolumes, TimeBlend::Motion; docs/animation.md)
//   index     UTF-8 JSON: grid, georeference, optics settings used, inputs, quantisation, and
//             per timestep: time, provenance, nz_t, maxima (the decoding scales) and the chunk's
//             offset, sizes and XXH64 (checksum.h) of the compressed bytes, and the same for
//             its wind chunk under the key "wind" (absent or null: no wind).
// Files written before issue 14 have no "terrain" key in the index's grid: they read as sea level
// (an empty ExtinctionVolumes::terrain_height_m), as does a file whose model had no terrain.
// Files written before the wind chunk (issue 13 follow-up) have no "wind" key: they read without
// U, V (the motion blend falls back to the cross-fade), as before. The version stays 1: readers
// before it look up the index's keys by name and ignore "wind", so they read such files as
// windless files, correctly.
// Each timestep is cropped to its own nz_t (just above its highest condensate); the reader pads
// every timestep to the file's nz (the largest nz_t) with zeros, so all volumes share one grid
// (the wind too: calm air above nz_t, where there is no condensate to move).
//
// Writing goes to a temporary file next to the target that is renamed over the target only by
// commit(); a writer destroyed without commit() (an exception, a failed conversion) removes the
// temporary file, so no partial .nph file is ever left behind.
#include <cstdint>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "volume/extinction_slices.h"
#include "volume/extinction_volumes.h"

namespace nph::cache {

inline constexpr std::uint32_t kFormatVersion = 1;
inline constexpr std::size_t kHeaderBytes = 64;

/// What a .nph file holds besides the volumes.
struct NphMetadata {
  int nx = 0, ny = 0;
  double dz_m = 0.0;
  double z_bottom_m = 0.0;
  geo::GridGeoreference georef;
  std::vector<float> terrain_height_m;  ///< nx*ny surface heights [m]; empty = sea level (no chunk)
  std::string optics_json = "{}";       ///< optics settings used (a JSON object, written by physics/)
  std::vector<std::string> inputs;      ///< input files
  std::string created_by;               ///< e.g. "nephele 0.1.0"
};

/// Per-timestep entry of the index.
struct TimestepInfo {
  geo::OptionalUtcTime time_utc;  ///< stored in the index as ISO 8601, "" for none
  std::string source_file;
  std::int64_t source_time_index = 0;
  int nz = 0;  ///< stored (cropped) layer count of this timestep
  float max_ice_per_m = 0.0f;
  float max_water_per_m = 0.0f;
  std::uint64_t chunk_offset = 0;
  std::uint64_t chunk_bytes = 0;  ///< compressed
  std::uint64_t raw_bytes = 0;    ///< decompressed
  std::uint64_t chunk_xxh64 = 0;
  /// The wind chunk (U, V codes, quantize.h quantiseWind); wind_chunk_bytes 0: no wind stored.
  std::uint64_t wind_chunk_offset = 0;
  std::uint64_t wind_chunk_bytes = 0;  ///< compressed
  std::uint64_t wind_raw_bytes = 0;    ///< decompressed: 2 * 2 bytes * nx * ny * nz
  std::uint64_t wind_chunk_xxh64 = 0;
  bool hasWind() const { return wind_chunk_bytes > 0; }
};

struct WriterOptions {
  int zstd_level = 3;    ///< 1 (fast) .. 19 (small); 3 is zstd's default
  int zstd_workers = 0;  ///< zstd worker threads (0: compress in the calling thread)
};

/// One timestep as stored: 16-bit codes, value_per_m = code * max_per_m / 65535 (quantize.h).
/// Uploadable as-is into a GL_R16 texture, whose normalised fetch times max_per_m is β
/// (Nes 2008 §5.1.2), at half the memory of floats.
struct QuantisedVolumes {
  int nx = 0, ny = 0, nz = 0;  ///< nz: the file's nz (padded with code 0)
  geo::OptionalUtcTime time_utc;
  std::vector<std::uint16_t> ice_codes;  ///< x fastest, as ExtinctionVolumes
  std::vector<std::uint16_t> water_codes;
  float max_ice_per_m = 0.0f;
  float max_water_per_m = 0.0f;
};

class NphWriter {
 public:
  /// Creates the temporary file next to `path`. Throws IoError when it cannot.
  NphWriter(std::filesystem::path path, NphMetadata metadata, WriterOptions options = {});
  ~NphWriter();  ///< removes the temporary file unless commit() succeeded
  NphWriter(const NphWriter&) = delete;
  NphWriter& operator=(const NphWriter&) = delete;

  /// Quantises, compresses and writes one timestep. Its nx, ny, dz_m and z_bottom_m must match
  /// the metadata (UsageError otherwise); values must be finite and non-negative (InputError).
  /// U, V (wind_u_m_per_s, wind_v_m_per_s) are stored when both are there (one value per voxel;
  /// UsageError for another non-zero count), a non-finite wind as calm (logged).
  void append(const ExtinctionVolumes& volumes);
  /// Writes the index and header, flushes, and renames the temporary file to `path`.
  void commit();

  std::size_t timestepCount() const;
  std::uint64_t bytesWritten() const;
  const std::filesystem::path& temporaryPath() const;

 private:
  struct State;
  std::unique_ptr<State> state_;
};

class NphReader {
 public:
  /// Opens `path` and reads header and index (not the volumes). InputError names the file and
  /// what is wrong (not a .nph file, unsupported version, truncated, checksum mismatch, ...).
  explicit NphReader(std::filesystem::path path);
  ~NphReader();
  NphReader(NphReader&&) noexcept;
  NphReader& operator=(NphReader&&) noexcept;

  /// true when the file starts with the .nph magic (cheap; no validation).
  static bool sniff(const std::filesystem::path& path);

  const std::filesystem::path& path() const;
  std::uint32_t formatVersion() const;
  const NphMetadata& metadata() const;
  int nz() const;  ///< the file's layer count (largest timestep nz)
  std::size_t timestepCount() const;
  const TimestepInfo& timestep(std::size_t t) const;
  std::uint64_t fileBytes() const;

  /// Reads, verifies and decodes timestep t, padded to nz() layers, with its U, V where the file
  /// stores them (the timestep's wind chunk, read and checked as its chunk). Thread-safe (pread).
  /// InputError names the file and the chunk on truncation, checksum or decompression errors.
  ExtinctionVolumes read(std::size_t t) const;
  /// The same timestep without decoding (see QuantisedVolumes); same checks as read().
  QuantisedVolumes readQuantised(std::size_t t) const;
  /// Timestep t decoded one layer at a time straight from the file (volume/extinction_slices.h;
  /// issue 19, memory): its chunk's zstd frame is decompressed as a stream while it is read, so
  /// the source holds zstd's window and one layer's codes, not the timestep (read() holds 8 bytes
  /// per voxel, its codes 4); every layer decodes to read()'s floats bit for bit (dequantise).
  /// Layers read upwards cost one decode of the chunk per pass; going down rewinds it. The chunk
  /// is checked here as read() checks it (bounds, XXH64 of its bytes, stated size) and again by
  /// each pass that reaches its last layer (a file changed since: InputError). The source owns a
  /// duplicate of the reader's descriptor and may outlive the reader; not thread-safe.
  std::unique_ptr<ExtinctionSlices> readSlices(std::size_t t) const;
  /// Timestep t as read() returns it without its volumes (ice_per_m, water_per_m empty): grid,
  /// georeference, terrain, time, provenance and maxima. Reads no chunk, so no wind either; nor
  /// does readSlices() (the wind's floats would be 8 bytes per voxel): its one-shot
  /// frames blend nothing, but their detail noise (volume/detail.h) stays world-fixed where read()'s
  /// is advected by the stored wind.
  ExtinctionVolumes readHeader(std::size_t t) const;

 private:
  struct State;
  std::unique_ptr<State> state_;
};

}  // namespace nph::cache
