// Hostile .nph files with VALID checksums (issue #18): the checksums catch every random mutation,
// so these are written by NphWriter and then given a crafted index, re-checksummed exactly as the
// writer does. The reader must refuse them with an InputError naming the file and the field.
#include <sys/stat.h>

#include <cstring>
#include <fstream>
#include <functional>
#include <string>
#include <vector>

#include "cache/checksum.h"
#include "cache/nph_cache.h"
#include "cache/nph_format.h"
#include "core/error.h"
#include "reliability_support.h"

namespace nph::reliability {
namespace {

using cache::kHeaderBytes;

std::vector<std::byte> readAll(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::vector<char> bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  std::vector<std::byte> out(bytes.size());
  std::memcpy(out.data(), bytes.data(), bytes.size());
  return out;
}

/// A valid one-timestep .nph (8 x 6 x 4 voxels of clear air) written by NphWriter.
std::string writeValidNph(const Scratch& dir) {
  const std::string path = dir.file("valid.nph");
  const ExtinctionVolumes v = ExtinctionVolumes::zeros(8, 6, 4, 1000.0, 250.0, 0.0);
  cache::NphWriter w(path, nphMetadataOf(v));
  w.append(v);
  w.commit();
  return path;
}

/// Replaces the index text of `path` by edit(text) and rewrites the header fields that depend on
/// it (index size, its XXH64, file size, header XXH64), as NphWriter::commit does.
void rewriteIndex(const std::string& path, const std::function<std::string(std::string)>& edit) {
  std::vector<std::byte> bytes = readAll(path);
  const auto index_offset = cache::detail::get<std::uint64_t>(bytes.data() + 16);
  const auto index_bytes = cache::detail::get<std::uint64_t>(bytes.data() + 24);
  std::string text(reinterpret_cast<const char*>(bytes.data() + index_offset), index_bytes);
  text = edit(text);
  bytes.resize(index_offset);
  const auto* t = reinterpret_cast<const std::byte*>(text.data());
  bytes.insert(bytes.end(), t, t + text.size());
  cache::detail::put<std::uint64_t>(bytes.data() + 24, text.size());
  cache::detail::put<std::uint64_t>(bytes.data() + 32, cache::xxh64(std::span(t, text.size())));
  cache::detail::put<std::uint64_t>(bytes.data() + 40, bytes.size());
  cache::detail::put<std::uint64_t>(bytes.data() + cache::detail::kHeaderChecksumOffset,
                                    cache::xxh64(std::span(bytes.data(), cache::detail::kHeaderChecksumOffset)));
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out.write(reinterpret_cast<const char*>(bytes.data()), std::streamsize(bytes.size()));
}

/// `text` with the first occurrence of `from` replaced by `to` (the test fails when absent).
std::string replaced(std::string text, const std::string& from, const std::string& to) {
  const auto at = text.find(from);
  EXPECT_NE(at, std::string::npos) << from << " not in the index: " << text;
  if (at != std::string::npos) text.replace(at, from.size(), to);
  return text;
}

TEST(HostileNph, UntouchedRewriteStillReads) {
  // The rewrite itself must produce a valid file, or the refusals below would prove nothing.
  const Scratch dir;
  const std::string path = writeValidNph(dir);
  rewriteIndex(path, [](std::string s) { return s; });
  const cache::NphReader r(path);
  EXPECT_EQ(r.read(0).voxelCount(), 8u * 6u * 4u);
}

TEST(HostileNph, GridOf2To30SquaredIsRefusedBeforeAnySizeWraps) {
  // nx = ny = 2^30 with nz = 4: 2 x 2 bytes x 2^62 wraps to 0 in 64 bits, which matched a chunk of
  // 0 raw bytes, and readQuantised copied from a wild address.
  const Scratch dir;
  const std::string path = writeValidNph(dir);
  rewriteIndex(path, [](std::string s) {
    s = replaced(s, "\"nx\": 8", "\"nx\": 1073741824");
    s = replaced(s, "\"ny\": 6", "\"ny\": 1073741824");
    return s;
  });
  saveFuzzInput(path, "nph");
  expectError<InputError>([&] { (void)cache::NphReader(path); },
                          {path, "grid nx x ny x nz", "1073741824 x 1073741824 x 4", "exceeds the limit"});
}

TEST(HostileNph, IndexNested100000DeepIsRefusedWithoutStackOverflow) {
  const Scratch dir;
  const std::string path = writeValidNph(dir);
  const std::string deep = std::string(100000, '[') + std::string(100000, ']');
  rewriteIndex(path, [&](std::string s) { return replaced(s, "\"optics\": {}", "\"optics\": " + deep); });
  saveFuzzInput(path, "nph");
  expectError<InputError>([&] { (void)cache::NphReader(path); },
                          {path, "the .nph index", "nests deeper than 64 levels"});
}

TEST(HostileNph, DuplicateKeyInTheIndexIsRefused) {
  const Scratch dir;
  const std::string path = writeValidNph(dir);
  rewriteIndex(path, [](std::string s) { return replaced(s, "\"nx\": 8", "\"nx\": 8, \"nx\": 9"); });
  saveFuzzInput(path, "nph");
  expectError<InputError>([&] { (void)cache::NphReader(path); }, {path, "key \"nx\" appears twice"});
}

TEST(HostileNph, AbsurdBottomHeightIsRefused) {
  // z_bottom_m = 1e308 overflowed the float -> int conversions of the ray caster.
  const Scratch dir;
  const std::string path = writeValidNph(dir);
  rewriteIndex(path, [](std::string s) { return replaced(s, "\"z_bottom_m\": 0.0", "\"z_bottom_m\": 1e308"); });
  saveFuzzInput(path, "nph");
  expectError<InputError>([&] { (void)cache::NphReader(path); }, {path, "z_bottom_m", "expected heights within"});
}

TEST(HostileNph, ChunkClaimingMoreBytesThanItsFrameHoldsIsRefusedBeforeAllocating) {
  // raw_bytes consistent with a larger nz, but the zstd frame says what it really holds.
  const Scratch dir;
  const std::string path = writeValidNph(dir);
  rewriteIndex(path, [](std::string s) {
    s = replaced(s, "\"nz\": 4,", "\"nz\": 40,");                     // the grid
    s = replaced(s, "\"nz\": 4,", "\"nz\": 40,");                     // the timestep
    return replaced(s, "\"raw_bytes\": 768", "\"raw_bytes\": 7680");  // 2 x 2 bytes x 8 x 6 x 40
  });
  const cache::NphReader r(path);
  saveFuzzInput(path, "nph");
  expectError<InputError>([&] { (void)r.read(0); }, {path, "decompresses to 768 bytes, the index says 7680"});
}

TEST(HostileNph, NonUtf8InputNameDoesNotFailTheConversionAtCommit) {
  // A Latin-1 file name made the index dump throw "invalid UTF-8 byte" naming no file, after the
  // whole conversion had run.
  const Scratch dir;
  ExtinctionVolumes v = ExtinctionVolumes::zeros(4, 4, 2, 1000.0, 250.0, 0.0);
  v.source_file = "wrfout_M\xfcnchen.nc";
  cache::NphWriter w(dir.file("latin1.nph"), nphMetadataOf(v));
  w.append(v);
  w.commit();
  EXPECT_EQ(cache::NphReader(dir.file("latin1.nph")).timestep(0).source_file, "wrfout_M\xef\xbf\xbdnchen.nc");
}

TEST(HostileNph, FifoIsRefusedAndSniffDoesNotBlock) {
  const Scratch dir;
  const std::string fifo = dir.file("pipe.nph");
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  EXPECT_FALSE(cache::NphReader::sniff(fifo));
  expectError<InputError>([&] { (void)cache::NphReader(fifo); }, {fifo, "is a FIFO", "expected a .nph cache file"});
}

}  // namespace
}  // namespace nph::reliability
