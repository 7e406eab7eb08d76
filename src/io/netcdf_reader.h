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

  /// Reads a hyperslab as float, applying scale_factor/add_offset. Values equal to _FillValue,
  /// missing_value or NetCDF's default fill become `fill_replacement` and are counted in `stats`.
  std::vector<float> readFloats(const std::string& var, const std::vector<std::size_t>& start,
                                const std::vector<std::size_t>& count, float fill_replacement,
                                ReadStats& stats) const;
  std::vector<double> readDoubles(const std::string& var) const;
  /// A char variable's row `index` (e.g. WRF Times(Time, DateStrLen)).
  std::string readTextRow(const std::string& var, std::size_t index) const;

 private:
  int varId(const std::string& name) const;
  void checkClassicFileSize() const;
  [[noreturn]] void fail(const std::string& what) const;
  std::string path_;
  int ncid_ = -1;
};

/// "a, b, c" for messages.
std::string joinNames(const std::vector<std::string>& names);

}  // namespace nph::io
