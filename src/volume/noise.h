#pragma once
// CPU twin of the detail noise volume (issue 13; glsl/common/noise.glsl, generated on the GPU by
// glsl/render/noise.comp, render/dlm/noise_texture.h): the same texels, computed by compiling the
// shader's functions as C++ (core/glsl_cpp.h), quantised to 8 bits as the GPU's RGBA8 texture,
// and sampled with GL_LINEAR + GL_REPEAT's rule. Also the tile statistics the detail needs to centre
// and scale its noise terms (glsl/common/detail.glsl): measured once on these texels and handed to
// the shaders as uniforms, so both sides use the same numbers.
#include <array>
#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

namespace nph::volume {

/// Texels per side of the periodic noise tile (64³ RGBA8 = 1 MiB): 16 texels per lattice cell of
/// the coarsest octave, 4 of the finest (noise.glsl). glsl/common/detail_field.glsl's
/// kDetailNoiseTexels must equal it (checked in volume/extinction_sampler.cpp).
inline constexpr int kNoiseTexels = 64;
/// Levels of the tile's mipmap chain, 64³ … 1³: the detail's level of detail (issue 13; the noise
/// is read prefiltered to the pixel's footprint, glsl/common/detail_field.glsl detailNoiseLod).
inline constexpr int kNoiseLevels = 7;

/// (mean, half range) of one noise term: the term minus the mean, divided by the half range, lies in
/// [−1, 1] with mean 0 over the tile.
struct NoiseTermStats {
  double mean = 0.0;
  double half_range = 1.0;
};

struct NoiseStats {
  NoiseTermStats r, g, a;     ///< single channels (the displacement's three axes)
  NoiseTermStats stratiform;  ///< n1.r + n2.a (detail.glsl detailDensity)
  NoiseTermStats convective;  ///< n1.r · n1.g · n2.b
};

struct NoiseVolume {
  std::vector<std::uint8_t> rgba;  ///< kNoiseTexels³ texels × 4 channels, x fastest (level 0)
  /// Levels 1 … kNoiseLevels − 1 (noiseMipLevel of the level before; (kNoiseTexels >> level)³ texels).
  std::vector<std::vector<std::uint8_t>> mips;
  NoiseStats stats;
  /// GL_LINEAR with GL_REPEAT at tile coordinates q (1 = one tile), channels in [0, 1] (level 0).
  glm::dvec4 sample(const glm::dvec3& q) const;
  /// textureLod with GL_LINEAR_MIPMAP_LINEAR (minification), GL_LINEAR (magnification) and
  /// GL_REPEAT (OpenGL 4.5 §8.14): level 0 for lod ≤ 0, else the two levels around lod blended by its
  /// fraction, the last level beyond it.
  glm::dvec4 sampleLod(const glm::dvec3& q, double lod) const;
  glm::dvec4 texel(int i, int j, int k) const;
};

/// The next level of the tile's mipmap chain: each texel the mean of its 2 × 2 × 2 texels in
/// `finer` (finer_size³ RGBA8 texels), rounded to the nearest code. The GPU's chain is made by this
/// function too (render/dlm/noise_texture.cpp), so both sides filter alike.
std::vector<std::uint8_t> noiseMipLevel(const std::vector<std::uint8_t>& finer, int finer_size);
/// Levels 1 … kNoiseLevels − 1 from level 0.
std::vector<std::vector<std::uint8_t>> noiseMipChain(const std::vector<std::uint8_t>& level0);

/// The float texel noise.glsl computes at texel (i, j, k) of a kNoiseTexels³ tile, before quantisation.
glm::vec4 noiseTexelFloat(int i, int j, int k);
/// The RGBA8 code of a channel value in [0, 1] (GL's UNORM conversion: round(v·255)).
std::uint8_t unormCode(float v);

/// The noise volume, computed on first use (thread-safe, ~0.1–0.5 s) and kept for the process.
const NoiseVolume& noiseVolume();

}  // namespace nph::volume
