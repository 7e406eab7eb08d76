#pragma once
// Settings of the optics stage: per hydrometeor class the particle density and effective radius
// of Nes 2008 eq. 5.3, how number concentrations turn into radii, the WRF schemes whose
// condensate is split by temperature, and the ICON condensate corrections (Muth 2026 §3.3.1).
// Two named presets: "default" (literature values below) and "nes2008" (Nes 2008 table 5.1).
#include <array>
#include <string>
#include <vector>

#include "io/model_fields.h"

namespace nph::physics {

using io::Hydrometeor;

/// Optical model of one hydrometeor class: spheres of bulk density ρ_f and effective radius r_f
/// in the geometric-optics limit (Q_ext = 2, Nes 2008 §2.2.2 eq. 2.4).
struct HydrometeorOptics {
  double effective_radius_m = 0.0;  ///< used when no number concentration is available
  double particle_density_kg_per_m3 = 0.0;
  /// Shape parameter μ of the gamma size distribution n(D) ∝ D^μ exp(-λD) assumed when r_eff is
  /// derived from mass and number (effective_radius.h).
  double gamma_shape = 0.0;
  double min_radius_m = 0.0;  ///< clamp of radii derived from number concentrations
  double max_radius_m = 0.0;
  bool ice_phase = false;  ///< counts towards the ice volume (else water)
};

/// Muth 2026 §3.3.1 "condensate consistency corrections" for ICON (both on by default).
struct IconCorrections {
  /// Correction 1: CLC_eff = max(CLC, min((qc+qi)/Q_crit, 1)) (Tompkins; Muth eq. 3.1).
  bool diagnose_cloud_cover = true;
  /// Correction 2: lower bound qc + qi >= Q_crit * CLC_eff, split by the ice fraction
  /// f_ice = clamp(-(T - 273.15 K) / 38 K, 0, 1), only where T > 180 K and p > 100 Pa.
  bool reconstruct_condensate = true;
  double critical_condensate_kg_per_kg = 3e-5;  ///< Q_crit (Muth eq. 3.1)
  double ice_ramp_k = 38.0;                     ///< f_ice reaches 1 at -38 °C (Muth §3.3.1)
  double min_temperature_k = 180.0;             ///< validity gate (Muth §3.3.1)
  double min_pressure_pa = 100.0;               ///< validity gate (Muth §3.3.1)
};

struct OpticsSettings {
  std::string preset = "default";
  std::array<HydrometeorOptics, io::kAllHydrometeors.size()> classes{};
  /// Derive r_eff from number concentrations (two-moment schemes) where the file has them.
  bool use_number_concentrations = true;
  /// WRF MP_PHYSICS values whose condensate is not split into ice and liquid arrays: below the
  /// freezing point QCLOUD is cloud ice and QRAIN is snow. WSM3 = 3 (Hong, Dudhia & Chen 2004,
  /// "simple ice": one array each for cloud water/ice and rain/snow, split at 0 °C). Kessler (1)
  /// is a warm-rain scheme: its condensate is liquid (supercooled) at all temperatures, so it is
  /// not listed. Every other WRF scheme writes ice in separate arrays (QICE, QSNOW, ...).
  std::vector<int> temperature_split_schemes = {3};
  IconCorrections icon;

  HydrometeorOptics& operator[](Hydrometeor h) { return classes[static_cast<std::size_t>(h)]; }
  const HydrometeorOptics& operator[](Hydrometeor h) const { return classes[static_cast<std::size_t>(h)]; }

  /// The settings as a JSON object (stored in the .nph index as provenance).
  std::string toJson() const;
};

/// "default": physically based effective radii (sources in optics_settings.cpp).
OpticsSettings defaultOptics();
/// "nes2008": Nes 2008 table 5.1 radii (cloud 0.01 mm, ice 1 mm, rain 1 mm, snow 2 mm,
/// graupel 2.5 mm), fixed radii (no number concentrations).
OpticsSettings nes2008Optics();
/// A preset by name; UsageError listing the known names otherwise.
OpticsSettings opticsPreset(const std::string& name);
std::vector<std::string> opticsPresetNames();

/// "cloud", "rain", "ice", "snow", "graupel", "hail".
const char* hydrometeorName(Hydrometeor h);
Hydrometeor hydrometeorFromName(const std::string& name);  ///< UsageError when unknown

/// Applies "class=value[unit]" (unit um, mm or m; default m), e.g. "snow=400um", to the
/// effective radius of that class. UsageError on malformed text.
void applyRadiusOverride(OpticsSettings& settings, const std::string& assignment);

}  // namespace nph::physics
