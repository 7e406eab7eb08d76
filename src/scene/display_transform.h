#pragma once
// The display transform — tone curve and sRGB encoding — as C++ functions compiled from the very
// GLSL the GPU passes run (glsl/common/display.glsl; core/glsl_cpp.h, Bruneton's method): the PNG
// writer and the accuracy metric here, the viewer (glsl/render/present.frag) and the plugin API's
// display composite (glsl/api/composite.frag) on the GPU. There is no second copy to keep in step.
// The signatures below are those of display.glsl with Number = float and Number = double; a
// mismatch is a link error.
namespace nph::scene::display {

/// kToneCurve* codes of display.glsl (scene::ToneCurve has the same order).
inline constexpr int kToneCurveClamp = 0, kToneCurveReinhard = 1, kToneCurveAcesFitted = 2;

namespace f32 {  // float: what `nephele render` writes to PNG
float toneCurve(float linear, int curve);
float linearToSrgb(float linear);
}  // namespace f32

namespace f64 {  // double: for metrics that must not round to float
double toneCurve(double linear, int curve);
double linearToSrgb(double linear);
}  // namespace f64

}  // namespace nph::scene::display
