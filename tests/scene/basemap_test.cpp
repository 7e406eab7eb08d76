// Basemap: equirectangular image -> data's map projection through GDAL's warper. A synthetic image
// whose colour encodes lon/lat (a float GeoTIFF written with GDAL, without georeference: the
// whole-Earth 2:1 rule) is reprojected into Lambert conformal; each pixel must decode to the
// lon/lat of its centre computed with Snyder's closed form (independent of PROJ).
#include <OpenImageIO/imageio.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <numbers>

#include "core/error.h"
#include "gdal_raster_writer.h"
#include "scene/basemap.h"
#include "scene/output_image.h"
#include "scene_test_support.h"

namespace nph::scene {
namespace {

constexpr double kDeg = std::numbers::pi / 180.0;

/// w × w/2 image, R = (lon + 180)/360, G = (lat + 90)/180 at pixel centres, B = 0.25: a float
/// GeoTIFF through GDAL (.tif), or a float EXR through OpenImageIO (.exr: a format Debian's GDAL
/// does not read, which basemap.h reads with OpenImageIO).
void writeLonLatImage(const std::string& path, int w) {
  const int h = w / 2;
  std::vector<float> px(std::size_t(w) * std::size_t(h) * 3);
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      const std::size_t o = (std::size_t(y) * std::size_t(w) + std::size_t(x)) * 3;
      px[o] = static_cast<float>((x + 0.5) / w);            // (lon + 180) / 360
      px[o + 1] = static_cast<float>(1.0 - (y + 0.5) / h);  // (lat + 90) / 180
      px[o + 2] = 0.25f;
    }
  }
  if (path.ends_with(".tif")) {
    test::writeGeoTiff(path, {w, h, 3, GDT_Float32, std::nullopt, ""}, std::vector<double>(px.begin(), px.end()));
    return;
  }
  auto out = OIIO::ImageOutput::create(path);
  ASSERT_TRUE(out);
  OIIO::ImageSpec spec(w, h, 3, OIIO::TypeDesc::FLOAT);
  ASSERT_TRUE(out->open(path, spec));
  ASSERT_TRUE(out->write_image(OIIO::TypeDesc::FLOAT, px.data()));
  ASSERT_TRUE(out->close());
}

/// Snyder (1987) eq. 15-1..15-5 inverse on the test's Lambert projection.
LonLat snyderLccInverse(double x, double y) {
  const double p1 = test::kLccLat1 * kDeg, p2 = test::kLccLat2 * kDeg, p0 = test::kLccLat0 * kDeg;
  auto t = [](double p) { return std::tan(std::numbers::pi / 4.0 + p / 2.0); };
  const double n = std::log(std::cos(p1) / std::cos(p2)) / std::log(t(p2) / t(p1));
  const double F = std::cos(p1) * std::pow(t(p1), n) / n, R = volume::kEarthRadius_m;
  const double rho0 = R * F / std::pow(t(p0), n);
  const double rho = std::hypot(x, rho0 - y), theta = std::atan2(x, rho0 - y);
  return {test::kLccLon0 + theta / n / kDeg,
          (2.0 * std::atan(std::pow(R * F / rho, 1.0 / n)) - std::numbers::pi / 2.0) / kDeg};
}

TEST(Basemap, LonLatImageReprojectedIntoLambertDecodesBack) {
  nph::test::ScratchDir dir("scene");
  const std::string path = dir.file("lonlat.tif");
  writeLonLatImage(path, 1440);
  const EquirectangularImage src = EquirectangularImage::load(path);
  ASSERT_EQ(src.image().width, 1440);

  const auto v = test::lambertVolumes();
  const volume::VolumeFrame frame = volume::frameOf(v);
  const SceneGeoreference geo(v, frame);
  const WorldRect rect = basemapRectangle(frame, 0.25);
  EXPECT_DOUBLE_EQ(rect.min_m.x, -0.25 * 300000.0);
  EXPECT_DOUBLE_EQ(rect.max_m.y, 240000.0 + 0.25 * 300000.0);
  const int W = 64, H = 48;
  const LinearRgbImage img = reprojectBasemap(src, geo, rect, W, H);
  ASSERT_EQ(img.width, W);
  double maxErr = 0.0;
  for (int py = 0; py < H; ++py) {
    for (int px = 0; px < W; ++px) {
      const glm::dvec2 w = worldFromBasemapPixel(rect, W, H, px, py);
      // World (0, 0) is the outer corner of cell (0, 0): projected = x0 − dx/2 + world.
      const LonLat expected = snyderLccInverse(v.georef.x0 - 1500.0 + w.x, v.georef.y0 - 1500.0 + w.y);
      const glm::vec3 c = img.at(px, py);
      const double lon = double(c.r) * 360.0 - 180.0, lat = double(c.g) * 180.0 - 90.0;
      maxErr = std::max({maxErr, std::abs(lon - expected.lon_deg), std::abs(lat - expected.lat_deg)});
      EXPECT_FLOAT_EQ(c.b, 0.25f);
    }
  }
  // Bilinear interpolation of a colour linear in lon/lat is exact; what is left is float storage
  // (2^-24 · 360° ≈ 2e-5°).
  EXPECT_LT(maxErr, 1e-4);
  // Row 0 is north: top-left pixel lies north-west of bottom-right.
  EXPECT_GT(img.at(0, 0).g, img.at(W - 1, H - 1).g);
  EXPECT_LT(img.at(0, 0).r, img.at(W - 1, H - 1).r);
}

TEST(Basemap, InterpolatedLonLatMatchesExactProjectionAtThePoleAndAntimeridian) {
  // GDAL's warper runs PROJ only where its approximating transformer finds a row non-linear
  // (basemap_gdal.cpp); compare it with projecting every pixel. The image is smooth everywhere on
  // the sphere (the unit vector of lon/lat as colour), so any lon/lat error shows as a colour
  // error. The output is finer than the source everywhere (8 km pixels, the source's 0.5° are
  // ≥ 14 km at 75°N), so GDAL's bilinear is the point-sampled bilinear of sampleLonLat (coarser
  // outputs get GDAL's widened, antialiasing kernel instead).
  LinearRgbImage img{720, 360, std::vector<float>(720 * 360 * 3)};
  for (int y = 0; y < 360; ++y) {
    for (int x = 0; x < 720; ++x) {
      const double lon = (-180.0 + (x + 0.5) * 0.5) * kDeg, lat = (90.0 - (y + 0.5) * 0.5) * kDeg;
      const std::size_t o = (std::size_t(y) * 720 + std::size_t(x)) * 3;
      img.rgb[o] = static_cast<float>(0.5 + 0.5 * std::cos(lat) * std::cos(lon));
      img.rgb[o + 1] = static_cast<float>(0.5 + 0.5 * std::cos(lat) * std::sin(lon));
      img.rgb[o + 2] = static_cast<float>(0.5 + 0.5 * std::sin(lat));
    }
  }
  const EquirectangularImage src(std::move(img));
  for (const char* proj :
       {"+proj=stere +lat_0=90 +lat_ts=60 +lon_0=-100 +x_0=0 +y_0=0 +R=6370000 +units=m +no_defs",
        "+proj=lcc +lat_1=40 +lat_2=60 +lat_0=50 +lon_0=180 +x_0=0 +y_0=0 +R=6370000 +units=m +no_defs",
        "+proj=merc +lat_ts=0 +lon_0=179 +x_0=0 +y_0=0 +R=6370000 +units=m +no_defs"}) {
    auto v = test::lambertVolumes(100, 100, 2, 20000.0);  // 2000 km square centred on (0, 0)
    v.georef.proj_definition = proj;
    const volume::VolumeFrame frame = volume::frameOf(v);
    const SceneGeoreference geo(v, frame);
    const WorldRect rect = basemapRectangle(frame, 0.1);
    const int W = 303, H = 249;
    const LinearRgbImage fast = reprojectBasemap(src, geo, rect, W, H);
    double maxDiff = 0.0;
    for (int py = 0; py < H; ++py) {
      for (int px = 0; px < W; ++px) {
        const LonLat ll = geo.lonLatFromWorld(worldFromBasemapPixel(rect, W, H, px, py));
        const glm::vec3 e = src.sampleLonLat(ll.lon_deg, ll.lat_deg), f = fast.at(px, py);
        maxDiff =
            std::max({maxDiff, double(std::abs(e.r - f.r)), double(std::abs(e.g - f.g)), double(std::abs(e.b - f.b))});
      }
    }
    // 1e-4° of lon/lat error moves this image's colour by < 1e-5.
    EXPECT_LT(maxDiff, 1e-5) << proj;
  }
}

TEST(Basemap, OffsetMovesTheMapUnderTheVolume) {
  nph::test::ScratchDir dir("scene");
  const std::string path = dir.file("lonlat.exr");
  writeLonLatImage(path, 720);
  const EquirectangularImage src = EquirectangularImage::load(path);
  const auto v = test::lambertVolumes();
  const volume::VolumeFrame frame = volume::frameOf(v);
  const SceneGeoreference plain(v, frame), shifted(v, frame, LonLatOffset{1.5, -0.5});
  const WorldRect rect = basemapRectangle(frame, 0.0);
  const LinearRgbImage a = reprojectBasemap(src, plain, rect, 16, 16);
  const LinearRgbImage b = reprojectBasemap(src, shifted, rect, 16, 16);
  EXPECT_NEAR((b.at(8, 8).r - a.at(8, 8).r) * 360.0f, 1.5f, 1e-3f);
  EXPECT_NEAR((b.at(8, 8).g - a.at(8, 8).g) * 180.0f, -0.5f, 1e-3f);
}

TEST(Basemap, SamplingWrapsAtTheAntimeridianAndClampsAtThePoles) {
  // 4×2 image: column colours 0, 1, 2, 3 (as red), rows equal.
  LinearRgbImage img{4, 2, std::vector<float>(24, 0.0f)};
  for (int y = 0; y < 2; ++y)
    for (int x = 0; x < 4; ++x) img.rgb[(std::size_t(y) * 4 + std::size_t(x)) * 3] = float(x);
  const EquirectangularImage e(img);
  // Pixel centres at lon −135, −45, 45, 135. At lon 180 we are half-way between column 3 and 0.
  EXPECT_FLOAT_EQ(e.sampleLonLat(-135.0, 0.0).r, 0.0f);
  EXPECT_FLOAT_EQ(e.sampleLonLat(45.0, 0.0).r, 2.0f);
  EXPECT_FLOAT_EQ(e.sampleLonLat(0.0, 0.0).r, 1.5f);
  EXPECT_FLOAT_EQ(e.sampleLonLat(180.0, 0.0).r, 1.5f);
  EXPECT_FLOAT_EQ(e.sampleLonLat(-180.0, 0.0).r, 1.5f);
  EXPECT_FLOAT_EQ(e.sampleLonLat(-180.0, 90.0).r, 1.5f);
  const glm::dvec2 uv = equirectUv(-180.0, 90.0);
  EXPECT_DOUBLE_EQ(uv.x, 0.0);
  EXPECT_DOUBLE_EQ(uv.y, 0.0);
  EXPECT_DOUBLE_EQ(equirectUv(0.0, -90.0).y, 1.0);
}

TEST(Basemap, EightBitImagesAreSrgbDecoded) {
  nph::test::ScratchDir dir("scene");
  const std::string path = dir.file("codes.png");
  const unsigned char codes[4 * 2 * 3] = {0, 128, 255, 10, 20, 30, 200, 100, 50, 255, 255, 255,
                                          1, 2,   3,   4,  5,  6,  7,   8,   9,  11,  12,  13};
  {
    auto out = OIIO::ImageOutput::create(path);
    ASSERT_TRUE(out);
    ASSERT_TRUE(out->open(path, OIIO::ImageSpec(4, 2, 3, OIIO::TypeDesc::UINT8)));
    ASSERT_TRUE(out->write_image(OIIO::TypeDesc::UINT8, codes));
    ASSERT_TRUE(out->close());
  }
  const EquirectangularImage e = EquirectangularImage::load(path);
  // IEC 61966-2-1 reference values: code 128 -> 0.2158605, 255 -> 1, 10 -> 0.0030353 (linear part).
  EXPECT_FLOAT_EQ(e.image().at(0, 0).r, 0.0f);
  EXPECT_NEAR(e.image().at(0, 0).g, 0.2158605f, 1e-6f);
  EXPECT_FLOAT_EQ(e.image().at(0, 0).b, 1.0f);
  EXPECT_NEAR(e.image().at(1, 0).r, 10.0f / 255.0f / 12.92f, 1e-7f);
  EXPECT_NEAR(linearToSrgb(srgbToLinear(0.73f)), 0.73f, 1e-6f);
  EXPECT_NEAR(srgbToLinear(0.5f), 0.2140411f, 1e-6f);
}

TEST(Basemap, MissingOrBadFilesAreInputErrorsNamingThem) {
  nph::test::ScratchDir dir("scene");
  // Each bad raster is refused with an InputError naming the file and what was expected, when it is
  // opened or, for damage GDAL sees only when it reads pixels, when it is warped; never a crash.
  auto expectInputError = [&](const std::string& path, const char* what) {
    try {
      const BasemapRaster r = BasemapRaster::open(path);
      auto v = test::lambertVolumes(8, 8, 2);
      const volume::VolumeFrame frame = volume::frameOf(v);
      (void)reprojectBasemap(r, SceneGeoreference(v, frame), basemapRectangle(frame, 0.0), 16, 16);
      ADD_FAILURE() << "accepted " << path;
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(path), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find(what), std::string::npos) << e.what();
    }
  };
  expectInputError(dir.file("no-such-bluemarble.jpg"), "not found");
  // Not an image at all.
  { std::ofstream(dir.file("notanimage.jpg")) << "this is not a JPEG"; }
  expectInputError(dir.file("notanimage.jpg"), "not a raster GDAL reads");
  // No georeference and not 2:1: nothing says where it lies.
  const unsigned char px[3 * 3 * 3] = {};
  auto out = OIIO::ImageOutput::create(dir.file("square.png"));
  ASSERT_TRUE(out);
  ASSERT_TRUE(out->open(dir.file("square.png"), OIIO::ImageSpec(3, 3, 3, OIIO::TypeDesc::UINT8)));
  ASSERT_TRUE(out->write_image(OIIO::TypeDesc::UINT8, px));
  ASSERT_TRUE(out->close());
  expectInputError(dir.file("square.png"), "width = 2·height");
  // A geotransform without a CRS (metres of what?).
  test::writeGeoTiff(dir.file("nocrs.tif"),
                     {40, 30, 3, GDT_Byte, std::array<double, 6>{500000.0, 100.0, 0.0, 4e6, 0.0, -100.0}, ""},
                     std::vector<double>(40 * 30 * 3, 100.0));
  expectInputError(dir.file("nocrs.tif"), "has no coordinate reference system");
  // Truncated: a valid lon/lat GeoTIFF over the volume, cut after its header and a third of its
  // pixels.
  const std::string cut = dir.file("truncated.tif");
  test::writeGeoTiff(cut,
                     {400, 300, 3, GDT_Byte, std::array<double, 6>{-82.0, 0.01, 0.0, 27.0, 0.0, -0.01}, "EPSG:4326"},
                     std::vector<double>(400 * 300 * 3, 100.0));
  std::filesystem::resize_file(cut, std::filesystem::file_size(cut) / 3);
  expectInputError(cut, "cannot read");
  // An absurd size declared by a few bytes (a VRT): refused from its header, before any read.
  {
    std::ofstream(dir.file("huge.vrt")) << R"(<VRTDataset rasterXSize="1000000" rasterYSize="1000000">
  <SRS>EPSG:4326</SRS><GeoTransform>-180, 0.00036, 0, 90, 0, -0.00018</GeoTransform>
  <VRTRasterBand dataType="Byte" band="1"/></VRTDataset>)";
  }
  expectInputError(dir.file("huge.vrt"), "basemap width x height = 1000000 x 1000000");
  // Bands GDAL reads but a basemap cannot use.
  test::writeGeoTiff(dir.file("int32.tif"), {8, 4, 1, GDT_Int32, std::nullopt, ""}, std::vector<double>(32, 1.0));
  expectInputError(dir.file("int32.tif"), "expected Byte or UInt16");
}

/// A lon/lat GeoTIFF of the whole Earth (EPSG:4326 with its geotransform) warps exactly as the
/// same pixels without georeference (the 2:1 rule): both are whole-Earth plate carrée.
TEST(Basemap, GeoreferencedWholeEarthTiffEqualsTheTwoToOneRule) {
  nph::test::ScratchDir dir("scene");
  const std::string plain = dir.file("plain.tif"), geo4326 = dir.file("epsg4326.tif");
  std::vector<double> px(360 * 180 * 3);
  for (std::size_t i = 0; i < px.size(); ++i) px[i] = double((i * 7919) % 256);
  test::writeGeoTiff(plain, {360, 180, 3, GDT_Byte, std::nullopt, ""}, px);
  test::writeGeoTiff(
      geo4326, {360, 180, 3, GDT_Byte, std::array<double, 6>{-180.0, 1.0, 0.0, 90.0, 0.0, -1.0}, "EPSG:4326"}, px);
  const BasemapRaster a = BasemapRaster::open(plain), b = BasemapRaster::open(geo4326);
  EXPECT_TRUE(a.wholeEarth());
  EXPECT_TRUE(b.wholeEarth());
  const auto v = test::lambertVolumes();
  const volume::VolumeFrame frame = volume::frameOf(v);
  const SceneGeoreference geo(v, frame);
  const WorldRect rect = basemapRectangle(frame, 0.5);
  const LinearRgbImage ia = reprojectBasemap(a, geo, rect, 64, 48), ib = reprojectBasemap(b, geo, rect, 64, 48);
  EXPECT_EQ(ia.rgb, ib.rgb);
  // 8-bit codes are sRGB-decoded: every value in [0, 1], and not all equal.
  EXPECT_GE(*std::min_element(ia.rgb.begin(), ia.rgb.end()), 0.0f);
  EXPECT_LE(*std::max_element(ia.rgb.begin(), ia.rgb.end()), 1.0f);
  EXPECT_NE(*std::min_element(ia.rgb.begin(), ia.rgb.end()), *std::max_element(ia.rgb.begin(), ia.rgb.end()));
}

TEST(Basemap, BlueMarbleFromMarbleQtData) {
  const std::string path = "/usr/share/marble/data/maps/earth/bluemarble/bluemarble.jpg";
  // make deps installs it (tools/debian-packages.txt); a missing file is a set-up defect, not a skip.
  ASSERT_TRUE(std::filesystem::exists(path)) << path << " is missing: install Debian package marble-qt-data";
  const EquirectangularImage e = EquirectangularImage::load(path);
  EXPECT_EQ(e.image().width, 2 * e.image().height);
  const glm::vec3 atlantic = e.sampleLonLat(-30.0, 0.0);    // open ocean: blue dominates red
  const glm::vec3 sahara = e.sampleLonLat(10.0, 23.0);      // desert: red dominates blue, bright
  const glm::vec3 antarctica = e.sampleLonLat(0.0, -85.0);  // ice: bright, near grey
  EXPECT_GT(atlantic.b, atlantic.r);
  EXPECT_GT(sahara.r, sahara.b);
  EXPECT_GT(sahara.r + sahara.g + sahara.b, 3.0f * (atlantic.r + atlantic.g + atlantic.b));
  EXPECT_GT(antarctica.g, 0.3f);
}

// Imagery LOD (issue 14 item 3): a raster with overviews is read at the level that matches the
// output, not at full resolution. The GeoTIFF (EPSG:4326, whole Earth, 2048 × 1024, 8-bit) is red
// at full resolution; GDAL builds its overviews (×2, ×4, ×8), whose pixels are then painted a
// different colour each, so the warped image says which level was read.
TEST(Basemap, OverviewMatchingTheOutputIsReadNotTheFullResolution) {
  nph::test::ScratchDir dir("scene");
  const std::string path = dir.file("overviews.tif");
  constexpr int kW = 2048, kH = 1024;
  std::vector<double> red(std::size_t(kW) * kH * 3, 0.0);
  for (std::size_t i = 0; i < red.size(); i += 3) red[i] = 255.0;
  test::writeGeoTiff(
      path, {kW, kH, 3, GDT_Byte, std::array<double, 6>{-180.0, 360.0 / kW, 0.0, 90.0, 0.0, -180.0 / kH}, "EPSG:4326"},
      red);
  // Overview k (factor 2^(k+1)) gets the code (0, 80·(k+1), 255 − 80·k) in every pixel.
  {
    GDALDatasetH ds = GDALOpen(path.c_str(), GA_Update);
    ASSERT_NE(ds, nullptr);
    int factors[] = {2, 4, 8};
    ASSERT_EQ(GDALBuildOverviews(ds, "NEAREST", 3, factors, 0, nullptr, nullptr, nullptr), CE_None);
    for (int b = 1; b <= 3; ++b) {
      GDALRasterBandH band = GDALGetRasterBand(ds, b);
      ASSERT_EQ(GDALGetOverviewCount(band), 3);
      for (int k = 0; k < 3; ++k) {
        GDALRasterBandH o = GDALGetOverview(band, k);
        const int ow = GDALGetRasterBandXSize(o), oh = GDALGetRasterBandYSize(o);
        const double code = b == 1 ? 0.0 : b == 2 ? 80.0 * (k + 1) : 255.0 - 80.0 * k;
        std::vector<double> fill(std::size_t(ow) * std::size_t(oh), code);
        ASSERT_EQ(GDALRasterIO(o, GF_Write, 0, 0, ow, oh, fill.data(), ow, oh, GDT_Float64, 0, 0), CE_None);
      }
    }
    GDALClose(ds);
  }
  const BasemapRaster raster = BasemapRaster::open(path);
  ASSERT_EQ(raster.overviewWidths(), (std::vector<int>{1024, 512, 256}));
  const auto levelRead = [&](int w) {
    const LinearRgbImage img = reprojectEquirectangular({raster}, w, w / 2);
    const glm::vec3 c = img.at(w / 3, w / 5);  // any pixel: each level is uniform
    for (int k = 0; k < 3; ++k) {
      const glm::vec3 painted(0.0f, srgbToLinear(80.0f * float(k + 1) / 255.0f),
                              srgbToLinear((255.0f - 80.0f * float(k)) / 255.0f));
      if (glm::length(c - painted) < 1e-4f) return k;
    }
    EXPECT_LT(glm::length(c - glm::vec3(1.0f, 0.0f, 0.0f)), 1e-4f) << "neither full resolution nor an overview";
    return -1;
  };
  // Source pixels per output pixel: 1 → full resolution; 2 → ×2; 3 → still ×2 (×4 would give
  // fewer source pixels than output pixels); 4, 5.3 → ×4; 8 and beyond → ×8 (the coarsest).
  EXPECT_EQ(levelRead(2048), -1);
  EXPECT_EQ(levelRead(1024), 0);
  EXPECT_EQ(levelRead(682), 0);
  EXPECT_EQ(levelRead(512), 1);
  EXPECT_EQ(levelRead(384), 1);
  EXPECT_EQ(levelRead(256), 2);
  EXPECT_EQ(levelRead(128), 2);
  // Into the data's projection too (reprojectBasemap): the test footprint with its margin
  // (≈ 600 km) at 2 × 2 pixels, ≈ 2.7° each against the source's 0.18°: the coarsest level.
  const auto v = test::lambertVolumes();
  const volume::VolumeFrame frame = volume::frameOf(v);
  const SceneGeoreference geo(v, frame);
  const LinearRgbImage flat = reprojectBasemap(raster, geo, basemapRectangle(frame, 0.5), 2, 2);
  const glm::vec3 c = flat.at(1, 1);
  EXPECT_NEAR(c.g, srgbToLinear(240.0f / 255.0f), 1e-4f) << "expected the ×8 overview's colour";
}

}  // namespace
}  // namespace nph::scene
