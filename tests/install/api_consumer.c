/* Built against an installed nephele with `pkg-config --cflags --libs nephele` (tests/install):
 * the header compiles as C99, libnephele.so.0 links, and the table of version 1 is there. */
#include <nephele/nephele.h>
#include <stdio.h>

int main(void) {
  const nph_api_v1* api = (const nph_api_v1*)nph_get_api(NPH_API_VERSION);
  if (api == NULL || api->version != 1u || api->struct_size != sizeof(nph_api_v1)) {
    fprintf(stderr, "nph_get_api(%u): no matching table\n", NPH_API_VERSION);
    return 1;
  }
  nph_dataset* ds = NULL;
  if (api->dataset_open("/nonexistent.nph", &ds) != NPH_ERROR_INPUT) return 1;
  printf("libnephele %s, API version %u: %s\n", api->library_version(), api->version, api->last_error(NULL));
  return 0;
}
