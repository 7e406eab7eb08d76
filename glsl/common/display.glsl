// Display transform: linear radiance (after the exposure scale 2^ev) → display-referred code
// values in [0, 1], per channel. One source for the PNG writer (scene/output_image.cpp), the
// viewer (glsl/render/present.frag), the plugin API's display composite (glsl/api/composite.frag)
// and the accuracy metric (accuracy/image_error.cpp); docs in scene/output_image.h.
//
// Written in the GLSL subset that also compiles as C++ (core/glsl_cpp.h; Bruneton 2017,
// "Precomputed atmospheric scattering: a new implementation", functions.glsl compiled by
// reference/functions.cc): `Number` is float in GLSL; in C++ the file is included into a
// namespace that makes it float (the PNG path) or double (the metric). Literals are written
// Number(x), so each instance computes in its own precision: float(x) of these decimals is the
// float literal x·f (checked by static_asserts in scene/output_image.cpp).
#ifndef NPH_GLSL_AS_CPP
#define Number float
#endif

// Tone curves (scene::ToneCurve has the same order; scene_file's "clamp" | "reinhard" | "aces").
const int kToneCurveClamp = 0;       // min(c, 1): images already in display range
const int kToneCurveReinhard = 1;    // c / (1 + c): Reinhard et al. 2002, eq. 3
const int kToneCurveAcesFitted = 2;  // Narkowicz 2016, "ACES Filmic Tone Mapping Curve"

// Narkowicz's fit of the ACES RRT+ODT luminance response for c ≥ 0, clamped to [0, 1]; the
// input is scaled by 0.6 to match the ACES reference exposure (white at c ≈ 13).
Number toneCurveAcesFitted(Number c) {
  const Number kExposureMatch = Number(0.6);
  const Number a = Number(2.51), b = Number(0.03), cc = Number(2.43), d = Number(0.59), e = Number(0.14);
  Number x = kExposureMatch * c;
  return clamp((x * (a * x + b)) / (x * (cc * x + d) + e), Number(0.0), Number(1.0));
}

// The curve `curve` (kToneCurve*) on one linear channel value; negative input counts as 0.
Number toneCurve(Number c, int curve) {
  c = max(c, Number(0.0));
  if (curve == kToneCurveReinhard) return c / (Number(1.0) + c);
  if (curve == kToneCurveAcesFitted) return toneCurveAcesFitted(c);
  return min(c, Number(1.0));
}

// The sRGB transfer function (IEC 61966-2-1:1999, eq. for V'): linear segment below 0.0031308,
// else 1.055·L^(1/2.4) − 0.055. Input in [0, 1] (the caller clamps or tone-maps first).
Number linearToSrgb(Number l) {
  return l <= Number(0.0031308) ? Number(12.92) * l : Number(1.055) * pow(l, Number(1.0) / Number(2.4)) - Number(0.055);
}
