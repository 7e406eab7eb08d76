/* 02-batch-osmesa: the smallest complete host of the nephele C API. It owns an OSMesa context
 * (software OpenGL 4.5 core), renders N frames of a dataset through nph_get_api and writes them
 * as binary PPM files — clouds over the lit ground, display-transformed like `nephele render`.
 *
 *   batch_osmesa DATASET OUT_PREFIX [FRAMES [WIDTH HEIGHT]]
 *
 * The frames sweep the dataset's timesteps (fractional times in between are blended). */
#include <GL/osmesa.h>
#include <stdio.h>
#include <stdlib.h>

#include <nephele/nephele.h>

static const nph_api_v1* api;

/* Prints the last error of `handle` and exits. */
static void check(nph_status s, const void* handle, const char* what) {
  if (s != NPH_OK) {
    fprintf(stderr, "%s: %s: %s\n", what, api->status_name(s), api->last_error(handle));
    exit(1);
  }
}

/* OSMesa's buffer has row 0 at the bottom (OSMESA_Y_UP); PPM wants the top row first. */
static int write_ppm(const char* path, const unsigned char* rgba, int w, int h) {
  FILE* f = fopen(path, "wb");
  if (f == NULL) return 0;
  fprintf(f, "P6\n%d %d\n255\n", w, h);
  for (int y = h - 1; y >= 0; --y) {
    for (int x = 0; x < w; ++x) fwrite(rgba + 4 * ((size_t)y * (size_t)w + (size_t)x), 1, 3, f);
  }
  return fclose(f) == 0;
}

int main(int argc, char** argv) {
  if (argc < 3) {
    fprintf(stderr, "usage: %s DATASET OUT_PREFIX [FRAMES [WIDTH HEIGHT]]\n", argv[0]);
    return 2;
  }
  const int frames = argc > 3 ? atoi(argv[3]) : 4;
  const int w = argc > 5 ? atoi(argv[4]) : 320, h = argc > 5 ? atoi(argv[5]) : 180;
  if (frames < 1 || w < 1 || h < 1) return 2;

  api = (const nph_api_v1*)nph_get_api(NPH_API_VERSION);
  if (api == NULL) {
    fprintf(stderr, "libnephele has no API version %u\n", NPH_API_VERSION);
    return 1;
  }

  /* The host's context: OpenGL 4.5 core on OSMesa, drawing into `pixels`. */
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
  unsigned char* pixels = malloc((size_t)w * (size_t)h * 4);
  if (ctx == NULL || pixels == NULL || !OSMesaMakeCurrent(ctx, pixels, GL_UNSIGNED_BYTE, w, h)) {
    fprintf(stderr, "no OSMesa OpenGL 4.5 core context\n");
    return 1;
  }

  nph_dataset* ds = NULL;
  nph_renderer* r = NULL;
  int32_t timesteps = 0;
  check(api->dataset_open(argv[1], &ds), NULL, "dataset_open");
  check(api->dataset_timestep_count(ds, &timesteps), ds, "dataset_timestep_count");
  nph_renderer_desc desc = NPH_RENDERER_DESC_INIT;
  desc.get_proc_address = (nph_get_proc_address_fn)OSMesaGetProcAddress;
  desc.quality_preset = "draft";
  check(api->renderer_create(ds, &desc, &r), ds, "renderer_create");
  check(api->set_camera_preset(r, "oblique", w, h), r, "set_camera_preset");
  check(api->set_sun(r, 135.0, 35.0), r, "set_sun");
  check(api->set_parameter(r, "ground", 1), r, "set_parameter ground");
  check(api->set_parameter(r, "display_transform", 1), r, "set_parameter display_transform");

  for (int i = 0; i < frames; ++i) {
    const double t = frames > 1 ? (double)(timesteps - 1) * i / (frames - 1) : 0.0;
    check(api->set_time(r, t), r, "set_time");
    glViewport(0, 0, w, h); /* the API composites over the viewport of the bound framebuffer */
    glClearColor(0.0f, 0.0f, 0.0f, 1.0f);
    glClear(GL_COLOR_BUFFER_BIT);
    check(api->render(r), r, "render");
    glFinish();
    nph_stats st;
    st.struct_size = sizeof st;
    check(api->get_stats(r, &st), r, "get_stats");
    char path[4096];
    snprintf(path, sizeof path, "%s%03d.ppm", argv[2], i);
    if (!write_ppm(path, pixels, w, h)) {
      fprintf(stderr, "%s: cannot write\n", path);
      return 1;
    }
    printf("%s: time %.2f, DLM %s, %.0f ms\n", path, t, st.dlm_rebuilt ? "rebuilt" : "reused", st.total_ms);
  }

  check(api->renderer_destroy(r), r, "renderer_destroy");
  check(api->dataset_close(ds), ds, "dataset_close");
  OSMesaDestroyContext(ctx);
  free(pixels);
  return 0;
}
