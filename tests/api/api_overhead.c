/* Cost of one render call of the C API against its ray cast, on OSMesa (not a test: figures for
 * docs/plugin-api.md). usage: nephele_api_overhead DATASET
 * For 1x1, 320x180 and 1280x720 (oblique preset, draft, DLM reused): the mean over 10 calls of
 * total_ms, raycast_ms, composite_ms and the rest — handle/thread/context checks and the GL state
 * save and restore. llvmpipe runs compute dispatches at submission, draws at the next flush. */
#include <GL/osmesa.h>
#include <stdio.h>

#include "nephele/nephele.h"
#include "osmesa_host.h"

int main(int argc, char** argv) {
  if (argc != 2) return 2;
  const nph_api_v1* api = (const nph_api_v1*)nph_get_api(NPH_API_VERSION);
  static unsigned char pixels[1280 * 720 * 4];
  OSMesaContext ctx = osmesa_host_context(pixels, 1280, 720);
  if (api == NULL || ctx == NULL) return 1;
  nph_dataset* ds = NULL;
  nph_renderer* r = NULL;
  nph_renderer_desc desc = NPH_RENDERER_DESC_INIT;
  desc.get_proc_address = (nph_get_proc_address_fn)OSMesaGetProcAddress;
  desc.quality_preset = "draft";
  if (api->dataset_open(argv[1], &ds) != NPH_OK || api->renderer_create(ds, &desc, &r) != NPH_OK) {
    fprintf(stderr, "%s\n", api->last_error(ds));
    return 1;
  }
  const int sizes[3][2] = {{1, 1}, {320, 180}, {1280, 720}};
  enum { kCalls = 10 };
  for (int s = 0; s < 3; ++s) {
    api->set_camera_preset(r, "oblique", sizes[s][0], sizes[s][1]);
    glViewport(0, 0, sizes[s][0], sizes[s][1]);
    api->render(r); /* warm-up: DLM build, target allocation */
    glFinish();
    double total = 0.0, raycast = 0.0, composite = 0.0;
    nph_stats st;
    st.struct_size = sizeof st;
    for (int i = 0; i < kCalls; ++i) {
      api->render(r);
      api->get_stats(r, &st);
      total += st.total_ms;
      raycast += st.raycast_ms;
      composite += st.composite_ms;
    }
    glFinish();
    printf("%dx%d: render call %.2f ms = ray cast %.2f + composite %.3f + checks and GL state save/restore %.3f (DLM "
           "%s)\n",
           sizes[s][0], sizes[s][1], total / kCalls, raycast / kCalls, composite / kCalls,
           (total - raycast - composite) / kCalls, st.dlm_rebuilt ? "rebuilt" : "reused");
  }
  api->renderer_destroy(r);
  api->dataset_close(ds);
  OSMesaDestroyContext(ctx);
  return 0;
}
