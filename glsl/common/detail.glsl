// Procedural sub-grid detail (issue 13; Muth 2026 §3.3.1 "Sub-Grid Detail Synthesis"): how the
// noise volume (glsl/common/noise.glsl) and the per-voxel controls (volume/detail.h) turn the
// reconstructed extinction β(x) into the detailed field
//
//   β_d(x) = β(x + d(x)) · ρ(x + d(x)),
//
// d the turbulent displacement, ρ the density factor. One source for the shaders
// (glsl/dlm/volume.glsl extinctionAt: the DLM passes and the eye pass) and the CPU twin
// (volume/extinction_sampler.cpp, through volume/detail.cpp compiling this file as C++).
//
// Controls c (RGBA8 at data resolution, volume/detail.h): c.x turbulence amplitude, c.y convective
// weight, c.z cloud fraction (1 where the file has none), c.w core (β / the column's max β).
// Noise statistics (volume/noise.h, measured on the texels): each noise term m below is centred on
// its tile mean and divided by its largest deviation, so m ∈ [−1, 1] and E[m] = 0 over the tile.
//
// Written in the GLSL subset that also compiles as C++ (core/glsl_cpp.h).
#if !defined(NPH_GLSL_AS_CPP) && !defined(Number)
#define Number float
#endif

// Turbulent displacement (Muth 2026 §3.3.1 "Turbulent displacement": three decorrelated fBm
// samples, one per axis, amplitude ∝ the turbulent velocity scale, capped — Muth: 500 m on a
// 2.2 km grid): `nd` is the noise at the displacement scale, `reach_m` the cap per axis, the
// statistics (mean, half range) of channels r, a and g.
vec3 detailDisplacement(vec4 nd, Number turbulence, vec3 reach_m, vec4 statsRA, vec2 statsG) {
  vec3 m = vec3((nd.x - statsRA.x) / statsRA.y, (nd.w - statsRA.z) / statsRA.w, (nd.y - statsG.x) / statsG.y);
  return reach_m * turbulence * m;
}

// Density factor ρ ∈ [0, 2] (Muth clamps his at 2 too) with E[ρ] = 1 over the noise: the detail
// moves extinction inside the cell instead of adding or removing it (issue 13 "mass preserving";
// where Muth's smoothstep(0, e, CLC + p) erodes, this form redistributes).
//   n1 = the noise at the displaced position, n2 = the noise at the same position in a second,
//   rotated and finer frame (so that the tiles of the two never line up);
//   statsS / statsC = (mean, half range) of the stratiform and convective terms; amplitude = the
//   knob's strength (volume/detail.h: subtle ½, full 1).
// Stratiform path: gradient fBm from both frames, its amplitude peaking at the cloud's edge
// (1 − core): eroded, frayed edges and a gently varying interior. Convective path: gradient fBm ×
// inverted Worley fBm × fine inverted Worley fBm (Muth's web-like modulation times cauliflower
// cells), attenuated in the dense core (deep convective cores are left dense) and by high
// turbulence (coherent structure breaks down). Blended by the convective weight. Cloud fraction
// f < 1 as acceptance: at least 1 − f of the full modulation, so a cell the model calls partly
// cloudy breaks into cloud and clear air (where ρ reaches 0) while keeping its mean.
Number detailDensity(vec4 n1, vec4 n2, vec4 c, Number amplitude, vec2 statsS, vec2 statsC) {
  Number mS = (n1.x + n2.w - statsS.x) / statsS.y;
  Number mC = (n1.x * n1.y * n2.z - statsC.x) / statsC.y;
  Number core = c.w;
  Number aS = mix(Number(0.4), Number(1.0), Number(1.0) - core);
  Number aC = mix(Number(1.0), Number(0.3), core) * mix(Number(1.0), Number(0.6), c.x);
  Number a = max(mix(aS, aC, c.y), Number(1.0) - c.z);
  Number m = mix(mS, mC, c.y);
  return clamp(Number(1.0) + amplitude * a * m, Number(0.0), Number(2.0));
}

// The second noise frame: rotated by 37° about z and 30° about x, scaled by 1.7 (incommensurate
// with the first, so the sum of both has no common period at the tile size).
vec3 detailSecondFrame(vec3 q) {
  const Number cz = Number(0.79863551), sz = Number(0.60181502), cx = Number(0.86602540), sx = Number(0.5);
  vec3 r = vec3(cz * q.x - sz * q.y, sz * q.x + cz * q.y, q.z);
  return Number(1.7) * vec3(r.x, cx * r.y - sx * r.z, sx * r.y + cx * r.z);
}
