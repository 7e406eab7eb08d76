// The floor under `nephele convert` (issue 19, "convert is within 2× of a raw NetCDF read of the
// same variables"): every variable the WRF loader reads (src/io/wrf_loader.cpp: the hydrometeor
// mixing ratios and number concentrations, QVAPOR, P, PB, T, PH, PHB, HGT, XLAT, XLONG), every
// timestep, read with nc_get_vara_float into one buffer allocated and touched once: the library's
// own cost (HDF5 chunk reads, zlib, unshuffle, the copy out) and nothing of ours. Not a test and
// not a Google Benchmark: tools/convert_speed.sh runs it interleaved with `nephele convert` and
// takes medians of CPU and wall time (docs/benchmarks.md, "convert against a raw read").
// Usage: nephele_netcdf_raw_read WRFOUT.nc   prints `variables=… values=… MB=… seconds=…`.
#include <netcdf.h>

#include <chrono>
#include <cstdio>
#include <cstring>
#include <string>
#include <vector>

namespace {

constexpr const char* kLoaderVariables[] = {"QCLOUD", "QRAIN", "QICE",   "QSNOW",     "QGRAUP", "QHAIL",  "QNCLOUD",
                                            "QNRAIN", "QNICE", "QNSNOW", "QNGRAUPEL", "QNHAIL", "QVAPOR", "P",
                                            "PB",     "T",     "PH",     "PHB",       "HGT",    "XLAT",   "XLONG"};

int fail(const char* path, const std::string& what, int status) {
  std::fprintf(stderr, "nephele_netcdf_raw_read: %s: %s (%s)\n", path, what.c_str(), nc_strerror(status));
  return 1;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: %s WRFOUT.nc\n", argv[0]);
    return 2;
  }
  const char* path = argv[1];
  const auto t0 = std::chrono::steady_clock::now();
  int ncid = 0;
  if (int s = nc_open(path, NC_NOWRITE, &ncid); s != NC_NOERR) return fail(path, "cannot open", s);
  std::vector<float> buffer;
  std::size_t variables = 0, values = 0;
  for (const char* name : kLoaderVariables) {
    int var = 0;
    if (nc_inq_varid(ncid, name, &var) != NC_NOERR) continue;  // absent in this file: the loader skips it too
    int ndims = 0;
    nc_inq_varndims(ncid, var, &ndims);
    const auto rank = static_cast<std::size_t>(ndims);
    std::vector<int> dims(rank);
    nc_inq_vardimid(ncid, var, dims.data());
    std::vector<std::size_t> count(rank), start(rank, 0);
    for (int d = 0; d < ndims; ++d) nc_inq_dimlen(ncid, dims[std::size_t(d)], &count[std::size_t(d)]);
    // WRF's first dimension is Time: one read per timestep, as the loader does.
    const std::size_t times = ndims > 0 ? count[0] : 1;
    if (ndims > 0) count[0] = 1;
    std::size_t n = 1;
    for (std::size_t c : count) n *= c;
    if (buffer.size() < n) {
      buffer.resize(n);  // allocated and touched once; later reads overwrite it
    }
    for (std::size_t t = 0; t < times; ++t) {
      if (ndims > 0) start[0] = t;
      const int s = nc_get_vara_float(ncid, var, start.data(), count.data(), buffer.data());
      if (s != NC_NOERR && s != NC_ERANGE) return fail(path, std::string("cannot read ") + name, s);
      values += n;
    }
    ++variables;
  }
  nc_close(ncid);
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  std::printf("variables=%zu values=%zu MB=%.1f seconds=%.3f\n", variables, values, double(values) * 4.0 / 1e6,
              seconds);
  return 0;
}
