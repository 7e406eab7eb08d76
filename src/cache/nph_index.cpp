#include "cache/nph_index.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <stdexcept>

#include <fmt/format.h>
#include "cache/checksum.h"

#include "core/error.h"
#include "core/json_limits.h"
#include "core/limits.h"

namespace nph::cache {

namespace {

using nlohmann::json;

/// Heights an index may declare: +-1000 km (the atmosphere nephele renders ends near 100 km).
/// z_bottom_m = +-1e308 overflowed the float -> int conversions of the ray caster.
constexpr double kMaxAbsHeight_m = 1.0e6;

json chunkJson(const ChunkRef& c) {
  return {{"offset", c.offset}, {"bytes", c.bytes}, {"raw_bytes", c.raw_bytes}, {"xxh64", toHex(c.xxh64)}};
}

ChunkRef chunkFromJson(const json& j) {
  ChunkRef c;
  c.offset = j.at("offset").get<std::uint64_t>();
  c.bytes = j.at("bytes").get<std::uint64_t>();
  c.raw_bytes = j.at("raw_bytes").get<std::uint64_t>();
  const std::string hex = j.at("xxh64").get<std::string>();
  const auto [end, ec] = std::from_chars(hex.data(), hex.data() + hex.size(), c.xxh64, 16);
  if (ec != std::errc() || end != hex.data() + hex.size() || hex.size() != 16) {
    throw std::invalid_argument("chunk xxh64 is not 16 hex digits: \"" + hex + "\"");
  }
  return c;
}

}  // namespace

json encodeIndex(const NphMetadata& m, const std::vector<TimestepInfo>& timesteps, const ChunkRef& geolocation,
                 const ChunkRef& terrain) {
  int nz = 0;
  for (const auto& t : timesteps) nz = std::max(nz, t.nz);
  json optics = json::parse(m.optics_json, nullptr, /*allow_exceptions=*/false);
  if (optics.is_discarded()) optics = m.optics_json;  // keep unparsable text verbatim
  json j;
  j["format"] = "nephele extinction cache";
  j["version"] = kFormatVersion;
  j["created_by"] = m.created_by;
  j["grid"] = {{"nx", m.nx},
               {"ny", m.ny},
               {"nz", nz},
               {"dz_m", m.dz_m},
               {"z_bottom_m", m.z_bottom_m},
               {"terrain", terrain.present() ? chunkJson(terrain) : json()},
               {"layout", "x fastest, then y, then z; voxel k centred at z_bottom_m+(k+0.5)*dz_m"}};
  j["georeference"] = {{"proj_definition", m.georef.proj_definition},
                       {"dx", m.georef.dx_m},
                       {"dy", m.georef.dy_m},
                       {"x0", m.georef.x0},
                       {"y0", m.georef.y0},
                       {"geographic", m.georef.geographic},
                       {"geolocation", geolocation.present() ? chunkJson(geolocation) : json()}};
  j["quantisation"] = {{"kind", "linear-uint16"},
                       {"decode", "value_per_m = code * max_per_m / 65535"},
                       {"max_abs_error", "max_per_m / 131070 + max_per_m * 2^-24"}};
  bool any_wind = false;
  for (const auto& t : timesteps) any_wind = any_wind || t.hasWind();
  if (any_wind) {
    j["quantisation"]["wind"] = {{"kind", "linear-int16, x-differenced, zigzag, byte planes"},
                                 {"decode", "u_m_per_s = code * 0.01"},
                                 {"max_abs_error", "0.005 m/s + 2^-24 relative, |u| <= 327.67 m/s (clamped)"}};
  }
  j["optics"] = std::move(optics);
  j["inputs"] = m.inputs;
  json steps = json::array();
  for (const auto& t : timesteps) {
    json step = {{"time_utc", geo::isoOrEmpty(t.time_utc)},
                 {"source_file", t.source_file},
                 {"source_time_index", t.source_time_index},
                 {"nz", t.nz},
                 {"max_ice_per_m", t.max_ice_per_m},
                 {"max_water_per_m", t.max_water_per_m},
                 {"chunk", chunkJson({t.chunk_offset, t.chunk_bytes, t.raw_bytes, t.chunk_xxh64})}};
    // Only where stored: a windless file's index is byte for byte what it was before the key.
    if (t.hasWind()) {
      step["wind"] = chunkJson({t.wind_chunk_offset, t.wind_chunk_bytes, t.wind_raw_bytes, t.wind_chunk_xxh64});
    }
    steps.push_back(std::move(step));
  }
  j["timesteps"] = std::move(steps);
  return j;
}

DecodedIndex decodeIndex(const std::string& file, const std::string& text) {
  DecodedIndex d;
  try {
    const json j = json_limits::parse(text, file, "the .nph index");
    NphMetadata& m = d.metadata;
    m.created_by = j.at("created_by").get<std::string>();
    const json& g = j.at("grid");
    m.nx = g.at("nx").get<int>();
    m.ny = g.at("ny").get<int>();
    d.nz = g.at("nz").get<int>();
    m.dz_m = g.at("dz_m").get<double>();
    m.z_bottom_m = g.at("z_bottom_m").get<double>();
    // Optional: files before issue 14 have no terrain (sea level).
    if (g.contains("terrain") && !g.at("terrain").is_null()) d.terrain = chunkFromJson(g.at("terrain"));
    const json& geo = j.at("georeference");
    m.georef.proj_definition = geo.at("proj_definition").get<std::string>();
    m.georef.dx_m = geo.at("dx").get<double>();
    m.georef.dy_m = geo.at("dy").get<double>();
    m.georef.x0 = geo.at("x0").get<double>();
    m.georef.y0 = geo.at("y0").get<double>();
    m.georef.geographic = geo.at("geographic").get<bool>();
    if (!geo.at("geolocation").is_null()) d.geolocation = chunkFromJson(geo.at("geolocation"));
    m.optics_json = j.at("optics").dump();
    m.inputs = j.at("inputs").get<std::vector<std::string>>();
    for (const json& s : j.at("timesteps")) {
      TimestepInfo t;
      t.time_utc = geo::parseOptional(s.at("time_utc").get<std::string>());
      t.source_file = s.at("source_file").get<std::string>();
      t.source_time_index = s.at("source_time_index").get<std::int64_t>();
      t.nz = s.at("nz").get<int>();
      t.max_ice_per_m = s.at("max_ice_per_m").get<float>();
      t.max_water_per_m = s.at("max_water_per_m").get<float>();
      const ChunkRef c = chunkFromJson(s.at("chunk"));
      t.chunk_offset = c.offset;
      t.chunk_bytes = c.bytes;
      t.raw_bytes = c.raw_bytes;
      t.chunk_xxh64 = c.xxh64;
      // Optional: files before the wind chunk (issue 13 follow-up) have no U, V.
      if (s.contains("wind") && !s.at("wind").is_null()) {
        const ChunkRef w = chunkFromJson(s.at("wind"));
        t.wind_chunk_offset = w.offset;
        t.wind_chunk_bytes = w.bytes;
        t.wind_raw_bytes = w.raw_bytes;
        t.wind_chunk_xxh64 = w.xxh64;
      }
      d.timesteps.push_back(std::move(t));
    }
  } catch (const std::exception& e) {  // nlohmann::json errors, bad checksum text
    throw InputError(fmt::format("{}: the index of this .nph file is invalid: {}", file, e.what()));
  }
  const auto& m = d.metadata;
  if (m.nx <= 0 || m.ny <= 0 || d.nz < 0 || !(m.dz_m > 0.0)) {
    throw InputError(fmt::format("{}: invalid grid {}x{}x{}, dz {} m in the index", file, m.nx, m.ny, d.nz, m.dz_m));
  }
  // Every size below is a product of these: bound it first (a valid-checksum index declaring
  // nx = ny = 2^30 made the byte count wrap to 0 and readQuantised copy from a wild address).
  limits::requireProductWithin(
      file, "the index's grid nx x ny x nz",
      {std::uint64_t(m.nx), std::uint64_t(m.ny), std::uint64_t(std::max(d.nz, 1))}, limits::kMaxGridPoints,
      "limits::kMaxGridPoints; a real grid this large needs a nephele built with a higher limit");
  if (!std::isfinite(m.z_bottom_m) || std::abs(m.z_bottom_m) > kMaxAbsHeight_m || !(m.dz_m <= kMaxAbsHeight_m)) {
    throw InputError(fmt::format("{}: grid z_bottom_m {} m / dz_m {} m in the index, expected heights within "
                                 "+-{} m",
                                 file, m.z_bottom_m, m.dz_m, kMaxAbsHeight_m));
  }
  for (std::size_t n = 0; n < d.timesteps.size(); ++n) {
    const TimestepInfo& t = d.timesteps[n];
    const std::uint64_t expected =
        2u * sizeof(std::uint16_t) * std::uint64_t(m.nx) * std::uint64_t(m.ny) * std::uint64_t(t.nz);
    if (t.nz < 0 || t.nz > d.nz || t.raw_bytes != expected) {
      throw InputError(fmt::format("{}: chunk {} ({}): nz {} / {} bytes do not fit the {}x{}x{} grid", file, n,
                                   geo::isoOrEmpty(t.time_utc), t.nz, t.raw_bytes, m.nx, m.ny, d.nz));
    }
    // U and V codes, int16 each: as many bytes as the extinction's two uint16 volumes.
    if (t.hasWind() && t.wind_raw_bytes != expected) {
      throw InputError(fmt::format("{}: wind chunk {} ({}): {} bytes do not fit nz {} of the {}x{} grid, expected {} "
                                   "(int16 U and V)",
                                   file, n, geo::isoOrEmpty(t.time_utc), t.wind_raw_bytes, t.nz, m.nx, m.ny, expected));
    }
  }
  return d;
}

}  // namespace nph::cache
