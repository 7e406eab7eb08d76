#include "icon_scene.h"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <numbers>
#include <vector>

#include "atmosphere.h"
#include "core/error.h"
#include "geo/utc_time.h"

namespace nph::datagen {
namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kDegPerRad = 180.0 / kPi;
constexpr double kEpsilonRdOverRv = 0.622;  ///< R_d / R_v, for specific humidity from e and p

double smoothstep(double e0, double e1, double x) {
  const double t = std::clamp((x - e0) / (e1 - e0), 0.0, 1.0);
  return t * t * (3.0 - 2.0 * t);
}
double layer(double z, double lo, double hi, double edge) {
  return smoothstep(lo - edge, lo, z) * (1.0 - smoothstep(hi, hi + edge, z));
}

struct Cumulus {
  double lon_deg, lat_deg, radius_km, top_m;
};

/// One model column, levels top to bottom (ICON order): half levels nz+1, full levels nz.
struct Column {
  std::vector<double> z_ifc, temp, pres, qv, qc, qi, qr, qs, qg, clc;
  void resize(int nz) {
    z_ifc.assign(std::size_t(nz + 1), 0.0);
    for (auto* v : {&temp, &pres, &qv, &qc, &qi, &qr, &qs, &qg, &clc}) v->assign(std::size_t(nz), 0.0);
  }
};

class Scene {
 public:
  explicit Scene(const IconSceneSpec& spec) : spec_(spec), noise_(spec.seed) {
    lon_min_ = spec.lon0_deg;
    lat_min_ = spec.lat0_deg;
    lon_span_ = (spec.nlon - 1) * spec.dlon_deg;
    lat_span_ = (spec.nlat - 1) * spec.dlat_deg;
    // Scattered cumulus: one cell per ~900 km^2 of the south-eastern half, positions from the seed.
    const double km_per_deg = kIconEarthRadius_m / 1000.0 / kDegPerRad;
    const double area_km2 =
        lon_span_ * km_per_deg * std::cos((lat_min_ + 0.5 * lat_span_) / kDegPerRad) * lat_span_ * km_per_deg;
    // Candidates anywhere, kept with a probability that is high in the south-east and fades out
    // along a noisy boundary, so the convective field has no straight edges.
    const int count = std::clamp(static_cast<int>(area_km2 / 2.0 / 900.0), 6, 4000);
    for (int c = 0, kept = 0; kept < count && c < 20 * count; ++c) {
      const double u = noise_.hash(c, 1, 0), v = noise_.hash(c, 2, 0);
      const double potential =
          smoothstep(0.35, 0.65, u - 0.6 * v + 0.35 + 0.5 * (noise_.fbm(3.0 * u, 3.0 * v, 9.0, 3) - 0.5));
      if (noise_.hash(c, 5, 0) >= potential) continue;
      ++kept;
      cumuli_.push_back({lon_min_ + u * lon_span_, lat_min_ + v * lat_span_, 4.0 + 8.0 * noise_.hash(c, 3, 0),
                         3000.0 + 4500.0 * noise_.hash(c, 4, 0)});
    }
  }

  double terrain(double lon, double lat) const {
    // An alpine ridge along the southern edge, up to 2400 m, plus low hills.
    const double y = (lat - lat_min_) / std::max(lat_span_, 1e-9);
    const double x = (lon - lon_min_) / std::max(lon_span_, 1e-9);
    const double ridge = 2400.0 * std::exp(-std::pow((y - 0.12) / 0.12, 2.0)) * (0.6 + 0.4 * std::sin(6.0 * x));
    const double hills = 300.0 * noise_.fbm(x * 6.0, y * 6.0, 0.5, 2);
    return std::max(0.0, ridge + hills);
  }

  void column(double lon, double lat, double hours, Column& col) const {
    const int nz = spec_.nz;
    col.resize(nz);
    const double hs = terrain(lon, lat);
    const double x = (lon - lon_min_) / std::max(lon_span_, 1e-9);
    const double y = (lat - lat_min_) / std::max(lat_span_, 1e-9);
    const double top = spec_.model_top_m;
    // Half levels, Gal-Chen terrain following: z = zc + h_s (1 - zc / z_top), zc stretched as
    // z_top s^1.6 so that layers are thin near the ground; index 0 is the model top.
    for (int k = 0; k <= nz; ++k) {
      const double s = double(nz - k) / nz;
      const double zc = top * std::pow(s, 1.6);
      col.z_ifc[std::size_t(k)] = zc + hs * (1.0 - zc / top);
    }
    const double drift = 0.02 * hours;  // features drift east by 2 % of the domain per hour
    const double n_st = noise_.fbm((x - drift) * 8.0, y * 8.0, 0.1 * hours, 3);
    // Stratus deck in the north-west, edge roughened by noise.
    const double deck = smoothstep(-0.05, 0.08, 0.55 - (x - drift) + 0.25 * (n_st - 0.5)) *
                        smoothstep(-0.05, 0.08, y - 0.4 + 0.2 * (n_st - 0.5));
    // Dissolving stratus patch (inconsistency B): cloud fraction left, condensate depleted.
    const double patch_r2 = std::pow((x - drift - 0.22) / 0.11, 2.0) + std::pow((y - 0.22) / 0.09, 2.0);
    const bool depleted_patch = patch_r2 < 0.8 + 0.4 * n_st;
    // Thin cirrus band across the middle; its eastern part has clc = 0 (inconsistency A).
    const double cirrus = std::exp(-std::pow((y - 0.55 - 0.15 * std::sin(5.0 * x)) / 0.12, 2.0));
    const bool cirrus_without_clc = x > 0.8;

    struct NearCumulus {
      const Cumulus* cu;
      double d, core;
    };
    std::vector<NearCumulus> near;
    const double km_per_deg = kIconEarthRadius_m / 1000.0 / kDegPerRad;
    for (const Cumulus& cu : cumuli_) {
      const double dx_km = (lon - cu.lon_deg - drift * lon_span_) * km_per_deg * std::cos(lat / kDegPerRad);
      const double dy_km = (lat - cu.lat_deg) * km_per_deg;
      const double d = std::hypot(dx_km, dy_km) / cu.radius_km;
      if (d <= 2.0) near.push_back({&cu, d, std::exp(-d * d)});
    }

    for (int k = 0; k < nz; ++k) {
      const std::size_t kk = std::size_t(k);
      const double z = 0.5 * (col.z_ifc[kk] + col.z_ifc[kk + 1]);
      const double agl = z - hs;
      const double temp = standardTemperatureK(z) + 1.5 * (noise_.at(x * 4.0, y * 4.0, z / 3000.0) - 0.5);
      const double pres = standardPressurePa(z);
      col.temp[kk] = temp;
      col.pres[kk] = pres;
      const double rh =
          0.7 * (1.0 - 0.7 * smoothstep(6000.0, 12000.0, z)) + 0.25 * deck * layer(agl, 500.0, 1600.0, 200.0);
      const double e = std::min(rh, 1.0) * saturationVapourPressurePa(temp);
      // Specific humidity (per kg of moist air): q = eps e / (p - (1 - eps) e).
      col.qv[kk] = kEpsilonRdOverRv * e / (pres - (1.0 - kEpsilonRdOverRv) * e);

      double qc = 0, qi = 0, qr = 0, qs = 0, qg = 0, clc = 0;
      // Stratus deck 700-1500 m above ground.
      const double st = deck * layer(agl, 700.0, 1500.0, 150.0);
      qc += 3.0e-4 * st * (0.7 + 0.6 * n_st);
      clc = std::max(clc, 100.0 * st);
      const double depleted_layer = depleted_patch ? layer(agl, 800.0, 1400.0, 100.0) : 0.0;
      clc = std::max(clc, 70.0 * depleted_layer);
      // Cirrus 9-11 km, thin.
      const double ci = cirrus * layer(z, 9000.0, 11000.0, 400.0) *
                        (0.4 + 0.6 * noise_.fbm(x * 10.0, y * 10.0, 3.0 + 0.1 * hours, 3));
      qi += 2.5e-5 * ci;
      if (!cirrus_without_clc) clc = std::max(clc, 80.0 * ci);
      // Cumulus towers (only those near this column, found once per column below).
      for (const NearCumulus& nc : near) {
        const Cumulus& cu = *nc.cu;
        const double body = nc.core * layer(z, hs + 1500.0, cu.top_m, 300.0);
        if (body <= 0.0) continue;
        const double growth = (z - hs - 1500.0) / std::max(cu.top_m - hs - 1500.0, 500.0);  // 0 base .. 1 top
        const double q_tot = 1.2e-3 * body * std::clamp(0.3 + growth, 0.0, 1.0);
        const double f_ice = std::clamp((kFreezingPoint_k - temp) / 25.0, 0.0, 1.0);
        qc += q_tot * (1.0 - f_ice);
        qi += q_tot * f_ice;
        if (cu.top_m > 6000.0) {
          qs += 2.0e-4 * body * f_ice;
          qg += 1.0e-4 * body * f_ice * nc.core;
          if (nc.d < 1.0 && z < hs + 1500.0) qr += 1.5e-4 * nc.core;  // light rain below tall towers
        }
        // Fringes (d > 1.3) carry condensate without cloud cover (inconsistency A).
        if (nc.d < 1.3) clc = std::max(clc, 100.0 * std::min(1.0, 1.5 * nc.core));
      }
      if (depleted_layer > 0.0) {  // the microphysics removed this layer's condensate
        qc = 0.0;
        qi = 0.0;
      }
      col.qc[kk] = qc;
      col.qi[kk] = qi;
      col.qr[kk] = qr;
      col.qs[kk] = qs;
      col.qg[kk] = qg;
      col.clc[kk] = std::clamp(clc, 0.0, 100.0);
    }
  }

 private:
  const IconSceneSpec& spec_;
  ValueNoise noise_;
  double lon_min_ = 0, lat_min_ = 0, lon_span_ = 1, lat_span_ = 1;
  std::vector<Cumulus> cumuli_;
};

struct FieldDef {
  const char* name;
  const char* standard_name;
  const char* long_name;
  const char* units;
  const char* param;  ///< GRIB2 discipline.category.number as cdo writes it
};
constexpr std::array<FieldDef, 10> kFields = {{
    {"temp", "air_temperature", "Temperature", "K", "0.0.0"},
    {"pres", "air_pressure", "Pressure", "Pa", "0.3.0"},
    {"qv", "specific_humidity", "Specific Humidity", "kg kg-1", "0.1.0"},
    {"qc", "mass_fraction_of_cloud_liquid_water_in_air", "Cloud Mixing Ratio", "kg kg-1", "22.1.0"},
    {"qi", "mass_fraction_of_cloud_ice_in_air", "Cloud Ice Mixing Ratio", "kg kg-1", "82.1.0"},
    {"qr", "mass_fraction_of_rain_in_air", "Rain mixing ratio", "kg kg-1", "24.1.0"},
    {"qs", "mass_fraction_of_snow_in_air", "Snow mixing ratio", "kg kg-1", "25.1.0"},
    {"qg", "mass_fraction_of_graupel_in_air", "Graupel mixing ratio", "kg kg-1", "32.1.0"},
    {"clc", "cloud_area_fraction_in_atmosphere_layer", "Cloud cover", "%", "22.6.0"},
    {"z_ifc", "geometric_height_at_half_level_center", "geometric height at half level center", "m", "6.3.0"},
}};

std::vector<double> Column::*memberFor(const std::string& name) {
  static const std::map<std::string, std::vector<double> Column::*> m = {
      {"temp", &Column::temp}, {"pres", &Column::pres},  {"qv", &Column::qv}, {"qc", &Column::qc},
      {"qi", &Column::qi},     {"qr", &Column::qr},      {"qs", &Column::qs}, {"qg", &Column::qg},
      {"clc", &Column::clc},   {"z_ifc", &Column::z_ifc}};
  return m.at(name);
}

/// Native grid cells: centres and vertices (radians), from a subdivided icosahedron, restricted to
/// the cells whose centre lies in the scene's lon/lat box.
struct NativeGrid {
  std::vector<double> clon, clat;                 // ncells
  std::vector<std::array<double, 3>> vlon, vlat;  // ncells x 3
};

using Vec3 = std::array<double, 3>;
Vec3 normalize(const Vec3& v) {
  const double n = std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
  return {v[0] / n, v[1] / n, v[2] / n};
}
void toLonLat(const Vec3& v, double& lon, double& lat) {
  lon = std::atan2(v[1], v[0]);
  lat = std::asin(std::clamp(v[2], -1.0, 1.0));
}
Vec3 fromLonLat(double lon, double lat) {
  return {std::cos(lat) * std::cos(lon), std::cos(lat) * std::sin(lon), std::sin(lat)};
}

NativeGrid buildNativeGrid(const IconSceneSpec& spec) {
  const double phi = (1.0 + std::sqrt(5.0)) / 2.0;
  std::vector<Vec3> v = {{0, 1, phi},  {0, -1, phi},  {0, 1, -phi}, {0, -1, -phi}, {1, phi, 0},  {-1, phi, 0},
                         {1, -phi, 0}, {-1, -phi, 0}, {phi, 0, 1},  {-phi, 0, 1},  {phi, 0, -1}, {-phi, 0, -1}};
  // Faces: every triple of mutually adjacent vertices (edge length 2 before normalisation).
  auto adjacent = [&](std::size_t a, std::size_t b) {
    const double dx = v[a][0] - v[b][0], dy = v[a][1] - v[b][1], dz = v[a][2] - v[b][2];
    return std::abs(dx * dx + dy * dy + dz * dz - 4.0) < 1e-9;
  };
  std::vector<std::array<std::size_t, 3>> faces;
  for (std::size_t a = 0; a < v.size(); ++a)
    for (std::size_t b = a + 1; b < v.size(); ++b)
      for (std::size_t c = b + 1; c < v.size(); ++c)
        if (adjacent(a, b) && adjacent(b, c) && adjacent(a, c)) faces.push_back({a, b, c});
  for (auto& p : v) p = normalize(p);
  const double lon_lo = spec.lon0_deg / kDegPerRad, lat_lo = spec.lat0_deg / kDegPerRad;
  const double lon_hi = (spec.lon0_deg + (spec.nlon - 1) * spec.dlon_deg) / kDegPerRad;
  const double lat_hi = (spec.lat0_deg + (spec.nlat - 1) * spec.dlat_deg) / kDegPerRad;
  const Vec3 centre = fromLonLat(0.5 * (lon_lo + lon_hi), 0.5 * (lat_lo + lat_hi));
  NativeGrid grid;
  const int n = spec.native_divisions;
  for (const auto& face : faces) {
    {
      {
        const std::size_t a = face[0], b = face[1], c = face[2];
        const Vec3 fc =
            normalize({v[a][0] + v[b][0] + v[c][0], v[a][1] + v[b][1] + v[c][1], v[a][2] + v[b][2] + v[c][2]});
        const double cos_angle = fc[0] * centre[0] + fc[1] * centre[1] + fc[2] * centre[2];
        if (cos_angle < std::cos(50.0 / kDegPerRad)) continue;  // face circumradius is ~37°
        auto point = [&](int i, int j) {
          const double s = double(i) / n, t = double(j) / n;
          Vec3 p;
          for (std::size_t d = 0; d < 3; ++d) p[d] = v[a][d] + (v[b][d] - v[a][d]) * s + (v[c][d] - v[a][d]) * t;
          return normalize(p);
        };
        auto emit = [&](const Vec3& p0, const Vec3& p1, const Vec3& p2) {
          const Vec3 m = normalize({p0[0] + p1[0] + p2[0], p0[1] + p1[1] + p2[1], p0[2] + p1[2] + p2[2]});
          double lon = 0, lat = 0;
          toLonLat(m, lon, lat);
          if (lon < lon_lo || lon > lon_hi || lat < lat_lo || lat > lat_hi) return;
          grid.clon.push_back(lon);
          grid.clat.push_back(lat);
          std::array<double, 3> bl{}, bt{};
          toLonLat(p0, bl[0], bt[0]);
          toLonLat(p1, bl[1], bt[1]);
          toLonLat(p2, bl[2], bt[2]);
          grid.vlon.push_back(bl);
          grid.vlat.push_back(bt);
        };
        for (int i = 0; i < n; ++i) {
          for (int j = 0; i + j < n; ++j) {
            emit(point(i, j), point(i + 1, j), point(i, j + 1));
            if (i + j < n - 1) emit(point(i + 1, j), point(i + 1, j + 1), point(i, j + 1));
          }
        }
      }
    }
  }
  return grid;
}

void countInconsistencies(const Column& col, IconTruth& truth) {
  for (std::size_t k = 0; k < col.clc.size(); ++k) {
    const double qw = col.qc[k] + col.qi[k];
    // Compare what a reader sees: the values as stored in float.
    const float clc_f = static_cast<float>(col.clc[k]);
    const float qw_f = static_cast<float>(col.qc[k]) + static_cast<float>(col.qi[k]);
    (void)qw;
    if (clc_f == 0.0f && qw_f > 0.0f) ++truth.clc_zero_with_condensate;
    if (clc_f > 0.0f && qw_f == 0.0f) ++truth.clc_without_condensate;
  }
}

}  // namespace

struct IconSceneSampler::Impl {
  IconSceneSpec spec;
  Scene scene;
  NativeGrid grid;
  std::vector<double> lons, lats;                 // regular axes (lat in written order)
  std::vector<std::pair<double, double>> points;  // (lon, lat) degrees, in file order
  explicit Impl(const IconSceneSpec& s) : spec(s), scene(spec) {}
};

IconSceneSampler::IconSceneSampler(const IconSceneSpec& spec, const std::string& path)
    : impl_(std::make_unique<Impl>(spec)) {
  if (spec.nlon < 2 || spec.nlat < 2 || spec.nz < 1 || spec.ntimes < 1 || !(spec.dlon_deg > 0) ||
      !(spec.dlat_deg > 0)) {
    throw UsageError(fmt::format("{}: ICON scene needs nlon, nlat >= 2, nz, ntimes >= 1, positive spacing", path));
  }
  Impl& m = *impl_;
  m.lons.resize(std::size_t(spec.nlon));
  m.lats.resize(std::size_t(spec.nlat));
  for (int i = 0; i < spec.nlon; ++i) m.lons[std::size_t(i)] = spec.lon0_deg + i * spec.dlon_deg;
  for (int j = 0; j < spec.nlat; ++j) {
    const int jj = spec.lat_descending ? spec.nlat - 1 - j : j;
    m.lats[std::size_t(j)] = spec.lat0_deg + jj * spec.dlat_deg;
  }
  if (native()) {
    m.grid = buildNativeGrid(spec);
    if (m.grid.clon.empty()) throw UsageError(fmt::format("{}: native grid has no cells in the region", path));
    for (std::size_t c = 0; c < m.grid.clon.size(); ++c)
      m.points.emplace_back(m.grid.clon[c] * kDegPerRad, m.grid.clat[c] * kDegPerRad);
  } else {
    for (int j = 0; j < spec.nlat; ++j)
      for (int i = 0; i < spec.nlon; ++i) m.points.emplace_back(m.lons[std::size_t(i)], m.lats[std::size_t(j)]);
  }
}
IconSceneSampler::~IconSceneSampler() = default;

bool IconSceneSampler::native() const { return impl_->spec.native_divisions > 0; }
const std::vector<double>& IconSceneSampler::lonAxisDeg() const { return impl_->lons; }
const std::vector<double>& IconSceneSampler::latAxisDeg() const { return impl_->lats; }
std::size_t IconSceneSampler::points() const { return impl_->points.size(); }
std::vector<double> IconSceneSampler::cellLonRad() const { return impl_->grid.clon; }
std::vector<double> IconSceneSampler::cellLatRad() const { return impl_->grid.clat; }
geo::UtcTime IconSceneSampler::time(int t) const {
  return geo::UtcTime::fromCivil(2026, 3, 18, 12).plusSeconds(3600.0 * double(t));
}

std::map<std::string, std::vector<float>> IconSceneSampler::fields(int t, IconTruth* truth) const {
  const Impl& m = *impl_;
  const std::size_t npts = m.points.size();
  std::map<std::string, std::vector<float>> out;
  for (const FieldDef& f : kFields) {
    const std::size_t levels = std::string(f.name) == "z_ifc" ? std::size_t(m.spec.nz + 1) : std::size_t(m.spec.nz);
    out[f.name].assign(levels * npts, 0.0f);
  }
  Column col;
  for (std::size_t p = 0; p < npts; ++p) {
    m.scene.column(m.points[p].first, m.points[p].second, double(t), col);
    if (truth) countInconsistencies(col, *truth);
    for (const FieldDef& f : kFields) {
      const std::vector<double>& values = col.*memberFor(f.name);
      std::vector<float>& dst = out[f.name];
      for (std::size_t k = 0; k < values.size(); ++k) dst[k * npts + p] = static_cast<float>(values[k]);
    }
  }
  return out;
}

IconTruth writeIconScene(const IconSceneSpec& spec, const std::string& path) {
  const IconSceneSampler sampler(spec, path);
  const bool native = sampler.native();
  IconTruth truth;
  truth.nlon = spec.nlon;
  truth.nlat = spec.nlat;
  truth.nz = spec.nz;
  truth.ntimes = spec.ntimes;
  truth.first_time_utc = "2026-03-18T12:00:00Z";

  NcWriter nc(path, spec.format);
  const int d_time = nc.defDim("time", 0);
  std::vector<int> horiz;  // horizontal dims of a 2-D field
  const NativeGrid& grid = sampler.impl_->grid;
  int id_lon = -1, id_lat = -1, id_clon = -1, id_clat = -1, id_clonb = -1, id_clatb = -1;
  if (native) {
    truth.ncells = static_cast<std::int64_t>(grid.clon.size());
    const int d_cells = nc.defDim("ncells", grid.clon.size());
    const int d_vert = nc.defDim("vertices", 3);
    horiz = {d_cells};
    id_clon = nc.defVar("clon", NC_DOUBLE, {d_cells});
    nc.attText(id_clon, "standard_name", "longitude");
    nc.attText(id_clon, "long_name", "center longitude");
    nc.attText(id_clon, "units", "radian");
    nc.attText(id_clon, "bounds", "clon_bnds");
    id_clat = nc.defVar("clat", NC_DOUBLE, {d_cells});
    nc.attText(id_clat, "standard_name", "latitude");
    nc.attText(id_clat, "long_name", "center latitude");
    nc.attText(id_clat, "units", "radian");
    nc.attText(id_clat, "bounds", "clat_bnds");
    id_clonb = nc.defVar("clon_bnds", NC_DOUBLE, {d_cells, d_vert});
    id_clatb = nc.defVar("clat_bnds", NC_DOUBLE, {d_cells, d_vert});
  } else {
    const int d_lon = nc.defDim("lon", std::size_t(spec.nlon));
    const int d_lat = nc.defDim("lat", std::size_t(spec.nlat));
    horiz = {d_lat, d_lon};
    id_lon = nc.defVar("lon", NC_DOUBLE, {d_lon});
    nc.attText(id_lon, "standard_name", "longitude");
    nc.attText(id_lon, "long_name", "longitude");
    nc.attText(id_lon, "units", "degrees_east");
    nc.attText(id_lon, "axis", "X");
    id_lat = nc.defVar("lat", NC_DOUBLE, {d_lat});
    nc.attText(id_lat, "standard_name", "latitude");
    nc.attText(id_lat, "long_name", "latitude");
    nc.attText(id_lat, "units", "degrees_north");
    nc.attText(id_lat, "axis", "Y");
  }
  const int d_h = nc.defDim("height", std::size_t(spec.nz));
  const int d_h2 = nc.defDim("height_2", std::size_t(spec.nz + 1));
  const int d_bnds = nc.defDim("bnds", 2);
  const int id_time = nc.defVar("time", NC_DOUBLE, {d_time});
  nc.attText(id_time, "standard_name", "time");
  if (native) {
    nc.attText(id_time, "units", "day as %Y%m%d.%f");  // ICON's absolute time axis
  } else {
    nc.attText(id_time, "units", "hours since 2026-03-18 12:00:00");
  }
  nc.attText(id_time, "calendar", "proleptic_gregorian");
  nc.attText(id_time, "axis", "T");
  const int id_height = nc.defVar("height", NC_DOUBLE, {d_h});
  nc.attText(id_height, "long_name", "generalized_height");
  nc.attText(id_height, "axis", "Z");
  nc.attText(id_height, "bounds", "height_bnds");
  const int id_height_bnds = nc.defVar("height_bnds", NC_DOUBLE, {d_h, d_bnds});
  const int id_height2 = nc.defVar("height_2", NC_DOUBLE, {d_h2});
  nc.attText(id_height2, "long_name", "generalized_height");
  nc.attText(id_height2, "axis", "Z");

  std::map<std::string, int> ids;
  for (const FieldDef& f : kFields) {
    const bool half = std::string(f.name) == "z_ifc";
    std::vector<int> dims;
    if (!half) dims.push_back(d_time);  // z_ifc is time-constant and written without time
    dims.push_back(half ? d_h2 : d_h);
    dims.insert(dims.end(), horiz.begin(), horiz.end());
    const int id = nc.defVar(f.name, NC_FLOAT, dims);
    nc.attText(id, "standard_name", f.standard_name);
    nc.attText(id, "long_name", f.long_name);
    nc.attText(id, "units", f.units);
    nc.attText(id, "param", f.param);
    if (native) {
      nc.attText(id, "CDI_grid_type", "unstructured");
      nc.attInt(id, "number_of_grid_in_reference", 1);
      nc.attText(id, "coordinates", "clat clon");
    }
    ids[f.name] = id;
  }
  nc.attText(NC_GLOBAL, "CDI", "Climate Data Interface version 2.1.1 (https://mpimet.mpg.de/cdi)");
  nc.attText(NC_GLOBAL, "Conventions", "CF-1.6");
  nc.attText(NC_GLOBAL, "title", "ICON-like cloud scene (stratus deck, scattered cumulus, thin cirrus)");
  nc.attText(NC_GLOBAL, "institution", "nephele-gen (synthetic)");
  nc.attText(NC_GLOBAL, "source", fmt::format("nephele-gen icon, seed {}", spec.seed));
  if (native) {
    nc.attInt(NC_GLOBAL, "number_of_grid_used", 47);
    nc.attText(NC_GLOBAL, "grid_file_uri", "synthetic: regional cut of a subdivided icosahedron");
    nc.attText(NC_GLOBAL, "uuidOfHGrid", "00000000-0000-0000-0000-000000000000");
  } else {
    nc.attText(NC_GLOBAL, "history", "cdo -f nc copy icon-d2_regular-lat-lon_model-level.grib2 out.nc (emulated)");
  }
  nc.endDef();

  // Coordinates.
  const std::vector<double>& lats = sampler.latAxisDeg();
  const std::vector<double>& lons = sampler.lonAxisDeg();
  if (native) {
    const std::size_t nc_cells = grid.clon.size();
    nc.putDouble(id_clon, {0}, {nc_cells}, grid.clon.data());
    nc.putDouble(id_clat, {0}, {nc_cells}, grid.clat.data());
    std::vector<double> bl(nc_cells * 3), bt(nc_cells * 3);
    for (std::size_t c = 0; c < nc_cells; ++c) {
      for (std::size_t v = 0; v < 3; ++v) {
        bl[c * 3 + v] = grid.vlon[c][v];
        bt[c * 3 + v] = grid.vlat[c][v];
      }
    }
    nc.putDouble(id_clonb, {0, 0}, {nc_cells, 3}, bl.data());
    nc.putDouble(id_clatb, {0, 0}, {nc_cells, 3}, bt.data());
  } else {
    nc.putDouble(id_lon, {0}, {lons.size()}, lons.data());
    nc.putDouble(id_lat, {0}, {lats.size()}, lats.data());
  }
  {
    std::vector<double> h(std::size_t(spec.nz)), hb(std::size_t(spec.nz) * 2), h2(std::size_t(spec.nz + 1));
    for (int k = 0; k < spec.nz; ++k) {
      h[std::size_t(k)] = k + 1;
      hb[std::size_t(k) * 2] = k + 1;
      hb[std::size_t(k) * 2 + 1] = k + 2;
    }
    for (int k = 0; k <= spec.nz; ++k) h2[std::size_t(k)] = k + 1;
    nc.putDouble(id_height, {0}, {h.size()}, h.data());
    nc.putDouble(id_height_bnds, {0, 0}, {h.size(), 2}, hb.data());
    nc.putDouble(id_height2, {0}, {h2.size()}, h2.data());
  }

  for (int t = 0; t < spec.ntimes; ++t) {
    const double hours = t;
    std::map<std::string, std::vector<float>> out = sampler.fields(t, &truth);
    const geo::CivilTime now = sampler.time(t).civil();
    const double time_value = native ? now.year * 10000.0 + now.month * 100.0 + now.day + now.hour / 24.0 : hours;
    nc.putDouble(id_time, {std::size_t(t)}, {1}, &time_value);
    for (const FieldDef& f : kFields) {
      const bool half = std::string(f.name) == "z_ifc";
      if (half && t > 0) continue;
      const std::vector<float>& data = out[f.name];
      std::vector<std::size_t> start_idx, count;
      if (!half) {
        start_idx.push_back(std::size_t(t));
        count.push_back(1);
      }
      start_idx.push_back(0);
      count.push_back(half ? std::size_t(spec.nz + 1) : std::size_t(spec.nz));
      if (native) {
        start_idx.push_back(0);
        count.push_back(sampler.points());
      } else {
        start_idx.insert(start_idx.end(), {0, 0});
        count.insert(count.end(), {std::size_t(spec.nlat), std::size_t(spec.nlon)});
      }
      nc.putFloat(ids[f.name], start_idx, count, data.data());
    }
  }
  nc.close();
  return truth;
}

}  // namespace nph::datagen
