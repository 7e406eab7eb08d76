// Named constants shared by the passes (issue #17 item 4; STYLE.md: no magic number without a
// name and a source). Plain GLSL: a pass includes it before the library files that use it.

// π to the precision a float holds (the former literal of clouds.comp and globe.glsl).
const float kPi = 3.14159265358979;

// "No hit" distance along a ray [m]: a ray that misses a sphere or the ground gets this, larger
// than any distance in a scene yet finite, so min/max and comparisons stay ordinary.
const float kNoHit_m = 3.0e38;
// Distance to the host's opaque geometry where the host has none: the largest finite float
// (FLT_MAX ≈ 3.40282e38, rounded down), beyond kNoHit_m so a missed ray is never clipped by it.
const float kNoHostGeometry_m = 3.4e38;
// "Never" for slab and brick exits [m]: beyond every scene (the Earth's diameter is 1.3e7 m) but
// far below kNoHit_m, so sums of it with scene distances stay finite.
const float kNeverExit_m = 1e30;
