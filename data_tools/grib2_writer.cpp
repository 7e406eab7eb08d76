#include "grib2_writer.h"

#include <eccodes.h>
#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <numbers>

#include "core/error.h"

namespace nph::datagen {
namespace {

struct Parameter {
  const char* scene_name;  ///< IconSceneSampler::fields key
  long category, number;   ///< discipline 0
  const char* dwd_file_name;
};
constexpr std::array<Parameter, 10> kParameters = {{{"temp", 0, 0, "t"},
                                                    {"pres", 3, 0, "p"},
                                                    {"qv", 1, 0, "qv"},
                                                    {"qc", 1, 22, "qc"},
                                                    {"qi", 1, 82, "qi"},
                                                    {"qr", 1, 24, "qr"},
                                                    {"qs", 1, 25, "qs"},
                                                    {"qg", 1, 32, "qg"},
                                                    {"clc", 6, 22, "clc"},
                                                    {"z_ifc", 3, 6, "hhl"}}};

void check(int err, const char* what) {
  if (err != CODES_SUCCESS) throw InputError(fmt::format("ecCodes: {}: {}", what, codes_get_error_message(err)));
}

struct HandleDeleter {
  void operator()(codes_handle* h) const { codes_handle_delete(h); }
};

std::array<unsigned char, 16> uuidBytes(const std::string& hex) {
  if (hex.size() != 32) throw UsageError(fmt::format("uuidOfHGrid {}: expected 32 hex digits", hex));
  std::array<unsigned char, 16> b{};
  for (std::size_t i = 0; i < 16; ++i) b[i] = static_cast<unsigned char>(std::stoul(hex.substr(2 * i, 2), nullptr, 16));
  return b;
}

/// What one message holds.
struct MessageSpec {
  long category = 0, number = 0;
  long level = 0;           ///< 0: a surface field (CLON/CLAT)
  bool half_level = false;  ///< HHL: no layer, second surface 101 as DWD's HHL concept
  long step_hours = 0;
  std::vector<double> values;  ///< `points` values
  std::string uuid;            ///< native grid only
  bool ieee64 = false;         ///< 64-bit IEEE whatever the packing (cell centres)
};

class MessageWriter {
 public:
  MessageWriter(const IconSceneSampler& sampler, const IconSceneSpec& spec, const Grib2WriteOptions& options)
      : sampler_(sampler), spec_(spec), options_(options) {}

  void append(const MessageSpec& m, const std::string& path) const {
    std::unique_ptr<codes_handle, HandleDeleter> h(codes_grib_handle_new_from_samples(nullptr, "GRIB2"));
    if (!h) throw InputError("ecCodes: the GRIB2 sample cannot be loaded (ECCODES_SAMPLES_PATH)");
    codes_handle* g = h.get();                         // replaced by a clone below
    check(codes_set_long(g, "centre", 78), "centre");  // DWD (edzw): DWD's shortNames
    check(codes_set_long(g, "dataDate", 20260318), "dataDate");
    check(codes_set_long(g, "dataTime", 1200), "dataTime");
    check(codes_set_long(g, "significanceOfReferenceTime", 1), "significanceOfReferenceTime");  // forecast start
    check(codes_set_long(g, "typeOfProcessedData", 1), "typeOfProcessedData");                  // forecast
    const std::size_t n = sampler_.points();
    if (sampler_.native()) {
      check(codes_set_long(g, "gridDefinitionTemplateNumber", 101), "gridDefinitionTemplateNumber");
      check(codes_set_long(g, "numberOfGridUsed", 26), "numberOfGridUsed");
      check(codes_set_long(g, "numberOfGridInReference", 1), "numberOfGridInReference");
      const auto uuid = uuidBytes(m.uuid);
      std::size_t len = uuid.size();
      check(codes_set_bytes(g, "uuidOfHGrid", uuid.data(), &len), "uuidOfHGrid");
      check(codes_set_long(g, "numberOfDataPoints", long(n)), "numberOfDataPoints");
    } else {
      const auto& lon = sampler_.lonAxisDeg();
      const auto& lat = sampler_.latAxisDeg();
      check(codes_set_long(g, "Ni", long(lon.size())), "Ni");
      check(codes_set_long(g, "Nj", long(lat.size())), "Nj");
      check(codes_set_long(g, "jScansPositively", spec_.lat_descending ? 0 : 1), "jScansPositively");
      check(codes_set_double(g, "latitudeOfFirstGridPointInDegrees", lat.front()), "latitudeOfFirstGridPoint");
      check(codes_set_double(g, "longitudeOfFirstGridPointInDegrees", lon.front()), "longitudeOfFirstGridPoint");
      check(codes_set_double(g, "latitudeOfLastGridPointInDegrees", lat.back()), "latitudeOfLastGridPoint");
      check(codes_set_double(g, "longitudeOfLastGridPointInDegrees", lon.back()), "longitudeOfLastGridPoint");
      check(codes_set_double(g, "iDirectionIncrementInDegrees", spec_.dlon_deg), "iDirectionIncrement");
      check(codes_set_double(g, "jDirectionIncrementInDegrees", spec_.dlat_deg), "jDirectionIncrement");
    }
    check(codes_set_long(g, "discipline", 0), "discipline");
    check(codes_set_long(g, "parameterCategory", m.category), "parameterCategory");
    check(codes_set_long(g, "parameterNumber", m.number), "parameterNumber");
    check(codes_set_long(g, "indicatorOfUnitOfTimeRange", 1), "indicatorOfUnitOfTimeRange");  // hours
    check(codes_set_long(g, "forecastTime", m.step_hours), "forecastTime");
    if (m.level > 0) {
      // Level type 150 carries 24 more octets in Section 4 (nlev, numberOfVGridUsed, uuidOfVGrid;
      // ecCodes grib2/section.4.def): make room as 6 vertical coordinate values first.
      const std::array<double, 6> room{};
      check(codes_set_long(g, "PVPresent", 1), "PVPresent");
      check(codes_set_double_array(g, "pv", room.data(), room.size()), "pv");
      check(codes_set_long(g, "typeOfFirstFixedSurface", 150), "typeOfFirstFixedSurface");
      // The second surface first: setting it resets the first one's value in ecCodes 2.28.
      check(codes_set_long(g, "typeOfSecondFixedSurface", m.half_level ? 101 : 150), "typeOfSecondFixedSurface");
      if (!m.half_level) {
        check(codes_set_long(g, "scaleFactorOfSecondFixedSurface", 0), "scaleFactorOfSecondFixedSurface");
        check(codes_set_long(g, "scaledValueOfSecondFixedSurface", m.level + 1), "scaledValueOfSecondFixedSurface");
      }
      check(codes_set_long(g, "scaleFactorOfFirstFixedSurface", 0), "scaleFactorOfFirstFixedSurface");
      check(codes_set_long(g, "scaledValueOfFirstFixedSurface", m.level), "scaledValueOfFirstFixedSurface");
    } else {
      check(codes_set_long(g, "typeOfFirstFixedSurface", 1), "typeOfFirstFixedSurface");  // ground or water surface
    }
    if (m.level > 0) {  // re-parsed, the handle knows the level-150 keys
      h.reset(codes_handle_clone(g));
      g = h.get();
      check(codes_set_long(g, "nlev", spec_.nz + 1), "nlev");
      check(codes_set_long(g, "numberOfVGridUsed", 1), "numberOfVGridUsed");
    }
    // Bits and values with the sample's simple packing, then the packing, then the exact values
    // again (switching repacks the quantised ones): ecCodes 2.28 cannot switch the sample's
    // constant field to complex packing. A constant field stays simple packing with 0 bits
    // (complex packing cannot encode it; it costs no bits either way).
    if (m.values.size() != n) throw UsageError(fmt::format("{}: {} values for {} points", path, m.values.size(), n));
    check(codes_set_long(g, "bitsPerValue", options_.bits_per_value), "bitsPerValue");
    check(codes_set_double_array(g, "values", m.values.data(), m.values.size()), "values");
    const auto [lo, hi] = std::minmax_element(m.values.begin(), m.values.end());
    const std::string packing = m.ieee64 ? "grid_ieee" : *lo == *hi ? "grid_simple" : options_.packing;
    if (packing != "grid_simple") {
      std::size_t packing_length = packing.size();
      check(codes_set_string(g, "packingType", packing.c_str(), &packing_length), "packingType");
      if (packing == "grid_ieee") {
        check(codes_set_long(g, "precision", m.ieee64 ? 2 : 1), "precision");  // 64- or 32-bit IEEE floats
      }
      check(codes_set_double_array(g, "values", m.values.data(), m.values.size()), "values");
    }
    const void* bytes = nullptr;
    std::size_t size = 0;
    check(codes_get_message(g, &bytes, &size), "message");
    std::unique_ptr<std::FILE, int (*)(std::FILE*)> f(std::fopen(path.c_str(), "ab"), &std::fclose);
    if (!f || std::fwrite(bytes, 1, size, f.get()) != size) throw InputError(fmt::format("{}: cannot write", path));
  }

 private:
  const IconSceneSampler& sampler_;
  const IconSceneSpec& spec_;
  const Grib2WriteOptions& options_;
};

}  // namespace

std::vector<std::string> writeIconSceneGrib2(const IconSceneSpec& spec, const std::string& dir,
                                             const Grib2WriteOptions& options) {
  std::filesystem::create_directories(dir);
  const IconSceneSampler sampler(spec, dir);
  const MessageWriter writer(sampler, spec, options);
  const bool native = sampler.native();
  const std::string grid_name = native ? "icosahedral" : "regular-lat-lon";
  const std::string run = "2026031812";
  std::vector<std::string> files;
  auto file_for = [&](const std::string& kind, long step, long level, const std::string& var) {
    const std::string path = options.layout == Grib2Layout::SingleFile
                                 ? fmt::format("{}/icon_scene.grib2", dir)
                                 : fmt::format("{}/icon-d2_germany_{}_{}_{}_{:03d}_{}_{}.grib2", dir, grid_name, kind,
                                               run, step, level, var);
    if (std::find(files.begin(), files.end(), path) == files.end()) {
      std::filesystem::remove(path);  // messages are appended
      files.push_back(path);
    }
    return path;
  };
  const std::size_t n = sampler.points();
  if (native) {  // cell centres in degrees (DWD: "deg E" / "deg N"), once, time-invariant, exact
    constexpr double kDegPerRad = 180.0 / std::numbers::pi;  // as io's NetCDF loader converts
    std::vector<double> clon = sampler.cellLonRad(), clat = sampler.cellLatRad();
    for (double& v : clon) v *= kDegPerRad;
    for (double& v : clat) v *= kDegPerRad;
    writer.append({191, 2, 0, false, 0, std::move(clon), options.coordinates_uuid, true},
                  file_for("time-invariant", 0, 0, "clon"));
    writer.append({191, 1, 0, false, 0, std::move(clat), options.coordinates_uuid, true},
                  file_for("time-invariant", 0, 0, "clat"));
  }
  for (int t = 0; t < spec.ntimes; ++t) {
    const auto fields = sampler.fields(t, nullptr);
    for (const Parameter& p : kParameters) {
      const bool hhl = std::string(p.scene_name) == "z_ifc";
      if (hhl && (t > 0 || !options.write_hhl)) continue;  // time-invariant: once per run
      const std::vector<float>& data = fields.at(p.scene_name);
      const long levels = hhl ? spec.nz + 1 : spec.nz;
      for (long k = 1; k <= levels; ++k) {
        const auto level = data.begin() + std::ptrdiff_t(std::size_t(k - 1) * n);
        writer.append({p.category, p.number, k, hhl, t, std::vector<double>(level, level + std::ptrdiff_t(n)),
                       options.fields_uuid, false},
                      file_for(hhl ? "time-invariant" : "model-level", t, k, p.dwd_file_name));
      }
    }
  }
  std::sort(files.begin(), files.end());
  return files;
}

}  // namespace nph::datagen
