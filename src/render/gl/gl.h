#pragma once
// Include this (never <GL/gl.h>) to call OpenGL. Every gl* name is a macro for a function pointer
// filled by loadGlFunctions() from the current context's GetProcAddress (cmake/gen_gl_loader.py).
#include "render/gl/gl_functions.h"  // generated: glcorearb.h + nph_gl* pointers + gl* macros

#include <string>

namespace nph::gl {

using GetProcAddressFn = void* (*)(const char* name);

/// Resolves every OpenGL 1.0-4.6 core entry point through `getProc`. Must be called with the
/// context current. Returns the number of entry points that resolved. Throws nph::GlError when a
/// function of GL <= 4.5 core that nephele needs is missing.
int loadGlFunctions(GetProcAddressFn getProc, const std::string& backendName);

}  // namespace nph::gl
