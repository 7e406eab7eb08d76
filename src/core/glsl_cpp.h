#pragma once
// Compiling the shared GLSL library as C++ (issue #17 item 4; STYLE.md 3, after Bruneton 2017:
// reference/definitions.h maps the GLSL types so that reference/functions.cc can #include the very
// functions.glsl the shaders run). A CPU twin of a shader function is never a hand-kept copy: it
// includes the same file of glsl/ — as "../glsl/<file>", relative to src/, the include root of
// every module — inside a namespace that opens with this prelude, e.g.
//
//   namespace nph::scene::display::f32 {
//   using namespace nph::glsl;
//   using Number = float;
//   #include "../glsl/common/display.glsl"
//   }
//
// in one .cpp file (scene/display_transform.cpp), with a header declaring the functions it uses.
//
// The subset such a file may use: scalar and glm vector types, the built-ins listed below (GLM
// and <cmath> implement them with GLSL's semantics for finite input), `const` globals, and
// functions without `in`/`out` qualifiers. It must not depend on uniforms, textures or #version;
// GLSL-only lines go under `#ifndef NPH_GLSL_AS_CPP`.
#include <cmath>

#include <glm/glm.hpp>

#define NPH_GLSL_AS_CPP 1

namespace nph::glsl {

using glm::bvec2, glm::bvec3, glm::ivec2, glm::ivec3, glm::ivec4, glm::uvec2, glm::uvec3, glm::vec2, glm::vec3,
    glm::vec4;
using glm::clamp, glm::dot, glm::floor, glm::length, glm::max, glm::min, glm::mix, glm::normalize, glm::smoothstep;
using uint = unsigned int;  // GLSL's 32-bit unsigned type (integer hashes, glsl/common/noise.glsl)
using glm::exp;
using std::asin, std::exp, std::log, std::log2, std::pow, std::sqrt;

}  // namespace nph::glsl
