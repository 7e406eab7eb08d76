/* Built against an installed nephele with `pkg-config --cflags --libs nephele` (tests/install):
 * the header compiles as C99, libnephele.so.0 links, and the tables of versions 1 and 2 are there. */
#include <nephele/nephele.h>
#include <stdio.h>

int main(void) {
  const nph_api_v1* api = (const nph_api_v1*)nph_get_api(1);
  const nph_api_v2* api2 = (const nph_api_v2*)nph_get_api(NPH_API_VERSION);
  if (api == NULL || api->version != 1u || api->struct_size != sizeof(nph_api_v1) || api2 == NULL ||
      api2->version != 2u || api2->struct_size != sizeof(nph_api_v2) || api2->set_passes == NULL) {
    fprintf(stderr, "nph_get_api(1 or %u): no matching table\n", NPH_API_VERSION);
    return 1;
  }
  nph_dataset* ds = NULL;
  if (api->dataset_open("/nonexistent.nph", &ds) != NPH_ERROR_INPUT) return 1;
  printf("libnephele %s, API version %u: %s\n", api->library_version(), api->version, api->last_error(NULL));
  return 0;
}
