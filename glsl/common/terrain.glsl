// The ground's height field (issue 14 item 2): the model's own terrain (WRF HGT, ICON HSURF) as a
// displaced surface in the flat view's world frame (volume/volume_frame.h), and the eye ray's first
// intersection with it. One source for the eye pass (glsl/render/clouds.comp) and the CPU reference
// ray marcher (volume/terrain_field.h compiles this file as C++, core/glsl_cpp.h, after Bruneton
// 2017's shared definitions).
//
// The surface (Thomann 2021 §5.3 draws WRF's HGT as a displaced mesh; Muth 2026 §3.4.10 and
// weBIGeo show clouds over real terrain): z = e·h(x, y), h the interpolating cubic spline through
// the heights at the mass points (i + ½)·dx, (j + ½)·dy — the same lattice as the voxel centres —
// and e the height exaggeration, applied exactly as to the clouds (Nes 2008 §5.5.2). Outside the
// data's footprint
// the edge heights are held (clamp to edge) and fade linearly to sea level over `fade_m`, so the
// ground beyond the domain is the plane z = 0 of the flat view (item 4, no void) with no cliff at
// the domain's edge.
//
// Intersection: a conservative march (Lipschitz bound, as sphere tracing, Hart 1996): along the
// ray f(t) = z(t) − e·h(xy(t)) changes at most at rate |d_z| + L·|d_xy| with L ≥ |∇(e·h)| an upper
// bound of the slope (TerrainGrid::lipschitz, from the data), so a step f/(|d_z| + L·|d_xy|) cannot
// cross the surface. Close to the surface the step is floored at a quarter of a cell horizontally
// (the data has no feature below its grid spacing; a ray grazing flat ground would otherwise creep),
// and the first step that lands below the surface is refined by bisection. The march is limited to
// the slab of heights the terrain has (z ∈ [min, max]) and to the rectangle outside which it is the
// plane z = 0, so a flat field costs nothing.
//
// The far ground (a user DEM, scene/dem.h): when the grid has_far, a second, coarser height field
// covers the far basemap's square around the footprint (scene::farBasemapRectangle), pixel-is-area
// like the basemap: texel (i, j) is the height at far_min_m + (i + ½, j + ½)·far_cell_m, j = 0 at
// the south edge, 0 where the DEM has no data. Beyond the footprint the fade then goes from the
// model lattice's edge to the far field (h = mix(h_far, h_edge, fade)) instead of to sea level, so
// the DEM's mountains go on to the horizon; inside the footprint the far field is not read. One
// surface, one march: the rectangle becomes the far square, the slab and the Lipschitz bound cover
// both fields (TerrainField::lipschitz), and the march's floor step is a quarter of the model's
// cell over the model's lattice and half a far pixel beyond it, so that a ray grazing the ground all
// the way across the far square (1024 pixels a side, 1448 on the diagonal: ≤ 2900 steps, plus the
// lattice's) stays within kTerrainMaxSteps. Beyond the far square the ground is the plane z = 0.
//
// A DEM finer than the model (scene::demRefinementFor) makes the lattice finer: r·nx × r·ny points at
// (i + ½)·dx/r, the same footprint; size and cell_m are the lattice's, so nothing below changes but
// the floor step (a quarter of the finer cell) and hence kTerrainMaxSteps (a lattice of 8 × 72
// points and the far square crossed by one grazing ray: ≤ 2300 + 2900 steps).
//
// Written in the GLSL subset that also compiles as C++ (core/glsl_cpp.h). Each side supplies
// TerrainGrid, TERRAIN_TEXEL(grid, i, j) (the height [m] at mass point (i, j), not exaggerated) and
// TERRAIN_FAR_TEXEL(grid, i, j) (the far field's, the same) before including this file: the shader
// fetches the R32F textures UNIT_TERRAIN and UNIT_FAR_TERRAIN, the CPU twin reads its vectors.
#ifndef NPH_GLSL_AS_CPP
#ifndef Number
#define Number float
#endif
#endif

const Number kTerrainMiss_m = Number(3.0e38);  // "no hit" distance
const int kTerrainMaxSteps = 8192;              // quarter cells: a 1000-cell lattice end to end and the far square
const int kTerrainBisections = 14;              // hit to 2^-14 of the last step

// The far field's height [m above MSL, not exaggerated] at world (x, y): bilinear between its
// texel centres, clamped to the edge inside its square, 0 outside it.
Number terrainFarHeight_m(TerrainGrid g, Vec2 xy) {
  Vec2 extent = Vec2(g.far_size) * g.far_cell_m;
  Vec2 r = xy - g.far_min_m;
  if (r.x < Number(0.0) || r.y < Number(0.0) || r.x > extent.x || r.y > extent.y) return Number(0.0);
  Vec2 q = r / g.far_cell_m - Vec2(Number(0.5));
  Vec2 qc = clamp(q, Vec2(Number(0.0)), Vec2(g.far_size - ivec2(1)));
  ivec2 i0 = ivec2(floor(qc));
  ivec2 i1 = min(i0 + ivec2(1), g.far_size - ivec2(1));
  Vec2 f = qc - Vec2(i0);
  return mix(mix(TERRAIN_FAR_TEXEL(g, i0.x, i0.y), TERRAIN_FAR_TEXEL(g, i1.x, i0.y), f.x),
             mix(TERRAIN_FAR_TEXEL(g, i0.x, i1.y), TERRAIN_FAR_TEXEL(g, i1.x, i1.y), f.x), f.y);
}

// The lattice's surface and its slope at the clamped continuous index qc ∈ [0, size − 1]²:
// (h [m], ∂h/∂q_x, ∂h/∂q_y [m per lattice step]), h = Σ_a Σ_b w_a(f_x)·w_b(f_y)·c(i₀ + a − 1, j₀ + b − 1)
// with the uniform cubic B-spline's weights (glsl/common/cubic_bspline.glsl) and indices clamped
// to the lattice. TERRAIN_TEXEL holds the coefficients c of the interpolating spline
// (volume/terrain_field.cpp splineCoefficients: Unser 1999's prefilter, as the clouds'
// `cubic_interpolating` reconstruction), so h passes through the lattice's heights exactly.
// Issue 14 (seventeenth session): the bilinear surface of before was C⁰ — a ruled patch per cell,
// its normal (central differences) kinked along every lattice line — so within ~10 km of a low
// eye the 500 m DEM showed its cells as facets and its ridgelines as polygons. The spline is C²,
// the normal is continuous and taken from the same polynomial (no finite differences), and on
// relief of 8 lattice steps' wavelength its normal is ~10–20× closer to the true surface's than
// the old one (tests/scene/terrain_surface_test.cpp). The plain B-spline of the heights (no
// prefilter) would be smoother still but lowers every peak and flattens every slope — its normals
// were further from the truth than the bilinear's. Cost: 16 texel fetches instead of 4. The
// weights are ≥ 0 and sum to 1, so the surface stays inside its coefficients' range and its
// slope inside the largest step between neighbouring coefficients: the march's slab and
// Lipschitz bound are the coefficients' (TerrainField::min_m, max_m, lipschitz).
Vec3 terrainLatticeSpline(TerrainGrid g, Vec2 qc) {
  ivec2 i0 = ivec2(floor(qc));
  Vec2 f = qc - Vec2(i0);
  ivec2 last = g.size - ivec2(1);
  Vec4 wx = cubicBSplineWeights(f.x), wy = cubicBSplineWeights(f.y);
  Vec4 sx = cubicBSplineSlopes(f.x), sy = cubicBSplineSlopes(f.y);
  Vec3 s = Vec3(Number(0.0));
  for (int b = 0; b < 4; ++b) {
    int j = min(max(i0.y - 1 + b, 0), last.y);
    Number row = Number(0.0), rowSlope = Number(0.0);
    for (int a = 0; a < 4; ++a) {
      Number h = TERRAIN_TEXEL(g, min(max(i0.x - 1 + a, 0), last.x), j);
      row += wx[a] * h;
      rowSlope += sx[a] * h;
    }
    s += Vec3(wy[b] * row, wy[b] * rowSlope, sy[b] * row);
  }
  return s;
}

// Terrain height in world metres (exaggerated) at world (x, y): the lattice's interpolating spline,
// clamped to the edge, faded to 0 over fade_m outside the footprint of the mass points.
Number terrainHeight_m(TerrainGrid g, Vec2 xy) {
  Vec2 q = xy / g.cell_m - Vec2(Number(0.5));  // continuous mass-point index
  Vec2 hi = Vec2(g.size - ivec2(1));
  Vec2 qc = clamp(q, Vec2(Number(0.0)), hi);
  Number h = terrainLatticeSpline(g, qc).x;
  Number outside_m = length((q - qc) * g.cell_m);
  Number fade = clamp(Number(1.0) - outside_m / g.fade_m, Number(0.0), Number(1.0));
  if (g.has_far && fade < Number(1.0)) return mix(terrainFarHeight_m(g, xy), h, fade) * g.exaggeration;
  return h * g.exaggeration * fade;
}

// Unit surface normal of the displaced (exaggerated) terrain, (−∂z/∂x, −∂z/∂y, 1) normalised. The
// exaggerated slope is what the picture shows, so it is what is shaded (the "z-factor" of hill
// shading). Inside the footprint (half a cell short of its edge, where the clamp and the fade
// begin) the slope is the B-spline's own, analytic: e·∂h/∂q / cell. Elsewhere — the fade to the
// far field or to sea level — central differences half a cell either way, as before.
Vec3 terrainNormal(TerrainGrid g, Vec2 xy) {
  Vec2 q = xy / g.cell_m - Vec2(Number(0.5));
  Vec2 hi = Vec2(g.size - ivec2(1));
  if (q.x >= Number(0.0) && q.y >= Number(0.0) && q.x <= hi.x && q.y <= hi.y) {
    Vec3 s = terrainLatticeSpline(g, q);
    Vec2 slope = g.exaggeration * Vec2(s.y, s.z) / g.cell_m;
    return normalize(Vec3(-slope.x, -slope.y, Number(1.0)));
  }
  Vec2 d = Number(0.5) * g.cell_m;
  Number dzdx = (terrainHeight_m(g, xy + Vec2(d.x, Number(0.0))) - terrainHeight_m(g, xy - Vec2(d.x, Number(0.0)))) /
                (Number(2.0) * d.x);
  Number dzdy = (terrainHeight_m(g, xy + Vec2(Number(0.0), d.y)) - terrainHeight_m(g, xy - Vec2(Number(0.0), d.y))) /
                (Number(2.0) * d.y);
  return normalize(Vec3(-dzdx, -dzdy, Number(1.0)));
}

// Ray parameter interval [t.x, t.y] inside the rectangle [lo, hi] of the xy plane (t.x > t.y: none).
Vec2 terrainRectInterval(Vec2 o, Vec2 d, Vec2 lo, Vec2 hi) {
  Number t0 = Number(-kTerrainMiss_m), t1 = kTerrainMiss_m;
  for (int a = 0; a < 2; ++a) {
    if (abs(d[a]) > Number(1e-12)) {
      Number ta = (lo[a] - o[a]) / d[a], tb = (hi[a] - o[a]) / d[a];
      t0 = max(t0, min(ta, tb));
      t1 = min(t1, max(ta, tb));
    } else if (o[a] < lo[a] || o[a] > hi[a]) {
      return Vec2(kTerrainMiss_m, Number(-kTerrainMiss_m));
    }
  }
  return Vec2(t0, t1);
}

// f(t) = z(t) − terrain height: positive above the ground.
Number terrainClearance_m(TerrainGrid g, Vec3 o, Vec3 d, Number t) {
  Vec3 p = o + t * d;
  return p.z - terrainHeight_m(g, Vec2(p.x, p.y));
}

// Distance along the ray o + t·d (d unit) to its first point on or under the terrain with t in
// [tMin, tMax]; kTerrainMiss_m when there is none.
Number terrainHitDistance(TerrainGrid g, Vec3 o, Vec3 d, Number tMin, Number tMax) {
  // Outside the rectangle the terrain reaches, the ground is the plane z = 0.
  Vec2 nearLo = Vec2(-g.fade_m), nearHi = Vec2(g.size) * g.cell_m + Vec2(g.fade_m);
  Vec2 rect = g.has_far ? terrainRectInterval(Vec2(o.x, o.y), Vec2(d.x, d.y), g.far_min_m,
                                              g.far_min_m + Vec2(g.far_size) * g.far_cell_m)
                        : terrainRectInterval(Vec2(o.x, o.y), Vec2(d.x, d.y), nearLo, nearHi);
  Number tPlane = d.z < Number(0.0) ? -o.z / d.z : kTerrainMiss_m;
  if (o.z <= Number(0.0) && (rect.x > rect.y || Number(0.0) < rect.x || Number(0.0) > rect.y)) tPlane = Number(0.0);
  // The slab of heights the terrain has.
  Number tLo = max(tMin, Number(0.0)), tHi = tMax;
  if (d.z < Number(0.0)) {
    // The end a metre under the lowest ground, where the ray is surely under the surface: ending
    // exactly at z = min left f = +rounding there, and the ray slipped through flat ground.
    tLo = max(tLo, (g.max_m - o.z) / d.z);
    tHi = min(tHi, (g.min_m - Number(1.0) - o.z) / d.z);
  } else if (d.z > Number(0.0)) {
    tHi = min(tHi, (g.max_m - o.z) / d.z);
  } else if (o.z > g.max_m) {
    tHi = Number(-1.0);
  }
  Number t0 = max(tLo, rect.x), t1 = min(tHi, rect.y);
  Number hit = kTerrainMiss_m;
  if (t0 <= t1) {
    Number dxy = length(Vec2(d.x, d.y));
    Number rate = abs(d.z) + g.lipschitz * dxy;
    Number minStep = dxy > Number(1e-6) ? Number(0.25) * min(g.cell_m.x, g.cell_m.y) / dxy : t1 - t0;
    Number farMinStep = dxy > Number(1e-6) ? Number(0.5) * min(g.far_cell_m.x, g.far_cell_m.y) / dxy : t1 - t0;
    Number t = t0;
    Number f = terrainClearance_m(g, o, d, t);
    if (f <= Number(0.0)) {
      hit = t;
    } else {
      for (int n = 0; n < kTerrainMaxSteps; ++n) {
        if (t >= t1) break;
        Number floorStep = minStep;
        if (g.has_far) {  // beyond the model lattice's reach, the far field's cell
          Vec2 p = Vec2(o.x, o.y) + t * Vec2(d.x, d.y);
          if (p.x < nearLo.x || p.y < nearLo.y || p.x > nearHi.x || p.y > nearHi.y) floorStep = max(minStep, farMinStep);
        }
        Number tn = min(t + max(f / rate, floorStep), t1);
        Number fn = terrainClearance_m(g, o, d, tn);
        if (fn <= Number(0.0)) {  // crossed in (t, tn]: bisection keeps f(a) > 0 ≥ f(b)
          Number a = t, b = tn;
          for (int k = 0; k < kTerrainBisections; ++k) {
            Number m = Number(0.5) * (a + b);
            if (terrainClearance_m(g, o, d, m) > Number(0.0)) {
              a = m;
            } else {
              b = m;
            }
          }
          hit = b;
          break;
        }
        t = tn;
        f = fn;
      }
    }
  }
  // No terrain hit in the rectangle: the plane z = 0 outside it (before or after).
  if (hit == kTerrainMiss_m && tPlane >= tMin && tPlane <= tMax && (tPlane < rect.x || tPlane > rect.y)) hit = tPlane;
  return hit;
}
