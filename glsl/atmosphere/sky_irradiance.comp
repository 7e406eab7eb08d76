#version 450 core
// Sky irradiance table E_sky(μ_s, h): the irradiance of a level surface from the sky alone,
// ∫_{upper hemisphere} L·cos θ dΩ (Bruneton 2017's indirect irradiance texture, here with
// Hillaire's sky radiance incl. Ψ_ms), per unit solar irradiance. 8 equal-width bands of cos θ
// (∫cos θ d(cos θ) per band) × 8 azimuth cells over [0, π], mirrored; 24-step marches.
// Mirrors atmosphere::skyIrradiance. u, v as the Ψ_ms table (multiScatteringUv).
#include "common/math.glsl"
#include "atmosphere/model.glsl"
layout(local_size_x = 8, local_size_y = 8) in;
layout(rgba32f, binding = IMAGE_ATMOSPHERE_LUT) uniform writeonly image2D u_lut;
const int kBands = 8, kAzimuths = 8, kSteps = 24;
void main() {
  ivec2 px = ivec2(gl_GlobalInvocationID.xy), size = imageSize(u_lut);
  if (any(greaterThanEqual(px, size))) return;
  vec2 rMu = multiScatteringRMu(px, size);
  float r = rMu.x, muS = rMu.y;
  vec3 toSun = vec3(sqrt(max(1.0 - muS * muS, 0.0)), 0.0, muS);
  float dPhi = kPi / float(kAzimuths);
  vec3 e = vec3(0.0);
  for (int i = 0; i < kBands; ++i) {
    float c0 = float(i) / float(kBands), c1 = float(i + 1) / float(kBands);
    float cosT = 0.5 * (c0 + c1), sinT = sqrt(1.0 - cosT * cosT);
    float weight = (c1 * c1 - c0 * c0) * dPhi;  // ½(c1² − c0²)·Δφ, both halves
    float len = atmosphereDistanceToTop(r, cosT);
    for (int j = 0; j < kAzimuths; ++j) {
      float phi = (float(j) + 0.5) * dPhi;
      vec3 w = vec3(sinT * cos(phi), sinT * sin(phi), cosT);
      e += atmosphereSegment(vec3(0.0, 0.0, r), w, len, toSun, kSteps, true, false).inscattered * weight;
    }
  }
  imageStore(u_lut, px, vec4(e, 1.0));
}
