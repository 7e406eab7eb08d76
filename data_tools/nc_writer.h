#pragma once
// Thin RAII writer over NetCDF-C for the sample-data generators. Every call checks the NetCDF
// status and throws nph::IoError naming the file and the variable or attribute involved.
// The file is written as "<path>.partial" and renamed to <path> by close(); a writer destroyed
// without close() (an exception part-way) removes it, so no partial output is left behind.
#include <netcdf.h>

#include <cstddef>
#include <string>
#include <vector>

namespace nph::datagen {

enum class NcFormat {
  Classic64,      ///< NC_64BIT_OFFSET: WRF's default io_form 2 output
  Netcdf4Deflate  ///< NC_NETCDF4 | NC_CLASSIC_MODEL with shuffle + deflate level 1 (WRF nc4 builds)
};

class NcWriter {
 public:
  NcWriter(const std::string& path, NcFormat format);
  ~NcWriter();
  NcWriter(const NcWriter&) = delete;
  NcWriter& operator=(const NcWriter&) = delete;

  /// len == 0 defines the unlimited dimension.
  int defDim(const std::string& name, std::size_t len);
  int defVar(const std::string& name, nc_type type, const std::vector<int>& dims);

  void attText(int varid, const std::string& name, const std::string& value);
  void attInt(int varid, const std::string& name, int value);
  void attFloat(int varid, const std::string& name, float value);
  void attDouble(int varid, const std::string& name, double value);
  void attFloats(int varid, const std::string& name, const std::vector<float>& values);

  void endDef();

  void putFloat(int varid, const std::vector<std::size_t>& start, const std::vector<std::size_t>& count,
                const float* data);
  void putDouble(int varid, const std::vector<std::size_t>& start, const std::vector<std::size_t>& count,
                 const double* data);
  void putText(int varid, const std::vector<std::size_t>& start, const std::vector<std::size_t>& count,
               const char* data);
  void putInt(int varid, const std::vector<std::size_t>& start, const std::vector<std::size_t>& count, const int* data);

  int id() const { return ncid_; }
  const std::string& path() const { return path_; }
  void close();

 private:
  void check(int status, const std::string& what) const;
  std::string path_;
  std::string partial_path_;
  int ncid_ = -1;
  NcFormat format_;
};

}  // namespace nph::datagen
