#pragma once
// KHR_debug output routed to nephele's log, and GL error checking.
//
// Every context gets a synchronous debug callback. Messages of type GL_DEBUG_TYPE_ERROR are
// recorded per thread; checkErrors() throws nph::GlError naming them (and anything glGetError
// reports). In strict mode — the default in debug builds, or NEPHELE_GL_DEBUG=strict — the callback
// logs the error and aborts on the spot, so a GL error in a debug build fails loudly at the call
// that caused it (run under gdb for the stack).
#include <string>
#include <string_view>

namespace nph::gl {

/// Enables KHR_debug output into the log (`verbose` also logs notifications). Called by Context.
void installDebugOutput(bool verbose);

/// True in debug builds (no NDEBUG) unless NEPHELE_GL_DEBUG says otherwise, and whenever
/// NEPHELE_GL_DEBUG=strict: the default of strict errors and of strict uniforms (program.h).
bool strictByDefault();

/// Strict mode: abort() on the first GL error. See above for the default.
void setStrictErrors(bool strict);
bool strictErrors();

/// Throws nph::GlError("<where>: ...") if GL errors were recorded since the last call.
void checkErrors(std::string_view where);

/// Removes and returns the recorded error text (empty if none); does not throw.
std::string takeErrors();

/// RAII debug group (glPushDebugGroup/glPopDebugGroup): names the passes in captures and logs.
class DebugGroup {
 public:
  explicit DebugGroup(std::string_view name);
  ~DebugGroup();
  DebugGroup(const DebugGroup&) = delete;
  DebugGroup& operator=(const DebugGroup&) = delete;
};

}  // namespace nph::gl
