// The clear atmosphere (issue 14): the model of src/atmosphere/atmosphere.h on the GPU, its
// look-up tables' parametrisations and the segment integral shared by the LUT passes and the
// ray caster. Bruneton 2017 ("Precomputed atmospheric scattering: a new implementation",
// functions.glsl) and Hillaire 2020 ("A Scalable and Production Ready Sky and Atmosphere
// Rendering Technique", EGSR; equation numbers below are his). Per unit solar irradiance
// (issue 12's convention): a radiance here times the sun's irradiance E is the radiance in the
// clouds' units. Positions are planet-centred [m]; a direction's μ is its cosine with the zenith.
// Requires common/math.glsl.

// One std140 block, declared in C++ as gl::AtmosphereBlock (render/gl/uniform_blocks.h): keep the
// members in its order; the GL test UniformBlocksMatchTheLinkedPrograms checks every offset.
layout(std140, binding = UBO_ATMOSPHERE) uniform AtmosphereBlock {
  vec3 u_rayleigh_scattering_per_m;  // β_R at the ground
  float u_bottom_radius_m;           // planet radius
  vec3 u_mie_scattering_per_m;       // β_M^s at the ground
  float u_top_radius_m;              // top of the atmosphere
  vec3 u_mie_extinction_per_m;       // β_M^s + β_M^a
  float u_rayleigh_scale_height_m;
  vec3 u_ozone_absorption_per_m;     // β_O at the tent's peak
  float u_mie_scale_height_m;
  vec3 u_ground_albedo;              // Lambertian ground of Ψ_ms
  float u_mie_g;                     // Cornette–Shanks asymmetry
  vec3 u_sky_view_to_sun;            // sun in the sky-view LUT's frame (z up, azimuth 0 = +x)
  float u_ozone_center_m;
  float u_ozone_half_width_m;
  float u_sun_angular_radius_rad;
  float u_sky_view_radius_m;         // the sky-view LUT's observer: distance to the centre
  bool u_multiple_scattering;        // Ψ_ms on (Hillaire §5.5) or single scattering only
};

layout(binding = UNIT_TRANSMITTANCE_LUT) uniform sampler2D u_transmittance_lut;
layout(binding = UNIT_MULTISCATTERING_LUT) uniform sampler2D u_multiscattering_lut;

struct AtmosphereMedium {
  vec3 rayleigh_scattering_per_m;
  vec3 mie_scattering_per_m;
  vec3 extinction_per_m;
};

// The ozone's absorption at altitude h (the tent of atmosphere.h).
vec3 atmosphereOzone(float h) {
  return max(0.0, 1.0 - abs(h - u_ozone_center_m) / u_ozone_half_width_m) * u_ozone_absorption_per_m;
}

// A plane-parallel ray with zenith cosine μ crosses the ozone layer (2w thick) over 2w/|μ|, without
// bound as μ → 0; a straight ray through the planet's layer crosses at most its chord tangent to
// the layer's bottom, 2·√(2·R·2w) (1237 km). The factor on the ozone's absorption that keeps a
// plane-parallel ray's ozone path within that chord (atmosphere::planeParallelOzoneCap): 1 for
// |μ| ≥ 0.024 (rays steeper than 1.4°), so only the flat view's grazing rays see it, whose
// thousands of kilometres of Chappuis absorption (green) otherwise tint the horizon magenta.
float planeParallelOzoneCap(float mu) {
  float layer_m = 2.0 * u_ozone_half_width_m;
  float chord_m = 2.0 * sqrt(2.0 * u_bottom_radius_m * layer_m);
  return min(1.0, abs(mu) * chord_m / layer_m);
}

// σ_s and σ_t at altitude h (atmosphere.h: exponential Rayleigh and Mie, ozone tent).
AtmosphereMedium atmosphereMedium(float h) {
  float rayleigh = exp(-h / u_rayleigh_scale_height_m);
  float mie = exp(-h / u_mie_scale_height_m);
  AtmosphereMedium m;
  m.rayleigh_scattering_per_m = rayleigh * u_rayleigh_scattering_per_m;
  m.mie_scattering_per_m = mie * u_mie_scattering_per_m;
  m.extinction_per_m = m.rayleigh_scattering_per_m + mie * u_mie_extinction_per_m + atmosphereOzone(h);
  return m;
}

// Rayleigh 3/(16π)(1 + c²) and Cornette–Shanks (Bruneton 2017 MiePhaseFunction); ∫ p dΩ = 1.
float rayleighPhase(float c) { return 3.0 / (16.0 * kPi) * (1.0 + c * c); }
float cornetteShanksPhase(float c, float g) {
  float g2 = g * g;
  return 3.0 / (8.0 * kPi) * (1.0 - g2) * (1.0 + c * c) / ((2.0 + g2) * pow(max(1.0 + g2 - 2.0 * g * c, 1e-6), 1.5));
}

// Bruneton 2017 DistanceToTop/BottomAtmosphereBoundary, RayIntersectsGround: the roots of
// t² + 2rμt + r² − R² = 0 with the discriminant r²(μ² − 1) + R².
float atmosphereDistanceToTop(float r, float mu) {
  float disc = r * r * (mu * mu - 1.0) + u_top_radius_m * u_top_radius_m;
  return max(0.0, -r * mu + sqrt(max(disc, 0.0)));
}
float atmosphereDistanceToGround(float r, float mu) {
  float disc = r * r * (mu * mu - 1.0) + u_bottom_radius_m * u_bottom_radius_m;
  return max(0.0, -r * mu - sqrt(max(disc, 0.0)));
}
bool atmosphereRayHitsGround(float r, float mu) {
  return mu < 0.0 && r * r * (mu * mu - 1.0) + u_bottom_radius_m * u_bottom_radius_m >= 0.0;
}

// Texel-centre mapping of [0, 1] onto a table of n texels (Bruneton 2017 GetTextureCoordFromUnitRange).
float texCoordFromUnit(float x, float n) { return 0.5 / n + x * (1.0 - 1.0 / n); }
float unitFromTexCoord(float u, float n) { return (u - 0.5 / n) / (1.0 - 1.0 / n); }

// Transmittance table (Bruneton 2017 §"Transmittance" GetTransmittanceTextureUvFromRMu): x_r =
// ρ/H with ρ the distance to the horizon and H its value at the top; x_μ the distance to the top
// between its extremes d_min = top − r (zenith) and d_max = ρ + H (horizon).
vec2 transmittanceUv(float r, float mu, vec2 size) {
  float H = sqrt(u_top_radius_m * u_top_radius_m - u_bottom_radius_m * u_bottom_radius_m);
  float rho = sqrt(max(r * r - u_bottom_radius_m * u_bottom_radius_m, 0.0));
  float d = atmosphereDistanceToTop(r, mu);
  float dMin = u_top_radius_m - r, dMax = rho + H;
  float xMu = (d - dMin) / (dMax - dMin);
  return vec2(texCoordFromUnit(clamp(xMu, 0.0, 1.0), size.x), texCoordFromUnit(clamp(rho / H, 0.0, 1.0), size.y));
}
// The inverse (GetRMuFromTransmittanceTextureUv).
vec2 transmittanceRMu(vec2 uv, vec2 size) {
  float xMu = unitFromTexCoord(uv.x, size.x), xR = unitFromTexCoord(uv.y, size.y);
  float H = sqrt(u_top_radius_m * u_top_radius_m - u_bottom_radius_m * u_bottom_radius_m);
  float rho = H * xR;
  float r = sqrt(rho * rho + u_bottom_radius_m * u_bottom_radius_m);
  float dMin = u_top_radius_m - r, dMax = rho + H;
  float d = dMin + xMu * (dMax - dMin);
  float mu = d == 0.0 ? 1.0 : (H * H - rho * rho - d * d) / (2.0 * r * d);
  return vec2(r, clamp(mu, -1.0, 1.0));
}

// T from (r, μ) to the top of the atmosphere (the ground ignored): the table.
vec3 transmittanceToTop(float r, float mu) {
  return texture(u_transmittance_lut, transmittanceUv(r, mu, vec2(textureSize(u_transmittance_lut, 0)))).rgb;
}

// Visible fraction of the sun's disc above the planet's horizon (Bruneton 2017
// GetTransmittanceToSun: a ramp over the disc's angular diameter).
float atmosphereSunVisibility(float r, float muS) {
  float sinH = u_bottom_radius_m / r;
  float cosH = -sqrt(max(1.0 - sinH * sinH, 0.0));
  float a = sinH * u_sun_angular_radius_rad;
  return smoothstep(-a, a, muS - cosH);
}

// The sunlight reaching radius r with the sun at zenith cosine μ_s, per unit solar irradiance.
vec3 sunTransmittance(float r, float muS) { return atmosphereSunVisibility(r, muS) * transmittanceToTop(r, muS); }

// Hillaire's Ψ_ms table (his MultiScatteringLut): u = μ_s·½ + ½; v = √(altitude / thickness)
// instead of his linear v, so that the rows crowd into the lowest kilometres where Rayleigh and Mie
// change fastest (the sky irradiance at 5 km: 13 % → 1 % off the CPU model). Also the sky-irradiance
// table's.
vec2 multiScatteringUv(float r, float muS, vec2 size) {
  float h = clamp((r - u_bottom_radius_m) / (u_top_radius_m - u_bottom_radius_m), 0.0, 1.0);
  return vec2(texCoordFromUnit(clamp(muS * 0.5 + 0.5, 0.0, 1.0), size.x), texCoordFromUnit(sqrt(h), size.y));
}
// The inverse: (r, μ_s) of a texel centre of a table of `size`.
vec2 multiScatteringRMu(ivec2 px, ivec2 size) {
  float muS = unitFromTexCoord((float(px.x) + 0.5) / float(size.x), float(size.x)) * 2.0 - 1.0;
  float v = unitFromTexCoord((float(px.y) + 0.5) / float(size.y), float(size.y));
  return vec2(u_bottom_radius_m + v * v * (u_top_radius_m - u_bottom_radius_m), muS);
}
vec3 multipleScattering(float r, float muS) {
  if (!u_multiple_scattering) return vec3(0.0);
  return texture(u_multiscattering_lut, multiScatteringUv(r, muS, vec2(textureSize(u_multiscattering_lut, 0)))).rgb;
}

// ∫_0^Δ e^{−σt} dt = (1 − e^{−σΔ})/σ per channel (Hillaire 2020 §5.1's analytic step), Δ for σ → 0.
vec3 atmosphereStepIntegral(vec3 sigma, float delta) {
  vec3 x = sigma * delta;
  return mix(delta * (1.0 - 0.5 * x), (1.0 - exp(-x)) / max(sigma, vec3(1e-30)), greaterThan(x, vec3(1e-4)));
}

struct AtmosphereSegment {
  vec3 transmittance;  // T(c, c + ℓ·v)
  vec3 inscattered;    // ∫ T·S dt, per unit solar irradiance (Hillaire eqs. 1, 3, 11)
};

// The segment from `origin` (planet-centred) along unit `dir` for `length_m` with the sun towards
// `toSun`, in `steps` pieces (σ_t and S at each piece's midpoint, integrated analytically);
// `quadratic`: piece boundaries at ℓ·(i/N)², dense near the origin where a sky ray is lowest
// (Hillaire's sky-view march). `planeParallel`: altitude = origin's + t·dir.z and μ_s = toSun.z
// everywhere (the flat view's world), the ozone's path capped (planeParallelOzoneCap). `flatSun`:
// μ_s = toSun.z everywhere on a round ray too (the flat view's sun over a round chord, sky.glsl
// aerialPerspectiveOfFlatPoint). Mirrors atmosphere::integrateSegment.
AtmosphereSegment atmosphereSegment(vec3 origin, vec3 dir, float length_m, vec3 toSun, int steps, bool quadratic,
                                    bool planeParallel, bool flatSun) {
  AtmosphereSegment s;
  s.transmittance = vec3(1.0);
  s.inscattered = vec3(0.0);
  float cosTheta = dot(dir, toSun);
  float phaseR = rayleighPhase(cosTheta), phaseM = cornetteShanksPhase(cosTheta, u_mie_g);
  float r0 = length(origin);
  float ozonePathCap = planeParallel ? planeParallelOzoneCap(dir.z) : 1.0;
  float tPrev = 0.0;
  for (int i = 0; i < steps; ++i) {
    float f = float(i + 1) / float(steps);
    float tNext = length_m * (quadratic ? f * f : f);
    float dt = tNext - tPrev, t = 0.5 * (tPrev + tNext);
    tPrev = tNext;
    float r, muS;
    if (planeParallel) {
      r = r0 + t * dir.z;
      muS = toSun.z;
    } else {
      vec3 x = origin + t * dir;
      r = length(x);
      muS = flatSun ? toSun.z : dot(x, toSun) / r;
      // A chord between two points in the air dips below the ground when they lie beyond each
      // other's horizon (sky.glsl aerialPerspectiveOfFlatPoint): the air there is the ground's.
      r = max(r, u_bottom_radius_m);
    }
    AtmosphereMedium m = atmosphereMedium(r - u_bottom_radius_m);
    if (planeParallel) m.extinction_per_m -= (1.0 - ozonePathCap) * atmosphereOzone(r - u_bottom_radius_m);
    vec3 sun = sunTransmittance(r, muS);
    vec3 ms = multipleScattering(r, muS);
    vec3 source = m.rayleigh_scattering_per_m * (sun * phaseR + ms) + m.mie_scattering_per_m * (sun * phaseM + ms);
    s.inscattered += s.transmittance * source * atmosphereStepIntegral(m.extinction_per_m, dt);
    s.transmittance *= exp(-m.extinction_per_m * dt);
  }
  return s;
}
AtmosphereSegment atmosphereSegment(vec3 origin, vec3 dir, float length_m, vec3 toSun, int steps, bool quadratic,
                                    bool planeParallel) {
  return atmosphereSegment(origin, dir, length_m, toSun, steps, quadratic, planeParallel, planeParallel);
}

// The sky-view table (Hillaire 2020 §5.3, his SkyViewLut): for the observer at u_sky_view_radius_m
// with the sun at azimuth 0, u = √(½ − ½cos φ) over the azimuth φ from the sun (the sky is
// symmetric about the sun's vertical), v the zenith angle, with the horizon at v = ½ and the
// angles squeezed towards it on both sides (v − ½ ∝ ±√(angle from the horizon)).
vec2 skyViewUv(float viewZenithCos, float cosAzimuth, float r, vec2 size) {
  float vHorizon = sqrt(max(r * r - u_bottom_radius_m * u_bottom_radius_m, 0.0));
  float beta = acos(clamp(vHorizon / r, -1.0, 1.0));  // the horizon's depression
  float zenithHorizonAngle = kPi - beta;
  float viewZenithAngle = acos(clamp(viewZenithCos, -1.0, 1.0));
  float v;
  if (viewZenithAngle <= zenithHorizonAngle) {
    float c = 1.0 - sqrt(max(1.0 - viewZenithAngle / zenithHorizonAngle, 0.0));
    v = 0.5 * c;
  } else {
    float c = sqrt(clamp((viewZenithAngle - zenithHorizonAngle) / beta, 0.0, 1.0));
    v = 0.5 + 0.5 * c;
  }
  float u = sqrt(clamp(0.5 - 0.5 * cosAzimuth, 0.0, 1.0));
  return vec2(texCoordFromUnit(u, size.x), texCoordFromUnit(v, size.y));
}
// The inverse: (view zenith cosine, cos φ) of a texel.
vec2 skyViewDirection(vec2 uv, float r, vec2 size) {
  float u = unitFromTexCoord(uv.x, size.x), v = unitFromTexCoord(uv.y, size.y);
  float vHorizon = sqrt(max(r * r - u_bottom_radius_m * u_bottom_radius_m, 0.0));
  float beta = acos(clamp(vHorizon / r, -1.0, 1.0));
  float zenithHorizonAngle = kPi - beta;
  float angle;
  if (v < 0.5) {
    float c = 1.0 - 2.0 * v;
    angle = zenithHorizonAngle * (1.0 - c * c);
  } else {
    float c = 2.0 * v - 1.0;
    angle = zenithHorizonAngle + beta * c * c;
  }
  return vec2(cos(angle), 1.0 - 2.0 * u * u);
}
