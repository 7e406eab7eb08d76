// Deep light map: analytic cases and GPU against the CPU reference (issue 4).
#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <memory>
#include <random>
#include <string_view>

#include <fmt/format.h>

#include "dlm_scenes.h"
#include "reference/dlm_reference.h"
#include "render/dlm/deep_light_map.h"
#include "render/gl/objects.h"
#include "render/gl/program.h"
#include "scene/sun.h"
#include "support/gl_fixture.h"

namespace nph::test {
namespace {

using DlmTest = GlTest;

// Float rounding of a GPU march of N steps against the double-precision twin: each step's
// exp/multiply adds ~1 ulp (6e-8) of relative error, plus trilinear weights; N ≤ 1000 here.
constexpr double kFloatSlack = 2e-4;

lighting::DlmSettings centralOnly() {
  lighting::DlmSettings s;
  s.peripheral = false;
  return s;
}

TEST_F(DlmTest, EmptyVolumeIsFullSunWithOneNodePerTexel) {
  const ExtinctionVolumes v = homogeneousSlab(8, 8, 8, 0.0f);
  const auto frame = volume::frameOf(v);
  auto tex = render::VolumeTextures::upload(v, frame, "empty");
  render::DeepLightMap dlm;
  scene::Sun sun{30.0, 40.0};
  ASSERT_TRUE(dlm.build(tex, -sun.toSun(), lighting::DlmSettings{}));
  const auto rb = dlm.readBack();
  for (const auto& nodes : rb.nodes) {
    ASSERT_EQ(nodes.size(), 1u);
    EXPECT_EQ(nodes[0].intensity, 1.0f);
  }
  EXPECT_EQ(dlm.stats().max_nodes_used, 1);
  EXPECT_EQ(dlm.stats().unbounded_texels, 0);
}

// llvmpipe's loop limit (docs/rendering.md "llvmpipe's loop limit"): a light march of ~32 000
// steps is ended by the driver once a SIMD group has made 65 535 loop iterations, and the light
// function beyond the cut is missing. The march counts it (DlmStats::cut_short). Closed form: the
// light below a homogeneous slab under a zenith sun, exp(−β·H·(1 − CP)), as the test below. Every
// texel inside the slab has it (within 0.02) or is counted — on any driver; with the default step
// none is cut, and on llvmpipe the tiny step is, so the count is exercised there.
TEST_F(DlmTest, MarchesTheDriverCutShortAreCounted) {
  const double beta = 2e-4, dz = 250.0;
  const int nz = 64;  // 16 km: optical depth 3.2
  const ExtinctionVolumes v = homogeneousSlab(8, 8, nz, float(beta));
  const auto frame = volume::frameOf(v);
  auto tex = render::VolumeTextures::upload(v, frame, "tall slab");
  const bool llvmpipe = std::string_view(reinterpret_cast<const char*>(glGetString(GL_RENDERER))).find("llvmpipe") !=
                        std::string_view::npos;
  for (const double step : {0.5, 0.002}) {
    render::DeepLightMap dlm;
    lighting::DlmSettings s = centralOnly();
    s.epsilon = 0.005;
    s.step_voxels = step;  // 0.002: 0.5 m, 32 000 steps through the slab
    ASSERT_TRUE(dlm.build(tex, {0, 0, -1}, s));
    const auto cp = lighting::forwardFractions(s);
    const double continuum = std::exp(-beta * nz * dz * (1 - cp.central));
    const auto& ls = dlm.lightSpace();
    const auto rb = dlm.readBack();
    int inside = 0, short_of_it = 0;
    for (int b = 0; b < ls.texels.y; ++b) {
      for (int a = 0; a < ls.texels.x; ++a) {
        const glm::dvec3 centre = ls.rayStart(a, b);
        const glm::dvec3 lo = frame.min_m() + frame.voxel_size_m, hi = frame.max_m() - frame.voxel_size_m;
        if (centre.x < lo.x || centre.x > hi.x || centre.y < lo.y || centre.y > hi.y) continue;  // the slab's sides
        ++inside;
        const auto& nodes = rb.nodes[std::size_t(b * ls.texels.x + a)];
        const double below = lighting::evaluateLightFunction(nodes.data(), int(nodes.size()), ls.depth_m);
        if (std::abs(below - continuum) > 0.02) ++short_of_it;
      }
    }
    std::printf("[ dlm      ] step %.3f voxels, %d steps: %lld marches counted cut short, %d of %d inner texels "
                "off the closed form %.4f\n",
                step, dlm.stats().steps, static_cast<long long>(dlm.stats().cut_short), short_of_it, inside, continuum);
    ASSERT_GT(inside, 4);
    EXPECT_LE(short_of_it, dlm.stats().cut_short) << "every texel off the closed form is counted";
    if (step == 0.5) {
      EXPECT_EQ(dlm.stats().cut_short, 0) << "the default step is within any driver's reach";
    } else if (llvmpipe) {
      EXPECT_GT(short_of_it, 0) << "llvmpipe cuts this march: the count is exercised";
    }
  }
}

// Homogeneous slab, sun at zenith. With the zero-padded trilinear rule β(z) is a trapezoid: β between
// the centres of the bottom and top layers, linear ramps to 0 over one layer thickness around each
// face; its integral is exactly β·nz·dz. The discrete solution is the product of the per-step
// factors T + (1 − T)·CP(θ/4) with T = exp(−β(z_mid)·Δ) of this closed-form profile
// (lighting/dlm_model.h); its continuum limit at the bottom is exp(−β·nz·dz·(1 − CP(θ/4))).
TEST_F(DlmTest, HomogeneousSlabMatchesTheDiscreteClosedFormWithinEpsilon) {
  const double beta = 2e-3, dz = 250.0;  // 1/m; slab 8 × 250 m = 2 km thick → optical depth 4
  const int nz = 8;
  const ExtinctionVolumes v = homogeneousSlab(8, 8, nz, float(beta));
  const auto frame = volume::frameOf(v);
  auto tex = render::VolumeTextures::upload(v, frame, "slab");
  render::DeepLightMap dlm;
  lighting::DlmSettings s = centralOnly();
  s.epsilon = 0.005;
  ASSERT_TRUE(dlm.build(tex, {0, 0, -1}, s));
  const auto cp = lighting::forwardFractions(s);
  const double step = dlm.stats().step_m;
  const auto& ls = dlm.lightSpace();
  auto profile = [&](double z) {
    const double top = nz * dz;
    if (z >= top + dz / 2 || z <= -dz / 2) return 0.0;
    if (z > top - dz / 2) return beta * (top + dz / 2 - z) / dz;
    if (z < dz / 2) return beta * (z + dz / 2) / dz;
    return beta;
  };
  const auto rb = dlm.readBack();
  const int a = ls.texels.x / 2, b = ls.texels.y / 2;
  const auto& nodes = rb.nodes[std::size_t(b * ls.texels.x + a)];
  ASSERT_FALSE(nodes.empty());
  double expected = 1.0, maxErr = 0.0;
  for (int n = 0; n <= dlm.stats().steps; ++n) {
    if (n > 0) {
      const double zMid = ls.origin_m.z - (n - 0.5) * step;
      const double T = std::exp(-profile(zMid) * step);
      expected *= lighting::centralStepFactor(T, cp.central);
    }
    const double got = lighting::evaluateLightFunction(nodes.data(), int(nodes.size()), n * step);
    maxErr = std::max(maxErr, std::abs(got - expected));
  }
  EXPECT_LE(maxErr, s.epsilon + kFloatSlack);
  const double continuum = std::exp(-beta * nz * dz * (1 - cp.central));
  const double below = lighting::evaluateLightFunction(nodes.data(), int(nodes.size()), ls.depth_m);
  EXPECT_NEAR(below, continuum, 0.01) << "discrete solution at the bottom " << expected;
  std::printf("[ slab     ] nodes %zu for %d samples, light below the slab %.5f (continuum %.5f), max err %.2e\n",
              nodes.size(), dlm.stats().steps + 1, below, continuum, maxErr);
}

TEST_F(DlmTest, OpaqueWallLeavesNoLightBehindIt) {
  ExtinctionVolumes v = homogeneousSlab(8, 8, 8, 0.0f);
  for (int k = 0; k < v.nz; ++k)
    for (int j = 0; j < v.ny; ++j) v.water_per_m[v.index(4, j, k)] = 1.0f;  // 3 km at 1/m: τ ≈ 3000
  v.updateMaxima();
  const auto frame = volume::frameOf(v);
  auto tex = render::VolumeTextures::upload(v, frame, "wall");
  render::DeepLightMap dlm;
  lighting::DlmSettings s = centralOnly();
  ASSERT_TRUE(dlm.build(tex, {1, 0, 0}, s));  // sun low in the west, light travelling east
  reference::DlmReference ref(v, frame, dlm.lightSpace(), s, dlm.stats().step_m, dlm.stats().steps, 1);
  // A point well behind the wall (x at voxel 6) and one in front of it (voxel 1).
  const glm::dvec3 behind = frame.worldFromGrid({6.5, 4.0, 4.0});
  const glm::dvec3 front = frame.worldFromGrid({1.5, 4.0, 4.0});
  EXPECT_LT(ref.intensityAt(behind), 1e-6);
  EXPECT_NEAR(ref.intensityAt(front), 1.0, 1e-9);
  // The GPU map agrees (evaluate the texel through the centre).
  const auto rb = dlm.readBack();
  const auto l = dlm.lightSpace().lightFromWorld(behind);
  const glm::ivec2 t(glm::dvec2(l.x, l.y) / dlm.lightSpace().texelSize_m());
  const auto& nodes = rb.nodes[std::size_t(t.y * dlm.lightSpace().texels.x + t.x)];
  EXPECT_LT(lighting::evaluateLightFunction(nodes.data(), int(nodes.size()), l.z), 1e-3);
}

TEST_F(DlmTest, UnchangedKeyIsNotRebuilt) {
  const ExtinctionVolumes v = homogeneousSlab(8, 8, 8, 1e-3f);
  const auto frame = volume::frameOf(v);
  auto tex = render::VolumeTextures::upload(v, frame, "slab-key");
  render::DeepLightMap dlm;
  lighting::DlmSettings s;
  EXPECT_TRUE(dlm.build(tex, {0.3, 0.1, -1}, s));
  EXPECT_FALSE(dlm.build(tex, {0.3, 0.1, -1}, s));
  EXPECT_EQ(dlm.stats().reuses, 1u);
  s.epsilon *= 0.5;
  EXPECT_TRUE(dlm.build(tex, {0.3, 0.1, -1}, s));
  EXPECT_TRUE(dlm.build(tex, {0.3, 0.2, -1}, s));
  EXPECT_EQ(dlm.stats().builds, 3u);
}

TEST_F(DlmTest, NodeBudgetOverflowIsCountedAndTheBoundKeptByDoublingEpsilon) {
  const ExtinctionVolumes v = noisyVolume(12, 12, 12, 7);
  const auto frame = volume::frameOf(v);
  auto tex = render::VolumeTextures::upload(v, frame, "noise");
  render::DeepLightMap dlm;
  lighting::DlmSettings s = centralOnly();
  s.epsilon = 1e-4;
  s.max_nodes = 6;
  s.max_epsilon_doublings = 12;
  ASSERT_TRUE(dlm.build(tex, {0.2, 0.3, -1}, s));
  const auto& st = dlm.stats();
  EXPECT_GT(st.overflowed_texels, 0) << "the scene must overflow 6 nodes at eps 1e-4";
  EXPECT_EQ(st.unbounded_texels, 0);
  reference::DlmReference ref(v, frame, dlm.lightSpace(), s, st.step_m, st.steps, 1);
  const auto rb = dlm.readBack();
  for (int b = 0; b < dlm.lightSpace().texels.y; ++b)
    for (int a = 0; a < dlm.lightSpace().texels.x; ++a) {
      const std::size_t t = std::size_t(b * dlm.lightSpace().texels.x + a);
      ASSERT_LE(rb.nodes[t].size(), 6u);
      double maxErr = 0.0;
      for (int n = 0; n <= st.steps; ++n) {
        const double s_m = n * st.step_m;
        maxErr = std::max(maxErr,
                          std::abs(lighting::evaluateLightFunction(rb.nodes[t].data(), int(rb.nodes[t].size()), s_m) -
                                   ref.texelIntensity(a, b, s_m)));
      }
      if (maxErr > double(rb.texel_epsilon[t]) + kFloatSlack) {
        std::string dump;
        for (const auto& nd : rb.nodes[t]) dump += fmt::format(" ({:.0f},{:.4f})", nd.depth_m, nd.intensity);
        dump += "\n ref:";
        for (int n = 0; n <= st.steps; n += 4)
          dump += fmt::format(" ({:.0f},{:.4f})", n * st.step_m, ref.texelIntensity(a, b, n * st.step_m));
        FAIL() << "texel " << a << "," << b << " err " << maxErr << " eps " << rb.texel_epsilon[t] << " nodes" << dump;
      }
    }
  // With no doublings allowed the same texels are reported as unbounded instead.
  s.max_epsilon_doublings = 0;
  ASSERT_TRUE(dlm.build(tex, {0.2, 0.3, -1}, s));
  EXPECT_GT(dlm.stats().unbounded_texels, 0);
}

// The per-frame path's build without the statistics read back (issue 19 item 2;
// DeepLightMap::setStatsReadBack): the overflow rule's retries are dispatched indirectly from the
// march's own flags instead of from counts read on the CPU. Same settings on a scene whose texels
// overflow the node budget in passes 1 and 3 (up to 3 doublings of ε, some texels left unbounded):
// the map must be the same bit for bit, the statistics — read when first asked for — the same,
// and the build itself must not have read anything back.
TEST_F(DlmTest, WithoutStatsReadBackTheMapIsTheSame) {
  const ExtinctionVolumes v = noisyVolume(12, 12, 12, 7);
  const auto frame = volume::frameOf(v);
  auto tex = render::VolumeTextures::upload(v, frame, "noise");
  for (int doublings : {0, 3, 12}) {
    SCOPED_TRACE(fmt::format("max_epsilon_doublings {}", doublings));
    lighting::DlmSettings s;  // peripheral: pass 3 has its own retries
    s.epsilon = 1e-4;
    s.max_nodes = 6;
    s.max_epsilon_doublings = doublings;
    render::DeepLightMap withStats, without;
    without.setStatsReadBack(false);
    ASSERT_TRUE(withStats.build(tex, {0.2, 0.3, -1}, s));
    ASSERT_TRUE(without.build(tex, {0.2, 0.3, -1}, s));
    const std::uint64_t readBacksInBuild = without.stats().build_read_backs;  // stats() reads them now
    EXPECT_EQ(readBacksInBuild, 0u);
    EXPECT_GE(withStats.stats().build_read_backs, 3u + (doublings > 0 ? 1u : 0u));
    EXPECT_TRUE(withStats.stats().timed);
    EXPECT_FALSE(without.stats().timed);
    const auto& a = withStats.stats();
    const auto& b = without.stats();
    EXPECT_GT(a.overflowed_texels, 0) << "the scene must overflow 6 nodes at eps 1e-4";
    if (doublings == 3) {
      EXPECT_GT(a.unbounded_texels, 0) << "some texels must stay over budget at 8 eps";
    }
    EXPECT_EQ(a.overflowed_texels, b.overflowed_texels);
    EXPECT_EQ(a.unbounded_texels, b.unbounded_texels);
    EXPECT_EQ(a.node_histogram, b.node_histogram);
    EXPECT_EQ(a.texels_per_epsilon_doubling, b.texels_per_epsilon_doubling);
    EXPECT_EQ(a.marched_steps, b.marched_steps);
    EXPECT_EQ(a.runs, b.runs);
    const auto ra = withStats.readBack();
    const auto rb = without.readBack();
    ASSERT_EQ(ra.nodes.size(), rb.nodes.size());
    for (std::size_t t = 0; t < ra.nodes.size(); ++t) {
      ASSERT_EQ(ra.nodes[t].size(), rb.nodes[t].size()) << "texel " << t;
      for (std::size_t k = 0; k < ra.nodes[t].size(); ++k) {
        EXPECT_EQ(std::bit_cast<std::uint32_t>(ra.nodes[t][k].depth_m),
                  std::bit_cast<std::uint32_t>(rb.nodes[t][k].depth_m));
        EXPECT_EQ(std::bit_cast<std::uint32_t>(ra.nodes[t][k].intensity),
                  std::bit_cast<std::uint32_t>(rb.nodes[t][k].intensity));
      }
      EXPECT_EQ(ra.texel_epsilon[t], rb.texel_epsilon[t]) << "texel " << t;
      EXPECT_EQ(ra.unbounded[t], rb.unbounded[t]) << "texel " << t;
    }
    // Two more builds, nobody asking in between: the third summarises the second's copies (their
    // fence long passed) without a read-back; the statistics are then the third build's.
    ASSERT_TRUE(without.build(tex, {0.25, 0.3, -1}, s));
    ASSERT_TRUE(without.build(tex, {0.3, 0.2, -1}, s));
    ASSERT_TRUE(withStats.build(tex, {0.3, 0.2, -1}, s));
    EXPECT_EQ(without.stats().build_read_backs, 0u);
    EXPECT_EQ(without.stats().node_histogram, withStats.stats().node_histogram);
    EXPECT_EQ(without.stats().overflowed_texels, withStats.stats().overflowed_texels);
    EXPECT_EQ(without.stats().builds, 3u);
  }
}

// Empty-space skipping keeps the ε contract: it jumps only over steps whose β is 0 and pushes both
// ends of the skipped run, along which the sampled function is linear, so the stored function is
// within ε of the same samples as without skipping. (Node positions may differ: Algorithm 2 tests
// the slope to every pushed sample, and a skipped interior sample can no longer close a segment.)
// Hence the two maps agree within 2ε; in pass 1 the light on skipped runs is constant and exact.
TEST_F(DlmTest, EmptySpaceSkippingChangesNothing) {
  const ExtinctionVolumes v = generatedHurricane();
  const auto frame = volume::frameOf(v);
  auto tex = render::VolumeTextures::upload(v, frame, "hurricane");
  const glm::dvec3 light = -scene::Sun{110.0, 40.0}.toSun();
  for (bool peripheral : {false, true}) {
    lighting::DlmSettings s;
    s.peripheral = peripheral;
    render::DeepLightMap a, b;
    ASSERT_TRUE(a.build(tex, light, s));
    s.empty_space_skipping = false;
    ASSERT_TRUE(b.build(tex, light, s));
    const auto ra = a.readBack(), rb = b.readBack();
    ASSERT_EQ(ra.nodes.size(), rb.nodes.size());
    double maxDiff = 0.0;
    for (std::size_t t = 0; t < ra.nodes.size(); ++t) {
      for (int n = 0; n <= a.stats().steps; ++n) {
        const double sm = n * a.stats().step_m;
        maxDiff = std::max(maxDiff,
                           std::abs(lighting::evaluateLightFunction(ra.nodes[t].data(), int(ra.nodes[t].size()), sm) -
                                    lighting::evaluateLightFunction(rb.nodes[t].data(), int(rb.nodes[t].size()), sm)));
      }
    }
    EXPECT_LE(maxDiff, 2 * s.epsilon + 1e-6);
    std::printf("[ skip     ] %s: with skipping %.1f ms, without %.1f ms, max |difference| %.2e\n",
                peripheral ? "passes 1-3" : "pass 1", a.stats().pass1_ms + a.stats().pass2_ms + a.stats().pass3_ms,
                b.stats().pass1_ms + b.stats().pass2_ms + b.stats().pass3_ms, maxDiff);
  }
}

// The generated hurricane's map with the default settings, sun at azimuth 200°, elevation 35°.
struct HurricaneMap {
  ExtinctionVolumes volumes = generatedHurricane();
  volume::VolumeFrame frame = volume::frameOf(volumes);
  render::VolumeTextures textures = render::VolumeTextures::upload(volumes, frame, "hurricane");
  std::unique_ptr<render::DeepLightMap> dlm = built(textures);
  render::DeepLightMap::Readback map = dlm->readBack();

  static std::unique_ptr<render::DeepLightMap> built(const render::VolumeTextures& t) {
    auto d = std::make_unique<render::DeepLightMap>();
    d->build(t, -scene::Sun{200.0, 35.0}.toSun(), lighting::DlmSettings{});
    return d;
  }
};

// dlmIntensity (glsl/dlm/lookup.glsl) at `points` on the GPU, compiled with `defines`.
std::vector<float> glslLookup(const render::DeepLightMap& dlm, const std::vector<glm::vec4>& points,
                              const gl::Defines& defines = {}) {
  auto in = gl::Buffer::create(points.size() * sizeof(glm::vec4), points.data());
  auto out = gl::Buffer::create(points.size() * sizeof(float));
  auto prog = gl::Program::compute("test/dlm_lookup.comp", defines);
  prog.use();
  dlm.bindForLookup();
  prog.set("u_count", int(points.size()));
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, gl::binding::SSBO_TEST_POINTS, in.id());
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, gl::binding::SSBO_TEST_RESULTS, out.id());
  prog.dispatchCovering({int(points.size()), 1, 1});
  glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
  std::vector<float> gpu(points.size());
  out.download(0, gpu.size() * sizeof(float), gpu.data());
  return gpu;
}

// The GLSL look-up (used by the ray caster and for ground shadows) agrees with the CPU look-up on
// the read-back map at random points in and around the cloud, including below it (ground shadow:
// the light past the last node) and outside the map's footprint (full sun).
TEST_F(DlmTest, GlslLookupMatchesCpuLookup) {
  const HurricaneMap h;
  ASSERT_TRUE(h.dlm->stats().rebuilt);
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(-0.2, 1.2);
  std::vector<glm::vec4> points;
  for (int i = 0; i < 4096; ++i) {
    const glm::dvec3 p = h.frame.min_m() + h.frame.size_m() * glm::dvec3(u(rng), u(rng), u(rng));
    points.emplace_back(glm::vec3(p), 0.0f);
  }
  points.emplace_back(glm::vec3(h.frame.worldFromGrid({20.0, 18.0, 0.0})), 0.0f);  // ground under the storm
  const std::vector<float> gpu = glslLookup(*h.dlm, points);
  double maxDiff = 0.0;
  int inside = 0;
  for (std::size_t i = 0; i < points.size(); ++i) {
    // The CPU look-up at the float position the GPU saw.
    const double cpu = render::DeepLightMap::lookup(h.map, h.dlm->lightSpace(), glm::dvec3(glm::vec3(points[i])));
    maxDiff = std::max(maxDiff, std::abs(cpu - double(gpu[i])));
    if (cpu < 0.999) ++inside;
  }
  EXPECT_LE(maxDiff, 1e-4);  // float light-space transform vs double
  EXPECT_GT(inside, 200) << "the points must sample the shadowed part of the map";
  EXPECT_LT(gpu.back(), 0.5f) << "the ground under the storm is in shadow";
}

// The look-up's linear scan (issue 19) finds the same bracket as the binary search it replaced
// (DLM_LOOKUP_BINARY_SEARCH, kept as the benchmark baseline): the node depths never decrease, so
// the last node at or before s is unique. Same bracket, same arithmetic: the results must be equal
// bit for bit, at points between nodes, on nodes (to float rounding: either side of a node),
// before the first node and past the last.
TEST_F(DlmTest, DlmLookupLinearScanIsBitIdenticalToTheBinarySearch) {
  const HurricaneMap h;
  const volume::VolumeFrame& frame = h.frame;
  const render::DeepLightMap& dlm = *h.dlm;
  const auto& map = h.map;
  ASSERT_TRUE(dlm.stats().rebuilt);
  const lighting::LightSpace& ls = dlm.lightSpace();
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-0.1, 1.1);
  std::vector<glm::vec4> points;
  for (int i = 0; i < 8192; ++i) {
    points.emplace_back(glm::vec3(frame.min_m() + frame.size_m() * glm::dvec3(u(rng), u(rng), u(rng))), 0.0f);
  }
  // Texel centres at every node depth of a few texels with many nodes (s ≈ depth[k]).
  int withManyNodes = 0;
  for (int b = 0; b < ls.texels.y && withManyNodes < 16; ++b) {
    for (int a = 0; a < ls.texels.x && withManyNodes < 16; ++a) {
      const auto& nodes = map.nodes[std::size_t(b) * std::size_t(ls.texels.x) + std::size_t(a)];
      if (nodes.size() < 6) continue;
      ++withManyNodes;
      const glm::dvec2 uv = (glm::dvec2(a, b) + 0.5) * ls.texelSize_m();
      for (const auto& n : nodes) {
        points.emplace_back(glm::vec3(ls.worldFromLight({uv.x, uv.y, double(n.depth_m)})), 0.0f);
      }
    }
  }
  ASSERT_GT(withManyNodes, 0) << "the map must have texels with at least 6 nodes to scan";
  const std::vector<float> scan = glslLookup(dlm, points);
  const std::vector<float> binary = glslLookup(dlm, points, {{"DLM_LOOKUP_BINARY_SEARCH", "1"}});
  ASSERT_EQ(scan.size(), binary.size());
  int shadowed = 0;
  for (std::size_t i = 0; i < scan.size(); ++i) {
    ASSERT_EQ(std::bit_cast<std::uint32_t>(scan[i]), std::bit_cast<std::uint32_t>(binary[i]))
        << "point " << i << ": linear scan " << scan[i] << ", binary search " << binary[i];
    if (scan[i] < 0.999f) ++shadowed;
  }
  EXPECT_GT(shadowed, 500) << "the points must sample the shadowed part of the map";
  std::printf("[ scan     ] %zu points, %d shadowed, %d texels' nodes hit exactly, mean %.2f nodes per texel\n",
              scan.size(), shadowed, withManyNodes, dlm.stats().mean_nodes);
}

// Issue 19, "nothing computed that a scene does not need": pass 1 marches only the texels pass 2
// reads at its cell centres, pass 2 leaves the look-ups out of clear cells (T = 1, where the update
// is P_k = P_{k−1} exactly), and passes 1 and 3 take the empty-space skip as a loop of at most one
// pass instead of a masked branch. None changes a bit of the map against the unpruned passes
// (DlmBaseline::no_pruning): same node lists, same ε per texel. Cell sizes of 4 (the default:
// centres between texels) and 3 and 6 texels (with the map's texel counts not multiples of them,
// centres at fractions near 0 where float rounding picks either corner: the read margin), sun at
// two elevations (different texel counts, scatter maps) on the generated hurricane.
TEST_F(DlmTest, PrunedPassesBuildTheSameMapBitForBit) {
  const ExtinctionVolumes v = generatedHurricane();
  const auto frame = volume::frameOf(v);
  auto tex = render::VolumeTextures::upload(v, frame, "hurricane");
  for (const auto& [sun, ds] : {std::pair{scene::Sun{200.0, 35.0}, 4}, std::pair{scene::Sun{110.0, 60.0}, 3},
                                std::pair{scene::Sun{110.0, 60.0}, 6}}) {
    lighting::DlmSettings s;
    s.scatter_downsample = ds;
    render::DeepLightMap lean, full;
    full.setBaseline({.no_pruning = true});
    ASSERT_TRUE(lean.build(tex, -sun.toSun(), s));
    ASSERT_TRUE(full.build(tex, -sun.toSun(), s));
    const glm::ivec2 n = lean.lightSpace().texels;
    ASSERT_EQ(n, full.lightSpace().texels);
    const std::int64_t all = std::int64_t(n.x) * n.y;
    EXPECT_EQ(full.stats().pass1_texels, all);
    if (ds % 2 == 0) {
      EXPECT_LT(lean.stats().pass1_texels, all * 3 / 5) << "cell centres between texels: ≤ ½ per axis";
    }
    EXPECT_LE(lean.stats().pass1_texels, all);
    const auto a = lean.readBack(), b = full.readBack();
    ASSERT_EQ(a.nodes.size(), b.nodes.size());
    long differing = 0, nodes = 0, shadowed = 0;
    for (std::size_t t = 0; t < a.nodes.size(); ++t) {
      nodes += long(a.nodes[t].size());
      if (!a.nodes[t].empty() && a.nodes[t].back().intensity < 0.99f) ++shadowed;
      bool same = a.nodes[t].size() == b.nodes[t].size() && a.texel_epsilon[t] == b.texel_epsilon[t] &&
                  a.unbounded[t] == b.unbounded[t];
      for (std::size_t k = 0; same && k < a.nodes[t].size(); ++k) {
        same = std::bit_cast<std::uint32_t>(a.nodes[t][k].depth_m) ==
                   std::bit_cast<std::uint32_t>(b.nodes[t][k].depth_m) &&
               std::bit_cast<std::uint32_t>(a.nodes[t][k].intensity) ==
                   std::bit_cast<std::uint32_t>(b.nodes[t][k].intensity);
      }
      differing += same ? 0 : 1;
    }
    EXPECT_EQ(differing, 0) << "texels whose node lists differ from the full passes'";
    EXPECT_GT(shadowed, long(a.nodes.size()) / 20) << "the map must be shadowed somewhere to compare";
    std::printf("[ lean     ] %dx%d texels, cells of %d: pass 1 marched %lld (%.0f %%), %ld nodes, %ld shadowed "
                "texels; passes %.0f+%.0f+%.0f ms (full %.0f+%.0f+%.0f)\n",
                n.x, n.y, ds, static_cast<long long>(lean.stats().pass1_texels),
                100.0 * double(lean.stats().pass1_texels) / double(all), nodes, shadowed, lean.stats().pass1_ms,
                lean.stats().pass2_ms, lean.stats().pass3_ms, full.stats().pass1_ms, full.stats().pass2_ms,
                full.stats().pass3_ms);
  }
}

// The adaptive light step (issue 19, session 16; DlmSettings::step_growth_max, glsl/dlm/march.comp).
// Each map is within its texel's ε of the samples it was given (Nes 2008 §5.3.4, §5.4); the adaptive
// march's samples are within step_growth_budget·ε of the fixed step's (the budget argument in
// march.comp). So at every step of every texel |I_adaptive − I_fixed| ≤ ε_a + ε_f + budget·ε, plus
// float rounding (kFloatSlack) and β's half-float rounding in a run's bound (2⁻¹¹ relative of a
// bound that is itself ≤ the budget). Returns the largest difference and the largest excess over
// that bound (≤ 0 when it holds); unbounded texels (no ε kept) are left out.
struct StepComparison {
  double max_diff = 0.0, max_excess = -1.0;
};
StepComparison compareSteps(const render::DeepLightMap& adaptive, const render::DeepLightMap& fixed) {
  const auto ra = adaptive.readBack(), rf = fixed.readBack();
  EXPECT_EQ(ra.nodes.size(), rf.nodes.size());
  const double budget = adaptive.settings().step_growth_budget * adaptive.settings().epsilon;
  StepComparison c;
  for (std::size_t t = 0; t < ra.nodes.size() && t < rf.nodes.size(); ++t) {
    if (ra.unbounded[t] || rf.unbounded[t]) continue;
    const double allowed = double(ra.texel_epsilon[t]) + double(rf.texel_epsilon[t]) + budget + kFloatSlack;
    for (int n = 0; n <= fixed.stats().steps; ++n) {
      const double sm = n * fixed.stats().step_m;
      const double d = std::abs(lighting::evaluateLightFunction(ra.nodes[t].data(), int(ra.nodes[t].size()), sm) -
                                lighting::evaluateLightFunction(rf.nodes[t].data(), int(rf.nodes[t].size()), sm));
      c.max_diff = std::max(c.max_diff, d);
      c.max_excess = std::max(c.max_excess, d - allowed);
    }
  }
  return c;
}

// On a storm with cloud edges everywhere (issue 13's coarse storm: convective cells, a stratiform
// shield, clear gaps), the adaptive step stays within its bound of the fixed step in both passes,
// and it does take runs (else the comparison would prove nothing).
TEST_F(DlmTest, AdaptiveStepStaysWithinItsBoundOfTheFixedStep) {
  const ExtinctionVolumes v = coarseStorm();
  const auto frame = volume::frameOf(v, 8.0);
  auto tex = render::VolumeTextures::upload(v, frame, "coarse storm");
  const glm::dvec3 light = -scene::Sun{140.0, 35.0}.toSun();
  for (bool peripheral : {false, true}) {
    lighting::DlmSettings s;
    s.peripheral = peripheral;
    render::DeepLightMap fixed, adaptive;
    ASSERT_TRUE(fixed.build(tex, light, s));
    s.step_growth_max = 4;
    ASSERT_TRUE(adaptive.build(tex, light, s));
    EXPECT_EQ(fixed.stats().run_steps, 0);
    EXPECT_EQ(fixed.stats().runs, 0);
    EXPECT_GT(adaptive.stats().runs, 0) << "no run taken: the test would compare the fixed step with itself";
    EXPECT_LE(adaptive.stats().run_steps, 4 * adaptive.stats().runs);
    const StepComparison c = compareSteps(adaptive, fixed);
    EXPECT_LE(c.max_excess, 0.0) << "max |difference| " << c.max_diff;
    std::printf("[ adaptive ] %s: %lld of %lld steps in %lld runs, max |difference| %.2e (bound ≈ %.3f)\n",
                peripheral ? "passes 1-3" : "pass 1", static_cast<long long>(adaptive.stats().run_steps),
                static_cast<long long>(adaptive.stats().marched_steps), static_cast<long long>(adaptive.stats().runs),
                c.max_diff, 2.5 * s.epsilon);
  }
}

// A thin dense sheet (one layer, τ = 2) inside a large uniform cloud (τ = 0.01 per layer): the runs
// through the uniform bricks must not step across the sheet. Its brick's (max, min) makes the
// bound large, so the march stays fine there; a run of 4 Δ over the sheet (its trilinear profile
// is 4 Δ wide) would sample β once at the run's midpoint — on the sheet's peak (τ doubled) or
// beside it (the sheet missed) — and move the light below it by far more than the bound.
TEST_F(DlmTest, AdaptiveStepDoesNotStepAcrossAThinDenseSheet) {
  constexpr int kSheet = 24;
  ExtinctionVolumes v = homogeneousSlab(32, 32, 48, 4e-5f);  // 250 m layers: τ 0.01 each
  for (int j = 0; j < v.ny; ++j)
    for (int i = 0; i < v.nx; ++i) v.water_per_m[v.index(i, j, kSheet)] = 8e-3f;  // τ 2
  v.updateMaxima();
  const auto frame = volume::frameOf(v);
  auto tex = render::VolumeTextures::upload(v, frame, "sheet");
  const glm::dvec3 light = -scene::Sun{200.0, 60.0}.toSun();
  lighting::DlmSettings s;
  render::DeepLightMap fixed, adaptive;
  ASSERT_TRUE(fixed.build(tex, light, s));
  s.step_growth_max = 4;
  ASSERT_TRUE(adaptive.build(tex, light, s));
  // Runs in the uniform bricks above and below the sheet's (bricks 1 and 4 of 6 along z).
  EXPECT_GT(adaptive.stats().run_steps, adaptive.stats().marched_steps / 20);
  const StepComparison c = compareSteps(adaptive, fixed);
  EXPECT_LE(c.max_excess, 0.0) << "max |difference| " << c.max_diff;
  // The sheet's shadow itself, in the middle of the map: the light 1½ layers below the sheet's
  // centre against 2½ above it (clear of its trilinear profile), the same in both maps within the
  // bound — and a shadow: the slant τ 2.3 through the sheet less the central forward share.
  const auto ra = adaptive.readBack(), rf = fixed.readBack();
  auto at = [&](const render::DeepLightMap::Readback& map, double k) {
    return render::DeepLightMap::lookup(map, adaptive.lightSpace(), frame.worldFromGrid({16.0, 16.0, k}));
  };
  const double above = at(ra, kSheet + 3.0), below = at(ra, kSheet - 1.0);
  EXPECT_LT(below, 0.5 * above) << "the sheet casts no shadow";
  EXPECT_NEAR(below, at(rf, kSheet - 1.0), 2.5 * s.epsilon + kFloatSlack);
  std::printf("[ sheet    ] %lld of %lld steps in %lld runs, max |difference| %.2e; light above %.4f, below %.4f\n",
              static_cast<long long>(adaptive.stats().run_steps),
              static_cast<long long>(adaptive.stats().marched_steps), static_cast<long long>(adaptive.stats().runs),
              c.max_diff, above, below);
}

}  // namespace
}  // namespace nph::test
namespace nph::test {
TEST(DlmScenes, GeneratedHurricaneHasCloud) {
  const ExtinctionVolumes v = generatedHurricane();
  float mx = 0.0f;
  std::size_t nans = 0;
  for (float x : v.water_per_m) {
    if (std::isnan(x)) ++nans;
    else mx = std::max(mx, x);
  }
  std::printf("hurricane %dx%dx%d dz %g zb %g water max %g (stored %g), nans %zu, sizes %zu %zu\n", v.nx, v.ny, v.nz,
              v.dz_m, v.z_bottom_m, double(mx), double(v.max_water_per_m), nans, v.water_per_m.size(),
              v.ice_per_m.size());
  EXPECT_GT(mx, 1e-3f);
}
}  // namespace nph::test
