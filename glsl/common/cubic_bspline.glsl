// The uniform cubic B-spline's weights (Sigg & Hadwiger 2005, "Fast Third-Order Texture Filtering",
// GPU Gems 2 ch. 20, eq. 20.3) — one source for the shaders' tricubic filter from 8 trilinear
// fetches (glsl/dlm/volume.glsl cubicBSplineRgba: the DLM passes, the eye pass and the column
// depths) and the CPU's 64-weight sum (volume/reconstruction.h reconstructAt: ExtinctionSampler,
// the column depths' twin), which compiles this file as C++ in double (core/glsl_cpp.h).
//
// Written in the GLSL subset that also compiles as C++ (core/glsl_cpp.h); the includer defines
// Number and Vec4 there (double, glm::dvec4).
#ifndef NPH_GLSL_AS_CPP
#define Number float
#define Vec4 vec4
#endif

// The weights (w0, w1, w2, w3) of the four samples c₁ − 1, c₁, c₁ + 1, c₁ + 2 around a point at
// fraction f ∈ [0, 1] past sample c₁ (eq. 20.3). They sum to 1 and are ≥ 0.
Vec4 cubicBSplineWeights(Number f) {
  Number g = Number(1.0) - f;
  return Vec4(g * g * g / Number(6.0), Number(2.0) / Number(3.0) - Number(0.5) * f * f * (Number(2.0) - f),
              Number(2.0) / Number(3.0) - Number(0.5) * g * g * (Number(1.0) + f), f * f * f / Number(6.0));
}

// Their derivatives d w_k / d f (−g²/2, f(3f − 4)/2, (1 + 2f − 3f²)/2, f²/2): the spline's slope is
// Σ w_k'·s_k per sample spacing. They sum to 0, and Σ w_k'·s_k = Σ_{k=1..3} B2_k(f)·(s_k − s_{k−1})
// with B2 the quadratic B-spline's weights (≥ 0, summing to 1), so the slope never exceeds the
// largest step between neighbouring samples (the terrain's Lipschitz bound, volume/terrain_field.cpp).
Vec4 cubicBSplineSlopes(Number f) {
  Number g = Number(1.0) - f;
  return Vec4(Number(-0.5) * g * g, Number(0.5) * f * (Number(3.0) * f - Number(4.0)),
              Number(0.5) * (Number(1.0) + Number(2.0) * f - Number(3.0) * f * f), Number(0.5) * f * f);
}

// The same weights merged pairwise into two linear fetches (§20.3): (g0, g1, h0, h1), where
// g0 = w0 + w1 and g1 = w2 + w3 weight the two fetches and h0 = w1 / g0, h1 = w3 / g1 are their
// fractions past samples c₁ − 1 and c₁ + 1 — a linear fetch at c₁ − 1 + h0 returns
// (w0·s(c₁ − 1) + w1·s(c₁)) / g0, exactly, because linear filtering's weights are then
// w0 / g0 and w1 / g0. g0, g1 ≥ 1/6 on [0, 1], so the divisions are safe.
Vec4 cubicBSplineFetches(Number f) {
  Vec4 w = cubicBSplineWeights(f);
  Number g0 = w.x + w.y, g1 = w.z + w.w;
  return Vec4(g0, g1, w.y / g0, w.w / g1);
}
