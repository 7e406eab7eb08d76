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
// The zero-mean noise term m ∈ [−1, 1] of either regime, blended by the convective weight.
Number detailModulation(vec4 n1, vec4 n2, Number convective, vec2 statsS, vec2 statsC) {
  Number mS = (n1.x + n2.w - statsS.x) / statsS.y;
  Number mC = (n1.x * n1.y * n2.z - statsC.x) / statsC.y;
  return mix(mS, mC, convective);
}

Number detailDensity(vec4 n1, vec4 n2, vec4 c, Number amplitude, vec2 statsS, vec2 statsC) {
  Number core = c.w;
  Number aS = mix(Number(0.4), Number(1.0), Number(1.0) - core);
  Number aC = mix(Number(1.0), Number(0.3), core) * mix(Number(1.0), Number(0.6), c.x);
  Number a = max(mix(aS, aC, c.y), Number(1.0) - c.z);
  Number m = detailModulation(n1, n2, c.y, statsS, statsC);
  return clamp(Number(1.0) + amplitude * a * m, Number(0.0), Number(2.0));
}

// The second noise frame: rotated by 37° about z and 30° about x, scaled by 1.7 (incommensurate
// with the first, so the sum of both has no common period at the tile size).
#define kDetailSecondFrameScale Number(1.7)
vec3 detailSecondFrame(vec3 q) {
  const Number cz = Number(0.79863551), sz = Number(0.60181502), cx = Number(0.86602540), sx = Number(0.5);
  vec3 r = vec3(cz * q.x - sz * q.y, sz * q.x + cz * q.y, q.z);
  return kDetailSecondFrameScale * vec3(r.x, cx * r.y - sx * r.z, sx * r.y + cx * r.z);
}

// ---- Shape: the silhouette from a normalised, isotropic coverage (issue 13 "square pillars") ----
// A cloudy 10-km cell holds τ ≫ 1 (β ≈ 0.01–0.05 /m over 10 km), so the visible surface of the
// reconstructed β is where it falls to ~1/1000 of the peak: in the far tail of the filter. The
// trilinear tail of an isolated column is a square (its iso-line at 1/300 of the peak reaches 1.00
// column along the axes and 1.33 along the diagonals; the cubic B-spline's 1.69 and 1.84), and the
// tail's reach grows with log β, so every level whose β differs shows as a rib. Muth 2026 §3.3.1
// ("cloud cover as acceptance", eq. 3.5) shapes the cloud by a coverage in [0, 1] plus a noise
// perturbation instead; here the coverage is built so that its iso-lines are round and do not
// depend on the magnitude of β:
//   per column n of the 3×3 around the sample, at the sample's height,
//     C_n = (1 − exp(−β_n·Δ)) · exp(−d_n² / 2σ²),   coverage = max_n C_n,
//   β_n the column's β at its centre (linear in height), Δ the column spacing (so C_n ≈ 1 for any
//   cell the model calls cloudy, 0.1 for τ_cell = 0.1), d_n the horizontal distance from the
//   column's centre in columns, σ = kDetailCoverageSigma: an isolated column is a disc, a group of
//   columns the union of discs — rounded, never a square.
// The shape factor (Muth eq. 3.5 with an offset so the edge sits inside the filter's support):
//   s = smoothstep(θ − w, θ + w, coverage + A·m),  A = kDetailShapePerturbation × strength,
// so the edge lies where coverage = θ − A·m, between 0.25 and 0.85 (0.45 … 1.15 columns from an
// isolated column's centre, wobbling with the noise), and the interior (coverage 1, 1 + A·m ≥ 0.7
// > θ + w) is untouched. It only erodes (s ∈ [0, 1]); the per-column mass correction (volume/detail.h)
// puts the eroded mass back into the column's remaining, optically thick cloud, where it is invisible.
#define kDetailCoverageSigma Number(0.65)
#define kDetailShapeThreshold Number(0.45)
#define kDetailShapeWidth Number(0.1)
#define kDetailShapePerturbation Number(0.25)
// The shape reads the coverage at x + 3·d (d the turbulent displacement, ≤ ¼ column × strength):
// up to ¾ column, so straight column faces and level boundaries wiggle visibly (issue 13 brief:
// 0.5–1 column) while β itself moves by d only (the mass stays in its column).
#define kDetailShapeDisplacement Number(3.0)

// C_n of one column: `beta_per_m` its β at the sample's height, `d_columns` the horizontal offset
// of the sample from its centre [columns], `column_m` the column spacing [m].
Number detailColumnCoverage(Number beta_per_m, vec2 d_columns, Number column_m) {
  Number d2 = dot(d_columns, d_columns);
  return (Number(1.0) - exp(-beta_per_m * column_m)) *
         exp(-d2 / (Number(2.0) * kDetailCoverageSigma * kDetailCoverageSigma));
}

// The mass correction between columns (volume/detail.h "Mass", twentieth session): c_J holds over
// the core of column J and blends to its neighbours across a band of ±kDetailCorrectionBand columns
// at each face, so a face is no step (the seams thin anvil edges showed, docs/detail.md). `g` is the
// continuous column index (column centres at integers); the result is the bilinear weights' (fx, fy)
// between the columns floor(g) and floor(g) + 1 on each axis: 0 or 1 in the cores, ½ on the face,
// a smoothstep between. solveDetailCorrection solves c with these same weights at the measured rays.
#define kDetailCorrectionBand Number(0.25)
vec2 detailCorrectionBlend(vec2 g) {
  vec2 f = g - floor(g);
  return smoothstep(vec2(Number(0.5) - kDetailCorrectionBand), vec2(Number(0.5) + kDetailCorrectionBand), f);
}

// The shape factor s ∈ [0, 1] from the coverage and the noise term m (detailModulation).
Number detailShape(Number coverage, Number m, Number amplitude) {
  return smoothstep(kDetailShapeThreshold - kDetailShapeWidth, kDetailShapeThreshold + kDetailShapeWidth,
                    coverage + kDetailShapePerturbation * amplitude * m);
}
