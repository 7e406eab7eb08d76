/* A host's GL: an OSMesa 4.5 core context made current on a static RGBA8 buffer (the C API's
 * measurement programs, api_overhead.c and api_soak.c). Returns NULL when Mesa cannot give one. */
#ifndef NEPHELE_TESTS_API_OSMESA_HOST_H
#define NEPHELE_TESTS_API_OSMESA_HOST_H
#include <GL/osmesa.h>

static OSMesaContext osmesa_host_context(unsigned char* pixels, int width, int height) {
  const int attribs[] = {OSMESA_FORMAT,
                         OSMESA_RGBA,
                         OSMESA_PROFILE,
                         OSMESA_CORE_PROFILE,
                         OSMESA_CONTEXT_MAJOR_VERSION,
                         4,
                         OSMESA_CONTEXT_MINOR_VERSION,
                         5,
                         0};
  OSMesaContext ctx = OSMesaCreateContextAttribs(attribs, NULL);
  if (ctx != NULL && !OSMesaMakeCurrent(ctx, pixels, GL_UNSIGNED_BYTE, width, height)) {
    OSMesaDestroyContext(ctx);
    return NULL;
  }
  return ctx;
}

#endif
