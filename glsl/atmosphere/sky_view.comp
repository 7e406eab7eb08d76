#version 450 core
// Sky-view table (Hillaire 2020 §5.3 SkyViewLut): the sky radiance seen by the observer at
// u_sky_view_radius_m (rebuilt when the observer's altitude or the sun moves) in every direction,
// parametrised by skyViewUv; each texel marches its ray to the ground or the top (eqs. 1, 3, 11,
// quadratic spacing). Per unit solar irradiance [1/sr].
#include "common/math.glsl"
#include "atmosphere/model.glsl"
layout(local_size_x = 8, local_size_y = 8) in;
layout(rgba32f, binding = IMAGE_ATMOSPHERE_LUT) uniform writeonly image2D u_lut;
const int kSteps = 40;
void main() {
  ivec2 px = ivec2(gl_GlobalInvocationID.xy), size = imageSize(u_lut);
  if (any(greaterThanEqual(px, size))) return;
  float r = u_sky_view_radius_m;
  vec2 zenithAzimuth = skyViewDirection((vec2(px) + 0.5) / vec2(size), r, vec2(size));
  float mu = zenithAzimuth.x, cosPhi = zenithAzimuth.y;
  float sinT = sqrt(max(1.0 - mu * mu, 0.0));
  vec3 dir = vec3(sinT * cosPhi, sinT * sqrt(max(1.0 - cosPhi * cosPhi, 0.0)), mu);
  float len = atmosphereRayHitsGround(r, mu) ? atmosphereDistanceToGround(r, mu) : atmosphereDistanceToTop(r, mu);
  AtmosphereSegment s = atmosphereSegment(vec3(0.0, 0.0, r), dir, len, u_sky_view_to_sun, kSteps, true, false);
  imageStore(u_lut, px, vec4(s.inscattered, 1.0));
}
