#include "atmosphere.h"

#include <algorithm>
#include <array>
#include <cmath>

namespace nph::datagen {
namespace {

/// Layers of the 1976 U.S. Standard Atmosphere below 32 km: base height [m], base temperature
/// [K], lapse rate dT/dz [K/m], base pressure [Pa] (NOAA/NASA/USAF 1976, table 4).
struct Layer {
  double base_m, base_k, lapse_k_per_m, base_pa;
};
constexpr std::array<Layer, 3> kLayers = {
    {{0.0, 288.15, -0.0065, 101325.0}, {11000.0, 216.65, 0.0, 22632.06}, {20000.0, 216.65, 0.001, 5474.889}}};
constexpr double kTopOfTable_m = 32000.0;

const Layer& layerForHeight(double z) {
  if (z >= kLayers[2].base_m) return kLayers[2];
  if (z >= kLayers[1].base_m) return kLayers[1];
  return kLayers[0];
}

double pressureInLayer(const Layer& l, double z) {
  constexpr double g_over_r = kStdGravity_m_per_s2 / kStdGasConstantDryAir_J_per_kgK;
  if (l.lapse_k_per_m == 0.0) return l.base_pa * std::exp(-g_over_r * (z - l.base_m) / l.base_k);
  const double t = l.base_k + l.lapse_k_per_m * (z - l.base_m);
  return l.base_pa * std::pow(t / l.base_k, -g_over_r / l.lapse_k_per_m);
}

std::uint64_t splitmix64(std::uint64_t x) {
  x += 0x9E3779B97F4A7C15ull;
  x = (x ^ (x >> 30)) * 0xBF58476D1CE4E5B9ull;
  x = (x ^ (x >> 27)) * 0x94D049BB133111EBull;
  return x ^ (x >> 31);
}

double smooth(double t) { return t * t * (3.0 - 2.0 * t); }

}  // namespace

double standardTemperatureK(double height_m) {
  const double z = std::clamp(height_m, -1000.0, kTopOfTable_m);
  const Layer& l = layerForHeight(z);
  return l.base_k + l.lapse_k_per_m * (z - l.base_m);
}

double standardPressurePa(double height_m) {
  const double z = std::min(height_m, kTopOfTable_m);
  return pressureInLayer(layerForHeight(z), z);
}

double standardHeightM(double pressure_pa) {
  constexpr double r_over_g = kStdGasConstantDryAir_J_per_kgK / kStdGravity_m_per_s2;
  const Layer& l = pressure_pa <= kLayers[2].base_pa   ? kLayers[2]
                   : pressure_pa <= kLayers[1].base_pa ? kLayers[1]
                                                       : kLayers[0];
  if (l.lapse_k_per_m == 0.0) return l.base_m - r_over_g * l.base_k * std::log(pressure_pa / l.base_pa);
  const double t = l.base_k * std::pow(pressure_pa / l.base_pa, -l.lapse_k_per_m * r_over_g);
  return l.base_m + (t - l.base_k) / l.lapse_k_per_m;
}

double saturationVapourPressurePa(double temperature_k) {
  // Bolton (1980), Mon. Wea. Rev. 108, eq. 10: e_s = 611.2 Pa * exp(17.67 T_c / (T_c + 243.5)).
  const double tc = temperature_k - kFreezingPoint_k;
  return 611.2 * std::exp(17.67 * tc / (tc + 243.5));
}

double ValueNoise::hash(std::int64_t a, std::int64_t b, std::int64_t c) const {
  std::uint64_t h = splitmix64(seed_);
  h = splitmix64(h ^ static_cast<std::uint64_t>(a));
  h = splitmix64(h ^ static_cast<std::uint64_t>(b));
  h = splitmix64(h ^ static_cast<std::uint64_t>(c));
  return static_cast<double>(h >> 11) * 0x1.0p-53;
}

double ValueNoise::at(double x, double y, double z) const {
  const double fx = std::floor(x), fy = std::floor(y), fz = std::floor(z);
  const auto ix = static_cast<std::int64_t>(fx), iy = static_cast<std::int64_t>(fy), iz = static_cast<std::int64_t>(fz);
  const double tx = smooth(x - fx), ty = smooth(y - fy), tz = smooth(z - fz);
  double result = 0.0;
  for (int c = 0; c < 8; ++c) {
    const int dx = c & 1, dy = (c >> 1) & 1, dz = (c >> 2) & 1;
    const double w = (dx ? tx : 1.0 - tx) * (dy ? ty : 1.0 - ty) * (dz ? tz : 1.0 - tz);
    result += w * hash(ix + dx, iy + dy, iz + dz);
  }
  return result;
}

double ValueNoise::fbm(double x, double y, double z, int octaves) const {
  double sum = 0.0, amplitude = 1.0, norm = 0.0, scale = 1.0;
  for (int o = 0; o < octaves; ++o) {
    sum += amplitude * at(x * scale + 17.0 * o, y * scale - 31.0 * o, z * scale + 7.0 * o);
    norm += amplitude;
    amplitude *= 0.5;
    scale *= 2.0;
  }
  return std::min(sum / norm, 0.999999);
}

}  // namespace nph::datagen
