#pragma once
// Read-only RAII access to a NetCDF file through NetCDF-C, with the checks every loader needs.
// Every failure is an nph::InputError whose message names the file, the variable or attribute,
// and what was expected (STYLE.md 6).
#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace nph::io {

/// Counts of values a read repaired or found missing.
struct ReadStats {
  std::int64_t fill_values = 0;  ///< values equal to _FillValue / missing_value / NetCDF's default fill
};

class NcReader {
 public:
  /// Opens `path`; InputError when it is missing, not NetCDF, or unreadable (e.g. truncated).
  explicit NcReader(std::string path);
  ~NcReader();
  NcReader(const NcReader&) = delete;
  NcReader& operator=(const NcReader&) = delete;

  const std::string& path() const { return path_; }

  bool hasVar(const std::string& name) const;
  bool hasDim(const std::string& name) const;
  /// Length of dimension `name`; nullopt when absent.
  std::optional<std::size_t> dimLength(const std::string& name) const;
  /// Dimension names and lengths of variable `name` (InputError when absent).
  std::vector<std::string> varDimNames(const std::string& name) const;
  std::vector<std::size_t> varShape(const std::string& name) const;
  /// The first of `names` that exists, or nullopt.
  std::optional<std::string> firstVar(std::initializer_list<const char*> names) const;

  /// Global attribute as a number (any numeric type); nullopt when absent, InputError when not numeric.
  std::optional<double> globalNumber(const std::string& name) const;
  std::optional<std::string> globalText(const std::string& name) const;
  std::optional<std::string> varText(const std::string& var, const std::string& att) const;

  /// Throws InputError unless `var` exists with exactly the dimensions `expected` (names, in order).
  void requireDims(const std::string& var, const std::vector<std::string>& expected) const;
  /// Throws InputError unless `var` is a numeric (not char/string) variable.
  void requireNumeric(const std::string& var) const;
  /// Throws InputError unless `var` is float/double, or an integer packed with scale_factor
  /// (an unpacked integer mixing ratio is garbage: 1 kg/kg per count).
  void requireFloatingOrPacked(const std::string& var) const;

  /// Reads a hyperslab as float, applying scale_factor/add_offset. Values equal to _FillValue,
  /// missing_value or NetCDF's default fill become `fill_replacement` and are counted in `stats`.
  std::vector<float> readFloats(const std::string& var, const std::vector<std::size_t>& start,
                                const std::vector<std::size_t>& count, float fill_replacement, ReadStats& stats) const;
  std::vector<double> readDoubles(const std::string& var) const;
  /// A char variable's row `index` (e.g. WRF Times(Time, DateStrLen)).
  std::string readTextRow(const std::string& var, std::size_t index) const;

 private:
  int varId(const std::string& name) const;
  void checkClassicFileSize();
  /// InputError when `var` of a NetCDF-4 file declares more bytes than kMaxCompressionRatio
  /// times the file's size (declared, never written).
  void requireStoredData(const std::string& var, int id) const;
  /// A NetCDF-4 variable may declare at most this many times the file's size: deflate cannot
  /// pass ~1032:1, and zstd on all-zero fields of a real wrfout stays far below.
  static constexpr double kMaxCompressionRatio = 4096.0;
  int format_ = 0;                 ///< nc_inq_format
  std::uintmax_t file_bytes_ = 0;  ///< size on disk at open
  /// A CF packing attribute (scale_factor / add_offset) of `var` into `value`: false when absent,
  /// InputError unless it is one finite number.
  bool packingAttribute(const std::string& var, int id, const char* name, double& value) const;
  [[noreturn]] void fail(const std::string& what) const;
  std::string path_;
  int ncid_ = -1;
};

/// "a, b, c" for messages.
std::string joinNames(const std::vector<std::string>& names);

}  // namespace nph::io
