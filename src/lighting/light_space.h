#pragma once
// The deep light map's light-space grid (Nes 2008 §5.3: "the z-axis of the light map will be
// aligned along the light direction"), fitted tightly to the non-empty part of the volume.
//
// Basis: w = direction the sunlight travels (−toSun), u and v span the plane orthogonal to it.
// A texel (a, b) of an nu × nv map owns the light ray  p(s) = origin + (a+½)·du·u + (b+½)·dv·v + s·w,
// s ∈ [0, depth_m]; s = 0 is where the ray enters the fitted box. Any sun direction works: zenith,
// along a grid axis, grazing (the box just gets long along w), even below the horizon (the map then
// lights from below; the renderer decides whether that is wanted).
#include <array>
#include <type_traits>

#include <glm/glm.hpp>

#include "core/glsl_cpp.h"

namespace nph::lighting {

struct LightSpace {
  glm::dvec3 u{1, 0, 0}, v{0, 1, 0}, w{0, 0, -1};  ///< orthonormal, w = light travel direction
  glm::dvec3 origin_m{0.0};  ///< world position of light-space (0, 0, 0): corner of the fitted box
  glm::dvec2 extent_m{0.0};  ///< size of the map along u and v
  double depth_m = 0.0;      ///< length of every light ray through the fitted box
  glm::ivec2 texels{1, 1};   ///< nu, nv

  glm::dvec2 texelSize_m() const { return extent_m / glm::dvec2(texels); }
  /// World -> light space (metres along u, v, w from origin).
  glm::dvec3 lightFromWorld(const glm::dvec3& world_m) const {
    const glm::dvec3 d = world_m - origin_m;
    return {glm::dot(d, u), glm::dot(d, v), glm::dot(d, w)};
  }
  glm::dvec3 worldFromLight(const glm::dvec3& light_m) const {
    return origin_m + light_m.x * u + light_m.y * v + light_m.z * w;
  }
  /// World position of the start of texel (a, b)'s ray (s = 0).
  glm::dvec3 rayStart(int a, int b) const {
    const glm::dvec2 t = texelSize_m();
    return worldFromLight({(a + 0.5) * t.x, (b + 0.5) * t.y, 0.0});
  }
};

namespace light_blend_f64 {  // glsl/common/light_blend.glsl compiled as C++ in double (core/glsl_cpp.h)
using namespace nph::glsl;
using Number = double;
/// The shared blend with LF_TEXEL bound to a callable: the file's function becomes a member.
template <class TexelValue>
struct Blend {
  TexelValue& texelValue;
#define LF_TEXEL(a, b, s) Number(texelValue(a, b, s))
#include "../glsl/common/light_blend.glsl"
#undef LF_TEXEL
};
}  // namespace light_blend_f64

/// The DLM look-up's blending rule on the CPU — glsl/common/light_blend.glsl, the file the eye
/// pass runs: light-space position l → bilinear blend of `texelValue(a, b, l.z)` over the four
/// texels around (l.x, l.y), clamped to the edge texels; 1 (full sun) outside the map's footprint.
template <class TexelValue>
double blendTexels(const LightSpace& ls, const glm::dvec3& l, TexelValue&& texelValue) {
  const glm::dvec2 texel = ls.texelSize_m();
  light_blend_f64::Blend<std::remove_reference_t<TexelValue>> blend{texelValue};
  return blend.lightBlend(l.x, l.y, l.z, texel.x, texel.y, ls.texels.x, ls.texels.y);
}

/// Orthonormal basis with w = `lightDirection` (normalised here). u is horizontal whenever the
/// light is not vertical; for a vertical light u = +x, v = ±y.
void lightBasis(const glm::dvec3& lightDirection, glm::dvec3& u, glm::dvec3& v, glm::dvec3& w);

/// Fits the light-space box around the world AABB [boxMin, boxMax] (the non-empty part of the
/// volume) for light travelling along `lightDirection`. The map has texels of about
/// `texelSize_m` along u and v (rounded so the extent is covered; at most `maxTexels` per side,
/// texels grow instead).
LightSpace fitLightSpace(const glm::dvec3& lightDirection, const glm::dvec3& boxMin, const glm::dvec3& boxMax,
                         glm::dvec2 texelSize_m, int maxTexels);

/// Texel size along u and v that resolves voxels of `voxelSize_m` seen from the light: the width of
/// one voxel projected onto each axis (Σ_i |axis_i|·voxel_i), times `texelVoxels`. Zenith sun over
/// a 3 km × 3 km × 250 m grid gives 3 km texels; a grazing sun gives ≈ 250 m along the vertical axis.
glm::dvec2 lightTexelSize(const LightSpace& basis, const glm::dvec3& voxelSize_m, double texelVoxels);

}  // namespace nph::lighting
