#include "nc_writer.h"

#include <fmt/format.h>

#include <filesystem>

#include "core/error.h"

namespace nph::datagen {

NcWriter::NcWriter(const std::string& path, NcFormat format)
    : path_(path), partial_path_(path + ".partial"), format_(format) {
  const int mode =
      format == NcFormat::Classic64 ? (NC_CLOBBER | NC_64BIT_OFFSET) : (NC_CLOBBER | NC_NETCDF4 | NC_CLASSIC_MODEL);
  check(nc_create(partial_path_.c_str(), mode, &ncid_), "create");
  int old_fill = 0;
  check(nc_set_fill(ncid_, NC_NOFILL, &old_fill), "set_fill");
}

NcWriter::~NcWriter() {
  // Not closed: writing failed part-way, so no partial output is left behind.
  if (ncid_ >= 0) {
    nc_close(ncid_);
    std::error_code ec;
    std::filesystem::remove(partial_path_, ec);
  }
}

void NcWriter::close() {
  if (ncid_ >= 0) {
    const int id = ncid_;
    ncid_ = -1;
    const int status = nc_close(id);
    std::error_code ec;
    if (status != NC_NOERR) std::filesystem::remove(partial_path_, ec);
    check(status, "close");
    std::filesystem::rename(partial_path_, path_, ec);
    if (ec) throw IoError(fmt::format("{}: cannot rename {} into place: {}", path_, partial_path_, ec.message()));
  }
}

void NcWriter::check(int status, const std::string& what) const {
  if (status != NC_NOERR) {
    throw IoError(fmt::format("{}: NetCDF {} failed: {}", path_, what, nc_strerror(status)));
  }
}

int NcWriter::defDim(const std::string& name, std::size_t len) {
  int id = -1;
  check(nc_def_dim(ncid_, name.c_str(), len == 0 ? NC_UNLIMITED : len, &id), "def_dim " + name);
  return id;
}

int NcWriter::defVar(const std::string& name, nc_type type, const std::vector<int>& dims) {
  int id = -1;
  check(nc_def_var(ncid_, name.c_str(), type, static_cast<int>(dims.size()), dims.data(), &id), "def_var " + name);
  if (format_ == NcFormat::Netcdf4Deflate && dims.size() >= 3 && type == NC_FLOAT) {
    check(nc_def_var_deflate(ncid_, id, 1, 1, 1), "def_var_deflate " + name);
  }
  return id;
}

void NcWriter::attText(int varid, const std::string& name, const std::string& value) {
  check(nc_put_att_text(ncid_, varid, name.c_str(), value.size(), value.c_str()), "put_att " + name);
}
void NcWriter::attInt(int varid, const std::string& name, int value) {
  check(nc_put_att_int(ncid_, varid, name.c_str(), NC_INT, 1, &value), "put_att " + name);
}
void NcWriter::attFloat(int varid, const std::string& name, float value) {
  check(nc_put_att_float(ncid_, varid, name.c_str(), NC_FLOAT, 1, &value), "put_att " + name);
}
void NcWriter::attDouble(int varid, const std::string& name, double value) {
  check(nc_put_att_double(ncid_, varid, name.c_str(), NC_DOUBLE, 1, &value), "put_att " + name);
}
void NcWriter::attFloats(int varid, const std::string& name, const std::vector<float>& values) {
  check(nc_put_att_float(ncid_, varid, name.c_str(), NC_FLOAT, values.size(), values.data()), "put_att " + name);
}

void NcWriter::endDef() { check(nc_enddef(ncid_), "enddef"); }

void NcWriter::putFloat(int varid, const std::vector<std::size_t>& start, const std::vector<std::size_t>& count,
                        const float* data) {
  check(nc_put_vara_float(ncid_, varid, start.data(), count.data(), data), "put_vara_float");
}
void NcWriter::putDouble(int varid, const std::vector<std::size_t>& start, const std::vector<std::size_t>& count,
                         const double* data) {
  check(nc_put_vara_double(ncid_, varid, start.data(), count.data(), data), "put_vara_double");
}
void NcWriter::putText(int varid, const std::vector<std::size_t>& start, const std::vector<std::size_t>& count,
                       const char* data) {
  check(nc_put_vara_text(ncid_, varid, start.data(), count.data(), data), "put_vara_text");
}
void NcWriter::putInt(int varid, const std::vector<std::size_t>& start, const std::vector<std::size_t>& count,
                      const int* data) {
  check(nc_put_vara_int(ncid_, varid, start.data(), count.data(), data), "put_vara_int");
}

}  // namespace nph::datagen
