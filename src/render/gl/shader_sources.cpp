#include "render/gl/shader_sources.h"

#include <string>

#include "core/error.h"

namespace nph::gl {

std::string_view shaderSource(std::string_view name) {
  for (const auto& s : embeddedShaders()) {
    if (name == s.name) return s.source;
  }
  throw GlError("no embedded shader named '" + std::string(name) + "' (shaders live in glsl/)");
}

}  // namespace nph::gl
