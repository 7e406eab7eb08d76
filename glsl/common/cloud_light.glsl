// Light at a cloud sample (issue 12): the phase functions, the multiple-scattering octave series,
// the sky light through the cloud around the sample, and the analytic clear sky that lights it.
// One source for the eye pass (glsl/render/clouds.comp) and its CPU twins (lighting/cloud_light.h
// compiles this file as C++ in double precision for the reference ray marcher, the path tracer's
// sky and the tests). Units: docs/rendering.md "Conventions" — the sun is a directional light of
// irradiance E, every other quantity is radiance; the phase functions are densities over the
// sphere (∫p dΩ = 1, unit 1/sr), so single scattering of sunlight is E·p·I_DLM.
//
// Written in the GLSL subset that also compiles as C++ (core/glsl_cpp.h, after Bruneton 2017).
#ifndef NPH_GLSL_AS_CPP
#define Number float
#define Vec3 vec3
#endif

const Number kInvFourPi = Number(0.0795774715459477);  // 1/(4π)

// Henyey–Greenstein phase function [1/sr] (Henyey & Greenstein 1941; Nes 2008 eq. 2.11 up to the
// 4π normalisation): p(ψ) = (1 − g²) / (4π·(1 + g² − 2g·cos ψ)^{3/2}).
Number hgPhase(Number cosPsi, Number g) {
  Number g2 = g * g;
  return kInvFourPi * (Number(1.0) - g2) / pow(max(Number(1.0) + g2 - Number(2.0) * g * cosPsi, Number(1e-6)), Number(1.5));
}

// The β_sca-weighted mix of the ice and water lobes at one sample (Nes 2008 eq. 5.12; albedo 1,
// so β_sca = β_ext): iceWeight = β_ice / (β_ice + β_water).
Number mixedPhase(Number cosPsi, Number iceWeight, Number gIce, Number gWater) {
  return iceWeight * hgPhase(cosPsi, gIce) + (Number(1.0) - iceWeight) * hgPhase(cosPsi, gWater);
}

// Multiple scattering of sunlight as an octave series (Wrenninge, Kulla & Lundqvist 2013, "Oz:
// the great and volumetric"; Hillaire 2016 §5.9.3; Muth 2026 §3.4.6; fitted to the path tracer
// by `nephele-bench accuracy --fit-octaves`, docs/accuracy.md):
//   F = Σ_{n<N} bⁿ · I^{aⁿ} · p_v(ψ; cⁿ·g_ice, cⁿ·g_water)        [1/sr]
// where I ∈ [0, 1] is the deep light map's sunlight at the sample. For pure attenuation
// I = T(τ) = e^{−τ}, and I^{aⁿ} = T(aⁿ·τ): octave n sees the optical depth scaled by aⁿ from the
// same look-up. n = 0 is single scattering exactly. The sample's sunlit in-scattering is E·F.
Number octaveSeries(Number sunlight, Number cosPsi, Number iceWeight, Number gIce, Number gWater, int octaves,
                    Number extinctionScale, Number energyScale, Number anisotropyScale) {
  Number sum = Number(0.0), energy = Number(1.0), depth = Number(1.0), aniso = Number(1.0);
  for (int n = 0; n < octaves; ++n) {
    Number light = n == 0 ? sunlight : (sunlight > Number(0.0) ? pow(sunlight, depth) : Number(0.0));
    sum += energy * light * mixedPhase(cosPsi, iceWeight, aniso * gIce, aniso * gWater);
    energy *= energyScale;
    depth *= extinctionScale;
    aniso *= anisotropyScale;
  }
  return sum;
}

// Diffuse (hemispherically incident) transmittance of a conservatively scattering layer of
// optical depth τ, two-stream (Eddington) approximation with the (1 − g) similarity scaling (Bohren
// 1987, "Multiple scattering of light and some of its observable consequences"; van de Hulst 1980):
// T_d = 1 / (1 + ¾·(1 − g)·τ). It carries the sky light down (and the ground-reflected light up) to
// a sample inside a cloud through the column above (below) it (volume/column_depth.h). Exact at
// τ = 0 and ∝ 1/((1 − g)·τ) for thick layers like the diffusion limit 4/(3(1 − g)(τ + 1.42))
// (van de Hulst), which it undershoots by ≈ 25 % at τ = 20, g = 0.85: the sky term is a model,
// the octave fit against the path tracer absorbs what it misses (docs/accuracy.md).
Number diffuseTransmittance(Number tau, Number g) {
  return Number(1.0) / (Number(1.0) + Number(0.75) * (Number(1.0) - g) * max(tau, Number(0.0)));
}

// Relative air mass of a solar elevation (Kasten & Young 1989, "Revised optical air mass tables
// and approximation formula", eq. 3), for elevations ≥ −0.5° (the formula's own range ends at the
// horizon's refraction; below it the sun is set for this model).
Number airMass(Number sinElevation) {
  Number deg = asin(clamp(sinElevation, Number(-1.0), Number(1.0))) * Number(57.29577951308232);
  return Number(1.0) / (max(sinElevation, Number(0.0)) + Number(0.50572) * pow(max(deg + Number(6.07995), Number(0.1)), Number(-1.6364)));
}

// Analytic clear sky (issue 12 item 2; a full atmosphere is issue 14's): the radiance of a uniform
// sky, per unit solar irradiance E at the top of the atmosphere, whose irradiance on a horizontal
// plane equals the diffuse irradiance of single Rayleigh and aerosol scattering,
//   E_d/E = sin h · [½·(1 − e^{−m·τ_R(λ)}) + f_a·(1 − e^{−m·τ_a(λ)})],   L_sky = E_d/(π·E),
// with m the air mass, τ_R(λ) = 0.0088·λ^{−4.05} (λ in µm; Hansen & Travis 1974 fit, 0.097 at
// 550 nm), τ_a = 0.1·(λ/0.55)^{−1.3} (Ångström: a moderately clear continental sky) and f_a = ¾
// of the aerosol's scattering going downward (its forward peak). Channels at λ = 680, 550, 440 nm.
// Below the horizon the sky fades out over 6° of civil twilight. Blue overhead, weaker and
// whiter towards low sun; ≈ 0.1 of E on the ground at 60° elevation (Bird & Hulstrom 1981 give
// 0.08–0.15 for clear skies).
Vec3 clearSkyRadiance(Number sinElevation) {
  const Vec3 tauRayleigh = Vec3(Number(0.0417), Number(0.0994), Number(0.2447));
  const Vec3 tauAerosol = Vec3(Number(0.0759), Number(0.1000), Number(0.1337));
  Number m = airMass(sinElevation);
  Vec3 scattered = Number(0.5) * (Vec3(Number(1.0)) - exp(-m * tauRayleigh)) +
                   Number(0.75) * (Vec3(Number(1.0)) - exp(-m * tauAerosol));
  // Twilight: the diffuse light of a sun just below the horizon fades to 0 at −6°.
  Number twilight = clamp((sinElevation + Number(0.1045)) / Number(0.1045), Number(0.0), Number(1.0));
  Number height = max(sinElevation, Number(0.0)) + Number(0.02) * twilight;
  return scattered * (height * Number(0.3183098861837907));
}
