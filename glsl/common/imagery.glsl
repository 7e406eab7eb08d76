// Filtering of the ground's imagery (issue 14 item 3): the basemaps are mipmapped, and every look-up
// is given the pixel's footprint in texture coordinates (compute shaders have no implicit
// derivatives: glsl/render/clouds.comp transfers ray differentials to the ground, Igehy 1999).
// Requires nothing.

// A texture gradient (in texture coordinates) no longer than a quarter of the texture (its 4×4
// level): rays grazing the ground at the horizon or the globe's limb have near-infinite footprints.
vec2 footprintClamped(vec2 g) {
  float l = length(g);
  return l > 0.25 ? g * (0.25 / l) : g;
}

// Anisotropic filtering spelt out in the shader, as EXT_texture_filter_anisotropic's specification
// describes the filter: the pixel's footprint is the parallelogram of the gradients dUvDx, dUvDy
// (texture coordinates per pixel, each clamped by footprintClamped); N = ⌈P_max/P_min⌉ ≤ 16
// trilinear taps, equally weighted, spread along the major axis over the footprint's length, each
// at the mipmap level of P_max/N texels (P the axes' lengths in texels of level 0).
// Why not the sampler's own GL_TEXTURE_MAX_ANISOTROPY: Mesa 22.3's llvmpipe returned texels from
// elsewhere in the texture for strongly elongated footprints — specks of wrong colour along the
// globe's limb (tests/golden globe frames, max 0.10 against 0.015 allowed), gone with the
// anisotropy at 1; the taps here give the same filter on every driver. The texture must have a
// full mipmap chain with GL_LINEAR_MIPMAP_LINEAR and an anisotropy of 1.
const int kMaxAnisotropicTaps = 16;
vec4 textureAnisotropic(sampler2D tex, vec2 uv, vec2 dUvDx, vec2 dUvDy) {
  vec2 size = vec2(textureSize(tex, 0));
  float lx = length(dUvDx * size), ly = length(dUvDy * size);  // the axes' lengths in texels
  vec2 major = lx >= ly ? dUvDx : dUvDy;
  float pMax = max(lx, ly), pMin = min(lx, ly);
  int taps = int(min(ceil(pMax / max(pMin, 1e-6)), float(kMaxAnisotropicTaps)));
  taps = max(taps, 1);
  float lod = log2(max(pMax / float(taps), 1e-6));  // below 0: magnified, level 0
  vec4 sum = vec4(0.0);
  for (int i = 0; i < taps; ++i) {
    sum += textureLod(tex, uv + major * ((float(i) + 0.5) / float(taps) - 0.5), lod);
  }
  return sum / float(taps);
}
