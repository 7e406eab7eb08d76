// The deep light map's light space (lighting/light_space.h): orthonormal u, v and w = the direction
// the sunlight travels; texel (a, b) owns the ray origin + (a+½)·du·u + (b+½)·dv·v + s·w.
// One std140 block, declared in C++ as gl::LightSpaceBlock (render/gl/uniform_blocks.h): keep the
// members in its order; the GL test UniformBlocks.MatchTheLinkedPrograms checks every offset.
layout(std140, binding = UBO_LIGHT_SPACE) uniform LightSpaceBlock {
  vec3 u_ls_origin_m;
  float u_ls_depth_m;
  vec3 u_ls_u;
  vec3 u_ls_v;
  vec3 u_ls_w;         // the direction the sunlight travels
  vec2 u_ls_texel_m;   // du, dv
  ivec2 u_ls_texels;   // nu, nv
};

vec3 lightFromWorld(vec3 world_m) {
  vec3 d = world_m - u_ls_origin_m;
  return vec3(dot(d, u_ls_u), dot(d, u_ls_v), dot(d, u_ls_w));
}

vec3 worldFromLight(vec3 l) { return u_ls_origin_m + l.x * u_ls_u + l.y * u_ls_v + l.z * u_ls_w; }
