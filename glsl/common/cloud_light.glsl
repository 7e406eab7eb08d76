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

// Multiple scattering of sunlight by the independent column (issue 12, "two_stream"; Nes 2008
// §5.2.3 names the missing diffuse light as the DLM's limit, Muth 2026 §3.4.6 asks for a
// multiple-scattering term): the sample is taken to lie at optical depth τ_a below the top of a
// horizontally uniform, conservatively scattering slab of optical depth τ* = τ_a + τ_b (its
// column depths, volume/column_depth.h), lit by the sun at μ₀. The Eddington approximation
// I(τ, μ) = I₀(τ) + μ·I₁(τ) with the δ-Eddington scaling of the forward peak (Joseph, Wiscombe &
// Weinman 1976: f = g², τ' = (1 − g²)·τ, g' = g/(1 + g)) — the forward peak stays in the direct
// beam, which is what the deep light map carries (Nes §5.2.3 central/peripheral forward
// scattering), so octave 0 = E·p·I_DLM and this term do not count it twice. For ω = 1 the moment
// equations (τ downward, μ upward, πF = E)
//   dI₁/dτ = −¾F·e^{−τ/μ₀},   dI₀/dτ = (1 − g')·I₁ + ¾F·g'·μ₀·e^{−τ/μ₀}
// give I₁ = ¾Fμ₀·e^{−τ/μ₀} + C₁ and I₀ = (1 − g')·C₁·τ − ¾Fμ₀²·e^{−τ/μ₀} + C₂; Marshak's conditions
// (no diffuse light enters at the top, I₀ − ⅔I₁ = 0, nor at the bottom, I₀ + ⅔I₁ = 0) fix
//   C₁ = −¾Fμ₀·[(μ₀ + ⅔) + (⅔ − μ₀)·e^{−τ*/μ₀}] / ((1 − g')·τ* + 4/3),   C₂ = ¾Fμ₀·(μ₀ + ⅔) + ⅔·C₁.
// Its reflectance is Joseph et al.'s conservative closed form
// R = [(1 − g')τ* + (⅔ − μ₀)(1 − e^{−τ*/μ₀})] / (4/3 + (1 − g')τ*) (tests/lighting). The radiance
// the diffuse field scatters towards a direction of cosine μ_out with the upward vertical is the
// source function of the full phase function p = f·δ + (1 − f)·p' over I₀ + μ·I₁: f·(I₀ + μ_out·I₁)
// + (1 − f)·(I₀ + g'·μ_out·I₁) = I₀ + g·μ_out·I₁ (f + (1 − f)·g' = g): the eye pass marches the
// unscaled β, so the forward peak's share of the diffuse light is scattered on along the view
// ray, not dropped. In a height-exaggerated world the beam is scaled by fluxScale and the vertical
// diffusion (1 − g') by diffusionScale (twoStreamSunFrame below; 1 and 1 at true scale). Returned
// per unit solar irradiance [1/sr]: the eye pass multiplies by E. Costs no look-up beyond the
// column depths the sky light already reads.
Number twoStreamDiffuse(Number tauAbove, Number tauBelow, Number mu0, Number fluxScale, Number diffusionScale,
                        Number muOut, Number g) {
  if (mu0 <= Number(0.0)) return Number(0.0);
  Number m = max(mu0, Number(0.02));  // grazing sun: keep e^{−τ/μ₀} finite; the beam is gone anyway
  Number f = g * g;
  Number gs = g / (Number(1.0) + g);
  Number k = (Number(1.0) - gs) / diffusionScale;
  Number ta = (Number(1.0) - f) * max(tauAbove, Number(0.0));
  Number tt = ta + (Number(1.0) - f) * max(tauBelow, Number(0.0));
  Number F = kInvFourPi * Number(4.0) * fluxScale;  // 1/π: πF = E = 1
  Number beam = exp(-ta / m);
  Number c1 = Number(-0.75) * F * m * ((m + Number(2.0 / 3.0)) + (Number(2.0 / 3.0) - m) * exp(-tt / m)) /
              (k * tt + Number(4.0 / 3.0));
  Number c2 = Number(0.75) * F * m * (m + Number(2.0 / 3.0)) + Number(2.0 / 3.0) * c1;
  Number i0 = k * c1 * ta - Number(0.75) * F * m * m * beam + c2;
  Number i1 = Number(0.75) * F * m * beam + c1;
  return max(i0 + g * muOut * i1, Number(0.0));
}

// The same Eddington column with its three transport constants free (issue 12, thirteenth
// session; docs/accuracy.md "Thirteenth session"): the moment equations (τ' = (1 − g²)τ downward)
//   dI₁/dτ' = −¾F·e^{−τ'/μ₀},   dI₀/dτ' = k·I₁ + ¾F·(K − k)·μ₀·e^{−τ'/μ₀}
// with k the vertical resistance (1 − g')/diffusionScale, K − k the drift of the first-scattered
// light along the beam (twoStreamDiffuse: K = 1; the physical column of the exaggerated world:
// K = 1/diffusionScale, lighting/diffusion_volume.h) and Marshak's conditions with a free
// extrapolation constant b (I₀ ∓ b·I₁ = 0 at the top and the bottom; b = ⅔ for radiance that is
// isotropic in the frame where the layer is measured, (e + 1)/3 for radiance isotropic in the
// exaggerated world, whose mean |vertical cosine| in the data is 1/(e + 1)) give
//   I₁ = ¾Fμ₀·e^{−τ'/μ₀} + C₁,   I₀ = k·C₁·τ' − ¾Fμ₀²K·e^{−τ'/μ₀} + C₂,
//   C₁ = −¾Fμ₀·[μ₀K·(1 − e^{−τ*'/μ₀}) + b·(1 + e^{−τ*'/μ₀})] / (k·τ*' + 2b),
//   C₂ = ¾Fμ₀·(μ₀K + b) + b·C₁;
// twoStreamDiffuse is the case K = 1, b = ⅔. twoStreamColumnMoments returns (I₀, I₁, 0) per unit
// irradiance; twoStreamColumn the source function I₀ + g·μ_out·I₁ [1/sr] (clamped at 0).
Vec3 twoStreamColumnMoments(Number tauAbove, Number tauBelow, Number mu0, Number fluxScale, Number k, Number K,
                            Number b, Number g) {
  if (mu0 <= Number(0.0)) return Vec3(Number(0.0));
  Number m = max(mu0, Number(0.02));
  Number f = g * g;
  Number ta = (Number(1.0) - f) * max(tauAbove, Number(0.0));
  Number tt = ta + (Number(1.0) - f) * max(tauBelow, Number(0.0));
  Number A = Number(0.75) * kInvFourPi * Number(4.0) * fluxScale * m;  // ¾Fμ₀, πF = E = 1
  Number beam = exp(-ta / m);
  Number et = exp(-tt / m);
  Number c1 = -A * (m * K * (Number(1.0) - et) + b * (Number(1.0) + et)) / (k * tt + Number(2.0) * b);
  Number c2 = A * (m * K + b) + b * c1;
  return Vec3(k * c1 * ta - A * m * K * beam + c2, A * beam + c1, Number(0.0));
}

Number twoStreamColumn(Number tauAbove, Number tauBelow, Number mu0, Number fluxScale, Number k, Number K, Number b,
                       Number muOut, Number g) {
  Vec3 moments = twoStreamColumnMoments(tauAbove, tauBelow, mu0, fluxScale, k, K, b, g);
  return max(moments.x + g * muOut * moments.y, Number(0.0));
}

// The sun of the two-stream term in a height-exaggerated world (docs/rendering.md "Conventions":
// heights × e, β × f(d) = |(d_x, d_y, d_z/e)| along d, so vertical optical depth is the data's).
// For a sun of world vertical cosine μ_w (Vec3 result):
//   x = μ₀, the vertical cosine of its image in the data: τ along the beam per vertical τ is 1/μ₀
//       with μ₀ = (μ_w/e) / |(√(1 − μ_w²), μ_w/e)|;
//   y = μ_w/μ₀: horizontal areas are the same in both frames, so the beam brings E·μ_w per unit
//       area and spends it over a vertical depth μ₀ — the slab sees a beam of E·μ_w/μ₀ at μ₀;
//   z = 3⟨(d_z/(e·f(d)))²⟩ over world directions: the vertical diffusion of the scattered light
//       against an unexaggerated medium. Light scattered evenly in the world mostly travels close
//       to the horizontal in the data (a world step d_z covers d_z/e of the data's height), so it
//       crosses the layer's optical depth more slowly: 3∫₀¹ μ²/(e²(1 − μ²) + μ²) dμ =
//       3/(e² − 1)·(a·atanh(1/a) − 1), a = e/√(e² − 1); 1 at e = 1, 0.226 at e = 4, 0.085 at e = 8.
// At e = 1 it is (μ_w, 1, 1). Measured against the path tracer on the accuracy scenes (exaggeration 8
// for the hurricane, 4 for stratus and cirrus): docs/accuracy.md "Issue 12, third phase".
Vec3 twoStreamSunFrame(Number muWorld, Number exaggeration) {
  Number e = max(exaggeration, Number(1.0));
  Number mw = clamp(muWorld, Number(0.0), Number(1.0));
  Number mu0 = (mw / e) / max(sqrt(Number(1.0) - mw * mw + mw * mw / (e * e)), Number(1e-6));
  Number flux = mu0 > Number(0.0) ? mw / mu0 : Number(0.0);
  Number diffusion = Number(1.0);
  if (e > Number(1.0001)) {
    Number a = e / sqrt(e * e - Number(1.0));
    diffusion = Number(3.0) / (e * e - Number(1.0)) * (a * Number(0.5) * log((a + Number(1.0)) / (a - Number(1.0))) - Number(1.0));
  }
  return Vec3(mu0, flux, diffusion);
}

// The forward lobe of the light scattered once (issue 12, thirteenth session; docs/accuracy.md
// "Thirteenth session"): `nephele-bench accuracy --decompose` found the thin cirrus' orders ≥ 2 of
// sunlight at half the truth's (3.7 cone + 1.4 two-stream against 9.6) although their energy is
// there: light scattered forward out of a grazing beam keeps travelling near the sun's direction,
// and an eye 35° off the sun sees it through the phase function's forward lobe. Two places of the
// model throw that lobe's shape away; both are restored here without adding energy:
//   1. The deep light map's cone carries I_DLM − e^{−τ_s} of light scattered within a few degrees
//      of the beam (Nes 2008 §5.2.3), and the eye scattered it with p(ψ; g) as if it were still the
//      beam. Light scattered once by an HG lobe and then by another is spread by their convolution,
//      and HG(g₁) ⊗ HG(g₂) = HG(g₁g₂) exactly (the Legendre moments g₁ⁿ and g₂ⁿ multiply), so it
//      reaches the eye with p(ψ; g²): + (I_DLM − e^{−τ_s})·(p(ψ; g²) − p(ψ; g)).
//   2. The two-stream source I₀ + g·μ_out·I₁ is the azimuthal mean over the vertical: the lobe of the
//      once-scattered light around the (grazing) sun is averaged away. In the small-angle picture
//      the light scattered once out of the δ-scaled beam at slant depth τ_s is (1 − f)·τ_s·e^{−τ_s}
//      (Poisson's first order) with the angular shape of p' = HG(g'), seen by the eye through
//      HG(g'·g); the two-stream keeps its isotropic part 1/(4π): + (1 − f)·τ_s·e^{−τ_s}·(p(ψ; g·g') −
//      1/(4π)), f = g², g' = g/(1 + g) (Joseph, Wiscombe & Weinman 1976).
// τ_s = τ_above/μ₀ is the slant depth of the column to the sun in the data (twoStreamSunFrame's μ₀),
// e^{−τ_s} the direct beam the cone's light is counted above. Both terms integrate to 0 over the
// sphere (HG lobes are normalised); no constant is fitted. Per unit irradiance [1/sr]; the sum
// with single scattering (sunlight·p(ψ; g) ≥ the cone's part) stays ≥ 0 for the cone, and
// cloudSunFactor clamps the total at 0.
Number forwardLobe(Number sunlight, Number cosPsi, Number g, Number tauAbove, Number mu0) {
  if (mu0 <= Number(0.0)) return Number(0.0);
  Number slant = max(tauAbove, Number(0.0)) / max(mu0, Number(0.02));
  Number direct = exp(-slant);
  Number f = g * g;
  Number gs = g / (Number(1.0) + g);
  Number cone = max(sunlight - direct, Number(0.0)) * (hgPhase(cosPsi, f) - hgPhase(cosPsi, g));
  Number firstOrder = (Number(1.0) - f) * slant * direct * (hgPhase(cosPsi, g * gs) - kInvFourPi);
  return cone + firstOrder;
}

// The sunlight a cloud sample scatters towards the eye per unit solar irradiance [1/sr], by the
// multiple-scattering model `mode` (lighting/render_settings.h MultipleScattering, the knob
// `multiple_scattering`): 0 single scattering E·p_v·I_DLM only; 1 the octave series (octaveSeries);
// 2 single scattering plus the independent-column two-stream diffuse light (twoStreamDiffuse) and
// the once-scattered light's forward lobe (forwardLobe, thirteenth session) with g the sample's
// β-weighted asymmetry, the sample's column depths (τ_above, τ_below), the sun frame
// of twoStreamSunFrame and the view's vertical cosine μ_out (towards the eye, in the data); 3 (the
// Monte Carlo radiance volume, sixteenth session) single scattering plus the forward lobe only: the
// caller adds the volume's orders ≥ 2, max(J, 0) (glsl/common/radiance_volume.glsl; on the CPU
// reference::McRadianceVolume::radianceAt), as the CPU row "orders ≥ 2 + DLM single +
// forwardLobe" of docs/accuracy.md "Fifteenth session" counts them: the map carries the cone of
// order 2, the volume everything scattered twice or more, its cone included, but the cone's share
// of order 2 is small on the accuracy scenes (0.0774 against 0.0770 with the exact beam).
Number cloudSunFactor(int mode, Number sunlight, Number cosPsi, Number iceWeight, Number gIce, Number gWater,
                      int octaves, Number extinctionScale, Number energyScale, Number anisotropyScale,
                      Number tauAbove, Number tauBelow, Vec3 sunFrame, Number muOut) {
  if (mode == 1)
    return octaveSeries(sunlight, cosPsi, iceWeight, gIce, gWater, octaves, extinctionScale, energyScale,
                        anisotropyScale);
  Number single = sunlight * mixedPhase(cosPsi, iceWeight, gIce, gWater);
  if (mode != 2 && mode != 3) return single;
  Number g = gWater + (gIce - gWater) * iceWeight;
  Number diffuse =
      mode == 2 ? twoStreamDiffuse(tauAbove, tauBelow, sunFrame.x, sunFrame.y, sunFrame.z, muOut, g) : Number(0.0);
#ifndef NO_FORWARD_LOBE  // benchmark baseline (render::EyePassBaseline::no_forward_lobe)
  diffuse += forwardLobe(sunlight, cosPsi, g, tauAbove, sunFrame.x);
#endif
  return max(single + diffuse, Number(0.0));
}

// Diffuse (hemispherically incident) transmittance of a conservatively scattering layer of
// optical depth τ, two-stream (Eddington) approximation with the (1 − g) similarity scaling (Bohren
// 1987, "Multiple scattering of light and some of its observable consequences"; van de Hulst 1980):
// T_d = 1 / (1 + ¾·(1 − g)·τ). It carries the sky light down to the ground under a cloud
// (clouds.comp; inside the cloud skyDiffuse below replaced it in the twelfth session). Exact at
// τ = 0 and ∝ 1/((1 − g)·τ) for thick layers like the diffusion limit 4/(3(1 − g)(τ + 1.42))
// (van de Hulst), which it undershoots by ≈ 25 % at τ = 20, g = 0.85: the sky term is a model,
// the octave fit against the path tracer absorbs what it misses (docs/accuracy.md).
Number diffuseTransmittance(Number tau, Number g) {
  return Number(1.0) / (Number(1.0) + Number(0.75) * (Number(1.0) - g) * max(tau, Number(0.0)));
}

// Sky light inside a cloud column (issue 12, twelfth session: `nephele-bench accuracy --decompose`
// found the former ½·(L_above·T_d(τ_up) + L_below·T_d(τ_down)) 32 % under the path tracer's sky
// light on the hurricane: it lets the sky through the column but forgets that the cloud reflects
// what it does not let through, so a non-absorbing cloud in a uniform sky came out grey instead of
// uniform — the white furnace failed). The mean radiance I₀ of the same Eddington slab as
// twoStreamDiffuse, lit by isotropic diffuse radiance L_above from above and L_below from below: with
// ω = 1 the moment equations give I₁ constant and I₀ linear in τ,
//   dI₀/dτ = −(1 − g)·I₁ (τ downward, I₁ the net downward moment),
// and Marshak's conditions (I₀ + ⅔I₁ = L_above at the top, I₀ − ⅔I₁ = L_below at the bottom) give
//   I₀(τ_up) = [L_above·(⅔ + k·τ_down) + L_below·(⅔ + k·τ_up)] / (4/3 + k·(τ_up + τ_down)),
// k = (1 − g)/diffusionScale (twoStreamSunFrame's vertical diffusion under height exaggeration,
// 1 at true scale). Uniform sky (L_above = L_below = L): I₀ = L at every depth, exactly (white
// furnace). Black below: the cloud's top sends ≈ L_above (its reflectance → 1), its base
// ½·L_above·T_d(τ*) as before. Thin cloud: ½·(L_above + L_below), as before. The sample scatters I₀
// (the isotropic part: the first-moment term g·μ·I₁ would go negative for thin clouds seen from
// the sunny side, where the Eddington phase is poor).
Vec3 skyDiffuse(Number tauAbove, Number tauBelow, Number g, Number diffusionScale, Vec3 above, Vec3 below) {
  Number k = (Number(1.0) - g) / max(diffusionScale, Number(1e-6));
  Number ta = k * max(tauAbove, Number(0.0));
  Number tb = k * max(tauBelow, Number(0.0));
  return (above * (Number(2.0 / 3.0) + tb) + below * (Number(2.0 / 3.0) + ta)) / (Number(4.0 / 3.0) + ta + tb);
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
