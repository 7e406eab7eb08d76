/* Soak of the C API (issue 18): many frames through one host context, and renderers created and
 * destroyed in it, watching the process's resident memory.
 *
 * usage: nephele_api_soak DATASET FRAMES [MAX_GROWTH_MB]
 * Each frame moves the clock (a fractional timestep: a blended volume), the sun (the deep light
 * map is rebuilt, 32 texels across) and the camera, and renders 96x54 on OSMesa; every 100th frame the renderer is
 * destroyed and a new one created (textures, programs, buffers of a whole renderer). VmRSS is
 * sampled after every 50th frame and printed. The warm-up is the first 20 % of the frames (at
 * least 100): Mesa's shader cache, the allocator's pools and the timestep cache fill there. With
 * MAX_GROWTH_MB the program exits 1 when RSS grows by more than that from the end of the warm-up
 * to the last frame. Memory, not time: nothing here depends on how fast the machine is. */
#include <GL/osmesa.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "nephele/nephele.h"
#include "osmesa_host.h"

static double rss_mb(void) {
  FILE* f = fopen("/proc/self/status", "r");
  char line[256];
  double kb = -1.0;
  while (f != NULL && fgets(line, sizeof line, f) != NULL) {
    if (strncmp(line, "VmRSS:", 6) == 0) kb = atof(line + 6);
  }
  if (f != NULL) fclose(f);
  return kb / 1024.0;
}

static nph_renderer* create(const nph_api_v1* api, nph_dataset* ds) {
  nph_renderer* r = NULL;
  nph_renderer_desc desc = NPH_RENDERER_DESC_INIT;
  desc.get_proc_address = (nph_get_proc_address_fn)OSMesaGetProcAddress;
  desc.quality_preset = "draft";
  if (api->renderer_create(ds, &desc, &r) != NPH_OK || api->set_parameter(r, "dlm_resolution", 32) != NPH_OK) {
    fprintf(stderr, "renderer_create: %s\n", api->last_error(r != NULL ? (const void*)r : (const void*)ds));
    exit(1);
  }
  return r;
}

int main(int argc, char** argv) {
  if (argc < 3) {
    fprintf(stderr, "usage: %s DATASET FRAMES [MAX_GROWTH_MB]\n", argv[0]);
    return 2;
  }
  const int frames = atoi(argv[2]);
  const double max_growth_mb = argc > 3 ? atof(argv[3]) : -1.0;
  const nph_api_v1* api = (const nph_api_v1*)nph_get_api(NPH_API_VERSION);
  static unsigned char pixels[96 * 54 * 4];
  OSMesaContext ctx = osmesa_host_context(pixels, 96, 54);
  if (api == NULL || ctx == NULL) return 1;
  nph_dataset* ds = NULL;
  if (api->dataset_open(argv[1], &ds) != NPH_OK) {
    fprintf(stderr, "%s\n", api->last_error(NULL));
    return 1;
  }
  int32_t count = 0;
  api->dataset_timestep_count(ds, &count);
  nph_renderer* r = create(api, ds);
  const int warmup = frames / 5 > 100 ? frames / 5 : 100;
  double rss_after_warmup = -1.0, rss = 0.0, peak = 0.0;
  printf("frame rss_mb\n");
  for (int f = 0; f < frames; ++f) {
    if (f > 0 && f % 100 == 0) {
      api->renderer_destroy(r);
      r = create(api, ds);
    }
    if (api->set_camera_preset(r, f % 2 ? "oblique" : "overview", 96, 54) != NPH_OK ||
        api->set_time(r, fmod(0.37 * f, (double)(count > 1 ? count - 1 : 1))) != NPH_OK ||
        api->set_sun(r, fmod(7.0 * f, 360.0), 20.0 + fmod(3.0 * f, 60.0)) != NPH_OK || api->render(r) != NPH_OK) {
      fprintf(stderr, "frame %d: %s\n", f, api->last_error(r));
      return 1;
    }
    if ((f + 1) % 50 == 0 || f + 1 == frames) {
      glFinish();
      rss = rss_mb();
      if (rss > peak) peak = rss;
      printf("%d %.1f\n", f + 1, rss);
      fflush(stdout);
    }
    if (f + 1 == warmup) rss_after_warmup = rss_mb();
  }
  api->renderer_destroy(r);
  api->dataset_close(ds);
  OSMesaDestroyContext(ctx);
  const double growth = rss - rss_after_warmup;
  printf("soak: %d frames, %d renderers; RSS %.1f MB after the warm-up (%d frames), %.1f MB at the end "
         "(%+.1f MB), peak %.1f MB\n",
         frames, (frames - 1) / 100 + 1, rss_after_warmup, warmup, rss, growth, peak);
  if (max_growth_mb >= 0.0 && growth > max_growth_mb) {
    fprintf(stderr, "soak: RSS grew by %.1f MB after the warm-up, more than %.1f MB\n", growth, max_growth_mb);
    return 1;
  }
  return 0;
}
