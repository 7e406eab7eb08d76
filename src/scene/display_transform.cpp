// glsl/common/display.glsl compiled as C++, once in float and once in double (core/glsl_cpp.h).
#include "scene/display_transform.h"

#include "core/glsl_cpp.h"

namespace nph::scene::display {

namespace f32 {
using namespace nph::glsl;
using Number = float;
#include "../glsl/common/display.glsl"
}  // namespace f32

namespace f64 {
using namespace nph::glsl;
using Number = double;
#include "../glsl/common/display.glsl"
}  // namespace f64

static_assert(f32::kToneCurveClamp == kToneCurveClamp && f32::kToneCurveReinhard == kToneCurveReinhard &&
              f32::kToneCurveAcesFitted == kToneCurveAcesFitted);
// The float instance computes what scene/output_image.cpp computed before with float literals:
// each decimal of display.glsl rounds to the same float through double, Number(x), as directly, x·f.
static_assert(float(0.6) == 0.6f && float(2.51) == 2.51f && float(0.03) == 0.03f && float(2.43) == 2.43f &&
              float(0.59) == 0.59f && float(0.14) == 0.14f);
static_assert(float(0.0031308) == 0.0031308f && float(12.92) == 12.92f && float(1.055) == 1.055f &&
              float(2.4) == 2.4f && float(0.055) == 0.055f);

}  // namespace nph::scene::display
