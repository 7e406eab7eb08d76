#version 450 core
// The Monte Carlo radiance volume on the GPU (issue 12, sixteenth session; render/dlm/
// radiance_volume.h; docs/accuracy.md "Sixteenth session"). The CPU candidate of the fifteenth
// session (reference/mc_radiance_volume.h, its twin) ported: what the deep light map lacks (Nes 2008
// §5.2.3: the light scattered out of the forward cone, in every direction, any number of times;
// Muth 2026 §3.4.6 asks for a multiple-scattering term) is simulated instead of modelled.
//
// One invocation per photon. Photon i starts on a face of the field's support box that faces the
// sun, the face chosen with its projected area (u_projected_m2), and flies along −u_to_sun with
// power A_proj/N per unit irradiance (applied by the resolve pass). It is traced through the same
// extinction the eye pass sees — extinctionAt of glsl/dlm/volume.glsl (the packed or the separate
// ice/water textures, the filter, the detail) — by delta tracking (Woodcock et al. 1965; Novák et al.
// 2018, "Monte Carlo methods for volumetric light transport simulation", §4.1) against the
// occupancy bricks' maxima as the piecewise-constant majorant (u_occupancy_per_m: dilated by the
// filter's reach, so they bound β in the brick and in the shell around the box). Height
// exaggeration keeps the data's optical depth: β and the majorant are scaled by f(d) = |(d_x, d_y,
// d_z/e)| along the flight (volume::VolumeFrame::opticalDepthScale), as the path tracer and the eye
// pass do. At a real collision the photon scatters with the ice or the water lobe (chosen with the
// ice weight β_ice/(β_ice + β_water), Nes eq. 5.12), Henyey–Greenstein sampled exactly, albedo 1;
// past u_roulette_after collisions it survives with q = 1 − 1/u_roulette_after and its weight is
// divided by q (unbiased Russian roulette, as the path tracer).
//
// Tally: the track-length estimator (Spanier & Gelbard 1969 §3; PBRT 4th ed. §14.3): a flight of a
// photon that has scattered at least u_min_order times adds w·ℓ·Y_lm(d) to every coarse cell it
// crosses over ℓ (Amanatides & Woo 1987), l ≤ 4 (glsl/common/spherical_harmonics.glsl); the resolve
// pass multiplies by P/V. GL 4.5 has no float atomics, so the sums are fixed point: each moment is a
// 64-bit two's-complement integer held as two 32-bit words (low, high) in the SSBO, one addition
// per crossing of x = round(w·ℓ·Y_lm / q) with q = u_quantum_m. The bound that fixes q
// (render/dlm/radiance_volume.cpp): ℓ ≤ the cell's diagonal D, |Y_lm| ≤ √((2l + 1)/(4π)) ≤ 0.846
// (Σ_m Y_lm² = (2l + 1)/(4π), the addition theorem) and w ≤ 16 (roulette's growth: 0.999^−2770), so
// x fits in an int32 with q = 16·0.846·D / 2³¹ — one quantum is ≈ 10⁻⁸ of a typical crossing,
// and the 64-bit sums cannot overflow (2³¹ crossings of the bound would be needed per 2⁻³² of the
// range). A crossing beyond the bound is clamped and counted (stats[4]), never silent. The low
// word's atomicAdd returns the old value; its unsigned wrap is the carry into the high word. The
// number of wraps of a sum of non-negative words does not depend on the order of the additions,
// so the 64-bit total is associative: the same photons give the same volume bit for bit, however
// the invocations are scheduled.
#include "dlm/volume.glsl"
#include "common/spherical_harmonics.glsl"

layout(local_size_x = 64) in;

layout(std430, binding = SSBO_MC_TALLY) buffer McTally {
  uint words[];  // per cell, per moment k (< 25): (low, high) at 2·(cell·25 + k)
};
layout(std430, binding = SSBO_MC_STATS) buffer McStats {
  uint stats[];  // photons collided, collisions, rouletted, truncated, clamped crossings
};

uniform int u_photons;          // N
uniform int u_seed;             // photon i draws from the stream (u_seed, i)
uniform vec3 u_to_sun;          // unit, world
uniform vec3 u_projected_m2;    // the support box's faces' areas projected along the sun, per axis
uniform int u_min_order;        // tally flights after at least this many scatterings
uniform ivec3 u_cells;          // the coarse grid, origin the volume box's min corner
uniform vec3 u_cell_m;          // its cell size [world m]
uniform float u_quantum_m;      // q: the fixed-point unit of w·ℓ·Y [m]
uniform float u_g_ice;          // Henyey–Greenstein asymmetry of each phase
uniform float u_g_water;
uniform float u_height_exaggeration;
uniform int u_roulette_after;   // collisions before Russian roulette (0: never)
uniform int u_max_events;       // a photon is cut (and counted) after this many collisions

// PCG32 (O'Neill 2014), one stream per photon seeded by a hash of (seed, index) (Jarzynski & Olano
// 2020, "Hash functions for GPU rendering": pcg as a hash).
uint pcgHash(uint v) {
  uint state = v * 747796405u + 2891336453u;
  uint word = ((state >> ((state >> 28u) + 4u)) ^ state) * 277803737u;
  return (word >> 22u) ^ word;
}
uint g_rng = 0u;
float uniform01() {  // [0, 1) with 24 bits
  g_rng = g_rng * 747796405u + 2891336453u;
  uint word = ((g_rng >> ((g_rng >> 28u) + 4u)) ^ g_rng) * 277803737u;
  word = (word >> 22u) ^ word;
  return float(word >> 8u) * (1.0 / 16777216.0);
}

// Henyey–Greenstein's cosine by inversion (Henyey & Greenstein 1941; PBRT 4th ed. §11.3.1).
float sampleHgCos(float g, float xi) {
  if (abs(g) < 1e-3) return 1.0 - 2.0 * xi;
  float s = (1.0 - g * g) / (1.0 - g + 2.0 * g * xi);
  return clamp((1.0 + g * g - s * s) / (2.0 * g), -1.0, 1.0);
}

// d turned by the polar cosine μ and azimuth φ (Duff et al. 2017's branchless basis; the CPU's
// reference::aroundAxis).
vec3 aroundAxis(vec3 axis, float mu, float phi) {
  float s = axis.z >= 0.0 ? 1.0 : -1.0;
  float a = -1.0 / (s + axis.z);
  float b = axis.x * axis.y * a;
  vec3 t = vec3(1.0 + s * axis.x * axis.x * a, s * b, -s * axis.x);
  vec3 bt = vec3(b, s + axis.y * axis.y * a, -axis.y);
  float st = sqrt(max(0.0, 1.0 - mu * mu));
  return normalize(st * cos(phi) * t + st * sin(phi) * bt + mu * axis);
}

// The support box: the volume box grown by the filter's support (reach − ½ voxel; β is 0 beyond).
vec3 supportPad_m() { return (u_reach_voxels - 0.5) * u_box_size_m / vec3(u_voxels); }

// Entry and exit of o + t·d in the support box (t ≥ 0); exit ≤ entry when missed.
vec2 supportInterval(vec3 o, vec3 d) {
  vec3 pad = supportPad_m();
  vec3 inv = 1.0 / safeDirection(d);
  vec2 t = slabInterval((u_box_min_m - pad - o) * inv, (u_box_min_m + u_box_size_m + pad - o) * inv);
  return vec2(max(t.x, 0.0), t.y);
}

// The occupancy brick around p (the edge bricks extended over the shell outside the box, whose β
// their dilated maxima bound: glsl/dlm/volume.glsl brickMaxAt) — its maximum β and the distance
// along d to its exit. p is nudged along d so a point on a face belongs to the brick ahead.
vec2 brickMajorant(vec3 p, vec3 d) {
  vec3 voxel = u_box_size_m / vec3(u_voxels);
  vec3 brickSize = voxel * float(u_brick_voxels);
  ivec3 bricks = (u_voxels + u_brick_voxels - 1) / u_brick_voxels;
  vec3 rel = p - u_box_min_m;
  ivec3 b = clamp(ivec3(floor((rel + 1e-4 * brickSize * sign(d)) / brickSize)), ivec3(0), bricks - 1);
  vec3 pad = u_reach_voxels * voxel;
  vec3 lo = vec3(b) * brickSize, hi = min(lo + brickSize, u_box_size_m);
  lo = mix(lo, -pad, equal(b, ivec3(0)));
  hi = mix(hi, u_box_size_m + pad, equal(b, bricks - 1));
  vec3 safeDir = safeDirection(d);
  vec3 t = mix((lo - rel) / safeDir, (hi - rel) / safeDir, greaterThan(d, vec3(0.0)));
  t = mix(t, vec3(kNeverExit_m), equal(d, vec3(0.0)));
  float exit_m = max(min(t.x, min(t.y, t.z)), 1e-4 * min(brickSize.x, min(brickSize.y, brickSize.z)));
  return vec2(texelFetch(u_occupancy_per_m, b, 0).r, exit_m);
}

// Delta tracking from o along d up to tMax: true at a real collision (distance tHit, (β_ice,
// β_water) there), false when the flight leaves. f: the optical-depth scale along d.
bool deltaTrack(vec3 o, vec3 d, float tMax, float f, out float tHit, out vec2 beta) {
  tHit = tMax;
  beta = vec2(0.0);
  float t = 0.0;
  while (t < tMax) {
    vec2 brick = brickMajorant(o + t * d, d);
    float tb = min(t + brick.y, tMax);
    float mu = brick.x * f;
    if (mu > 0.0) {
      for (;;) {
        t -= log(1.0 - uniform01()) / mu;
        if (t >= tb) break;
        vec2 b = extinctionAt(o + t * d);
        // β ≤ the brick's maximum up to the half-float rounding of the packed texture
        if (uniform01() * brick.x < b.x + b.y) {
          tHit = t;
          beta = b;
          return true;
        }
      }
    }
    t = tb;  // memoryless: the next brick's majorant takes over at its face
  }
  return false;
}

// Adds x to the 64-bit moment `m` (a word pair): the low word's wrap carries into the high word.
void tallyAdd(uint m, int x) {
  if (x == 0) return;
  uint old = atomicAdd(words[2u * m], uint(x));
  uint high = (old + uint(x) < old ? 1u : 0u) + (x < 0 ? 0xffffffffu : 0u);
  if (high != 0u) atomicAdd(words[2u * m + 1u], high);
}

// The track-length tally of the flight o + t·d, t ∈ [0, len], weight w, harmonics y (Amanatides &
// Woo 1987 over the coarse grid; the CPU's tallySegment).
void tallySegment(vec3 o, vec3 d, float len, float w, float y[25]) {
  vec3 lo = u_box_min_m, hi = u_box_min_m + vec3(u_cells) * u_cell_m;
  float t0 = 0.0, t1 = len;
  for (int a = 0; a < 3; ++a) {
    if (d[a] == 0.0) {
      if (o[a] < lo[a] || o[a] >= hi[a]) return;
      continue;
    }
    float ta = (lo[a] - o[a]) / d[a], tb = (hi[a] - o[a]) / d[a];
    t0 = max(t0, min(ta, tb));
    t1 = min(t1, max(ta, tb));
  }
  if (!(t1 > t0)) return;
  vec3 mid = (o + 0.5 * (t0 + t1) * d - lo) / u_cell_m;
  vec3 start = (o + t0 * d - lo) / u_cell_m;
  ivec3 idx, stp;
  vec3 tNext, tDelta;
  for (int a = 0; a < 3; ++a) {
    float s = d[a] == 0.0 ? mid[a] : start[a] + (d[a] > 0.0 ? 1e-5 : -1e-5);
    idx[a] = clamp(int(floor(s)), 0, u_cells[a] - 1);
    if (d[a] > 0.0) {
      stp[a] = 1;
      tNext[a] = t0 + ((float(idx[a]) + 1.0) - start[a]) * u_cell_m[a] / d[a];
      tDelta[a] = u_cell_m[a] / d[a];
    } else if (d[a] < 0.0) {
      stp[a] = -1;
      tNext[a] = t0 + (float(idx[a]) - start[a]) * u_cell_m[a] / d[a];
      tDelta[a] = -u_cell_m[a] / d[a];
    } else {
      stp[a] = 0;
      tNext[a] = kNeverExit_m;
      tDelta[a] = kNeverExit_m;
    }
  }
  float scale = w / u_quantum_m;
  float t = t0;
  for (int guard = 0; guard < 4 * (u_cells.x + u_cells.y + u_cells.z) + 8; ++guard) {
    int axis = tNext.x <= tNext.y ? (tNext.x <= tNext.z ? 0 : 2) : (tNext.y <= tNext.z ? 1 : 2);
    float tExit = min(tNext[axis], t1);
    if (tExit > t) {
      uint cell = uint((idx.z * u_cells.y + idx.y) * u_cells.x + idx.x);
      float q = scale * (tExit - t);
      for (int k = 0; k < kShCount; ++k) {
        float x = round(q * y[k]);
        if (abs(x) > 2147483520.0) {  // past the bound (float's largest below 2³¹): clamped, counted
          atomicAdd(stats[4], 1u);
          x = clamp(x, -2147483520.0, 2147483520.0);
        }
        tallyAdd(cell * uint(kShCount) + uint(k), int(x));
      }
      t = tExit;
    }
    if (tExit >= t1) return;
    idx[axis] += stp[axis];
    if (idx[axis] < 0 || idx[axis] >= u_cells[axis]) return;
    tNext[axis] += tDelta[axis];
  }
}

void main() {
  uint i = gl_GlobalInvocationID.x;
  if (i >= uint(u_photons)) return;
  g_rng = pcgHash(i ^ pcgHash(uint(u_seed)));
  // The entry point on a face facing the sun, chosen by projected area.
  vec3 pad = supportPad_m();
  vec3 lo = u_box_min_m - pad, hi = u_box_min_m + u_box_size_m + pad;
  float u = uniform01() * (u_projected_m2.x + u_projected_m2.y + u_projected_m2.z);
  int axis = u < u_projected_m2.x ? 0 : (u < u_projected_m2.x + u_projected_m2.y ? 1 : 2);
  vec3 o = lo + vec3(uniform01(), uniform01(), uniform01()) * (hi - lo);
  o[axis] = u_to_sun[axis] > 0.0 ? hi[axis] : lo[axis];
  vec3 d = -u_to_sun;
  float weight = 1.0;
  int order = 0;
  bool collided = false;
  for (;;) {
    vec2 span = supportInterval(o, d);
    float tOut = span.y > span.x ? span.y : 0.0;  // o is inside (or on) the box
    float f = length(vec3(d.xy, d.z / u_height_exaggeration));
    float tHit;
    vec2 beta;
    bool hit = deltaTrack(o, d, tOut, f, tHit, beta);
    if (order >= u_min_order) {
      float y[25];
      shBasis4(d, y);
      tallySegment(o, d, hit ? tHit : tOut, weight, y);
    }
    if (!hit) break;
    collided = true;
    ++order;
    if (order >= u_max_events) {
      atomicAdd(stats[3], 1u);
      break;
    }
    if (u_roulette_after > 0 && order >= u_roulette_after) {
      float q = 1.0 - 1.0 / float(u_roulette_after);
      if (uniform01() >= q) {
        atomicAdd(stats[2], 1u);
        break;
      }
      weight /= q;
    }
    bool ice = uniform01() * (beta.x + beta.y) < beta.x;
    float mu = sampleHgCos(ice ? u_g_ice : u_g_water, uniform01());
    o += tHit * d;
    d = aroundAxis(d, mu, 2.0 * kPi * uniform01());
  }
  if (collided) {
    atomicAdd(stats[0], 1u);
    atomicAdd(stats[1], uint(order));
  }
}
