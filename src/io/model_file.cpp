#include "model_file.h"

#include <fmt/format.h>

#include <glob.h>

#include <algorithm>
#include <array>
#include <filesystem>
#include <fstream>

#include "core/error.h"
#include "grib2_loader.h"
#include "icon_loader.h"
#include "netcdf_reader.h"
#include "wrf_loader.h"

namespace nph::io {

const char* formatName(FileFormat format) {
  switch (format) {
    case FileFormat::WrfOut: return "WRF wrfout";
    case FileFormat::IconRegular: return "ICON regular lat-lon";
    case FileFormat::IconNative: return "ICON native grid";
    case FileFormat::Grib2IconRegular: return "ICON GRIB2 regular lat-lon";
    case FileFormat::Grib2IconNative: return "ICON GRIB2 native grid";
  }
  return "unknown";
}

bool hasModelFileSignature(const std::string& path) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) return false;  // a FIFO would block the read
  std::ifstream in(path, std::ios::binary);
  std::array<char, 8> head{};
  in.read(head.data(), head.size());
  const auto n = static_cast<std::size_t>(in.gcount());
  const auto starts = [&](const char* sig, std::size_t len) {
    return n >= len && std::equal(sig, sig + len, head.data());
  };
  return starts("CDF\x01", 4) || starts("CDF\x02", 4) || starts("CDF\x05", 4) ||  // classic, 64-bit offset, CDF-5
         starts("\x89HDF\r\n\x1a\n", 8) ||                                        // netCDF-4 (HDF5)
         starts("GRIB", 4);
}

namespace {

FileFormat gribFormat(const Grib2Dataset& grib) {
  return grib.native() ? FileFormat::Grib2IconNative : FileFormat::Grib2IconRegular;
}

std::vector<TimestepRef> gribTimesteps(const std::shared_ptr<const Grib2Dataset>& grib) {
  std::vector<TimestepRef> refs;
  const FileFormat format = gribFormat(*grib);
  for (std::size_t t = 0; t < grib->times().size(); ++t)
    refs.push_back({grib->firstFileOf(t), std::int64_t(t), geo::parseOptional(grib->times()[t]), format, grib});
  return refs;
}

}  // namespace

std::vector<std::string> expandModelInputs(const std::vector<std::string>& inputs) {
  std::vector<std::string> files;
  for (const std::string& input : inputs) {
    std::error_code ec;
    if (std::filesystem::is_directory(input, ec)) {
      std::vector<std::string> inside;
      for (const auto& entry : std::filesystem::directory_iterator(input, ec)) {
        const std::string p = entry.path().string();
        if (entry.is_regular_file() && hasModelFileSignature(p)) inside.push_back(p);
      }
      if (ec) throw InputError(fmt::format("{}: the folder cannot be listed ({})", input, ec.message()));
      if (inside.empty()) {
        throw InputError(fmt::format("{}: is a folder without GRIB2 or NetCDF files, expected model output", input));
      }
      std::sort(inside.begin(), inside.end());
      files.insert(files.end(), inside.begin(), inside.end());
    } else if (!std::filesystem::exists(input, ec) && input.find_first_of("*?[") != std::string::npos) {
      glob_t g{};
      const int status = ::glob(input.c_str(), 0, nullptr, &g);
      std::vector<std::string> matched(g.gl_pathv, g.gl_pathv + (status == 0 ? g.gl_pathc : 0));
      ::globfree(&g);
      if (matched.empty()) throw InputError(fmt::format("{}: the pattern matches no file", input));
      files.insert(files.end(), matched.begin(), matched.end());  // glob(3) sorts
    } else {
      files.push_back(input);
    }
  }
  return files;
}

FileFormat sniffFormat(const std::string& path) {
  if (hasGribSignature(path)) return gribFormat(*Grib2Dataset::open({path}));
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
  if (hasGribSignature(path)) {
    const auto grib = Grib2Dataset::open({path});
    return ModelFile(path, gribFormat(*grib), gribTimesteps(grib), options);
  }
  const FileFormat format = sniffFormat(path);
  const std::vector<geo::OptionalUtcTime> times =
      format == FileFormat::WrfOut ? listWrfTimes(path) : listIconTimes(path);
  std::vector<TimestepRef> refs;
  for (std::size_t t = 0; t < times.size(); ++t) refs.push_back({path, std::int64_t(t), times[t], format, nullptr});
  return ModelFile(path, format, std::move(refs), options);
}

ModelTimestep loadTimestep(const TimestepRef& ref, const LoadOptions& options) {
  if (ref.grib) return ref.grib->load(std::size_t(ref.index), options);
  return ref.format == FileFormat::WrfOut ? loadWrfTimestep(ref.file, ref.index, options)
                                          : loadIconTimestep(ref.file, ref.index, options);
}

void loadDeferredDetail(ModelTimestep& ts, const LoadOptions& options) {
  if (!ts.detail_deferred) return;
  if (ts.model == ModelKind::Wrf) loadWrfDetail(ts, options);
  ts.detail_deferred = false;
}

ModelSeries ModelSeries::open(const std::vector<std::string>& paths, const LoadOptions& options) {
  ModelSeries series;
  series.options_ = options;
  std::vector<std::string> grib_files;
  for (const std::string& p : paths) {
    if (hasGribSignature(p)) {
      grib_files.push_back(p);
      continue;
    }
    const ModelFile file = openModelFile(p, options);
    series.timesteps_.insert(series.timesteps_.end(), file.timesteps().begin(), file.timesteps().end());
  }
  if (!grib_files.empty()) {
    const std::vector<TimestepRef> refs = gribTimesteps(Grib2Dataset::open(grib_files));
    series.timesteps_.insert(series.timesteps_.end(), refs.begin(), refs.end());
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
