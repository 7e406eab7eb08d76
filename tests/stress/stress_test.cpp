// Numerical stability stress suite (issue 6): the GPU deep light map + ray caster at the extremes.
//
// Every case of kCases runs through the same checks (runCase):
//   finite        every cloud-layer, frame and DLM value is finite
//   ranges        α ∈ [0, 1], RGB ≥ 0; DLM intensities ∈ [0, 1], depths ≥ 0
//   monotone      with the peripheral passes off (no scattering added to a light ray) every
//                 texel's stored light is non-increasing with depth
//   energy        per pixel, premultiplied C ≤ α·(E·max(4π·p_ice, 4π·p_water)(ψ) + L_amb): each
//                 step adds T_acc(1 − T)(E·I·4πp + L) with I ≤ 1 (clouds.comp), so the sum over
//                 steps is bounded by the total scattered fraction α times the largest source
//   deterministic two builds + renders from scratch give bit-identical images
// plus case-specific expectations (closed forms where they exist). Separate tests: bad voxels
// (NaN, ±Inf, negative, absurd) are rejected by the uploader and the path tracer; GPU alpha
// against the path tracer's exact alpha, and its second-order convergence as the step shrinks.
//
// | case                  | volume                         | sun           | settings               | extra expectation
// |
// |-----------------------|--------------------------------|---------------|------------------------|----------------------------|
// | extinction_1e-9       | 8×8×8 slab, β = 1e-9 /m        | 45°           | default                | α < 1e-5, DLM
// light ≈ 1    | | extinction_1e3        | 8×8×8 slab, β = 1e3 /m (τ 2e6) | 45°           | default                |
// centre α = 1               | | optical_depth_2e4     | 8×8×8 slab, β = 10 /m          | 45°           | default |
// centre α = 1               | | mixed_1e-9_to_1e3     | 12³ log-uniform 1e-9…1e3 /m    | 30°           | default | |
// | sun_zenith            | 12³ noisy                      | 90°           | default                | | | sun_along_x
// | 12³ noisy                      | az 90°, el 0° | default                | light exactly along +x grid| |
// sun_along_y           | 12³ noisy                      | az 180°, el 0°| default                | light exactly along
// +y grid| | sun_0.1deg            | 12³ noisy                      | 0.1°          | default                | | |
// sun_below_horizon     | 12³ noisy                      | −10°          | default                | | | volume_1x1x1 |
// one voxel, β = 1e-3 /m         | 45°           | default                |                            | | volume_1xNx1
// | 1×16×1, β = 1e-3 /m            | 30°           | default                |                            | | thin_layer
// | 32×32×1, dz = 2 m, β = 0.05 /m | 20°           | default                |                            | | domain_1km
// | 16×16×8 of 62.5 m, noisy       | 40°           | default                |                            | |
// domain_10000km        | 64×64×4 of 156 km × 250 m      | 40°           | default                | | | step_huge | 12³
// noisy                      | 45°           | Δ = 20 voxels (both)   |                            | | step_tiny | 12³
// noisy                      | 45°           | Δ = 0.02 / 0.05 voxel  |                            | |
// node_budget_overflow  | 12³ noisy                      | 30°           | 2 nodes, ε 1e-4, no ×2 | overflow counted,
// flagged  | | epsilon_0             | 12³ noisy                      | 30°           | ε = 0                  | |
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <random>

#include "accuracy/accuracy_scenes.h"
#include "accuracy/image_error.h"
#include "core/error.h"
#include "reference/path_tracer.h"
#include "render/dlm/deep_light_map.h"
#include "render/dlm/volume_textures.h"
#include "render/raycast/cloud_renderer.h"
#include "support/gl_fixture.h"

namespace nph::test {
namespace {

ExtinctionVolumes box(int nx, int ny, int nz, double dx_m, double dz_m) {
  return ExtinctionVolumes::zeros(nx, ny, nz, dx_m, dz_m, 1000.0);
}

ExtinctionVolumes uniform(int nx, int ny, int nz, double dx_m, double dz_m, float beta) {
  ExtinctionVolumes v = box(nx, ny, nz, dx_m, dz_m);
  std::fill(v.water_per_m.begin(), v.water_per_m.end(), beta);
  v.updateMaxima();
  return v;
}

// Random ice and water up to `max` /m (uniform), or log-uniform between lo and hi.
ExtinctionVolumes noisy(int n, double dx_m, double dz_m, float max = 5e-3f) {
  ExtinctionVolumes v = box(n, n, n, dx_m, dz_m);
  std::mt19937 rng(3);
  std::uniform_real_distribution<float> u(0.0f, max);
  for (std::size_t i = 0; i < v.voxelCount(); ++i) {
    v.water_per_m[i] = u(rng);
    v.ice_per_m[i] = i % 3 == 0 ? u(rng) : 0.0f;
  }
  v.updateMaxima();
  return v;
}

ExtinctionVolumes logUniform(int n, double lo, double hi) {
  ExtinctionVolumes v = box(n, n, n, 3000.0, 250.0);
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(std::log(lo), std::log(hi));
  for (std::size_t i = 0; i < v.voxelCount(); ++i) v.water_per_m[i] = float(std::exp(u(rng)));
  v.updateMaxima();
  return v;
}

struct StressCase {
  const char* name;
  std::function<ExtinctionVolumes()> volume;
  double sun_azimuth_deg;
  double sun_elevation_deg;
  std::function<void(lighting::DlmSettings&, render::RenderSettings&)> settings;
  std::function<void(const render::RenderOutput&, const render::DlmStats&, const render::DeepLightMap::Readback&)>
      expect;
};

void defaults(lighting::DlmSettings&, render::RenderSettings&) {}
void nothing(const render::RenderOutput&, const render::DlmStats&, const render::DeepLightMap::Readback&) {}

constexpr int kSize = 24;  // pixels per side
constexpr std::size_t kCentre = (std::size_t(kSize / 2) * kSize + kSize / 2) * 4;

void centreOpaque(const render::RenderOutput& out, const render::DlmStats&, const render::DeepLightMap::Readback&) {
  EXPECT_EQ(out.cloud_layer.rgba[kCentre + 3], 1.0f);
}

const StressCase kCases[] = {
    {"extinction_1e-9", [] { return uniform(8, 8, 8, 3000.0, 250.0, 1e-9f); }, 135.0, 45.0, defaults,
     [](const render::RenderOutput& out, const render::DlmStats&, const render::DeepLightMap::Readback& map) {
       for (std::size_t i = 3; i < out.cloud_layer.rgba.size(); i += 4) EXPECT_LT(out.cloud_layer.rgba[i], 1e-5f);
       for (const auto& texel : map.nodes)
         for (const auto& n : texel) EXPECT_GT(n.intensity, 1.0 - 1e-4);
     }},
    {"extinction_1e3", [] { return uniform(8, 8, 8, 3000.0, 250.0, 1e3f); }, 135.0, 45.0, defaults, centreOpaque},
    {"optical_depth_2e4", [] { return uniform(8, 8, 8, 3000.0, 250.0, 10.0f); }, 135.0, 45.0, defaults, centreOpaque},
    {"mixed_1e-9_to_1e3", [] { return logUniform(12, 1e-9, 1e3); }, 200.0, 30.0, defaults, nothing},
    {"sun_zenith", [] { return noisy(12, 3000.0, 250.0); }, 0.0, 90.0, defaults, nothing},
    {"sun_along_x", [] { return noisy(12, 3000.0, 250.0); }, 90.0, 0.0, defaults, nothing},
    {"sun_along_y", [] { return noisy(12, 3000.0, 250.0); }, 180.0, 0.0, defaults, nothing},
    {"sun_0.1deg", [] { return noisy(12, 3000.0, 250.0); }, 250.0, 0.1, defaults, nothing},
    {"sun_below_horizon", [] { return noisy(12, 3000.0, 250.0); }, 250.0, -10.0, defaults, nothing},
    {"volume_1x1x1", [] { return uniform(1, 1, 1, 3000.0, 250.0, 1e-3f); }, 135.0, 45.0, defaults, nothing},
    {"volume_1xNx1", [] { return uniform(1, 16, 1, 3000.0, 250.0, 1e-3f); }, 100.0, 30.0, defaults, nothing},
    {"thin_layer", [] { return uniform(32, 32, 1, 3000.0, 2.0, 0.05f); }, 300.0, 20.0, defaults, nothing},
    {"domain_1km", [] { return noisy(16, 62.5, 62.5, 0.2f); }, 135.0, 40.0, defaults, nothing},
    {"domain_10000km", [] { return uniform(64, 64, 4, 156250.0, 250.0, 2e-3f); }, 135.0, 40.0, defaults, nothing},
    {"step_huge", [] { return noisy(12, 3000.0, 250.0); }, 135.0, 45.0,
     [](lighting::DlmSettings& d, render::RenderSettings& r) {
       d.step_voxels = 20.0;
       r.step_voxels = 20.0;
     },
     nothing},
    {"step_tiny", [] { return noisy(12, 3000.0, 250.0); }, 135.0, 45.0,
     [](lighting::DlmSettings& d, render::RenderSettings& r) {
       d.step_voxels = 0.05;
       r.step_voxels = 0.02;
     },
     nothing},
    {"node_budget_overflow", [] { return noisy(12, 3000.0, 250.0); }, 200.0, 30.0,
     [](lighting::DlmSettings& d, render::RenderSettings&) {
       d.max_nodes = 2;
       d.epsilon = 1e-4;
       d.max_epsilon_doublings = 0;
     },
     [](const render::RenderOutput&, const render::DlmStats& st, const render::DeepLightMap::Readback& map) {
       EXPECT_GT(st.unbounded_texels, 0) << "overflow must be counted";
       EXPECT_EQ(std::size_t(std::count(map.unbounded.begin(), map.unbounded.end(), true)),
                 std::size_t(st.unbounded_texels));
       for (const auto& texel : map.nodes) EXPECT_LE(texel.size(), 2u);
     }},
    {"epsilon_0", [] { return noisy(12, 3000.0, 250.0); }, 200.0, 30.0,
     [](lighting::DlmSettings& d, render::RenderSettings&) { d.epsilon = 0.0; }, nothing},
};

scene::Camera cameraFor(const volume::VolumeFrame& f) {
  scene::Camera c;
  const glm::dvec3 size = f.size_m();
  c.target_m = f.min_m() + 0.5 * size;
  const double side = std::max({size.x, size.y, size.z});
  c.position_m = c.target_m + 1.6 * side * glm::normalize(glm::dvec3(0.35, -0.7, 0.6));
  c.vertical_fov_deg = 45.0;
  c.width = kSize;
  c.height = kSize;
  c.near_m = 1e-3 * side;
  return c;
}

double hg4pi(double cosPsi, double g) {
  return (1.0 - g * g) / std::pow(std::max(1.0 + g * g - 2.0 * g * cosPsi, 1e-6), 1.5);
}

struct Rendered {
  render::RenderOutput out;
  render::DlmStats stats;
  render::DeepLightMap::Readback map;
};

Rendered renderOnce(const render::VolumeTextures& tex, const scene::Camera& cam, const scene::Sun& sun,
                    const lighting::DlmSettings& d, const render::RenderSettings& r) {
  Rendered x;
  render::DeepLightMap dlm;
  dlm.build(tex, -sun.toSun(), d);
  render::CloudRenderer renderer;
  x.out = renderer.render(tex, dlm, cam, sun, r);
  x.stats = dlm.stats();
  x.map = dlm.readBack();
  return x;
}

class StressTest : public GlTest, public ::testing::WithParamInterface<StressCase> {};

TEST_P(StressTest, InvariantsHold) {
  const StressCase& c = GetParam();
  const ExtinctionVolumes v = c.volume();
  const volume::VolumeFrame frame = volume::frameOf(v);
  const auto tex = render::VolumeTextures::upload(v, frame, std::string("stress-") + c.name);
  scene::Sun sun;
  sun.azimuth_deg = c.sun_azimuth_deg;
  sun.elevation_deg = c.sun_elevation_deg;
  lighting::DlmSettings d;
  render::RenderSettings r;
  r.jitter = false;
  c.settings(d, r);
  const scene::Camera cam = cameraFor(frame);

  const Rendered a = renderOnce(tex, cam, sun, d, r);
  const Rendered b = renderOnce(tex, cam, sun, d, r);
  // deterministic
  EXPECT_EQ(a.out.cloud_layer.rgba, b.out.cloud_layer.rgba) << "cloud layer differs between two runs";
  EXPECT_EQ(a.out.frame.rgba, b.out.frame.rgba) << "frame differs between two runs";

  // finite, ranges, energy
  const glm::dvec3 E = sun.colour * sun.intensity, ambient = r.ambient * sun.intensity;
  int bad = 0;
  for (int y = 0; y < kSize; ++y)
    for (int x = 0; x < kSize; ++x) {
      const std::size_t i = (std::size_t(y) * kSize + std::size_t(x)) * 4;
      const float* L = &a.out.cloud_layer.rgba[i];
      const float* F = &a.out.frame.rgba[i];
      const double cosPsi = glm::dot(-sun.toSun(), -cam.rayDirection(x + 0.5, y + 0.5));
      const double phaseMax = std::max(hg4pi(cosPsi, r.g_ice), hg4pi(cosPsi, r.g_water));
      bool ok = std::isfinite(L[3]) && L[3] >= 0.0f && L[3] <= 1.0f;
      for (int ch = 0; ch < 3; ++ch) {
        ok = ok && std::isfinite(L[ch]) && std::isfinite(F[ch]) && L[ch] >= 0.0f && F[ch] >= 0.0f;
        const double bound = double(L[3]) * (E[ch] * phaseMax + ambient[ch]);
        ok = ok && double(L[ch]) <= bound * (1.0 + 1e-4) + 1e-6;
      }
      if (!ok && ++bad <= 3) {
        ADD_FAILURE() << c.name << " pixel (" << x << ", " << y << "): rgba " << L[0] << " " << L[1] << " " << L[2]
                      << " " << L[3] << ", frame " << F[0] << " " << F[1] << " " << F[2];
      }
    }
  EXPECT_EQ(bad, 0) << "pixels violating finite/range/energy bounds";

  // DLM values finite and in range
  for (const auto& texel : a.map.nodes)
    for (const auto& n : texel) {
      ASSERT_TRUE(std::isfinite(n.depth_m) && std::isfinite(n.intensity)) << c.name;
      ASSERT_GE(n.depth_m, 0.0);
      ASSERT_GE(n.intensity, 0.0);
      ASSERT_LE(n.intensity, 1.0);
    }
  // monotone without added scattering (pass 1 only)
  lighting::DlmSettings central = d;
  central.peripheral = false;
  render::DeepLightMap dlm;
  dlm.build(tex, -sun.toSun(), central);
  const auto map = dlm.readBack();
  for (std::size_t t = 0; t < map.nodes.size(); ++t)
    for (std::size_t k = 1; k < map.nodes[t].size(); ++k) {
      ASSERT_LE(map.nodes[t][k].intensity, map.nodes[t][k - 1].intensity + 1e-7f)
          << c.name << " texel " << t << " node " << k;
      ASSERT_GE(map.nodes[t][k].depth_m, map.nodes[t][k - 1].depth_m) << c.name << " texel " << t;
    }
  c.expect(a.out, a.stats, a.map);
}

INSTANTIATE_TEST_SUITE_P(Cases, StressTest, ::testing::ValuesIn(kCases),
                         [](const ::testing::TestParamInfo<StressCase>& i) {
                           std::string n = i.param.name;
                           std::replace_if(
                               n.begin(), n.end(),
                               [](char ch) { return !std::isalnum(static_cast<unsigned char>(ch)); }, '_');
                           return n;
                         });

using StressBadVoxels = GlTest;

// NaN, ±Inf, negative and absurd voxels never reach the GPU: the uploader rejects them (the
// loaders already do for model fields), as does the path tracer.
TEST_F(StressBadVoxels, AreRejectedBeforeTheGpu) {
  for (float badValue : {std::numeric_limits<float>::quiet_NaN(), std::numeric_limits<float>::infinity(),
                         -std::numeric_limits<float>::infinity(), -1e-3f, 1e30f}) {
    for (int phase = 0; phase < 2; ++phase) {
      ExtinctionVolumes v = uniform(4, 4, 4, 3000.0, 250.0, 1e-3f);
      (phase ? v.ice_per_m : v.water_per_m)[21] = badValue;
      const volume::VolumeFrame frame = volume::frameOf(v);
      EXPECT_THROW(render::VolumeTextures::upload(v, frame, "bad"), InputError) << badValue;
      if (badValue <= 1e6f || std::isnan(badValue)) {
        EXPECT_THROW(reference::PathTracer(v, frame, scene::Sun{}, reference::PathTracerSettings{}), InputError);
      }
    }
  }
}

using StressConvergence = GlTest;

// The GPU's alpha (midpoint rule along the view ray, no jitter, no early termination) against the
// path tracer's exact alpha (piecewise Gauss–Legendre on the same zero-border trilinear field):
// bounded at the default step, and converging at second order as the step halves (the midpoint
// rule on a piecewise-cubic integrand), until float rounding (~1e-6) takes over.
TEST_F(StressConvergence, GpuAlphaMatchesPathTracerAndConvergesAtSecondOrder) {
  struct Scene {
    const char* name;
    ExtinctionVolumes v;
    double exaggeration;
  };
  Scene scenes[] = {{"cirrus", accuracy::cirrusLayer(24, 4), 4.0}, {"cumulus", accuracy::cumulusField(24, 5), 1.0}};
  for (Scene& s : scenes) {
    const volume::VolumeFrame frame = volume::frameOf(s.v, s.exaggeration);
    const auto tex = render::VolumeTextures::upload(s.v, frame, std::string("conv-") + s.name);
    const scene::Sun sun{200.0, 40.0};
    scene::Camera cam = cameraFor(frame);
    cam.width = 48;
    cam.height = 48;
    const reference::PathTracer pt(s.v, frame, sun, reference::PathTracerSettings{});
    const std::vector<float> exact = pt.renderAlpha(cam);
    render::DeepLightMap dlm;
    dlm.build(tex, -sun.toSun(), lighting::DlmSettings{});
    render::CloudRenderer renderer;
    std::vector<double> rmse;
    double coverage = 0.0;
    for (float a : exact) coverage += double(a) / double(exact.size());
    for (double step : {1.0, 0.5, 0.25, 0.125}) {
      render::RenderSettings r;
      r.jitter = false;
      r.min_transmittance = 0.0;
      r.step_voxels = step;
      const auto out = renderer.render(tex, dlm, cam, sun, r);
      double sq = 0.0, mx = 0.0;
      for (std::size_t i = 0; i < exact.size(); ++i) {
        const double e = double(out.cloud_layer.rgba[4 * i + 3]) - double(exact[i]);
        sq += e * e;
        mx = std::max(mx, std::abs(e));
      }
      rmse.push_back(std::sqrt(sq / double(exact.size())));
      std::printf("[ stress   ] %s alpha, step %.3f voxel: RMSE %.3e, max %.3e (coverage %.2f)\n", s.name, step,
                  rmse.back(), mx, coverage);
      if (step == 0.5) {
        EXPECT_LE(rmse.back(), 2e-3) << s.name;
        EXPECT_LE(mx, 2e-2) << s.name;
      }
    }
    EXPECT_GT(coverage, 0.05) << s.name;
    // Observed order between the coarser pairs (before the float floor).
    const double order = std::log2(rmse[0] / rmse[1]);
    const double order2 = std::log2(rmse[1] / rmse[2]);
    std::printf("[ stress   ] %s observed order %.2f, %.2f\n", s.name, order, order2);
    EXPECT_GT(std::max(order, order2), 1.6) << s.name;
    EXPECT_LT(rmse[3], rmse[0]) << s.name;
  }
}

// The truth-noise term of the relMSE (accuracy/image_error.h rel_mse_noise, issue 12): a reference
// of known per-pixel standard error, and an image drawn around it with exactly that spread, give a
// relMSE whose expectation is the term; the term itself is the closed form, and without a standard
// error it is 0.
TEST(ImageError, TruthNoiseTermOfTheRelMseIsItsExpectation) {
  const int w = 200, h = 100;
  scene::RgbaImage ref, img;
  ref.width = img.width = w;
  ref.height = img.height = h;
  std::vector<float> se;
  std::mt19937 rng(5);
  std::normal_distribution<double> gauss(0.0, 1.0);
  double closedForm = 0.0;
  for (int i = 0; i < w * h; ++i) {
    const float y = 0.05f + 0.9f * float(i % 97) / 96.0f, sigma = 0.02f + 0.03f * float(i % 13) / 12.0f;
    ref.rgba.insert(ref.rgba.end(), {y, y, y, 1.0f});
    se.insert(se.end(), {sigma, sigma, sigma});  // grey: the luminance of (σ, σ, σ) is σ
    const float noisy = float(double(y) + double(sigma) * gauss(rng));
    img.rgba.insert(img.rgba.end(), {noisy, noisy, noisy, 1.0f});
    closedForm += double(sigma) * double(sigma) / (double(y) * double(y) + 0.01);
  }
  closedForm /= double(w * h);
  const accuracy::ImageError e = accuracy::compareImages(img, ref, se);
  EXPECT_NEAR(e.rel_mse_noise, closedForm, 1e-6 * closedForm);
  // 20 000 pixels: the sample mean of σ²·χ²₁ terms is within 3 % of its expectation (σ of the
  // mean ≈ √2/√20 000 ≈ 1 % relative), and far from 0 — the term is what the noise adds.
  EXPECT_NEAR(e.rel_mse, e.rel_mse_noise, 0.03 * e.rel_mse_noise);
  EXPECT_EQ(accuracy::compareImages(img, ref).rel_mse_noise, 0.0);
}

}  // namespace
}  // namespace nph::test
