#pragma once
// GLSL sources embedded into the binary at build time (cmake/embed_glsl.py): each stage file of
// glsl/ (.comp .vert .frag .geom) with its #include lines already resolved.
#include <span>
#include <string_view>

namespace nph::gl {

struct EmbeddedShader {
  const char* name;    ///< path relative to glsl/, e.g. "test/gradient3d.comp"
  const char* source;  ///< resolved source, starting with #version
};

std::span<const EmbeddedShader> embeddedShaders();

/// The resolved source of `name`; throws nph::GlError if no such shader was embedded.
std::string_view shaderSource(std::string_view name);

}  // namespace nph::gl
