#version 450 core
// Light cache (issue 19, "Frame time", item 1b): the deep light map's sunlight baked into a
// world-space volume whenever the map is (re)built, so that the eye pass reads it with one
// trilinear fetch per sample instead of the four-texel node-list look-up of glsl/dlm/lookup.glsl
// (Nes 2008 §5.4.2 evaluates the map per sample; the issue measured that look-up as most of the
// ray cast's cost on llvmpipe, 1 090 M table reads against 95 M volume fetches per demo frame).
// The cache spans the extinction volume's box (glsl/dlm/volume.glsl u_box_min_m, u_box_size_m)
// with u_cache_texels texels; texel i holds I_DLM at the world point
//   box_min + (i + ½) / texels · box_size,
// the same centre convention as the extinction textures, so texture(u_light_cache,
// volumeUvw(world)) with GL_LINEAR and GL_CLAMP_TO_EDGE interpolates between baked centres (and
// holds the edge value in the filter's pad outside the box). Stored as R16F: I ∈ [0, 1] keeps
// 11 significant bits, a relative step of 2⁻¹¹ ≈ 5e-4 (≪ the map's own ε = 0.01).
// The error against the direct look-up is the interpolation of I between the cache's centres;
// it is measured per cache resolution in tests/render/frame_time_gl_test.cpp and
// tests/bench/frame_benchmark.cpp (docs/benchmarks.md).
#include "dlm/volume.glsl"
#include "dlm/light_space.glsl"
#include "dlm/lookup.glsl"

layout(local_size_x = 4, local_size_y = 4, local_size_z = 4) in;
layout(r16f, binding = IMAGE_LIGHT_CACHE) uniform writeonly image3D u_light_cache_img;
uniform ivec3 u_cache_texels;

void main() {
  ivec3 i = ivec3(gl_GlobalInvocationID);
  if (any(greaterThanEqual(i, u_cache_texels))) return;
  vec3 world_m = u_box_min_m + (vec3(i) + 0.5) / vec3(u_cache_texels) * u_box_size_m;
  imageStore(u_light_cache_img, i, vec4(dlmIntensity(world_m)));
}
