#include "physics/optics_settings.h"

#include <fmt/format.h>

#include <cstdlib>
#include <nlohmann/json.hpp>

#include "core/error.h"
#include "physics/constants.h"

namespace nph::physics {

namespace {

constexpr double kMicrometre = 1e-6;
constexpr double kMillimetre = 1e-3;

HydrometeorOptics make(double r_m, double rho, double mu, double r_min, double r_max, bool ice) {
  HydrometeorOptics o;
  o.effective_radius_m = r_m;
  o.particle_density_kg_per_m3 = rho;
  o.gamma_shape = mu;
  o.min_radius_m = r_min;
  o.max_radius_m = r_max;
  o.ice_phase = ice;
  return o;
}

}  // namespace

OpticsSettings defaultOptics() {
  OpticsSettings s;
  s.preset = "default";
  // Cloud droplets: r_eff ≈ 10 µm; observed 4-17 µm in stratiform and cumulus clouds (Miles,
  // Verlinde & Clothiaux 2000, J. Atmos. Sci. 57; Stephens 1978); Muth 2026 §3.3.1 clamps to
  // [4, 15] µm. μ = 5 gives (r_vol/r_eff)^3 = 0.66, the continental k of Martin, Johnson & Spice
  // (1994, J. Atmos. Sci. 51).
  s[Hydrometeor::Cloud] = make(10 * kMicrometre, kDensityWater, 5.0, 2 * kMicrometre, 50 * kMicrometre, false);
  // Rain: exponential (Marshall & Palmer 1948, J. Meteor. 5) with λ = 4.1 R^-0.21 mm⁻¹; at
  // R = 5 mm/h λ ≈ 2.9 mm⁻¹ and r_eff = 3/(2λ) ≈ 0.5 mm.
  s[Hydrometeor::Rain] = make(0.5 * kMillimetre, kDensityWater, 0.0, 50 * kMicrometre, 3 * kMillimetre, false);
  // Cloud ice: r_eff ≈ 30 µm, typical of cirrus and anvils (Heymsfield & Platt 1984, J. Atmos.
  // Sci. 41; Muth 2026 §3.3.1 clamps Sun & Rikus radii to [10, 150] µm); solid-ice spheres.
  s[Hydrometeor::Ice] = make(30 * kMicrometre, kDensityIce, 0.0, 5 * kMicrometre, 250 * kMicrometre, true);
  // Snow: aggregates of bulk density ≈ 100 kg/m³ (Rutledge & Hobbs 1983, J. Atmos. Sci. 40;
  // Locatelli & Hobbs 1974 measure 0.05-0.2 g/cm³), exponential sizes (Gunn & Marshall 1958)
  // with r_eff of a few hundred µm: 0.5 mm.
  s[Hydrometeor::Snow] = make(0.5 * kMillimetre, 100.0, 0.0, 50 * kMicrometre, 5 * kMillimetre, true);
  // Graupel: bulk density 400 kg/m³ and N0 = 4e6 m⁻⁴ (Rutledge & Hobbs 1984, J. Atmos. Sci. 41);
  // at 1 g/m³ λ = (π ρ_g N0 / C)^(1/4) ≈ 1.5 mm⁻¹, so r_eff = 3/(2λ) ≈ 1 mm.
  s[Hydrometeor::Graupel] = make(1.0 * kMillimetre, 400.0, 0.0, 100 * kMicrometre, 5 * kMillimetre, true);
  // Hail: density 900 kg/m³ (Milbrandt & Yau 2005, J. Atmos. Sci. 62), diameters of 5-10 mm:
  // r_eff 2.5 mm.
  s[Hydrometeor::Hail] = make(2.5 * kMillimetre, 900.0, 0.0, 0.5 * kMillimetre, 25 * kMillimetre, true);
  return s;
}

OpticsSettings nes2008Optics() {
  // Nes 2008 table 5.1 (after Pruppacher & Klett): radii only. The table gives no particle
  // densities; eq. 5.3 is read with solid spheres: liquid water for cloud and rain, solid ice
  // for the frozen classes. Hail is not in the table and takes graupel's radius.
  OpticsSettings s = defaultOptics();
  s.preset = "nes2008";
  s.use_number_concentrations = false;
  s[Hydrometeor::Cloud].effective_radius_m = 0.01 * kMillimetre;
  s[Hydrometeor::Ice].effective_radius_m = 1.0 * kMillimetre;
  s[Hydrometeor::Rain].effective_radius_m = 1.0 * kMillimetre;
  s[Hydrometeor::Snow].effective_radius_m = 2.0 * kMillimetre;
  s[Hydrometeor::Graupel].effective_radius_m = 2.5 * kMillimetre;
  s[Hydrometeor::Hail].effective_radius_m = 2.5 * kMillimetre;
  for (Hydrometeor h : {Hydrometeor::Ice, Hydrometeor::Snow, Hydrometeor::Graupel, Hydrometeor::Hail}) {
    s[h].particle_density_kg_per_m3 = kDensityIce;
  }
  return s;
}

std::vector<std::string> opticsPresetNames() { return {"default", "nes2008"}; }

OpticsSettings opticsPreset(const std::string& name) {
  if (name == "default") return defaultOptics();
  if (name == "nes2008") return nes2008Optics();
  throw UsageError(fmt::format("unknown optics preset '{}' (known: default, nes2008)", name));
}

const char* hydrometeorName(Hydrometeor h) {
  switch (h) {
    case Hydrometeor::Cloud: return "cloud";
    case Hydrometeor::Rain: return "rain";
    case Hydrometeor::Ice: return "ice";
    case Hydrometeor::Snow: return "snow";
    case Hydrometeor::Graupel: return "graupel";
    case Hydrometeor::Hail: return "hail";
  }
  return "?";
}

Hydrometeor hydrometeorFromName(const std::string& name) {
  for (Hydrometeor h : io::kAllHydrometeors) {
    if (name == hydrometeorName(h)) return h;
  }
  throw UsageError(fmt::format("unknown hydrometeor class '{}' (known: cloud, rain, ice, snow, graupel, hail)", name));
}

void applyRadiusOverride(OpticsSettings& settings, const std::string& assignment) {
  const auto eq = assignment.find('=');
  if (eq == std::string::npos) {
    throw UsageError(fmt::format("radius override '{}': expected CLASS=VALUE[um|mm|m]", assignment));
  }
  const Hydrometeor h = hydrometeorFromName(assignment.substr(0, eq));
  const std::string value = assignment.substr(eq + 1);
  char* end = nullptr;
  const double number = std::strtod(value.c_str(), &end);
  const std::string unit(end);
  double factor = 0.0;
  if (unit.empty() || unit == "m") factor = 1.0;
  else if (unit == "mm") factor = kMillimetre;
  else if (unit == "um" || unit == "µm") factor = kMicrometre;
  const double radius = number * factor;
  if (end == value.c_str() || factor == 0.0 || !(radius > 0.0) || radius > 0.1) {
    throw UsageError(
        fmt::format("radius override '{}': expected a radius between 0 and 10 cm with unit um, mm or m", assignment));
  }
  settings[h].effective_radius_m = radius;
  settings.preset += "+" + assignment;
}

std::string OpticsSettings::toJson() const {
  nlohmann::json j;
  j["preset"] = preset;
  j["equation"] = "beta = 3 rho_air q / (2 rho_particle r_eff) (Nes 2008 eq. 5.3)";
  j["use_number_concentrations"] = use_number_concentrations;
  j["temperature_split_schemes"] = temperature_split_schemes;
  for (Hydrometeor h : io::kAllHydrometeors) {
    const HydrometeorOptics& o = (*this)[h];
    j["classes"][hydrometeorName(h)] = {{"effective_radius_m", o.effective_radius_m},
                                        {"particle_density_kg_per_m3", o.particle_density_kg_per_m3},
                                        {"gamma_shape", o.gamma_shape},
                                        {"min_radius_m", o.min_radius_m},
                                        {"max_radius_m", o.max_radius_m},
                                        {"volume", o.ice_phase ? "ice" : "water"}};
  }
  j["icon_corrections"] = {{"diagnose_cloud_cover", icon.diagnose_cloud_cover},
                           {"reconstruct_condensate", icon.reconstruct_condensate},
                           {"critical_condensate_kg_per_kg", icon.critical_condensate_kg_per_kg},
                           {"ice_ramp_k", icon.ice_ramp_k}};
  return j.dump();
}

}  // namespace nph::physics
