#include "grib2_loader.h"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <filesystem>
#include <set>

#include "core/error.h"
#include "field_checks.h"
#include "icon_fields.h"

namespace nph::io {
namespace {

/// typeOfFirstFixedSurface of ICON's model levels (code table 4.5: 150 = generalized vertical
/// height coordinate; DWD's ICON model-level and HHL files).
constexpr long kModelLevelType = 150;

struct ParameterRow {
  long category, number;
  Grib2Role role;
  int hydrometeor;  // Hydrometeor for Q rows, else -1
  const char* dwd_name;
};
/// Discipline 0 (meteorological products): code table 4.2 and DWD's local entries (ecCodes
/// definitions/grib2/localConcepts/edzw/shortName.def).
constexpr std::array<ParameterRow, 13> kParameters = {{
    {1, 22, Grib2Role::Q, int(Hydrometeor::Cloud), "QC"},
    {1, 82, Grib2Role::Q, int(Hydrometeor::Ice), "QI"},
    {1, 24, Grib2Role::Q, int(Hydrometeor::Rain), "QR"},
    {1, 25, Grib2Role::Q, int(Hydrometeor::Snow), "QS"},
    {1, 32, Grib2Role::Q, int(Hydrometeor::Graupel), "QG"},
    {1, 71, Grib2Role::Q, int(Hydrometeor::Hail), "QH"},
    {1, 0, Grib2Role::QV, -1, "QV"},
    {0, 0, Grib2Role::T, -1, "T"},
    {3, 0, Grib2Role::P, -1, "P"},
    {3, 6, Grib2Role::HHL, -1, "HHL"},
    {6, 22, Grib2Role::CLC, -1, "CLC"},
    {191, 2, Grib2Role::CLON, -1, "CLON"},
    {191, 1, Grib2Role::CLAT, -1, "CLAT"},
}};

const ParameterRow* rowOf(const Grib2Message& m) {
  if (m.discipline != 0) return nullptr;
  for (const ParameterRow& r : kParameters) {
    if (r.category != m.category || r.number != m.parameter) continue;
    const bool grid_coordinate = r.role == Grib2Role::CLON || r.role == Grib2Role::CLAT;
    // Model-level fields only: T at 2 m or HSURF (0.3.6 at the surface) are other quantities.
    if (!grid_coordinate && m.level_type != kModelLevelType) return nullptr;
    return &r;
  }
  return nullptr;
}

const char* nameOf(Grib2Role role, int hydrometeor) {
  for (const ParameterRow& r : kParameters)
    if (r.role == role && r.hydrometeor == hydrometeor) return r.dwd_name;
  return "?";
}

std::string listLevels(const std::set<long>& levels) {
  std::vector<long> v(levels.begin(), levels.end());
  if (v.size() > 12) return fmt::format("{} .. {} (with gaps)", v.front(), v.back());
  return fmt::format("{}", fmt::join(v, ", "));
}

}  // namespace

std::shared_ptr<const Grib2Dataset> Grib2Dataset::open(const std::vector<std::string>& files) {
  if (files.empty()) throw UsageError("Grib2Dataset::open: no files");
  auto ds = std::make_shared<Grib2Dataset>();
  std::set<std::string> seen;
  for (const std::string& f : files) {
    std::error_code ec;
    const std::string canonical = std::filesystem::weakly_canonical(f, ec).string();
    if (seen.insert(ec ? f : canonical).second) ds->files_.push_back(f);
  }
  std::vector<Grib2Message> fields, coordinates;
  std::map<std::string, std::size_t> ignored;  // shortName -> messages
  for (const std::string& f : ds->files_) {
    for (Grib2Message& m : scanGrib2File(f)) {
      ++ds->message_count_;
      const ParameterRow* row = rowOf(m);
      if (!row) {
        ++ignored[m.short_name.empty() ? fmt::format("{}.{}.{}", m.discipline, m.category, m.parameter) : m.short_name];
        continue;
      }
      m.short_name = row->dwd_name;  // DWD's name, whatever table the writer's ecCodes used (QC, not clwmr)
      (row->role == Grib2Role::CLON || row->role == Grib2Role::CLAT ? coordinates : fields).push_back(std::move(m));
    }
  }
  const std::string what = ds->files_.size() == 1
                               ? ds->files_.front()
                               : fmt::format("{} (and {} more GRIB2 files)", ds->files_.front(), ds->files_.size() - 1);
  const auto temperature =
      std::find_if(fields.begin(), fields.end(), [](const Grib2Message& m) { return rowOf(m)->role == Grib2Role::T; });
  if (temperature == fields.end()) {
    throw InputError(fmt::format("{}: no temperature on model levels, expected T (GRIB2 0.0.0) with "
                                 "typeOfFirstFixedSurface 150 (generalized vertical height), one message per level",
                                 what));
  }
  ds->grid_ = temperature->grid;
  const Grib2Grid& grid = ds->grid_;
  const std::string& ref = temperature->where();
  if (grid.type != "regular_ll" && grid.type != "unstructured_grid") {
    throw InputError(fmt::format("{}: gridType {} is not supported, expected regular_ll (DWD regular-lat-lon files) "
                                 "or unstructured_grid (ICON's native grid)",
                                 ref, grid.type));
  }
  if (grid.type == "regular_ll" && (grid.i_scans_negatively || grid.j_points_consecutive)) {
    throw InputError(fmt::format("{}: scanning mode (iScansNegatively {}, jPointsAreConsecutive {}) is not supported, "
                                 "expected rows west to east (both 0)",
                                 ref, int(grid.i_scans_negatively), int(grid.j_points_consecutive)));
  }
  if (grid.type == "regular_ll" &&
      (grid.ni < 1 || grid.nj < 1 || std::size_t(grid.ni) * std::size_t(grid.nj) != grid.points)) {
    throw InputError(fmt::format("{}: Ni x Nj = {} x {} but numberOfDataPoints = {}, expected a complete regular grid",
                                 ref, grid.ni, grid.nj, grid.points));
  }
  for (Grib2Message& m : fields) {
    if (!(m.grid == grid)) {
      throw InputError(fmt::format("mixed grids: {} is on {}, but {} is on {}; expected one grid for every field", ref,
                                   grid.describe(), m.where(), m.grid.describe()));
    }
    const ParameterRow* row = rowOf(m);
    const Key key{row->role, row->hydrometeor};
    auto [it, inserted] = ds->index_[key][m.valid_time_utc].try_emplace(m.level, m);
    if (!inserted) {
      throw InputError(fmt::format("{} and {} both hold {} level {} at {}, expected one message per variable, level "
                                   "and time",
                                   it->second.where(), m.where(), row->dwd_name, m.level, m.valid_time_utc));
    }
  }
  if (ds->native()) {
    std::string other_uuid;
    for (Grib2Message& m : coordinates) {
      if (m.grid.uuid != grid.uuid || m.grid.points != grid.points) {
        other_uuid = m.where() + " has uuidOfHGrid " + m.grid.uuid;
        continue;
      }
      const ParameterRow* row = rowOf(m);
      ds->index_[Key{row->role, -1}][m.valid_time_utc].try_emplace(0, m);
    }
    for (Grib2Role role : {Grib2Role::CLON, Grib2Role::CLAT}) {
      if (ds->index_.count(Key{role, -1}) == 0) {
        throw InputError(
            other_uuid.empty()
                ? fmt::format("{}: native grid {} needs the cell centres, expected {} (GRIB2 0.191.{}) with "
                              "uuidOfHGrid {} among the inputs (DWD's time-invariant ..._{}.grib2)",
                              ref, grid.describe(), nameOf(role, -1), role == Grib2Role::CLON ? 2 : 1, grid.uuid,
                              role == Grib2Role::CLON ? "clon" : "clat")
                : fmt::format("mismatched grid UUID: {} is on native grid uuidOfHGrid {} ({} cells), but {}; "
                              "expected {} of the same grid (uuidOfHGrid and cell count equal)",
                              ref, grid.uuid, grid.points, other_uuid, nameOf(role, -1)));
      }
    }
  }

  // Timesteps: the validity times of temperature; every level of every variable at each of them.
  const auto& t_by_time = ds->index_.at(Key{Grib2Role::T, -1});
  for (const auto& [time, levels] : t_by_time) ds->times_.push_back(time);
  ds->nz_ = t_by_time.begin()->second.size();
  if (ds->index_.count(Key{Grib2Role::HHL, -1}) == 0) {
    throw InputError(fmt::format("{}: no HHL, expected the half-level heights (GRIB2 0.3.6 on typeOfFirstFixedSurface "
                                 "150, {} levels; DWD's time-invariant ..._hhl.grib2) among the inputs",
                                 what, ds->nz_ + 1));
  }
  if (ds->index_.count(Key{Grib2Role::P, -1}) == 0) {
    throw InputError(fmt::format("{}: no pressure on model levels, expected P (GRIB2 0.3.0) on typeOfFirstFixedSurface "
                                 "150 among the inputs",
                                 what));
  }
  const bool any_condensate = std::any_of(ds->index_.begin(), ds->index_.end(),
                                          [](const auto& entry) { return entry.first.role == Grib2Role::Q; });
  if (!any_condensate) {
    throw InputError(fmt::format("{}: no condensate on model levels, expected at least one of QC, QI, QR, QS, QG "
                                 "(GRIB2 0.1.22, 0.1.82, 0.1.24, 0.1.25, 0.1.32) among the inputs",
                                 what));
  }
  for (const auto& [key, by_time] : ds->index_) {
    if (key.role == Grib2Role::CLON || key.role == Grib2Role::CLAT) continue;
    const bool invariant = key.role == Grib2Role::HHL;
    const std::size_t expected = invariant ? ds->nz_ + 1 : ds->nz_;
    for (const std::string& time : ds->times_) {
      const LevelMap& levels = ds->levelsAt(key, time, invariant);
      std::set<long> missing;
      for (long k = 1; k <= long(expected); ++k)
        if (levels.count(k) == 0) missing.insert(k);
      if (!missing.empty() || levels.size() != expected) {
        std::set<long> present;
        for (const auto& [k, m] : levels) present.insert(k);
        throw InputError(fmt::format("{}: {} at {} has levels {}, expected levels 1 .. {} (one message per level{}); "
                                     "missing: {}",
                                     levels.begin()->second.file, nameOf(key.role, key.hydrometeor), time,
                                     listLevels(present), expected, invariant ? ", half levels" : "",
                                     missing.empty() ? std::string("none, but extra levels") : listLevels(missing)));
      }
    }
  }
  ds->ignored_ = std::move(ignored);
  return ds;
}

const Grib2Dataset::LevelMap& Grib2Dataset::levelsAt(const Key& key, const std::string& time,
                                                     bool time_invariant) const {
  const auto& by_time = index_.at(key);
  if (auto it = by_time.find(time); it != by_time.end()) return it->second;
  if (!time_invariant) {
    throw InputError(fmt::format("{}: {} has no messages valid at {}, expected every variable at every time of T",
                                 by_time.begin()->second.begin()->second.file, nameOf(key.role, key.hydrometeor),
                                 time));
  }
  return by_time.begin()->second;  // time-invariant fields: DWD writes them once per run
}

const std::string& Grib2Dataset::firstFileOf(std::size_t t) const {
  return index_.at(Key{Grib2Role::T, -1}).at(times_.at(t)).begin()->second.file;
}

std::string Grib2Dataset::variableSummary() const {
  std::vector<std::string> parts;
  for (const auto& [key, by_time] : index_) {
    parts.push_back(fmt::format("{} {} levels x {} times", nameOf(key.role, key.hydrometeor),
                                by_time.begin()->second.size(), by_time.size()));
  }
  std::vector<std::string> others;
  for (const auto& [name, count] : ignored_) others.push_back(fmt::format("{} ({})", name, count));
  return fmt::format("{}{}", fmt::join(parts, ", "),
                     others.empty() ? std::string() : fmt::format("; not read: {}", fmt::join(others, ", ")));
}

std::vector<float> Grib2Dataset::readLevels(const Key& key, const std::string& time, std::size_t levels,
                                            bool time_invariant, IconQuantity quantity, LoadRepairs& repairs) const {
  const LevelMap& by_level = levelsAt(key, time, time_invariant);
  const std::size_t n = grid_.points;
  std::vector<float> out(levels * n);
  for (std::size_t k = 0; k < levels; ++k) {
    const Grib2Message& m = by_level.at(long(k + 1));
    std::size_t missing = 0;
    const std::vector<double> values = readGrib2Values(m, missing);
    const bool condensate = quantity == IconQuantity::Condensate || quantity == IconQuantity::SpecificHumidity ||
                            quantity == IconQuantity::CloudCoverPercent;
    if (missing > 0 && !condensate) {
      throw InputError(
          fmt::format("{}: {} of {} points are missing (bitmap), expected a complete field", m.where(), missing, n));
    }
    std::vector<float> level(n);
    for (std::size_t p = 0; p < n; ++p) level[p] = std::isnan(values[p]) ? 0.0f : static_cast<float>(values[p]);
    repairs.missing_as_zero += std::int64_t(missing);
    checkIconField(m.file, fmt::format("message {} ({}, level {})", m.number, m.short_name, m.level), quantity, level,
                   repairs);
    std::copy(level.begin(), level.end(), out.begin() + std::ptrdiff_t(k * n));
  }
  return out;
}

ModelTimestep Grib2Dataset::load(std::size_t t, const LoadOptions& options) const {
  if (t >= times_.size()) {
    throw UsageError(fmt::format("{}: timestep {} requested, the GRIB2 data has {}", files_.front(), t, times_.size()));
  }
  const std::string& time = times_[t];
  IconSourceFields src;
  src.path = firstFileOf(t);
  src.time_index = std::int64_t(t);
  src.time_utc = geo::parseOptional(time);
  src.nz = nz_;
  src.npoints = grid_.points;
  src.native = native();
  requireWithinBudget(src.path, "one timestep", double(src.npoints) * double(nz_ + 1), 12, memoryBudgetBytes(options));
  for (const auto& [key, by_time] : index_) {
    if (key.role == Grib2Role::Q) {
      src.q_kg_per_kg[Hydrometeor(key.hydrometeor)] =
          readLevels(key, time, nz_, false, IconQuantity::Condensate, src.repairs);
    }
  }
  src.temperature_k = readLevels(Key{Grib2Role::T, -1}, time, nz_, false, IconQuantity::Temperature, src.repairs);
  src.pressure_pa = readLevels(Key{Grib2Role::P, -1}, time, nz_, false, IconQuantity::Pressure, src.repairs);
  if (index_.count(Key{Grib2Role::QV, -1}) > 0) {
    src.water_vapour_kg_per_kg =
        readLevels(Key{Grib2Role::QV, -1}, time, nz_, false, IconQuantity::SpecificHumidity, src.repairs);
  } else {
    src.water_vapour_kg_per_kg.assign(nz_ * src.npoints, 0.0f);
  }
  if (index_.count(Key{Grib2Role::CLC, -1}) > 0) {
    src.cloud_cover_fraction =
        readLevels(Key{Grib2Role::CLC, -1}, time, nz_, false, IconQuantity::CloudCoverPercent, src.repairs);
  }
  src.heights_name = "HHL";
  src.heights_are_half_levels = true;
  src.heights_m = readLevels(Key{Grib2Role::HHL, -1}, time, nz_ + 1, true, IconQuantity::Height, src.repairs);

  if (!native()) {
    // Longitudes as ICON-D2's regular files write them (first point 356.06 E) become -3.94 E.
    const double lon0 = grid_.lon_first_deg >= 180.0 ? grid_.lon_first_deg - 360.0 : grid_.lon_first_deg;
    const double dlat = grid_.j_scans_positively ? grid_.dj_deg : -grid_.dj_deg;
    src.lon_name = "longitudes (Section 3)";
    src.lat_name = "latitudes (Section 3)";
    for (long i = 0; i < grid_.ni; ++i) src.lon_deg.push_back(lon0 + double(i) * grid_.di_deg);
    for (long j = 0; j < grid_.nj; ++j) src.lat_deg.push_back(grid_.lat_first_deg + double(j) * dlat);
  } else {
    for (Grib2Role role : {Grib2Role::CLON, Grib2Role::CLAT}) {
      const Grib2Message& m = levelsAt(Key{role, -1}, time, true).begin()->second;
      std::size_t missing = 0;
      std::vector<double> values = readGrib2Values(m, missing);
      if (missing > 0) {
        throw InputError(
            fmt::format("{}: {} cell centres are missing (bitmap), expected every cell", m.where(), missing));
      }
      (role == Grib2Role::CLON ? src.lon_deg : src.lat_deg) = std::move(values);
      (role == Grib2Role::CLON ? src.lon_name : src.lat_name) = m.where();
    }
  }
  return assembleIconTimestep(std::move(src), options);
}

}  // namespace nph::io
