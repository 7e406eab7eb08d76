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
// from its D-th collision on (D = u_roulette_after) the n-th survives with q_n = n/(n + 1) and its
// weight is divided by q_n — (n + 1)/D after n collisions (unbiased Russian roulette with a weight
// linear in the path's length, as the path tracer: reference/path_tracer.h).
//
// Tally: the track-length estimator (Spanier & Gelbard 1969 §3; PBRT 4th ed. §14.3): a flight of a
// photon that has scattered at least u_min_order times adds w·ℓ·Y_lm(d) to every coarse cell it
// crosses over ℓ (Amanatides & Woo 1987), l ≤ 4 (glsl/common/spherical_harmonics.glsl); the resolve
// pass multiplies by P/V. GL 4.5 has no float atomics, so the sums are fixed point: each moment is a
// 64-bit two's-complement integer held as two 32-bit words (low, high) in the SSBO, one addition
// per crossing of x = round(w·ℓ·Y_lm / q) with q = u_quantum_m. The bound that fixes q
// (render/dlm/radiance_volume.cpp): ℓ ≤ the cell's diagonal D, |Y_lm| ≤ √((2l + 1)/(4π)) ≤ 0.846
// (Σ_m Y_lm² = (2l + 1)/(4π), the addition theorem) and w ≤ 16 (roulette: (n + 1)/D ≤ 16 up to n = 16 D), so
// x fits in an int32 with q = 16·0.846·D / 2³¹ — one quantum is ≈ 10⁻⁸ of a typical crossing,
// and the 64-bit sums cannot overflow (2³¹ crossings of the bound would be needed per 2⁻³² of the
// range). A crossing beyond the bound is clamped and counted (stats[4]), never silent. The low
// word's atomicAdd returns the old value; its unsigned wrap is the carry into the high word. The
// number of wraps of a sum of non-negative words does not depend on the order of the additions,
// so the 64-bit total is associative: the same photons give the same volume bit for bit, however
// the invocations are scheduled.
//
// llvmpipe's loop limiter (seventeenth session; docs/accuracy.md "Seventeenth session"). Mesa's
// llvmpipe ends every loop of a shader once a counter shared by all its loops reaches
// LP_MAX_TGSI_LOOP_ITERATIONS = 65 535 back-edges (gallivm/lp_bld_limits.h; lp_exec_endloop), and
// the counter belongs to a SIMD group of 8 or 16 invocations. A photon in a thick deck makes
// thousands of null collisions, brick steps and cell crossings: past the limit its loops fell
// through silently and it left the volume without its remaining collisions — the sixteenth
// session's 87.1 collisions per photon on the hurricane against the CPU twin's 97.6 (and far fewer
// with larger occupancy bricks, whose majorants need more null collisions). So the photons are
// resumable: a dispatch gives each photon at most u_step_budget steps (counted with weights that
// bound the back-edges they cost, below), then the photon pauses and its state (position,
// direction, weight, order, random state) waits in the McPhotons buffer for the next dispatch;
// the host dispatches until none is left (render/dlm/radiance_volume.cpp). Delta tracking is
// memoryless, so a flight paused at a null collision resumes there as a new flight from that point
// (Novák et al. 2018 §4.1): the same estimator. Where a pause falls depends only on the photon's
// own steps, so the volume stays bit-identical for the same photons. A loop that still ends
// without its exit condition (the limiter) is counted (stats[6]), never silent.
//
// Cost: the crossings' integers are summed in registers, as 64-bit pairs (uaddCarry), for as long
// as the photon's flights stay in one coarse cell — in a thick deck tens of flights, a cell being
// many mean free paths wide — and added to the SSBO once when it moves to another cell (or pauses):
// integer addition is associative, so the totals are those of one atomic per crossing, which the
// sixteenth session did (25–50 atomics per crossed cell, executed lane by lane on llvmpipe;
// TALLY_EVERY_CROSSING restores that for the benchmark, tests/bench/dlm_benchmark.cpp).
#include "dlm/volume.glsl"
#include "common/spherical_harmonics.glsl"

layout(local_size_x = 64) in;

layout(std430, binding = SSBO_MC_TALLY) buffer McTally {
  uint words[];  // per cell, per moment k (< 25): (low, high) at 2·(cell·25 + k)
};
layout(std430, binding = SSBO_MC_STATS) buffer McStats {
  uint stats[];  // collided, collisions, rouletted, truncated, clamped crossings, paused, cut short
};
// A photon between dispatches: (position, weight), (direction, −), (random state, order, alive, −).
struct McPhoton {
  vec4 position_weight;
  vec4 direction;
  uvec4 state;
};
layout(std430, binding = SSBO_MC_PHOTONS) buffer McPhotons {
  McPhoton photons[];
};

uniform int u_photons;          // N
uniform bool u_start;           // the first dispatch: photons start from the sun
uniform int u_step_budget;      // weighted steps per photon and dispatch (see the header)
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

// The steps this invocation took in this dispatch, weighted by the back-edges they may cost:
// a brick or a null collision 1, a flight (its harmonics' loops) kFlightSteps, a cell crossing (its
// moment loop and a run's flush) kCrossingSteps.
int g_steps = 0;
const int kFlightSteps = 24;
const int kCrossingSteps = 52;
const int kLeft = 0, kHit = 1, kPaused = 2;

// Delta tracking from o along d up to tMax: kHit at a real collision (distance tHit, (β_ice,
// β_water) there), kLeft when the flight leaves, kPaused when the step budget is spent (at tHit, a
// null collision or a brick face: the flight resumes there). f: the optical-depth scale along d.
int deltaTrack(vec3 o, vec3 d, float tMax, float f, out float tHit, out vec2 beta) {
  tHit = tMax;
  beta = vec2(0.0);
  float t = 0.0;
  while (t < tMax) {
    vec2 brick = brickMajorant(o + t * d, d);
    float tb = min(t + brick.y, tMax);
    float mu = brick.x * f;
    if (mu > 0.0) {
      for (;;) {
        if (++g_steps > u_step_budget) {
          tHit = t;
          return kPaused;
        }
        t -= log(1.0 - uniform01()) / mu;
        if (t >= tb) break;
        vec2 b = extinctionAt(o + t * d);
        // β ≤ the brick's maximum up to the half-float rounding of the packed texture
        if (uniform01() * brick.x < b.x + b.y) {
          tHit = t;
          beta = b;
          return kHit;
        }
      }
    }
    t = tb;  // memoryless: the next brick's majorant takes over at its face
    if (++g_steps > u_step_budget && t < tMax) {
      tHit = t;
      return kPaused;
    }
  }
  if (!(t >= tMax)) atomicAdd(stats[6], 1u);  // the loop ended without its condition: llvmpipe's limiter
  return kLeft;
}

// The invocation's tally run (see the header): the cell it belongs to (−1: none) and the 64-bit
// two's-complement sums of its crossings' integers, per moment, as (low, high) word pairs.
int g_runCell = -1;
// Zeroed in main(): a global without an initializer is undefined in GLSL. llvmpipe happens to zero
// it; NVIDIA's 580 driver does not, and the first run of every photon added garbage to the moments
// (|GPU − CPU| 2–5·10⁷ on the H200, twenty-second session; docs/benchmarks.md "On an NVIDIA GPU").
uint g_runLow[25], g_runHigh[25];

// Adds the run to the SSBO's 64-bit moments of its cell and empties it: the low word's atomicAdd
// returns the old value, whose unsigned wrap is the carry into the high word.
void flushRun() {
  if (g_runCell < 0) return;
  for (int k = 0; k < kShCount; ++k) {
    uint low = g_runLow[k], high = g_runHigh[k];
    if (low == 0u && high == 0u) continue;
    uint m = uint(g_runCell) * uint(kShCount) + uint(k);
    uint old = atomicAdd(words[2u * m], low);
    high += old + low < old ? 1u : 0u;
    if (high != 0u) atomicAdd(words[2u * m + 1u], high);
    g_runLow[k] = 0u;
    g_runHigh[k] = 0u;
  }
  g_runCell = -1;
}

// Starts a run in `cell` (the previous one flushed) unless it is the current one.
void runEnter(int cell) {
  if (cell == g_runCell) return;
  flushRun();
  g_runCell = cell;
}

// Adds x (sign-extended to 64 bits) to moment k of the run.
void runAdd(int k, int x) {
  uint carry;
  g_runLow[k] = uaddCarry(g_runLow[k], uint(x), carry);
  g_runHigh[k] += carry + (x < 0 ? 0xffffffffu : 0u);
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
      g_steps += kCrossingSteps;
      runEnter((idx.z * u_cells.y + idx.y) * u_cells.x + idx.x);
      float q = scale * (tExit - t);
      for (int k = 0; k < kShCount; ++k) {
        float x = round(q * y[k]);
        if (abs(x) > 2147483520.0) {  // past the bound (float's largest below 2³¹): clamped, counted
          atomicAdd(stats[4], 1u);
          x = clamp(x, -2147483520.0, 2147483520.0);
        }
        runAdd(k, int(x));
      }
#ifdef TALLY_EVERY_CROSSING
      flushRun();  // the sixteenth session's cost: every crossing's moments to the SSBO at once (benchmark)
#endif
      t = tExit;
    }
    if (tExit >= t1) return;
    idx[axis] += stp[axis];
    if (idx[axis] < 0 || idx[axis] >= u_cells[axis]) return;
    tNext[axis] += tDelta[axis];
  }
}

// Photon i's stream and its entry point on a face facing the sun, chosen by projected area.
vec3 photonEntry(uint i) {
  g_rng = pcgHash(i ^ pcgHash(uint(u_seed)));
  vec3 pad = supportPad_m();
  vec3 lo = u_box_min_m - pad, hi = u_box_min_m + u_box_size_m + pad;
  float u = uniform01() * (u_projected_m2.x + u_projected_m2.y + u_projected_m2.z);
  int axis = u < u_projected_m2.x ? 0 : (u < u_projected_m2.x + u_projected_m2.y ? 1 : 2);
  vec3 o = lo + vec3(uniform01(), uniform01(), uniform01()) * (hi - lo);
  o[axis] = u_to_sun[axis] > 0.0 ? hi[axis] : lo[axis];
  return o;
}

void main() {
  uint i = gl_GlobalInvocationID.x;
  if (i >= uint(u_photons)) return;
  for (int k = 0; k < kShCount; ++k) {
    g_runLow[k] = 0u;
    g_runHigh[k] = 0u;
  }
  vec3 o, d;
  float weight;
  int order;
  if (u_start) {
    o = photonEntry(i);
    d = -u_to_sun;
    weight = 1.0;
    order = 0;
  } else {
    McPhoton p = photons[i];
    if (p.state.z == 0u) return;  // ended in an earlier dispatch
    o = p.position_weight.xyz;
    weight = p.position_weight.w;
    d = p.direction.xyz;
    g_rng = p.state.x;
    order = int(p.state.y);
  }
  bool alive = true, paused = false;
  while (alive && !paused) {
    vec2 span = supportInterval(o, d);
    float tOut = span.y > span.x ? span.y : 0.0;  // o is inside (or on) the box
    float f = length(vec3(d.xy, d.z / u_height_exaggeration));
    float tHit;
    vec2 beta;
    g_steps += kFlightSteps;
    int flight = deltaTrack(o, d, tOut, f, tHit, beta);
    if (order >= u_min_order) {
      float y[25];
      shBasis4(d, y);
      tallySegment(o, d, flight == kLeft ? tOut : tHit, weight, y);
    }
    if (flight == kPaused) {
      o += tHit * d;  // a null collision or a brick face: the flight goes on from there
      paused = true;
      break;
    }
    if (flight == kLeft) {
      alive = false;
      break;
    }
    ++order;
    if (order >= u_max_events) {
      atomicAdd(stats[3], 1u);
      alive = false;
      break;
    }
    if (u_roulette_after > 0 && order >= u_roulette_after) {
      float q = float(order) / float(order + 1);
      if (uniform01() >= q) {
        atomicAdd(stats[2], 1u);
        alive = false;
        break;
      }
      weight /= q;
    }
    bool ice = uniform01() * (beta.x + beta.y) < beta.x;
    float mu = sampleHgCos(ice ? u_g_ice : u_g_water, uniform01());
    o += tHit * d;
    d = aroundAxis(d, mu, 2.0 * kPi * uniform01());
    if (g_steps > u_step_budget) {  // the budget is spent: pause at the collision, d drawn
      paused = true;
      break;
    }
  }
  if (alive && !paused) atomicAdd(stats[6], 1u);  // the loop ended without its condition (limiter)
  flushRun();
  photons[i].position_weight = vec4(o, weight);
  photons[i].direction = vec4(d, 0.0);
  photons[i].state = uvec4(g_rng, uint(order), paused ? 1u : 0u, 0u);
  if (paused) {
    atomicAdd(stats[5], 1u);
  } else if (order > 0) {
    atomicAdd(stats[0], 1u);
    atomicAdd(stats[1], uint(order));
  }
}
