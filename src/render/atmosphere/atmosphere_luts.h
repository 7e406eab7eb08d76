#pragma once
// The atmosphere's look-up tables on the GPU (issue 14 item 1; Hillaire 2020 §5, Bruneton 2017):
// built by the compute shaders of glsl/atmosphere/ — at construction the transmittance (256×64),
// multiple-scattering Ψ_ms (64×32) and sky-irradiance (64×16) tables, which depend on the
// atmosphere only; per frame, when the observer's altitude or the sun moved, the sky-view table
// (192×108). Ψ_ms has 64 columns of μ_s, not Hillaire's 32, for twilight (docs/atmosphere.md).
// The CPU oracle of every table is atmosphere/atmosphere.h (tests/atmosphere).
#include <glm/glm.hpp>

#include "atmosphere/atmosphere.h"
#include "render/gl/objects.h"
#include "render/gl/program.h"
#include "render/gl/uniform_blocks.h"

namespace nph::render {

class AtmosphereLuts {
 public:
  static constexpr glm::ivec2 kTransmittanceSize{256, 64};
  static constexpr glm::ivec2 kMultiScatteringSize{64, 32};
  static constexpr glm::ivec2 kSkyIrradianceSize{64, 16};
  static constexpr glm::ivec2 kSkyViewSize{192, 108};

  /// Builds the tables that depend on the atmosphere alone (a GL context must be current).
  explicit AtmosphereLuts(const atmosphere::Parameters& parameters = atmosphere::Parameters::earth());

  /// Rebuilds the sky-view table for an observer at `altitude_m` (clamped into the atmosphere)
  /// with the sun towards `to_sun` (z up; only its elevation matters: the table puts the sun at
  /// azimuth 0). Does nothing when neither changed. Returns true when it rebuilt.
  bool updateSkyView(double altitude_m, const glm::dvec3& to_sun);
  /// Binds the block and the four tables for the passes that read them (glsl/atmosphere/sky.glsl).
  void bind() const;

  const atmosphere::Parameters& parameters() const { return parameters_; }
  /// Wall time of the start-up tables (incl. glFinish) and of the last sky-view build [ms].
  double buildMilliseconds() const { return build_ms_; }
  double skyViewMilliseconds() const { return sky_view_ms_; }

 private:
  void run(const gl::Program& program, const gl::Texture& target, glm::ivec2 size);

  atmosphere::Parameters parameters_;
  gl::AtmosphereBlock block_;
  gl::UniformBuffer<gl::AtmosphereBlock> ubo_;
  gl::Program sky_view_program_;
  gl::Texture transmittance_, multi_scattering_, sky_irradiance_, sky_view_;
  double build_ms_ = 0.0, sky_view_ms_ = 0.0;
  bool sky_view_valid_ = false;
};

}  // namespace nph::render
