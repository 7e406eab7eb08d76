#version 450 core
// Atmosphere test probe: evaluates one of the functions of glsl/atmosphere/ per query (u_mode):
// 0 sky-view radiance along a.xyz (sun u_sky_view_to_sun); 1 transmittance to the top at
// (r, μ) = a.xy; 2 flat aerial perspective from altitude a.x along b.xyz for a.y metres (sun
// a.zw = (azimuth, elevation) in radians), result rgb = inscattered, and transmittance in the
// second half of the buffer; 3 sky irradiance at altitude a.x, sin(sun elevation) a.y; 4 Ψ_ms
// at (r, μ_s) = a.xy; 5 as 2 for a point in the air, the clouds' aerialPerspectiveOfFlatPoint.
#include "common/math.glsl"
#include "atmosphere/model.glsl"
#include "atmosphere/sky.glsl"
layout(local_size_x = 64) in;
layout(std430, binding = SSBO_TEST_POINTS) readonly buffer Queries { vec4 queries[]; };
layout(std430, binding = SSBO_TEST_RESULTS) writeonly buffer Results { vec4 results[]; };
uniform int u_count;
uniform int u_mode;
void main() {
  int i = int(gl_GlobalInvocationID.x);
  if (i >= u_count) return;
  vec4 a = queries[2 * i], b = queries[2 * i + 1];
  vec3 out0 = vec3(0.0), out1 = vec3(0.0);
  if (u_mode == 0) {
    out0 = skyViewRadiance(a.xyz, u_sky_view_to_sun);
  } else if (u_mode == 1) {
    out0 = transmittanceToTop(a.x, a.y);
  } else if (u_mode == 2) {
    vec3 toSun = vec3(cos(a.w) * cos(a.z), cos(a.w) * sin(a.z), sin(a.w));
    AtmosphereSegment s = aerialPerspectiveFlat(a.x, b.xyz, a.y, toSun);
    out0 = s.inscattered;
    out1 = s.transmittance;
  } else if (u_mode == 5) {
    vec3 toSun = vec3(cos(a.w) * cos(a.z), cos(a.w) * sin(a.z), sin(a.w));
    AtmosphereSegment s = aerialPerspectiveOfFlatPoint(a.x, b.xyz, a.y, toSun);
    out0 = s.inscattered;
    out1 = s.transmittance;
  } else if (u_mode == 3) {
    out0 = skyIrradiance(a.x, a.y);
  } else {
    out0 = multipleScattering(a.x, a.y);
  }
  results[2 * i] = vec4(out0, 0.0);
  results[2 * i + 1] = vec4(out1, 0.0);
}
