// nephele-nc-probe: opens one NetCDF file through NetCDF-C and exits — the separate process in
// which nephele opens a netCDF-4/HDF5 file first (io/netcdf_reader.cpp probeHdf5Open), so a
// damaged file that makes libhdf5 crash or loop does so here and not in the renderer or its host.
// Usage: nephele-nc-probe FILE. Exit status 0: opened; 64 + e: NetCDF-C refused it with the error
// -e (NC_E...; the caller reports it without opening the file itself: libhdf5's invalid free lives
// on exactly that error path, and whether it crashes depends on the heap); 2: usage. It links nothing of nephele's and
// calls only nc_open, nc_inq and nc_close.
#include <netcdf.h>

#include <csignal>
#include <cstdio>
#include <cstdlib>

#include <unistd.h>

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: nephele-nc-probe FILE (run by nephele to open netCDF-4 files safely)\n");
    return 2;
  }
  // Fault injection for the tests of the guard (reliability.HostileNetcdf...): the probe dies the
  // way libhdf5 makes it die, or never comes back.
  if (std::getenv("NEPHELE_TEST_HDF5_PROBE_CRASH") != nullptr) std::raise(SIGSEGV);
  if (std::getenv("NEPHELE_TEST_HDF5_PROBE_HANG") != nullptr) {
    for (;;) ::pause();
  }
  int id = -1;
  const int status = nc_open(argv[1], NC_NOWRITE, &id);
  if (status != NC_NOERR) return 64 + (status < 0 && status > -191 ? -status : 191);
  int ndims = 0, nvars = 0, natts = 0, unlimited = -1;
  nc_inq(id, &ndims, &nvars, &natts, &unlimited);
  nc_close(id);
  return 0;
}
