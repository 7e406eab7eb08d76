#include "accuracy/ms_fit.h"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <numbers>
#include <random>

#include <fmt/format.h>

#include "core/error.h"
#include "core/log.h"
#include "lighting/cloud_light.h"
#include "lighting/diffusion_volume.h"
#include "reference/mc_radiance_volume.h"
#include "reference/ray_marcher.h"
#include "render/dlm/radiance_volume.h"

namespace nph::accuracy {
namespace {

// Per-pixel sums of the candidate terms (per unit solar irradiance; luminance factor applied later).
enum Term : int {
  kSingle = 0,
  kOctaves,         // the default octaves n = 1, 2 (a 0.65, b 0.75, c 0)
  kTwoStreamData,   // two-stream with the data's μ₀, no beam or diffusion scaling (exaggeration half-kept)
  kTwoStreamWorld,  // two-stream with the world's μ₀ and μ_out (exaggeration ignored)
  kTwoStream,       // the eye pass's: twoStreamSunFrame (beam and diffusion scaled)
  kSlabBoth,        // two-stream on sunPathSlab's equivalent slab, both ways (a candidate, not kept)
  kSlabSide,        // same, only shorter paths (side light; a candidate, not kept)
  kDiffusionIso,    // the coarse diffusion volume's (DLM source, physical drift) isotropic part φ/(4π)
  kDiffusion0,  // kDiffusionConfigs × {3-D (φ + 3g·F·ω)/(4π), the same grid's columns, two_stream × φ/φ₁}
  kColMarshak,  // twoStreamColumn: Marshak's b = (e + 1)/3 (radiance isotropic in the world), K = 1
  kColPhys,     // twoStreamColumn: the physical drift K = 1/ds, b = ⅔
  kColPhysMarshak,  // both
  kColGreenKubo,    // resistance and drift of the data frame by Green–Kubo (greenKubo below), b = (e + 1)/3
  kColGreenKuboB,   // the same with b = ⅔
  kFwdOrder2,       // small-angle order 2: τ_s·e^{−τ_s}·p(ψ; g²) added to two_stream
  kFwdReshape,      // first-order diffuse light reshaped: (1 − f)·τ_s·e^{−τ_s}·(p(ψ; g·g') − 1/4π)
  kConeReshape,     // the cone's light seen through the convolved lobe: (I − e^{−τ_s})·(p(ψ; g²) − p(ψ; g))
  kForwardLobe,     // the two together, as the eye pass adds them since (lighting::forwardLobe)
  kAlpha,           // Σ w (diagnostics)
  kTauColumn,       // Σ w·(τ_a + τ_b) (diagnostics)
  kColumn0,         // kColumnBins × 2 octaves
};
constexpr int kColumnBins = 8;
constexpr std::array<double, kColumnBins - 1> kColumnEdges{0.5, 1.0, 2.0, 4.0, 8.0, 16.0, 32.0};
constexpr int kColumnEnd = kColumn0 + 2 * kColumnBins;
// The coarse diffusion volume (lighting/diffusion_volume.h), four configurations: source the DLM's
// converged I or the column's beam e^{−(1−g²)τ_up/μ₀} (the two_stream term's), drift physical or
// the two_stream term's convention; each solved in 3-D and as independent columns on the same grid.
constexpr int kDiffusionConfigs = 4;
constexpr std::array<const char*, kDiffusionConfigs> kDiffusionConfigNames{
    "DLM source, physical drift", "DLM source, two_stream drift", "column beam, physical drift",
    "column beam, two_stream drift"};
int diffusionTerm(int config, int kind) { return kColumnEnd + 3 * config + kind; }  // kind 0 3-D, 1 1-D, 2 ratio
constexpr int kDiffusionEnd = kColumnEnd + 3 * kDiffusionConfigs;
// The Monte Carlo radiance volume (reference/mc_radiance_volume.h; fifteenth session): one photon
// trace per scene fills these tallies; each is read with its series truncated after l = 0 … 8 (the 2x2x1 tally: 4).
// kMcBeam is p_v(ψ)·(e^{−τ} − I_DLM): single scattering from the exact beam (the DLM without its
// forward cone, θ = 0, as --decompose's order 1) in place of the DLM's, so a tally of light
// scattered ≥ 1 times is not counted twice with the cone.
struct McVariant {
  const char* name;
  reference::McTallySpec spec;
};
const std::array<McVariant, 5> kMcVariants{{
    {"cells 4x4x2, orders >= 1", {4, 2, 1, -1, 1, 8}},
    {"cells 4x4x2, orders >= 2", {4, 2, 2, -1, 1, 8}},
    {"cells 8x8x4, orders >= 1", {8, 4, 1, -1, 1, 8}},
    {"cells 2x2x1, orders >= 1", {2, 1, 1, -1, 1, 4}},
    {"cells 4x4x2, orders >= 1, a quarter of the photons", {4, 2, 1, -1, 4, 8}},
}};
constexpr int kMcTallies = int(kMcVariants.size());
constexpr int kMcBeam = kDiffusionEnd;
constexpr int kMcOrders = reference::kMcMaxL + 1;  // the series truncated after l = 0 … 8
int mcTerm(int tally, int max_l) { return kMcBeam + 1 + kMcOrders * tally + max_l; }
// The GPU's radiance volume (render/dlm/radiance_volume.h; sixteenth session): cells 4x4x2, orders
// >= 2, l <= 4, the eye pass's multiple_scattering = radiance_volume, read back and evaluated here.
constexpr int kGpuMc = kMcBeam + 1 + kMcOrders * kMcTallies;
constexpr int kTerms = kGpuMc + 1;

int columnBin(double tau) {
  int b = 0;
  while (b < kColumnBins - 1 && tau >= kColumnEdges[std::size_t(b)]) ++b;
  return b;
}

struct SceneTerms {
  std::string name;
  double y_sun = 0.0;
  std::vector<double> y_truth, y_sky;
  std::vector<std::array<double, kTerms>> terms;
  std::vector<glm::dvec3> sky_rgb;  // for the candidates' pictures: sky + E·(single + term)
  std::vector<double> alpha;
};

// A candidate's picture from the per-pixel sums (the sky light's colour and the sun's colour ×
// single scattering + the term): what marchCloudLayer would render with the term in the eye pass.
scene::RgbaImage termImage(const SceneTerms& d, int width, int height, const glm::dvec3& sun,
                           const std::vector<int>& terms) {
  scene::RgbaImage img;
  img.width = width;
  img.height = height;
  img.rgba.assign(std::size_t(width) * std::size_t(height) * 4, 0.0f);
  for (std::size_t px = 0; px < d.terms.size(); ++px) {
    double f = d.terms[px][kSingle];
    for (int term : terms) f += d.terms[px][std::size_t(term)];
    const glm::dvec3 c = d.sky_rgb[px] + sun * f;
    for (int ch = 0; ch < 3; ++ch) img.rgba[4 * px + std::size_t(ch)] = float(c[ch]);
    img.rgba[4 * px + 3] = float(d.alpha[px]);
  }
  return img;
}

// A candidate against the independent column's dark side-lit towers at low sun (tried in session 9,
// docs/accuracy.md "Golden hour"; not kept): the column assumes the beam enters at the column's
// top, e^{−(1−f)τ_a/μ₀} at the sample, while the deep light map carries the beam that arrived by
// whatever path (its forward peak kept, Nes 2008 §5.2.3), I = e^{−(1−f)τ_s}. The equivalent slab
// keeps the map's beam: incidence μ_e = clamp(τ_a/τ_s, μ₀, 1), depth below its lit face τ_s·μ_e,
// the column below unchanged — side-lit (τ_s < τ_a/μ₀): the face turns to the sun and takes the
// full beam instead of its μ₀ share; `shadow`: also deeper for a sample in another cloud's shadow.
// Returns (τ_above, τ_below, μ₀) for twoStreamDiffuse.
glm::dvec3 sunPathSlab(double tau_above, double tau_below, double sunlight, double mu0, double g, bool shadow) {
  if (mu0 <= 0.0 || sunlight <= 1e-12) return {tau_above, tau_below, mu0};
  const double ts = -std::log(std::min(sunlight, 1.0)) / (1.0 - g * g);
  const double ta = std::max(tau_above, 0.0);
  const double me = std::clamp(ta / std::max(ts, 1e-6), mu0, 1.0);
  const double te = ts * me;
  if (!shadow && te >= ta) return {tau_above, tau_below, mu0};
  return {te, tau_below, me};
}

// The vertical transport of the scattered light in the data frame of a height-exaggerated world
// (thirteenth session, a candidate): light travels straight in the data, collides at β per data
// metre whatever its direction, and its world direction is redrawn by HG(g') at each collision
// (δ-Eddington: the forward peak stays in the beam), so the stationary distribution is isotropic
// in the world and the data's vertical velocity is v = d_z/√(e²(d_x² + d_y²) + d_z²). Green–Kubo:
// the vertical diffusion D_z = Σ_{n≥0}⟨v₀v_n⟩/β' — as a diffusion scale 3(1 − g')Σ⟨v₀v_n⟩ (1 at
// e = 1; twoStreamSunFrame's 3⟨v²⟩ keeps only n = 0 and the world's decorrelation) — and the mean
// displacement of light first scattered out of the beam, Σ_{n≥1}E[v_n | beam]/β' = q·v_beam/σ'_tr,
// the drift q (g' at e = 1). Monte Carlo (fixed seed, 2·10⁵ histories × 60 collisions; ≈ 1 % noise).
glm::dvec2 greenKubo(double e, double g, double muWorld) {
  std::mt19937_64 rng(12345);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  auto vz = [&](const glm::dvec3& d) { return d.z / std::sqrt(e * e * (d.x * d.x + d.y * d.y) + d.z * d.z); };
  auto scatter = [&](const glm::dvec3& d) {
    double c = 1.0 - 2.0 * u(rng);
    if (std::abs(g) > 1e-6) {
      const double s = (1.0 - g * g) / (1.0 - g + 2.0 * g * u(rng));
      c = (1.0 + g * g - s * s) / (2.0 * g);
    }
    const double sn = std::sqrt(std::max(0.0, 1.0 - c * c)), ph = 2.0 * std::numbers::pi * u(rng);
    const glm::dvec3 a = glm::normalize(glm::cross(d, std::abs(d.z) < 0.9 ? glm::dvec3(0, 0, 1) : glm::dvec3(1, 0, 0)));
    const glm::dvec3 b = glm::cross(d, a);
    return glm::normalize(c * d + sn * (std::cos(ph) * a + std::sin(ph) * b));
  };
  const int histories = 200000, collisions = 60;
  double corr = 0.0, drift = 0.0;
  const glm::dvec3 beam(std::sqrt(std::max(0.0, 1.0 - muWorld * muWorld)), 0.0, -muWorld);
  for (int i = 0; i < histories; ++i) {
    const double z = 1.0 - 2.0 * u(rng), ph = 2.0 * std::numbers::pi * u(rng), r = std::sqrt(1.0 - z * z);
    glm::dvec3 d(r * std::cos(ph), r * std::sin(ph), z);
    const double v0 = vz(d);
    for (int n = 1; n < collisions; ++n) corr += v0 * vz(d = scatter(d));
    d = beam;
    for (int n = 1; n < collisions; ++n) drift += vz(d = scatter(d));
  }
  corr /= histories;
  drift /= histories;
  const double ds0 = lighting::twoStreamSunFrame(0.5, e).z;  // 3⟨v²⟩, exact (the n = 0 term)
  const double ds = (1.0 - g) * ds0 + 3.0 * (1.0 - g) * corr;
  const double vb = -vz(beam);
  return {ds, vb > 0.0 ? (1.0 - g) * -drift / vb : g};
}

// Least squares of the free weights θ over `free` terms with `fixed` terms at weight 1.
struct Model {
  std::string name;
  std::vector<int> fixed, free;
};

double predict(const SceneTerms& d, std::size_t px, const Model& m, const std::vector<double>& theta) {
  const auto& t = d.terms[px];
  double f = t[kSingle];
  for (int j : m.fixed) f += t[std::size_t(j)];
  for (std::size_t j = 0; j < m.free.size(); ++j) f += theta[j] * t[std::size_t(m.free[j])];
  return d.y_sky[px] + d.y_sun * f;
}

std::vector<double> solve(std::vector<double> a, std::vector<double> b, std::size_t n) {
  // Gaussian elimination with partial pivoting and a tiny ridge (ill-posed bins stay at 0).
  for (std::size_t i = 0; i < n; ++i) a[i * n + i] += 1e-9 * (1.0 + a[i * n + i]);
  for (std::size_t c = 0; c < n; ++c) {
    std::size_t p = c;
    for (std::size_t r = c + 1; r < n; ++r)
      if (std::abs(a[r * n + c]) > std::abs(a[p * n + c])) p = r;
    for (std::size_t k = 0; k < n; ++k) std::swap(a[c * n + k], a[p * n + k]);
    std::swap(b[c], b[p]);
    for (std::size_t r = c + 1; r < n; ++r) {
      const double f = a[r * n + c] / a[c * n + c];
      for (std::size_t k = c; k < n; ++k) a[r * n + k] -= f * a[c * n + k];
      b[r] -= f * b[c];
    }
  }
  std::vector<double> x(n, 0.0);
  for (std::size_t i = n; i-- > 0;) {
    double s = b[i];
    for (std::size_t k = i + 1; k < n; ++k) s -= a[i * n + k] * x[k];
    x[i] = s / a[i * n + i];
  }
  return x;
}

MsModelResult evaluate(const std::vector<SceneTerms>& data, const Model& m) {
  const std::size_t n = m.free.size();
  std::vector<double> theta(n, 0.0);
  if (n > 0) {
    std::vector<double> a(n * n, 0.0), b(n, 0.0);
    for (const SceneTerms& d : data) {
      double norm = 0.0;
      for (double y : d.y_truth) norm += y * y + 0.01;
      const double wScene = 1.0 / (norm * double(data.size()));
      for (std::size_t px = 0; px < d.y_truth.size(); ++px) {
        const double r = d.y_truth[px] - predict(d, px, m, std::vector<double>(n, 0.0));
        for (std::size_t i = 0; i < n; ++i) {
          const double qi = d.y_sun * d.terms[px][std::size_t(m.free[i])];
          b[i] += wScene * qi * r;
          for (std::size_t j = 0; j < n; ++j)
            a[i * n + j] += wScene * qi * d.y_sun * d.terms[px][std::size_t(m.free[j])];
        }
      }
    }
    theta = solve(a, b, n);
  }
  MsModelResult r;
  r.model = m.name;
  r.weights = theta;
  for (const SceneTerms& d : data) {
    double norm = 0.0, sq = 0.0, sum = 0.0, sumRef = 0.0, rel = 0.0;
    for (std::size_t px = 0; px < d.y_truth.size(); ++px) {
      const double y = predict(d, px, m, theta), yt = d.y_truth[px];
      norm += yt * yt + 0.01;
      sq += (y - yt) * (y - yt);
      rel += (y - yt) * (y - yt) / (yt * yt + 0.01);
      sum += y;
      sumRef += yt;
    }
    r.objective += sq / norm / double(data.size());
    r.scenes.push_back({d.name, sum / sumRef - 1.0, rel / double(d.y_truth.size())});
  }
  return r;
}

}  // namespace

MsComparison compareMultipleScattering(const SweepOptions& o) {
  const std::string cacheDir = groundTruthCacheDir(o);
  const SceneSet set = sweepScenes(o);
  const Variant base = defaultVariant();
  const reference::RayMarchSettings march = base.render;
  const lighting::OctaveSeries oct = march.octaves;
  std::vector<SceneTerms> data;
  MsComparison out;
  for (const AccuracyScene& sc : set.scenes) {
    if (!o.scene_filter.empty() && sc.name.find(o.scene_filter) == std::string::npos) continue;
    const GroundTruth gt = groundTruth(sc, base.render, o.ground_truth, cacheDir);
    log::info("{}: ground truth {}", sc.name, gt.from_cache ? "from cache" : "traced");
    {
      double norm = 0.0, noise = 0.0;
      for (std::size_t i = 0; i < std::size_t(sc.camera.width * sc.camera.height); ++i) {
        const float* p = &gt.image.rgba[4 * i];
        const float* se = &gt.standard_error[3 * i];
        const double y = luminance(p[0], p[1], p[2]), sigma = luminance(se[0], se[1], se[2]);
        norm += y * y + 0.01;
        noise += sigma * sigma;
      }
      out.objective_noise_floor += noise / norm;  // divided by the scene count below
    }
    const render::VolumeTextures tex = render::VolumeTextures::upload(*sc.volumes, sc.frame, sc.name + "-ms");
    const auto light = convergedLight(base.dlm, tex, sc);
    SceneTerms d;
    d.name = sc.name;
    const int pixels = sc.camera.width * sc.camera.height;
    const glm::dvec3 e = sc.sun.colour * sc.sun.intensity;
    d.y_sun = luminance(e.x, e.y, e.z);
    d.y_truth.resize(std::size_t(pixels));
    for (int i = 0; i < pixels; ++i) {
      const float* p = &gt.image.rgba[4 * std::size_t(i)];
      d.y_truth[std::size_t(i)] = luminance(p[0], p[1], p[2]);
    }
    d.y_sky.assign(std::size_t(pixels), 0.0);
    d.terms.assign(std::size_t(pixels), std::array<double, kTerms>{});
    d.sky_rgb.assign(std::size_t(pixels), glm::dvec3(0.0));
    d.alpha.assign(std::size_t(pixels), 0.0);
    const lighting::SkyLight sky = lighting::skyLightFor(march, sc.sun.elevation_deg, sc.sun.colour, sc.sun.intensity);
    const ColumnDepths depths = columnDepths(*sc.volumes);
    const glm::dvec3 toSun = sc.sun.toSun();
    const glm::dvec3 sunFrame = lighting::twoStreamSunFrame(toSun.z, sc.frame.height_exaggeration);
    // The coarse diffusion volume (issue 12 item 1, second approach): per configuration 3-D and,
    // on the same grid, independent columns.
    lighting::DiffusionVolumeOptions dvo;
    dvo.g_ice = march.g_ice;
    dvo.g_water = march.g_water;
    dvo.coarsen_xy = o.diffusion_coarsen_xy;
    dvo.coarsen_z = o.diffusion_coarsen_z;
    std::array<lighting::DiffusionVolume, 2 * kDiffusionConfigs> dv;  // [2·config + (0 3-D, 1 columns)]
    for (int v = 0; v < 2 * kDiffusionConfigs; ++v) {
      const int config = v / 2;
      const bool dlmSource = config < 2;
      dvo.drift = config % 2 == 0 ? lighting::DiffusionDrift::Physical : lighting::DiffusionDrift::TwoStream;
      const auto start = std::chrono::steady_clock::now();
      lighting::DiffusionVolume& vol = dv[std::size_t(v)];
      vol.frame = sc.frame;
      vol.coarsen = glm::ivec3(dvo.coarsen_xy, dvo.coarsen_xy, dvo.coarsen_z);
      vol.problem = lighting::diffusionProblemFor(
          *sc.volumes, sc.frame, toSun,
          [&](const glm::dvec3& p, double g) {
            if (dlmSource) return light->intensityAt(p);
            return std::exp(-(1.0 - g * g) * columnDepthAt(depths, sc.frame, p).x / std::max(sunFrame.x, 0.02));
          },
          dvo);
      lighting::DiffusionSolveOptions so;
      so.horizontal = v % 2 == 0;
      so.min_resistance = o.diffusion_min_resistance;
      so.flux_limited_passes = o.diffusion_flux_limited_passes;
      vol.solution = lighting::solveDiffusion(vol.problem, so);
      log::info("{}: diffusion volume {}x{}x{} ({}, {}): {} CG iterations, residual {:.1e}, {:.0f} ms", sc.name,
                vol.problem.cells.x, vol.problem.cells.y, vol.problem.cells.z,
                kDiffusionConfigNames[std::size_t(config)], so.horizontal ? "3-D" : "columns", vol.solution.iterations,
                vol.solution.relative_residual,
                std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count());
    }
    // The Monte Carlo radiance volume (fifteenth session) and the exact beam it goes with.
    lighting::DlmSettings beamOnly = base.dlm;
    beamOnly.forward_angle_deg = 0.0;
    beamOnly.peripheral = false;
    const auto beam = convergedLight(beamOnly, tex, sc);
    reference::McSettings mcs;
    mcs.photons = o.mc_photons;
    mcs.phase.ice = physics::PhaseFunction{physics::PhaseModel::HenyeyGreenstein, march.g_ice};
    mcs.phase.water = physics::PhaseFunction{physics::PhaseModel::HenyeyGreenstein, march.g_water};
    std::vector<reference::McTallySpec> mcSpecs;
    for (const McVariant& v : kMcVariants) mcSpecs.push_back(v.spec);
    mcSpecs.front().coarsen_xy = o.mc_coarsen_xy;  // --ms-mc-coarsen (default 4 x 4 x 2)
    mcSpecs.front().coarsen_z = o.mc_coarsen_z;
    mcSpecs.front().subdivide_z = o.mc_subdivide_z;
    reference::McStats mcStats;
    const std::vector<reference::McRadianceVolume> mc =
        reference::traceMcRadianceVolumes(*sc.volumes, sc.frame, toSun, mcSpecs, mcs, &mcStats);
    log::info("{}: Monte Carlo radiance volume: {} photons, {} collided, {:.1f} collisions per photon, {} rouletted, "
              "{} cut; {:.2f} s CPU wall ({} tallies)",
              sc.name, mcStats.photons, mcStats.collided,
              double(mcStats.collisions) / double(std::max<std::uint64_t>(1, mcStats.photons)), mcStats.rouletted,
              mcStats.truncated, mcStats.seconds, mc.size());
    {  // the cost of the first tally alone (orders >= 1, l <= 8), as a GPU port would build it
      reference::McStats one;
      reference::traceMcRadianceVolumes(*sc.volumes, sc.frame, toSun, {mcSpecs.front()}, mcs, &one);
      log::info("{}: one tally alone: {:.2f} s", sc.name, one.seconds);
      out.mc_seconds.push_back({sc.name, one.seconds});
    }
    // The GPU's volume (sixteenth session), as the eye pass builds it, read back.
    render::RadianceVolumeSettings gpuSettings;
    gpuSettings.photons = std::uint32_t(std::min<std::uint64_t>(o.mc_photons, 1u << 30));
    gpuSettings.g_ice = float(march.g_ice);
    gpuSettings.g_water = float(march.g_water);
    gpuSettings.backend = render::RadianceVolumeBackend::Gpu;  // the port itself, also on llvmpipe
    gpuSettings.photons_per_column = 0;                        // the twin's photon count exactly
    render::RadianceVolume gpuVolume;
    gpuVolume.build(tex, toSun, gpuSettings);
    reference::McTallySpec gpuSpec;
    gpuSpec.coarsen_xy = gpuSettings.coarsen_xy;
    gpuSpec.coarsen_z = gpuSettings.coarsen_z;
    gpuSpec.min_order = gpuSettings.min_order;
    gpuSpec.max_l = 4;
    const std::vector<float> gpuMoments = gpuVolume.readBackMoments();
    const reference::McRadianceVolume gpuMc =
        reference::mcRadianceVolumeOf(sc.frame, gpuSpec, std::vector<double>(gpuMoments.begin(), gpuMoments.end()));
    log::info("{}: GPU radiance volume: {} photons, {:.1f} collisions per photon, {} rouletted, {} cut, {} clamped; "
              "{:.0f} ms (llvmpipe)",
              sc.name, gpuVolume.stats().photons,
              double(gpuVolume.stats().collisions) / double(std::max<std::uint64_t>(1, gpuVolume.stats().photons)),
              gpuVolume.stats().rouletted, gpuVolume.stats().truncated, gpuVolume.stats().clamped,
              gpuVolume.stats().build_ms);
    out.gpu_mc_ms.push_back({sc.name, gpuVolume.stats().build_ms});
    out.mc_photons = mcStats.photons;
    out.mc_cost_tally = fmt::format("cells {}x{}x{}{}, orders >= 1", o.mc_coarsen_xy, o.mc_coarsen_xy, o.mc_coarsen_z,
                                    o.mc_subdivide_z > 1 ? fmt::format("/{}", o.mc_subdivide_z) : std::string());
    const double exag = sc.frame.height_exaggeration;
    const int w = sc.camera.width;
    // Thirteenth session's candidates: the column's transport constants in the data frame.
    const double gsIce = march.g_ice / (1.0 + march.g_ice), gsWater = march.g_water / (1.0 + march.g_water);
    const glm::dvec2 gkIce = greenKubo(exag, gsIce, toSun.z), gkWater = greenKubo(exag, gsWater, toSun.z);
    log::info("{}: Green-Kubo in the data frame (e {:.0f}, mu_w {:.3f}): diffusion scale {:.4f} ice / {:.4f} water "
              "against 3<v^2> {:.4f}; drift {:.3f} / {:.3f} against g' {:.3f} / {:.3f}",
              sc.name, exag, toSun.z, gkIce.x, gkWater.x, sunFrame.z, gkIce.y, gkWater.y, gsIce, gsWater);
    const double marshakWorld = (exag + 1.0) / 3.0;
    reference::marchSamples(
        *sc.volumes, sc.frame, sc.camera, march.step_voxels, 0.0,
        [&](int x, int y, const glm::dvec3& dir, const reference::RaySample& s) {
          const std::size_t px = std::size_t(y) * std::size_t(w) + std::size_t(x);
          auto& t = d.terms[px];
          const double cosPsi = glm::dot(-toSun, -dir);
          const double I = light->intensityAt(s.position_m);
          const double g = march.g_water + (march.g_ice - march.g_water) * s.ice_weight;
          const glm::dvec2 tau = columnDepthAt(depths, sc.frame, s.position_m);
          const double muOut = -dir.z / (sc.frame.height_exaggeration * sc.frame.opticalDepthScale(dir));
          t[kSingle] += s.weight * lighting::mixedPhase(cosPsi, s.ice_weight, march.g_ice, march.g_water) * I;
          t[kOctaves] +=
              s.weight * (lighting::octaveSunFactor(oct, I, cosPsi, s.ice_weight, march.g_ice, march.g_water) -
                          lighting::mixedPhase(cosPsi, s.ice_weight, march.g_ice, march.g_water) * I);
          t[kTwoStreamData] += s.weight * lighting::twoStreamDiffuse(tau.x, tau.y, sunFrame.x, 1.0, 1.0, muOut, g);
          t[kTwoStreamWorld] += s.weight * lighting::twoStreamDiffuse(tau.x, tau.y, toSun.z, 1.0, 1.0, -dir.z, g);
          t[kTwoStream] +=
              s.weight * lighting::twoStreamDiffuse(tau.x, tau.y, sunFrame.x, sunFrame.y, sunFrame.z, muOut, g);
          {
            const double gs = g / (1.0 + g), ds = sunFrame.z, k = (1.0 - gs) / ds;
            auto col = [&](double kk, double K, double b) {
              return lighting::twoStreamColumn(tau.x, tau.y, sunFrame.x, sunFrame.y, kk, K, b, muOut, g);
            };
            t[kColMarshak] += s.weight * col(k, 1.0, marshakWorld);
            t[kColPhys] += s.weight * col(k, 1.0 / ds, 2.0 / 3.0);
            t[kColPhysMarshak] += s.weight * col(k, 1.0 / ds, marshakWorld);
            const glm::dvec2 gk = gkWater + (gkIce - gkWater) * s.ice_weight;
            const double kg = (1.0 - gs) / gk.x, Kg = kg + gk.y / gk.x;
            t[kColGreenKubo] += s.weight * col(kg, Kg, marshakWorld);
            t[kColGreenKuboB] += s.weight * col(kg, Kg, 2.0 / 3.0);
            // Forward-peaked orders ≥ 2 (the cirrus): τ_s the true slant depth to the sun through
            // the column (τ_a/μ₀ in the data frame), HG ⊗ HG = HG(g₁g₂) (Legendre moments multiply).
            const double taus = std::max(tau.x, 0.0) / std::max(sunFrame.x, 0.02);
            const double poisson = taus * std::exp(-taus);
            const double f = g * g, iso = 1.0 / (4.0 * std::numbers::pi);
            t[kFwdOrder2] += s.weight * poisson * lighting::hgPhase(cosPsi, g * g);
            t[kFwdReshape] += s.weight * (1.0 - f) * poisson * (lighting::hgPhase(cosPsi, g * gs) - iso);
            t[kConeReshape] += s.weight * std::max(I - std::exp(-taus), 0.0) *
                               (lighting::hgPhase(cosPsi, g * g) - lighting::hgPhase(cosPsi, g));
            t[kForwardLobe] += s.weight * lighting::forwardLobe(I, cosPsi, g, tau.x, sunFrame.x);
          }
          for (const bool shadow : {true, false}) {
            const glm::dvec3 slab = sunPathSlab(tau.x, tau.y, I, sunFrame.x, g, shadow);
            t[shadow ? kSlabBoth : kSlabSide] +=
                s.weight * lighting::twoStreamDiffuse(slab.x, slab.y, slab.z, sunFrame.y, sunFrame.z, muOut, g);
          }
          {
            const glm::dvec3 toEye = glm::normalize(glm::dvec3(-dir.x, -dir.y, -dir.z / exag));
            const double ts = lighting::twoStreamDiffuse(tau.x, tau.y, sunFrame.x, sunFrame.y, sunFrame.z, muOut, g);
            t[kDiffusionIso] += s.weight * std::max(dv[0].fluenceAt(s.position_m), 0.0) / (4.0 * std::numbers::pi);
            for (int c = 0; c < kDiffusionConfigs; ++c) {
              const lighting::DiffusionVolume &v3 = dv[std::size_t(2 * c)], &v1 = dv[std::size_t(2 * c + 1)];
              const double phi3 = v3.fluenceAt(s.position_m), phi1 = v1.fluenceAt(s.position_m);
              t[std::size_t(diffusionTerm(c, 0))] += s.weight * v3.radianceAt(s.position_m, toEye, g);
              t[std::size_t(diffusionTerm(c, 1))] += s.weight * v1.radianceAt(s.position_m, toEye, g);
              const double ratio = phi1 > 1e-9 ? std::clamp(phi3 / phi1, 0.0, 10.0) : 1.0;
              t[std::size_t(diffusionTerm(c, 2))] += s.weight * ratio * ts;
            }
          }
          {
            const double p = lighting::mixedPhase(cosPsi, s.ice_weight, march.g_ice, march.g_water);
            t[kMcBeam] += s.weight * p * (beam->intensityAt(s.position_m) - I);
            for (int k = 0; k < kMcTallies; ++k) {
              const auto j =
                  mc[std::size_t(k)].radianceByOrder(s.position_m, -dir, s.ice_weight, march.g_ice, march.g_water);
              for (int l = 0; l < kMcOrders; ++l) t[std::size_t(mcTerm(k, l))] += s.weight * j[std::size_t(l)];
            }
            t[kGpuMc] += s.weight * gpuMc.radianceAt(s.position_m, -dir, s.ice_weight, march.g_ice, march.g_water, 4);
          }
          const double total = tau.x + tau.y;
          t[kAlpha] += s.weight;
          t[kTauColumn] += s.weight * total;
          const int bin = columnBin(total);
          const double iso4pi = 1.0 / (4.0 * 3.14159265358979323846);
          t[std::size_t(kColumn0 + bin)] += s.weight * std::pow(I, oct.extinction_scale) * iso4pi;
          t[std::size_t(kColumn0 + kColumnBins + bin)] +=
              s.weight * std::pow(I, oct.extinction_scale * oct.extinction_scale) * iso4pi;
          const glm::dvec3 l = s.weight * reference::sampleSkyLight(sky, depths, sc.frame, s, march);
          d.y_sky[px] += luminance(l.x, l.y, l.z);
          d.sky_rgb[px] += l;
        },
        [&](int x, int y, double T) { d.alpha[std::size_t(y) * std::size_t(w) + std::size_t(x)] = 1.0 - T; });
    if (o.write_images) {
      const std::filesystem::path dir(o.out_dir);
      scene::writePng(termImage(d, w, sc.camera.height, e, {kTwoStream}),
                      (dir / (sc.name + "-terms-two_stream.png")).string());
      for (int l : {0, 2, 4, 8})
        scene::writePng(termImage(d, w, sc.camera.height, e, {kMcBeam, mcTerm(0, l)}),
                        (dir / fmt::format("{}-terms-mc-p{}.png", sc.name, l)).string());
      for (int c = 0; c < kDiffusionConfigs; ++c)
        for (int kind : {0, 2})
          scene::writePng(
              termImage(d, w, sc.camera.height, e, {diffusionTerm(c, kind)}),
              (dir / fmt::format("{}-terms-diffusion{}-{}.png", sc.name, c, kind == 0 ? "3d" : "ratio")).string());
    }
    {  // what each term contributes (luminance sums over the image), for the log
      std::array<double, kTerms> sum{};
      double yt = 0.0, ys = 0.0;
      for (std::size_t px = 0; px < d.y_truth.size(); ++px) {
        yt += d.y_truth[px];
        ys += d.y_sky[px];
        for (int j = 0; j < kTerms; ++j) sum[std::size_t(j)] += d.terms[px][std::size_t(j)];
      }
      log::info(
          "{}: sun frame mu0 {:.3f} beam x{:.2f} diffusion x{:.3f}; mean column tau {:.1f}; luminance sums: truth "
          "{:.0f}, sky {:.0f}, single {:.0f}, octaves {:.0f}, two-stream {:.0f} (data frame {:.0f}, world {:.0f}), "
          "diffusion isotropic {:.0f}",
          sc.name, sunFrame.x, sunFrame.y, sunFrame.z, sum[kTauColumn] / sum[kAlpha], yt, ys, d.y_sun * sum[kSingle],
          d.y_sun * sum[kOctaves], d.y_sun * sum[kTwoStream], d.y_sun * sum[kTwoStreamData],
          d.y_sun * sum[kTwoStreamWorld], d.y_sun * sum[kDiffusionIso]);
      for (int c = 0; c < kDiffusionConfigs; ++c)
        log::info("{}: diffusion ({}): 3-D {:.0f}, columns {:.0f}, two-stream x 3-D/1-D {:.0f}", sc.name,
                  kDiffusionConfigNames[std::size_t(c)], d.y_sun * sum[std::size_t(diffusionTerm(c, 0))],
                  d.y_sun * sum[std::size_t(diffusionTerm(c, 1))], d.y_sun * sum[std::size_t(diffusionTerm(c, 2))]);
      // The Monte Carlo volume's parts as mean luminance per pixel (--decompose's units): the exact
      // beam's single scattering, orders >= 1 and >= 2 of the first two tallies (P8), their
      // difference being the image's order 2.
      const double px = double(d.y_truth.size());
      log::info("{}: Monte Carlo parts, mean Y: truth {:.4f}, sky {:.4f}, single (DLM) {:.4f}, single (exact beam) "
                "{:.4f}, orders >= 2 (volume, orders >= 1 P8) {:.4f}, orders >= 3 (orders >= 2 P8) {:.4f}",
                sc.name, yt / px, ys / px, d.y_sun * sum[kSingle] / px, d.y_sun * (sum[kSingle] + sum[kMcBeam]) / px,
                d.y_sun * sum[std::size_t(mcTerm(0, kMcOrders - 1))] / px,
                d.y_sun * sum[std::size_t(mcTerm(1, kMcOrders - 1))] / px);
    }
    data.push_back(std::move(d));
    // The models of the knob, rendered exactly (the CPU twin of the eye pass, no early termination;
    // radiance_volume with the GPU's volume read back).
    for (const lighting::MultipleScattering ms :
         {lighting::MultipleScattering::Single, lighting::MultipleScattering::Octaves,
          lighting::MultipleScattering::TwoStream, lighting::MultipleScattering::RadianceVolume}) {
      reference::RayMarchSettings m = march;
      m.min_transmittance = 0.0;
      m.multiple_scattering = ms;
      const auto start = std::chrono::steady_clock::now();
      const scene::RgbaImage img = reference::marchCloudLayer(
          *sc.volumes, sc.frame, sc.camera, sc.sun, [&](const glm::dvec3& p) { return light->intensityAt(p); }, m,
          &gpuMc);
      MsRenderedScene r;
      r.march_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
      r.scene = sc.name;
      r.model = std::string(lighting::kMultipleScatteringNames[std::size_t(ms)]);
      r.error = compareImages(img, gt.image, gt.standard_error);
      if (o.write_images) {
        scene::writePng(img, (std::filesystem::path(o.out_dir) / (sc.name + "-" + r.model + ".png")).string());
        if (ms == lighting::MultipleScattering::Single)
          scene::writePng(gt.image, (std::filesystem::path(o.out_dir) / (sc.name + "-truth.png")).string());
      }
      log::info("{} {}: relMSE {:.4f}, luminance bias {:+.1f} %, >2/255 {:.1f} %, {:.0f} ms", sc.name, r.model,
                r.error.rel_mse, 100.0 * r.error.luminance_bias, 100.0 * r.error.share_off_2_255, r.march_ms);
      out.rendered.push_back(r);
    }
  }
  out.objective_noise_floor /= double(std::max<std::size_t>(1, data.size()));
  if (data.empty()) throw UsageError("accuracy --compare-ms: no scene matches --scenes " + o.scene_filter);
  std::vector<int> column;
  for (int j = kColumn0; j < kColumnEnd; ++j) column.push_back(j);
  std::vector<Model> models{
      {"single scattering", {}, {}},
      {"octaves (default a 0.65, b 0.75, c 0)", {kOctaves}, {}},
      {"octaves, scale fitted", {}, {kOctaves}},
      {"octave weights by column depth (16 fitted)", {}, column},
      {"two_stream, data frame's mu0 only", {kTwoStreamData}, {}},
      {"two_stream, world's mu0 (exaggeration ignored)", {kTwoStreamWorld}, {}},
      {"two_stream without the forward lobe (the twelfth session's default)", {kTwoStream}, {}},
      {"**two_stream** (eye pass: sun frame scaled, + forwardLobe since the thirteenth session)",
       {kTwoStream, kForwardLobe},
       {}},
      {"two_stream, scale fitted", {}, {kTwoStream}},
      {"two_stream on the sun-path slab, both ways", {kSlabBoth}, {}},
      {"two_stream on the sun-path slab, side light only", {kSlabSide}, {}},
      {"two_stream + octaves, both fitted", {}, {kTwoStream, kOctaves}},
      {"column: Marshak b = (e + 1)/3", {kColMarshak}, {}},
      {"column: physical drift K = 1/ds", {kColPhys}, {}},
      {"column: physical drift + Marshak (e + 1)/3", {kColPhysMarshak}, {}},
      {"column: Green-Kubo diffusion and drift + Marshak (e + 1)/3", {kColGreenKubo}, {}},
      {"column: Green-Kubo diffusion and drift, b = 2/3", {kColGreenKuboB}, {}},
      {"two_stream + small-angle order 2 tau_s e^-tau_s p(g^2)", {kTwoStream, kFwdOrder2}, {}},
      {"two_stream + first order reshaped (1-f) tau_s e^-tau_s (p(g g') - 1/4pi)", {kTwoStream, kFwdReshape}, {}},
      {"two_stream + cone reshaped (I - e^-tau_s)(p(g^2) - p(g))", {kTwoStream, kConeReshape}, {}},
      {"two_stream + cone reshaped + first order reshaped", {kTwoStream, kConeReshape, kFwdReshape}, {}},
      {"two_stream + small-angle order 2, weight fitted", {kTwoStream}, {kFwdOrder2}},
  };
  models.push_back({"diffusion volume, isotropic part (DLM source, physical drift)", {kDiffusionIso}, {}});
  for (int c = 0; c < kDiffusionConfigs; ++c) {
    const std::string n = kDiffusionConfigNames[std::size_t(c)];
    models.push_back({"diffusion volume 3-D (" + n + ")", {diffusionTerm(c, 0)}, {}});
    models.push_back({"diffusion volume, the grid's columns (" + n + ")", {diffusionTerm(c, 1)}, {}});
    models.push_back({"two_stream x 3-D/1-D ratio (" + n + ")", {diffusionTerm(c, 2)}, {}});
    models.push_back({"two_stream x ratio, scale fitted (" + n + ")", {}, {diffusionTerm(c, 2)}});
  }
  // The Monte Carlo radiance volume: with the exact beam (orders >= 1), or beside the DLM's single
  // scattering and forward lobe (orders >= 2), series truncated after l = 0 … 8 (the 2x2x1 tally: 4).
  for (int k = 0; k < kMcTallies; ++k)
    for (int l = 0; l < kMcOrders; ++l) {
      if (l > kMcVariants[std::size_t(k)].spec.max_l) continue;
      if (k > 0 && l % 2 == 1) continue;  // the other tallies at even l
      const std::string cells =
          k == 0 ? fmt::format("cells {0}x{0}x{1}{2}, orders >= 1", o.mc_coarsen_xy, o.mc_coarsen_z,
                               o.mc_subdivide_z > 1 ? fmt::format("/{}", o.mc_subdivide_z) : std::string())
                 : std::string(kMcVariants[std::size_t(k)].name);
      const std::string n = fmt::format("MC radiance volume ({}), P{}", cells, l);
      if (kMcVariants[std::size_t(k)].spec.min_order >= 2)
        models.push_back({n + " + DLM single + forwardLobe", {kForwardLobe, mcTerm(k, l)}, {}});
      else models.push_back({n + " + exact beam", {kMcBeam, mcTerm(k, l)}, {}});
    }
  models.push_back(
      {"MC radiance volume (cells 4x4x2, orders >= 1), P2 + DLM single (the cone counted twice)", {mcTerm(0, 2)}, {}});
  models.push_back({"exact beam alone (single scattering, no cone)", {kMcBeam}, {}});
  models.push_back(
      {"**GPU radiance volume** (cells 4x4x2, orders >= 2, l <= 4; eye pass radiance_volume) + DLM single + "
       "forwardLobe",
       {kForwardLobe, kGpuMc},
       {}});
  for (const Model& m : models) {
    out.models.push_back(evaluate(data, m));
    const MsModelResult& r = out.models.back();
    std::string line;
    for (const MsModelScene& s : r.scenes) line += fmt::format(" {:+.1f}%/{:.3f}", 100.0 * s.luminance_bias, s.rel_mse);
    std::string wts;
    for (double x : r.weights) wts += fmt::format(" {:.3f}", x);
    log::info("{}: objective {:.4f} weights[{}] bias/relMSE:{}", r.model, r.objective, wts, line);
  }
  return out;
}

std::string msComparisonMarkdown(const MsComparison& c) {
  const std::vector<MsModelResult>& results = c.models;
  if (results.empty()) return {};
  std::string md = "| model | fitted weights | objective | mean relMSE |";
  std::string sep = "| --- | --- | ---: | ---: |";
  for (const MsModelScene& s : results.front().scenes) {
    md += " " + s.scene + " bias / relMSE |";
    sep += " ---: |";
  }
  md += "\n" + sep + "\n";
  for (const MsModelResult& r : results) {
    std::string w;
    for (double x : r.weights) w += fmt::format("{}{:.3f}", w.empty() ? "" : ", ", x);
    double mean = 0.0;
    for (const MsModelScene& s : r.scenes) mean += s.rel_mse / double(r.scenes.size());
    md += fmt::format("| {} | {} | {:.4f} | {:.4f} |", r.model, w, r.objective, mean);
    for (const MsModelScene& s : r.scenes)
      md += fmt::format(" {:+.1f} % / {:.3f} |", 100.0 * s.luminance_bias, s.rel_mse);
    md += "\n";
  }
  md += fmt::format(
      "\nObjective = mean over scenes of Σ ΔY² / Σ (Y_ref² + 0.01); the truth's own noise is {:.4f} of it.\n\n",
      c.objective_noise_floor);
  if (!c.mc_seconds.empty()) {
    md += fmt::format(
        "Monte Carlo radiance volume: {} photons per scene; the trace with one tally ({}, l <= 8; TBB on this "
        "machine) in s:",
        c.mc_photons, c.mc_cost_tally);
    for (const auto& [scene, seconds] : c.mc_seconds) md += fmt::format(" {} {:.1f};", scene, seconds);
    md += "\n\n";
  }
  if (!c.gpu_mc_ms.empty()) {
    md += fmt::format("GPU radiance volume (render/dlm/radiance_volume.h, {} photons, cells 4x4x2, l <= 4, "
                      "llvmpipe on this machine), build in ms:",
                      c.mc_photons);
    for (const auto& [scene, ms] : c.gpu_mc_ms) md += fmt::format(" {} {:.0f};", scene, ms);
    md += "\n\n";
  }
  md += "| scene | model | relMSE | luminance bias | > 2/255 | truth noise RMSE | CPU march ms |\n"
        "| --- | --- | ---: | ---: | ---: | ---: | ---: |\n";
  std::vector<std::pair<std::string, double>> means;
  for (const MsRenderedScene& r : c.rendered) {
    md += fmt::format("| {} | {} | {:.4f} | {:+.1f} % | {:.1f} % | {:.3g} | {:.0f} |\n", r.scene, r.model,
                      r.error.rel_mse, 100.0 * r.error.luminance_bias, 100.0 * r.error.share_off_2_255,
                      r.error.ref_noise_rmse, r.march_ms);
    auto it = std::find_if(means.begin(), means.end(), [&](const auto& m) { return m.first == r.model; });
    if (it == means.end()) it = means.insert(means.end(), {r.model, 0.0});
    it->second += r.error.rel_mse;
  }
  const double scenes = double(std::max<std::size_t>(1, c.rendered.size() / std::max<std::size_t>(1, means.size())));
  for (const auto& [model, sum] : means) md += fmt::format("| **mean** | {} | {:.4f} | | | | |\n", model, sum / scenes);
  return md;
}

}  // namespace nph::accuracy
