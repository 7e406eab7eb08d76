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

// The part [t0, t1] of the segment [0, length_m] of the ray from `origin` (planet-centred) along
// `dir` that lies inside the atmosphere's top sphere, in `steps` pieces; length_m = kNoHit_m for a
// ray into space. Transmittance 1 and nothing in-scattered where the ray misses the shell.
// `flatSun`: the sun's zenith cosine is toSun.z all along (the flat view's sun, model.glsl).
AtmosphereSegment atmosphereSegmentInShell(vec3 origin, vec3 dir, float length_m, vec3 toSun, int steps,
                                           bool flatSun) {
  AtmosphereSegment s;
  s.transmittance = vec3(1.0);
  s.inscattered = vec3(0.0);
  float b = dot(origin, dir);
  float c = dot(origin, origin) - u_top_radius_m * u_top_radius_m;
  float disc = b * b - c;
  if (disc <= 0.0) return s;
  float t0 = max(-b - sqrt(disc), 0.0), t1 = min(-b + sqrt(disc), length_m);
  if (t1 <= t0) return s;
  return atmosphereSegment(origin + t0 * dir, dir, t1 - t0, toSun, steps, false, false, flatSun);
}
AtmosphereSegment atmosphereSegmentInShell(vec3 origin, vec3 dir, float length_m, vec3 toSun, int steps) {
  return atmosphereSegmentInShell(origin, dir, length_m, toSun, steps, false);
}

// The flat view's aerial perspective of a point in the air: a cloud (issue 14, thirteenth
// session). The flat world is a map: the point `length_m` along unit `dir` from an eye h0 up lies
// D = length·|dir_xy| away over the ground, h = h0 + length·dir.z up. Plane-parallel, the air
// between is a straight line through layers that stay level; on the planet the same point (ground
// distance D, altitude h) is seen along the straight chord from the eye, which sags below that line
// by up to D²/(8R) (1.8 km at 300 km: a cloud's haze from 2 km up is that of air 1.8 km lower,
// ×1.25 Rayleigh and ×4.4 Mie density). So the clouds' haze is taken along the round chord
// (Hillaire 2020 eq. 1 along the line of sight's real air); within a few tens of kilometres the two
// agree to O(D²/R). The sun stays the flat view's, μ_s = toSun.z all along: the clouds themselves
// are lit by it (clouds.comp sunAtClouds), and on the planet a 2° sun is 1.6° below the horizon
// 400 km away from it, so the air in front of a sunlit cloud would fall into the planet's shadow
// (a blue rim on every distant cloud base turned dark: seen on `make demo`'s terrain shot). The point is placed on the sphere at angle θ = D/R;
// the chord's vertical part in closed form, (h − h0) − 2(R + h)·sin²(θ/2), as the difference of two
// radii in float would lose it. CPU twin: atmosphere::aerialPerspectiveOfFlatPoint.
AtmosphereSegment aerialPerspectiveOfFlatPoint(float altitude0_m, vec3 dir, float length_m, vec3 toSun) {
  float horizontal = length(dir.xy);
  float theta = length_m * horizontal / u_bottom_radius_m;
  float h = altitude0_m + length_m * dir.z;
  float r = u_bottom_radius_m + h;
  vec2 e = horizontal > 0.0 ? dir.xy / horizontal : vec2(0.0);
  float s = sin(0.5 * theta);
  vec3 chord = vec3(r * sin(theta) * e, (h - altitude0_m) - 2.0 * r * s * s);
  float chordLength = length(chord);
  vec3 eye = vec3(0.0, 0.0, u_bottom_radius_m + altitude0_m);
  if (chordLength <= 0.0) return atmosphereSegmentInShell(eye, dir, 0.0, toSun, kAerialPerspectiveSteps, true);
  return atmosphereSegmentInShell(eye, chord / chordLength, chordLength, toSun, kAerialPerspectiveSteps, true);
}

// The globe (planet-centred rays): the part of the segment [0, length_m] of the ray from `origin`
// along `dir` inside the atmosphere; length_m = kNoHit_m for a ray into space.
AtmosphereSegment aerialPerspectiveGlobe(vec3 origin, vec3 dir, float length_m, vec3 toSun) {
  return atmosphereSegmentInShell(origin, dir, length_m, toSun, 32);
}

// The flat view's horizon (issue 14, twelfth session). The flat ground is a map: it goes on to the
// horizontal, where the curved planet's ground ends at its horizon, √(2Rh) from an eye h up (a
// point h_p up stays in sight √(2R·h_p) further). Up to there the plane-parallel air above is the
// planet's to within D²/(2R) of height; beyond it a plane-parallel ray a fraction of a degree below
// the horizontal stays in the same air for thousands of kilometres (5730 km at −0.3° from 30 km
// up) where a real one leaves the atmosphere past its tangent point. The far ground then showed
// the in-scattering equilibrium of the low air, 5× brighter than the sky the sky-view table shows
// just above the horizon from a high eye (the sky above looked black), through thousands of
// kilometres of the ozone layer's Chappuis absorption (β_O peaks in green): a magenta band.
//
// The fraction of the flat ground kept at horizontal distance D from the eye: 1 up to ¾ of the
// planet's horizon distance, falling smoothly to 0 at it. That is the rule for an eye in the air,
// which sees the sky over the horizon. An eye above the air (a map seen from space, as `make
// demo`'s overview from 700 km) would see the map cut into a disc on black space by it: there the
// map is the picture, and the rule fades out between half the atmosphere's height and its top,
// leaving the plane-parallel haze (its ozone capped, model.glsl atmosphereSegment).
float flatGroundVisibility(float eyeAltitude_m, float pointAltitude_m, float distance_m) {
  // At least 1 m: smoothstep's edges must differ (an eye and a point both at sea level).
  float horizon_m = max(sqrt(2.0 * u_bottom_radius_m * max(eyeAltitude_m, 0.0)) +
                            sqrt(2.0 * u_bottom_radius_m * max(pointAltitude_m, 0.0)),
                        1.0);
  float thickness_m = u_top_radius_m - u_bottom_radius_m;
  float inTheAir = 1.0 - smoothstep(0.5 * thickness_m, thickness_m, eyeAltitude_m);
  return 1.0 - inTheAir * smoothstep(0.75 * horizon_m, horizon_m, distance_m);
}

// Where the flat ground is not kept, the ray sees what the curved planet shows in its direction:
// the atmosphere along the straight ray from the eye (0, 0, R + h) to the planet's ground or out
// into space — the sky-view table's limb for an eye inside the atmosphere (the same march: the
// far ground fades into the sky above the horizon), marched here so that an eye above the top
// of the atmosphere, where the table's observer is held at its top, sees the same.
AtmosphereSegment roundPlanetAlong(float eyeAltitude_m, vec3 dir, vec3 toSun) {
  float r = u_bottom_radius_m + max(eyeAltitude_m, 1.0);
  float mu = dir.z / length(dir);
  float length_m = atmosphereRayHitsGround(r, mu) ? atmosphereDistanceToGround(r, mu) : kNoHit_m;
  return atmosphereSegmentInShell(vec3(0.0, 0.0, r), normalize(dir), length_m, toSun, kAerialPerspectiveSteps);
}

// The flat view's sky above its horizon (issue 14, fourteenth session). For an eye in the air it is
// the sky-view table's. An eye above the air (the table's observer held at its top) saw black
// above the horizontal: a plane-parallel atmosphere has nothing above its top, while the flat
// ground's haze below the horizontal runs through all of it — a hard black strip over a bright
// band. On the planet, the horizon of an eye h up lies the dip δ = acos(R/(R + h)) below the
// horizontal (12.4° from 150 km) and the atmosphere's limb glows just above it, fading into space
// over the few degrees in which the line of sight's tangent height climbs through the air. The
// flat view puts its horizon at the horizontal, so it shows the planet's limb where the planet's
// horizon would be: the direction at elevation α is taken at α − δ on the round planet
// (roundPlanetAlong, the straight ray through the spherical shell), so the limb sits on the flat
// horizon and fades upward into black space. The same fade as flatGroundVisibility's hands over
// between the two: the table up to half the atmosphere's height, the limb above its top.
// CPU check: render.*.RaycastTest.HighEyeSkyAboveTheHorizonIsThePlanetsLimb.
vec3 flatSkyRadiance(float eyeAltitude_m, vec3 dir, vec3 toSun) {
  vec3 table = skyViewRadiance(dir, toSun);
  float thickness_m = u_top_radius_m - u_bottom_radius_m;
  float aboveTheAir = smoothstep(0.5 * thickness_m, thickness_m, eyeAltitude_m);
  if (aboveTheAir <= 0.0) return table;
  float r = u_bottom_radius_m + max(eyeAltitude_m, 1.0);
  float dip = acos(clamp(u_bottom_radius_m / r, -1.0, 1.0));
  vec3 d = normalize(dir);
  float horizontal = length(d.xy);
  vec2 e = horizontal > 1e-6 ? d.xy / horizontal : vec2(1.0, 0.0);
  float elevation = atan(d.z, horizontal) - dip;
  vec3 limbDir = vec3(cos(elevation) * e, sin(elevation));
  return mix(table, roundPlanetAlong(eyeAltitude_m, limbDir, toSun).inscattered, aboveTheAir);
}
