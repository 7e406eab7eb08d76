#include "model_file.h"

#include <fmt/format.h>

#include <algorithm>

#include "core/error.h"
#include "icon_loader.h"
#include "netcdf_reader.h"
#include "wrf_loader.h"

namespace nph::io {

const char* formatName(FileFormat format) {
  switch (format) {
    case FileFormat::WrfOut: return "WRF wrfout";
    case FileFormat::IconRegular: return "ICON regular lat-lon";
    case FileFormat::IconNative: return "ICON native grid";
  }
  return "unknown";
}

FileFormat sniffFormat(const std::string& path) {
  const NcReader nc(path);
  // WRF: its global grid attributes or its characteristic dimensions.
  if (nc.globalNumber("WEST-EAST_GRID_DIMENSION") || (nc.hasDim("west_east") && nc.hasDim("bottom_top"))) {
    return FileFormat::WrfOut;
  }
  if (nc.hasDim("ncells") || (nc.hasVar("clon") && nc.hasVar("clat"))) return FileFormat::IconNative;
  const bool icon_vars = nc.firstVar({"clc", "CLC", "z_ifc", "HHL", "qc", "qi"}).has_value();
  const bool latlon = (nc.hasDim("lat") || nc.hasDim("latitude")) && (nc.hasDim("lon") || nc.hasDim("longitude"));
  if (icon_vars && latlon) return FileFormat::IconRegular;
  throw InputError(fmt::format("{}: NetCDF file is neither WRF output (expected dims west_east, bottom_top, "
                               "south_north, Time) nor ICON output (expected qc/clc/z_ifc on lat/lon, or ncells "
                               "with clon/clat)",
                               path));
}

ModelFile::ModelFile(std::string path, FileFormat format, std::vector<TimestepRef> timesteps, LoadOptions options)
    : path_(std::move(path)), format_(format), timesteps_(std::move(timesteps)), options_(options) {}

ModelTimestep ModelFile::load(std::size_t i) const {
  if (i >= timesteps_.size()) {
    throw UsageError(fmt::format("{}: timestep {} requested, the file has {}", path_, i, timesteps_.size()));
  }
  return loadTimestep(timesteps_[i], options_);
}

ModelFile openModelFile(const std::string& path, const LoadOptions& options) {
  const FileFormat format = sniffFormat(path);
  const std::vector<geo::OptionalUtcTime> times =
      format == FileFormat::WrfOut ? listWrfTimes(path) : listIconTimes(path);
  std::vector<TimestepRef> refs;
  for (std::size_t t = 0; t < times.size(); ++t) refs.push_back({path, std::int64_t(t), times[t], format});
  return ModelFile(path, format, std::move(refs), options);
}

ModelTimestep loadTimestep(const TimestepRef& ref, const LoadOptions& options) {
  return ref.format == FileFormat::WrfOut ? loadWrfTimestep(ref.file, ref.index, options)
                                          : loadIconTimestep(ref.file, ref.index, options);
}

ModelSeries ModelSeries::open(const std::vector<std::string>& paths, const LoadOptions& options) {
  ModelSeries series;
  series.options_ = options;
  for (const std::string& p : paths) {
    const ModelFile file = openModelFile(p, options);
    series.timesteps_.insert(series.timesteps_.end(), file.timesteps().begin(), file.timesteps().end());
  }
  const bool all_timed = std::all_of(series.timesteps_.begin(), series.timesteps_.end(),
                                     [](const TimestepRef& r) { return r.time_utc.has_value(); });
  if (all_timed) {
    std::stable_sort(series.timesteps_.begin(), series.timesteps_.end(),
                     [](const TimestepRef& a, const TimestepRef& b) { return *a.time_utc < *b.time_utc; });
  }
  return series;
}

ModelTimestep ModelSeries::load(std::size_t i) const {
  if (i >= timesteps_.size())
    throw UsageError(fmt::format("timestep {} requested, the series has {}", i, timesteps_.size()));
  return loadTimestep(timesteps_[i], options_);
}

}  // namespace nph::io
