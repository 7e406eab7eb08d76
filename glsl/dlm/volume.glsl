// Extinction volumes (Nes 2008 §5.2.1): ice and water β_ext [1/m] as 3-D textures, sampled
// trilinearly between voxel centres with zero outside the grid (GL_LINEAR, GL_CLAMP_TO_BORDER,
// border 0) — the same rule as volume/extinction_sampler.cpp on the CPU. β is continuous
// everywhere: it fades to 0 over the half voxel outside the box instead of jumping at the face,
// so a ray skimming a face cannot flip between "cloud" and "clear" on float rounding.
#include "common/math.glsl"
#include "common/ray_box.glsl"
layout(binding = UNIT_ICE_PER_M) uniform sampler3D u_ice_per_m;
layout(binding = UNIT_WATER_PER_M) uniform sampler3D u_water_per_m;
layout(binding = UNIT_OCCUPANCY_PER_M) uniform sampler3D u_occupancy_per_m;  // per brick: max β (dilated by one voxel)
// One std140 block, declared in C++ as gl::VolumeBlock (render/gl/uniform_blocks.h): keep the
// members in its order; the GL test UniformBlocks.MatchTheLinkedPrograms checks every offset.
layout(std140, binding = UBO_VOLUME) uniform VolumeBlock {
  vec3 u_box_min_m;      // world AABB of the volume
  int u_brick_voxels;
  vec3 u_box_size_m;
  bool u_has_ice;        // absent phases are never fetched
  ivec3 u_voxels;
  bool u_has_water;
};

vec3 volumeUvw(vec3 world_m) { return (world_m - u_box_min_m) / u_box_size_m; }

bool insideVolume(vec3 uvw) { return all(greaterThanEqual(uvw, vec3(0.0))) && all(lessThanEqual(uvw, vec3(1.0))); }

// The volume box grown by one voxel: β is exactly 0 beyond it.
bool insideGrownVolume(vec3 uvw) {
  vec3 pad = 1.0 / vec3(u_voxels);
  return all(greaterThanEqual(uvw, -pad)) && all(lessThanEqual(uvw, 1.0 + pad));
}


// (β_ice, β_water) at a world position.
vec2 extinctionAt(vec3 world_m) {
  vec3 uvw = volumeUvw(world_m);
  if (!insideGrownVolume(uvw)) return vec2(0.0);
  return vec2(u_has_ice ? texture(u_ice_per_m, uvw).r : 0.0, u_has_water ? texture(u_water_per_m, uvw).r : 0.0);
}

// Max β of the occupancy brick containing `world_m`; in the one-voxel shell around the box, that of
// the nearest edge brick (whose dilated max bounds the fading shell); 0 beyond the shell.
float brickMaxAt(vec3 world_m) {
  vec3 uvw = volumeUvw(world_m);
  if (!insideGrownVolume(uvw)) return 0.0;
  ivec3 voxel = clamp(ivec3(floor(uvw * vec3(u_voxels))), ivec3(0), u_voxels - 1);
  return texelFetch(u_occupancy_per_m, voxel / u_brick_voxels, 0).r;
}

// Distance along `dir` from `world_m` (inside the volume) to the exit of its occupancy brick.
float brickExitDistance(vec3 world_m, vec3 dir) {
  vec3 voxelSize = u_box_size_m / vec3(u_voxels);
  vec3 brickSize = voxelSize * float(u_brick_voxels);
  vec3 rel = world_m - u_box_min_m;
  vec3 brickMin = floor(rel / brickSize) * brickSize;
  vec3 brickMax = min(brickMin + brickSize, u_box_size_m);
  vec3 safeDir = safeDirection(dir);
  vec3 t = mix((brickMin - rel) / safeDir, (brickMax - rel) / safeDir, greaterThan(dir, vec3(0.0)));
  t = mix(t, vec3(kNeverExit_m), equal(dir, vec3(0.0)));
  return max(min(t.x, min(t.y, t.z)), 0.0);
}

// Distance along `dir` over which a ray from `world_m` stays in empty space, given that the
// occupancy at `world_m` is 0: to the exit of its brick inside the volume; 0 in the one-voxel
// shell (no skipping there); beyond the shell, to the grown box's entry (kNeverExit_m when missed).
float emptySkipDistance(vec3 world_m, vec3 dir) {
  vec3 uvw = volumeUvw(world_m);
  if (insideVolume(uvw)) return brickExitDistance(world_m, dir);
  if (insideGrownVolume(uvw)) return 0.0;
  vec3 pad = u_box_size_m / vec3(u_voxels);
  vec3 safeDir = safeDirection(dir);
  vec2 t = slabInterval((u_box_min_m - pad - world_m) / safeDir, (u_box_min_m + u_box_size_m + pad - world_m) / safeDir);
  if (t.y < max(t.x, 0.0)) return kNeverExit_m;
  return max(t.x, 0.0);
}
