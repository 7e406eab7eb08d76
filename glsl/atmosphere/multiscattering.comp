#version 450 core
// Hillaire 2020 §5.5's multiple-scattering table Ψ_ms(μ_s, h) (his MultiScatteringLut), eqs. 5–10:
// from the texel's point x, 64 directions ω (8 equal-area bands of cos θ × 8 azimuths) each march
// to the ground or the top gathering once-scattered sunlight with an isotropic phase (L') and the
// unit-light transfer (L_f); the lit Lambertian ground closes a ray that hits it.
//   L_2nd = Σ L'·p_u·dΩ, f_ms = Σ L_f·p_u·dΩ, Ψ_ms = L_2nd / (1 − f_ms).
// Mirrors atmosphere::multipleScattering (the CPU oracle takes the same quadrature, finer).
#include "common/math.glsl"
#include "atmosphere/model.glsl"
layout(local_size_x = 8, local_size_y = 8) in;
layout(rgba32f, binding = IMAGE_ATMOSPHERE_LUT) uniform writeonly image2D u_lut;
const int kBands = 8, kAzimuths = 8, kSteps = 32;
void main() {
  ivec2 px = ivec2(gl_GlobalInvocationID.xy), size = imageSize(u_lut);
  if (any(greaterThanEqual(px, size))) return;
  vec2 rMu = multiScatteringRMu(px, size);
  float r = rMu.x, muS = rMu.y;
  vec3 x = vec3(0.0, 0.0, r);
  vec3 toSun = vec3(sqrt(max(1.0 - muS * muS, 0.0)), 0.0, muS);
  const float isotropic = 1.0 / (4.0 * kPi);
  const float cellSr = 4.0 * kPi / float(kBands * kAzimuths);
  vec3 second = vec3(0.0), transfer = vec3(0.0);
  for (int i = 0; i < kBands; ++i) {
    float cosT = -1.0 + (float(i) + 0.5) * 2.0 / float(kBands);
    float sinT = sqrt(1.0 - cosT * cosT);
    bool ground = atmosphereRayHitsGround(r, cosT);
    float len = ground ? atmosphereDistanceToGround(r, cosT) : atmosphereDistanceToTop(r, cosT);
    float dt = len / float(kSteps);
    for (int j = 0; j < kAzimuths; ++j) {
      float phi = (float(j) + 0.5) * 2.0 * kPi / float(kAzimuths);
      vec3 w = vec3(sinT * cos(phi), sinT * sin(phi), cosT);
      vec3 throughput = vec3(1.0), lum = vec3(0.0), lf = vec3(0.0);
      for (int k = 0; k < kSteps; ++k) {
        vec3 y = x + (float(k) + 0.5) * dt * w;
        float ry = length(y);
        AtmosphereMedium m = atmosphereMedium(ry - u_bottom_radius_m);
        vec3 sigmaS = m.rayleigh_scattering_per_m + m.mie_scattering_per_m;
        vec3 piece = throughput * atmosphereStepIntegral(m.extinction_per_m, dt);
        lum += piece * sigmaS * sunTransmittance(ry, dot(y, toSun) / ry) * isotropic;
        lf += piece * sigmaS;
        throughput *= exp(-m.extinction_per_m * dt);
      }
      if (ground) {
        vec3 g = x + len * w;
        float cosSun = dot(normalize(g), toSun);
        lum += throughput * sunTransmittance(length(g), cosSun) * max(cosSun, 0.0) * u_ground_albedo / kPi;
      }
      second += lum * isotropic * cellSr;
      transfer += lf * isotropic * cellSr;
    }
  }
  imageStore(u_lut, px, vec4(second / (1.0 - transfer), 1.0));
}
