#pragma once
// Writes test rasters through GDAL's own API (issue 14 item 3: the basemap tests read real files
// GDAL wrote, not hand-made bytes): float or 8-bit GeoTIFFs with or without a geotransform/CRS.
#include <gdal.h>
#include <gtest/gtest.h>
#include <ogr_srs_api.h>

#include <array>
#include <optional>
#include <string>
#include <vector>

namespace nph::scene::test {

struct RasterSpec {
  int width = 0, height = 0, bands = 3;
  GDALDataType type = GDT_Float32;
  std::optional<std::array<double, 6>> geotransform;  ///< none: no georeference
  std::string srs;                                    ///< "" = no CRS; else any OSRSetFromUserInput string
};

/// Writes `spec` as a GeoTIFF at `path`; `pixels` band-interleaved by pixel (w·h·bands values in
/// the band type's range). Fails the test on any GDAL error.
/// `nodata`: every band's nodata value (none: unset).
inline void writeGeoTiff(const std::string& path, const RasterSpec& spec, const std::vector<double>& pixels,
                         std::optional<double> nodata = std::nullopt) {
  GDALAllRegister();
  GDALDriverH gtiff = GDALGetDriverByName("GTiff");
  ASSERT_NE(gtiff, nullptr);
  GDALDatasetH ds = GDALCreate(gtiff, path.c_str(), spec.width, spec.height, spec.bands, spec.type, nullptr);
  ASSERT_NE(ds, nullptr) << path;
  if (spec.geotransform) {
    std::array<double, 6> gt = *spec.geotransform;
    ASSERT_EQ(GDALSetGeoTransform(ds, gt.data()), CE_None);
  }
  if (!spec.srs.empty()) {
    OGRSpatialReferenceH srs = OSRNewSpatialReference(nullptr);
    ASSERT_EQ(OSRSetFromUserInput(srs, spec.srs.c_str()), OGRERR_NONE) << spec.srs;
    ASSERT_EQ(GDALSetSpatialRef(ds, srs), CE_None);
    OSRDestroySpatialReference(srs);
  }
  if (nodata) {
    for (int b = 1; b <= spec.bands; ++b)
      ASSERT_EQ(GDALSetRasterNoDataValue(GDALGetRasterBand(ds, b), *nodata), CE_None);
  }
  std::vector<double> copy = pixels;
  const int pixelSpace = int(sizeof(double)) * spec.bands;
  ASSERT_EQ(
      GDALDatasetRasterIO(ds, GF_Write, 0, 0, spec.width, spec.height, copy.data(), spec.width, spec.height,
                          GDT_Float64, spec.bands, nullptr, pixelSpace, pixelSpace * spec.width, int(sizeof(double))),
      CE_None);
  GDALClose(ds);
}

}  // namespace nph::scene::test
