#include "render/atmosphere/atmosphere_luts.h"

#include <algorithm>
#include <chrono>
#include <cmath>

#include "render/gl/debug.h"

namespace nph::render {
namespace {

gl::AtmosphereBlock blockOf(const atmosphere::Parameters& p) {
  gl::AtmosphereBlock b;
  b.rayleigh_scattering_per_m = glm::vec3(p.rayleigh_scattering_per_m);
  b.bottom_radius_m = float(p.bottom_radius_m);
  b.mie_scattering_per_m = glm::vec3(p.mie_scattering_per_m);
  b.top_radius_m = float(p.top_radius_m);
  b.mie_extinction_per_m = glm::vec3(p.mie_scattering_per_m + p.mie_absorption_per_m);
  b.rayleigh_scale_height_m = float(p.rayleigh_scale_height_m);
  b.ozone_absorption_per_m = glm::vec3(p.ozone_absorption_per_m);
  b.mie_scale_height_m = float(p.mie_scale_height_m);
  b.ground_albedo = glm::vec3(p.ground_albedo);
  b.mie_g = float(p.mie_g);
  b.ozone_center_m = float(p.ozone_center_m);
  b.ozone_half_width_m = float(p.ozone_half_width_m);
  b.sun_angular_radius_rad = float(p.sun_angular_radius_rad);
  b.sky_view_radius_m = float(p.bottom_radius_m);
  b.multiple_scattering = p.multiple_scattering ? 1u : 0u;
  return b;
}

gl::Texture lut(glm::ivec2 size, const char* name) {
  return gl::Texture::create2D(GL_RGBA32F, size.x, size.y).label(name).sampling(GL_LINEAR, GL_CLAMP_TO_EDGE);
}

}  // namespace

AtmosphereLuts::AtmosphereLuts(const atmosphere::Parameters& p)
    : parameters_(p),
      block_(blockOf(p)),
      ubo_(gl::UniformBuffer<gl::AtmosphereBlock>::create(block_, "atmosphere block")),
      sky_view_program_(gl::Program::compute("atmosphere/sky_view.comp")) {
  gl::DebugGroup group("atmosphere tables");
  const auto t0 = std::chrono::steady_clock::now();
  transmittance_ = lut(kTransmittanceSize, "atmosphere transmittance");
  multi_scattering_ = lut(kMultiScatteringSize, "atmosphere multiple scattering");
  sky_irradiance_ = lut(kSkyIrradianceSize, "atmosphere sky irradiance");
  sky_view_ = lut(kSkyViewSize, "atmosphere sky view");
  bind();
  // Each pass reads the tables of the ones before it (Hillaire 2020 Fig. 2).
  run(gl::Program::compute("atmosphere/transmittance.comp"), transmittance_, kTransmittanceSize);
  run(gl::Program::compute("atmosphere/multiscattering.comp"), multi_scattering_, kMultiScatteringSize);
  run(gl::Program::compute("atmosphere/sky_irradiance.comp"), sky_irradiance_, kSkyIrradianceSize);
  glFinish();
  gl::checkErrors("atmosphere tables");
  build_ms_ = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}

void AtmosphereLuts::run(const gl::Program& program, const gl::Texture& target, glm::ivec2 size) {
  program.use();
  glBindImageTexture(gl::binding::IMAGE_ATMOSPHERE_LUT, target.id(), 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_RGBA32F);
  program.dispatchCovering({size.x, size.y, 1});
  glMemoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT | GL_SHADER_IMAGE_ACCESS_BARRIER_BIT);
}

bool AtmosphereLuts::updateSkyView(double altitude_m, const glm::dvec3& to_sun) {
  const atmosphere::Parameters& p = parameters_;
  // Inside the atmosphere, at least 1 m above the ground (the table's horizon needs r > R).
  const double r = std::clamp(p.bottom_radius_m + altitude_m, p.bottom_radius_m + 1.0, p.top_radius_m - 1.0);
  const glm::dvec3 s = glm::normalize(to_sun);
  const glm::vec3 sun(float(std::sqrt(std::max(1.0 - s.z * s.z, 0.0))), 0.0f, float(s.z));
  if (sky_view_valid_ && block_.sky_view_radius_m == float(r) && block_.sky_view_to_sun == sun) return false;
  gl::DebugGroup group("atmosphere sky view");
  const auto t0 = std::chrono::steady_clock::now();
  block_.sky_view_radius_m = float(r);
  block_.sky_view_to_sun = sun;
  ubo_.update(block_);
  bind();
  run(sky_view_program_, sky_view_, kSkyViewSize);
  gl::checkErrors("atmosphere sky view");
  sky_view_ms_ = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  sky_view_valid_ = true;
  return true;
}

void AtmosphereLuts::bind() const {
  ubo_.bind();
  glBindTextureUnit(gl::binding::UNIT_TRANSMITTANCE_LUT, transmittance_.id());
  glBindTextureUnit(gl::binding::UNIT_MULTISCATTERING_LUT, multi_scattering_.id());
  glBindTextureUnit(gl::binding::UNIT_SKY_IRRADIANCE_LUT, sky_irradiance_.id());
  glBindTextureUnit(gl::binding::UNIT_SKY_VIEW_LUT, sky_view_.id());
}

}  // namespace nph::render
