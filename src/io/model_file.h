#pragma once
// Entry point of io/: recognise a model file, list its timesteps, load one lazily; and series of
// files (several times per file, several files) as one list of timesteps.
#include <cstdint>
#include <string>
#include <vector>

#include "load_options.h"
#include "model_fields.h"

namespace nph::io {

enum class FileFormat : std::uint8_t {
  WrfOut,       ///< WRF ARW wrfout (dims Time/bottom_top/south_north/west_east)
  IconRegular,  ///< ICON on a regular lat-lon grid (dims lat, lon)
  IconNative    ///< ICON on its native triangular grid (dim ncells, clon/clat)
};
const char* formatName(FileFormat format);

/// Recognises a file from its NetCDF header; InputError for a non-NetCDF file, or a NetCDF file
/// that is neither wrfout nor ICON (the message says what was looked for).
FileFormat sniffFormat(const std::string& path);

/// One timestep of one file.
struct TimestepRef {
  std::string file;
  std::int64_t index = 0;         ///< inside `file`
  geo::OptionalUtcTime time_utc;  ///< none when the file does not say
  FileFormat format = FileFormat::WrfOut;
};

/// A recognised model file; cheap to keep, loads a timestep on demand.
class ModelFile {
 public:
  ModelFile(std::string path, FileFormat format, std::vector<TimestepRef> timesteps, LoadOptions options);
  const std::string& path() const { return path_; }
  FileFormat format() const { return format_; }
  const std::vector<TimestepRef>& timesteps() const { return timesteps_; }
  /// Loads timestep `i` (0-based within this file).
  ModelTimestep load(std::size_t i) const;

 private:
  std::string path_;
  FileFormat format_;
  std::vector<TimestepRef> timesteps_;
  LoadOptions options_;
};

/// Sniffs `path` and lists its timesteps (reads only the header and the time axis).
ModelFile openModelFile(const std::string& path, const LoadOptions& options = {});

/// Loads one timestep described by `ref`.
ModelTimestep loadTimestep(const TimestepRef& ref, const LoadOptions& options = {});

/// Timesteps of several files in time order (stable: files without times keep their order).
class ModelSeries {
 public:
  static ModelSeries open(const std::vector<std::string>& paths, const LoadOptions& options = {});
  std::size_t size() const { return timesteps_.size(); }
  const TimestepRef& at(std::size_t i) const { return timesteps_.at(i); }
  const std::vector<TimestepRef>& timesteps() const { return timesteps_; }
  ModelTimestep load(std::size_t i) const;

 private:
  std::vector<TimestepRef> timesteps_;
  LoadOptions options_;
};

}  // namespace nph::io
