#pragma once
// The air density that turns a model's mixing ratio q into a mass content C = ρ_ref · q
// (Nes 2008 §2.2.3 eq. 2.5; Muth 2026 §3.3.1 eq. 3.2-3.3), derived from the model's own p, T, q.
//
// Partial pressures: p = ρ_d R_d T + ρ_v R_v T (condensate occupies no pressure). Then:
//
// WRF: q_x = ρ_x / ρ_d is per kg of DRY air (r_v = QVAPOR likewise), so the reference density is
//   the dry-air density:  p = ρ_d R_d T (1 + r_v/ε)  ⇒  ρ_d = p / (R_d T (1 + r_v/ε)),
//   ε = R_d/R_v. (This is WRF's own 1/ALT.)
// ICON: q_x = ρ_x / ρ is specific (per kg of MOIST air including condensate), so the reference
//   density is the total density ρ = ρ_d + ρ_v + Σρ_x. With q_d = 1 - q_v - q_c,
//   p = ρ T (R_d q_d + R_v q_v) = ρ R_d T (1 + (1/ε - 1) q_v - q_c)  ⇒  ρ = p / (R_d T_ρ),
//   T_ρ = T (1 + 0.608 q_v - q_c) (density temperature, as ICON's own `tempv` diagnostic).
//   Muth's eq. 3.2, T_v = T (1 + 0.608 q_v), is this without condensate loading (< 1 % apart).
namespace nph::physics {

/// ρ_d [kg/m³] from p [Pa], T [K] and the vapour mixing ratio r_v [kg/kg dry air] (WRF).
double dryAirDensity(double pressure_pa, double temperature_k, double vapour_mixing_ratio);

/// ρ [kg/m³] of moist air with condensate from p, T, specific humidity q_v and the specific
/// condensate content q_c = Σ q_x [kg/kg moist air] (ICON).
double moistAirDensity(double pressure_pa, double temperature_k, double specific_humidity, double specific_condensate);

}  // namespace nph::physics
