// Ground detail at storm scale (issue 14, fourteenth session): a synthesised tint of the draped
// imagery from the terrain's own height and slope, at the height field's resolution (a DEM's ~1 km
// lattice: glsl/common/terrain.glsl) where the basemap has ~15 km pixels (Blue Marble). Synthesis,
// not data: off by default (style knob ground_tint; docs/terrain.md "Ground detail"), so that a
// meteorologist's ground is the imagery as it is. Nes 2008 §5.5 drapes Blue Marble and names its
// resolution as the limit at storm scale; Thomann 2021 §5.3 colours WRF's HGT mesh by height.
//
// Two covers, each a fraction of the surface, blended over the imagery by area (a pixel that is
// a fraction s snow is s·ρ_snow + (1 − s)·ρ_imagery; the imagery keeps the rest, so its colour
// still shows through and where it is already white the snow changes little):
//   - snow above the snow line h_s, a 600 m transition, and not on slopes steeper than ~45° (the
//     repose angle of snow: it slides off steep rock faces, which stay dark in winter photographs of
//     the Alps); broadband albedo of old snow and firn 0.6–0.8 (Cuffey & Paterson 2010, table 5.2):
//     ρ_snow = (0.78, 0.80, 0.83), bluer in blue as snow is;
//   - bare rock on slopes of 30–45° and steeper (scree and cliffs carry no vegetation), albedo of
//     granite and limestone 0.2–0.3: ρ_rock = (0.26, 0.24, 0.22).
// The slopes are the TRUE slopes: the shaded normal is the exaggerated surface's (terrain.glsl's
// "z-factor"), so tan θ_true = tan θ_drawn / e; the heights are true heights (world z / e).
const vec3 kSnowAlbedo = vec3(0.78, 0.80, 0.83);
const vec3 kRockAlbedo = vec3(0.26, 0.24, 0.22);
const float kSnowTransition_m = 600.0;  // snow cover from 0 to full over h_s ± 300 m
const float kSnowMaxCover = 0.95;       // a little of the imagery stays even on full snow
const float kRockMaxCover = 0.7;        // sparse vegetation and debris on steep ground
const float kTanSnowSlides = 1.0;       // 45°: snow slides off
const float kTanSnowHolds = 0.70;       // 35°: snow holds
const float kTanRockFrom = 0.58;        // 30°: rock starts to show
const float kTanRockFull = 1.0;         // 45°: bare rock

// The imagery's albedo with snow and rock covers at true height `height_m` on a surface whose
// drawn (exaggerated) normal makes cosine `cosDrawnSlope` with the local vertical, exaggeration e.
vec3 groundTint(vec3 albedo, float height_m, float cosDrawnSlope, float exaggeration, float snowLine_m) {
  float c = clamp(cosDrawnSlope, 1e-4, 1.0);
  float tanTrue = sqrt(max(1.0 - c * c, 0.0)) / c / max(exaggeration, 1e-6);
  float rock = kRockMaxCover * smoothstep(kTanRockFrom, kTanRockFull, tanTrue);
  float snow = kSnowMaxCover * smoothstep(snowLine_m - 0.5 * kSnowTransition_m, snowLine_m + 0.5 * kSnowTransition_m,
                                          height_m) *
               (1.0 - smoothstep(kTanSnowHolds, kTanSnowSlides, tanTrue));
  // Rock where there is no snow: the covers share the surface.
  vec3 covered = mix(albedo, kRockAlbedo, rock);
  return mix(covered, kSnowAlbedo, snow);
}
