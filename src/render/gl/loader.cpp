#include "render/gl/gl.h"

#include <cstring>
#include <string>

#include "core/error.h"
#include "core/log.h"

namespace nph::gl::detail {
struct GlFunctionEntry {
  const char* name;
  const char* version;
  void** slot;
};
extern const GlFunctionEntry kGlFunctions[];
extern const int kGlFunctionCount;
}  // namespace nph::gl::detail

namespace nph::gl {

int loadGlFunctions(GetProcAddressFn getProc, const std::string& backendName) {
  int resolved = 0;
  std::string missing45;
  for (int i = 0; i < detail::kGlFunctionCount; ++i) {
    const auto& f = detail::kGlFunctions[i];
    *f.slot = getProc(f.name);
    if (*f.slot != nullptr) {
      ++resolved;
    } else if (std::strcmp(f.version, "GL_VERSION_4_6") != 0) {
      if (!missing45.empty()) missing45 += ", ";
      missing45 += f.name;
    }
  }
  if (!missing45.empty()) {
    throw GlError("OpenGL loader (" + backendName +
                  "): entry points of GL <= 4.5 core are missing: " + missing45.substr(0, 400));
  }
  log::debug("OpenGL loader ({}): {} of {} entry points resolved", backendName, resolved, detail::kGlFunctionCount);
  return resolved;
}

}  // namespace nph::gl
