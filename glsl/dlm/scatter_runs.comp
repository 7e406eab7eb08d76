#version 450 core
// Deep light map, after pass 2 (issue 19, "Frame time"): the flat runs of the scatter map. One
// invocation per scatter cell column walks its slices back to front and stores, for each slice k,
//   R[k] = the first slice j > k with P_j ≠ P_{j−1}  (u_slices when P stays P_k to the last slice),
// so P is the same on slices k … R[k] − 1. Pass 3 (march.comp) uses it to skip empty space across
// scatter-slice centres where P is flat — above the cloud tops P is 0, and beside a cloud it
// stops changing once the neighbours are clear — instead of stopping at every slice centre.
layout(local_size_x = 8, local_size_y = 8) in;
layout(r32f, binding = IMAGE_SCATTER_MAP) readonly uniform image3D u_scatter_img;
layout(r16i, binding = IMAGE_SCATTER_RUNS) writeonly uniform iimage3D u_runs;
uniform ivec3 u_cells;  // cells.x, cells.y, slices

void main() {
  ivec2 cell = ivec2(gl_GlobalInvocationID.xy);
  if (any(greaterThanEqual(cell, u_cells.xy))) return;
  int next = u_cells.z;
  float P = imageLoad(u_scatter_img, ivec3(cell, u_cells.z - 1)).r;
  for (int k = u_cells.z - 1; k >= 0; --k) {
    imageStore(u_runs, ivec3(cell, k), ivec4(next));
    if (k == 0) break;
    float before = imageLoad(u_scatter_img, ivec3(cell, k - 1)).r;
    if (before != P) next = k;
    P = before;
  }
}
