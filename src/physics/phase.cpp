#include "physics/phase.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <mutex>
#include <numbers>
#include <string>

#include "core/error.h"

namespace nph::physics {
namespace {

constexpr double kInv4Pi = 1.0 / (4.0 * std::numbers::pi);

void checkAsymmetry(double g, const char* who) {
  if (!(g > -1.0 && g < 1.0)) {
    throw UsageError(std::string(who) + ": asymmetry parameter g = " + std::to_string(g) + ", expected -1 < g < 1");
  }
}

// 8-point Gauss–Legendre nodes and weights on [-1, 1] (Abramowitz & Stegun 1964, Table 25.4).
constexpr std::array<double, 4> kGaussX{0.1834346424956498, 0.5255324099163290, 0.7966664774136267, 0.9602898564975363};
constexpr std::array<double, 4> kGaussW{0.3626837833783620, 0.3137066458778873, 0.2223810344533745, 0.1012285362903763};

template <class F>
double gauss8(F&& f, double a, double b) {
  const double mid = 0.5 * (a + b), half = 0.5 * (b - a);
  double s = 0.0;
  for (std::size_t i = 0; i < kGaussX.size(); ++i) {
    s += kGaussW[i] * (f(mid - half * kGaussX[i]) + f(mid + half * kGaussX[i]));
  }
  return s * half;
}

}  // namespace

double henyeyGreenstein(double cos_psi, double g) {
  const double denom = 1.0 + g * g - 2.0 * g * cos_psi;
  return kInv4Pi * (1.0 - g * g) / (denom * std::sqrt(denom));
}

double cornetteShanks(double cos_psi, double g) {
  const double denom = 1.0 + g * g - 2.0 * g * cos_psi;
  return kInv4Pi * 3.0 * (1.0 - g * g) / (2.0 * (2.0 + g * g)) * (1.0 + cos_psi * cos_psi) / (denom * std::sqrt(denom));
}

// CP_HG(θ) = 2π ∫_c^1 p_HG(μ) dμ with c = cos θ. Since d/dμ (1 + g² − 2gμ)^{-1/2} = g (…)^{-3/2},
//     CP = (1 − g²)/(2g) · [1/(1 − g) − 1/s],        s = √(1 + g² − 2gc).
// This cancels catastrophically for small g and small θ; with s² − (1 − g)² = 2g(1 − c) it becomes
//     CP = (1 + g)(1 − c) / (s (s + 1 − g)),         1 − c = 2 sin²(θ/2),
// exact for every g in (−1, 1) (g = 0 gives (1 − c)/2, the isotropic value).
double henyeyGreensteinCumulative(double theta_rad, double g) {
  const double theta = std::clamp(theta_rad, 0.0, std::numbers::pi);
  const double sinHalf = std::sin(0.5 * theta);
  const double oneMinusC = 2.0 * sinHalf * sinHalf;
  const double s = std::sqrt((1.0 - g) * (1.0 - g) + 2.0 * g * oneMinusC);
  return (1.0 + g) * oneMinusC / (s * (s + 1.0 - g));
}

// Inverse of the HG CDF in μ (from the closed form above): for |g| > 1e-6
//     μ = (1 + g² − ((1 − g²)/(1 − g + 2gu))²) / (2g),
// u = 1 ↦ μ = 1 (forward); isotropic 2u − 1 below. (Pharr, Jakob & Humphreys, PBRT 4th ed. §11.3.1)
double sampleHenyeyGreenstein(double u, double g) {
  if (std::abs(g) < 1e-6) return 2.0 * u - 1.0;
  const double t = (1.0 - g * g) / (1.0 - g + 2.0 * g * u);
  return std::clamp((1.0 + g * g - t * t) / (2.0 * g), -1.0, 1.0);
}

double PhaseFunction::eval(double cos_psi) const {
  return model == PhaseModel::HenyeyGreenstein ? henyeyGreenstein(cos_psi, g) : cornetteShanks(cos_psi, g);
}

CumulativePhaseTable::CumulativePhaseTable(PhaseFunction phase, double tolerance) : phase_(phase) {
  checkAsymmetry(phase.g, "CumulativePhaseTable");
  if (!(tolerance > 0.0)) throw UsageError("CumulativePhaseTable: tolerance must be positive");
  const auto dcp = [this](double t) { return derivative(t); };
  constexpr std::size_t kMaxIntervals = std::size_t(1) << 20;
  for (std::size_t n = 256;; n *= 2) {
    h_ = std::numbers::pi / double(n);
    cp_.assign(n + 1, 0.0);
    dcp_.assign(n + 1, 0.0);
    for (std::size_t i = 0; i <= n; ++i) dcp_[i] = derivative(double(i) * h_);
    max_error_ = 0.0;
    for (std::size_t i = 0; i < n; ++i) {
      const double a = double(i) * h_, b = a + h_, mid = a + 0.5 * h_;
      // Integrate the two halves separately so the midpoint value doubles as the error check.
      const double toMid = gauss8(dcp, a, mid);
      cp_[i + 1] = cp_[i] + toMid + gauss8(dcp, mid, b);
      max_error_ = std::max(max_error_, std::abs((*this)(mid) - (cp_[i] + toMid)));
    }
    if (max_error_ < tolerance) break;
    if (n >= kMaxIntervals) {
      throw UsageError("CumulativePhaseTable: g = " + std::to_string(phase.g) + " needs more than " +
                       std::to_string(kMaxIntervals) + " intervals for tolerance " + std::to_string(tolerance));
    }
  }
}

double CumulativePhaseTable::derivative(double theta_rad) const {
  return 2.0 * std::numbers::pi * phase_.eval(std::cos(theta_rad)) * std::sin(theta_rad);
}

double CumulativePhaseTable::operator()(double theta_rad) const {
  const double theta = std::clamp(theta_rad, 0.0, std::numbers::pi);
  const std::size_t last = cp_.size() - 1;
  const double x = theta / h_;
  const std::size_t i = std::min(std::size_t(x), last - 1);
  const double t = std::clamp(x - double(i), 0.0, 1.0);
  // Cubic Hermite basis on [i, i+1] with derivatives scaled by the spacing.
  const double t2 = t * t, t3 = t2 * t;
  const double h00 = 2.0 * t3 - 3.0 * t2 + 1.0, h10 = t3 - 2.0 * t2 + t;
  const double h01 = -2.0 * t3 + 3.0 * t2, h11 = t3 - t2;
  return h00 * cp_[i] + h10 * h_ * dcp_[i] + h01 * cp_[i + 1] + h11 * h_ * dcp_[i + 1];
}

double cumulativePhase(const PhaseFunction& phase, double theta_rad) {
  if (phase.model == PhaseModel::HenyeyGreenstein) {
    checkAsymmetry(phase.g, "cumulativePhase");
    return henyeyGreensteinCumulative(theta_rad, phase.g);
  }
  static std::mutex mutex;
  static std::map<double, std::unique_ptr<CumulativePhaseTable>> tables;
  const CumulativePhaseTable* table = nullptr;
  {
    std::lock_guard lock(mutex);
    auto& slot = tables[phase.g];
    if (!slot) slot = std::make_unique<CumulativePhaseTable>(phase);
    table = slot.get();
  }
  return (*table)(theta_rad);
}

}  // namespace nph::physics
