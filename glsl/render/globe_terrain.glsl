// Terrain on the globe (issue 14 item 2; docs/terrain.md "Globe"): the model's height field
// (glsl/common/terrain.glsl, the same surface as the flat view's) displaces the sphere R inside the
// globe's look-up table (render/raycast/globe.h):
//   |p| = R + H(p),   H(p) = e·h(W(p))·fade_table(p)
// with W the table's ECEF → world xy map (globeWorldFromEcef), e·h the exaggerated, edge-faded
// heights of terrainHeight_m and fade_table a linear ramp to 0 over the table's outer margin
// (u_terrain_edge_m): the table ends a few per cent beyond the footprint, before terrain.glsl's own
// fade to sea level does, and the ground must not end in a cliff there. Outside the table the ground
// is the sphere R, as without terrain. Thomann 2021 §5.3 draws WRF's HGT as a displaced mesh on the
// globe; here the eye pass marches it, as the flat view does, so no mesh and no depth buffer.
//
// Intersection: the conservative march of terrain.glsl carried to ECEF. Along a ray (unit d),
//   f(t) = |p(t)| − R − H(p(t))
// changes at most at the rate 1 + L·L_h + H_max/edge (|d|p|/dt| ≤ 1; the world point moves at most
// L_h world metres per ECEF metre (globe.h) and the surface rises at most L per world metre; the
// table's ramp at most H_max/edge per metre): u_terrain_rate, from the CPU. Steps f/rate cannot
// cross the surface; close to it they are floored at a quarter of a cell; the first step under the
// surface is refined by bisection. The march runs only where the ray is inside the shell
// R + min ≤ |p| ≤ R + max (spheres with |o|² − r² from the CPU in double, as the ground's) and on
// the table's side of the plane p·c ≥ (R + min)·cos α_table.
// Requires render/globe.glsl, common/terrain.glsl and clouds.comp's terrainGrid().

// Table margin ramp: 1 inside, falling linearly to 0 at the table's edge over u_terrain_edge_m.
float globeTableFade(vec3 p) {
  vec2 ab = globeRotatedLonLat(u_local_from_ecef * p);
  vec2 edge = min(ab - u_ab_min_rad, u_ab_max_rad - ab) * u_earth_radius_m;  // metres of arc to the edges
  return clamp(min(edge.x, edge.y) / u_terrain_edge_m, 0.0, 1.0);
}

// H(p): the terrain's world height [m] above the sphere R under the ECEF point p (0 outside the table).
float globeTerrainHeight_m(vec3 p) {
  vec3 w = globeWorldFromEcef(p);
  if (w.x == kOutsideTable_m) return 0.0;
  return terrainHeight_m(terrainGrid(), w.xy) * globeTableFade(p);
}

float globeTerrainClearance_m(vec3 o, vec3 d, float t) {
  vec3 p = o + t * d;
  return length(p) - u_earth_radius_m - globeTerrainHeight_m(p);
}

// The march itself over [t0, t1] of o + t·d (d unit): the first t with f(t) ≤ 0, kNoHit_m if none.
float globeTerrainMarch(vec3 o, vec3 d, float t0, float t1) {
  // The table's side of the plane p·c ≥ (R + min)·cos α_table (a cone's cap, as globeVolumeInterval).
  float oc = dot(o, u_cap_axis) - u_terrain_cap_min_dot_m, dc = dot(d, u_cap_axis);
  if (dc > 0.0) t0 = max(t0, -oc / dc);
  else if (dc < 0.0) t1 = min(t1, -oc / dc);
  else if (oc < 0.0) t1 = -1.0;
  if (t0 > t1) return kNoHit_m;
  float minStep = 0.25 * min(u_terrain_cell_m.x, u_terrain_cell_m.y) / u_lipschitz_h;
  float t = t0;
  float f = globeTerrainClearance_m(o, d, t);
  if (f <= 0.0) return t;
  for (int n = 0; n < kTerrainMaxSteps && t < t1; ++n) {
    float tn = min(t + max(f / u_terrain_rate, minStep), t1);
    float fn = globeTerrainClearance_m(o, d, tn);
    if (fn <= 0.0) {  // crossed in (t, tn]: bisection keeps f(a) > 0 ≥ f(b)
      float a = t, b = tn;
      for (int k = 0; k < kTerrainBisections; ++k) {
        float m = 0.5 * (a + b);
        if (globeTerrainClearance_m(o, d, m) > 0.0) a = m;
        else b = m;
      }
      return b;
    }
    t = tn;
    f = fn;
  }
  return kNoHit_m;
}

// Distance along the eye ray camera + t·d (d unit; u_terrain_c_m2 are |o|² − r² of the shell's
// spheres for the camera, in double on the CPU like the ground's) to the displaced ground: the
// terrain inside the table's part of the shell, else the sphere R; kNoHit_m when the ray misses the
// Earth.
float globeTerrainDistance(vec3 o, vec3 d) {
  float tSphere = globeGroundDistance(o, d);
  vec2 shell = sphereInterval(o, d, u_terrain_c_m2.x);  // inside R + max
  float t0 = max(shell.x, 0.0), t1 = shell.y;
  vec2 core = sphereInterval(o, d, u_terrain_c_m2.y);  // R + min − 1 m: surely under the ground
  if (core.x <= core.y && core.y >= 0.0) t1 = min(t1, max(core.x, 0.0));
  float hit = t0 <= t1 ? globeTerrainMarch(o, d, t0, t1) : kNoHit_m;
  return hit < kNoHit_m ? hit : tSphere;
}

// Whether the terrain hides the sun from the ground point g (ECEF, lifted off the surface by the
// caller), towards the unit toSun (above g's horizon): the march up to where the ray leaves the
// sphere R + max (|g|² − r² in float: g is under that sphere, the root is well conditioned).
bool globeTerrainShadows(vec3 g, vec3 toSun) {
  float rTop = u_earth_radius_m + u_terrain_max_m;
  vec2 shell = sphereInterval(g, toSun, dot(g, g) - rTop * rTop);
  return shell.y > 0.0 && globeTerrainMarch(g, toSun, 0.0, shell.y) < kNoHit_m;
}

// Unit outward normal of the displaced globe ground at the ECEF point g: central differences of H
// half a cell east and north of g, n ∝ up − ∂H/∂east·east − ∂H/∂north·north (the exaggerated slope,
// as terrainNormal in the flat view).
vec3 globeTerrainNormal(vec3 g) {
  vec3 up = normalize(g);
  vec3 east = cross(vec3(0.0, 0.0, 1.0), up);
  east = dot(east, east) > 1e-12 ? normalize(east) : vec3(0.0, 1.0, 0.0);  // on a pole: any tangent
  vec3 north = cross(up, east);
  float h = 0.5 * min(u_terrain_cell_m.x, u_terrain_cell_m.y);
  float dHdE = (globeTerrainHeight_m(g + h * east) - globeTerrainHeight_m(g - h * east)) / (2.0 * h);
  float dHdN = (globeTerrainHeight_m(g + h * north) - globeTerrainHeight_m(g - h * north)) / (2.0 * h);
  return normalize(up - dHdE * east - dHdN * north);
}
