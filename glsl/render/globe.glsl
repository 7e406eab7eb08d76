// Globe view (Nes 2008 §7.2 future work; the method is described in src/render/raycast/globe.h and
// docs/rendering.md). Eye rays are straight in Earth-centred coordinates (ECEF, metres); every
// sample is carried into the flat world frame where the volumes, occupancy bricks and the deep
// light map live: z = |p| − R, xy through a rotated-lon/lat → world look-up table built with the
// scene's PROJ transform on the CPU. Requires dlm/volume.glsl.
#include "common/math.glsl"
#include "common/imagery.glsl"
layout(binding = UNIT_GLOBE_WORLD_XY) uniform sampler2D u_globe_world_xy;  // RG32F world x, y at texel centres
layout(binding = UNIT_GLOBE_BASEMAP) uniform sampler2D u_globe_basemap;   // equirectangular: RGB linear albedo, A city lights; row 0 = 90°N

// One std140 block, declared in C++ as gl::GlobeBlock (render/gl/uniform_blocks.h): keep the
// members in its order; the GL test UniformBlocksMatchTheLinkedPrograms checks every offset.
layout(std140, binding = UBO_GLOBE) uniform GlobeBlock {
  mat3 u_local_from_ecef;   // rows east, north, up at the footprint centre
  vec3 u_cap_axis;          // unit ECEF of the footprint centre
  float u_cap_min_dot_m;    // (R + z_min)·cos α: every cloud point has p·c at least this
  vec3 u_sphere_c_m2;       // |o|² − r² for r = R (ground), R + z_max (lens top); double on the CPU
  float u_lipschitz_h;      // world-xy metres per ECEF metre, upper bound (globe.h)
  vec3 u_limb_radiance;     // sky colour at the limb (a cosmetic atmosphere, docs/rendering.md)
  float u_earth_radius_m;   // volume::kEarthRadius_m
  vec2 u_ab_min_rad;        // rotated lon/lat box of the table
  vec2 u_ab_max_rad;
  bool u_has_globe_basemap;
  // Terrain on the globe (render/globe_terrain.glsl), read when the eye pass has terrain:
  float u_terrain_cap_min_dot_m;  // (R + min − 1 m)·cos α of the table's cone
  float u_terrain_rate;           // bound of |df/dt| along a ray: 1 + L·L_h + H_max/edge
  float u_terrain_edge_m;         // the table's margin: heights ramp to 0 over it at the table's edge
  vec2 u_terrain_c_m2;            // |o|² − r² for r = R + max, R + min − 1 m; double on the CPU
};

const float kOutsideTable_m = -1.0e30;

// An ECEF direction in the footprint centre's local frame (east, north, up).
vec3 globeLocalDirection(vec3 d) { return u_local_from_ecef * d; }
// e-folding height of the limb glow: a look, not a scattering model (docs/rendering.md).
const float kLimbScaleHeight_m = 30000.0;

// Ray–sphere entry/exit with c = |o|² − r² given (cancellation-free in double on the CPU); the
// larger-magnitude root first, the other as c/q (Numerical Recipes §5.6). (kNoHit_m, −kNoHit_m) =
// missed.
vec2 sphereInterval(vec3 o, vec3 d, float c) {
  float b = dot(o, d);
  float disc = b * b - c;
  if (disc < 0.0) return vec2(kNoHit_m, -kNoHit_m);
  float q = b < 0.0 ? -b + sqrt(disc) : -b - sqrt(disc);
  if (q == 0.0) return vec2(0.0);
  float t0 = q, t1 = c / q;
  return vec2(min(t0, t1), max(t0, t1));
}

// Distance to the ground sphere (kNoHit_m when the ray misses it).
float globeGroundDistance(vec3 o, vec3 d) {
  vec2 g = sphereInterval(o, d, u_sphere_c_m2.x);
  return g.x >= 0.0 ? g.x : kNoHit_m;
}

// The part of the ray inside the lens |p| ≤ R + z_max, p·c ≥ (R + z_min) cos α (globe.h), before
// the ground.
vec2 globeVolumeInterval(vec3 o, vec3 d, float tGround) {
  vec2 outer = sphereInterval(o, d, u_sphere_c_m2.y);
  float lo = max(outer.x, 0.0), hi = min(outer.y, tGround);
  float oc = dot(o, u_cap_axis) - u_cap_min_dot_m, dc = dot(d, u_cap_axis);
  if (dc > 0.0) lo = max(lo, -oc / dc);
  else if (dc < 0.0) hi = min(hi, -oc / dc);
  else if (oc < 0.0) hi = -1.0;
  return vec2(lo, hi);
}

// Latitude-like angles by atan(y, ρ), not asin(y/r): llvmpipe's asin (Mesa 22.3) is off by
// ≈ 1.6·10⁻⁴ rad near 24° — a kilometre on the ground, which put the globe's imagery and table
// 1 km south of where the CPU's exact transform puts them (found by the globe's terrain placement
// test, issue 14: every pixel's decoded latitude 0.0093° low, longitude exact); its atan is exact
// to float rounding.
// The rotated lon/lat (a, b) of the point q given in the footprint centre's local frame (east,
// north, up): a = atan(east, up), b = atan(north, |(east, up)|) (render/raycast/globe.h).
vec2 globeRotatedLonLat(vec3 q) { return vec2(atan(q.x, q.z), atan(q.y, length(q.xz))); }

// World position of an ECEF point; xy = kOutsideTable_m outside the table's box. Bilinear between
// texel centres by hand: fixed-point filter weights (8 bits on many GPUs) would cost ~1/256 texel.
vec3 globeWorldFromEcef(vec3 p) {
  vec3 q = u_local_from_ecef * p;
  float r = length(q);
  vec2 ab = globeRotatedLonLat(q);
  vec2 uv = (ab - u_ab_min_rad) / (u_ab_max_rad - u_ab_min_rad);
  if (any(lessThan(uv, vec2(0.0))) || any(greaterThan(uv, vec2(1.0)))) {
    return vec3(kOutsideTable_m, kOutsideTable_m, r - u_earth_radius_m);
  }
  ivec2 size = textureSize(u_globe_world_xy, 0);
  vec2 t = uv * vec2(size) - 0.5;
  ivec2 i0 = clamp(ivec2(floor(t)), ivec2(0), size - 1);
  ivec2 i1 = min(i0 + 1, size - 1);
  vec2 f = clamp(t - vec2(i0), 0.0, 1.0);
  vec2 a = texelFetch(u_globe_world_xy, i0, 0).rg, b = texelFetch(u_globe_world_xy, ivec2(i1.x, i0.y), 0).rg;
  vec2 c = texelFetch(u_globe_world_xy, ivec2(i0.x, i1.y), 0).rg, d = texelFetch(u_globe_world_xy, i1, 0).rg;
  return vec3(mix(mix(a, b, f.x), mix(c, d, f.x), f.y), r - u_earth_radius_m);
}

// ECEF distance a ray may jump from a sample whose occupancy brick is empty (world point w) and
// stay in empty space, whatever its direction (globe.h): inside the box, to the brick's faces
// (horizontal distance / L_h, vertical distance as is); in the shell of the filter's reach, 0; beyond it, the
// largest per-axis gap to the grown box; outside the table, 0 (step normally).
float globeEmptySkip(vec3 w) {
  if (w.x == kOutsideTable_m) return 0.0;
  vec3 uvw = volumeUvw(w);
  if (insideVolume(uvw)) {
    vec3 brickSize = u_box_size_m / vec3(u_voxels) * float(u_brick_voxels);
    vec3 rel = w - u_box_min_m;
    vec3 brickMin = floor(rel / brickSize) * brickSize;
    vec3 brickMax = min(brickMin + brickSize, u_box_size_m);
    vec3 dist = min(rel - brickMin, brickMax - rel);
    return min(min(dist.x, dist.y) / u_lipschitz_h, dist.z);
  }
  if (insideGrownVolume(uvw)) return 0.0;
  vec3 pad = volumePad_m();
  vec3 gap = max(max(u_box_min_m - pad - w, w - (u_box_min_m + u_box_size_m + pad)), vec3(0.0));
  return max(max(gap.x, gap.y) / u_lipschitz_h, gap.z);
}

// The change of the equirectangular texture coordinates (scene::equirectUv: u = λ/2π + ½,
// v = ½ − φ/π) when the ground point g (ECEF) moves by dP along the sphere (dP·g = 0): with
// ρ² = g_x² + g_y² the squared distance from the polar axis,
//   dλ = (g_x dP_y − g_y dP_x)/ρ²,   dφ = dP_z/ρ        (λ = atan(g_y, g_x), φ = asin(g_z/|g|)).
// ρ is kept from 0 (a pixel on the pole: the widest footprint in u, the clamp below takes it).
vec2 equirectUvDifferential(vec3 g, vec3 dP) {
  float rho2 = max(dot(g.xy, g.xy), 1.0);
  return vec2((g.x * dP.y - g.y * dP.x) / rho2 / (2.0 * kPi), -dP.z * inversesqrt(rho2) / kPi);
}

// Albedo of the ground at the ECEF point g: the whole equirectangular basemap by true lon/lat,
// filtered over the pixel's footprint (issue 14 item 3: mipmaps and anisotropic filtering, as the
// flat view's imagery): dPx, dPy are the ray differentials transferred to the ground (Igehy 1999;
// clouds.comp surfaceDifferential), turned into texture gradients for textureGrad (a compute
// shader has no implicit derivatives; common/imagery.glsl filters). The gradients are analytic, so the u seam at the
// antimeridian (u wraps from 1 to 0) does not widen the footprint.
// A: the night side's city lights on the same grid, filtered alike (0 without; night_lights.glsl).
vec4 globeAlbedo(vec3 g, vec3 dPx, vec3 dPy, vec3 fallback) {
  if (!u_has_globe_basemap) return vec4(fallback, 0.0);
  vec3 n = normalize(g);
  float lon = atan(n.y, n.x), lat = atan(n.z, length(n.xy));  // not asin: see globeRotatedLonLat
  vec2 uv = vec2(lon / (2.0 * kPi) + 0.5, 0.5 - lat / kPi);  // scene::equirectUv
  return textureAnisotropic(u_globe_basemap, uv, footprintClamped(equirectUvDifferential(g, dPx)),
                            footprintClamped(equirectUvDifferential(g, dPy)));
}

// Smooth day/night factor of the sky light at a point whose local vertical has cosine cosSun
// with the sun (civil twilight ends at −6°: sin(−6°) ≈ −0.1).
float globeDaylight(float cosSun) { return smoothstep(-0.1, 0.1, cosSun); }

// What a ray that misses the Earth sees: black space and a glow at the limb, strongest where the
// ray passes closest to the surface on the day side (exp(−h/H) of the closest-approach height).
vec3 globeSpace(vec3 o, vec3 d, vec3 toSun) {
  float tc = max(-dot(o, d), 0.0);
  vec3 pc = o + tc * d;
  float h = max(length(pc) - u_earth_radius_m, 0.0);
  return u_limb_radiance * exp(-h / kLimbScaleHeight_m) * globeDaylight(dot(normalize(pc), toSun));
}
