// Tileable 3-D noise for the procedural sub-grid detail (issue 13; Muth 2026 §3.3.1 "Sub-Grid
// Detail Synthesis", after Schneider's Nubis Perlin–Worley noise): one RGBA texel per lattice point
// of a periodic tile, generated ONCE by glsl/render/noise.comp (Thomann 2021 §4.4: a compute shader
// fills the 3-D texture, one noise per channel) and by its CPU twin (volume/noise.cpp compiles this
// file as C++, core/glsl_cpp.h). Both sides hash integers (Jarzynski & Olano 2020, "Hash functions
// for GPU rendering", pcg3d), so the random numbers are bit-identical; only the float arithmetic
// after them may round differently (tests: GPU and CPU texels within 1 code of 255).
//
// Channels, each in [0, 1] (tile coordinates p ∈ [0, 1)³):
//   r  gradient (Perlin) fBm, 4 lattice cells per tile, 3 octaves (gain ½, lacunarity 2)
//   g  inverted Worley fBm ("cauliflower" cells, 1 − F1), 4 cells per tile, 3 octaves
//   b  inverted Worley fBm, 8 cells per tile, 2 octaves (the fine Worley term)
//   a  gradient fBm of another seed, 4 cells, 3 octaves
// Periodic (Thomann 2021 §4.3): lattice indices are wrapped with a non-negative modulo before
// hashing, so the tile repeats seamlessly.
//
// Written in the GLSL subset that also compiles as C++ (core/glsl_cpp.h).
#if !defined(NPH_GLSL_AS_CPP) && !defined(Number)
#define Number float
#endif

// pcg3d (Jarzynski & Olano 2020): three well-mixed 32-bit words from three.
uvec3 pcg3d(uvec3 v) {
  v = v * 1664525u + 1013904223u;
  v.x += v.y * v.z;
  v.y += v.z * v.x;
  v.z += v.x * v.y;
  v ^= v >> 16u;
  v.x += v.y * v.z;
  v.y += v.z * v.x;
  v.z += v.x * v.y;
  return v;
}

// Non-negative lattice index modulo the period (Thomann 2021 §4.3: GLSL's % keeps the sign).
ivec3 wrapLattice(ivec3 c, int period) { return ((c % period) + period) % period; }

// Three uniform numbers in [0, 1) of lattice point c (already wrapped) and a seed: the top 24 bits
// of each word, exactly representable in a float on both sides.
vec3 latticeRandom(ivec3 c, int seed) {
  uvec3 h = pcg3d(uvec3(c) + uvec3(uint(seed) * 1013u, uint(seed) * 7919u, uint(seed) * 104729u));
  return vec3(h >> 8u) * Number(1.0 / 16777216.0);
}

// Perlin gradient noise (Perlin 2002: quintic fade, gradients at the lattice points) of period
// `period` lattice cells at lattice coordinates x; about [−1, 1].
Number gradientNoise(vec3 x, int period, int seed) {
  vec3 i = floor(x);
  vec3 f = x - i;
  vec3 u = f * f * f * (f * (f * Number(6.0) - Number(15.0)) + Number(10.0));
  ivec3 c0 = ivec3(i);
  Number n[8];
  for (int k = 0; k < 8; ++k) {
    ivec3 o = ivec3(k & 1, (k >> 1) & 1, (k >> 2) & 1);
    vec3 g = latticeRandom(wrapLattice(c0 + o, period), seed) * Number(2.0) - Number(1.0);
    n[k] = dot(g, f - vec3(o));
  }
  Number x00 = mix(n[0], n[1], u.x), x10 = mix(n[2], n[3], u.x);
  Number x01 = mix(n[4], n[5], u.x), x11 = mix(n[6], n[7], u.x);
  return mix(mix(x00, x10, u.y), mix(x01, x11, u.y), u.z);
}

// Distance to the nearest feature point, one per lattice cell (Worley 1996; Thomann 2021 §4.2, the
// 27 cells around x), of period `period` cells; clamped to [0, 1] cell sizes.
Number worleyF1(vec3 x, int period, int seed) {
  vec3 i = floor(x);
  vec3 f = x - i;
  ivec3 c0 = ivec3(i);
  Number d2 = Number(1.0);
  for (int k = 0; k < 27; ++k) {
    ivec3 o = ivec3(k % 3 - 1, (k / 3) % 3 - 1, k / 9 - 1);
    vec3 d = vec3(o) + latticeRandom(wrapLattice(c0 + o, period), seed) - f;
    d2 = min(d2, dot(d, d));
  }
  return sqrt(d2);
}

// fBm of gradient noise mapped to [0, 1]: octaves of period cells·2^o, amplitude ½^o, normalised by
// the sum of amplitudes (a single octave spans about ±0.87, so 0.5 + 0.5·n stays in [0, 1]).
Number gradientFbm(vec3 p, int cells, int octaves, int seed) {
  Number sum = Number(0.0), norm = Number(0.0), amplitude = Number(1.0);
  int period = cells;
  for (int o = 0; o < octaves; ++o) {
    sum += amplitude * gradientNoise(p * Number(period), period, seed + o);
    norm += amplitude;
    amplitude *= Number(0.5);
    period *= 2;
  }
  return clamp(Number(0.5) + Number(0.5) * sum / norm, Number(0.0), Number(1.0));
}

// fBm of inverted Worley noise (1 − F1: bright cell centres, the rounded "cauliflower" of
// cumulus; Muth 2026 §3.3.1 convective path) in [0, 1].
Number worleyFbm(vec3 p, int cells, int octaves, int seed) {
  Number sum = Number(0.0), norm = Number(0.0), amplitude = Number(1.0);
  int period = cells;
  for (int o = 0; o < octaves; ++o) {
    sum += amplitude * (Number(1.0) - worleyF1(p * Number(period), period, seed + o));
    norm += amplitude;
    amplitude *= Number(0.5);
    period *= 2;
  }
  return sum / norm;
}

// The texel at integer coordinates `texel` of a tile of size³ texels (texel centres at (t + ½)/size).
vec4 noiseTexel(ivec3 texel, int size) {
  vec3 p = (vec3(texel) + Number(0.5)) / Number(size);
  return vec4(gradientFbm(p, 4, 3, 0), worleyFbm(p, 4, 3, 16), worleyFbm(p, 8, 2, 32), gradientFbm(p, 4, 3, 48));
}
