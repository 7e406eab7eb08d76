// The detailed extinction field (issue 13) read through the volume: one source for the shaders
// (glsl/dlm/volume.glsl: the DLM passes and the eye pass) and their CPU twin
// (volume/extinction_sampler.cpp, which compiles this file as C++ members of a struct whose
// primitives read the voxels on the CPU; core/glsl_cpp.h, issue 17 item 4). The arithmetic on the
// controls and the noise is glsl/common/detail.glsl's; this file is the order in which they are
// read, so the GPU and the CPU cannot drift apart in it.
//
// The including code defines, before the #include:
//   the volume's parameters under the VolumeBlock's names: u_voxels, u_box_size_m, u_displacement_m,
//     u_detail_amplitude, u_noise_period_m, u_noise_stats_ra, u_noise_stats_gs, u_noise_stats_c,
//     u_detail_flow (τ_a, τ_b [s], phase a's weight, 0: volume/detail.h detailFlow);
//   vec3 volumeUvw(vec3 world_m) and bool insideGrownVolume(vec3 uvw);
//   vec2 plainExtinctionAt(vec3 world_m): (β_ice, β_water) of the reconstruction alone [1/m];
//   vec4 detailControlsAt(vec3 uvw): the RGBA8 controls in [0, 1] (GL_LINEAR, clamp to edge);
//   vec4 detailNoiseAt(vec3 q, Number lod): the noise tile at q tiles, at mipmap level of detail lod
//     (textureLod: GL_LINEAR_MIPMAP_LINEAR, GL_LINEAR when magnified, GL_REPEAT);
//   vec2 detailWindAt(vec3 uvw): the horizontal wind (U, V) [m/s] (GL_LINEAR, clamp to edge; 0
//     where the volume has none);
//   Number columnExtinctionAt(vec2 column_uv, Number w): β_ice + β_water at a column's centre
//     (column_uv, a voxel centre horizontally) and height w (uvw units), linear in height, 0 outside
//     the grid (GL_LINEAR with the zero border);
//   Number detailCorrectionTexel(ivec2 column): column's mass correction c_J, the nearest column's
//     outside the grid (1 where the correction is not applied).
//
// Written in the GLSL subset that also compiles as C++ (core/glsl_cpp.h).

// The shape's coverage at a world position (detail.glsl detailShape): the largest C_n of the 3×3
// columns around the nearest column centre, each column's β read at its centre (linear in height
// only; the zero border outside the grid). Columns farther than 1½ columns on an axis add at most
// exp(−1.5²/2σ²) = 0.10, below any edge (coverage ≥ θ − w − A = 0.15), so the switch of the 3×3 set
// at a column face leaves the shape continuous.
Number detailCoverageAt(vec3 world_m) {
  vec3 uvw = volumeUvw(world_m);
  vec2 n = vec2(u_voxels.x, u_voxels.y);
  vec2 g = vec2(uvw.x, uvw.y) * n - Number(0.5);  // continuous column index, centres at integers
  vec2 nearest = floor(g + Number(0.5));
  Number column_m = max(u_box_size_m.x / n.x, u_box_size_m.y / n.y);
  Number coverage = Number(0.0);
  for (int dy = -1; dy <= 1; ++dy) {
    for (int dx = -1; dx <= 1; ++dx) {
      vec2 col = nearest + vec2(Number(dx), Number(dy));
      Number b = columnExtinctionAt((col + Number(0.5)) / n, uvw.z);
      coverage = max(coverage, detailColumnCoverage(b, g - col, column_m));
    }
  }
  return coverage;
}

// Level of detail of the noise (issue 13: the "hairy fringe" of full detail seen from afar). The tile
// holds octaves down to 4 texels per lattice cell; seen from far enough, a pixel covers many of them,
// and the shape's smoothstep and the density turn the undersampled octaves into grain that crawls
// with the jitter. A ray whose footprint is `footprint_m` wide reads the tile prefiltered to it:
// the mipmap level where one texel spans the footprint, lod = log2(footprint · texels / period)
// (the GL rule for a texture seen at that scale, OpenGL 4.5 §8.14.1; texels per tile
// kDetailNoiseTexels = volume/noise.h kNoiseTexels). The levels are box means, so the noise keeps its
// mean and the detail fades towards its own mean (ρ → 1, the shape → the coverage's round edge)
// where it could not be resolved. 0 (footprint 0) is the full-resolution tile: the DLM passes and
// the mass measurement read it so; the eye pass passes its ray's footprint (extinctionAtFootprint).
#define kDetailNoiseTexels 64
Number detailNoiseLod(Number footprint_m, Number period_m) {
  if (!(footprint_m > Number(0.0))) return Number(0.0);
  return max(log2(footprint_m * Number(kDetailNoiseTexels) / period_m), Number(0.0));
}

// The noise advected with the wind (volume/detail.h DetailFlow, the flow-map scheme): the tile at
// (p + o_a) / period and (p + o_b) / period, o = −u·τ of each phase, blended by phase a's weight; `second`
// reads the second, rotated frame (detail.glsl detailSecondFrame) at the same point. Without a
// wind o_a = o_b = 0: both reads are the world-fixed tile's, bit for bit as before the advection.
// `footprint_m` sets the level of detail (detailNoiseLod; the second frame is 1.7× finer).
vec4 detailAdvectedNoiseAt(vec3 p_m, vec3 o_a, vec3 o_b, vec3 period_m, bool second, Number footprint_m) {
  vec3 qa = (p_m + o_a) / period_m, qb = (p_m + o_b) / period_m;
  Number period = min(period_m.x, min(period_m.y, period_m.z));
  if (second) {
    qa = detailSecondFrame(qa);
    qb = detailSecondFrame(qb);
    period = period / kDetailSecondFrameScale;
  }
  Number lod = detailNoiseLod(footprint_m, period);
  // Still air (DETAIL_WIND_ON false: no U, V): o_a = o_b = 0 and phase a's weight is 1, so the
  // blend is the one read, bit for bit (mix(x, y, 1) = y) — half the noise fetches.
  if (!(DETAIL_WIND_ON)) return detailNoiseAt(qa, lod);
  return mix(detailNoiseAt(qb, lod), detailNoiseAt(qa, lod), u_detail_flow.z);
}

// The mass correction at a horizontal position (uv, the volume's texture coordinates): c of the
// column, blended with its neighbours' across the band at its faces (detail.glsl
// detailCorrectionBlend) — four texels, weighted here so that the CPU twin and the GPU agree.
Number detailCorrectionAt(vec2 uv) {
  vec2 g = uv * vec2(Number(u_voxels.x), Number(u_voxels.y)) - Number(0.5);
  ivec2 c0 = ivec2(floor(g));
  vec2 f = detailCorrectionBlend(g);
  Number low = mix(detailCorrectionTexel(c0), detailCorrectionTexel(c0 + ivec2(1, 0)), f.x);
  Number high = mix(detailCorrectionTexel(c0 + ivec2(0, 1)), detailCorrectionTexel(c0 + ivec2(1, 1)), f.x);
  return mix(low, high, f.y);
}

// (β_ice, β_water) of the detailed field β(x + d)·ρ(x + d)·s·c at a world position (detail.glsl):
// the controls and the wind at x, the displacement d from the noise at x / 2P, β at the displaced
// point, the density factor and the shape's noise term from the noise there, the shape's coverage
// at x + 3d, the columns' mass correction at x. Every noise read is advected: at x − u(x)·τ per
// phase (the wind read once, at x, so the whole stencil of one sample moves together). The noise is
// read prefiltered to `footprint_m` (detailNoiseLod; 0: full resolution).
vec2 detailedExtinctionAt(vec3 world_m, Number footprint_m) {
  vec3 uvw = volumeUvw(world_m);
  if (!insideGrownVolume(uvw)) return vec2(Number(0.0));
  vec4 c = detailControlsAt(uvw);
  vec2 u = vec2(Number(0.0));
  if (DETAIL_WIND_ON) u = detailWindAt(uvw);
  vec3 oa = vec3(-u.x * u_detail_flow.x, -u.y * u_detail_flow.x, Number(0.0));
  vec3 ob = vec3(-u.x * u_detail_flow.y, -u.y * u_detail_flow.y, Number(0.0));
  vec4 nd = detailAdvectedNoiseAt(world_m, oa, ob, Number(2.0) * u_noise_period_m, false, footprint_m);
  vec3 d = detailDisplacement(nd, c.x, u_displacement_m, u_noise_stats_ra, vec2(u_noise_stats_gs.x, u_noise_stats_gs.y));
  vec3 q = world_m + d;
  vec2 beta = plainExtinctionAt(q);
  if (!(beta.x + beta.y > Number(0.0))) return beta;
  vec4 n1 = detailAdvectedNoiseAt(q, oa, ob, u_noise_period_m, false, footprint_m);
  vec4 n2 = detailAdvectedNoiseAt(q, oa, ob, u_noise_period_m, true, footprint_m);
  vec2 statsS = vec2(u_noise_stats_gs.z, u_noise_stats_gs.w), statsC = vec2(u_noise_stats_c.x, u_noise_stats_c.y);
  Number rho = detailDensity(n1, n2, c, u_detail_amplitude, statsS, statsC);
  Number m = detailModulation(n1, n2, c.y, statsS, statsC);
  Number shape = detailShape(detailCoverageAt(world_m + kDetailShapeDisplacement * d), m, u_detail_amplitude);
  return beta * (rho * shape * detailCorrectionAt(vec2(uvw.x, uvw.y)));
}
