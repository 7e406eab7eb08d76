#include "accuracy/octave_fit.h"

#include <chrono>
#include <cmath>
#include <filesystem>
#include <limits>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "core/error.h"
#include "core/log.h"
#include "reference/ray_marcher.h"

namespace nph::accuracy {
namespace {

// Optical-depth bins: bin 0 is τ = 0 (I = 1), bins 1..kBins log-spaced over [kTauMin, kTauMax].
constexpr int kBins = 128;
constexpr double kTauMin = 1e-3, kTauMax = 1e4;
const double kLogStep = std::log(kTauMax / kTauMin) / (kBins - 1);

double binTau(int bin) { return bin == 0 ? 0.0 : kTauMin * std::exp(kLogStep * (bin - 1)); }

// Grids of the search. N octaves: the series is evaluated for N = 1 … kMaxOctaves at once.
constexpr int kMaxOctaves = 12;
std::vector<double> grid(double lo, double hi, double step) {
  std::vector<double> g;
  for (double x = lo; x <= hi + 1e-9; x += step) g.push_back(x);
  return g;
}

// One scene's per-pixel data: α, ψ and the weight histograms over the sunlight's optical depth.
struct SceneSamples {
  std::string name;
  int pixels = 0;
  double y_sun = 0.0;  // luminance of E
  std::vector<double> alpha, cos_psi, y_truth, sigma_truth;
  std::vector<double> y_sky;                // luminance of the sky light each pixel gathers (not fitted)
  std::vector<float> hist_ice, hist_water;  // [pixel][bin]
};

void addToHistogram(float* hist, double sunlight, double weight) {
  const double tau = sunlight >= 1.0 ? 0.0 : (sunlight > 0.0 ? -std::log(sunlight) : kTauMax);
  if (tau < kTauMin) {  // between τ = 0 (bin 0) and kTauMin (bin 1), linear in τ
    const double f = tau / kTauMin;
    hist[0] += float(weight * (1.0 - f));
    hist[1] += float(weight * f);
    return;
  }
  const double x = std::min(std::log(tau / kTauMin) / kLogStep, double(kBins - 2));
  const int i = int(x);
  const double f = x - i;
  hist[1 + i] += float(weight * (1.0 - f));
  hist[2 + i] += float(weight * f);
}

// ½wᵀGw − hᵀw + c0/2 over w_1 … w_{N−1} ≥ 0 (G lower triangle filled, index n·kMaxOctaves + m).
struct NormalEquations {
  std::vector<double> g = std::vector<double>(kMaxOctaves * kMaxOctaves, 0.0);
  std::vector<double> h = std::vector<double>(kMaxOctaves, 0.0);
  double c0 = 0.0;
  double gram(int n, int m) const {
    return n >= m ? g[std::size_t(n * kMaxOctaves + m)] : g[std::size_t(m * kMaxOctaves + n)];
  }
  /// Non-negative least squares by cyclic coordinate descent (convex; 12 unknowns). Returns the
  /// objective Σ r² (normalised) at the solution.
  double solve(std::vector<double>& w) const {
    w.assign(kMaxOctaves, 0.0);
    w[0] = 1.0;
    for (int sweep = 0; sweep < 500; ++sweep) {
      double change = 0.0;
      for (int n = 1; n < kMaxOctaves; ++n) {
        if (!(gram(n, n) > 0.0)) continue;
        double rest = h[std::size_t(n)];
        for (int m = 1; m < kMaxOctaves; ++m)
          if (m != n) rest -= gram(n, m) * w[std::size_t(m)];
        const double next = std::max(0.0, rest / gram(n, n));
        change = std::max(change, std::abs(next - w[std::size_t(n)]));
        w[std::size_t(n)] = next;
      }
      if (change < 1e-9) break;
    }
    double obj = c0;
    for (int n = 1; n < kMaxOctaves; ++n) {
      obj -= 2.0 * h[std::size_t(n)] * w[std::size_t(n)];
      for (int m = 1; m < kMaxOctaves; ++m) obj += w[std::size_t(n)] * gram(n, m) * w[std::size_t(m)];
    }
    return obj;
  }
};

}  // namespace

OctaveFitResult fitOctaveSeries(const SweepOptions& o) {
  const std::string cacheDir = groundTruthCacheDir(o);
  const SceneSet set = sweepScenes(o);
  const Variant base = defaultVariant();
  const reference::RayMarchSettings march = base.render;

  // 1. Per scene: truth, converged light, binned samples.
  std::vector<SceneSamples> data;
  std::vector<const AccuracyScene*> used;
  std::vector<GroundTruth> truths;
  std::vector<std::unique_ptr<reference::DlmReference>> lights;
  std::vector<render::VolumeTextures> textures;
  for (const AccuracyScene& sc : set.scenes) {
    if (!o.scene_filter.empty() && sc.name.find(o.scene_filter) == std::string::npos) continue;
    truths.push_back(groundTruth(sc, base.render, o.ground_truth, cacheDir));
    const GroundTruth& gt = truths.back();
    log::info("{}: ground truth {} ({:.0f} s, noise rmse {:.3g}, {:.2g} of paths cut, {:.2g} rouletted)", sc.name,
              gt.from_cache ? "from cache" : "traced", gt.seconds, gt.noise_rmse, gt.truncated_share,
              gt.rouletted_share);
    textures.push_back(render::VolumeTextures::upload(*sc.volumes, sc.frame, sc.volume_name + "-octave-fit"));
    lights.push_back(convergedLight(base.dlm, textures.back(), sc));
    const reference::DlmReference& light = *lights.back();
    SceneSamples d;
    d.name = sc.name;
    d.pixels = sc.camera.width * sc.camera.height;
    const glm::dvec3 e = sc.sun.colour * sc.sun.intensity;
    d.y_sun = luminance(e.x, e.y, e.z);
    const lighting::SkyLight sky = lighting::skyLightFor(march, sc.sun.elevation_deg, sc.sun.colour, sc.sun.intensity);
    const ColumnDepths depths = columnDepths(*sc.volumes);
    d.y_sky.assign(std::size_t(d.pixels), 0.0);
    d.alpha.assign(std::size_t(d.pixels), 0.0);
    d.cos_psi.assign(std::size_t(d.pixels), 0.0);
    d.y_truth.resize(std::size_t(d.pixels));
    d.sigma_truth.resize(std::size_t(d.pixels));
    d.hist_ice.assign(std::size_t(d.pixels) * kBins, 0.0f);
    d.hist_water.assign(std::size_t(d.pixels) * kBins, 0.0f);
    for (int i = 0; i < d.pixels; ++i) {
      const float* p = &gt.image.rgba[4 * std::size_t(i)];
      d.y_truth[std::size_t(i)] = luminance(p[0], p[1], p[2]);
      const float* se = &gt.standard_error[3 * std::size_t(i)];
      d.sigma_truth[std::size_t(i)] = luminance(se[0], se[1], se[2]);
    }
    const glm::dvec3 lightDir = -sc.sun.toSun();
    const int w = sc.camera.width;
    reference::marchSamples(
        *sc.volumes, sc.frame, sc.camera, march.step_voxels, 0.0,
        [&](int x, int y, const glm::dvec3& dir, const reference::RaySample& s) {
          const std::size_t px = std::size_t(y) * std::size_t(w) + std::size_t(x);
          d.cos_psi[px] = glm::dot(lightDir, -dir);
          const double sunlight = light.intensityAt(s.position_m);
          addToHistogram(&d.hist_ice[px * kBins], sunlight, s.weight * s.ice_weight);
          addToHistogram(&d.hist_water[px * kBins], sunlight, s.weight * (1.0 - s.ice_weight));
          const glm::dvec3 l = s.weight * reference::sampleSkyLight(sky, depths, sc.frame, s, march);
          d.y_sky[px] += luminance(l.x, l.y, l.z);
        },
        [&](int x, int y, double T) { d.alpha[std::size_t(y) * std::size_t(w) + std::size_t(x)] = 1.0 - T; });
    data.push_back(std::move(d));
    used.push_back(&sc);
  }
  if (data.empty()) throw UsageError("accuracy --fit-octaves: no scene matches --scenes " + o.scene_filter);

  OctaveFitResult r;
  // 2. Grid search. err[a][c][b][N] summed over scenes (relMSE per scene, then mean).
  std::vector<double> as = grid(0.05, 0.95, 0.05), bs = grid(0.05, 0.95, 0.05);
  const std::vector<double> cs = grid(0.0, 1.0, 0.1);
  as.insert(as.begin(), {0.01, 0.02});
  as.push_back(0.98);
  bs.push_back(0.98);
  const std::size_t na = as.size(), nb = bs.size(), nc = cs.size();
  std::vector<double> err(na * nc * nb * kMaxOctaves, 0.0);
  std::vector<NormalEquations> normal(na * nc);
  auto at = [&](std::size_t ia, std::size_t ic, std::size_t ib, int n) -> double& {
    return err[((ia * nc + ic) * nb + ib) * kMaxOctaves + std::size_t(n)];
  };
  const double gIce = march.g_ice, gWater = march.g_water;
  for (const SceneSamples& d : data) {
    const auto start = std::chrono::steady_clock::now();
    const std::size_t P = std::size_t(d.pixels);
    double yTruthSq = 0.0;  // Σ (Y_ref² + 0.01): the scene's normaliser
    for (double y : d.y_truth) yTruthSq += y * y + 0.01;
    double noise = 0.0;
    for (double sigma : d.sigma_truth) noise += sigma * sigma;
    r.objective_noise_floor += noise / yTruthSq / double(data.size());
    std::vector<double> sIce(kMaxOctaves * P, 0.0), sWater(kMaxOctaves * P, 0.0), q(kMaxOctaves * P);
    std::vector<double> decay(kBins);
    for (std::size_t ia = 0; ia < na; ++ia) {
      // S_n(pixel) = Σ_bins H·e^{−aⁿτ}
      for (int n = 0; n < kMaxOctaves; ++n) {
        const double scale = std::pow(as[ia], n);
        for (int k = 0; k < kBins; ++k) decay[std::size_t(k)] = std::exp(-scale * binTau(k));
        for (std::size_t px = 0; px < P; ++px) {
          if (d.alpha[px] == 0.0) continue;  // nothing was hit: S stays 0
          const float* hi = &d.hist_ice[px * kBins];
          const float* hw = &d.hist_water[px * kBins];
          double si = 0.0, sw = 0.0;
          for (int k = 0; k < kBins; ++k) {
            si += double(hi[k]) * decay[std::size_t(k)];
            sw += double(hw[k]) * decay[std::size_t(k)];
          }
          sIce[std::size_t(n) * P + px] = si;
          sWater[std::size_t(n) * P + px] = sw;
        }
      }
      for (std::size_t ic = 0; ic < nc; ++ic) {
        for (int n = 0; n < kMaxOctaves; ++n) {
          const double aniso = std::pow(cs[ic], n);
          for (std::size_t px = 0; px < P; ++px) {
            q[std::size_t(n) * P + px] =
                sIce[std::size_t(n) * P + px] * lighting::hgPhase(d.cos_psi[px], aniso * gIce) +
                sWater[std::size_t(n) * P + px] * lighting::hgPhase(d.cos_psi[px], aniso * gWater);
          }
        }
        {  // normal equations of the free weights w_1 … w_{N−1} (w_0 = 1): r = Y_ref − Y_amb·α − Y_sun·Q_0
          NormalEquations& ne = normal[ia * nc + ic];
          for (std::size_t px = 0; px < P; ++px) {
            const double res = d.y_truth[px] - d.y_sky[px] - d.y_sun * q[px];
            ne.c0 += res * res / yTruthSq / double(data.size());
            for (int n = 1; n < kMaxOctaves; ++n) {
              const double qn = d.y_sun * q[std::size_t(n) * P + px];
              ne.h[std::size_t(n)] += qn * res / yTruthSq / double(data.size());
              for (int m = 1; m <= n; ++m) {
                ne.g[std::size_t(n * kMaxOctaves + m)] +=
                    qn * d.y_sun * q[std::size_t(m) * P + px] / yTruthSq / double(data.size());
              }
            }
          }
        }
        for (std::size_t ib = 0; ib < nb; ++ib) {
          std::vector<double> sq(kMaxOctaves, 0.0);
          for (std::size_t px = 0; px < P; ++px) {
            double y = d.y_sky[px], energy = 1.0;
            const double yt = d.y_truth[px];
            for (int n = 0; n < kMaxOctaves; ++n) {
              y += d.y_sun * energy * q[std::size_t(n) * P + px];
              energy *= bs[ib];
              const double diff = y - yt;
              sq[std::size_t(n)] += diff * diff;
            }
          }
          for (int n = 0; n < kMaxOctaves; ++n)
            at(ia, ic, ib, n) += sq[std::size_t(n)] / yTruthSq / double(data.size());
        }
      }
    }
    log::info("{}: grid of {} settings in {:.1f} s", d.name, err.size(),
              std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
  }
  r.objective = std::numeric_limits<double>::infinity();
  std::size_t bestA = 0, bestB = 0, bestC = 0;
  int bestN = 0;
  for (std::size_t ia = 0; ia < na; ++ia)
    for (std::size_t ic = 0; ic < nc; ++ic)
      for (std::size_t ib = 0; ib < nb; ++ib)
        for (int n = 0; n < kMaxOctaves; ++n)
          if (at(ia, ic, ib, n) < r.objective) {
            r.objective = at(ia, ic, ib, n);
            bestA = ia, bestB = ib, bestC = ic, bestN = n;
          }
  r.best = {bestN + 1, as[bestA], bs[bestB], cs[bestC], {}};
  for (std::size_t ib = 0; ib < nb; ++ib) r.along_b.emplace_back(bs[ib], at(bestA, bestC, ib, bestN));
  for (std::size_t ia = 0; ia < na; ++ia) r.along_a.emplace_back(as[ia], at(ia, bestC, bestB, bestN));
  log::info("octave fit: N {} a {:.2f} b {:.2f} c {:.2f}, objective {:.4f} (binned)", r.best.octaves,
            r.best.extinction_scale, r.best.energy_scale, r.best.anisotropy_scale, r.objective);

  r.objective_free = std::numeric_limits<double>::infinity();
  for (std::size_t ia = 0; ia < na; ++ia)
    for (std::size_t ic = 0; ic < nc; ++ic) {
      std::vector<double> w;
      const double obj = normal[ia * nc + ic].solve(w);
      if (obj < r.objective_free) {
        r.objective_free = obj;
        while (w.size() > 1 && w.back() == 0.0) w.pop_back();
        r.best_free = {int(w.size()), as[ia], 0.0, cs[ic], w};
      }
    }
  log::info("octave fit, free weights: a {:.2f} c {:.2f}, weights {}, objective {:.4f} (binned)",
            r.best_free.extinction_scale, r.best_free.anisotropy_scale, fmt::join(r.best_free.energy, " "),
            r.objective_free);

  // 3. The single-scattering model and the winner rendered exactly and measured.
  for (std::size_t i = 0; i < used.size(); ++i) {
    const AccuracyScene& sc = *used[i];
    const reference::DlmReference& light = *lights[i];
    auto render = [&](const lighting::OctaveSeries& series, double* ms) {
      reference::RayMarchSettings m = march;
      m.min_transmittance = 0.0;
      m.octaves = series;
      m.multiple_scattering = lighting::MultipleScattering::Octaves;
      const auto start = std::chrono::steady_clock::now();
      scene::RgbaImage img = reference::marchCloudLayer(
          *sc.volumes, sc.frame, sc.camera, sc.sun, [&](const glm::dvec3& p) { return light.intensityAt(p); }, m);
      if (ms) *ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
      return img;
    };
    const ImageError single =
        compareImages(render(lighting::OctaveSeries{}, nullptr), truths[i].image, truths[i].standard_error);
    if (o.write_images) {
      scene::writePng(truths[i].image, (std::filesystem::path(o.out_dir) / (sc.name + "-truth.png")).string());
    }
    auto measure = [&](const lighting::OctaveSeries& series, const std::string& label) {
      OctaveFitSceneResult s;
      s.scene = sc.name;
      s.single = single;
      const scene::RgbaImage fitted = render(series, &s.march_ms);
      s.fitted = compareImages(fitted, truths[i].image, truths[i].standard_error);
      if (o.write_images) {
        scene::writePng(fitted, (std::filesystem::path(o.out_dir) / (sc.name + "-" + label + ".png")).string());
      }
      log::info("{} ({}): relMSE {:.4f} -> {:.4f}, luminance bias {:+.1f} % -> {:+.1f} %, >2/255 {:.1f} % -> {:.1f} %",
                sc.name, label, s.single.rel_mse, s.fitted.rel_mse, 100.0 * s.single.luminance_bias,
                100.0 * s.fitted.luminance_bias, 100.0 * s.single.share_off_2_255, 100.0 * s.fitted.share_off_2_255);
      return s;
    };
    r.scenes_free.push_back(measure(r.best_free, "octaves-free"));
    r.scenes.push_back(measure(r.best, "octaves"));
  }
  return r;
}

namespace {

std::string sceneTable(const std::vector<OctaveFitSceneResult>& scenes) {
  std::string md =
      "| scene | relMSE single | relMSE octaves | luminance bias single | luminance bias octaves | > 2/255 single | "
      "> 2/255 octaves | truth noise RMSE | CPU march ms |\n| --- | ---: | ---: | ---: | ---: | ---: | ---: | ---: | "
      "---: |\n";
  double s1 = 0.0, s2 = 0.0;
  for (const OctaveFitSceneResult& s : scenes) {
    md += fmt::format("| {} | {:.4f} | {:.4f} | {:+.1f} % | {:+.1f} % | {:.1f} % | {:.1f} % | {:.3g} | {:.0f} |\n",
                      s.scene, s.single.rel_mse, s.fitted.rel_mse, 100.0 * s.single.luminance_bias,
                      100.0 * s.fitted.luminance_bias, 100.0 * s.single.share_off_2_255,
                      100.0 * s.fitted.share_off_2_255, s.fitted.ref_noise_rmse, s.march_ms);
    s1 += s.single.rel_mse;
    s2 += s.fitted.rel_mse;
  }
  const double n = double(std::max<std::size_t>(1, scenes.size()));
  md += fmt::format("| **mean** | {:.4f} | {:.4f} | | | | | | |\n\n", s1 / n, s2 / n);
  return md;
}

}  // namespace

std::string octaveFitMarkdown(const OctaveFitResult& r) {
  std::string md = fmt::format(
      "Fitted octave series: N = {}, a (extinction) = {:.2f}, b (energy) = {:.2f}, c (anisotropy) = {:.2f}; "
      "objective (mean over scenes of Σ ΔY² / Σ (Y_ref² + 0.01)) {:.4f} (binned search), of which the truth's own "
      "noise is {:.4f}\n\n",
      r.best.octaves, r.best.extinction_scale, r.best.energy_scale, r.best.anisotropy_scale, r.objective,
      r.objective_noise_floor);
  md += sceneTable(r.scenes);
  md += "Objective along b (a, c, N at the best): ";
  for (const auto& [b, e] : r.along_b) md += fmt::format("{:.2f}: {:.4f}; ", b, e);
  md += "\n\nObjective along a (b, c, N at the best): ";
  for (const auto& [a, e] : r.along_a) md += fmt::format("{:.2f}: {:.4f}; ", a, e);
  md += fmt::format(
      "\n\nFree octave weights (w₀ = 1, non-negative least squares): a = {:.2f}, c = {:.2f}, weights {:.3f}; "
      "objective {:.4f}\n\n",
      r.best_free.extinction_scale, r.best_free.anisotropy_scale, fmt::join(r.best_free.energy, ", "),
      r.objective_free);
  md += sceneTable(r.scenes_free);
  return md;
}

}  // namespace nph::accuracy
