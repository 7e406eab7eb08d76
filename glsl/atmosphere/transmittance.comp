#version 450 core
// Transmittance table (Hillaire 2020 §5.1 TransmittanceLut; Bruneton 2017
// ComputeTransmittanceToTopAtmosphereBoundaryTexture): each texel's (r, μ) from
// transmittanceRMu, T = exp(−∫σ_t) to the top of the atmosphere by the midpoint rule (eq. 2).
#include "common/math.glsl"
#include "atmosphere/model.glsl"
layout(local_size_x = 8, local_size_y = 8) in;
layout(rgba32f, binding = IMAGE_ATMOSPHERE_LUT) uniform writeonly image2D u_lut;
const int kSteps = 128;
void main() {
  ivec2 px = ivec2(gl_GlobalInvocationID.xy), size = imageSize(u_lut);
  if (any(greaterThanEqual(px, size))) return;
  vec2 rMu = transmittanceRMu((vec2(px) + 0.5) / vec2(size), vec2(size));
  float r = rMu.x, mu = rMu.y;
  float dt = atmosphereDistanceToTop(r, mu) / float(kSteps);
  vec3 tau = vec3(0.0);
  for (int i = 0; i < kSteps; ++i) {
    float t = (float(i) + 0.5) * dt;
    float ri = sqrt(t * t + 2.0 * r * mu * t + r * r);  // law of cosines
    tau += atmosphereMedium(ri - u_bottom_radius_m).extinction_per_m * dt;
  }
  imageStore(u_lut, px, vec4(exp(-tau), 1.0));
}
