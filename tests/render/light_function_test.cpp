#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>

#include "lighting/light_function.h"
#include "lighting/light_space.h"
#include "volume/extinction_sampler.h"
#include "volume/occupancy.h"
#include "volume/volume_frame.h"

namespace nph::scene {
namespace {

double maxDeviation(const std::vector<lighting::LightNode>& nodes, const std::vector<double>& s,
                    const std::vector<double>& I) {
  double m = 0.0;
  for (std::size_t i = 0; i < s.size(); ++i) {
    m = std::max(m, std::abs(lighting::evaluateLightFunction(nodes.data(), int(nodes.size()), s[i]) - I[i]));
  }
  return m;
}

TEST(LightFunction, CompressionKeepsEpsilonOnRandomFunctions) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  for (double eps : {0.0, 1e-4, 1e-2, 0.1}) {
    for (int trial = 0; trial < 50; ++trial) {
      std::vector<double> s, I;
      double v = 1.0;
      for (int n = 0; n < 300; ++n) {
        s.push_back(n * 125.0);
        v = std::clamp(v * (0.97 + 0.04 * u(rng)) + (u(rng) < 0.05 ? 0.05 : 0.0), 0.0, 1.0);
        I.push_back(v);
      }
      const auto nodes = lighting::compressLightFunction(s, I, eps);
      // float storage of depth/intensity: 1e-6 absolute
      EXPECT_LE(maxDeviation(nodes, s, I), eps + 1e-6) << "eps " << eps;
      EXPECT_LE(nodes.size(), s.size());
    }
  }
}

TEST(LightFunction, LinearPiecesNeedOnlyTheirEnds) {
  std::vector<double> s, I;
  for (int n = 0; n <= 100; ++n) {
    s.push_back(n);
    I.push_back(n <= 40 ? 1.0 : 1.0 - 0.01 * (n - 40));  // flat, then a straight ramp
  }
  const auto nodes = lighting::compressLightFunction(s, I, 1e-6);
  ASSERT_EQ(nodes.size(), 3u);
  EXPECT_FLOAT_EQ(nodes[1].depth_m, 40.0f);
  EXPECT_FLOAT_EQ(nodes[2].intensity, 0.4f);
}

TEST(LightFunction, ConstantRayIsOneNode) {
  const std::vector<double> s = {0, 1, 2, 3}, I = {1, 1, 1, 1};
  EXPECT_EQ(lighting::compressLightFunction(s, I, 0.0).size(), 1u);
}

TEST(LightFunction, EvaluationClampsAndInterpolates) {
  const std::vector<lighting::LightNode> n = {{10, 1.0f}, {20, 0.5f}, {40, 0.25f}};
  EXPECT_DOUBLE_EQ(lighting::evaluateLightFunction(n.data(), 3, 0.0), 1.0);
  EXPECT_DOUBLE_EQ(lighting::evaluateLightFunction(n.data(), 3, 15.0), 0.75);
  EXPECT_DOUBLE_EQ(lighting::evaluateLightFunction(n.data(), 3, 30.0), 0.375);
  EXPECT_DOUBLE_EQ(lighting::evaluateLightFunction(n.data(), 3, 99.0), 0.25);
  EXPECT_DOUBLE_EQ(lighting::evaluateLightFunction(n.data(), 0, 5.0), 1.0);
}

TEST(LightSpace, FitsTheBoxForZenithAxisAndGrazingSuns) {
  const glm::dvec3 lo(0, 0, 0), hi(30000, 20000, 5000);
  for (glm::dvec3 d : {glm::dvec3(0, 0, -1), glm::dvec3(1, 0, 0), glm::dvec3(0, -1, 0),
                       glm::dvec3(std::cos(0.01745), 0, -std::sin(0.01745)), glm::dvec3(0.3, -0.2, -0.9)}) {
    const lighting::LightSpace ls = lighting::fitLightSpace(d, lo, hi, {500.0, 500.0}, 4096);
    EXPECT_NEAR(glm::length(ls.w), 1.0, 1e-12);
    EXPECT_NEAR(glm::dot(ls.u, ls.v), 0.0, 1e-12);
    EXPECT_NEAR(glm::dot(ls.u, ls.w), 0.0, 1e-12);
    EXPECT_NEAR(glm::dot(glm::cross(ls.u, ls.v), ls.w), 1.0, 1e-12) << "right-handed";
    const glm::dvec2 ext = ls.texelSize_m() * glm::dvec2(ls.texels);
    for (int c = 0; c < 8; ++c) {  // every box corner is inside the light-space box
      const glm::dvec3 p((c & 1) ? hi.x : lo.x, (c & 2) ? hi.y : lo.y, (c & 4) ? hi.z : lo.z);
      const glm::dvec3 l = ls.lightFromWorld(p);
      EXPECT_GE(l.x, -1e-6);
      EXPECT_GE(l.y, -1e-6);
      EXPECT_GE(l.z, -1e-6);
      EXPECT_LE(l.x, ext.x + 1e-6);
      EXPECT_LE(l.y, ext.y + 1e-6);
      EXPECT_LE(l.z, ls.depth_m + 1e-6);
    }
  }
  // Zenith sun: depth is the box height, texels are 500 m.
  const lighting::LightSpace z = lighting::fitLightSpace({0, 0, -1}, lo, hi, {500.0, 500.0}, 4096);
  EXPECT_NEAR(z.depth_m, 5000.0, 1e-9);
  EXPECT_EQ(z.texels.x * z.texels.y, 60 * 40);
}

TEST(LightSpace, GrazingSunGetsVerticalResolution) {
  lighting::LightSpace basis;
  lighting::lightBasis({std::cos(0.01745), 0, -std::sin(0.01745)}, basis.u, basis.v, basis.w);
  const glm::dvec2 t = lighting::lightTexelSize(basis, {3000, 3000, 250}, 1.0);
  EXPECT_LT(std::min(t.x, t.y), 400.0) << "one light-space axis is nearly vertical: ~dz";
}

TEST(Occupancy, BricksAreDilatedByOneVoxel) {
  ExtinctionVolumes v;
  v.nx = v.ny = v.nz = 16;
  v.water_per_m.assign(v.voxelCount(), 0.0f);
  v.water_per_m[v.index(8, 3, 3)] = 2.0f;  // first voxel of brick (1, 0, 0)
  const volume::OccupancyGrid g = volume::buildOccupancy(v, 8);
  EXPECT_EQ(g.at(1, 0, 0), 2.0f);
  EXPECT_EQ(g.at(0, 0, 0), 2.0f) << "voxel 7 of brick 0 interpolates with voxel 8";
  EXPECT_EQ(g.at(0, 1, 0), 0.0f);
  EXPECT_EQ(g.nonEmptyMinVoxel, glm::ivec3(8, 3, 3));
}

// Issue 19 (the DLM's adaptive light step, glsl/dlm/march.comp): min_per_m bounds every sample
// the filter can return inside its brick from below, and is the voxels' value in the interior of a
// uniform region (where the light march may take runs) and 0 at the grid's faces and beside a
// clear voxel (where it must not).
TEST(Occupancy, LowerBoundHoldsForEverySampleInTheBrick) {
  ExtinctionVolumes v = ExtinctionVolumes::zeros(32, 32, 24, 3000.0, 250.0, 0.0);
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> u(1e-3f, 3e-3f);
  for (float& b : v.water_per_m) b = u(rng);
  v.water_per_m[v.index(28, 28, 20)] = 0.0f;  // a clear voxel in brick (3, 3, 2)
  v.updateMaxima();
  const volume::VolumeFrame frame = volume::frameOf(v);
  for (auto r : {volume::Reconstruction::Trilinear, volume::Reconstruction::Cubic}) {
    const volume::OccupancyGrid g = volume::buildOccupancy(v, 8, r);
    ASSERT_EQ(g.min_per_m.size(), g.max_per_m.size());
    const volume::ExtinctionSampler sampler(v, frame, r);
    std::uniform_real_distribution<double> x(0.0, 1.0);
    int below = 0;
    for (int n = 0; n < 20000; ++n) {
      const glm::dvec3 grid(x(rng) * v.nx, x(rng) * v.ny, x(rng) * v.nz);
      const glm::ivec3 b = glm::min(glm::ivec3(glm::floor(grid)), glm::ivec3(v.nx, v.ny, v.nz) - 1) / g.brick;
      const std::size_t i =
          (std::size_t(b.z) * std::size_t(g.bricks.y) + std::size_t(b.y)) * std::size_t(g.bricks.x) + std::size_t(b.x);
      const double beta = sampler.at(frame.worldFromGrid(grid)).total();
      below += beta < double(g.min_per_m[i]) * (1.0 - 1e-6) ? 1 : 0;
      ASSERT_LE(beta, double(g.max_per_m[i]) * (1.0 + 1e-6));
    }
    EXPECT_EQ(below, 0) << volume::kReconstructionNames[std::size_t(r)];
    auto minAt = [&](int i, int j, int k) {
      return g.min_per_m[(std::size_t(k) * std::size_t(g.bricks.y) + std::size_t(j)) * std::size_t(g.bricks.x) +
                         std::size_t(i)];
    };
    EXPECT_GE(minAt(1, 1, 1), 1e-3f) << "brick (1, 1, 1): every neighbour in the uniform cloud";
    EXPECT_EQ(minAt(0, 1, 1), 0.0f) << "brick (0, 1, 1) touches a face: the zero border";
    EXPECT_EQ(minAt(2, 2, 1), 0.0f) << "brick (2, 2, 1) neighbours the clear voxel's brick";
  }
  const volume::OccupancyGrid spline = volume::buildOccupancy(v, 8, volume::Reconstruction::CubicInterpolating);
  EXPECT_EQ(*std::max_element(spline.min_per_m.begin(), spline.min_per_m.end()), 0.0f)
      << "the interpolating spline has no lower bound";
}

}  // namespace
}  // namespace nph::scene
