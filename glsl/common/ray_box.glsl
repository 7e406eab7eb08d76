// Ray against axis-aligned boxes by the slab method (Kay & Kajiya 1986, "Ray tracing complex
// scenes", §4): per axis the distances t0, t1 to the two planes of the slab; the ray is inside
// the box between the largest entry and the smallest exit.

// Zero direction components replaced by a tiny magnitude (1e-20, far below any step of a scene),
// so that (plane − origin) / d stays finite: IEEE ±inf would turn 0·inf into NaN for a ray lying
// in a face plane. The sign choice (+) is harmless: such a ray never leaves its slab.
const float kTinyDirection = 1e-20;
vec3 safeDirection(vec3 d) { return mix(d, vec3(kTinyDirection), equal(d, vec3(0.0))); }

// (entry, exit) along the ray from the per-axis plane distances t0, t1 (either order per axis);
// the box is hit where entry ≤ exit. Entry may be negative (origin inside the box).
vec2 slabInterval(vec3 t0, vec3 t1) {
  vec3 lo = min(t0, t1), hi = max(t0, t1);
  return vec2(max(max(lo.x, lo.y), lo.z), min(min(hi.x, hi.y), hi.z));
}
