#pragma once
// A disk cache of reprojected basemaps (issue 19 item 3, "the reprojected basemap cached, keyed by
// image and projection"). Decoding Blue Marble's JPEG and warping it through GDAL onto the data's
// projection costs ≈ 0.8 CPU-s and a ≈ 500 MB transient per render (docs/benchmarks.md), and
// every process pays it again: each chunk of a render farm, each `nephele render` of the same
// storm from another camera, make demo's shots of one storm. The warp's result depends only on
// the source files, the output grid (world rectangle, pixels) and the world → lon/lat mapping, so
// it is stored once under a key made of exactly those, and read back bit for bit.
//
// Key (the whole string is stored in the entry and compared on reading; its 64-bit hash names the
// file): the entry format; the code that warps (path, size and modification time of the binary
// object holding this module: a rebuild invalidates every entry, so a change to the warp can never
// be served a stale picture); per source layer its canonical path, size and modification time;
// for map grids the projection's definition, the lon/lat offset and the lon/lat of three world
// points (the world → projected map is affine, so they pin it), the rectangle and the pixels.
// Layers not read from a regular file (images in memory) are never cached.
//
// Entries: <dir>/basemaps/<hash>.nbm: a header (magic, key, size, flags) and the floats in one
// zstd frame with its content checksum. Written under a temporary name and renamed (readers never
// see a partial entry; core/temp_files.h), touched on use; after each write the folder is trimmed
// to NEPHELE_CACHE_MAX_MB (default 2048) by dropping the least recently used. Anything unreadable
// — truncated, corrupt, another key — is a miss (logged at debug) and is rewritten.
//
// Folder: $NEPHELE_CACHE_DIR, else $XDG_CACHE_HOME/nephele, else $HOME/.cache/nephele.
// NEPHELE_CACHE_DIR=off turns the cache off. The tests run with a folder in the build tree
// (cmake/NepheleTesting.cmake).
#include <cstdint>
#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "scene/basemap.h"

namespace nph::scene {

/// The cache folder from the environment (see above); nullopt when the cache is off or no folder
/// can be named (no HOME).
std::optional<std::filesystem::path> basemapCacheDir();

/// The key of a warp onto a map grid (reprojectBasemap), or nullopt when a layer is not a file.
std::optional<std::string> basemapCacheKey(const std::vector<BasemapRaster>& layers, const SceneGeoreference& geo,
                                           const WorldRect& rect, int width, int height);
/// The key of a warp onto the whole Earth in lon/lat (reprojectEquirectangular), or nullopt.
std::optional<std::string> equirectangularCacheKey(const std::vector<BasemapRaster>& layers, int width, int height);

/// What the cache did, for tests and logs.
struct BasemapCacheStats {
  int hits = 0;
  int misses = 0;  ///< computed (and stored where a folder is set)
};
/// Counts of this process (all threads).
BasemapCacheStats basemapCacheStats();

/// The image under `key` from the cache folder, else `compute()` stored there. With no folder or
/// no key, `compute()` alone. A failure to store is logged and the computed image returned.
LinearRgbImage cachedBasemap(const std::optional<std::string>& key, const std::function<LinearRgbImage()>& compute);

/// The cached forms of reprojectBasemap and reprojectEquirectangular (same arguments, same bytes).
LinearRgbImage reprojectBasemapCached(const std::vector<BasemapRaster>& layers, const SceneGeoreference& geo,
                                      const WorldRect& rect, int width, int height);
LinearRgbImage reprojectEquirectangularCached(const std::vector<BasemapRaster>& layers, int width, int height);

}  // namespace nph::scene
