// Grid helpers shared by the passes.

// Texture coordinate of the centre of voxel `voxel` in a grid of `size` voxels.
vec3 voxelCentreUvw(ivec3 voxel, ivec3 size) {
  return (vec3(voxel) + 0.5) / vec3(size);
}

// true when `voxel` lies inside a grid of `size` voxels.
bool insideGrid(ivec3 voxel, ivec3 size) {
  return all(greaterThanEqual(voxel, ivec3(0))) && all(lessThan(voxel, size));
}
