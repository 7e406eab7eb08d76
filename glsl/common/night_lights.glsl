// City lights on the night side (issue 14 item 3: Debian marble-qt-data's citylights.jpg on the
// night side of the globe, and of the flat view once the sun has set). Nes 2008 §5.5 embeds the
// clouds in satellite imagery of the Earth and notes (§6.2) that a storm "would not be visible
// during the night"; Thomann 2021 §5.10.1 renders every time of day, before sunrise included. At
// night the imagery that tells where the storm is, is the lights of the cities under it.
//
// The lights are radiance emitted by the ground, added to its reflected radiance before the two
// things every ground radiance goes through in glsl/render/clouds.comp: the air between the eye and
// the ground (aerial perspective, L·T_air + L_in; Hillaire 2020) and the clouds in front of it
// (frame = C + T_cloud·L_ground, Nes 2008 eq. 5.18's background term). So the clouds dim them by
// exactly their transmittance and the air by its own, as they dim the lit ground.
//
// Units (docs/rendering.md "Conventions": everything but the sun is radiance [W/(m²·sr)]): the
// lights are given as a fraction k (the style knob `city_lights`) of E/π, the radiance of a white
// Lambertian ground under the overhead sun:
//   L_lights = k · Y(E)/π · I · fade(μ_s) · c,
// I ∈ [0, 1] the lights' intensity at the ground point (the imagery's A channel,
// scene::cityLightsIntensity), Y(E) the luminance of the sun's irradiance E (colour × intensity:
// a brighter sun, a brighter exposure-matched night), c the lights' colour (luminance 1) and μ_s
// the sine of the sun's elevation at the ground point (its local vertical). Tied to E because the
// renderer has one exposure for day and night: real lights are orders of magnitude dimmer than
// sunlit ground and would need a night exposure; with k the default (lighting/render_settings.h) a
// city core reads as bright as sunlit dark land.
//
// fade(μ_s): street lighting comes on at sunset and is fully on by the end of civil twilight (sun
// 6° below the horizon): 1 − smoothstep(sin(−6°), 0, μ_s). It is exactly 0 while the sun is up, so
// the day side's pixels keep their bits whatever the knob (tests/render/night_lights_gl_test.cpp).
//
// Written in the GLSL subset that also compiles as C++ (core/glsl_cpp.h): scene/night_lights.cpp
// is the CPU twin the tests compare against (`Number` is float here and there; literals are
// wrapped in Number() so that C++ computes in float too).
#ifndef NPH_GLSL_AS_CPP
#ifndef Number
#define Number float
#endif
#endif

const Number kCityLightsFullBelowSin = Number(-0.104528463);  // sin(−6°): the end of civil twilight
// The lights' colour: high-pressure sodium, the street lighting that dominates the night images
// (its emission peaks at 589 nm), as linear Rec.709 (1, 0.66, 0.30) scaled to luminance 1 (÷ 0.7063).
// A look: citylights.jpg (DMSP's panchromatic band) carries no colour.
const vec3 kCityLightsColour = vec3(Number(1.41585), Number(0.934461), Number(0.424753));
const Number kCityLightsInvPi = Number(0.318309886);

// The lights' share at a ground point whose local vertical has sine μ_s of the sun's elevation.
Number cityLightsFade(Number sinSunElevation) {
  return Number(1.0) - smoothstep(kCityLightsFullBelowSin, Number(0.0), sinSunElevation);
}

// The lights' radiance (see above): intensity I, the sun's elevation sine μ_s, the sun's
// irradiance E (colour × intensity) and the knob k.
vec3 cityLightsRadiance(Number intensity, Number sinSunElevation, vec3 sunIrradiance, Number k) {
  Number luminance = dot(sunIrradiance, vec3(Number(0.2126), Number(0.7152), Number(0.0722)));  // Rec.709 Y
  return (k * luminance * kCityLightsInvPi * intensity * cityLightsFade(sinSunElevation)) * kCityLightsColour;
}
