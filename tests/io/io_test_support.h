#pragma once
// Helpers for the io tests: small NetCDF-C edits used to break generated files in controlled ways,
// and the tests' scratch folder (support/scratch_dir.h).
#include <gtest/gtest.h>
#include <netcdf.h>

#include "support/scratch_dir.h"

namespace nph::io::test {

/// Asserts a NetCDF-C status inside a test helper.
inline void ncCheck(int status, const char* what) {
  ASSERT_EQ(status, NC_NOERR) << what << ": " << nc_strerror(status);
}

}  // namespace nph::io::test
