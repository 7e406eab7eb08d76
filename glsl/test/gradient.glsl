// The known image of the GL foundation tests: an exactly representable value per voxel
// (integers and their scale by GRADIENT_SCALE, a power of two injected as a #define).
#ifndef GRADIENT_SCALE
#define GRADIENT_SCALE 1.0
#endif
vec4 gradientValue(ivec3 v) {
  return vec4(float(v.x), float(v.y), float(v.z), float(v.x + 2 * v.y + 3 * v.z)) * GRADIENT_SCALE;
}
