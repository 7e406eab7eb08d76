// What the ray caster asks of the atmosphere (issue 14): sky radiance from the sky-view table,
// the sunlight at an altitude, the sky's irradiance of a level surface, and aerial perspective
// by direct march of a segment (Hillaire 2020 §5.4 allows either this or his froxel volume; the
// march costs a few dozen steps per ground pixel and no per-frame volume). Per unit solar
// irradiance: multiply by E (u_sun_radiance) for the clouds' units (issue 12).
// Requires common/math.glsl and atmosphere/model.glsl.
layout(binding = UNIT_SKY_VIEW_LUT) uniform sampler2D u_sky_view_lut;
layout(binding = UNIT_SKY_IRRADIANCE_LUT) uniform sampler2D u_sky_irradiance_lut;

// Sky radiance seen from the sky-view table's observer along `dir` (z up; the table holds the sun
// at azimuth 0 in its frame, so only the azimuth difference φ to `toSun` matters).
vec3 skyViewRadiance(vec3 dir, vec3 toSun) {
  vec2 dh = dir.xy, sh = toSun.xy;
  float dl = length(dh), sl = length(sh);
  float cosPhi = dl > 1e-6 && sl > 1e-6 ? dot(dh, sh) / (dl * sl) : 1.0;
  vec2 size = vec2(textureSize(u_sky_view_lut, 0));
  return texture(u_sky_view_lut, skyViewUv(dir.z / length(dir), cosPhi, u_sky_view_radius_m, size)).rgb;
}

// The sunlight (per unit solar irradiance at the top) reaching altitude h with the sun at
// elevation asin(sinSunElevation): the transmittance to the top and the planet's shadow.
vec3 sunlightAt(float altitude_m, float sinSunElevation) {
  return sunTransmittance(u_bottom_radius_m + max(altitude_m, 0.0), sinSunElevation);
}

// Irradiance of a level surface at altitude h from the sky alone (the direct sun left out), the
// sun at elevation asin(sinSunElevation); per unit solar irradiance. The clouds' sky-light term.
vec3 skyIrradiance(float altitude_m, float sinSunElevation) {
  vec2 size = vec2(textureSize(u_sky_irradiance_lut, 0));
  return texture(u_sky_irradiance_lut, multiScatteringUv(u_bottom_radius_m + max(altitude_m, 0.0), sinSunElevation, size)).rgb;
}

// Steps of a ground pixel's aerial perspective: in-scattering changes slowly along a segment
// (σ_t and S are integrated analytically within each piece).
const int kAerialPerspectiveSteps = 24;

// Aerial perspective in the flat view: the straight segment from altitude h0 along `dir` for
// `length_m`, plane-parallel (the flat world: altitude h0 + t·dir.z, the sun's zenith cosine
// toSun.z everywhere). What lies behind is seen as L0·transmittance + inscattered.
AtmosphereSegment aerialPerspectiveFlat(float altitude0_m, vec3 dir, float length_m, vec3 toSun) {
  return atmosphereSegment(vec3(0.0, 0.0, u_bottom_radius_m + altitude0_m), dir, length_m, toSun,
                           kAerialPerspectiveSteps, false, true);
}

// The globe (planet-centred rays): the part of the segment [0, length_m] of the ray from `origin`
// along `dir` inside the atmosphere; length_m = kNoHit_m for a ray into space.
AtmosphereSegment aerialPerspectiveGlobe(vec3 origin, vec3 dir, float length_m, vec3 toSun) {
  AtmosphereSegment s;
  s.transmittance = vec3(1.0);
  s.inscattered = vec3(0.0);
  float b = dot(origin, dir);
  float c = dot(origin, origin) - u_top_radius_m * u_top_radius_m;
  float disc = b * b - c;
  if (disc <= 0.0) return s;
  float t0 = max(-b - sqrt(disc), 0.0), t1 = min(-b + sqrt(disc), length_m);
  if (t1 <= t0) return s;
  return atmosphereSegment(origin + t0 * dir, dir, t1 - t0, toSun, 32, false, false);
}
