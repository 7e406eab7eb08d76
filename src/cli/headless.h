#pragma once
// The headless GL context of the render, animate and bench subcommands, from their --gl option.
#include <memory>
#include <string>

#include "render/gl/context.h"

namespace nph::cli {

/// "auto" (NEPHELE_GL or EGL, then OSMesa), "egl" or "osmesa"; UsageError for anything else.
std::unique_ptr<gl::Context> createHeadlessContext(const std::string& gl_option);

}  // namespace nph::cli
