// LD_PRELOAD shim for tracing LeakSanitizer reports from an `<unknown module>` (docs/reliability.md,
// "The glfw-xvfb leak report"): every dlclose prints the library's name and the executable ranges
// of /proc/self/maps before the real dlclose unmaps it, so a frame address in the report can be
// mapped back to its library. Build: cc -shared -fPIC -O1 -o /tmp/dlclose_log.so tools/dlclose_log.c -ldl
#define _GNU_SOURCE
#include <dlfcn.h>
#include <link.h>
#include <stdio.h>
#include <string.h>

int dlclose(void* handle) {
  static int (*real)(void*) = 0;
  if (!real) real = (int (*)(void*))dlsym(RTLD_NEXT, "dlclose");
  struct link_map* lm = 0;
  if (dlinfo(handle, RTLD_DI_LINKMAP, &lm) == 0 && lm) {
    fprintf(stderr, "dlclose-log: %s base=%p\n", lm->l_name, (void*)lm->l_addr);
    FILE* f = fopen("/proc/self/maps", "r");
    char line[512];
    while (f && fgets(line, sizeof line, f))
      if (strstr(line, "r-xp")) fprintf(stderr, "dlclose-log:   %s", line);
    if (f) fclose(f);
  }
  return real(handle);
}
