#version 450 core
// Resolve of the Monte Carlo radiance volume (issue 12, sixteenth session; glsl/dlm/
// radiance_volume.comp writes the tallies): one invocation per coarse cell turns its 25 fixed-point
// sums (64-bit two's complement as (low, high) words) into the moments c_lm = ∫ L Y_lm dω per unit
// irradiance, c = sum·q·P/V (q the fixed-point quantum, P = A_proj/N the power per photon, V the
// cell's world volume: u_scale), and stores them in seven RGBA32F 3-D textures, moment k in
// texture k/4, channel k mod 4 (the 28th–25th channels are 0), so the eye pass fetches them with
// hardware trilinear filtering between the cell centres (GL_LINEAR, GL_CLAMP_TO_EDGE: the CPU
// twin's McRadianceVolume::momentsAt clamps to the edge cells the same way). The sum is converted
// in double: the 64-bit total exceeds float's 24 bits long before it loses meaning.
layout(local_size_x = 4, local_size_y = 4, local_size_z = 4) in;

layout(std430, binding = SSBO_MC_TALLY) readonly buffer McTally {
  uint words[];
};
layout(rgba32f, binding = IMAGE_MC_MOMENTS) uniform writeonly image3D u_moments[7];

uniform ivec3 u_cells;
uniform float u_scale;  // q·P/V

float momentOf(uint m) {
  double v = double(int(words[2u * m + 1u])) * 4294967296.0LF + double(words[2u * m]);
  return float(v * double(u_scale));
}

void main() {
  ivec3 c = ivec3(gl_GlobalInvocationID);
  if (any(greaterThanEqual(c, u_cells))) return;
  uint base = uint((c.z * u_cells.y + c.y) * u_cells.x + c.x) * 25u;
  for (int t = 0; t < 7; ++t) {
    vec4 v = vec4(0.0);
    for (int ch = 0; ch < 4; ++ch) {
      int k = 4 * t + ch;
      if (k < 25) v[ch] = momentOf(base + uint(k));
    }
    imageStore(u_moments[t], c, v);
  }
}
